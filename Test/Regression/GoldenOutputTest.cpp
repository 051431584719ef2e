// Outputs pinned: tiny SceneGen scenes (64x48, 3 frames; the 4-view and 16-bit cases 2 frames) run
// through SceneGen, ViewSyn (general, 1D, RGB, 4:0:0, four reference views, 16-bit depth, the other
// filters and hole fillings) and MeshRender, and the MD5 of every output must equal its line in
// Test/golden.md5. A change of any output byte fails here; that is the point: this issue class changes
// structure, not pictures. When a change of pictures is intended, regenerate the file explicitly:
//
//   scripts/update_golden.sh      (VS_UPDATE_GOLDEN=1 build/Test/RegressionTests --gtest_filter='Golden*')
//
// which rewrites the changed lines and prints each one as "NAME: OLD -> NEW"; say why in the commit.
// The x86-64 baseline build of CI (scripts/test.sh) checks its scalar fallbacks against the same file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Md5.h"
#include "Common/Options.h"
#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

const fs::path kGoldenFile = fs::path(VS_SOURCE_DIR) / "Test" / "golden.md5";

// Lines "DIGEST  NAME" (md5sum's format), `#` comments.
std::map<std::string, std::string> readGolden() {
  std::map<std::string, std::string> digests;
  std::ifstream in(kGoldenFile);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string digest, name;
    if (words >> digest >> name) digests[name] = digest;
  }
  return digests;
}

void writeGolden(const std::map<std::string, std::string>& digests) {
  std::ofstream out(kGoldenFile, std::ios::binary | std::ios::trunc);
  out << "# MD5 of every output of Test/Regression/GoldenOutputTest.cpp (tiny SceneGen scenes through\n"
         "# SceneGen, ViewSyn and MeshRender). Regenerate only for an intended change of pictures:\n"
         "# scripts/update_golden.sh (prints what changed).\n";
  for (const auto& [name, digest] : digests) out << digest << "  " << name << "\n";
}

// Compares `file`'s digest with the golden one for `name`; with VS_UPDATE_GOLDEN=1 stores it instead
// and prints the change.
void expectGolden(const std::string& name, const fs::path& file) {
  ASSERT_TRUE(fs::exists(file)) << file;
  const std::string digest = md5OfFile(file.string());
  std::map<std::string, std::string> golden = readGolden();
  const char* update = std::getenv("VS_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") {
    const auto old = golden.find(name);
    if (old == golden.end() || old->second != digest) {
      std::printf("golden: %s: %s -> %s\n", name.c_str(), old == golden.end() ? "(new)" : old->second.c_str(),
                  digest.c_str());
      golden[name] = digest;
      writeGolden(golden);
    }
    return;
  }
  ASSERT_TRUE(golden.count(name)) << name << " is not in " << kGoldenFile << ": run scripts/update_golden.sh";
  EXPECT_EQ(digest, golden[name]) << name << " (" << file << ") changed; if the change of pictures is intended, "
                                  << "run scripts/update_golden.sh and say why in the commit";
}

test::ToolResult run(const std::string& tool, const std::string& arguments, const fs::path& dir) {
  test::ToolResult result = test::runTool(tool, arguments, dir, dir);
  EXPECT_EQ(result.exitCode, 0) << tool << " " << arguments << "\n" << result.out << result.err;
  return result;
}

// SceneGen renders `scene` (a file of cfg/scenes) with `keys` into `dir`; its files are pinned too.
fs::path renderScene(const std::string& name, const std::string& keys) {
  const fs::path dir = test::scratchDir("golden_" + name);
  const std::string sceneFile = (fs::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "tiny.scene").string();
  run("SceneGen", "SceneFile=" + test::quoted(sceneFile) + " OutputFolder=scene Threads=1 " + keys, dir);
  return dir / "scene";
}

// 4:2:0 sequence -> its luma planes only (4:0:0), for the 4:0:0 case.
void writeLumaOnly(const fs::path& from, const fs::path& to, int width, int height) {
  std::ifstream in(from, std::ios::binary);
  std::ofstream out(to, std::ios::binary | std::ios::trunc);
  const size_t luma = size_t(width) * height, frame = luma * 3 / 2;
  std::vector<char> bytes(frame);
  while (in.read(bytes.data(), std::streamsize(frame))) out.write(bytes.data(), std::streamsize(luma));
}

