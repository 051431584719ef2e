// RVS synthesis configs (Common/RvsConfig.h): recognised by content, translated key by key into ours
// with RVS's path rule (the working folder), its camera overrides, its depth conventions (far >= 1000
// is infinitely far, level 0 is "no depth"), refused where we cannot honour a key; pose traces.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "Common/CameraJson.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/RvsConfig.h"
#include "Common/Scene.h"
#include "Plan/Plan.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

// Runs the test body with the working folder set to `dir` (RVS names are relative to it), restoring it.
class WorkingFolder {
public:
  explicit WorkingFolder(const fs::path& dir) : previous_(fs::current_path()) { fs::current_path(dir); }
  ~WorkingFolder() { fs::current_path(previous_); }

private:
  fs::path previous_;
};

// Three perspective cameras in MPEG-I JSON written by hand (independent of our writer): v0 and v1 as
// references, vv the virtual camera; v1 with a far plane of 1000 (RVS: infinitely far).
void writeCameras(const fs::path& path, const std::string& virtualResolution = "[64, 32]") {
  std::ofstream(path) << R"({ "Version": "3.0", "cameras": [
  { "Name": "v0", "Position": [0, 0.1, 0], "Rotation": [0, 0, 0], "Depthmap": 1, "Background": 0,
    "Resolution": [64, 32], "Projection": "Perspective", "Focal": [50, 50], "Principle_point": [32, 16],
    "Depth_range": [0.5, 25], "BitDepthColor": 10, "BitDepthDepth": 10, "ColorSpace": "YUV420", "DepthColorSpace": "YUV420" },
  { "Name": "v1", "Position": [0, -0.1, 0], "Rotation": [0, 0, 0], "Depthmap": 1, "Background": 0,
    "Resolution": [64, 32], "Projection": "Perspective", "Focal": [50, 50], "Principle_point": [32, 16],
    "Depth_range": [0.8, 1000], "BitDepthColor": 10, "BitDepthDepth": 10, "ColorSpace": "YUV420", "DepthColorSpace": "YUV420" },
  { "Name": "vv", "Position": [0, 0, 0], "Rotation": [0, 0, 0], "Depthmap": 1, "Background": 0,
    "Resolution": )" << virtualResolution
                      << R"(, "Projection": "Perspective", "Focal": [50, 50], "Principle_point": [32, 16],
    "Depth_range": [0.5, 20], "BitDepthColor": 10, "BitDepthDepth": 12, "ColorSpace": "YUV420", "DepthColorSpace": "YUV420" }
] }
)";
}

std::string baseConfig(const std::string& extra = "") {
  return R"({
  "Version": "2.0",
  "_NOTE": "a comment",
  "InputCameraParameterFile": "cams/cameras.json",
  "VirtualCameraParameterFile": "cams/cameras.json",
  "InputCameraNames": ["v0", "v1"],
  "VirtualCameraNames": ["vv", "v0"],
  "ViewImageNames": ["seq/t0.yuv", "seq/t1.yuv"],
  "DepthMapNames": ["seq/d0.yuv", "seq/d1.yuv"],
  "OutputFiles": ["out/vv.yuv", "out/v0.yuv"],
  "StartFrame": 3,
  "NumberOfFrames": 2,
  "Precision": 4.0,
  "ColorSpace": "YUV",
  "ViewSynthesisMethod": "Triangles",
  "BlendingMethod": "Multispectral",
  "BlendingLowFreqFactor": 1.0,
  "BlendingHighFreqFactor": 4.0)" +
         extra + "\n}\n";
}

