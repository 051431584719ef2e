#pragma once
// Sub-pixel sampling of a plane (VSRS's Precision and Filter keys, in both directions).
//
// A position is first rounded to the 1/precision pel grid (Precision 1, 2, 4: integer, half, quarter
// pel), then the plane is interpolated there with a separable kernel:
//   Filter 0  bilinear           (1 - f, f)
//   Filter 1  bicubic            Keys' cubic convolution with a = -0.5 (Catmull-Rom), 4 taps
//   Filter 2  MPEG-4 AVC         half pel (1, -5, 20, 20, -5, 1) / 32; quarter pel the mean of the
//                                nearest integer and half-pel kernels, as in H.264's luma rule
// Every kernel is exactly (0, ..., 1, ..., 0) at phase 0, so integer positions return the sample
// itself. Positions outside the plane read the nearest edge sample (never outside the buffer).
#include <cmath>
#include <vector>

#include "Common/Frame.h"

namespace vs {

class SubPixelSampler {
public:
  SubPixelSampler(int precision, int filter);

  // Value at (x, y), in the plane's own sample coordinates (integers are sample centres), not rounded
  // or clamped to the sample range: bicubic and 6-tap kernels may overshoot; callers clamp.
  float sample(const Plane& plane, double x, double y) const;
  // sample(plane, x, y) for an integer y (the 1D path, where rows map to rows): the same value,
  // bit for bit, without the vertical pass. Rows outside the plane read the nearest edge row.
  float sampleRow(const Plane& plane, double x, long long y) const;

  int precision() const { return precision_; }
  int taps() const { return taps_; }
  // Kernel weights of one phase (0 .. precision-1): taps() values for offsets first()..first()+taps-1.
  const float* kernel(int phase) const { return &kernels_[size_t(phase) * size_t(taps_)]; }
  int first() const { return first_; }

private:
  // Rounds x to the 1/precision grid: integer part `whole` (floor, also for negative x) and phase
  // 0 .. precision-1. The grid index is an integer-valued double; below 2^52 it converts exactly and
  // the power-of-two precision splits it with a shift and a mask, as floor(g / precision) would.
  void gridPosition(double x, long long& whole, int& phase) const {
    const double g = std::floor(x * precision_ + 0.5);
    if (std::fabs(g) < 4503599627370496.0) {  // 2^52
      const long long index = (long long)g;
      whole = index >> precisionShift_;  // arithmetic shift: floor division
      phase = int(index & (precision_ - 1));
      return;
    }
    whole = (long long)std::floor(g / precision_);  // far outside any plane
    phase = int(g - double(whole) * precision_);
  }

  int precision_;
  int precisionShift_;  // log2(precision)
  int taps_;
  int first_;  // offset of the first tap relative to the integer part
  std::vector<float> kernels_;
};

}  // namespace vs
