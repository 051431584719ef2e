// QualityReport: the QualityMetrics key's names, the CSV columns, and values equal to the metric
// functions' (themselves checked against plain definitions in IvPsnrTest and SsimTest).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Frame.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "Common/QualityReport.h"
#include "Common/Ssim.h"

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
