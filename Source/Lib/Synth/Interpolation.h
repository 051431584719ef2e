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
// itself. Positions outside the plane read the nearest edge sample (never outside the buffer), or for
// an equirectangular reference the samples round its wrap and across its poles (SphereEdges).
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "Common/Frame.h"
#include "Synth/Kernels/Rows.h"

namespace vs {

// How a plane continues beyond its edges for an equirectangular reference (Synth/Warp.h). A look-up
// normally reads the nearest edge sample there. A full circle of longitudes continues round the wrap
// (column -1 is column width - 1: `wrap`), and where the picture reaches a pole (latitude +-90 with a
// full circle: `north`, `south`) the row beyond it is the one as far on the other side of the pole,
// half a turn round: row -1 - r at column x + width / 2 at the top, row 2 height - 1 - r likewise at the
// bottom (in the plane's own sample coordinates, so for a chroma plane too).
struct SphereEdges {
  bool wrap = false, north = false, south = false;
  bool any() const { return wrap || north || south; }
};

class SubPixelSampler {
public:
  SubPixelSampler(int precision, int filter);

  // Value at (x, y), in the plane's own sample coordinates (integers are sample centres), not rounded
  // or clamped to the sample range: bicubic and 6-tap kernels may overshoot; callers clamp.
  float sample(const Plane& plane, double x, double y) const {
    return taps_ == 4 ? sampleTaps<4>(plane, x, y) : taps_ == 6 ? sampleTaps<6>(plane, x, y) : sampleTaps<2>(plane, x, y);
  }
  // sample(plane, x, y) for an integer y (the 1D path, where rows map to rows): the same value,
  // bit for bit, without the vertical pass. Rows outside the plane read the nearest edge row.
  float sampleRow(const Plane& plane, double x, long long y) const {
    return taps_ == 4 ? sampleRowTaps<4>(plane, x, y) : taps_ == 6 ? sampleRowTaps<6>(plane, x, y) : sampleRowTaps<2>(plane, x, y);
  }

  // sampleTaps<TAPS> for a plane that continues beyond its edges as `edges` says: the same value, bit
  // for bit, where the kernel reads inside the plane (the same arithmetic in the same order).
  template <int TAPS>
  float sampleSphereTaps(const Plane& plane, double x, double y, const SphereEdges& edges) const;
  // Whether a kernel at (x, y) may read beyond a width x height plane (conservatively: within four
  // samples of an edge), where sampleSphereTaps and sampleTaps may differ.
  static bool nearEdge(double x, double y, int width, int height) {
    return !(x >= 4.0 && y >= 4.0 && x <= width - 5.0 && y <= height - 5.0);
  }

  int precision() const { return precision_; }
  // Whether y rounds to a whole row of the grid (phase 0), and which: sample(plane, x, y) is then
  // sampleRow(plane, x, row), bit for bit (the row of weight 1 alone contributes).
  bool wholeRow(double y, long long& row) const {
    long long whole;
    int phase;
    gridPosition(y, whole, phase);
    row = whole;
    return phase == 0;
  }
  int taps() const { return taps_; }
  // Kernel weights of one phase (0 .. precision-1): taps() values for offsets first()..first()+taps-1.
  const float* kernel(int phase) const { return &kernels_[size_t(phase) * size_t(taps_)]; }
  int first() const { return first_; }

