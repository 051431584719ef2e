// SceneGen's outputs: camera file round trip, ViewSyn and MeshRender configs that load, frames that
// move, the automatic depth range, settings and the executable's messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "Common/CameraFile.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"
#include "Scene/SceneGen.h"
#include "Scene/Scenes.h"
#include "Process.h"
#include "TestPaths.h"


namespace vs {
namespace {

namespace fs = std::filesystem;

SceneGenSettings settingsFrom(const std::vector<std::string>& overrides) {
  return readSceneGenSettings(Config::load(sceneGenOptionTable(), "", overrides));
}

SceneGenResult generate(const std::vector<std::string>& overrides, const fs::path& folder) {
  std::vector<std::string> all = overrides;
  all.push_back("OutputFolder=" + folder.string());
  std::ostringstream log;
  return generateScene(settingsFrom(all), log);
}

std::string errorOf(const std::vector<std::string>& overrides) {
  try {
    settingsFrom(overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void expectSameCameras(const std::vector<Camera>& read, const std::vector<Camera>& written) {
  ASSERT_EQ(read.size(), written.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].name, written[i].name);
    EXPECT_EQ(read[i].K, written[i].K) << read[i].name;
    EXPECT_EQ(read[i].R, written[i].R) << read[i].name;
    EXPECT_EQ(read[i].t, written[i].t) << read[i].name;
  }
}

TEST(SceneGenOutputTest, WrittenCameraFileReadsBackEqual) {
  for (const char* scene : {"tiny", "arc"}) {
    SCOPED_TRACE(scene);
    const auto folder = test::scratchDir(std::string("scenegen_cameras_") + scene);
    const SceneGenResult result = generate(
        {std::string("Scene=") + scene, "TotalNumberOfFrames=1", "SourceWidth=64", "SourceHeight=48", "AntiAliasing=1"},
        folder);
    EXPECT_EQ(result.cameraFile, (folder / "cameras.txt").string());
    const CameraFile file = readCameraFile(result.cameraFile);
    EXPECT_TRUE(file.warnings().empty());
    expectSameCameras(file.cameras(), result.cameras);
    for (size_t i = 0; i < result.cameras.size(); ++i) EXPECT_EQ(result.cameras[i].name, "cam" + std::to_string(i));
  }
}

TEST(SceneGenOutputTest, FileRigRendersTheSameAsTheRigItWasWrittenFrom) {
  const auto arcFolder = test::scratchDir("scenegen_rig_arc");
  const auto fileFolder = test::scratchDir("scenegen_rig_file");
  const std::vector<std::string> common{"Scene=arc",       "TotalNumberOfFrames=1", "SourceWidth=80",
                                        "SourceHeight=60", "NearestDepthValue=2",   "FarthestDepthValue=20"};
  const SceneGenResult arc = generate(common, arcFolder);
  std::vector<std::string> fromFile = common;
  fromFile.push_back("Rig=file");
  fromFile.push_back("CameraParameterFile=" + arc.cameraFile);
  const SceneGenResult file = generate(fromFile, fileFolder);
  expectSameCameras(file.cameras, arc.cameras);
  for (size_t c = 0; c < arc.cameras.size(); ++c) {
    std::ifstream a(arc.texturePaths[c], std::ios::binary), b(file.texturePaths[c], std::ios::binary);
    const std::string bytesA((std::istreambuf_iterator<char>(a)), {}), bytesB((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(bytesA.empty());
    EXPECT_EQ(bytesA, bytesB) << arc.texturePaths[c];
  }
}

TEST(SceneGenOutputTest, WrittenConfigsAreValidViewSynAndMeshRenderConfigs) {
  const auto folder = test::scratchDir("scenegen_configs");
  const SceneGenResult result = generate({"Scene=tiny", "CameraCount=4", "DepthBitDepth=16"}, folder);
  ASSERT_EQ(result.viewSynConfigs.size(), 2u);  // cam1 from cam0 + cam2, cam2 from cam1 + cam3
  ASSERT_EQ(result.meshRenderConfigs.size(), 2u);
  for (size_t k = 0; k < result.viewSynConfigs.size(); ++k) {
    EXPECT_EQ(fs::path(result.viewSynConfigs[k]).filename(), "viewsyn_cam" + std::to_string(k + 1) + ".cfg");
    EXPECT_EQ(fs::path(result.meshRenderConfigs[k]).filename(), "meshrender_cam" + std::to_string(k + 1) + ".cfg");
    for (bool mesh : {false, true}) {
      const std::string path = mesh ? result.meshRenderConfigs[k] : result.viewSynConfigs[k];
      SCOPED_TRACE(path);
      const Config config = Config::load(mesh ? meshRenderOptionTable() : viewSynOptionTable(), path, {});
      const Scene scene = loadScene(config);
      const SynthesisSettings& s = scene.settings;
      EXPECT_TRUE(scene.warnings.empty());
      EXPECT_EQ(s.depthType, 0);
      EXPECT_EQ(s.textureFormat, (FrameFormat{64, 48, 8, ChromaFormat::Yuv420}));
      EXPECT_EQ(s.depthFormat, (FrameFormat{64, 48, 16, ChromaFormat::Yuv420}));
      EXPECT_EQ(s.frameCount, 3);
      EXPECT_EQ(s.startFrame, 0);
      EXPECT_TRUE(fs::equivalent(s.cameraFile, result.cameraFile));
      ASSERT_EQ(s.references.size(), 2u);
      EXPECT_EQ(s.references[0].cameraName, "cam" + std::to_string(k));
      EXPECT_EQ(s.virtualCameraName, "cam" + std::to_string(k + 1));
      EXPECT_EQ(s.references[1].cameraName, "cam" + std::to_string(k + 2));
      EXPECT_EQ(scene.virtualCamera.t, result.cameras[k + 1].t);
      for (int side = 0; side < 2; ++side) {
        const ReferenceView& view = s.references[size_t(side)];
        const size_t camera = k + size_t(side) * 2;
        EXPECT_TRUE(fs::equivalent(view.texturePath, result.texturePaths[camera]));
        EXPECT_TRUE(fs::equivalent(view.depthPath, result.depthPaths[camera]));
        EXPECT_EQ(view.depthRange.znear, result.depthRange.znear) << "the exact range the depth was quantised with";
        EXPECT_EQ(view.depthRange.zfar, result.depthRange.zfar);
        EXPECT_EQ(view.camera.K, result.cameras[camera].K);
      }
      ASSERT_FALSE(s.referenceViewPath.empty());
      EXPECT_TRUE(fs::equivalent(s.referenceViewPath, result.texturePaths[k + 1]))
          << "ground truth of the virtual camera";
      EXPECT_EQ(fs::path(s.outputPath).parent_path(), fs::path(result.cameraFile).parent_path());
      EXPECT_FALSE(fs::exists(s.outputPath)) << "the output is not one of the generated files";
      // Every input holds exactly the frames the config asks for.
      for (const std::string& input : {s.references[0].texturePath, s.references[1].texturePath, s.referenceViewPath}) {
        YuvReader reader(input, s.textureFormat);
        EXPECT_EQ(reader.frameCount(), s.frameCount);
        EXPECT_EQ(reader.trailingBytes(), 0u);
      }
      for (const ReferenceView& view : s.references) {
        YuvReader reader(view.depthPath, s.depthFormat);
        EXPECT_EQ(reader.frameCount(), s.frameCount);
        EXPECT_EQ(reader.trailingBytes(), 0u);
      }
    }
    // The two tools write different output files, so both can run on one folder.
    const Config viewSyn = Config::load(viewSynOptionTable(), result.viewSynConfigs[k], {});
    const Config mesh = Config::load(meshRenderOptionTable(), result.meshRenderConfigs[k], {});
    EXPECT_NE(viewSyn.getPath("OutputVirtualViewImageName"), mesh.getPath("OutputVirtualViewImageName"));
  }
}

TEST(SceneGenOutputTest, TwoCamerasGiveNoSynthesisConfig) {
  const auto folder = test::scratchDir("scenegen_two");
  const SceneGenResult result = generate({"Scene=tiny", "CameraCount=2", "TotalNumberOfFrames=1"}, folder);
  EXPECT_EQ(result.cameras.size(), 2u);
  EXPECT_TRUE(result.viewSynConfigs.empty());
  EXPECT_TRUE(fs::exists(result.texturePaths[1]));
}

std::vector<Frame> readAll(const std::string& path, const FrameFormat& format) {
  YuvReader reader(path, format);
  std::vector<Frame> frames(size_t(reader.frameCount()));
  for (size_t n = 0; n < frames.size(); ++n) reader.read(int64_t(n), frames[n]);
  return frames;
}

TEST(SceneGenOutputTest, FramesDifferWhenObjectsMoveAndNotOtherwise) {
  const FrameFormat texture{64, 48, 8, ChromaFormat::Yuv420};
  const FrameFormat depth{64, 48, 8, ChromaFormat::Yuv420};
  const auto moving = generate({"Scene=tiny"}, test::scratchDir("scenegen_moving"));
  const auto frozen = generate({"Scene=tiny", "MotionScale=0"}, test::scratchDir("scenegen_frozen"));
  for (size_t c = 0; c < moving.cameras.size(); ++c) {
    const std::vector<Frame> movingTexture = readAll(moving.texturePaths[c], texture);
    const std::vector<Frame> movingDepth = readAll(moving.depthPaths[c], depth);
    const std::vector<Frame> frozenTexture = readAll(frozen.texturePaths[c], texture);
    ASSERT_EQ(movingTexture.size(), 3u);
    ASSERT_EQ(frozenTexture.size(), 3u);
    for (size_t n = 1; n < 3; ++n) {
      EXPECT_FALSE(movingTexture[n] == movingTexture[n - 1]) << "camera " << c << " frame " << n;
      EXPECT_FALSE(movingDepth[n] == movingDepth[n - 1]) << "camera " << c << " frame " << n;
      EXPECT_TRUE(frozenTexture[n] == frozenTexture[0]) << "camera " << c << " frame " << n;
    }
    EXPECT_TRUE(frozenTexture[0] == movingTexture[0]) << "frame 0 is the scene as defined";
  }
}

TEST(SceneGenOutputTest, AutomaticDepthRangeBracketsTheTrueDepthRange) {
  for (const char* scene : {"tiny", "arc", "sphere"}) {
    SCOPED_TRACE(scene);
    const auto folder = test::scratchDir(std::string("scenegen_auto_") + scene);
    const SceneGenSettings s = settingsFrom({std::string("Scene=") + scene, "SourceWidth=96", "SourceHeight=72",
                                             "TotalNumberOfFrames=3", "OutputFolder=" + folder.string()});
    std::ostringstream log;
    const SceneGenResult result = generateScene(s, log);
    // The true range, independently: every camera, every frame.
    double nearest = kNoSurface, farthest = 0;
    for (int frame = 0; frame < s.frames; ++frame)
      for (const Camera& camera : result.cameras) {
        RenderOptions options;
        options.motionScale = s.motionScale;
        for (double z : renderView(buildScene(s), camera, s.width, s.height, frame, options).depth)
          if (z != kNoSurface) {
            nearest = std::min(nearest, z);
            farthest = std::max(farthest, z);
          }
      }
    EXPECT_EQ(result.trueNearest, nearest);
    EXPECT_EQ(result.trueFarthest, farthest);
    EXPECT_LT(result.depthRange.znear, nearest);
    EXPECT_GT(result.depthRange.zfar, farthest);
    EXPECT_GT(result.depthRange.znear, nearest / 1.03) << "a small margin, not a loose one";
    EXPECT_LT(result.depthRange.zfar, farthest * 1.03);
    EXPECT_EQ(result.clampedSamples, 0);
    // The written levels use most of the range.
    int lowest = 255, highest = 0;
    for (const std::string& path : result.depthPaths)
      for (const Frame& f : readAll(path, FrameFormat{96, 72, 8, ChromaFormat::Yuv420}))
        for (uint16_t level : f.planes[0].samples) {
          lowest = std::min<int>(lowest, level);
          highest = std::max<int>(highest, level);
        }
    EXPECT_GE(highest, 240);
    EXPECT_LE(lowest, 10);
  }
}

TEST(SceneGenOutputTest, GivenDepthRangeIsUsedAndClampingIsCounted) {
  const auto folder = test::scratchDir("scenegen_clamp");
  const SceneGenResult result =
      generate({"Scene=plane", "BackgroundDepth=3", "NearestDepthValue=4", "FarthestDepthValue=inf"}, folder);
  EXPECT_EQ(result.depthRange.znear, 4.0);
  EXPECT_EQ(result.depthRange.zfar, HUGE_VAL);
  EXPECT_EQ(result.clampedSamples, int64_t(3) * 2 * 128 * 96);  // nearer than Znear everywhere
  std::ifstream cfg(result.viewSynConfigs[0]);
  const std::string text((std::istreambuf_iterator<char>(cfg)), {});
  EXPECT_TRUE(contains(text, "LeftFarthestDepthValue           inf")) << text;
}

TEST(SceneGenOutputTest, ScenePresetsAndOverrides) {
  const SceneGenSettings demo = settingsFrom({});
  EXPECT_EQ(demo.scene, "demo");
  EXPECT_EQ(demo.width, 1024);
  EXPECT_EQ(demo.height, 768);
  EXPECT_EQ(demo.frames, 10);
  EXPECT_EQ(demo.cameraCount, 3);
  EXPECT_EQ(demo.rig, RigType::Parallel);
  EXPECT_EQ(demo.principalX, 511.5);
  EXPECT_EQ(demo.principalY, 383.5);
  EXPECT_TRUE(std::isnan(demo.znear));
  EXPECT_EQ(settingsFrom({"Scene=arc"}).rig, RigType::Arc);
  EXPECT_EQ(settingsFrom({"Scene=tiny"}).width, 64);
  // A different width keeps the scene's field of view unless FocalLength is given.
  EXPECT_EQ(settingsFrom({"SourceWidth=512", "SourceHeight=384"}).focalLength, 500.0);
  EXPECT_EQ(settingsFrom({"SourceWidth=512", "FocalLength=700"}).focalLength, 700.0);
  for (const std::string& name : builtInSceneNames()) {
    const SceneGenSettings s = settingsFrom({"Scene=" + name});
    EXPECT_FALSE(buildScene(s).empty()) << name;
    EXPECT_FALSE(buildCameras(s).empty()) << name;
  }
}

TEST(SceneGenOutputTest, BadSettingsAreReportedTogether) {
  const std::string message = errorOf({"SourceWidth=65", "Rig=file", "NearestDepthValue=5", "FarthestDepthValue=2"});
  EXPECT_TRUE(contains(message, "even")) << message;
  EXPECT_TRUE(contains(message, "CameraParameterFile")) << message;
  EXPECT_TRUE(contains(message, "NearestDepthValue")) << message;
  EXPECT_TRUE(contains(errorOf({"Scene=sphere", "SphereRadius=2", "SphereDepth=1"}), "SphereDepth"));
  EXPECT_TRUE(contains(errorOf({"Scene=cube"}), "Scene"));
  EXPECT_TRUE(contains(errorOf({"CameraCount=0"}), "CameraCount"));
  EXPECT_TRUE(contains(errorOf({"Rig=arc", "CameraCount=40", "ArcAngle=10"}), "180"));
  const std::string unknown = errorOf({"Baselin=0.1"});
  EXPECT_TRUE(contains(unknown, "did you mean 'Baseline'")) << unknown;
}

TEST(SceneGenOutputTest, HelpTextListsEveryKey) {
  const OptionTable table = sceneGenOptionTable();
  const std::string help = table.helpText();
  for (const OptionSpec& spec : table.options()) {
    EXPECT_TRUE(contains(help, "  " + spec.key + "  (")) << spec.key;
    EXPECT_FALSE(spec.help.empty()) << spec.key;
  }
  for (const std::string& name : builtInSceneNames()) EXPECT_TRUE(contains(sceneListText(), name));
}

TEST(SceneGenOutputTest, ManualDocumentsEveryKeyAndScene) {
  std::ifstream manual(fs::path(VS_SOURCE_DIR) / "doc" / "scenegen.md");
  ASSERT_TRUE(manual.good()) << "doc/scenegen.md";
  const std::string text((std::istreambuf_iterator<char>(manual)), {});
  const OptionTable table = sceneGenOptionTable();
  for (const OptionSpec& spec : table.options()) EXPECT_TRUE(contains(text, "`" + spec.key + "`")) << spec.key;
  for (const std::string& name : builtInSceneNames()) EXPECT_TRUE(contains(text, "`" + name + "`")) << name;
}

// ---------------------------------------------------------------------------------------------------
// The executable.

using test::ToolResult;

ToolResult runSceneGenTool(const std::string& arguments, const fs::path& scratch) {
  return test::runTool("SceneGen", arguments, scratch);
}

TEST(SceneGenOutputTest, ExecutableRendersFromAConfigFileAndReportsBadInput) {
  if (!fs::exists(test::binDir() / "SceneGen")) GTEST_SKIP() << "Bin/SceneGen is not built";
  const auto scratch = test::scratchDir("scenegen_app");
  {
    std::ofstream cfg(scratch / "tiny.cfg");
    cfg << "# a SceneGen config\nScene tiny\nTotalNumberOfFrames 2\nOutputFolder out   # relative to this file\n";
  }
  const ToolResult ok = runSceneGenTool("'" + (scratch / "tiny.cfg").string() + "' CameraCount=3", scratch);
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_TRUE(contains(ok.out, "SceneGen ")) << ok.out;
  EXPECT_TRUE(fs::exists(scratch / "out" / "viewsyn_cam1.cfg"));
  EXPECT_TRUE(fs::exists(scratch / "out" / "texture_cam2.yuv"));

  const ToolResult help = runSceneGenTool("--help", scratch);
  EXPECT_EQ(help.exitCode, 0);
  const OptionTable table = sceneGenOptionTable();
  for (const OptionSpec& spec : table.options()) EXPECT_TRUE(contains(help.out, spec.key)) << spec.key;

  const ToolResult bad = runSceneGenTool("'" + (scratch / "tiny.cfg").string() + "' Basline=1 SourceWidth=x", scratch);
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_TRUE(contains(bad.err, "Basline")) << bad.err;
  EXPECT_TRUE(contains(bad.err, "SourceWidth")) << bad.err;

  EXPECT_EQ(runSceneGenTool("'" + (scratch / "missing.cfg").string() + "'", scratch).exitCode, 1);
  EXPECT_EQ(runSceneGenTool("--frobnicate", scratch).exitCode, 2);
}

}  // namespace
}  // namespace vs
