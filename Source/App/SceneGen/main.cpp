// SceneGen: renders built-in analytic scenes into multi-view video plus depth with exact ground truth,
// and writes ready ViewSyn and MeshRender configs. `SceneGen [FILE.cfg] [Key=Value ...]`; see --help.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Scene/SceneGen.h"

namespace {

void printUsage(std::FILE* out, const vs::OptionTable& table) {
  std::fprintf(out,
      "SceneGen %s: renders a built-in scene of analytic objects by ray casting: texture and depth YUV per\n"
      "camera (each texture is also the ground truth of its camera), a VSRS camera parameter file, and\n"
      "ViewSyn and MeshRender configs for every camera between two neighbours.\n\n"
      "Usage:\n"
      "  SceneGen FILE.cfg [Key=Value ...]   render; Key=Value overrides the file (same syntax as ViewSyn)\n"
      "  SceneGen Key=Value ...              render without a config file\n"
      "  SceneGen --help                     this text\n\n"
      "Exit codes: 0 success, 1 bad input (the message says which file, line or key), 2 bad usage.\n"
      "The manual: doc/scenegen.md.\n\nScenes (key Scene):\n%s\n"
      "Keys (type and range; default; meaning). A default of 'scene' is the chosen scene's own value;\n"
      "'auto' is derived from the rendered depths:\n",
      VS_VERSION, vs::sceneListText().c_str());
  std::fputs(table.helpText().c_str(), out);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::sceneGenOptionTable();
  vs::CommandLineTool tool;
  tool.name = "SceneGen";
  tool.table = &table;
  tool.printUsage = [&](std::FILE* out) { printUsage(out, table); };
  tool.run = [&](const std::vector<std::string>& args, vs::ToolAction) {
    // A first argument of the form Key=Value means: no config file, overrides only.
    const bool hasConfigFile = args[0].find('=') == std::string::npos;
    const std::string cfgPath = hasConfigFile ? args[0] : std::string();
    const std::vector<std::string> overrides(args.begin() + (hasConfigFile ? 1 : 0), args.end());
    return vs::runSceneGen(vs::Config::load(table, cfgPath, overrides));
  };
  return vs::runCommandLine(argc, argv, tool);
}
