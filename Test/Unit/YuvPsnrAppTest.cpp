// Runs Bin/YuvPsnr on files generated here and reads its printed numbers back.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "Process.h"
#include "TestPaths.h"

#if defined(__unix__)
#include <sys/wait.h>
#endif

namespace fs = std::filesystem;

namespace {

const double kInf = std::numeric_limits<double>::infinity();

using vs::test::quoted;
using vs::test::ToolResult;

fs::path toolPath() { return vs::test::binDir() / "YuvPsnr"; }

ToolResult runTool(const std::string& arguments, const fs::path& scratch) {
  return vs::test::runTool("YuvPsnr", arguments, scratch);
}

// A clip held as plain sample vectors: clip[frame][plane][i].
using Clip = std::vector<std::vector<std::vector<int>>>;

// Writes the clip as planar YUV: bytes for 8 bit, little-endian 16-bit words above (written here by
// hand, not through YuvWriter).
void writeClip(const fs::path& path, const Clip& clip, int bitDepth) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  for (const auto& frame : clip)
    for (const auto& plane : frame)
      for (int s : plane) {
        if (bitDepth > 8) {
          file.put(char(s & 0xff));
          file.put(char(s >> 8));
        } else {
          file.put(char(s));
        }
      }
  ASSERT_TRUE(file.good());
}

double expectedPsnr(const std::vector<int>& a, const std::vector<int>& b, int bitDepth) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += double(a[i] - b[i]) * double(a[i] - b[i]);
  if (sum == 0) return kInf;
  const double peak = std::pow(2.0, bitDepth) - 1;
  return 10 * std::log10(peak * peak * double(a.size()) / sum);
}

double expectedMse(const std::vector<int>& a, const std::vector<int>& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += double(a[i] - b[i]) * double(a[i] - b[i]);
  return sum / double(a.size());
}

double parseDb(const std::string& token) { return token == "inf" ? kInf : std::stod(token); }

// The tool's output, read back: per-frame rows and the mean rows.
struct ParsedOutput {
  std::vector<int64_t> frameIndices;
  std::vector<std::vector<double>> frameValues;  // Y [U V YUV] per frame
  std::vector<std::string> meanPlanes;           // "Y", "U", ...
  std::vector<double> frameMeans, mseMeans;
  std::vector<std::string> meanNotes;
};

ParsedOutput parseOutput(const std::string& out) {
  ParsedOutput parsed;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream tokens(line);
    std::string first;
    if (!(tokens >> first)) continue;
    if (first.find_first_not_of("0123456789") == std::string::npos) {
      parsed.frameIndices.push_back(std::stoll(first));
      std::vector<double> values;
      std::string token;
      while (tokens >> token) values.push_back(parseDb(token));
      parsed.frameValues.push_back(values);
    } else if (first == "Y" || first == "U" || first == "V" || first == "YUV") {
      std::string frameMean, mseMean, note;
      tokens >> frameMean >> mseMean;
      std::getline(tokens, note);
      parsed.meanPlanes.push_back(first);
      parsed.frameMeans.push_back(parseDb(frameMean));
      parsed.mseMeans.push_back(parseDb(mseMean));
      parsed.meanNotes.push_back(note);
    }
  }
  return parsed;
}

// Printed with 4 decimals.
void expectPrinted(double printed, double expected, const std::string& what) {
  if (std::isinf(expected)) EXPECT_EQ(printed, expected) << what;
  else EXPECT_NEAR(printed, expected, 5.1e-5) << what;
}

class YuvPsnrAppTest : public ::testing::Test {
protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(toolPath())) << toolPath() << " is missing: build the YuvPsnr target";
  }
};

}  // namespace

