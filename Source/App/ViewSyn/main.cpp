// ViewSyn: VSRS-compatible view synthesis. `ViewSyn FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/InputCheck.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Synth/Run.h"

namespace {

void printUsage(std::FILE* out, const vs::OptionTable& table) {
  std::fprintf(out,
      "ViewSyn %s: synthesizes a virtual camera view from two reference views with depth (VSRS 4.x configs).\n\n"
      "Usage:\n"
      "  ViewSyn FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  ViewSyn --check FILE.cfg [Key=Value ...]  check the config, the camera file and every input file\n"
      "                                            (type, format, size), print the effective configuration\n"
      "                                            and the cameras; write nothing\n"
      "  ViewSyn --help                            this text\n"
      "  ViewSyn --help-markdown                   the keys as Markdown tables (the manual's source)\n\n"
      "Exit codes: 0 success, 1 bad input (the message says which file, line or key), 2 bad usage.\n"
      "The manual: doc/manual.md. Keys (type and range; default; meaning):\n",
      VS_VERSION);
  std::fputs(table.helpText().c_str(), out);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::viewSynOptionTable();
  vs::CommandLineTool tool;
  tool.name = "ViewSyn";
  tool.table = &table;
  tool.printUsage = [&](std::FILE* out) { printUsage(out, table); };
  tool.hasCheck = true;
  tool.run = [&](const std::vector<std::string>& args, bool check) {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (check) {
      const vs::Scene scene = vs::loadScene(config);
      vs::printConfigCheck("ViewSyn", args[0], config, scene);
      for (const std::string& warning : vs::checkInputs(scene)) std::printf("warning: %s\n", warning.c_str());
      vs::checkOutputs(scene);
      std::printf("input files OK\nconfiguration OK\n");
      return 0;
    }
    vs::runViewSyn(config);
    return 0;
  };
  return vs::runCommandLine(argc, argv, tool);
}
