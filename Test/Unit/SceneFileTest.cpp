// Scene files: every cfg/scenes/NAME.scene holds the built-in scene NAME exactly (same objects, same
// preset, byte-identical outputs), and bad scene files are refused with file:line and what was expected.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Scene/SceneFile.h"
#include "Scene/SceneGen.h"
#include "Scene/Scenes.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

fs::path sceneFilePath(const std::string& name) { return fs::path(VS_SOURCE_DIR) / "cfg" / "scenes" / (name + ".scene"); }

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }
bool sameBits(const Rgb& a, const Rgb& b) { return sameBits(a.r, b.r) && sameBits(a.g, b.g) && sameBits(a.b, b.b); }

void expectSameObject(const Primitive& file, const Primitive& builtIn) {
  SCOPED_TRACE(builtIn.name);
  EXPECT_EQ(file.name, builtIn.name);
  EXPECT_EQ(file.shape, builtIn.shape);
  EXPECT_TRUE(sameBits(file.halfSize, builtIn.halfSize));
  EXPECT_TRUE(sameBits(file.position, builtIn.position));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(sameBits(file.orientation[r][c], builtIn.orientation[r][c])) << r << c;
  EXPECT_TRUE(sameBits(file.motion.velocity, builtIn.motion.velocity));
  EXPECT_TRUE(sameBits(file.motion.spinAxis, builtIn.motion.spinAxis));
  EXPECT_TRUE(sameBits(file.motion.spinDegrees, builtIn.motion.spinDegrees));
  const Texture &a = file.texture, &b = builtIn.texture;
  EXPECT_EQ(a.pattern, b.pattern);
  EXPECT_TRUE(sameBits(a.colourA, b.colourA));
  EXPECT_TRUE(sameBits(a.colourB, b.colourB));
  EXPECT_TRUE(sameBits(a.scale, b.scale));
  EXPECT_TRUE(sameBits(a.direction, b.direction));
  EXPECT_TRUE(sameBits(a.bandDirection, b.bandDirection));
  EXPECT_TRUE(sameBits(a.bandWidth, b.bandWidth));
  EXPECT_EQ(a.octaves, b.octaves);
  EXPECT_TRUE(sameBits(a.detail, b.detail));
  EXPECT_TRUE(sameBits(a.detailScale, b.detailScale));
  EXPECT_EQ(a.seed, b.seed);
}

class BuiltInSceneFile : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltInSceneFile, HoldsTheBuiltInSceneExactly) {
  const std::string name = GetParam();
  const SceneFile file = readSceneFile(sceneFilePath(name).string());
  const SceneGenSettings preset = scenePreset(name);
  EXPECT_EQ(file.preset.scene, name);
  EXPECT_FALSE(file.description.empty());
  EXPECT_EQ(file.preset.width, preset.width);
  EXPECT_EQ(file.preset.height, preset.height);
  EXPECT_EQ(file.preset.frames, preset.frames);
  EXPECT_EQ(file.preset.rig, preset.rig);
  EXPECT_EQ(file.preset.cameraCount, preset.cameraCount);
  EXPECT_TRUE(sameBits(file.preset.focalLength, preset.focalLength));
  if (preset.rig == RigType::Parallel) {
    EXPECT_TRUE(sameBits(file.preset.baseline, preset.baseline));
  } else {
    EXPECT_TRUE(sameBits(file.preset.arcRadius, preset.arcRadius));
    EXPECT_TRUE(sameBits(file.preset.arcStepDegrees, preset.arcStepDegrees));
  }
  const std::vector<Primitive> builtIn = buildScene(preset);
  ASSERT_EQ(file.objects.size(), builtIn.size());
  for (size_t i = 0; i < builtIn.size(); ++i) expectSameObject(file.objects[i], builtIn[i]);
}

