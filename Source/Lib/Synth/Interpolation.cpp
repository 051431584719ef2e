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
  kernels_.fill(0.0f);  // precision * taps_ <= 24 (checked above)
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

}  // namespace vs
