// SceneGen: renders built-in analytic scenes into multi-view video plus depth with exact ground truth,
// and writes ready ViewSyn and MeshRender configs. `SceneGen [FILE.cfg] [Key=Value ...]`; see --help.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Scene/SceneGen.h"

namespace {

void printUsage(const vs::OptionTable& table) {
  std::printf(
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
  std::fputs(table.helpText().c_str(), stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::sceneGenOptionTable();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    printUsage(table);
    return 2;
  }
  if (args[0] == "--help" || args[0] == "-h") {
    printUsage(table);
    return 0;
  }
  if (args[0].rfind("--", 0) == 0) {
    std::fprintf(stderr, "SceneGen: unknown option '%s' (see SceneGen --help)\n", args[0].c_str());
    return 2;
  }
  try {
    // A first argument of the form Key=Value means: no config file, overrides only.
    const bool hasConfigFile = args[0].find('=') == std::string::npos;
    const std::string cfgPath = hasConfigFile ? args[0] : std::string();
    const std::vector<std::string> overrides(args.begin() + (hasConfigFile ? 1 : 0), args.end());
    return vs::runSceneGen(vs::Config::load(table, cfgPath, overrides));
  } catch (const vs::InputError& e) {
    std::fprintf(stderr, "SceneGen: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "SceneGen: error: out of memory\n");
    return 1;
  }
}
