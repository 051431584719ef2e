#pragma once
// Rasterising the general depth warp's triangles into a z-buffer (doc/algorithms.md, "Warping"): pixel
// centres inside a triangle of warped reference samples get the inverse depth interpolated from its
// corners, kept where it is the largest.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

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

// A triangle set up for its pixel centres: barycentric coordinates are affine in (px, py),
// b1 = a1 px + c1 py + k1 and b2 = a2 px + c2 py + k2, and the inverse depth is w0 + b1 dw1 + b2 dw2.
struct TriangleSetup {
  double a1, c1, k1, a2, c2, k2, w0, dw1, dw2;
};

// Raises the pixel centres of [x0, x1] x [y0, y1] that lie inside the set-up triangle (every
// barycentric coordinate at least -1e-9).
template <class Raise>
inline void raiseCovered(const Raise& raise, int width, const TriangleSetup& t, int x0, int x1, int y0, int y1) {
  for (int py = y0; py <= y1; ++py) {
    const double r1 = t.c1 * py + t.k1, r2 = t.c2 * py + t.k2;
    for (int px = x0; px <= x1; ++px) {
      const double b1 = t.a1 * px + r1, b2 = t.a2 * px + r2, b0 = 1.0 - b1 - b2;
      if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) continue;
      raise(size_t(py) * width + px, t.w0 + b1 * t.dw1 + b2 * t.dw2);
    }
  }
}

// Raises the z-buffer (width x height) at the pixel centres inside the triangle with corners (x[i],
// y[i]) and inverse depths w[i] >= 0, with the barycentric interpolation of w; a degenerate triangle
// (area below 1e-12) raises nothing.
// raise(i, value) keeps the larger of cell i and value in the z-buffer's order (AtomicMaxBuffer::raise,
// or its loneWriter() where one thread writes the buffer).
template <class Raise>
inline void rasteriseTriangle(const Raise& raise, int width, int height, const double* x, const double* y,
                              const double* w) {
  const double minX = std::min(x[0], std::min(x[1], x[2])), maxX = std::max(x[0], std::max(x[1], x[2]));
  const double minY = std::min(y[0], std::min(y[1], y[2])), maxY = std::max(y[0], std::max(y[1], y[2]));
  int x0, x1, y0, y1;
  if (!coveredRange(minX, maxX, width, x0, x1) || !coveredRange(minY, maxY, height, y0, y1)) return;
  const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (std::fabs(area) < 1e-12) return;
  const double inv = 1.0 / area;
  TriangleSetup t;
  t.a1 = (y[2] - y[0]) * inv;
  t.c1 = -(x[2] - x[0]) * inv;
  t.a2 = -(y[1] - y[0]) * inv;
  t.c2 = (x[1] - x[0]) * inv;
  t.k1 = -(t.a1 * x[0] + t.c1 * y[0]);
  t.k2 = -(t.a2 * x[0] + t.c2 * y[0]);
  t.w0 = w[0];
  t.dw1 = w[1] - w[0];
  t.dw2 = w[2] - w[0];
  raiseCovered(raise, width, t, x0, x1, y0, y1);
}

#if defined(__SSE4_1__)
// Two doubles, and a mask of two lanes; each lane is computed exactly as the scalar double is.
typedef double DoublePair __attribute__((vector_size(16)));
typedef int64_t MaskPair __attribute__((vector_size(16)));