TEST_F(YuvPsnrAppTest, PrintsPerFrameAndMeanPsnrOfGeneratedFiles) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_420");
  const int width = 11, height = 7, bitDepth = 8;
  const size_t lumaSize = size_t(width * height), chromaSize = size_t(6 * 4);
  std::mt19937 random(99);
  std::uniform_int_distribution<int> sample(0, 255);
  Clip ref(3), test(3);
  for (size_t f = 0; f < 3; ++f) {
    for (size_t size : {lumaSize, chromaSize, chromaSize}) {
      std::vector<int> plane(size);
      for (int& s : plane) s = sample(random);
      ref[f].push_back(plane);
    }
    test[f] = ref[f];
  }
  // Frame 0: noise everywhere; frame 1: identical; frame 2: noise in Y and V, U identical.
  std::uniform_int_distribution<int> noise(-6, 6);
  for (size_t f : {size_t(0), size_t(2)})
    for (size_t p : {size_t(0), size_t(1), size_t(2)}) {
      if (f == 2 && p == 1) continue;
      for (int& s : test[f][p]) s = std::min(255, std::max(0, s + noise(random) * int(p + 1)));
    }
  writeClip(dir / "ref.yuv", ref, bitDepth);
  writeClip(dir / "test.yuv", test, bitDepth);

  const ToolResult result =
      runTool(quoted((dir / "ref.yuv").string()) + " " + quoted((dir / "test.yuv").string()) + " 11 7", dir);
  ASSERT_EQ(result.exitCode, 0) << result.out << result.err;
  const ParsedOutput parsed = parseOutput(result.out);
  ASSERT_EQ(parsed.frameIndices, (std::vector<int64_t>{0, 1, 2})) << result.out;

  double meanMse[3] = {0, 0, 0};
  for (size_t f = 0; f < 3; ++f) {
    const std::vector<double>& printed = parsed.frameValues[f];
    ASSERT_EQ(printed.size(), 4u) << result.out;
    double psnr[3];
    for (size_t p = 0; p < 3; ++p) {
      psnr[p] = expectedPsnr(ref[f][p], test[f][p], bitDepth);
      meanMse[p] += expectedMse(ref[f][p], test[f][p]) / 3;
      expectPrinted(printed[p], psnr[p], "frame " + std::to_string(f) + " plane " + std::to_string(p));
    }
    expectPrinted(printed[3], (6 * psnr[0] + psnr[1] + psnr[2]) / 8, "YUV of frame " + std::to_string(f));
  }
  EXPECT_EQ(parsed.frameValues[1], (std::vector<double>{kInf, kInf, kInf, kInf}));
  EXPECT_TRUE(std::isfinite(parsed.frameValues[2][0]));
  EXPECT_EQ(parsed.frameValues[2][1], kInf);
  EXPECT_EQ(parsed.frameValues[2][3], kInf);

  ASSERT_EQ(parsed.meanPlanes, (std::vector<std::string>{"Y", "U", "V", "YUV"})) << result.out;
  // Frame means leave identical frames out: Y and V over frames 0 and 2, U over frame 0 only.
  const double y0 = expectedPsnr(ref[0][0], test[0][0], 8), y2 = expectedPsnr(ref[2][0], test[2][0], 8);
  const double u0 = expectedPsnr(ref[0][1], test[0][1], 8);
  const double v0 = expectedPsnr(ref[0][2], test[0][2], 8), v2 = expectedPsnr(ref[2][2], test[2][2], 8);
  expectPrinted(parsed.frameMeans[0], (y0 + y2) / 2, "mean Y");
  expectPrinted(parsed.frameMeans[1], u0, "mean U");
  expectPrinted(parsed.frameMeans[2], (v0 + v2) / 2, "mean V");
  expectPrinted(parsed.frameMeans[3], (6 * y0 + u0 + v0) / 8, "mean YUV (frames 1 and 2 are inf)");
  EXPECT_NE(parsed.meanNotes[0].find("1 identical frame excluded"), std::string::npos) << parsed.meanNotes[0];
  EXPECT_NE(parsed.meanNotes[1].find("2 identical frames excluded"), std::string::npos) << parsed.meanNotes[1];
  EXPECT_NE(parsed.meanNotes[3].find("2 identical frames excluded"), std::string::npos) << parsed.meanNotes[3];

  auto db = [](double mse) { return 10 * std::log10(255.0 * 255.0 / mse); };
  for (size_t p = 0; p < 3; ++p) expectPrinted(parsed.mseMeans[p], db(meanMse[p]), "mean-MSE plane " + std::to_string(p));
  expectPrinted(parsed.mseMeans[3], (6 * db(meanMse[0]) + db(meanMse[1]) + db(meanMse[2])) / 8, "mean-MSE YUV");
}

