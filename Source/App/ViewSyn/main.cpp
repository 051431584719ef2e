// ViewSyn: VSRS-compatible view synthesis. `ViewSyn FILE.cfg [Key=Value ...]`; see --help.
#include "Common/Options.h"
#include "Pipeline/SynthesisCommandLine.h"
#include "Plan/Plan.h"
#include "Synth/ViewSynRenderer.h"

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::viewSynOptionTable();
  vs::SynthesisTool tool;
  tool.name = "ViewSyn";
  tool.description = "synthesizes a virtual camera view from reference views with depth (VSRS 4.x configs, or RVS 4.0\n"
                     "JSON synthesis configs: doc/manual.md, \"RVS synthesis configs\").";
  tool.checkHelp = "check the config, the camera file, every input file (type, format, size) and every\n"
                   "      output name; print the effective configuration and the cameras; write nothing";
  tool.manual = "doc/manual.md";
  tool.keys = &table;
  tool.run = [](const vs::Config& config) { vs::runViewSyn(config); };
  // Refuses what no path can do (SynthesisMode 1 on a rig that is not rectified), as a run would.
  tool.validate = [](const vs::Config&, const vs::Scene& scene) { vs::makePlan(scene); };
  return vs::runCommandLine(argc, argv, vs::synthesisCommandLine(tool));
}
