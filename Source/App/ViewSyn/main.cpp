// ViewSyn: VSRS-compatible view synthesis. `ViewSyn FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Synth/ViewSynRenderer.h"

namespace {

void printUsage(std::FILE* out, const vs::OptionTable& table) {
  std::fprintf(out,
      "ViewSyn %s: synthesizes a virtual camera view from two reference views with depth (VSRS 4.x configs).\n\n"
      "Usage:\n"
      "  ViewSyn FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  ViewSyn --check FILE.cfg [Key=Value ...]  check the config and camera file, print the effective\n"
      "                                            configuration and the cameras, open no YUV file\n"
      "  ViewSyn --print-config FILE.cfg [Key=Value ...]\n"
      "                                            print the effective configuration and the scene as\n"
      "                                            JSON (for scripts); open no YUV file\n"
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
  tool.hasPrintConfig = true;
  tool.run = [&](const std::vector<std::string>& args, vs::ToolAction action) {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (action == vs::ToolAction::PrintConfig) {
      std::fputs(vs::configJson("ViewSyn", config, vs::loadScene(config)).c_str(), stdout);
      return 0;
    }
    if (action == vs::ToolAction::Check) {
      vs::printConfigCheck("ViewSyn", args[0], config, vs::loadScene(config));
      std::printf("configuration OK\n");
      return 0;
    }
    vs::runViewSyn(config);
    return 0;
  };
  return vs::runCommandLine(argc, argv, tool);
}
