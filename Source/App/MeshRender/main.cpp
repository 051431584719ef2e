// MeshRender: mesh-based view synthesis with OpenGL. `MeshRender FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Mesh/EglContext.h"
#include "Mesh/MeshSynthesizer.h"

namespace {

void printUsage(const vs::OptionTable& table) {
  std::printf(
      "MeshRender %s: synthesizes a virtual camera view by rendering the reference views' depth maps as\n"
      "textured triangle meshes with OpenGL (headless EGL: a GPU, or Mesa's llvmpipe on the CPU). Reads\n"
      "the same configuration files as ViewSyn, plus the Mesh keys.\n\n"
      "Usage:\n"
      "  MeshRender FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  MeshRender --check FILE.cfg [Key=Value ...]  check the config and camera file and that an OpenGL\n"
      "                                               context can be created; print the effective\n"
      "                                               configuration, the cameras and the renderer; open no\n"
      "                                               YUV file\n"
      "  MeshRender --help                            this text\n\n"
      "Exit codes: 0 success, 1 bad input or no OpenGL (the message says which file, line or key, or what\n"
      "EGL tried), 2 bad usage.\n"
      "The manual: doc/meshrender.md. Keys (type and range; default; meaning):\n",
      VS_VERSION);
  std::fputs(table.helpText().c_str(), stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::meshRenderOptionTable();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    printUsage(table);
    return 2;
  }
  if (args[0] == "--help" || args[0] == "-h") {
    printUsage(table);
    return 0;
  }
  bool checkOnly = false;
  if (args[0] == "--check") {
    checkOnly = true;
    args.erase(args.begin());
    if (args.empty()) {
      std::fprintf(stderr, "MeshRender: --check needs a config file\n");
      return 2;
    }
  }
  if (args[0].rfind("--", 0) == 0) {
    std::fprintf(stderr, "MeshRender: unknown option '%s' (see MeshRender --help)\n", args[0].c_str());
    return 2;
  }
  try {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (checkOnly) {
      const vs::Scene scene = vs::loadScene(config);
      vs::readMeshSettings(config);
      std::printf("MeshRender %s --check %s\n\n%s\n", VS_VERSION, args[0].c_str(), config.effectiveText().c_str());
      for (const std::string& warning : scene.warnings) std::printf("warning: %s\n", warning.c_str());
      std::printf("%s\n", vs::describeCameras(scene).c_str());
      const vs::EglContext context;
      std::printf("OpenGL: %s\nconfiguration OK\n", context.description().c_str());
      return 0;
    }
    return vs::runMeshRender(config);
  } catch (const vs::InputError& e) {
    std::fprintf(stderr, "MeshRender: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "MeshRender: error: out of memory\n");
    return 1;
  }
}
