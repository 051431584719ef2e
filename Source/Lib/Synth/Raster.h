#pragma once
// Rasterising the general depth warp's triangles into a z-buffer (doc/algorithms.md, "Warping"): pixel
// centres inside a triangle of warped reference samples get the inverse depth interpolated from its
// corners, kept where it is the largest.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <atomic>

#if defined(__AVX__)
#include <immintrin.h>
#elif defined(__SSE4_1__)
#include <smmintrin.h>
#endif

// Synth/Kernels/QuadRow.cpp compiles this header once per x86-64 level, each with its -march and
// VS_LEVEL_NS (v1 .. v4): everything here then lies in vs::<level>, so that the inline functions
// and templates of one level are never merged by the linker with another's (which could run AVX-512
// code on a CPU without it). Everywhere else it is plain vs.
#if defined(VS_LEVEL_NS)
#define VS_RASTER_LEVEL_BEGIN inline namespace VS_LEVEL_NS {
#define VS_RASTER_LEVEL_END }
#else
#define VS_RASTER_LEVEL_BEGIN
#define VS_RASTER_LEVEL_END
#endif

namespace vs {
VS_RASTER_LEVEL_BEGIN

// The z-buffer's order: non-negative inverse depths order like their bits read as signed 64-bit
// integers, and kNoDepth (-1) reads as a negative one. Keeps the larger of the cell and the value in
// that order (AtomicMaxBuffer::raise, for one writer): the cell is stored whether or not it changes,
// a select and a store with no branch to mispredict.
inline void raiseCell(double& cell, double value) {
  int64_t a, b;
  std::memcpy(&a, &value, sizeof a);
  std::memcpy(&b, &cell, sizeof b);
  const int64_t larger = a > b ? a : b;
  std::memcpy(&cell, &larger, sizeof larger);
}

// raise(i, value) over a z-buffer of doubles that one thread writes: raiseCell on cell i. A small
// object that holds the cells' address (a vector's own would be read again after every store).
struct LoneRaise {
  double* cells;
  void operator()(size_t i, double value) const { raiseCell(cells[i], value); }
};

// raiseCell for a z-buffer that many threads raise at once (AtomicMaxBuffer, Parallel.h): the cell
// holds the doubles' bits; an integer atomic max is the max in that order, whatever the order of writes.
inline void raiseAtomicCell(std::atomic<int64_t>& cell, double value) {
  int64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  int64_t current = cell.load(std::memory_order_relaxed);
  while (bits > current && !cell.compare_exchange_weak(current, bits, std::memory_order_relaxed)) {
  }
}
struct AtomicRaise {
  std::atomic<int64_t>* cells;
  void operator()(size_t i, double value) const { raiseAtomicCell(cells[i], value); }
};

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
// or LoneRaise where one thread writes the buffer).
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
// The triangles of kQuads quads of warped samples side by side in vector lanes: kQuads 1 with SSE4.1
// (two doubles a register), 2 with AVX (four), 4 with AVX-512 (eight). Each lane is computed exactly
// as the scalar double is.
template <int kQuads>
struct QuadLanes;
template <>
struct QuadLanes<1> {
  static constexpr int kLanes = 2;
  typedef double Doubles __attribute__((vector_size(16)));
  typedef int64_t Mask __attribute__((vector_size(16)));
  // std::ceil and std::floor lane by lane.
  static Doubles ceil(Doubles v) { return Doubles(_mm_ceil_pd(__m128d(v))); }
  static Doubles floor(Doubles v) { return Doubles(_mm_floor_pd(__m128d(v))); }
  static Doubles splat(double v) { return Doubles{v, v}; }
  static Mask lanes(const bool* yes) { return Mask{-int64_t(yes[0]), -int64_t(yes[1])}; }
  static bool any(Mask m) { return !_mm_testz_si128(__m128i(m), __m128i(m)); }
  // Each quad's two lanes exchanged.
  static Doubles swapped(Doubles v) { return Doubles{v[1], v[0]}; }
  // One coordinate of the corners of quad q[0] (samples q[0] and q[0] + 1 of rows `top` and `bottom`)
  // in the lanes rasteriseQuads takes: triangles (0, 1, 3) and (0, 3, 2).
  [[gnu::always_inline]] static void corners(const double* top, const double* bottom, const int* q, Doubles* out) {
    const int a = q[0];
    out[0] = Doubles{top[a], top[a]};
    out[1] = Doubles{top[a + 1], bottom[a + 1]};
    out[2] = Doubles{bottom[a + 1], bottom[a]};
  }
  // corners() for the quads x, x + 1, ... that follow each other along the rows (samples x to x +
  // kQuads of both rows are read).
  [[gnu::always_inline]] static void cornersInRow(const double* top, const double* bottom, int x, Doubles* out) {
    const int q[1] = {x};
    corners(top, bottom, q, out);
  }
};
#if defined(__AVX__)
template <>
struct QuadLanes<2> {
  static constexpr int kLanes = 4;
  typedef double Doubles __attribute__((vector_size(32)));
  typedef int64_t Mask __attribute__((vector_size(32)));
  static Doubles ceil(Doubles v) { return Doubles(_mm256_ceil_pd(__m256d(v))); }
  static Doubles floor(Doubles v) { return Doubles(_mm256_floor_pd(__m256d(v))); }
  static Doubles splat(double v) { return Doubles{v, v, v, v}; }
  static Mask lanes(const bool* yes) {
    return Mask{-int64_t(yes[0]), -int64_t(yes[1]), -int64_t(yes[2]), -int64_t(yes[3])};
  }
  static bool any(Mask m) { return !_mm256_testz_si256(__m256i(m), __m256i(m)); }
  static Doubles swapped(Doubles v) { return Doubles{v[1], v[0], v[3], v[2]}; }
  [[gnu::always_inline]] static void corners(const double* top, const double* bottom, const int* q, Doubles* out) {
    const int a = q[0], b = q[1];
    out[0] = Doubles{top[a], top[a], top[b], top[b]};
    out[1] = Doubles{top[a + 1], bottom[a + 1], top[b + 1], bottom[b + 1]};
    out[2] = Doubles{bottom[a + 1], bottom[a], bottom[b + 1], bottom[b]};
  }
  // Two samples of each row at a time, and their lanes moved into place.
  [[gnu::always_inline]] static void cornersInRow(const double* top, const double* bottom, int x, Doubles* out) {
    typedef double Two __attribute__((vector_size(16)));
    Two t0, t1, b0, b1;  // samples x and x + 1, then x + 1 and x + 2
    std::memcpy(&t0, top + x, sizeof t0);
    std::memcpy(&t1, top + x + 1, sizeof t1);
    std::memcpy(&b0, bottom + x, sizeof b0);
    std::memcpy(&b1, bottom + x + 1, sizeof b1);
    out[0] = __builtin_shufflevector(t0, t0, 0, 0, 1, 1);
    out[1] = __builtin_shufflevector(t1, b1, 0, 2, 1, 3);
    out[2] = __builtin_shufflevector(b1, b0, 0, 2, 1, 3);
  }
};
#endif
#if defined(__AVX512F__)
template <>
struct QuadLanes<4> {
  static constexpr int kLanes = 8;
  typedef double Doubles __attribute__((vector_size(64)));
  typedef int64_t Mask __attribute__((vector_size(64)));
  // (The zero-masking forms: GCC 12's plain ones start from an undefined register, which
  // -Wmaybe-uninitialized reports.)
  static Doubles ceil(Doubles v) {
    return Doubles(_mm512_maskz_roundscale_pd(0xff, __m512d(v), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
  }
  static Doubles floor(Doubles v) {
    return Doubles(_mm512_maskz_roundscale_pd(0xff, __m512d(v), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
  }
  static Doubles splat(double v) { return Doubles{v, v, v, v, v, v, v, v}; }
  static Mask lanes(const bool* yes) {
    return Mask{-int64_t(yes[0]), -int64_t(yes[1]), -int64_t(yes[2]), -int64_t(yes[3]),
                -int64_t(yes[4]), -int64_t(yes[5]), -int64_t(yes[6]), -int64_t(yes[7])};
  }
  static bool any(Mask m) { return _mm512_test_epi64_mask(__m512i(m), __m512i(m)) != 0; }
  static Doubles swapped(Doubles v) { return Doubles{v[1], v[0], v[3], v[2], v[5], v[4], v[7], v[6]}; }
  [[gnu::always_inline]] static void corners(const double* top, const double* bottom, const int* q, Doubles* out) {
    const int a = q[0], b = q[1], c = q[2], d = q[3];
    out[0] = Doubles{top[a], top[a], top[b], top[b], top[c], top[c], top[d], top[d]};
    out[1] = Doubles{top[a + 1], bottom[a + 1], top[b + 1], bottom[b + 1],
                     top[c + 1], bottom[c + 1], top[d + 1], bottom[d + 1]};
    out[2] = Doubles{bottom[a + 1], bottom[a], bottom[b + 1], bottom[b],
                     bottom[c + 1], bottom[c], bottom[d + 1], bottom[d]};
  }
  // Four samples of each row at a time, and their lanes moved into place.
  [[gnu::always_inline]] static void cornersInRow(const double* top, const double* bottom, int x, Doubles* out) {
    typedef double Four __attribute__((vector_size(32)));
    Four t0, t1, b0, b1;  // samples x to x + 3, then x + 1 to x + 4
    std::memcpy(&t0, top + x, sizeof t0);
    std::memcpy(&t1, top + x + 1, sizeof t1);
    std::memcpy(&b0, bottom + x, sizeof b0);
    std::memcpy(&b1, bottom + x + 1, sizeof b1);
    out[0] = __builtin_shufflevector(t0, t0, 0, 0, 1, 1, 2, 2, 3, 3);
    out[1] = __builtin_shufflevector(t1, b1, 0, 4, 1, 5, 2, 6, 3, 7);
    out[2] = __builtin_shufflevector(b1, b0, 0, 4, 1, 5, 2, 6, 3, 7);
  }
};
#endif

// std::min(a, b), which is b < a ? b : a, and std::max(a, b), which is a < b ? b : a, lane by lane.
template <class Doubles>
inline Doubles leastLanes(Doubles a, Doubles b) {
  return b < a ? b : a;
}
template <class Doubles>
inline Doubles mostLanes(Doubles a, Doubles b) {
  return a < b ? b : a;
}

// Which triangles of quads in the lanes of QuadLanes<kQuads> to draw, from their corners' inverse
// depths w (as corners() puts them: lane 2q holds quad q's corners 0, 1, 3, lane 2q + 1 its corners 0,
// 3, 2): the general depth warp's rule, the same comparisons, minimums and maximums in every lane. A
// triangle is drawn when corners 0 and 3 are warped (not below 0), its own third corner is (at least
// 0), and the three span at most `discontinuity` (the rule's test that both third corners are below 0
// only ever stops triangles that this last test stops too).
template <int kQuads>
inline typename QuadLanes<kQuads>::Mask drawnTriangles(const typename QuadLanes<kQuads>::Doubles* w,
                                                       double discontinuity) {
  using L = QuadLanes<kQuads>;
  using Doubles = typename L::Doubles;
  using Mask = typename L::Mask;
  Mask odd;
  for (int k = 0; k < L::kLanes; ++k) odd[k] = -int64_t(k & 1);
  const Doubles corner0 = w[0], corner3 = odd ? w[1] : w[2], third = odd ? w[2] : w[1];
  const Doubles lo03 = leastLanes(corner0, corner3), hi03 = mostLanes(corner0, corner3);
  const Mask warped = ~(corner0 < 0) & ~(corner3 < 0) & (third >= 0);
  return warped & Mask(mostLanes(hi03, third) - leastLanes(lo03, third) <= discontinuity);
}

// rasteriseTriangle() for the two triangles of each of kQuads quads at once, triangle k in lane k of
// the corners x[i], y[i], w[i] (lanes 2q and 2q + 1 for quad q), drawn where lane k of `drawn` is set
// (QuadLanes::lanes of a flag per triangle, or drawnTriangles): the same pixels
// raised with the same values (the z-buffer keeps the largest whatever the order). The general depth
// warp's quads are about a pixel wide: when all the pixel centres a quad's two boxes reach lie in one
// 2 x 2 square, as they nearly always do, that square is tested without branches; a quad reaching
// further has its triangles drawn one by one.
template <int kQuads, class Raise>
[[gnu::always_inline]] inline void rasteriseQuads(const Raise& raise, int width, int height,
                                                  const typename QuadLanes<kQuads>::Doubles* x,
                                                  const typename QuadLanes<kQuads>::Doubles* y,
                                                  const typename QuadLanes<kQuads>::Doubles* w,
                                                  typename QuadLanes<kQuads>::Mask drawn) {
  using L = QuadLanes<kQuads>;
  using Doubles = typename L::Doubles;
  using Mask = typename L::Mask;
  constexpr int kLanes = L::kLanes;
  // coveredRange() lane by lane: [first, last] as doubles, and where it is not empty.
  auto covered = [](Doubles lo, Doubles hi, int size, Doubles& first, Doubles& last) {
    const Doubles zero = L::splat(0.0), top = L::splat(double(size - 1));
    const Mask some = ~((hi < -1e-9) | (lo > size - 1 + 1e-9));
    Doubles l = lo - 1e-9, h = hi + 1e-9;
    l = l < zero ? zero : l;
    h = top < h ? top : h;
    first = L::ceil(l);  // ceil and floor of non-negative values, as coveredRange's conversions to
    last = L::floor(h);  // int give
    return some & Mask(first <= last);
  };
  Doubles firstX, lastX, firstY, lastY;
  const Mask inX = covered(leastLanes(x[0], leastLanes(x[1], x[2])), mostLanes(x[0], mostLanes(x[1], x[2])), width,
                           firstX, lastX);
  const Mask inY = covered(leastLanes(y[0], leastLanes(y[1], y[2])), mostLanes(y[0], mostLanes(y[1], y[2])), height,
                           firstY, lastY);
  const Doubles area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  const Mask magnitude = Mask(area) & INT64_MAX;  // fabs
  const Mask valid = drawn & inX & inY & ~(Doubles(magnitude) < 1e-12);
  if (!L::any(valid)) return;
  const Doubles inv = 1.0 / area;
  const Doubles a1 = (y[2] - y[0]) * inv, c1 = -(x[2] - x[0]) * inv;
  const Doubles a2 = -(y[1] - y[0]) * inv, c2 = (x[1] - x[0]) * inv;
  const Doubles k1 = -(a1 * x[0] + c1 * y[0]), k2 = -(a2 * x[0] + c2 * y[0]);
  const Doubles dw1 = w[1] - w[0], dw2 = w[2] - w[0];
  // Each quad's square, in both of its lanes: the least first and the largest last pixel centre of
  // its two triangles (a lane not drawn reaches none).
  const Doubles none = L::splat(1e300);
  const Doubles fromX = valid ? firstX : none, toX = valid ? lastX : -none;
  const Doubles fromY = valid ? firstY : none, toY = valid ? lastY : -none;
  const Doubles left = leastLanes(fromX, L::swapped(fromX)), right = mostLanes(toX, L::swapped(toX));
  const Doubles top = leastLanes(fromY, L::swapped(fromY)), bottom = mostLanes(toY, L::swapped(toY));
  const Mask fits = (right - left <= 1.0) & (bottom - top <= 1.0);
  const Mask square = valid & fits;
  if (L::any(valid & ~fits))  // rare: the lanes are looked at one by one only then
    for (int k = 0; k < kLanes; ++k) {
      if (!valid[k] || fits[k]) continue;
      const TriangleSetup t = {a1[k], c1[k], k1[k], a2[k], c2[k], k2[k], w[0][k], dw1[k], dw2[k]};
      raiseCovered(raise, width, t, int(firstX[k]), int(lastX[k]), int(firstY[k]), int(lastY[k]));
    }
  if (!L::any(square)) return;
  // Every sample of a quad's square is raised, without a branch: where none of its lanes covers it,
  // with -0, whose bits are the least in the z-buffer's order (the doubles' bits as signed integers),
  // which changes nothing. The square's second column or row may lie outside the picture, where no
  // lane reaches: those raise the first one's instead. A quad without a square raises the cells of
  // column and row 0 so. The cells are found in every lane at once, as doubles (whole numbers below
  // 2^53, so exact) converted to integers: cells[row][column], quad q's in its lanes.
  const Mask anySquare = square | Mask(L::swapped(Doubles(square)));
  const Doubles zero = L::splat(0.0);
  const Doubles column = anySquare ? left : zero, row = anySquare ? top : zero;
  const Doubles nextColumn = leastLanes(column + 1.0, L::splat(double(width - 1)));
  const Doubles rowCell = row * double(width);
  const Doubles nextRowCell = leastLanes(row + 1.0, L::splat(double(height - 1))) * double(width);
  auto cellIndex = [](Doubles v) { return __builtin_convertvector(v, Mask); };
  const Mask cells[2][2] = {{cellIndex(rowCell + column), cellIndex(rowCell + nextColumn)},
                            {cellIndex(nextRowCell + column), cellIndex(nextRowCell + nextColumn)}};
  const Mask nothing = Mask(L::splat(-0.0));  // INT64_MIN in every lane
  auto raiseAt = [&](int dy, int dx, Doubles px, Mask rowIn, Doubles r1, Doubles r2) {
    const Doubles b1 = a1 * px + r1, b2 = a2 * px + r2, b0 = 1.0 - b1 - b2;
    const Mask inside = rowIn & (px >= firstX) & (px <= lastX) & ~((b0 < -1e-9) | (b1 < -1e-9) | (b2 < -1e-9));
    // Raising with a quad's two lanes' values is raising with the larger in that order (found for
    // every quad at once: each lane against its pair's).
    const Mask bits = inside ? Mask(w[0] + b1 * dw1 + b2 * dw2) : nothing;
    const Mask pair = Mask(L::swapped(Doubles(bits)));
    const Mask largest = bits < pair ? pair : bits;
    // Through memory: one vector store each, then scalar loads, cheaper than taking lanes out of
    // a register one by one.
    alignas(sizeof(Mask)) int64_t at[kLanes];
    alignas(sizeof(Mask)) double values[kLanes];
    std::memcpy(at, &cells[dy][dx], sizeof at);
    std::memcpy(values, &largest, sizeof values);
    for (int q = 0; q < kQuads; ++q) raise(size_t(at[2 * q]), values[2 * q]);
  };
  const Doubles columnAfter = left + 1.0;
  {
    const Mask rowIn = square & (top >= firstY) & (top <= lastY);
    const Doubles r1 = c1 * top + k1, r2 = c2 * top + k2;
    raiseAt(0, 0, left, rowIn, r1, r2);
    raiseAt(0, 1, columnAfter, rowIn, r1, r2);
  }
  {
    const Doubles nextRow = top + 1.0;
    const Mask rowIn = square & (nextRow >= firstY) & (nextRow <= lastY);
    const Doubles r1 = c1 * nextRow + k1, r2 = c2 * nextRow + k2;
    raiseAt(1, 0, left, rowIn, r1, r2);
    raiseAt(1, 1, columnAfter, rowIn, r1, r2);
  }
}

// The quads rasteriseQuads takes at once where this build has the registers for them (0: none, the
// triangles are drawn one by one).
#if defined(__AVX512F__)
constexpr int kQuadsAtOnce = 4;
#elif defined(__AVX__)
constexpr int kQuadsAtOnce = 2;
#else
constexpr int kQuadsAtOnce = 1;
#endif
#else
constexpr int kQuadsAtOnce = 0;
#endif

// Rasterises the triangles of the quads between two rows of `width` warped reference samples
// (positions x, y in the virtual view and inverse depths w; w < 0: not warped): quad x has corners 0
// to 3 at samples x and x + 1 of the top row, then of the bottom row, and triangles (0, 1, 3) and
// (0, 3, 2), each drawn when its three corners are warped and their inverse depths span at most
// `discontinuity` (more, and it crosses a depth edge). Into a z-buffer outWidth x outHeight.
template <class Raise>
inline void rasteriseQuadRow(const Raise& raise, int width, int outWidth, int outHeight, double discontinuity,
                             const double* xTop, const double* yTop, const double* wTop, const double* xBottom,
                             const double* yBottom, const double* wBottom) {
  const Raise put = raise;  // a copy no store can change: what it holds stays in registers
#if defined(__SSE4_1__)
  // kQuadsAtOnce quads side by side, their depth corners first, which decide what to draw
  // (drawnTriangles). At the row's end, lanes past its last quad repeat quad x, not drawn.
  using Lanes = QuadLanes<kQuadsAtOnce>;
  for (int x = 0; x + 1 < width; x += kQuadsAtOnce) {
    typename Lanes::Doubles tx[3], ty[3], tw[3];
    typename Lanes::Mask drawn;
    const bool sideBySide = x + kQuadsAtOnce < width;
    int quad[kQuadsAtOnce];
    if (sideBySide) {
      Lanes::cornersInRow(wTop, wBottom, x, tw);
      drawn = drawnTriangles<kQuadsAtOnce>(tw, discontinuity);
    } else {
      bool inRow[2 * kQuadsAtOnce];
      for (int q = 0; q < kQuadsAtOnce; ++q) {
        quad[q] = x + q + 1 < width ? x + q : x;
        inRow[2 * q] = inRow[2 * q + 1] = q == 0 || quad[q] != x;
      }
      Lanes::corners(wTop, wBottom, quad, tw);
      drawn = drawnTriangles<kQuadsAtOnce>(tw, discontinuity) & Lanes::lanes(inRow);
    }
    if (!Lanes::any(drawn)) continue;
    if (sideBySide) {
      Lanes::cornersInRow(xTop, xBottom, x, tx);
      Lanes::cornersInRow(yTop, yBottom, x, ty);
    } else {
      Lanes::corners(xTop, xBottom, quad, tx);
      Lanes::corners(yTop, yBottom, quad, ty);
    }
    rasteriseQuads<kQuadsAtOnce>(put, outWidth, outHeight, tx, ty, tw, drawn);
  }
#else
  for (int x = 0; x + 1 < width; ++x) {
    // Which of quad x's two triangles to draw: corners 0 and 3 belong to both, and a quad with a
    // corner not warped has none (drawnTriangles' rule, one quad at a time).
    const double d0 = wTop[x], d1 = wTop[x + 1], d2 = wBottom[x], d3 = wBottom[x + 1];
    bool draw[2] = {false, false};
    if (!(d0 < 0 || d3 < 0 || (d1 < 0 && d2 < 0))) {
      const double lo03 = std::min(d0, d3), hi03 = std::max(d0, d3);
      draw[0] = d1 >= 0 && std::max(hi03, d1) - std::min(lo03, d1) <= discontinuity;
      draw[1] = d2 >= 0 && std::max(hi03, d2) - std::min(lo03, d2) <= discontinuity;
    }
    if (draw[0]) {
      const double tx[3] = {xTop[x], xTop[x + 1], xBottom[x + 1]}, ty[3] = {yTop[x], yTop[x + 1], yBottom[x + 1]};
      const double tw[3] = {wTop[x], wTop[x + 1], wBottom[x + 1]};
      rasteriseTriangle(put, outWidth, outHeight, tx, ty, tw);
    }
    if (draw[1]) {
      const double tx[3] = {xTop[x], xBottom[x + 1], xBottom[x]}, ty[3] = {yTop[x], yBottom[x + 1], yBottom[x]};
      const double tw[3] = {wTop[x], wBottom[x + 1], wBottom[x]};
      rasteriseTriangle(put, outWidth, outHeight, tx, ty, tw);
    }
  }
#endif
}

VS_RASTER_LEVEL_END
}  // namespace vs
