// MeshRender: mesh-based view synthesis with OpenGL. `MeshRender FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Mesh/EglContext.h"
#include "Mesh/MeshSynthesizer.h"
#include "Pipeline/RunReport.h"

namespace {

void printUsage(std::FILE* out, const vs::OptionTable& table) {
  std::fprintf(out,
      "MeshRender %s: synthesizes a virtual camera view by rendering the reference views' depth maps as\n"
      "textured triangle meshes with OpenGL (headless EGL: a GPU, or Mesa's llvmpipe on the CPU). Reads\n"
      "the same configuration files as ViewSyn, plus the Mesh keys.\n\n"
      "Usage:\n"
      "  MeshRender FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  MeshRender --check FILE.cfg [Key=Value ...]  check the config and camera file and that an OpenGL\n"
      "                                               context can be created; print the effective\n"
      "                                               configuration, the cameras and the renderer; open no\n"
      "                                               YUV file\n"
      "  MeshRender --print-config FILE.cfg [Key=Value ...]\n"
      "                                               print the effective configuration and the scene as\n"
      "                                               JSON (for scripts); open no YUV file\n"
      "  MeshRender --help                            this text\n\n"
      "Exit codes: 0 success, 1 bad input or no OpenGL (the message says which file, line or key, or what\n"
      "EGL tried), 2 bad usage.\n"
      "The manual: doc/meshrender.md. Keys (type and range; default; meaning):\n",
      VS_VERSION);
  std::fputs(table.helpText().c_str(), out);
}

}  // namespace

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::meshRenderOptionTable();
  vs::CommandLineTool tool;
  tool.name = "MeshRender";
  tool.table = &table;
  tool.printUsage = [&](std::FILE* out) { printUsage(out, table); };
  tool.hasCheck = true;
  tool.hasPrintConfig = true;
  tool.run = [&](const std::vector<std::string>& args, vs::ToolAction action) {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (action == vs::ToolAction::PrintConfig) {
      const vs::Scene scene = vs::loadScene(config);
      vs::readMeshSettings(config);
      std::fputs(vs::configJson("MeshRender", config, scene).c_str(), stdout);
      return 0;
    }
    if (action == vs::ToolAction::Check) {
      const vs::Scene scene = vs::loadScene(config);
      vs::readMeshSettings(config);
      vs::printConfigCheck("MeshRender", args[0], config, scene);
      const vs::EglContext context;
      std::printf("OpenGL: %s\nconfiguration OK\n", context.description().c_str());
      return 0;
    }
    return vs::runMeshRender(config);
  };
  return vs::runCommandLine(argc, argv, tool);
}
