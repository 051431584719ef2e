#pragma once
// The frame loop shared by ViewSyn and MeshRender (../shared/DESIGN.md, "Data flow"): check every
// input (type, format, whole frames) and output name before frame 0 (Common/InputCheck.h), open the
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
// asked for, the frames they do hold are written and then InputError says how many. The outputs (and
// the renderer's own files) are temporary files until the run ends well, then renamed into place: a
// refused or failed run leaves every previous file as it was (Common/SafeOutput.h). Warns when the
// least covered frame has less than 1 % of its samples warped from any reference view.
// Progress and summary go to `log` (nullptr: silent); `report` keeps the frames for the JSON summary.
RunSummary runSequence(const std::string& toolName, const Scene& scene, FrameRenderer& renderer, RunReport& report,
                       std::FILE* log = stdout);

}  // namespace vs