// The whole chain through the keys: SceneFile=... and Scene=NAME write the same bytes into every
// output file (small sizes, so that the five scenes take well under a second).
TEST_P(BuiltInSceneFile, RendersByteIdenticallyToTheBuiltInName) {
  const std::string name = GetParam();
  const fs::path root = test::scratchDir("scene_file_" + name);
  const std::vector<std::string> common{"SourceWidth=48", "SourceHeight=32", "TotalNumberOfFrames=2", "Threads=1"};
  std::vector<std::string> fromName = common, fromFile = common;
  fromName.push_back("Scene=" + name);
  fromName.push_back("OutputFolder=" + (root / "name").string());
  fromFile.push_back("SceneFile=" + sceneFilePath(name).string());
  fromFile.push_back("OutputFolder=" + (root / "file").string());
  std::ostringstream log;
  const SceneGenResult a = generateScene(readSceneGenSettings(Config::load(sceneGenOptionTable(), "", fromName)), log);
  const SceneGenResult b = generateScene(readSceneGenSettings(Config::load(sceneGenOptionTable(), "", fromFile)), log);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(root / "name")) names.push_back(entry.path().filename().string());
  ASSERT_GE(names.size(), 3u);  // cameras.txt, textures, depths (and configs with 3 cameras or more)
  for (const std::string& file : names) {
    ASSERT_TRUE(fs::exists(root / "file" / file)) << file;
    EXPECT_TRUE(readBytes(root / "name" / file) == readBytes(root / "file" / file)) << name << ": " << file << " differs";
  }
  EXPECT_EQ(a.depthRange.znear, b.depthRange.znear);
  fs::remove_all(root);
}

INSTANTIATE_TEST_SUITE_P(SceneFile, BuiltInSceneFile, ::testing::Values("demo", "arc", "plane", "sphere", "tiny"));

std::string errorOf(const std::string& text) {
  try {
    parseSceneFile(text, "bad.scene");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFile, BadLinesNameFileLineAndWhatWasExpected) {
  const std::string error = errorOf(
      "SourceWidth 64\n"
      "Colour 1\n"                  // line 2: unknown setting
      "Object a cone\n"             // line 3: unknown shape
      "  Position 1 2\n"            // line 4: too few numbers
      "  HalfSize 1 x 1\n"          // line 5: not a number
      "  ColourA 0.5 2 0\n"         // line 6: out of range
      "  Texture marble\n");        // line 7: unknown pattern
  for (const char* part : {"bad.scene:2: unknown scene setting 'Colour'", "bad.scene:3: shape 'cone'",
                           "bad.scene:4: Position: 3 number(s) expected, 2 given", "bad.scene:5: HalfSize: 'x'",
                           "bad.scene:6: ColourA: channels in [0, 1]", "bad.scene:7: Texture:"})
    EXPECT_NE(error.find(part), std::string::npos) << part << "\nin:\n" << error;
  EXPECT_NE(errorOf("SourceWidth 64\n").find("no Object"), std::string::npos);
}

TEST(SceneFile, DetailScaleDefaultsToThePatternsProportionAndCanBeGiven) {
  const SceneFile scene = parseSceneFile(
      "Object a box\n  Texture noise\n  Scale 2\n"
      "Object b box\n  Texture noise\n  Scale 2\n  DetailScale 0.5\n", "x.scene");
  EXPECT_EQ(scene.objects[0].texture.detailScale, 2.0 / 40.0);
  EXPECT_EQ(scene.objects[1].texture.detailScale, 0.5);
}

TEST(SceneFile, KeysForBuiltInObjectsAreRefusedWithASceneFile) {
  const std::vector<std::string> args{"SceneFile=" + sceneFilePath("plane").string(), "BackgroundDepth=3", "Scene=arc"};
  try {
    readSceneGenSettings(Config::load(sceneGenOptionTable(), "", args));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("BackgroundDepth applies to the built-in scenes only"), std::string::npos) << text;
    EXPECT_NE(text.find("Scene and SceneFile are both set"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace vs
