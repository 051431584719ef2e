#pragma once
// Plain references for the rasterisers' tests (RasterTest, RowWarpTest): the z-buffer's order and
// the pixel-centre range of a span, written out simply and apart from the code they check.
#include <algorithm>
#include <cstdint>
#include <cstring>

namespace vs::plain {

inline int64_t bitsOf(double value) {
  int64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Keeps the larger of the cell and the value in AtomicMaxBuffer's order: the doubles' bits as
// signed integers.
inline void raise(double& cell, double value) {
  if (bitsOf(value) > bitsOf(cell)) cell = value;
}

// Pixel-centre range [first, last] covered by [lo, hi] within [0, size - 1] (1e-9 of slack each
// side); false when empty.
inline bool coveredRange(double lo, double hi, int size, int& first, int& last) {
  if (hi < -1e-9 || lo > size - 1 + 1e-9) return false;
  lo = std::max(lo - 1e-9, 0.0);
  hi = std::min(hi + 1e-9, double(size - 1));
  first = int(lo);
  if (double(first) < lo) ++first;
  last = int(hi);
  return first <= last;
}

}  // namespace vs::plain