  // Calls f(std::integral_constant<int, taps()>()): a loop over many samples that calls
  // sampleTaps<TAPS> and sampleRowTaps<TAPS> inside f picks the kernel once, not once per sample.
  template <class F>
  decltype(auto) withTaps(F&& f) const {
    if (taps_ == 4) return f(std::integral_constant<int, 4>());
    if (taps_ == 6) return f(std::integral_constant<int, 6>());
    return f(std::integral_constant<int, 2>());
  }
  // sample() and sampleRow() with the tap count known at compile time (TAPS must be taps()): the
  // loops unroll, the arithmetic (order included) is the same for every count, and the calls inline
  // into the warps.
  template <int TAPS>
  float sampleTaps(const Plane& plane, double x, double y) const;
  template <int TAPS>
  float sampleRowTaps(const Plane& plane, double x, long long y) const;
  // sampleRowTaps at the grid position with integer part ix and phase px of a row `width` samples
  // wide (what sampleRowTaps computes once it has rounded x).
  template <int TAPS>
  float sampleGridTaps(const uint16_t* row, int width, long long ix, int px) const;

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
  // Precision 4 x 6 taps at most; a plain array keeps the sampler cheap to copy (the warps copy it
  // into each thread's locals).
  std::array<float, 24> kernels_{};
};

template <int TAPS>
inline float SubPixelSampler::sampleRowTaps(const Plane& plane, double x, long long y) const {
  // sample() with phase 0 vertically: only the row of weight exactly 1 contributes, and
  // 0 + 1 * rowSum is rowSum. The horizontal pass is sample()'s own: all taps inside the plane (zero
  // weights add +0), clamped taps of non-zero weight at its border.
  long long ix;
  int px;
  gridPosition(x, ix, px);
  return sampleGridTaps<TAPS>(plane.row(int(std::clamp(y, 0LL, (long long)plane.height - 1))), plane.width, ix, px);
}

template <int TAPS>
inline float SubPixelSampler::sampleGridTaps(const uint16_t* row, int width, long long ix, int px) const {
  const long long maxX = width - 1;
  const float* kx = kernel(px);
  const long long left = ix + first_;
  float rowSum = 0.0f;
  if (left >= 0 && left + TAPS - 1 <= maxX) {
    // Phase 0 too: its kernel is (0, .., 1, .., 0), and 0 + 0 * a + 1 * b + 0 * c .. is b exactly
    // (samples are finite and 0 * a is +0 or -0, which leave a sum unchanged), so no branch on the
    // phase, which a slanted surface makes unpredictable.
    const uint16_t* taps = row + left;
    for (int tx = 0; tx < TAPS; ++tx) rowSum += kx[tx] * float(taps[tx]);
    return rowSum;
  }
  if (px == 0) return float(row[std::clamp(ix, 0LL, maxX)]);
  for (int tx = 0; tx < TAPS; ++tx) {
    if (kx[tx] == 0.0f) continue;
    rowSum += kx[tx] * float(row[std::clamp(ix + first_ + tx, 0LL, maxX)]);
  }
  return rowSum;
}

template <int TAPS>
inline float SubPixelSampler::sampleTaps(const Plane& plane, double x, double y) const {
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
  if (left >= 0 && top >= 0 && left + TAPS - 1 <= maxX && top + TAPS - 1 <= maxY) {
    // Inside the plane: no clamping; rows whose weight is 0 (phase 0) are skipped.
    float sum = 0.0f;
    for (int ty = 0; ty < TAPS; ++ty) {
      if (ky[ty] == 0.0f) continue;
      const uint16_t* row = plane.row(int(top + ty)) + left;
      float rowSum = 0.0f;
      for (int tx = 0; tx < TAPS; ++tx) rowSum += kx[tx] * float(row[tx]);
      sum += ky[ty] * rowSum;
    }
    return sum;
  }
  float sum = 0.0f;
  for (int ty = 0; ty < TAPS; ++ty) {
    if (ky[ty] == 0.0f) continue;
    const long long sy = std::clamp(iy + first_ + ty, 0LL, maxY);
    const uint16_t* row = plane.row(int(sy));
    float rowSum = 0.0f;
    for (int tx = 0; tx < TAPS; ++tx) {
      if (kx[tx] == 0.0f) continue;
      const long long sx = std::clamp(ix + first_ + tx, 0LL, maxX);
      rowSum += kx[tx] * float(row[sx]);
    }
    sum += ky[ty] * rowSum;
  }
  return sum;
}

template <int TAPS>
inline float SubPixelSampler::sampleSphereTaps(const Plane& plane, double x, double y, const SphereEdges& edges) const {
  long long ix, iy, turnedX;
  int px, py, turnedPhase;
  gridPosition(x, ix, px);
  gridPosition(y, iy, py);
  gridPosition(x + 0.5 * plane.width, turnedX, turnedPhase);  // half a turn round, for rows across a pole
  const float* ky = kernel(py);
  const long long width = plane.width, maxY = plane.height - 1;
  float sum = 0.0f;
  for (int ty = 0; ty < TAPS; ++ty) {
    if (ky[ty] == 0.0f) continue;
    long long sy = iy + first_ + ty;
    bool turned = false;
    if (sy < 0 && edges.north) {
      sy = -1 - sy;
      turned = true;
    } else if (sy > maxY && edges.south) {
      sy = 2 * maxY + 1 - sy;
      turned = true;
    }
    const uint16_t* row = plane.row(int(std::clamp(sy, 0LL, maxY)));
    const long long cx = turned ? turnedX : ix;
    const float* kx = kernel(turned ? turnedPhase : px);
    float rowSum = 0.0f;
    for (int tx = 0; tx < TAPS; ++tx) {
      if (kx[tx] == 0.0f) continue;
      const long long column = cx + first_ + tx;
      const long long sx = edges.wrap ? (column % width + width) % width : std::clamp(column, 0LL, width - 1);
      rowSum += kx[tx] * float(row[sx]);
    }
    sum += ky[ty] * rowSum;
  }
  return sum;
}

// One row of a plane sampled at every grid position of a range of integer parts, once, so that many
// look-ups along the row cost a load each instead of a kernel sum each (the 1D warps, where every
// warped sample of a row reads the same reference row). at(x) is sampleRowTaps(plane, x, y), bit for
// bit, for any x; positions whose integer part lies outside [first, last] are computed directly.
// The table holds precision() planes of (last - first + 1) values, phase by phase, so that the
// interior of each phase is one loop over consecutive samples that the compiler vectorises (each lane
// does the scalar float arithmetic in the same order), compiled for the CPU's x86-64 level
// (Synth/Kernels/Rows.h).
class SampledRow {
public:
  template <int TAPS>
  void build(const SubPixelSampler& sampler, const Plane& plane, long long y, long long first, long long last) {
    static_assert(TAPS == 2 || TAPS == 4 || TAPS == 6, "the kernels' tap counts");
    sampler_ = &sampler;
    row_ = plane.row(int(std::clamp(y, 0LL, (long long)plane.height - 1)));
    width_ = plane.width;
    first_ = first;
    last_ = std::max(first, last);
    stride_ = size_t(last_ - first_ + 1);
    shift_ = sampler.precision() == 1 ? 0 : sampler.precision() == 2 ? 1 : 2;
    mask_ = sampler.precision() - 1;
    values_.resize(stride_ * size_t(sampler.precision()));
    // Integer parts whose taps all lie inside the row: [-offset, width - 1 - offset - (TAPS - 1)].
    const long long offset = sampler.first();
    const long long innerFirst = std::max(first_, -offset);
    const long long innerLast = std::min(last_, (long long)width_ - 1 - offset - (TAPS - 1));
    for (int phase = 0; phase < sampler.precision(); ++phase) {
      float* out = values_.data() + size_t(phase) * stride_;  // out[ix - first] for ix in [first, last]
      const float* kernel = sampler.kernel(phase);
      float k[TAPS];
      for (int t = 0; t < TAPS; ++t) k[t] = kernel[t];
      long long ix = first_;
      for (; ix < std::min(innerFirst, last_ + 1); ++ix)
        out[ix - first_] = sampler.sampleGridTaps<TAPS>(row_, width_, ix, phase);
      if (ix <= innerLast) {
        // Locals: the float stores could otherwise alias the row and the counts.
        const uint16_t* taps = row_ + (ix + offset);
        float* to = out + (ix - first_);
        const long long count = innerLast - ix + 1;
        if (phase == 0) {
          // Every kernel is (0, .., 1, .., 0) at phase 0, and 0 + 0 * a + 1 * b + 0 * c .. is b exactly
          // (the samples are finite and non-negative): the sample itself.
          rowKernels().sampleRowPhase0(taps - offset, count, to);  // a loop compiled for the CPU's level
        } else {
          // The sum over the taps, k[t] * taps[n + t] in that order from 0, in a loop compiled for
          // the CPU's x86-64 level (Synth/Kernels/Rows.h). Phase 0's plane, built first, holds
          // float(row[i]) for every i in [first, last] (the sample itself, of the clamped position at
          // the ends), exactly what the sum converts each tap to: where it covers the taps, they are
          // read from it as floats, not converted again for every phase.
          const RowKernels& kernels = rowKernels();
          const long long from = ix + offset - first_;  // phase 0's index of the first tap
          if (from >= 0 && from + count + TAPS - 1 <= (long long)stride_) {
            (TAPS == 2 ? kernels.sampleFloatRowPhase2
                       : TAPS == 4 ? kernels.sampleFloatRowPhase4 : kernels.sampleFloatRowPhase6)(
                values_.data() + from, k, count, to);
          } else {
            (TAPS == 2 ? kernels.sampleRowPhase2 : TAPS == 4 ? kernels.sampleRowPhase4 : kernels.sampleRowPhase6)(
                taps, k, count, to);
          }
        }
        ix = innerLast + 1;
      }
      for (; ix <= last_; ++ix) out[ix - first_] = sampler.sampleGridTaps<TAPS>(row_, width_, ix, phase);
    }
  }

