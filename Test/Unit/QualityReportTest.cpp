// QualityReport and the QualityMetrics key: names, CSV columns, values equal to the metric functions'
// (themselves checked against plain definitions in IvPsnrTest and SsimTest), and a real ViewSyn run.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/IvPsnr.h"
#include "Common/Json.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "Common/QualityReport.h"
#include "Common/Ssim.h"
#include "Common/Yuv.h"
#include "Synth/ViewSynRenderer.h"
#include "TestPaths.h"

TEST(QualityReport, NamesUnknownMetrics) {
  std::string error;
  EXPECT_TRUE(vs::QualityReport::validate({"psnr", "ivpsnr", "wspsnr", "ssim", "msssim"}, error));
  EXPECT_FALSE(vs::QualityReport::validate({"ssim", "vmaf"}, error));
  EXPECT_NE(error.find("'vmaf'"), std::string::npos);
}

TEST(QualityReport, ColumnsAndValues) {
  vs::FrameFormat format;
  format.width = 24;
  format.height = 20;
  vs::Frame truth(format), output(format);
  for (int p = 0; p < 3; ++p)
    for (size_t i = 0; i < truth.planes[p].samples.size(); ++i) {
      truth.planes[p].samples[i] = uint16_t((i * 37 + size_t(p) * 11) % 256);
      output.planes[p].samples[i] = uint16_t((i * 37 + size_t(p) * 11 + i % 5) % 256);
    }
  vs::QualityReport none({"psnr"}, true);
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.csvHeader(), "");
  vs::QualityReport report({"ssim", "ivpsnr"}, true);
  EXPECT_EQ(report.csvHeader(), ",ivpsnr,ssim_y,ssim_u,ssim_v,ssim_yuv");
  report.score(truth, output);
  const vs::FrameQuality ssim = vs::ssim(truth, output);
  const std::string expected = "," + vs::formatPsnr(vs::ivPsnr(truth, output).ivpsnr, 4) + "," +
                               vs::formatPsnr(ssim.plane[0], 6) + "," + vs::formatPsnr(ssim.plane[1], 6) + "," +
                               vs::formatPsnr(ssim.plane[2], 6) + "," + vs::formatPsnr(ssim.yuv, 6);
  EXPECT_EQ(report.csvCells(), expected);
  // A second, identical frame: IV-PSNR inf is left out of the mean, SSIM is not.
  report.score(truth, truth);
  EXPECT_NE(report.csvCells().find("inf"), std::string::npos);
  const std::string mean = report.meanText();
  EXPECT_NE(mean.find("ivpsnr " + vs::formatPsnr(vs::ivPsnr(truth, output).ivpsnr, 4)), std::string::npos) << mean;
  EXPECT_NE(mean.find("ssim_y " + vs::formatPsnr((ssim.plane[0] + vs::ssim(truth, truth).plane[0]) / 2, 6)),
            std::string::npos) << mean;
  vs::QualityReport luma({"wspsnr"}, false);
  EXPECT_EQ(luma.csvHeader(), ",wspsnr_y");
}

namespace vs {
namespace {

// ViewSyn on Art view 3 with QualityMetrics writes the metrics' columns to the report CSV, with the
// values the library functions give for its output against the truth.
TEST(QualityReport, ViewSynReportCarriesTheChosenMetrics) {
  const std::filesystem::path data = test::dataDir();
  VS_REQUIRE_DIR(data / "middlebury2005");
  const std::filesystem::path scene = data / "middlebury2005" / "Art";
  const std::filesystem::path scratch = test::scratchDir("quality_metrics_key");
  const std::string out = (scratch / "out.yuv").string(), csv = (scratch / "report.csv").string();
  const std::string truthPath = (scene / "view3.yuv").string();
  const Config config = Config::load(viewSynOptionTable(), (scene / "synth_view3_general.cfg").string(),
                                     {"OutputVirtualViewImageName=" + out, "ReferenceVirtualViewImageName=" + truthPath,
                                      "QualityMetrics=ivpsnr,msssim", "ReportFile=" + csv,
                                      "SummaryFile=" + (scratch / "summary.json").string()});
  runViewSyn(config, nullptr);
  std::ifstream file(csv);
  std::string header, row;
  std::getline(file, header);
  std::getline(file, row);
  EXPECT_NE(header.find("total_s,ivpsnr,msssim_y,msssim_u,msssim_v,msssim_yuv"), std::string::npos) << header;
  FrameFormat format;
  format.width = 688;
  format.height = 554;
  Frame truth, output;
  YuvReader(truthPath, format).read(0, truth);
  YuvReader(out, format).read(0, output);
  const std::string expected = "," + formatPsnr(ivPsnr(truth, output).ivpsnr, 4) + "," +
                               formatPsnr(msSsim(truth, output).plane[0], 6);
  EXPECT_NE(row.find(expected), std::string::npos) << row << " lacks " << expected;
  // The JSON summary carries the same, at full precision.
  std::ifstream jsonFile(scratch / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(jsonFile)), std::istreambuf_iterator<char>());
  const JsonValue summary = parseJson(text, "summary.json");
  EXPECT_DOUBLE_EQ(summary.find("frames")->items[0].find("ivpsnr")->number, ivPsnr(truth, output).ivpsnr);
  EXPECT_DOUBLE_EQ(summary.find("mean")->find("msssim_yuv")->number, msSsim(truth, output).yuv);

  // Without a reference view the key is a configuration error naming both keys.
  try {
    const Config bad = Config::load(viewSynOptionTable(), (scene / "synth_view3_general.cfg").string(),
                                    {"OutputVirtualViewImageName=" + out, "QualityMetrics=ssim"});
    runViewSyn(bad, nullptr);
    ADD_FAILURE() << "QualityMetrics without a reference view was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ReferenceVirtualViewImageName"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vs
