// The executables with equirectangular cameras: SceneGen renders the room scene from an ERP rig, ViewSyn
// synthesizes the ERP camera between two others and scores it with WS-PSNR, so does MeshRender,
// CameraConvert keeps ERP cameras in JSON and refuses them in the VSRS text format.
#include <gtest/gtest.h>

#include <cstdio>
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

  // MeshRender renders the same ERP rig (Mesh/MeshErp.h), scored the same way, about as well.
  ASSERT_EQ(test::runTool("MeshRender", "--check meshrender_m.cfg", root, root / "out").exitCode, 0);
  const test::ToolResult mesh =
      test::runTool("MeshRender", "meshrender_m.cfg OutputVirtualViewImageName=mesh_m.yuv", root, root / "out");
  ASSERT_EQ(mesh.exitCode, 0) << mesh.err;
  EXPECT_NE(mesh.out.find("wspsnr_y"), std::string::npos) << mesh.out;
  EXPECT_NE(mesh.out.find("equirectangular camera(s): the mesh is taken into the virtual camera"), std::string::npos)
      << mesh.out;
  const auto meanPsnrY = [](const std::string& out) {
    const size_t at = out.find("mean PSNR: Y ");
    return at == std::string::npos ? -1.0 : std::stod(out.substr(at + 13));
  };
  std::printf("room 64x32, ERP virtual camera: mean PSNR-Y ViewSyn %.2f dB, MeshRender %.2f dB\n",
              meanPsnrY(synthesized.out), meanPsnrY(mesh.out));
  EXPECT_GE(meanPsnrY(mesh.out), meanPsnrY(synthesized.out) - 2.0) << mesh.out;

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
