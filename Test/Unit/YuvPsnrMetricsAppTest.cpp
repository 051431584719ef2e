// YuvPsnr's --metrics, its options, WxH and the CSV and JSON reports: Bin/YuvPsnr on files written
// here, its numbers read back and compared with the library (itself checked against the plain
// definitions in IvPsnrTest and SsimTest) and with cases whose answer is known.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "TestFormat.h"

#include "Common/Frame.h"
#include "Common/IvPsnr.h"
#include "Common/Json.h"
#include "Common/Ssim.h"
#include "Common/Yuv.h"
#include "Process.h"
#include "TestPaths.h"

namespace fs = std::filesystem;

namespace {

using vs::test::quoted;
using vs::test::ToolResult;

ToolResult runTool(const std::string& arguments, const fs::path& scratch) {
  return vs::test::runTool("YuvPsnr", arguments, scratch);
}

using test::makeFormat;

// Three frames: random texture with repeated first and last columns, and the test clip the same
// shifted left by one sample in every plane (4:4:4) plus, in frame 2, noise.
void writeClips(const fs::path& refPath, const fs::path& testPath, const vs::FrameFormat& format,
                std::vector<vs::Frame>& refs, std::vector<vs::Frame>& tests) {
  std::mt19937 random(4);
  std::uniform_int_distribution<int> sample(0, format.maxValue());
  std::normal_distribution<double> noise(0, 3);
  vs::YuvWriter refWriter(refPath.string(), format), testWriter(testPath.string(), format);
  for (int f = 0; f < 3; ++f) {
    vs::Frame ref(format), test(format);
    for (int p = 0; p < vs::planeCount(format.chroma); ++p) {
      vs::Plane& a = ref.planes[p];
      for (uint16_t& s : a.samples) s = uint16_t(sample(random));
      for (int y = 0; y < a.height; ++y) a.at(0, y) = a.at(a.width - 1, y) = a.at(1, y);
      for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
          double v = a.at(std::min(x + 1, a.width - 1), y);
          if (f == 2) v += noise(random);
          test.planes[p].at(x, y) = uint16_t(std::clamp(std::lround(v), 0L, long(format.maxValue())));
        }
    }
    refWriter.append(ref);
    testWriter.append(test);
    refs.push_back(ref);
    tests.push_back(test);
  }
  refWriter.commit();  // a writer renames its file into place only when told the output is complete
  testWriter.commit();
}

