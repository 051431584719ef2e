#pragma once
// The output sequences of a run: the virtual view (OutputVirtualViewImageName) and, when configured,
// its depth (OutputVirtualDepthMapName), both at the virtual view's size (VirtualWidth, VirtualHeight).
// Both are checked before either is created; each is written to
// a temporary file and renamed into place by commit() when the run ends well, so that a refused or
// failed run leaves the previous files as they were (Common/SafeOutput.h).
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
  // Checks and creates the outputs (temporary files); throws InputError (an output that is an input, a
  // folder that does not exist, ...). A Y4M output takes the frame rate of `rate` (a Y4M texture's
  // header; nullptr: 25:1).
  explicit SequenceOutputs(const SynthesisSettings& settings, const Y4mHeader* rate = nullptr);

  // Appends `output`, then, when a depth output is configured, the levels `virtualDepth` fills
  // (false: the renderer cannot provide them, an InputError naming `toolName`).
  void append(const Frame& output, const std::function<bool(Plane& levels)>& virtualDepth, const std::string& toolName);
  // Renames every output into place (the run ended well). Throws InputError when that fails.
  void commit();

private:
  const SynthesisSettings& settings_;
  std::unique_ptr<YuvWriter> writer_, depthWriter_;
  Frame virtualDepth_;
};

}  // namespace vs
