#pragma once
// The frame loop shared by ViewSyn and MeshRender (../shared/DESIGN.md, "Data flow"): open the
// inputs, check how many frames they hold, then for each frame read, render, append to the output,
// score against the reference view when one is configured; print VSRS-style progress and a summary.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/InputCheck.h"
#include "Common/Scene.h"
#include "Synth/Synthesizer.h"

namespace vs {

class FrameRenderer {
public:
  virtual ~FrameRenderer() = default;
  // Renders the virtual view of one frame; adds its stage times to `times`.
  virtual void render(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) = 0;
  // Lines describing what this renderer will do (the plan), printed before the first frame.
  virtual std::vector<std::string> plan() const = 0;
  // The last rendered frame's depth as levels of `range` (OutputVirtualDepthMapName); false when the
  // renderer cannot provide it.
  virtual bool virtualDepth(const std::vector<ReferenceFrame>& /*references*/, const DepthRange& /*range*/,
                            Plane& /*levels*/) {
    return false;
  }
  // Luma samples of the last rendered frame that no reference view covered (filled as holes); -1:
  // unknown. The run warns when a frame has less than 1 % covered.
  virtual int64_t uncoveredSamples() const { return -1; }
  // Files the renderer writes itself (MeshRender's PLY), checked with the run's outputs before frame 0.
  virtual std::vector<NamedOutput> extraOutputs() const { return {}; }
  // Renames the renderer's own files into place; called once the run has ended well.
  virtual void commitOutputs() {}
};

struct RunSummary {
  int64_t framesWritten = 0;
  double meanPsnrY = 0, meanPsnrU = 0, meanPsnrV = 0;  // frame means; 0 without a reference view
  StageTimes times;                                      // sums over all frames
  std::vector<std::string> warnings;                     // camera file, inputs and run, one line each
};

// Runs the whole sequence. Throws InputError for bad input; when the inputs hold fewer frames than
// asked for, the frames they do hold are written and then InputError says how many.
// Progress and summary go to `log` (nullptr: silent).
RunSummary runSequence(const std::string& toolName, const Config& config, const Scene& scene, FrameRenderer& renderer,
                       std::FILE* log = stdout);

// ViewSyn's run(): loads the scene, lets the plan decide, runs the sequence.
RunSummary runViewSyn(const Config& config, std::FILE* log = stdout);

}  // namespace vs
