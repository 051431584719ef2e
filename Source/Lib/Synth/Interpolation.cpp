#include "Synth/Interpolation.h"

#include <algorithm>
#include <cmath>

#include "Common/Error.h"

namespace vs {

namespace {

double cubic(double x) {  // Keys, a = -0.5
  const double a = -0.5;
  x = std::fabs(x);
  if (x <= 1) return (a + 2) * x * x * x - (a + 3) * x * x + 1;
  if (x < 2) return a * x * x * x - 5 * a * x * x + 8 * a * x - 4 * a;
  return 0;
}

}  // namespace

SubPixelSampler::SubPixelSampler(int precision, int filter) : precision_(precision) {
  VS_CHECK(precision == 1 || precision == 2 || precision == 4);
  precisionShift_ = precision == 1 ? 0 : precision == 2 ? 1 : 2;
  VS_CHECK(filter >= 0 && filter <= 2);
  if (filter == 0) {
    taps_ = 2;
    first_ = 0;
  } else if (filter == 1) {
    taps_ = 4;
    first_ = -1;
  } else {
    taps_ = 6;
    first_ = -2;
  }
  kernels_.assign(size_t(precision) * size_t(taps_), 0.0f);
  for (int phase = 0; phase < precision; ++phase) {
    const double f = double(phase) / precision;
    float* k = &kernels_[size_t(phase) * size_t(taps_)];
    if (filter == 0) {
      k[0] = float(1 - f);
      k[1] = float(f);
    } else if (filter == 1) {
      for (int t = 0; t < 4; ++t) k[t] = float(cubic(f - (t + first_)));
    } else {
      static const double half[6] = {1 / 32.0, -5 / 32.0, 20 / 32.0, 20 / 32.0, -5 / 32.0, 1 / 32.0};
      double w[6] = {0, 0, 0, 0, 0, 0};
      if (phase * 4 == 0) {
        w[2] = 1;
      } else if (phase * 4 == precision * 2) {
        for (int t = 0; t < 6; ++t) w[t] = half[t];
      } else if (phase * 4 == precision) {  // quarter: mean of integer and half pel
        for (int t = 0; t < 6; ++t) w[t] = 0.5 * half[t];
        w[2] += 0.5;
      } else {  // three quarters: mean of half pel and the next integer
        for (int t = 0; t < 6; ++t) w[t] = 0.5 * half[t];
        w[3] += 0.5;
      }
      for (int t = 0; t < 6; ++t) k[t] = float(w[t]);
    }
  }
}

float SubPixelSampler::sampleRow(const Plane& plane, double x, long long y) const {
  // sample() with phase 0 vertically: only the row of weight exactly 1 contributes, and
  // 0 + 1 * rowSum is rowSum. The horizontal pass is sample()'s own: all taps inside the plane (zero
  // weights add +0), clamped taps of non-zero weight at its border.
  long long ix;
  int px;
  gridPosition(x, ix, px);
  const long long maxX = plane.width - 1;
  const uint16_t* row = plane.row(int(std::clamp(y, 0LL, (long long)plane.height - 1)));
  if (px == 0) return float(row[std::clamp(ix, 0LL, maxX)]);
  const float* kx = kernel(px);
  const long long left = ix + first_;
  float rowSum = 0.0f;
  if (left >= 0 && left + taps_ - 1 <= maxX) {
    const uint16_t* taps = row + left;
    for (int tx = 0; tx < taps_; ++tx) rowSum += kx[tx] * float(taps[tx]);
    return rowSum;
  }
  for (int tx = 0; tx < taps_; ++tx) {
    if (kx[tx] == 0.0f) continue;
    rowSum += kx[tx] * float(row[std::clamp(ix + first_ + tx, 0LL, maxX)]);
  }
  return rowSum;
}

float SubPixelSampler::sample(const Plane& plane, double x, double y) const {
  // Round to the 1/precision grid. floor() of the scaled position keeps negative positions right
  // (truncation towards zero would move them the wrong way).
  long long ix, iy;
  int px, py;
  gridPosition(x, ix, px);
  gridPosition(y, iy, py);
  const float* kx = kernel(px);
  const float* ky = kernel(py);
  const long long maxX = plane.width - 1, maxY = plane.height - 1;
  if (px == 0 && py == 0) {
    const long long cx = std::clamp(ix, 0LL, maxX), cy = std::clamp(iy, 0LL, maxY);
    return float(plane.at(int(cx), int(cy)));
  }
  const long long left = ix + first_, top = iy + first_;
  if (left >= 0 && top >= 0 && left + taps_ - 1 <= maxX && top + taps_ - 1 <= maxY) {
    // Inside the plane: no clamping; rows whose weight is 0 (phase 0) are skipped.
    float sum = 0.0f;
    for (int ty = 0; ty < taps_; ++ty) {
      if (ky[ty] == 0.0f) continue;
      const uint16_t* row = plane.row(int(top + ty)) + left;
      float rowSum = 0.0f;
      for (int tx = 0; tx < taps_; ++tx) rowSum += kx[tx] * float(row[tx]);
      sum += ky[ty] * rowSum;
    }
    return sum;
  }
  float sum = 0.0f;
  for (int ty = 0; ty < taps_; ++ty) {
    if (ky[ty] == 0.0f) continue;
    const long long sy = std::clamp(iy + first_ + ty, 0LL, maxY);
    const uint16_t* row = plane.row(int(sy));
    float rowSum = 0.0f;
    for (int tx = 0; tx < taps_; ++tx) {
      if (kx[tx] == 0.0f) continue;
      const long long sx = std::clamp(ix + first_ + tx, 0LL, maxX);
      rowSum += kx[tx] * float(row[sx]);
    }
    sum += ky[ty] * rowSum;
  }
  return sum;
}

}  // namespace vs
