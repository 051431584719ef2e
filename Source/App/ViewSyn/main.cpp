// ViewSyn: VSRS-compatible view synthesis. `ViewSyn FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Synth/Run.h"

namespace {

void printUsage(const vs::OptionTable& table) {
  std::printf(
      "ViewSyn %s: synthesizes a virtual camera view from two reference views with depth (VSRS 4.x configs).\n\n"
      "Usage:\n"
      "  ViewSyn FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  ViewSyn --check FILE.cfg [Key=Value ...]  check the config and camera file, print the effective\n"
      "                                            configuration and the cameras, open no YUV file\n"
      "  ViewSyn --help                            this text\n"
      "  ViewSyn --help-markdown                   the keys as Markdown tables (the manual's source)\n\n"
      "Exit codes: 0 success, 1 bad input (the message says which file, line or key), 2 bad usage.\n"
      "The manual: doc/manual.md. Keys (type and range; default; meaning):\n",
      VS_VERSION);
  std::fputs(table.helpText().c_str(), stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::viewSynOptionTable();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    printUsage(table);
    return 2;
  }
  if (args[0] == "--help" || args[0] == "-h") {
    printUsage(table);
    return 0;
  }
  if (args[0] == "--help-markdown") {
    std::fputs(table.markdownTable().c_str(), stdout);
    return 0;
  }
  bool checkOnly = false;
  if (args[0] == "--check") {
    checkOnly = true;
    args.erase(args.begin());
    if (args.empty()) {
      std::fprintf(stderr, "ViewSyn: --check needs a config file\n");
      return 2;
    }
  }
  if (args[0].rfind("--", 0) == 0) {
    std::fprintf(stderr, "ViewSyn: unknown option '%s' (see ViewSyn --help)\n", args[0].c_str());
    return 2;
  }
  try {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (checkOnly) {
      const vs::Scene scene = vs::loadScene(config);
      std::printf("ViewSyn %s --check %s\n\n%s\n", VS_VERSION, args[0].c_str(), config.effectiveText().c_str());
      for (const std::string& warning : scene.warnings) std::printf("warning: %s\n", warning.c_str());
      std::printf("%s\nconfiguration OK\n", vs::describeCameras(scene).c_str());
      return 0;
    }
    vs::runViewSyn(config);
    return 0;
  } catch (const vs::InputError& e) {
    std::fprintf(stderr, "ViewSyn: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "ViewSyn: error: out of memory\n");
    return 1;
  }
}
