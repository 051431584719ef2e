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
#include <vector>

#include "Common/Frame.h"

namespace vs {

class SubPixelSampler {
public:
  SubPixelSampler(int precision, int filter);

  // Value at (x, y), in the plane's own sample coordinates (integers are sample centres), not rounded
  // or clamped to the sample range: bicubic and 6-tap kernels may overshoot; callers clamp.
  float sample(const Plane& plane, double x, double y) const;

  int precision() const { return precision_; }
  int taps() const { return taps_; }
  // Kernel weights of one phase (0 .. precision-1): taps() values for offsets first()..first()+taps-1.
  const float* kernel(int phase) const { return &kernels_[size_t(phase) * size_t(taps_)]; }
  int first() const { return first_; }

private:
  int precision_;
  int taps_;
  int first_;  // offset of the first tap relative to the integer part
  std::vector<float> kernels_;
};

}  // namespace vs