// rasteriseTriangle() for two triangles at once, triangle k in lane k of the corners x[i], y[i], w[i],
// drawn where draw[k]: the same pixels raised with the same values (the z-buffer keeps the largest
// whatever the order). The general depth warp's triangles are about a pixel wide: the two
// triangles of a quad are set up side by side, and when all the pixel centres their boxes reach lie
// in one 2 x 2 square, as they nearly always do, that square is tested without branches.
template <class Raise>
[[gnu::always_inline]] inline void rasteriseTrianglePair(const Raise& raise, int width, int height, const DoublePair* x,
                                  const DoublePair* y, const DoublePair* w, const bool* draw) {
  // std::min(a, b) is b < a ? b : a, and std::max(a, b) is a < b ? b : a, lane by lane.
  auto least = [](DoublePair a, DoublePair b) { return b < a ? b : a; };
  auto most = [](DoublePair a, DoublePair b) { return a < b ? b : a; };
  // coveredRange() lane by lane: [first, last] as doubles, and where it is not empty.
  auto covered = [](DoublePair lo, DoublePair hi, int size, DoublePair& first, DoublePair& last) {
    const double top = double(size - 1);
    const DoublePair zero = {0.0, 0.0}, topPair = {top, top};
    const MaskPair some = ~((hi < -1e-9) | (lo > size - 1 + 1e-9));
    DoublePair l = lo - 1e-9, h = hi + 1e-9;
    l = l < zero ? zero : l;
    h = topPair < h ? topPair : h;
    first = DoublePair(_mm_ceil_pd(__m128d(l)));  // ceil and floor of non-negative values, as
    last = DoublePair(_mm_floor_pd(__m128d(h)));  // coveredRange's conversions to int give
    return some & MaskPair(first <= last);
  };
  DoublePair firstX, lastX, firstY, lastY;
  const MaskPair inX = covered(least(x[0], least(x[1], x[2])), most(x[0], most(x[1], x[2])), width, firstX, lastX);
  const MaskPair inY = covered(least(y[0], least(y[1], y[2])), most(y[0], most(y[1], y[2])), height, firstY, lastY);
  const DoublePair area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  const MaskPair magnitude = MaskPair(area) & INT64_MAX;  // fabs
  const MaskPair drawn = {-int64_t(draw[0]), -int64_t(draw[1])};
  const MaskPair valid = drawn & inX & inY & ~(DoublePair(magnitude) < 1e-12);
  if (!(valid[0] | valid[1])) return;
  const DoublePair inv = 1.0 / area;
  const DoublePair a1 = (y[2] - y[0]) * inv, c1 = -(x[2] - x[0]) * inv;
  const DoublePair a2 = -(y[1] - y[0]) * inv, c2 = (x[1] - x[0]) * inv;
  const DoublePair k1 = -(a1 * x[0] + c1 * y[0]), k2 = -(a2 * x[0] + c2 * y[0]);
  const DoublePair dw1 = w[1] - w[0], dw2 = w[2] - w[0];
  // The square holding every lane's pixel centres (a lane not drawn reaches none).
  const DoublePair none = {1e300, 1e300};
  const DoublePair fromX = valid ? firstX : none, toX = valid ? lastX : -none;
  const DoublePair fromY = valid ? firstY : none, toY = valid ? lastY : -none;
  const double left = std::min(fromX[0], fromX[1]), right = std::max(toX[0], toX[1]);
  const double top = std::min(fromY[0], fromY[1]), bottom = std::max(toY[0], toY[1]);
  if (right - left > 1 || bottom - top > 1) {
    for (int k = 0; k < 2; ++k) {
      if (!valid[k]) continue;
      const TriangleSetup t = {a1[k], c1[k], k1[k], a2[k], c2[k], k2[k], w[0][k], dw1[k], dw2[k]};
      raiseCovered(raise, width, t, int(firstX[k]), int(lastX[k]), int(firstY[k]), int(lastY[k]));
    }
    return;
  }
  // Every sample of the square is raised, without a branch: where no lane covers it, with -0, whose
  // bits are the least in the z-buffer's order (the doubles' bits as signed integers), which changes
  // nothing. The square's second column or row may lie outside the picture, where no lane reaches:
  // those raise the first one's instead.
  const size_t column = size_t(left), nextColumnCell = size_t(std::min(int(left) + 1, width - 1));
  const size_t row = size_t(top) * width, nextRowCell = size_t(std::min(int(top) + 1, height - 1)) * width;
  const size_t cells[2][2] = {{row + column, row + nextColumnCell}, {nextRowCell + column, nextRowCell + nextColumnCell}};
  auto raiseAt = [&](size_t cell, double px, MaskPair rowIn, DoublePair r1, DoublePair r2) {
    const DoublePair b1 = a1 * px + r1, b2 = a2 * px + r2, b0 = 1.0 - b1 - b2;
    const MaskPair inside = rowIn & (px >= firstX) & (px <= lastX) & ~((b0 < -1e-9) | (b1 < -1e-9) | (b2 < -1e-9));
    // Raising with both lanes' values is raising with the larger in that order.
    const MaskPair bits = inside ? MaskPair(w[0] + b1 * dw1 + b2 * dw2) : MaskPair{INT64_MIN, INT64_MIN};
    const int64_t larger = std::max(bits[0], bits[1]);
    double value;
    std::memcpy(&value, &larger, sizeof value);
    raise(cell, value);
  };
  const double nextColumn = left + 1;
  {
    const MaskPair rowIn = valid & (top >= firstY) & (top <= lastY);
    const DoublePair r1 = c1 * top + k1, r2 = c2 * top + k2;
    raiseAt(cells[0][0], left, rowIn, r1, r2);
    raiseAt(cells[0][1], nextColumn, rowIn, r1, r2);
  }
  {
    const double nextRow = top + 1;
    const MaskPair rowIn = valid & (nextRow >= firstY) & (nextRow <= lastY);
    const DoublePair r1 = c1 * nextRow + k1, r2 = c2 * nextRow + k2;
    raiseAt(cells[1][0], left, rowIn, r1, r2);
    raiseAt(cells[1][1], nextColumn, rowIn, r1, r2);
  }
}
#endif

}  // namespace vs