std::vector<std::vector<std::string>> readCsv(const fs::path& path) {
  std::ifstream file(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(file, line)) {
    std::vector<std::string> cells;
    std::stringstream cellStream(line);
    std::string cell;
    while (std::getline(cellStream, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

double cellValue(const std::string& text) {
  if (text == "nan") return std::numeric_limits<double>::quiet_NaN();
  return text == "inf" ? std::numeric_limits<double>::infinity() : std::stod(text);
}

// Equal, or both NaN (MS-SSIM of a picture too small for its coarse scales).
void expectSame(double printed, double expected) {
  if (std::isnan(expected)) {
    EXPECT_TRUE(std::isnan(printed));
  } else {
    EXPECT_EQ(printed, expected);
  }
}

class YuvPsnrMetricsAppTest : public ::testing::Test {
protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(vs::test::binDir() / "YuvPsnr")) << "build the YuvPsnr target";
  }
};

}  // namespace

TEST_F(YuvPsnrMetricsAppTest, CsvAndJsonCarryEveryMetricPerFrameAndTheMean) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_metrics");
  const vs::FrameFormat format = makeFormat(48, 30, 10, vs::ChromaFormat::Yuv444);
  std::vector<vs::Frame> refs, tests;
  writeClips(dir / "ref.yuv", dir / "test.yuv", format, refs, tests);
  const ToolResult result =
      runTool(quoted((dir / "ref.yuv").string()) + " " + quoted((dir / "test.yuv").string()) +
                  " 48x30 --bitdepth 10 --chroma 444 --metrics all --csv " + quoted((dir / "out.csv").string()) +
                  " --json=" + quoted((dir / "out.json").string()),
              dir);
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("IV-PSNR"), std::string::npos);
  EXPECT_NE(result.out.find("(2 identical frames left out)"), std::string::npos) << result.out;

  const auto rows = readCsv(dir / "out.csv");
  ASSERT_EQ(rows.size(), 5u);  // header, 3 frames, mean
  const std::vector<std::string>& header = rows[0];
  ASSERT_EQ(header.size(), 18u);
  EXPECT_EQ(header[0], "frame");
  EXPECT_EQ(header[5], "ivpsnr");
  EXPECT_EQ(header[17], "msssim_yuv");
  auto column = [&](const std::string& key) { return size_t(std::find(header.begin(), header.end(), key) - header.begin()); };
  for (int f = 0; f < 3; ++f) {
    const std::vector<std::string>& row = rows[size_t(f + 1)];
    EXPECT_EQ(row[0], std::to_string(f));
    const double iv = vs::ivPsnr(refs[size_t(f)], tests[size_t(f)]).ivpsnr;
    // The shift alone is matched exactly (frames 0 and 1); noise is not (frame 2).
    if (f < 2) {
      EXPECT_TRUE(std::isinf(iv));
    }
    EXPECT_EQ(cellValue(row[column("ivpsnr")]), iv);
    EXPECT_EQ(cellValue(row[column("ssim_u")]), vs::ssim(refs[size_t(f)], tests[size_t(f)]).plane[1]);
    expectSame(cellValue(row[column("msssim_y")]), vs::msSsim(refs[size_t(f)], tests[size_t(f)]).plane[0]);
    EXPECT_EQ(cellValue(row[column("wspsnr_v")]), vs::wsPsnr(refs[size_t(f)], tests[size_t(f)]).plane[2]);
    EXPECT_TRUE(std::isfinite(cellValue(row[column("psnr_y")])));
  }
  // Means: IV-PSNR over the one finite frame; SSIM over all three.
  EXPECT_EQ(rows[4][0], "mean");
  EXPECT_EQ(cellValue(rows[4][column("ivpsnr")]), cellValue(rows[3][column("ivpsnr")]));
  const double ssimMean = (cellValue(rows[1][column("ssim_y")]) + cellValue(rows[2][column("ssim_y")]) +
                           cellValue(rows[3][column("ssim_y")])) / 3;
  EXPECT_NEAR(cellValue(rows[4][column("ssim_y")]), ssimMean, 1e-15);

  std::ifstream jsonFile(dir / "out.json");
  const std::string text((std::istreambuf_iterator<char>(jsonFile)), std::istreambuf_iterator<char>());
  const vs::JsonValue json = vs::parseJson(text, "out.json");
  const vs::JsonValue* frames = json.find("frames");
  ASSERT_TRUE(frames && frames->items.size() == 3);
  EXPECT_TRUE(std::isinf(frames->items[0].find("ivpsnr")->number));
  EXPECT_EQ(frames->items[2].find("ivpsnr")->number, cellValue(rows[3][column("ivpsnr")]));
  EXPECT_EQ(json.find("mean")->find("ssim_y")->number, cellValue(rows[4][column("ssim_y")]));
}

TEST_F(YuvPsnrMetricsAppTest, SizeAsWxHAndOptionsReachTheMetrics) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_metrics_options");
  const vs::FrameFormat format = makeFormat(48, 30, 10, vs::ChromaFormat::Yuv444);
  std::vector<vs::Frame> refs, tests;
  writeClips(dir / "ref.yuv", dir / "test.yuv", format, refs, tests);
  const std::string files = quoted((dir / "ref.yuv").string()) + " " + quoted((dir / "test.yuv").string());
  // WxH and WIDTH HEIGHT print the same; without --metrics only PSNR is printed.
  const ToolResult a = runTool(files + " 48x30 --bitdepth 10 --chroma 444", dir);
  const ToolResult b = runTool(files + " 48 30 --bitdepth 10 --chroma 444", dir);
  ASSERT_EQ(a.exitCode, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(a.out.find("IV-PSNR"), std::string::npos);
  // Range 0 and no offset correction: IV-PSNR is the 4:1:1 mean of the plane PSNRs, not inf.
  const ToolResult c = runTool(files + " 48x30 --bitdepth 10 --chroma 444 --frames 1 --metrics ivpsnr "
                                       "--search-range 0 --unnoticeable 0 --csv " + quoted((dir / "c.csv").string()),
                               dir);
  ASSERT_EQ(c.exitCode, 0) << c.err;
  vs::IvPsnrOptions options;
  options.searchRange = 0;
  options.unnoticeable[0] = options.unnoticeable[1] = options.unnoticeable[2] = 0;
  const double expected = vs::ivPsnr(refs[0], tests[0], options).ivpsnr;
  EXPECT_TRUE(std::isfinite(expected));
  EXPECT_EQ(cellValue(readCsv(dir / "c.csv")[1][1]), expected);
  // --ssim-convention wang and --average-weights reach SSIM.
  const ToolResult d = runTool(files + " 48x30 --bitdepth 10 --chroma 444 --frames 1 --metrics ssim "
                                       "--ssim-convention wang --average-weights 1:1:1 --threads 3 --csv " +
                                   quoted((dir / "d.csv").string()),
                               dir);
  ASSERT_EQ(d.exitCode, 0) << d.err;
  vs::SsimOptions ssimOptions;
  ssimOptions.convention = vs::SsimConvention::Wang;
  ssimOptions.averageWeights[0] = 1;
  const vs::FrameQuality ssim = vs::ssim(refs[0], tests[0], ssimOptions);
  const auto rows = readCsv(dir / "d.csv");
  EXPECT_EQ(cellValue(rows[1][1]), ssim.plane[0]);
  EXPECT_EQ(cellValue(rows[1][4]), ssim.yuv);
}

