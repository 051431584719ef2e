#include "Pipeline/SequenceOutputs.h"

#include "Common/Error.h"

namespace vs {

FrameFormat SequenceOutputs::depthFormat(const SynthesisSettings& s) {
  FrameFormat format = s.depthFormat;
  format.width = s.virtualFormat().width;
  format.height = s.virtualFormat().height;
  format.bitDepth = s.virtualDepthRange.bitDepth;
  return format;
}

FrameFormat SequenceOutputs::maskFormat(const SynthesisSettings& s) {
  FrameFormat format = s.virtualFormat();
  format.bitDepth = 8;
  return format;
}

SequenceOutputs::SequenceOutputs(const SynthesisSettings& settings, const Y4mHeader* rate) : settings_(settings) {
  const SynthesisSettings& s = settings;
  const std::vector<std::string> inputs = s.inputPaths();
  const FrameFormat depth = depthFormat(s), mask = maskFormat(s);
  // Each further output must not be an input, nor the output sequence (checkOutputs compares the
  // outputs with each other before any of them is created).
  std::vector<std::string> notOutput = inputs;
  notOutput.push_back(s.outputPath);
  struct Extra {
    const std::string& path;
    const FrameFormat& format;
    const char* key;
    std::unique_ptr<YuvWriter>& writer;
    Frame& frame;
  };
  const Extra extras[] = {
      {s.virtualDepthPath, depth, "OutputVirtualDepthMapName", depthWriter_, virtualDepth_},
      {s.virtualMaskPath, mask, "OutputVirtualMaskName", maskWriter_, mask_},
      {s.maskedVirtualDepthPath, depth, "OutputMaskedVirtualDepthMapName", maskedDepthWriter_, maskedDepth_},
  };
  YuvWriter::checkOutput(s.outputPath, s.virtualFormat(), inputs, "OutputVirtualViewImageName");
  for (const Extra& extra : extras)
    if (!extra.path.empty()) YuvWriter::checkOutput(extra.path, extra.format, notOutput, extra.key);
  writer_ = std::make_unique<YuvWriter>(s.outputPath, s.virtualFormat(), inputs, "OutputVirtualViewImageName", rate);
  // The virtual depth's frame only where it is written, plain or masked (a 1920x1080 frame is 6 MB).
  if (!s.virtualDepthPath.empty() || !s.maskedVirtualDepthPath.empty()) virtualDepth_.reset(depth);
  for (const Extra& extra : extras) {
    if (extra.path.empty()) continue;
    extra.writer = std::make_unique<YuvWriter>(extra.path, extra.format, notOutput, extra.key);
    extra.frame.reset(extra.format);
    extra.frame.fill(0);  // chroma mid-grey (the mask's 128), written as it is every frame
  }
}

void SequenceOutputs::append(const Frame& output, const PlaneSource& virtualDepth, const PlaneSource& virtualMask,
                             const std::string& toolName) {
  writer_->append(output);
  const bool depthNeeded = depthWriter_ || maskedDepthWriter_;
  if (depthNeeded && !virtualDepth(virtualDepth_.planes[0]))
    throw InputError(toolName + " cannot write " +
                     (depthWriter_ ? "OutputVirtualDepthMapName" : "OutputMaskedVirtualDepthMapName"));
  if (depthWriter_) depthWriter_->append(virtualDepth_);
  if (!maskWriter_ && !maskedDepthWriter_) return;
  Plane& mask = mask_.planes[0];
  if (!virtualMask(mask))
    throw InputError(toolName + " cannot write " + (maskWriter_ ? "OutputVirtualMaskName" : "OutputMaskedVirtualDepthMapName"));
  if (maskWriter_) maskWriter_->append(mask_);
  if (!maskedDepthWriter_) return;
  // The depth with level 0 (RVS: the value 0 it writes at masked samples) where the mask is set.
  Plane& masked = maskedDepth_.planes[0];
  masked.samples = virtualDepth_.planes[0].samples;
  for (size_t i = 0; i < masked.samples.size(); ++i)
    if (mask.samples[i]) masked.samples[i] = 0;
  maskedDepthWriter_->append(maskedDepth_);
}

void SequenceOutputs::commit() {
  writer_->commit();
  for (const auto* writer : {&depthWriter_, &maskWriter_, &maskedDepthWriter_})
    if (*writer) (*writer)->commit();
}

}  // namespace vs
