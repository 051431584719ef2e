// MeshRender: mesh-based view synthesis with OpenGL. `MeshRender FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/InputCheck.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Mesh/EglContext.h"
#include "Mesh/MeshPly.h"
#include "Mesh/MeshSynthesizer.h"

namespace {

void printUsage(std::FILE* out, const vs::OptionTable& table) {
  std::fprintf(out,
      "MeshRender %s: synthesizes a virtual camera view by rendering the reference views' depth maps as\n"
      "textured triangle meshes with OpenGL (headless EGL: a GPU, or Mesa's llvmpipe on the CPU). Reads\n"
      "the same configuration files as ViewSyn, plus the Mesh keys.\n\n"
      "Usage:\n"
      "  MeshRender FILE.cfg [Key=Value ...]          synthesize every frame; Key=Value overrides the file\n"
      "  MeshRender --check FILE.cfg [Key=Value ...]  check the config, the camera file, every input file\n"
      "                                               (type, format, size) and that an OpenGL context can\n"
      "                                               be created; print the effective configuration, the\n"
      "                                               cameras and the renderer; write nothing\n"
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
  tool.run = [&](const std::vector<std::string>& args, bool check) {
    const std::vector<std::string> overrides(args.begin() + 1, args.end());
    const vs::Config config = vs::Config::load(table, args[0], overrides);
    if (check) {
      const vs::Scene scene = vs::loadScene(config);
      const vs::MeshSettings settings = vs::readMeshSettings(config);
      vs::printConfigCheck("MeshRender", args[0], config, scene);
      for (const std::string& warning : vs::checkInputs(scene)) std::printf("warning: %s\n", warning.c_str());
      std::vector<vs::NamedOutput> plyFiles;
      if (!settings.plyPath.empty())
        for (const vs::ReferenceView& view : scene.settings.references)
          plyFiles.push_back({"MeshPlyOutput", vs::plyPathForView(settings.plyPath, view.label)});
      vs::checkOutputs(scene, plyFiles);
      std::printf("input files OK\n");
      const vs::EglContext context;
      std::printf("OpenGL: %s\nconfiguration OK\n", context.description().c_str());
      return 0;
    }
    return vs::runMeshRender(config);
  };
  return vs::runCommandLine(argc, argv, tool);
}
