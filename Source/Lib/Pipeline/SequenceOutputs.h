#pragma once
// The output sequences of a run: the virtual view (OutputVirtualViewImageName) and, when configured,
// its depth (OutputVirtualDepthMapName), its mask (OutputVirtualMaskName) and its masked depth
// (OutputMaskedVirtualDepthMapName), all at the virtual view's size (VirtualWidth, VirtualHeight).
// Every one is checked before any is created; each is written to a temporary file and renamed into
// place by commit() when the run ends well, so that a refused or failed run leaves the previous files
// as they were (Common/SafeOutput.h).
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

  // What the renderer gives for the depth and mask outputs: each fills the plane, or returns false
  // when the renderer cannot provide it.
  using PlaneSource = std::function<bool(Plane& plane)>;
  // Appends `output`, then each configured depth or mask output, from the levels `virtualDepth` and
  // the mask `virtualMask` fill (false: an InputError naming `toolName`).
  void append(const Frame& output, const PlaneSource& virtualDepth, const PlaneSource& virtualMask,
              const std::string& toolName);
  // Renames every output into place (the run ended well). Throws InputError when that fails.
  void commit();

  // The formats of the depth outputs and of the mask: the virtual view's size; the depth files' chroma
  // format with the virtual depth range's bit depth; the mask 8-bit in the output's chroma format.
  static FrameFormat depthFormat(const SynthesisSettings& settings);
  static FrameFormat maskFormat(const SynthesisSettings& settings);

private:
  const SynthesisSettings& settings_;
  std::unique_ptr<YuvWriter> writer_, depthWriter_, maskWriter_, maskedDepthWriter_;
  Frame virtualDepth_, mask_, maskedDepth_;
};

}  // namespace vs