TEST_F(YuvPsnrAppTest, LumaOnlyTenBitWithStartAndFrames) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_400");
  const int width = 5, height = 3, bitDepth = 10;
  std::mt19937 random(5);
  std::uniform_int_distribution<int> sample(0, 1023), noise(-40, 40);
  Clip ref(4), test(4);
  for (size_t f = 0; f < 4; ++f) {
    std::vector<int> plane(size_t(width * height)), noisy(plane.size());
    for (size_t i = 0; i < plane.size(); ++i) {
      plane[i] = sample(random);
      noisy[i] = std::min(1023, std::max(0, plane[i] + noise(random)));
    }
    ref[f] = {plane};
    test[f] = {noisy};
  }
  writeClip(dir / "ref.yuv", ref, bitDepth);
  writeClip(dir / "test.yuv", test, bitDepth);
  const ToolResult result = runTool(quoted((dir / "ref.yuv").string()) + " " + quoted((dir / "test.yuv").string()) +
                                        " 5 3 --chroma 400 --bitdepth=10 --start 1 --frames=2",
                                    dir);
  ASSERT_EQ(result.exitCode, 0) << result.out << result.err;
  const ParsedOutput parsed = parseOutput(result.out);
  ASSERT_EQ(parsed.frameIndices, (std::vector<int64_t>{1, 2})) << result.out;
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(parsed.frameValues[i].size(), 1u) << "4:0:0 prints Y only\n" << result.out;
    expectPrinted(parsed.frameValues[i][0], expectedPsnr(ref[i + 1][0], test[i + 1][0], bitDepth), "Y");
  }
  ASSERT_EQ(parsed.meanPlanes, (std::vector<std::string>{"Y"})) << result.out;
  expectPrinted(parsed.frameMeans[0],
                (expectedPsnr(ref[1][0], test[1][0], 10) + expectedPsnr(ref[2][0], test[2][0], 10)) / 2, "mean Y");
}

TEST_F(YuvPsnrAppTest, ComparesTheFramesOfTheShorterFile) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_shorter");
  const std::vector<int> plane(16, 100);
  const std::vector<int> chroma(4, 128);
  writeClip(dir / "ref.yuv", Clip(3, {plane, chroma, chroma}), 8);
  writeClip(dir / "test.yuv", Clip(2, {plane, chroma, chroma}), 8);
  {
    std::ofstream partial(dir / "test.yuv", std::ios::binary | std::ios::app);
    partial << "abc";  // a trailing partial frame
  }
  const ToolResult result =
      runTool(quoted((dir / "ref.yuv").string()) + " " + quoted((dir / "test.yuv").string()) + " 4 4", dir);
  ASSERT_EQ(result.exitCode, 0) << result.out << result.err;
  const ParsedOutput parsed = parseOutput(result.out);
  EXPECT_EQ(parsed.frameIndices, (std::vector<int64_t>{0, 1})) << result.out;
  EXPECT_NE(result.err.find("partial frame of 3 bytes"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("holds 3 whole frames"), std::string::npos) << result.err;
  ASSERT_EQ(parsed.meanNotes.size(), 4u) << result.out;
  EXPECT_EQ(parsed.frameMeans[0], kInf);
  EXPECT_NE(parsed.meanNotes[0].find("all frames identical"), std::string::npos) << parsed.meanNotes[0];

  const ToolResult tooMany = runTool(quoted((dir / "ref.yuv").string()) + " " +
                                         quoted((dir / "test.yuv").string()) + " 4 4 --start 1 --frames 2",
                                     dir);
  EXPECT_EQ(tooMany.exitCode, 1) << tooMany.out;
  EXPECT_NE(tooMany.err.find("test.yuv"), std::string::npos) << tooMany.err;
  EXPECT_NE(tooMany.err.find("holds 2 whole frames"), std::string::npos) << tooMany.err;
}

