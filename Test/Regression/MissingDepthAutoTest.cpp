// MissingDepthLevel auto through the tools (Plan/MissingDepth.h, FrameRenderer::prepare): on real
// data the plan's decision is printed per reference view, and the output is byte for byte the one of
// the explicit setting it decided (ViewSyn general and 1D, MeshRender: one decision, shared code).
// Truth for the readings: Middlebury's level 0 is "no disparity found" (data README), open3d's is
// mostly a surface the depth sensor missed that "far" describes well (issue 32's table).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Runs `tool` on `config` in `sceneDir` twice, with auto and with `explicitSetting`; the outputs must
// be identical and the log must print `decision` for each of the two reference views.
void expectAutoEquals(const std::string& tool, const std::filesystem::path& sceneDir, const std::string& config,
                      const std::string& explicitSetting, const std::string& decision, const std::string& name) {
  const std::filesystem::path scratch = test::scratchDir("missing_auto_" + name);
  const std::string autoOut = (scratch / "auto.yuv").string(), explicitOut = (scratch / "explicit.yuv").string();
  const test::ToolResult autoRun =
      test::runTool(tool, config + " Threads=1 MissingDepthLevel=auto MissingDepthFill=auto OutputVirtualViewImageName=" +
                              test::quoted(autoOut),
                    scratch, sceneDir);
  ASSERT_EQ(autoRun.exitCode, 0) << autoRun.err;
  const test::ToolResult explicitRun = test::runTool(
      tool, config + " Threads=1 " + explicitSetting + " OutputVirtualViewImageName=" + test::quoted(explicitOut), scratch,
      sceneDir);
  ASSERT_EQ(explicitRun.exitCode, 0) << explicitRun.err;
  for (const char* view : {"Left: ", "Right: "}) {
    const size_t at = autoRun.out.find(std::string("depth level 0 (auto), ") + view);
    ASSERT_NE(at, std::string::npos) << autoRun.out;
    const std::string line = autoRun.out.substr(at, autoRun.out.find('\n', at) - at);
    EXPECT_NE(line.find(decision), std::string::npos) << line;
  }
  const std::string autoBytes = fileBytes(autoOut);
  EXPECT_FALSE(autoBytes.empty());
  EXPECT_TRUE(autoBytes == fileBytes(explicitOut)) << name << ": auto differs from " << explicitSetting;
}

TEST(MissingDepthAutoTools, MiddleburyLevelZeroIsMissingAndFilledInEveryPath) {
  const std::filesystem::path scene = test::dataDir() / "middlebury2006" / "Rocks2";
  VS_REQUIRE_DIR(scene);
  const std::string filled = "MissingDepthLevel=0 MissingDepthFill=1";
  const std::string decision = "treated as missing, filled from the farther side";
  expectAutoEquals("ViewSyn", scene, "synth_view3_general.cfg", filled, decision, "rocks2_general");
  expectAutoEquals("ViewSyn", scene, "synth_view3_1d.cfg", filled, decision, "rocks2_1d");
  expectAutoEquals("MeshRender", scene, "synth_view3_general.cfg", filled, decision, "rocks2_mesh");
}

TEST(MissingDepthAutoTools, Open3dLevelZeroStaysFar) {
  const std::filesystem::path scene = test::dataDir() / "open3d" / "RGBD5";
  VS_REQUIRE_DIR(scene);
  expectAutoEquals("ViewSyn", scene, "synth_view2_general.cfg", "MissingDepthLevel=-1", "kept as Zfar", "open3d");
}

}  // namespace
}  // namespace vs
