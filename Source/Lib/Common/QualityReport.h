#pragma once
// The quality metrics a run scores each frame with against ReferenceVirtualViewImageName, beyond the
// PSNR it always reports (key QualityMetrics; doc/metrics.md). One object per run: parse the list
// once, then score() each frame; the names and values go into the log line and the CSV report.
#include <string>
#include <vector>

#include "Common/Frame.h"

namespace vs {

class QualityReport {
public:
  // `metrics`: names from psnr, ivpsnr, wspsnr, ssim, msssim (psnr is always reported and adds
  // nothing here). Returns false and names the first unknown one in `error`.
  static bool validate(const std::vector<std::string>& metrics, std::string& error);

  QualityReport(const std::vector<std::string>& metrics, bool hasChroma);
  bool empty() const { return keys_.empty(); }
  // CSV column names, each preceded by a comma ("" when empty()).
  std::string csvHeader() const;
  // Scores one frame; then csvCells() (each value preceded by a comma) and logText() describe it.
  void score(const Frame& truth, const Frame& output);
  std::string csvCells() const;
  std::string logText() const;
  // "name mean ..." of the frames scored so far (dB metrics leave inf frames out).
  std::string meanText() const;

private:
  bool ivpsnr_ = false, wspsnr_ = false, ssim_ = false, msssim_ = false, hasChroma_ = true;
  std::vector<std::string> keys_;  // ivpsnr, wspsnr_y, ..., ssim_yuv, msssim_y, ...
  std::vector<bool> decibel_;
  std::vector<double> last_, sum_;
  std::vector<long long> counted_;
};

}  // namespace vs
