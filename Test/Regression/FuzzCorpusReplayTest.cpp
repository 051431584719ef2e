// Replays every input of the committed fuzz corpus (Test/Fuzz/corpus/<target>/) through the same
// functions the libFuzzer targets run (Fuzz/FuzzTargets.h), in the regular build: each input must be
// accepted or refused with vs::InputError, never crash, abort or throw anything else. Inputs that once
// crashed a target are kept in the corpus as regression seeds (issue 8).
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Fuzz/FuzzTargets.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

fs::path corpusDir() { return fs::path(VS_SOURCE_DIR) / "Test" / "Fuzz" / "corpus"; }

std::vector<uint8_t> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct Target {
  const char* name;
  std::function<bool(const uint8_t*, size_t)> run;
};

void PrintTo(const Target& target, std::ostream* out) { *out << target.name; }

class FuzzCorpusReplay : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzCorpusReplay, EveryInputIsAcceptedOrRefusedWithInputError) {
  const fs::path dir = corpusDir() / GetParam().name;
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  std::vector<fs::path> inputs;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) inputs.push_back(entry.path());
  std::sort(inputs.begin(), inputs.end());
  ASSERT_FALSE(inputs.empty()) << dir;
  int accepted = 0;
  for (const fs::path& input : inputs) {
    const std::vector<uint8_t> bytes = readBytes(input);
    try {
      accepted += GetParam().run(bytes.data(), bytes.size()) ? 1 : 0;
    } catch (const std::exception& e) {
      ADD_FAILURE() << input << ": threw " << typeid(e).name() << " (not vs::InputError): " << e.what();
    } catch (...) {
      ADD_FAILURE() << input << ": threw something that is not a std::exception";
    }
  }
  std::printf("%s: %zu inputs, %d accepted, %zu refused with InputError\n", GetParam().name, inputs.size(), accepted,
              inputs.size() - size_t(accepted));
  // A corpus that only ever fails to parse tests little: some inputs must get through.
  EXPECT_GT(accepted, 0);
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzCorpusReplay,
                         ::testing::Values(Target{"FuzzConfig", fuzz::fuzzConfig},
                                           Target{"FuzzCameraFile", fuzz::fuzzCameraFile},
                                           Target{"FuzzCameraJson", fuzz::fuzzCameraJson},
                                           Target{"FuzzYuv", fuzz::fuzzYuv}),
                         [](const ::testing::TestParamInfo<Target>& info) { return std::string(info.param.name); });

// The committed corpus stays small: minimized with -merge=1, under 200 files and 1 MB per target.
TEST(FuzzCorpus, StaysSmall) {
  for (const char* target : {"FuzzConfig", "FuzzCameraFile", "FuzzCameraJson", "FuzzYuv"}) {
    size_t files = 0;
    uintmax_t bytes = 0;
    for (const auto& entry : fs::directory_iterator(corpusDir() / target))
      if (entry.is_regular_file()) {
        ++files;
        bytes += entry.file_size();
      }
    EXPECT_LT(files, 200u) << target;
    EXPECT_LT(bytes, uintmax_t(1) << 20) << target;
  }
}

}  // namespace
}  // namespace vs
