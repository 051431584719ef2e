// The executables with equirectangular cameras: SceneGen renders the room scene from an ERP rig, ViewSyn
// synthesizes the ERP camera between two others and scores it with WS-PSNR, MeshRender refuses ERP,
// CameraConvert keeps ERP cameras in JSON and refuses them in the VSRS text format.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "Common/Camera.h"
#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

Camera erpCamera(const std::string& name, double x) {
  Camera c;
  c.name = name;
  c.projection = Projection::Equirectangular;
  c.erp.width = 64;
  c.erp.height = 32;
  c.t = Vec3(x, 0, 0);
  return c;
}

TEST(EquirectangularTools, SceneGenViewSynMeshRenderAndCameraConvert) {
  const fs::path root = test::scratchDir("erp_tools");
  const std::string rig = (root / "rig.json").string();
  CameraInfo info;
  info.width = 64;
  info.height = 32;
  writeCameraJson(rig, {erpCamera("a", -0.15), erpCamera("m", 0.02), erpCamera("b", 0.15)}, {info, info, info});
  const std::string scene = (fs::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string();
  const test::ToolResult generated =
      test::runTool("SceneGen",
                    test::quoted("SceneFile=" + scene) + " Rig=file " + test::quoted("CameraParameterFile=" + rig) +
                        " SourceWidth=64 SourceHeight=32 DepthBitDepth=16 " +
                        test::quoted("OutputFolder=" + (root / "out").string()),
                    root);
  ASSERT_EQ(generated.exitCode, 0) << generated.err;
  ASSERT_TRUE(fs::exists(root / "out" / "cameras.json"));
  ASSERT_FALSE(fs::exists(root / "out" / "cameras.txt"));

  const test::ToolResult synthesized =
      test::runTool("ViewSyn", "viewsyn_m.cfg OutputVirtualViewImageName=out_m.yuv SynthesisMode=auto", root, root / "out");
  ASSERT_EQ(synthesized.exitCode, 0) << synthesized.err;
  EXPECT_NE(synthesized.out.find("wspsnr_y"), std::string::npos) << synthesized.out;
  EXPECT_NE(synthesized.out.find("equirectangular 64x32"), std::string::npos);
  EXPECT_NE(synthesized.out.find("an equirectangular camera"), std::string::npos);  // auto: why not the 1D path

  const test::ToolResult mesh = test::runTool("MeshRender", "--check meshrender_m.cfg", root, root / "out");
  EXPECT_EQ(mesh.exitCode, 1);
  EXPECT_NE(mesh.err.find("is equirectangular: MeshRender renders pinhole cameras only"), std::string::npos) << mesh.err;

  const std::string cameras = (root / "out" / "cameras.json").string();
  const test::ToolResult toText =
      test::runTool("CameraConvert", test::quoted(cameras) + " " + test::quoted((root / "c.txt").string()), root);
  EXPECT_EQ(toText.exitCode, 1);
  EXPECT_NE(toText.err.find("VSRS text format holds pinhole cameras only"), std::string::npos) << toText.err;
  EXPECT_FALSE(fs::exists(root / "c.txt"));
  const test::ToolResult resized = test::runTool(
      "CameraConvert", test::quoted(cameras) + " " + test::quoted((root / "c.json").string()) + " --resolution 32 16", root);
  EXPECT_EQ(resized.exitCode, 1);
  EXPECT_NE(resized.err.find("Resolution is part of the camera"), std::string::npos) << resized.err;
  const test::ToolResult toJson =
      test::runTool("CameraConvert", test::quoted(cameras) + " " + test::quoted((root / "c.json").string()), root);
  ASSERT_EQ(toJson.exitCode, 0) << toJson.err;
  const CameraFile back = readCameraFile((root / "c.json").string());
  ASSERT_EQ(back.cameras().size(), 3u);
  for (const Camera& c : back.cameras()) {
    EXPECT_TRUE(c.isEquirectangular()) << c.name;
    EXPECT_EQ(c.erp.width, 64);
    EXPECT_EQ(c.erp.lonMin, -180);
    EXPECT_EQ(c.erp.latMax, 90);
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace vs