TEST_F(YuvPsnrAppTest, HelpListsEveryOptionAndExitsZero) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_help");
  const ToolResult result = runTool("--help", dir);
  EXPECT_EQ(result.exitCode, 0);
  for (const char* expected : {"Usage:\n  YuvPsnr REF.yuv TEST.yuv WIDTH HEIGHT", "--frames", "--start", "--bitdepth", "--chroma", "default 8",
                               "range 8..16", "420|444|400", "6 Y + U + V"})
    EXPECT_NE(result.out.find(expected), std::string::npos) << expected << "\n" << result.out;
  EXPECT_EQ(runTool("a.yuv --help", dir).exitCode, 0);
}

TEST_F(YuvPsnrAppTest, BadArgumentsExitTwoWithAMessage) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_badargs");
  const std::pair<const char*, const char*> cases[] = {
      {"", "expected 4 arguments"},
      {"a.yuv b.yuv 16", "expected 4 arguments"},
      {"a.yuv b.yuv 16 abc", "HEIGHT 'abc'"},
      {"a.yuv b.yuv -16 16", "WIDTH '-16'"},
      {"a.yuv b.yuv 16 16 --chroma 422", "--chroma F: expected one of 420, 444, 400, got '422'"},
      {"a.yuv b.yuv 16 16 --bitdepth 7", "--bitdepth B: expected an integer in [8, 16], got '7'"},
      {"a.yuv b.yuv 16 16 --frames 0", "--frames N: expected an integer in [1, 9223372036854775807], got '0'"},
      {"a.yuv b.yuv 16 16 --frobnicate", "unknown option '--frobnicate'"},
      {"a.yuv b.yuv 16 16 --start", "--start needs S"},
  };
  for (const auto& [arguments, message] : cases) {
    const ToolResult result = runTool(arguments, dir);
    EXPECT_EQ(result.exitCode, 2) << arguments;
    EXPECT_NE(result.err.find(message), std::string::npos) << arguments << "\n" << result.err;
    EXPECT_TRUE(result.out.empty()) << arguments << "\n" << result.out;
  }
  // Every problem in one run.
  const ToolResult several = runTool("a.yuv b.yuv x 16 --chroma 9 --bitdepth 99", dir);
  EXPECT_EQ(several.exitCode, 2);
  for (const char* message : {"WIDTH 'x'", "--chroma F: expected one of 420, 444, 400, got '9'",
                              "--bitdepth B: expected an integer in [8, 16], got '99'"})
    EXPECT_NE(several.err.find(message), std::string::npos) << message << "\n" << several.err;
}

TEST_F(YuvPsnrAppTest, MissingFileExitsOneNamingIt) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_missing");
  writeClip(dir / "ref.yuv", Clip(1, {std::vector<int>(16, 1), std::vector<int>(4, 2), std::vector<int>(4, 3)}), 8);
  const std::string missing = (dir / "missing.yuv").string();
  const ToolResult result = runTool(quoted((dir / "ref.yuv").string()) + " " + quoted(missing) + " 4 4", dir);
  EXPECT_EQ(result.exitCode, 1);
  EXPECT_NE(result.err.find(missing), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("No such file or directory"), std::string::npos) << result.err;
}