// Luma PSNR of 8-bit 64x48 sequences over all frames (frames of `frameBytes`), written plainly here:
// a pinned output must also resemble the ray-cast truth, so that the digests never pin garbage.
double lumaPsnr(const fs::path& a, const fs::path& b, size_t frameBytes) {
  std::ifstream inA(a, std::ios::binary), inB(b, std::ios::binary);
  std::vector<unsigned char> x(frameBytes), y(frameBytes);
  double squared = 0.0;
  size_t samples = 0;
  while (inA.read(reinterpret_cast<char*>(x.data()), std::streamsize(frameBytes)) &&
         inB.read(reinterpret_cast<char*>(y.data()), std::streamsize(frameBytes)))
    for (size_t i = 0; i < size_t(64 * 48); ++i, ++samples) squared += (double(x[i]) - y[i]) * (double(x[i]) - y[i]);
  if (samples == 0) return 0.0;
  return 10.0 * std::log10(255.0 * 255.0 / std::max(squared / double(samples), 1e-12));
}

constexpr size_t kFrame420 = 64 * 48 * 3 / 2;
constexpr double kResemblesTruthDb = 25.0;  // the tiny scene's syntheses score 33 to 36 dB

struct Case {
  std::string name;
  std::string tool;    // ViewSyn or MeshRender
  std::string config;  // in the scene folder
  std::string keys;    // Key=Value overrides
};

class GoldenOutput : public ::testing::TestWithParam<Case> {};

// The 3-camera tiny scene and its inputs are pinned once, by the first case.
TEST(Golden, SceneGenTinyScene) {
  const fs::path scene = renderScene("scene", "");
  for (const char* file : {"cameras.txt", "texture_cam0.yuv", "depth_cam0.yuv", "texture_cam1.yuv", "depth_cam2.yuv"})
    expectGolden(std::string("scenegen_tiny_") + file, scene / file);
}

TEST_P(GoldenOutput, Md5) {
  const Case& c = GetParam();
  const fs::path scene = renderScene(c.name, "");
  run(c.tool, test::quoted(c.config) + " " + c.keys + " OutputVirtualViewImageName=golden.yuv Threads=1", scene);
  expectGolden(c.name, scene / "golden.yuv");
  EXPECT_GT(lumaPsnr(scene / "golden.yuv", scene / "texture_cam1.yuv", kFrame420), kResemblesTruthDb);
}

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

