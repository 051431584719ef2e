// ViewSyn: VSRS-compatible view synthesis. `ViewSyn FILE.cfg [Key=Value ...]`; see --help.
#include "Common/Options.h"
#include "Pipeline/SynthesisCommandLine.h"
#include "Plan/Plan.h"
#include "Synth/ViewSynRenderer.h"

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::viewSynOptionTable();
  vs::SynthesisTool tool;
  tool.name = "ViewSyn";
  tool.description = "synthesizes a virtual camera view from two reference views with depth (VSRS 4.x configs).";
  tool.checkHelp = "check the config and camera file, print the effective configuration and the cameras;\n"
                   "      open no YUV file";
  tool.manual = "doc/manual.md";
  tool.keys = &table;
  tool.run = [](const vs::Config& config) { vs::runViewSyn(config); };
  // Refuses what no path can do (SynthesisMode 1 on a rig that is not rectified), as a run would.
  tool.validate = [](const vs::Config&, const vs::Scene& scene) { vs::makePlan(scene); };
  return vs::runCommandLine(argc, argv, vs::synthesisCommandLine(tool));
}
