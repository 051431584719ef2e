// What a tool cannot do is refused by its plan (Plan/Plan.h) before any YUV file is opened, by
// `--check` and by a run alike: MeshRender cannot write the virtual view's depth
// (OutputVirtualDepthMapName), which used to pass --check and fail after the first frame.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "Process.h"
#include "TestPaths.h"
#include "TinyScene.h"

namespace vs {
namespace {

namespace fs = std::filesystem;
using test::TinyScene;

TEST(PlanRefusal, MeshRenderRefusesOutputVirtualDepthMapNameBeforeOpeningAnyYuvFile) {
  const fs::path root = test::scratchDir("plan_refusal_mesh_depth");
  TinyScene scene(root / "scene");
  scene.writeAll();
  scene.set("OutputVirtualDepthMapName", "virtual_depth.yuv");
  scene.writeConfig();
  // An input is missing: a tool that opened its inputs first would complain about that file instead.
  fs::remove(scene.path("left.yuv"));
  const std::string config = test::quoted(scene.configPath().string());
  for (const std::string& mode : {std::string("--check "), std::string()}) {
    const test::ToolResult result = test::runTool("MeshRender", mode + config, root, scene.dir);
    EXPECT_EQ(result.exitCode, 1) << mode << result.err;
    EXPECT_NE(result.err.find("OutputVirtualDepthMapName '" + scene.path("virtual_depth.yuv").string() + "'"),
              std::string::npos)
        << result.err;
    EXPECT_NE(result.err.find("MeshRender cannot write the virtual view's depth"), std::string::npos) << result.err;
    EXPECT_EQ(result.err.find("left.yuv"), std::string::npos) << result.err;
    EXPECT_EQ(result.out.find("configuration OK"), std::string::npos) << result.out;
    EXPECT_FALSE(fs::exists(scene.outputPath())) << mode;
    EXPECT_FALSE(fs::exists(scene.path("virtual_depth.yuv"))) << mode;
  }
  // ViewSyn writes the virtual depth: the same configuration passes its --check (which opens no YUV
  // file either, so the missing input does not matter there).
  const test::ToolResult viewSyn = test::runTool("ViewSyn", "--check " + config, root, scene.dir);
  EXPECT_EQ(viewSyn.exitCode, 0) << viewSyn.err;
  EXPECT_NE(viewSyn.out.find("configuration OK"), std::string::npos) << viewSyn.out;
}

// ViewSyn's --check asks the plan too: SynthesisMode 1 on a rig that is not rectified is refused with
// the measured deviation, as the run refuses it, instead of "configuration OK".
TEST(PlanRefusal, ViewSynCheckRefusesTheOneDimensionalPathOnARigThatIsNotRectified) {
  const fs::path root = test::scratchDir("plan_refusal_1d");
  TinyScene scene(root / "scene");
  scene.writeAll();
  std::vector<Camera> cameras = scene.cameras();
  cameras[2].t.y = 0.5;  // the right camera off the x axis
  writeCameraFile(scene.path("cameras.txt").string(), cameras);
  scene.set("SynthesisMode", "1");
  scene.writeConfig();
  const test::ToolResult result =
      test::runTool("ViewSyn", "--check " + test::quoted(scene.configPath().string()), root, scene.dir);
  EXPECT_EQ(result.exitCode, 1) << result.err;
  EXPECT_NE(result.err.find("SynthesisMode 1 (1D parallel) needs a rectified rig"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("Right: "), std::string::npos) << result.err;
  EXPECT_EQ(result.out.find("configuration OK"), std::string::npos) << result.out;
}

}  // namespace
}  // namespace vs
