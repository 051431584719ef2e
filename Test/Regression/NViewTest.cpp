// N reference views and MPEG-I JSON cameras, end to end with the executables on SceneGen scenes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"
#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

double meanPsnrY(const std::string& output) {
  const size_t at = output.find("mean PSNR: Y ");
  if (at == std::string::npos) return -1;
  return std::stod(output.substr(at + 13));
}

// A 5-camera parallel rig of SceneGen's tiny scene (static, so one frame suffices).
fs::path makeRig(const std::string& name) {
  const fs::path dir = test::scratchDir(name);
  const test::ToolResult result = test::runTool(
      "SceneGen", "Scene=tiny CameraCount=5 TotalNumberOfFrames=2 OutputFolder=" + test::quoted((dir / "rig").string()), dir);
  EXPECT_EQ(result.exitCode, 0) << result.err;
  return dir / "rig";
}

// A config synthesizing cam2 from the listed cameras with the Reference keys, depth ranges taken
// from the generated viewsyn config.
std::string referenceConfig(const fs::path& rig, const std::vector<int>& cameras) {
  const Config generated = Config::load(viewSynOptionTable(), (rig / "viewsyn_cam2.cfg").string(), {});
  std::string names, textures, depths, nears, fars;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const std::string c = std::to_string(cameras[k]), sep = k ? "," : "";
    names += sep + "cam" + c;
    textures += sep + "texture_cam" + c + ".yuv";
    depths += sep + "depth_cam" + c + ".yuv";
    nears += sep + generated.raw("LeftNearestDepthValue");
    fars += sep + generated.raw("LeftFarthestDepthValue");
  }
  return "SourceWidth " + generated.raw("SourceWidth") + "\nSourceHeight " + generated.raw("SourceHeight") +
         "\nTotalNumberOfFrames 2\nCameraParameterFile cameras.txt\nVirtualCameraName cam2\n"
         "ReferenceCameraNames " + names + "\nReferenceViewImageNames " + textures + "\nReferenceDepthMapNames " + depths +
         "\nReferenceNearestDepthValues " + nears + "\nReferenceFarthestDepthValues " + fars +
         "\nReferenceVirtualViewImageName texture_cam2.yuv\nSynthesisMode 0\nPrecision 4\nFilter 1\n";
}

TEST(NView, MoreReferenceViewsScoreHigher) {
  const fs::path rig = makeRig("nview_more");
  std::ofstream(rig / "two.cfg") << referenceConfig(rig, {0, 4}) << "OutputVirtualViewImageName two.yuv\n";
  std::ofstream(rig / "four.cfg") << referenceConfig(rig, {0, 1, 3, 4}) << "OutputVirtualViewImageName four.yuv\n";
  const test::ToolResult two = test::runTool("ViewSyn", test::quoted((rig / "two.cfg").string()), rig);
  const test::ToolResult four = test::runTool("ViewSyn", test::quoted((rig / "four.cfg").string()), rig);
  ASSERT_EQ(two.exitCode, 0) << two.err;
  ASSERT_EQ(four.exitCode, 0) << four.err;
  EXPECT_NE(four.out.find("Reference 4"), std::string::npos) << four.out;
  EXPECT_GT(meanPsnrY(four.out), meanPsnrY(two.out) + 0.5) << two.out << four.out;
  // The Left/Right keys still mean what they did: the same two views give the same picture.
  std::ofstream(rig / "lr.cfg") << readText(rig / "viewsyn_cam2.cfg") << "\nLeftCameraName cam0\nLeftViewImageName texture_cam0.yuv\n"
                                << "LeftDepthMapName depth_cam0.yuv\nRightCameraName cam4\nRightViewImageName texture_cam4.yuv\n"
                                << "RightDepthMapName depth_cam4.yuv\nSynthesisMode 0\nPrecision 4\nFilter 1\n"
                                << "OutputVirtualViewImageName lr.yuv\n";
  const test::ToolResult leftRight = test::runTool("ViewSyn", test::quoted((rig / "lr.cfg").string()), rig);
  ASSERT_EQ(leftRight.exitCode, 0) << leftRight.err;
  EXPECT_TRUE(readText(rig / "lr.yuv") == readText(rig / "two.yuv"));
}

