#include "Pipeline/SequenceOutputs.h"

#include "Common/Error.h"

namespace vs {

SequenceOutputs::SequenceOutputs(const SynthesisSettings& settings, const Y4mHeader* rate) : settings_(settings) {
  const SynthesisSettings& s = settings;
  const std::vector<std::string> inputs = s.inputPaths();
  const FrameFormat outputFormat = s.virtualFormat();
  FrameFormat depthFormat = s.depthFormat;
  depthFormat.width = outputFormat.width;
  depthFormat.height = outputFormat.height;
  depthFormat.bitDepth = s.virtualDepthRange.bitDepth;
  std::vector<std::string> notDepth = inputs;
  notDepth.push_back(s.outputPath);
  YuvWriter::checkOutput(s.outputPath, outputFormat, inputs, "OutputVirtualViewImageName");
  if (!s.virtualDepthPath.empty())
    YuvWriter::checkOutput(s.virtualDepthPath, depthFormat, notDepth, "OutputVirtualDepthMapName");
  writer_ = std::make_unique<YuvWriter>(s.outputPath, outputFormat, inputs, "OutputVirtualViewImageName", rate);
  virtualDepth_.reset(depthFormat);
  if (!s.virtualDepthPath.empty()) {
    depthWriter_ = std::make_unique<YuvWriter>(s.virtualDepthPath, depthFormat, notDepth, "OutputVirtualDepthMapName");
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