std::string caseName(const ::testing::TestParamInfo<Case>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(
    Golden, GoldenOutput,
    ::testing::Values(
        Case{"ViewSyn_general", "ViewSyn", "viewsyn_cam1.cfg", "SynthesisMode=0"},
        Case{"ViewSyn_general_vsrs", "ViewSyn", "viewsyn_cam1.cfg",
             "SynthesisMode=0 Precision=4 Filter=2 BoundaryNoiseRemoval=1 ViewBlending=1 IvsrsInpaint=0 "
             "DepthEdgeAlignment=0"},
        Case{"ViewSyn_1d", "ViewSyn", "viewsyn_cam1.cfg", "SynthesisMode=1"},
        Case{"ViewSyn_1d_options", "ViewSyn", "viewsyn_cam1.cfg",
             "SynthesisMode=1 Precision=4 Filter=0 SplattingOption=1 MergingOption=1 CleanNoiseOption=1 "
             "TemporalImprovementOption=0"},
        Case{"ViewSyn_rgb", "ViewSyn", "viewsyn_cam1.cfg", "SynthesisMode=0 ColorSpace=1"},
        Case{"ViewSyn_rgb_1d", "ViewSyn", "viewsyn_cam1.cfg", "SynthesisMode=1 ColorSpace=1"},
        Case{"MeshRender_default", "MeshRender", "meshrender_cam1.cfg", ""},
        Case{"MeshRender_step2", "MeshRender", "meshrender_cam1.cfg",
             "MeshGridStep=2 MeshDiscontinuityThreshold=0.05"}),
    caseName);

TEST(Golden, ViewSyn_400) {
  const fs::path scene = renderScene("400", "");
  for (const char* camera : {"cam0", "cam1", "cam2"})
    writeLumaOnly(scene / ("texture_" + std::string(camera) + ".yuv"), scene / ("luma_" + std::string(camera) + ".yuv"),
                  64, 48);
  run("ViewSyn",
      "viewsyn_cam1.cfg ChromaFormat=400 LeftViewImageName=luma_cam0.yuv RightViewImageName=luma_cam2.yuv "
      "ReferenceVirtualViewImageName=luma_cam1.yuv OutputVirtualViewImageName=golden.yuv Threads=1",
      scene);
  expectGolden("ViewSyn_400", scene / "golden.yuv");
  EXPECT_GT(lumaPsnr(scene / "golden.yuv", scene / "luma_cam1.yuv", 64 * 48), kResemblesTruthDb);
}

TEST(Golden, ViewSyn_16bitDepth) {
  const fs::path scene = renderScene("16bit", "DepthBitDepth=16 TotalNumberOfFrames=2");
  run("ViewSyn", "viewsyn_cam1.cfg SynthesisMode=0 OutputVirtualViewImageName=golden.yuv Threads=1", scene);
  expectGolden("ViewSyn_16bit_depth", scene / "golden.yuv");
  EXPECT_GT(lumaPsnr(scene / "golden.yuv", scene / "texture_cam1.yuv", kFrame420), kResemblesTruthDb);
  expectGolden("scenegen_tiny16_depth_cam0.yuv", scene / "depth_cam0.yuv");
}

// The left view alone (every Right key left out): extrapolation.
TEST(Golden, ViewSyn_extrapolate) {
  const fs::path scene = renderScene("extrapolate", "");
  std::ifstream in(scene / "viewsyn_cam1.cfg");
  std::ofstream out(scene / "left.cfg");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("Right", 0) != 0) out << line << "\n";
  out.close();
  run("ViewSyn", "left.cfg OutputVirtualViewImageName=golden.yuv Threads=1", scene);
  expectGolden("ViewSyn_extrapolate", scene / "golden.yuv");
  EXPECT_GT(lumaPsnr(scene / "golden.yuv", scene / "texture_cam1.yuv", kFrame420), kResemblesTruthDb);
}

// Four reference views (cam0, cam1, cam3, cam4 of a 5-camera rig) synthesize cam2.
TEST(Golden, ViewSyn_4views) {
  const fs::path scene = renderScene("4views", "CameraCount=5 TotalNumberOfFrames=2");
  const Config generated = Config::load(viewSynOptionTable(), (scene / "viewsyn_cam2.cfg").string(), {});
  std::string names, textures, depths, nears, fars;
  for (int c : {0, 1, 3, 4}) {
    const std::string n = std::to_string(c), sep = names.empty() ? "" : ",";
    names += sep + "cam" + n;
    textures += sep + "texture_cam" + n + ".yuv";
    depths += sep + "depth_cam" + n + ".yuv";
    nears += sep + generated.raw("LeftNearestDepthValue");
    fars += sep + generated.raw("LeftFarthestDepthValue");
  }
  std::ofstream(scene / "four.cfg") << "SourceWidth 64\nSourceHeight 48\nTotalNumberOfFrames 2\n"
                                       "CameraParameterFile cameras.txt\nVirtualCameraName cam2\n"
                                    << "ReferenceCameraNames " << names << "\nReferenceViewImageNames " << textures
                                    << "\nReferenceDepthMapNames " << depths << "\nReferenceNearestDepthValues " << nears
                                    << "\nReferenceFarthestDepthValues " << fars
                                    << "\nOutputVirtualViewImageName golden.yuv\nSynthesisMode 0\nThreads 1\n";
  run("ViewSyn", "four.cfg", scene);
  expectGolden("ViewSyn_4views", scene / "golden.yuv");
  EXPECT_GT(lumaPsnr(scene / "golden.yuv", scene / "texture_cam2.yuv", kFrame420), kResemblesTruthDb);
}

}  // namespace
}  // namespace vs
