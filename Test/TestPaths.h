#pragma once
// Where tests find the shared data and samples: environment variables VS_DATA_DIR / VS_SAMPLES_DIR,
// else the CMake cache entries of the same names (default ../shared/...). Tests that need them call
// VS_REQUIRE_DIR and are skipped with a clear message when the folder is absent.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

namespace vs::test {

inline std::filesystem::path dataDir() {
  const char* env = std::getenv("VS_DATA_DIR");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(VS_DATA_DIR_DEFAULT);
}

inline std::filesystem::path samplesDir() {
  const char* env = std::getenv("VS_SAMPLES_DIR");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(VS_SAMPLES_DIR_DEFAULT);
}

inline std::filesystem::path binDir() { return std::filesystem::path(VS_BIN_DIR); }

// A fresh, empty scratch folder for one test, removed and recreated on every call. Its name carries a
// hash of the build's Bin folder, so two builds' test runs at once (a sanitizer build beside a release
// build, two checkouts on one machine) never empty each other's folders.
inline std::filesystem::path scratchDir(const std::string& name) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string build = std::to_string(std::hash<std::string>{}(std::string(VS_BIN_DIR)) % 1000000007u);
  std::filesystem::path dir =
      std::filesystem::path(tmp && *tmp ? tmp : "/tmp") / ("vs_test_" + build + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace vs::test

#define VS_REQUIRE_DIR(dir)                                                                       \
  do {                                                                                            \
    if (!std::filesystem::is_directory(dir))                                                      \
      GTEST_SKIP() << "test data folder " << (dir)                                                \
                   << " is absent; set VS_DATA_DIR / VS_SAMPLES_DIR to run this test";            \
  } while (0)
