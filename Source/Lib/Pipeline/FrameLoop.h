#pragma once
// The frame loop shared by ViewSyn and MeshRender (../shared/DESIGN.md, "Data flow"): open the
// inputs, check how many frames they hold, then for each frame read (ahead, on another thread),
// render, append to the outputs, score against the reference view when one is configured; the run
// report prints progress and the summary and writes the CSV.
#include <cstdio>
#include <string>

#include "Common/Scene.h"
#include "Pipeline/FrameRenderer.h"
#include "Pipeline/RunReport.h"

namespace vs {

// Runs the whole sequence. Throws InputError for bad input; when the inputs hold fewer frames than
// asked for, the frames they do hold are written and then InputError says how many.
// Progress and summary go to `log` (nullptr: silent); `report` keeps the frames for the JSON summary.
RunSummary runSequence(const std::string& toolName, const Scene& scene, FrameRenderer& renderer, RunReport& report,
                       std::FILE* log = stdout);

}  // namespace vs
