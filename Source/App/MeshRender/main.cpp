// MeshRender: mesh-based view synthesis with OpenGL. `MeshRender FILE.cfg [Key=Value ...]`; see --help.
#include <cstdio>

#include "Common/Options.h"
#include "Mesh/EglContext.h"
#include "Mesh/MeshSynthesizer.h"
#include "Pipeline/SynthesisCommandLine.h"
#include "Plan/Plan.h"

int main(int argc, char** argv) {
  const vs::OptionTable table = vs::meshRenderOptionTable();
  vs::SynthesisTool tool;
  tool.name = "MeshRender";
  tool.description =
      "synthesizes a virtual camera view by rendering the reference views' depth maps as\n"
      "textured triangle meshes with OpenGL (headless EGL: a GPU, or Mesa's llvmpipe on the CPU). Reads\n"
      "the same configuration files as ViewSyn, plus the Mesh keys.";
  tool.checkHelp = "check the config and camera file and that an OpenGL context can be created; print the\n"
                   "      effective configuration, the cameras and the renderer; open no YUV file";
  tool.manual = "doc/meshrender.md";
  tool.keys = &table;
  tool.run = [](const vs::Config& config) { vs::runMeshRender(config); };
  tool.validate = [](const vs::Config& config, const vs::Scene& scene) {
    vs::readMeshSettings(config);
    vs::makePlan(scene, vs::Tool::MeshRender);  // refuses what MeshRender cannot do, as a run would
  };
  tool.describe = [](std::FILE* out) {
    const vs::EglContext context;
    std::fprintf(out, "OpenGL: %s\n", context.description().c_str());
  };
  return vs::runCommandLine(argc, argv, vs::synthesisCommandLine(tool));
}