TEST(NView, ReferenceKeysAreCheckedTogether) {
  const std::string base =
      "CameraParameterFile c.txt\nVirtualCameraName v\nOutputVirtualViewImageName o.yuv\nSourceWidth 16\nSourceHeight 8\n";
  auto problems = [&](const std::string& extra) {
    try {
      readSynthesisSettings(Config::fromText(viewSynOptionTable(), base + extra, "n.cfg", "/tmp"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(problems("ReferenceCameraNames a,b,c\nReferenceViewImageNames a,b,c\nReferenceDepthMapNames da,db,dc\n"), "");
  EXPECT_NE(problems("ReferenceCameraNames a,b,c\nReferenceViewImageNames a,b\nReferenceDepthMapNames da,db,dc\n")
                .find("ReferenceViewImageNames lists 2 items but ReferenceCameraNames 3"),
            std::string::npos);
  EXPECT_NE(problems("ReferenceCameraNames a\nReferenceViewImageNames a\nReferenceDepthMapNames d\nLeftCameraName x\n")
                .find("'LeftCameraName' and ReferenceCameraNames exclude each other"),
            std::string::npos);
  EXPECT_NE(problems("ReferenceCameraNames a,,b\n").find("without empty items"), std::string::npos);
  std::string tooMany, files;
  for (int k = 0; k < 33; ++k) tooMany += (k ? "," : "") + std::to_string(k);
  EXPECT_NE(problems("ReferenceCameraNames " + tooMany + "\nReferenceViewImageNames " + tooMany +
                     "\nReferenceDepthMapNames " + tooMany + "\n")
                .find("at most 32"),
            std::string::npos);
}

// A JSON camera file gives depth ranges and bit depths; synthesizing from it and from its VSRS text
// conversion gives bit-identical output.
TEST(NView, JsonCamerasAndTheirTextConversionSynthesizeIdentically) {
  const fs::path rig = makeRig("nview_json");
  const Config generated = Config::load(viewSynOptionTable(), (rig / "viewsyn_cam2.cfg").string(), {});
  const std::string range = generated.raw("LeftNearestDepthValue") + " " + generated.raw("LeftFarthestDepthValue");
  ASSERT_EQ(test::runTool("CameraConvert", "cameras.txt cameras.json --depth-range " + range + " --bitdepth-depth 8", rig, rig).exitCode, 0);
  ASSERT_EQ(test::runTool("CameraConvert", "cameras.json cameras_back.txt", rig, rig).exitCode, 0);
  // No depth values in the config: the JSON's Depth_range is used.
  std::string config;
  std::istringstream lines(readText(rig / "viewsyn_cam2.cfg"));
  for (std::string line; std::getline(lines, line);)
    if (line.find("DepthValue") == std::string::npos && line.find("CameraParameterFile") == std::string::npos) config += line + "\n";
  std::ofstream(rig / "json.cfg") << config << "CameraParameterFile cameras.json\nOutputVirtualViewImageName json.yuv\n";
  const test::ToolResult json = test::runTool("ViewSyn", "json.cfg", rig, rig);
  ASSERT_EQ(json.exitCode, 0) << json.err;
  std::ofstream(rig / "text.cfg") << config << "CameraParameterFile cameras_back.txt\nOutputVirtualViewImageName text.yuv\n"
                                  << "LeftNearestDepthValue " << generated.raw("LeftNearestDepthValue") << "\nLeftFarthestDepthValue "
                                  << generated.raw("LeftFarthestDepthValue") << "\nRightNearestDepthValue "
                                  << generated.raw("LeftNearestDepthValue") << "\nRightFarthestDepthValue "
                                  << generated.raw("LeftFarthestDepthValue") << "\n";
  const test::ToolResult text = test::runTool("ViewSyn", "text.cfg", rig, rig);
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_GT(meanPsnrY(json.out), 25.0);
  EXPECT_TRUE(readText(rig / "json.yuv") == readText(rig / "text.yuv"));
  // Without a JSON range and without keys, the depth range is missing: a clear error.
  std::ofstream(rig / "none.cfg") << config << "CameraParameterFile cameras_back.txt\nOutputVirtualViewImageName none.yuv\n";
  const test::ToolResult none = test::runTool("ViewSyn", "none.cfg", rig, rig);
  EXPECT_EQ(none.exitCode, 1);
  EXPECT_NE(none.err.find("no depth range for camera 'cam1'"), std::string::npos) << none.err;
}

// OutputVirtualDepthMapName writes the virtual depth: on SceneGen's exact scene it matches the
// virtual camera's own depth map almost everywhere.
TEST(NView, VirtualDepthOutputMatchesTheTrueDepth) {
  const fs::path rig = makeRig("nview_depth");
  const test::ToolResult run = test::runTool(
      "ViewSyn", "viewsyn_cam2.cfg OutputVirtualDepthMapName=virtual_depth.yuv SynthesisMode=0", rig, rig);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Config generated = Config::load(viewSynOptionTable(), (rig / "viewsyn_cam2.cfg").string(), {});
  const FrameFormat format{int(generated.getInt("SourceWidth")), int(generated.getInt("SourceHeight")), 8, ChromaFormat::Yuv420};
  YuvReader truth((rig / "depth_cam2.yuv").string(), format), synthesized((rig / "virtual_depth.yuv").string(), format);
  ASSERT_EQ(synthesized.frameCount(), 2);
  Plane a, b;
  truth.readLuma(0, a);
  synthesized.readLuma(0, b);
  size_t close = 0;
  for (size_t i = 0; i < a.samples.size(); ++i) close += std::abs(int(a.samples[i]) - int(b.samples[i])) <= 2 ? 1 : 0;
  EXPECT_GT(double(close) / double(a.samples.size()), 0.95);
}

}  // namespace
}  // namespace vs