struct RvsFixture : ::testing::Test {
  // One folder per test: ctest runs the tests of this fixture side by side.
  fs::path dir = test::scratchDir(std::string("rvs_config_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::path config = dir / "configs" / "rvs.json";  // in a subfolder: names are not relative to it
  void SetUp() override {
    fs::create_directories(dir / "cams");
    fs::create_directories(dir / "configs");
    writeCameras(dir / "cams" / "cameras.json");
  }
  void write(const std::string& text) { std::ofstream(config) << text; }
  std::string errorOf(const std::vector<std::string>& overrides = {}) {
    WorkingFolder folder(dir);
    try {
      Config::loadAll(viewSynOptionTable(), config.string(), overrides);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST(RvsConfig, RecognisedByContentNotByName) {
  EXPECT_TRUE(looksLikeJsonConfig("{}"));
  EXPECT_TRUE(looksLikeJsonConfig("\xEF\xBB\xBF \r\n\t{\"a\": 1}"));
  EXPECT_TRUE(looksLikeJsonConfig("[1, 2]"));  // JSON, refused later as not an object
  EXPECT_FALSE(looksLikeJsonConfig("SourceWidth 1024\n"));
  EXPECT_FALSE(looksLikeJsonConfig("# {\n"));
  EXPECT_FALSE(looksLikeJsonConfig(""));
}

TEST_F(RvsFixture, EveryKeyMapsOntoOursWithPathsFromTheWorkingFolder) {
  write(baseConfig());
  WorkingFolder folder(dir);
  const std::vector<Config> configs = Config::loadAll(viewSynOptionTable(), config.string(), {"Threads=2"});
  ASSERT_EQ(configs.size(), 2u);  // one per virtual camera
  // Without ViewSynthesisMethod, RVS's default ("Triangles") gives our general path too.
  std::string noMethod = baseConfig();
  noMethod.erase(noMethod.find("  \"ViewSynthesisMethod\": \"Triangles\",\n"), 38);
  std::ofstream(dir / "configs" / "nomethod.json") << noMethod;
  EXPECT_EQ(Config::loadAll(viewSynOptionTable(), (dir / "configs" / "nomethod.json").string(), {})[0].getString("SynthesisMode"), "0");
  const Config& c = configs[0];
  const std::string working = fs::current_path().string();
  EXPECT_EQ(c.getPath("CameraParameterFile"), working + "/cams/cameras.json");
  EXPECT_EQ(c.getPath("VirtualCameraParameterFile"), working + "/cams/cameras.json");
  EXPECT_EQ(c.getString("ReferenceCameraNames"), "v0,v1");
  EXPECT_EQ(c.getList("ReferenceViewImageNames"), (std::vector<std::string>{working + "/seq/t0.yuv", working + "/seq/t1.yuv"}));
  EXPECT_EQ(c.getList("ReferenceDepthMapNames"), (std::vector<std::string>{working + "/seq/d0.yuv", working + "/seq/d1.yuv"}));
  EXPECT_EQ(c.getString("VirtualCameraName"), "vv");
  EXPECT_EQ(configs[1].getString("VirtualCameraName"), "v0");
  EXPECT_EQ(c.getPath("OutputVirtualViewImageName"), working + "/out/vv.yuv");
  EXPECT_EQ(configs[1].getPath("OutputVirtualViewImageName"), working + "/out/v0.yuv");
  EXPECT_EQ(c.getInt("StartFrame"), 3);
  EXPECT_EQ(c.getInt("TotalNumberOfFrames"), 2);
  EXPECT_EQ(c.getString("Precision"), "4");
  EXPECT_EQ(c.getInt("ColorSpace"), 0);
  EXPECT_EQ(c.getString("SynthesisMode"), "0");
  // Formats from the cameras: 64 x 32, 10-bit 4:2:0 texture, 4:2:0 depth.
  EXPECT_EQ(c.getInt("SourceWidth"), 64);
  EXPECT_EQ(c.getInt("SourceHeight"), 32);
  EXPECT_EQ(c.getInt("TextureBitDepth"), 10);
  EXPECT_EQ(c.getString("ChromaFormat"), "420");
  EXPECT_EQ(c.getString("DepthChromaFormat"), "420");
  EXPECT_EQ(c.getInt("DepthBitDepth"), 10);
  // Depth: RVS reads a far plane of 1000 as infinite, and level 0 as "no depth".
  EXPECT_EQ(c.getString("ReferenceNearestDepthValues"), "0.5,0.8");
  EXPECT_EQ(c.getString("ReferenceFarthestDepthValues"), "25,inf");
  EXPECT_EQ(c.getInt("MissingDepthLevel"), 0);
  // Key=Value overrides apply to every virtual camera's configuration.
  EXPECT_EQ(c.getInt("Threads"), 2);
  EXPECT_EQ(configs[1].getInt("Threads"), 2);
  // Where a value came from: the RVS config's line.
  EXPECT_EQ(c.origin("ReferenceCameraNames"), config.string() + ":6");
  // Config::load reads one virtual camera only, and says why not more.
  try {
    Config::load(viewSynOptionTable(), config.string(), {});
    ADD_FAILURE() << "two virtual cameras read by Config::load";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("names 2 virtual cameras"), std::string::npos) << e.what();
  }
}

TEST_F(RvsFixture, TheSceneTakesItsCamerasDepthBitsAndOverrides) {
  write(baseConfig(R"(,
  "InputOverrides": {"BitDepthDepth": 16, "Depth_range": [0.25, 50]},
  "VirtualOverrides": {"Position": [0.5, 0, 0]},
  "DepthOutputFiles": ["out/vv_depth.yuv", "out/v0_depth.yuv"])"));
  WorkingFolder folder(dir);
  const std::vector<Config> configs = Config::loadAll(viewSynOptionTable(), config.string(), {});
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_EQ(configs[0].getString("InputCameraOverrides"), R"({"BitDepthDepth":16,"Depth_range":[0.25,50]})");
  EXPECT_EQ(configs[0].getString("ReferenceNearestDepthValues"), "0.25,0.25");
  EXPECT_EQ(configs[0].getString("ReferenceFarthestDepthValues"), "50,50");
  const Scene scene = loadScene(configs[0]);
  ASSERT_EQ(scene.settings.references.size(), 2u);
  for (const ReferenceView& view : scene.settings.references) {
    EXPECT_EQ(view.depthFormat.bitDepth, 16);  // the override, not the file's 10
    EXPECT_EQ(view.depthRange.znear, 0.25);
    EXPECT_EQ(view.depthRange.zfar, 50);
  }
  // The virtual camera moved 0.5 forward (MPEG-I x is our z); the references did not move.
  EXPECT_DOUBLE_EQ(scene.virtualCamera.t.z, 0.5);
  EXPECT_DOUBLE_EQ(scene.settings.references[0].camera.t.z, 0.0);
  EXPECT_DOUBLE_EQ(scene.settings.references[0].camera.t.x, -0.1);  // MPEG-I y (left) is our -x
  // The virtual depth output: the virtual camera's range, in the inputs' depth bit depth (DepthBitDepth).
  EXPECT_EQ(configs[0].getInt("DepthBitDepth"), 16);
  EXPECT_EQ(scene.settings.virtualDepthRange.znear, 0.5);
  EXPECT_EQ(scene.settings.virtualDepthRange.zfar, 20);
  EXPECT_EQ(scene.settings.virtualDepthRange.bitDepth, 16);
  EXPECT_EQ(configs[1].getPath("OutputVirtualDepthMapName"), fs::current_path().string() + "/out/v0_depth.yuv");
}

TEST_F(RvsFixture, WhatWeCannotHonourIsRefusedNamingFileLineAndKey) {
  struct Case {
    std::string extra;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {",\n  \"BlendingFactr\": 1.0", "rvs.json:19: unknown RVS key \"BlendingFactr\" (did you mean \"BlendingFactor\"?)"},
      {",\n  \"MaskedOutputFiles\": [\"m0.yuv\", \"m1.yuv\"]", "rvs.json:19: \"MaskedOutputFiles\": masked textures are not written"},
      {",\n  \"OutputMasks\": [\"m0.yuv\"]", "\"OutputMasks\" lists 1 files for 2 VirtualCameraNames"},
      {",\n  \"DepthOutputFiles\": [\"d.yuv\"]", "\"DepthOutputFiles\" lists 1 files for 2 VirtualCameraNames"},
      {",\n  \"VirtualPoseTraceName\": 3", "\"VirtualPoseTraceName\" must be a non-empty string"},
  };
  for (const Case& c : cases) {
    write(baseConfig(c.extra));
    const std::string error = errorOf();
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.extra << "\n" << error;
  }
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::vector<Case> values = {
      {replaced(baseConfig(), "\"Precision\": 4.0", "\"Precision\": 3.0"), "rvs.json:13: \"Precision\" 3: 1, 2 or 4 expected"},
      {replaced(baseConfig(), "\"Triangles\"", "\"Squares\""), "rvs.json:15: \"ViewSynthesisMethod\" 'Squares'"},
      {replaced(baseConfig(), "\"Multispectral\"", "\"Max\""), "rvs.json:16: \"BlendingMethod\" 'Max'"},
      {replaced(baseConfig(), "\"YUV\"", "\"XYZ\""), "\"ColorSpace\" 'XYZ'"},
      {replaced(baseConfig(), ", \"seq/d1.yuv\"]", "]"), "rvs.json:9: \"DepthMapNames\" lists 1 files for 2 InputCameraNames"},
      {replaced(baseConfig(), "\"Version\": \"2.0\"", "\"Version\": \"1.0\""), "\"Version\" '1.0'"},
      {replaced(baseConfig(), "\"v1\"]", "\"v,1\"]"), "holds a comma"},
      {replaced(baseConfig(), "\"OutputFiles\": [\"out/vv.yuv\", \"out/v0.yuv\"],", ""), "missing RVS key \"OutputFiles\""},
      {"[1, 2]", "an RVS config is a JSON object"},
      {"{\"cameras\": []}", "this is a camera parameter file"},
  };
  for (const Case& c : values) {
    write(c.extra);
    const std::string error = errorOf();
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.extra << "\n" << error;
  }
  // Every problem at once: two bad keys give two lines.
  write(baseConfig(",\n  \"Foo\": 1,\n  \"MaskedOutputFiles\": [\"a\", \"b\"]"));
  const std::string both = errorOf();
  EXPECT_NE(both.find("\"Foo\""), std::string::npos) << both;
  EXPECT_NE(both.find("\"MaskedOutputFiles\""), std::string::npos) << both;
  // Our own keys given as overrides are checked as ever.
  write(baseConfig());
  EXPECT_NE(errorOf({"Precision=3"}).find("Precision = '3'"), std::string::npos);
}

TEST_F(RvsFixture, AVirtualCameraOfAnotherSizeGivesTheVirtualViewItsResolution) {
  writeCameras(dir / "cams" / "cameras.json", "[128, 64]");
  write(baseConfig());
  EXPECT_EQ(errorOf(), "");
  WorkingFolder folder(dir);
  std::vector<Config> configs = Config::loadAll(viewSynOptionTable(), config.string(), {});
  ASSERT_EQ(configs.size(), 2u);
  // RVS writes each virtual view at its camera's Resolution: 'vv' at 128x64, v0 at the inputs' 64x32.
  EXPECT_EQ(configs[0].getInt("VirtualWidth"), 128);
  EXPECT_EQ(configs[0].getInt("VirtualHeight"), 64);
  EXPECT_EQ(configs[0].origin("VirtualWidth"), config.string() + ":5");  // VirtualCameraParameterFile's line
  EXPECT_EQ(configs[1].getInt("VirtualWidth"), 0);
  EXPECT_EQ(loadScene(configs[0]).settings.virtualFormat().width, 128);
  // VirtualOverrides bring it back to the inputs' size.
  write(baseConfig(",\n  \"VirtualOverrides\": {\"Resolution\": [64, 32]}"));
  configs = Config::loadAll(viewSynOptionTable(), config.string(), {});
  EXPECT_EQ(configs[0].getInt("VirtualWidth"), 0);
}

TEST_F(RvsFixture, MasksBecomeOurMaskOutputs) {
  write(baseConfig(R"(,
  "OutputMasks": ["out/vv_mask.yuv", "out/v0_mask.yuv"],
  "MaskedDepthOutputFiles": ["out/vv_masked.yuv", "out/v0_masked.yuv"])"));
  WorkingFolder folder(dir);
  const std::vector<Config> configs = Config::loadAll(viewSynOptionTable(), config.string(), {});
  ASSERT_EQ(configs.size(), 2u);
  const std::string working = fs::current_path().string();
  EXPECT_EQ(configs[0].getPath("OutputVirtualMaskName"), working + "/out/vv_mask.yuv");
  EXPECT_EQ(configs[1].getPath("OutputMaskedVirtualDepthMapName"), working + "/out/v0_masked.yuv");
  EXPECT_EQ(configs[0].origin("OutputVirtualMaskName"), config.string() + ":19");
  // The masked depth is written in the virtual camera's depth range, as DepthOutputFiles would be.
  EXPECT_EQ(configs[0].getDouble("VirtualNearestDepthValue"), 0.5);
  EXPECT_EQ(configs[0].getDouble("VirtualFarthestDepthValue"), 20);
  const Scene scene = loadScene(configs[0]);
  EXPECT_TRUE(scene.settings.wantsMask());
  EXPECT_TRUE(makePlan(scene).virtualMaskOutput);
  // MeshRender reads the keys, and its plan refuses them.
  const Config mesh = Config::loadAll(meshRenderOptionTable(), config.string(), {})[0];
  EXPECT_THROW(makePlan(loadScene(mesh), Tool::MeshRender), InputError);
}

TEST(RvsPoseTrace, ReadsRvsCsvAndRefusesMalformedRows) {
  const std::vector<Pose> poses =
      parsePoseTrace("X, Y, Z, Yaw, Pitch, Roll\r\n0.1429, 0.0777, -0.2628, 28.5324, 40.3759, 0\n1,2,3,4,5,6\n\n\n", "t.csv");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].x, 0.1429);
  EXPECT_EQ(poses[0].z, -0.2628);
  EXPECT_EQ(poses[0].pitch, 40.3759);
  EXPECT_EQ(poses[1].roll, 6);
  auto error = [](const std::string& text) {
    try {
      parsePoseTrace(text, "t.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("X, Y, Z, Yaw, Pitch\n1,2,3,4,5\n").find("t.csv:1: a pose trace starts with the header"), std::string::npos);
  EXPECT_NE(error("X,Y,Z,Yaw,Pitch,Roll\n1,2,3,4,5\n").find("t.csv:2: six numbers expected"), std::string::npos);
  EXPECT_NE(error("X,Y,Z,Yaw,Pitch,Roll\n1,2,3,4,5,x\n").find("t.csv:2: six numbers expected"), std::string::npos);
  EXPECT_NE(error("X,Y,Z,Yaw,Pitch,Roll\n1,2,3,4,5,6\n\n1,2,3,4,5,6\n").find("t.csv:4: a pose after a blank line"),
            std::string::npos);
  EXPECT_NE(error("").find("empty pose trace"), std::string::npos);
}

TEST(RvsPoseTrace, APoseMovesByItsPositionAndTurnsToItsAngles) {
  Camera base;
  base.t = Vec3(1, 2, 3);
  base.R = rotationFromYawPitchRoll(10, 20, 30);  // replaced by the pose's angles
  Pose pose;
  pose.x = 0.5;   // forward in MPEG-I axes: our +z
  pose.y = 0.25;  // left: our -x
  pose.z = 0.125; // up: our -y
  pose.yaw = 90;  // turned to the left
  const Camera moved = posedCamera(base, pose);
  EXPECT_DOUBLE_EQ(moved.t.x, 1 - 0.25);
  EXPECT_DOUBLE_EQ(moved.t.y, 2 - 0.125);
  EXPECT_DOUBLE_EQ(moved.t.z, 3 + 0.5);
  // The optical axis (our camera z, row 2 of R) now points to MPEG-I +y (left), our -x; "up" (our
  // camera -y, minus row 1) stays our world -y.
  EXPECT_NEAR(moved.R[2][0], -1, 1e-12);
  EXPECT_NEAR(moved.R[2][1], 0, 1e-12);
  EXPECT_NEAR(moved.R[2][2], 0, 1e-12);
  EXPECT_NEAR(moved.R[1][1], 1, 1e-12);
}

TEST_F(RvsFixture, ThePoseTraceGivesEachFrameItsCamera) {
  std::ofstream(dir / "trace.csv") << "X, Y, Z, Yaw, Pitch, Roll\n0,0,0,0,0,0\n0,0,0,0,0,0\n0,0,0,0,0,0\n"
                                      "0.5,0,0,0,0,0\n0,0,0.25,5,0,0\n";
  write(baseConfig(",\n  \"VirtualPoseTraceName\": \"trace.csv\""));
  WorkingFolder folder(dir);
  const std::vector<Config> configs = Config::loadAll(viewSynOptionTable(), config.string(), {});
  const Scene scene = loadScene(configs[0]);
  ASSERT_EQ(scene.virtualCameraPerFrame.size(), 2u);  // StartFrame 3, two frames: rows 3 and 4
  EXPECT_DOUBLE_EQ(scene.virtualCameraPerFrame[0].t.z, 0.5);
  EXPECT_DOUBLE_EQ(scene.virtualCameraPerFrame[1].t.y, -0.25);
  // Too short a trace: StartFrame 3 and three frames need five rows.
  const std::vector<Config> longer = Config::loadAll(viewSynOptionTable(), config.string(), {"TotalNumberOfFrames=3"});
  try {
    loadScene(longer[0]);
    ADD_FAILURE() << "a short pose trace was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("VirtualPoseTraceName holds 5 poses; frames 3 to 5 need 6"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vs
