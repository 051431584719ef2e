// Memory stays flat with sequence length (issue 8): ViewSyn on a long sequence peaks at the same
// resident memory as on a short one, so nothing grows per frame (no frames kept, no leaks).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "ProcessStats.h"
#include "TestPaths.h"
#include "TinyScene.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

int envInt(const char* name, int fallback) {
  const char* value = std::getenv(name);
  return value && *value ? std::atoi(value) : fallback;
}

// VS_MEMORY_WIDTH, VS_MEMORY_HEIGHT and VS_MEMORY_FRAMES enlarge the run for a measurement by hand
// (e.g. 640 x 480 x 300); the defaults keep the test to a few seconds. The parameter is SynthesisMode:
// the general 3D path and the 1D parallel path.
class MemoryFlat : public ::testing::TestWithParam<const char*> {};

TEST_P(MemoryFlat, LongSequencePeaksLikeAShortOne) {
#if defined(__SANITIZE_ADDRESS__)
  // ASan's allocator (quarantine, fake stacks of threads) grows with the run whatever the program does;
  // the sanitizer run finds leaks with LeakSanitizer, and the plain build runs this test.
  GTEST_SKIP() << "peak memory is measured in the plain build, not under AddressSanitizer";
#endif
  const fs::path root = test::scratchDir(std::string("memory_flat_mode") + GetParam());
  test::TinyScene scene(root / "scene");
  scene.width = envInt("VS_MEMORY_WIDTH", 160);
  scene.height = envInt("VS_MEMORY_HEIGHT", 96);
  scene.frames = envInt("VS_MEMORY_FRAMES", 300);
  scene.writeAll();
  scene.set("Threads", "2");
  scene.set("SynthesisMode", GetParam());
  scene.writeConfig();

  const std::string config = scene.configPath().string();
  const test::ProcessStats shortRun =
      test::runMeasured("ViewSyn", {config, "TotalNumberOfFrames=3"}, root / "short.txt");
  const test::ProcessStats longRun = test::runMeasured(
      "ViewSyn", {config, "TotalNumberOfFrames=" + std::to_string(scene.frames)}, root / "long.txt");
  ASSERT_TRUE(shortRun.measured && longRun.measured);
  ASSERT_EQ(shortRun.exitCode, 0);
  ASSERT_EQ(longRun.exitCode, 0);
  ASSERT_EQ(fs::file_size(scene.outputPath()), uint64_t(scene.frames) * scene.textureFormat().frameBytes());
  const long allowedKiB = shortRun.maxRssKiB + shortRun.maxRssKiB / 10 + 4 * 1024;
  std::printf("peak RSS, SynthesisMode %s, %d x %d: 3 frames %ld KiB (%.2f s), %d frames %ld KiB (%.2f s)\n",
              GetParam(), scene.width, scene.height, shortRun.maxRssKiB, shortRun.seconds, scene.frames,
              longRun.maxRssKiB, longRun.seconds);
  EXPECT_LE(longRun.maxRssKiB, allowedKiB) << "3 frames peak at " << shortRun.maxRssKiB << " KiB, " << scene.frames
                                           << " frames at " << longRun.maxRssKiB << " KiB";
}

INSTANTIATE_TEST_SUITE_P(SynthesisMode, MemoryFlat, ::testing::Values("0", "1"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return std::string("Mode") + info.param;
                         });

}  // namespace
}  // namespace vs
