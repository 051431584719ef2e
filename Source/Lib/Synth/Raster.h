#pragma once
// Rasterising the general depth warp's triangles into a z-buffer (doc/algorithms.md, "Warping"): pixel
// centres inside a triangle of warped reference samples get the inverse depth interpolated from its
// corners, kept where it is the largest.
#include <algorithm>
#include <cmath>

namespace vs {

// Pixel-centre range [first, last] covered by [lo, hi] within [0, size - 1]; false when empty.
inline bool coveredRange(double lo, double hi, int size, int& first, int& last) {
  if (hi < -1e-9 || lo > size - 1 + 1e-9) return false;
  lo = std::max(lo - 1e-9, 0.0);
  hi = std::min(hi + 1e-9, double(size - 1));
  first = int(lo);
  if (double(first) < lo) ++first;  // ceil of a non-negative value
  last = int(hi);                    // floor of a non-negative value
  return first <= last;
}

// Raises the z-buffer (width x height) at the pixel centres inside the triangle with corners (x[i],
// y[i]) and inverse depths w[i] >= 0, with the barycentric interpolation of w; a degenerate triangle
// (area below 1e-12) raises nothing.
// raise(i, value) keeps the larger of cell i and value (AtomicMaxBuffer::raise, or raiseAlone where one
// thread writes the buffer).
template <class Raise>
inline void rasteriseTriangle(const Raise& raise, int width, int height, const double* x, const double* y,
                              const double* w) {
  const double minX = std::min(x[0], std::min(x[1], x[2])), maxX = std::max(x[0], std::max(x[1], x[2]));
  const double minY = std::min(y[0], std::min(y[1], y[2])), maxY = std::max(y[0], std::max(y[1], y[2]));
  int x0, x1, y0, y1;
  if (!coveredRange(minX, maxX, width, x0, x1) || !coveredRange(minY, maxY, height, y0, y1)) return;
  const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (std::fabs(area) < 1e-12) return;
  // Barycentric coordinates of pixel centres are affine in (px, py): b = A px + B py + C.
  const double inv = 1.0 / area;
  const double a1 = (y[2] - y[0]) * inv, c1 = -(x[2] - x[0]) * inv;
  const double a2 = -(y[1] - y[0]) * inv, c2 = (x[1] - x[0]) * inv;
  const double k1 = -(a1 * x[0] + c1 * y[0]), k2 = -(a2 * x[0] + c2 * y[0]);
  const double dw1 = w[1] - w[0], dw2 = w[2] - w[0];
  for (int py = y0; py <= y1; ++py) {
    const double r1 = c1 * py + k1, r2 = c2 * py + k2;
    for (int px = x0; px <= x1; ++px) {
      const double b1 = a1 * px + r1, b2 = a2 * px + r2, b0 = 1.0 - b1 - b2;
      if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) continue;
      raise(size_t(py) * width + px, w[0] + b1 * dw1 + b2 * dw2);
    }
  }
}

}  // namespace vs