  template <int TAPS>
  float at(double x) const {
    return atGrid<TAPS>(x, gridIndex(x));
  }
  // The grid index of x as SubPixelSampler::gridPosition finds it (an integer-valued double).
  double gridIndex(double x) const { return std::floor(x * double(mask_ + 1) + 0.5); }
  // at(x) given g = gridIndex(x), which a loop over many positions can compute in vector lanes first.
  template <int TAPS>
  float atGrid(double x, double g) const {
    if (std::fabs(g) < 4503599627370496.0) {  // 2^52
      const long long index = (long long)g, ix = index >> shift_;
      const int phase = int(index & mask_);
      if (ix >= first_ && ix <= last_) return values_[size_t(phase) * stride_ + size_t(ix - first_)];
      return sampler_->sampleGridTaps<TAPS>(row_, width_, ix, phase);
    }
    return sampleFar<TAPS>(x);  // far outside any plane
  }

  // The table as numbers (a built one): atGrid(x, g) with |g| < 2^52, index = (long long)g and ix = index
  // >> shift() in [first(), last()] is values()[(index & mask()) * stride() + ix - first()].
  const float* values() const { return values_.data(); }
  long long first() const { return first_; }
  long long last() const { return last_; }
  long long stride() const { return (long long)stride_; }
  int shift() const { return shift_; }
  long long mask() const { return mask_; }

private:
  template <int TAPS>
  float sampleFar(double x) const {
    const double g = std::floor(x * double(mask_ + 1) + 0.5);
    const long long whole = (long long)std::floor(g / double(mask_ + 1));
    return sampler_->sampleGridTaps<TAPS>(row_, width_, whole, int(g - double(whole) * double(mask_ + 1)));
  }

  const SubPixelSampler* sampler_ = nullptr;
  const uint16_t* row_ = nullptr;
  int width_ = 0;
  long long first_ = 0, last_ = 0;
  size_t stride_ = 1;
  int shift_ = 0, mask_ = 0;
  std::vector<float> values_;
};

}  // namespace vs
