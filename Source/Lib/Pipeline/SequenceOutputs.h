#pragma once
// The output sequences of a run: the virtual view (OutputVirtualViewImageName) and, when configured,
// its depth (OutputVirtualDepthMapName). Both are checked before either is created, so that a refused
// run truncates nothing; frames are appended whole (Common/Yuv.h).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"

namespace vs {

class SequenceOutputs {
public:
  // Checks and creates the outputs; throws InputError (an output that is an input, a folder that
  // does not exist, ...).
  explicit SequenceOutputs(const SynthesisSettings& settings);

  // Appends `output`, then, when a depth output is configured, the levels `virtualDepth` fills
  // (false: the renderer cannot provide them, an InputError naming `toolName`).
  void append(const Frame& output, const std::function<bool(Plane& levels)>& virtualDepth, const std::string& toolName);
  // What is on disk, for messages: "N whole frames were written to OUT[, M to DEPTH]".
  std::string written() const;

private:
  const SynthesisSettings& settings_;
  std::unique_ptr<YuvWriter> writer_, depthWriter_;
  Frame virtualDepth_;
};

}  // namespace vs
