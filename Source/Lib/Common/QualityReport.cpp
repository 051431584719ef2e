#include "Common/QualityReport.h"

#include <cmath>
#include <cstdio>

#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "Common/Ssim.h"

namespace vs {

namespace {
const char* const kKnown[] = {"psnr", "ivpsnr", "wspsnr", "ssim", "msssim"};
}

bool QualityReport::validate(const std::vector<std::string>& metrics, std::string& error) {
  for (const std::string& name : metrics) {
    bool known = false;
    for (const char* k : kKnown) known = known || name == k;
    if (!known) {
      error = "'" + name + "' is not one of psnr, ivpsnr, wspsnr, ssim, msssim";
      return false;
    }
  }
  return true;
}

QualityReport::QualityReport(const std::vector<std::string>& metrics, bool hasChroma) : hasChroma_(hasChroma) {
  for (const std::string& name : metrics) {
    ivpsnr_ = ivpsnr_ || name == "ivpsnr";
    wspsnr_ = wspsnr_ || name == "wspsnr";
    ssim_ = ssim_ || name == "ssim";
    msssim_ = msssim_ || name == "msssim";
  }
  auto planes = [&](const char* metric, bool decibel) {
    const char* suffix[4] = {"_y", "_u", "_v", "_yuv"};
    for (int p = 0; p < (hasChroma ? 4 : 1); ++p) {
      keys_.push_back(std::string(metric) + suffix[p]);
      decibel_.push_back(decibel);
    }
  };
  if (ivpsnr_) {
    keys_.push_back("ivpsnr");
    decibel_.push_back(true);
  }
  if (wspsnr_) planes("wspsnr", true);
  if (ssim_) planes("ssim", false);
  if (msssim_) planes("msssim", false);
  last_.assign(keys_.size(), 0.0);
  sum_.assign(keys_.size(), 0.0);
  counted_.assign(keys_.size(), 0);
}

std::string QualityReport::csvHeader() const {
  std::string header;
  for (const std::string& key : keys_) header += "," + key;
  return header;
}

void QualityReport::score(const Frame& truth, const Frame& output) {
  std::vector<double> values;
  auto addPlanes = [&](const FrameQuality& q) {
    for (int p = 0; p < (hasChroma_ ? 3 : 1); ++p) values.push_back(q.plane[p]);
    if (hasChroma_) values.push_back(q.yuv);
  };
  if (ivpsnr_) values.push_back(ivPsnr(truth, output, IvPsnrOptions(), ivpsnrScratch_).ivpsnr);
  if (wspsnr_) addPlanes(wsPsnr(truth, output, latitudeRangeDeg_));
  if (ssim_) addPlanes(ssim(truth, output));
  if (msssim_) addPlanes(msSsim(truth, output));
  last_ = values;
  for (size_t i = 0; i < values.size(); ++i) {
    if (decibel_[i] && std::isinf(values[i])) continue;
    sum_[i] += values[i];
    ++counted_[i];
  }
}

std::string QualityReport::csvCells() const {
  std::string cells;
  for (size_t i = 0; i < last_.size(); ++i) cells += "," + formatPsnr(last_[i], decibel_[i] ? 4 : 6);
  return cells;
}

std::string QualityReport::logText() const {
  std::string text;
  for (size_t i = 0; i < last_.size(); ++i)
    text += "  " + keys_[i] + " " + formatPsnr(last_[i], decibel_[i] ? 4 : 6);
  return text;
}

double QualityReport::mean(const std::vector<double>& values, bool decibel) {
  double sum = 0;
  long long counted = 0;
  for (double v : values) {
    if (decibel && std::isinf(v)) continue;
    sum += v;
    ++counted;
  }
  if (counted == 0) return decibel && !values.empty() ? INFINITY : NAN;
  return sum / double(counted);
}

std::string QualityReport::format(size_t column, double value) const {
  return formatPsnr(value, decibel_[column] ? 4 : 6);
}

std::string QualityReport::meanText() const {
  std::string text;
  for (size_t i = 0; i < keys_.size(); ++i) {
    const double mean = counted_[i] > 0 ? sum_[i] / double(counted_[i]) : (decibel_[i] ? INFINITY : NAN);
    text += (i ? "  " : "") + keys_[i] + " " + formatPsnr(mean, decibel_[i] ? 4 : 6);
  }
  return text;
}

}  // namespace vs
