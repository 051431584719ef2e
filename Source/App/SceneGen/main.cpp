// SceneGen: renders built-in analytic scenes into multi-view video plus depth with exact ground truth,
// and writes ready ViewSyn and MeshRender configs. `SceneGen [FILE.cfg] [Key=Value ...]`; see --help.
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Scene/SceneGen.h"

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::sceneGenOptionTable();
  vs::CommandLineTool tool;
  tool.name = "SceneGen";
  tool.description =
      "renders a built-in scene of analytic objects by ray casting: texture and depth YUV per\n"
      "camera (each texture is also the ground truth of its camera), a VSRS camera parameter file, and\n"
      "ViewSyn and MeshRender configs for every camera between two neighbours.";
  tool.synopsis = {"FILE.cfg [Key=Value ...]   render; Key=Value overrides the file (same syntax as ViewSyn)",
                   "Key=Value ...              render without a config file"};
  tool.notes = "Exit codes: 0 success, 1 bad input (the message says which file, line or key), 2 bad usage.\n"
               "The manual: doc/scenegen.md.\n\nScenes (key Scene):\n" + vs::sceneListText() + "\n";
  tool.keys = &table;
  tool.keysHeading = "Keys (type and range; default; meaning). A default of 'scene' is the chosen scene's own value;\n"
                     "'auto' is derived from the rendered depths:";
  tool.run = [&](const vs::CommandLine& line) {
    // A first argument of the form Key=Value means: no config file, overrides only.
    const std::vector<std::string>& args = line.positional;
    const bool hasConfigFile = !args.empty() && args[0].find('=') == std::string::npos;
    const std::vector<std::string> overrides(args.begin() + (hasConfigFile ? 1 : 0), args.end());
    return vs::runSceneGen(vs::Config::load(table, hasConfigFile ? args[0] : std::string(), overrides));
  };
  return vs::runCommandLine(argc, argv, tool);
}