TEST_F(YuvPsnrMetricsAppTest, BadMetricOptionsAreNamed) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_metrics_errors");
  const std::pair<const char*, const char*> cases[] = {
      {"a.yuv b.yuv 16x16 --metrics psnr,foo", "--metrics LIST: expected a comma-separated list of psnr, ivpsnr, wspsnr, ssim, msssim (or all), got 'psnr,foo'"},
      {"a.yuv b.yuv 16x16 --metrics ''", "--metrics LIST: expected a comma-separated list of psnr, ivpsnr, wspsnr, ssim, msssim (or all), got ''"},
      {"a.yuv b.yuv 16x --metrics psnr", "size '16x'"},
      {"a.yuv b.yuv 16x16 --search-range 17", "--search-range R: expected an integer in [0, 16], got '17'"},
      {"a.yuv b.yuv 16x16 --search-weights 0:0:0", "--search-weights Y:U:V: expected Y:U:V of integers in 0..1000, not all 0, got '0:0:0'"},
      {"a.yuv b.yuv 16x16 --average-weights 0:1:1", "--average-weights Y:U:V: expected Y:U:V of integers in 0..1000, not all 0, Y > 0, got '0:1:1'"},
      {"a.yuv b.yuv 16x16 --unnoticeable 2", "--unnoticeable F[:F:F]: expected F or F:F:F with each F in 0..1, got '2'"},
      {"a.yuv b.yuv 16x16 --ssim-convention matlab", "--ssim-convention C: expected one of qmiv, wang, got 'matlab'"},
      {"a.yuv b.yuv 16x16 --latitude-range 0", "--latitude-range DEG: expected a number of degrees in (0, 180], got '0'"},
      {"a.yuv b.yuv 16x16 --csv", "--csv needs FILE"},
  };
  for (const auto& [arguments, message] : cases) {
    const ToolResult result = runTool(arguments, dir);
    EXPECT_EQ(result.exitCode, 2) << arguments;
    EXPECT_NE(result.err.find(message), std::string::npos) << arguments << "\n" << result.err;
  }
  // An unwritable report is refused before any work, with exit code 1.
  const vs::FrameFormat format = makeFormat(16, 16, 8, vs::ChromaFormat::Yuv420);
  vs::Frame frame(format);
  frame.fill(9);
  vs::YuvWriter writer((dir / "a.yuv").string(), format);
  writer.append(frame);
  writer.commit();
  const ToolResult result = runTool(quoted((dir / "a.yuv").string()) + " " + quoted((dir / "a.yuv").string()) +
                                        " 16x16 --metrics ssim --json " + quoted((dir / "no/such/dir/r.json").string()),
                                    dir);
  EXPECT_EQ(result.exitCode, 1);
  EXPECT_NE(result.err.find("r.json"), std::string::npos) << result.err;
  EXPECT_EQ(result.out.find("mean"), std::string::npos);
}

TEST_F(YuvPsnrMetricsAppTest, HelpListsEveryOption) {
  const fs::path dir = vs::test::scratchDir("yuvpsnr_metrics_help");
  const ToolResult result = runTool("--help", dir);
  ASSERT_EQ(result.exitCode, 0);
  for (const char* option : {"--metrics", "--search-range", "--unnoticeable", "--search-weights", "--average-weights",
                             "--ssim-convention", "--latitude-range", "--threads", "--csv", "--json", "WIDTHxHEIGHT"})
    EXPECT_NE(result.out.find(option), std::string::npos) << option;
}
