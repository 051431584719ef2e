#pragma once
// What the frame loop (Pipeline/FrameLoop.h) asks of a renderer: the pipeline owns this interface and
// knows no renderer; ViewSyn's (Synth/ViewSynRenderer.h) and MeshRender's (Mesh/MeshSynthesizer.h)
// adapters implement it, and the apps wire one into the loop (../shared/DESIGN.md, "Layout").
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Common/InputCheck.h"
#include "Common/Timing.h"

namespace vs {

class FrameRenderer {
public:
  virtual ~FrameRenderer() = default;
  // Renders the virtual view of one frame; adds its stage times to `times`.
  virtual void render(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) = 0;
  // Called once, as soon as the first frame's inputs are read (the loop's own reading threads exist by
  // then), before prepare(). A renderer that loads a library on a thread of its own (MeshRender's
  // OpenGL context: Mesa and LLVM) starts it here: glibc holds a lock for the whole of a dlopen that
  // every thread creation takes, so a thread created meanwhile would wait for the load to end.
  virtual void firstInputsRead() {}
  // Called with the first frame's inputs before it is rendered, for decisions that need the pictures
  // (MissingDepthLevel auto); returns the lines that say what was decided (none: nothing to decide).
  virtual std::vector<std::string> prepare(const std::vector<ReferenceFrame>& /*firstFrame*/) { return {}; }
  // Lines describing what this renderer will do (the plan), printed before the first frame.
  virtual std::vector<std::string> plan() const = 0;
  // The plan's decisions as key/value pairs (Plan::fields), for the JSON summary; none by default.
  virtual std::vector<std::pair<std::string, std::string>> decisions() const { return {}; }
  // The last rendered frame's depth as levels of `range` (OutputVirtualDepthMapName); false when the
  // renderer cannot provide it.
  virtual bool virtualDepth(const std::vector<ReferenceFrame>& /*references*/, const DepthRange& /*range*/,
                            Plane& /*levels*/) {
    return false;
  }
  // The last rendered frame's mask (OutputVirtualMaskName): 255 where no reference view gave the luma
  // sample, 0 elsewhere; false when the renderer cannot provide it.
  virtual bool virtualMask(const std::vector<ReferenceFrame>& /*references*/, Plane& /*mask*/) { return false; }
  // Luma samples of the last rendered frame that no reference view covered (filled as holes); -1:
  // unknown. The loop warns when a frame has less than 1 % covered.
  virtual int64_t uncoveredSamples() const { return -1; }
  // Files the renderer writes itself (MeshRender's PLY), checked with the run's outputs before frame 0.
  virtual std::vector<NamedOutput> extraOutputs() const { return {}; }
  // VirtualPoseTraceName: the virtual camera of the next frames is `camera` (called before each frame's
  // render). False when the renderer cannot move its virtual camera; the loop then refuses the run.
  virtual bool moveVirtualCamera(const Camera& /*camera*/) { return false; }
  // Renames the renderer's own files into place; called once the run has ended well.
  virtual void commitOutputs() {}
};

}  // namespace vs
