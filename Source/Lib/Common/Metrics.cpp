#include "Common/Metrics.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace vs {

double planeMse(const Plane& a, const Plane& b) {
  VS_CHECK_MSG(a.width == b.width && a.height == b.height, "planes of different sizes");
  VS_CHECK(a.samples.size() == size_t(a.width) * size_t(a.height) && b.samples.size() == a.samples.size());
  VS_CHECK_MSG(!a.samples.empty(), "MSE of empty planes");
  // 64-bit integer sum is exact: a squared 16-bit difference is < 2^32, so overflow needs > 2^32 samples.
  uint64_t sum = 0;
  const uint16_t* pa = a.samples.data();
  const uint16_t* pb = b.samples.data();
  const size_t count = a.samples.size();
  for (size_t i = 0; i < count; ++i) {
    const int64_t d = int64_t(pa[i]) - int64_t(pb[i]);
    sum += uint64_t(d * d);
  }
  return double(sum) / double(count);
}

double psnrFromMse(double mse, int bitDepth) {
  VS_CHECK(bitDepth >= 1 && bitDepth <= 16);
  VS_CHECK_MSG(mse >= 0, "negative or NaN MSE");
  if (mse == 0) return std::numeric_limits<double>::infinity();
  const double peak = double((1 << bitDepth) - 1);
  return 10.0 * std::log10(peak * peak / mse);
}

double weightedYuvPsnr(double y, double u, double v) { return (6.0 * y + u + v) / 8.0; }

std::string formatPsnr(double db, int decimals) {
  if (std::isinf(db)) return db > 0 ? "inf" : "-inf";
  if (std::isnan(db)) return "nan";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, db);
  return text;
}

FramePsnr framePsnr(const Frame& ref, const Frame& test) {
  VS_CHECK_MSG(ref.format == test.format, "PSNR of frames of different formats");
  const int bitDepth = ref.format.bitDepth;
  FramePsnr result;
  result.mseY = planeMse(ref.planes[0], test.planes[0]);
  result.y = psnrFromMse(result.mseY, bitDepth);
  result.hasChroma = ref.format.chroma != ChromaFormat::Yuv400;
  if (!result.hasChroma) {
    result.yuv = result.y;
    return result;
  }
  result.mseU = planeMse(ref.planes[1], test.planes[1]);
  result.mseV = planeMse(ref.planes[2], test.planes[2]);
  result.u = psnrFromMse(result.mseU, bitDepth);
  result.v = psnrFromMse(result.mseV, bitDepth);
  result.yuv = weightedYuvPsnr(result.y, result.u, result.v);
  return result;
}

void PsnrAccumulator::Sums::add(double psnr, double mse) {
  if (std::isinf(psnr)) ++identicalFrames;
  else finitePsnrSum += psnr;
  mseSum += mse;
}

PsnrAccumulator::PsnrAccumulator(int bitDepth, bool hasChroma) : bitDepth_(bitDepth), hasChroma_(hasChroma) {
  VS_CHECK(bitDepth >= 1 && bitDepth <= 16);
}

void PsnrAccumulator::add(const FramePsnr& frame) {
  VS_CHECK_MSG(frame.hasChroma == hasChroma_, "a frame's chroma presence differs from the accumulator's");
  ++frames_;
  planes_[0].add(frame.y, frame.mseY);
  if (hasChroma_) {
    planes_[1].add(frame.u, frame.mseU);
    planes_[2].add(frame.v, frame.mseV);
  }
  yuv_.add(frame.yuv, 0);
}

PsnrAccumulator::Mean PsnrAccumulator::mean(const Sums& sums) const {
  VS_CHECK_MSG(frames_ > 0, "mean PSNR of no frames");
  Mean result;
  result.identicalFrames = sums.identicalFrames;
  const int64_t finiteFrames = frames_ - sums.identicalFrames;
  result.frameMean = finiteFrames > 0 ? sums.finitePsnrSum / double(finiteFrames)
                                      : std::numeric_limits<double>::infinity();
  result.psnrOfMeanMse = psnrFromMse(sums.mseSum / double(frames_), bitDepth_);
  return result;
}

PsnrAccumulator::Mean PsnrAccumulator::y() const { return mean(planes_[0]); }

PsnrAccumulator::Mean PsnrAccumulator::u() const {
  VS_CHECK(hasChroma_);
  return mean(planes_[1]);
}

PsnrAccumulator::Mean PsnrAccumulator::v() const {
  VS_CHECK(hasChroma_);
  return mean(planes_[2]);
}

PsnrAccumulator::Mean PsnrAccumulator::yuv() const {
  if (!hasChroma_) return y();
  Mean result = mean(yuv_);
  result.psnrOfMeanMse = weightedYuvPsnr(y().psnrOfMeanMse, u().psnrOfMeanMse, v().psnrOfMeanMse);
  return result;
}

}  // namespace vs
