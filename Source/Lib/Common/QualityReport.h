#pragma once
// The quality metrics a run scores each frame with against ReferenceVirtualViewImageName, beyond the
// PSNR it always reports (key QualityMetrics; doc/metrics.md). The frame loop score()s each frame;
// the run report (Pipeline/RunReport) prints keys() and the values in the log, the CSV and the JSON.
#include <string>
#include <vector>

#include "Common/Frame.h"
#include "Common/IvPsnr.h"

namespace vs {

class QualityReport {
public:
  // `metrics`: names from psnr, ivpsnr, wspsnr, ssim, msssim (psnr is always reported and adds
  // nothing here). Returns false and names the first unknown one in `error`.
  static bool validate(const std::vector<std::string>& metrics, std::string& error);

  QualityReport(const std::vector<std::string>& metrics, bool hasChroma);
  bool empty() const { return keys_.empty(); }
  // The latitude range (degrees, centred on the equator) of the equirectangular pictures WS-PSNR scores:
  // an ERP virtual camera's Ver_range span; 180 (the whole sphere) unless set.
  void setLatitudeRange(double degrees) { latitudeRangeDeg_ = degrees; }
  // CSV column names, each preceded by a comma ("" when empty()).
  std::string csvHeader() const;
  // Scores one frame; then csvCells() (each value preceded by a comma) and logText() describe it.
  void score(const Frame& truth, const Frame& output);
  std::string csvCells() const;
  std::string logText() const;
  // "name mean ..." of the frames scored so far (dB metrics leave inf frames out).
  std::string meanText() const;

  // The column names (ivpsnr, wspsnr_y ... msssim_yuv), whether each is in dB, and the last frame's values.
  const std::vector<std::string>& keys() const { return keys_; }
  bool decibel(size_t column) const { return decibel_[column]; }
  const std::vector<double>& lastValues() const { return last_; }
  // The mean of one column over frames' values: dB columns leave +inf out (+inf when all are).
  static double mean(const std::vector<double>& values, bool decibel);
  // A value as the CSV and the log print it: 4 decimals for dB, 6 for indices; inf, nan as words.
  std::string format(size_t column, double value) const;

private:
  bool ivpsnr_ = false, wspsnr_ = false, ssim_ = false, msssim_ = false, hasChroma_ = true;
  double latitudeRangeDeg_ = 180.0;
  std::vector<std::string> keys_;  // ivpsnr, wspsnr_y, ..., ssim_yuv, msssim_y, ...
  std::vector<bool> decibel_;
  std::vector<double> last_, sum_;
  std::vector<long long> counted_;
  IvPsnrScratch ivpsnrScratch_;  // IV-PSNR's padded pictures, reused frame after frame
};

}  // namespace vs
