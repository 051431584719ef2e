#pragma once
// ViewSyn's renderer as the frame loop sees it (Pipeline/FrameRenderer.h): what the plan decided, a
// copy of a reference view or the synthesizer on the chosen path; and ViewSyn's run(), which wires it
// into the pipeline.
#include <cstdio>

#include "Common/Config.h"
#include "Pipeline/RunReport.h"

namespace vs {

// Loads the scene, lets the plan decide, runs the sequence (Pipeline/FrameLoop.h); writes SummaryFile
// also when the run fails. Progress and summary go to `log` (nullptr: silent).
RunSummary runViewSyn(const Config& config, std::FILE* log = stdout);

}  // namespace vs
