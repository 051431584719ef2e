#include "Pipeline/SequenceOutputs.h"

#include "Common/Error.h"

namespace vs {

SequenceOutputs::SequenceOutputs(const SynthesisSettings& settings, const Y4mHeader* rate) : settings_(settings) {
  const SynthesisSettings& s = settings;
  const std::vector<std::string> inputs = s.inputPaths();
  FrameFormat depthFormat = s.depthFormat;
  depthFormat.bitDepth = s.virtualDepthRange.bitDepth;
  std::vector<std::string> notDepth = inputs;
  notDepth.push_back(s.outputPath);
  YuvWriter::checkOutput(s.outputPath, s.textureFormat, inputs, "OutputVirtualViewImageName");
  if (!s.virtualDepthPath.empty())
    YuvWriter::checkOutput(s.virtualDepthPath, depthFormat, notDepth, "OutputVirtualDepthMapName");
  writer_ = std::make_unique<YuvWriter>(s.outputPath, s.textureFormat, inputs, "OutputVirtualViewImageName", rate);
  // The virtual depth's frame only where it is written (a 1920x1080 frame is 6 MB).
  if (!s.virtualDepthPath.empty()) {
    depthWriter_ = std::make_unique<YuvWriter>(s.virtualDepthPath, depthFormat, notDepth, "OutputVirtualDepthMapName");
    virtualDepth_.reset(depthFormat);
    virtualDepth_.fill(0);
  }
}

void SequenceOutputs::append(const Frame& output, const std::function<bool(Plane& levels)>& virtualDepth,
                             const std::string& toolName) {
  writer_->append(output);
  if (!depthWriter_) return;
  if (!virtualDepth(virtualDepth_.planes[0])) throw InputError(toolName + " cannot write OutputVirtualDepthMapName");
  depthWriter_->append(virtualDepth_);
}

void SequenceOutputs::commit() {
  writer_->commit();
  if (depthWriter_) depthWriter_->commit();
}

}  // namespace vs
