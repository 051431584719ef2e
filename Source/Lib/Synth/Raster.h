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
#include <type_traits>

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

#if defined(__AVX512F__) && defined(__AVX512DQ__)
// Eight samples raised into one writer's z-buffer at once where their cells are consecutive (a run of
// one level along an output row, as on a rectified rig): `at` holds each lane's cell as a double (a
// whole number below 2^53, exact) and `first` lane 0's. Where the lanes' cells are first, first + 1, ...,
// first + 7, each cell is raised once, by its own sample: one load, a max of the bits as signed 64-bit
// integers in every lane, one store; otherwise nothing is raised and the result is false. (The
// zero-masking forms of the intrinsics: GCC 12's plain ones warn.) The points of the general and the
// 1D depth warps (Kernels/QuadRow.cpp, Kernels/Rows.cpp) use it.
inline bool raiseConsecutiveCells(double* cells, __m512d at, long long first, __m512d values) {
  const __m512i iota = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
  if (_mm512_cmpeq_epi64_mask(_mm512_maskz_cvttpd_epi64(0xff, at), _mm512_add_epi64(_mm512_set1_epi64(first), iota)) !=
      0xff)
    return false;
  double* start = cells + first;
  _mm512_storeu_si512(start, _mm512_maskz_max_epi64(0xff, _mm512_loadu_si512(start), _mm512_castpd_si512(values)));
  return true;
}
#endif

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

#if defined(__AVX512F__) && defined(__AVX512DQ__)
// A rectified pair of rows (doc/speed.md, "Rectified rows ..."): every warped sample of the top row
// lies exactly on one output row Y and every one of the bottom row on Y + 1, as a rig with the same
// rotation and intrinsics whose centres are displaced along x gives them (the projection's y is the
// reference row, bit for bit). Quad q's triangles T0 = (top q, top q + 1, bottom q + 1) and T1 = (top q,
// bottom q + 1, bottom q) then reach pixel centres on rows Y and Y + 1 only, and with the z-buffer's
// 1e-9 tolerances and the rounding of their coefficients, T0 covers on row Y only centres within
// kRectifiedNear of its top edge [top q, top q + 1] and on row Y + 1 only within it of its corner
// bottom q + 1; T1 on row Y + 1 only near its bottom edge [bottom q, bottom q + 1], on row Y only near
// top q. (With coordinates within 2^16, rows below 2^16 and corners within 64 of each other, the
// barycentric coordinates' rounding errors stay under 2^-30 in pixel units, and a centre d outside an
// edge of length at most 16 has a coordinate below -d / 16: at d = 2^-21 that is below -1e-9 by more
// than those errors.)
//
// Eight quads whose top positions, and bottom positions, increase by more than 2 kRectifiedNear from
// sample to sample are then drawn centre by centre, the first n of them (up to eight) whose centres fit
// one register on each row: the centres of row Y between the first and last top positions, each evaluated with the triangle whose edge holds it (T0 of the
// quad whose top positions enclose it) and, where it lies within kRectifiedNear of a top position,
// with the other triangles meeting there (the neighbouring quad's T0 and T1 of the quad starting
// there); row Y + 1 the same with the bottom positions, T1's edges and T0's corners. Each evaluation
// is rasteriseQuads' for that triangle and centre, the same operations on the same values (the
// triangles' coefficients computed as there, in lanes, and moved to the centres' lanes), so a centre
// gets the largest of the values the triangle rasteriser gives it; the eight cells are raised with
// one load, a max of the bits as signed integers and one store. A group that does not qualify is drawn
// by rasteriseQuads.
constexpr double kRectifiedNear = 1.0 / 1048576.0;  // 2^-20

// Whether every warped sample (w >= 0) of the row has y bit for bit equal to `row`.
inline bool samplesOnRow(const double* y, const double* w, int width, double row) {
  const __m512i rowBits = _mm512_set1_epi64(__builtin_bit_cast(long long, row));
  const __m512d zero = _mm512_setzero_pd();
  for (int x = 0; x < width; x += 8) {
    const __mmask8 in = width - x >= 8 ? __mmask8(0xff) : __mmask8((1u << (width - x)) - 1);
    const __mmask8 warped = _mm512_mask_cmp_pd_mask(in, _mm512_maskz_loadu_pd(in, w + x), zero, _CMP_GE_OQ);
    if (_mm512_mask_cmpneq_epi64_mask(warped, _mm512_maskz_loadu_epi64(in, y + x), rowBits)) return false;
  }
  return true;
}

// The set-up of eight triangles (one per quad) as rasteriseQuads computes it, for the rows it is
// evaluated on: b1 = a1 px + r1, b2 = a2 px + r2 on that row. `from` is the first covered centre, or
// 1e300 where the triangle is not drawn (so that no centre passes px >= from).
struct RectifiedTriangles {
  typedef QuadLanes<4>::Doubles Doubles;
  Doubles a1, a2, w0, dw1, dw2, from, to;
  Doubles r1[2], r2[2];  // rows Y and Y + 1
};

// kSecond: T1 = (x0, x1, x2) = (top q, bottom q + 1, bottom q) on rows (Y, Y + 1, Y + 1), else T0 = (top q,
// top q + 1, bottom q + 1) on rows (Y, Y, Y + 1). Rows `rows` (bit r: row Y + r) of r1 and r2 are set.
// kBox false: the triangles are evaluated only at centres strictly between the two positions of their edge
// and inside the view (rows with no position near a centre), which every box holding the edge holds;
// `from` and `to` then only mark the triangles drawn, and the box is not computed.
template <bool kSecond, bool kBox>
[[gnu::always_inline]] inline RectifiedTriangles rectifiedSetUp(QuadLanes<4>::Doubles x0, QuadLanes<4>::Doubles x1,
                                                                QuadLanes<4>::Doubles x2, QuadLanes<4>::Doubles w0,
                                                                QuadLanes<4>::Doubles w1, QuadLanes<4>::Doubles w2,
                                                                QuadLanes<4>::Mask drawn, int width, double rowY,
                                                                unsigned rows) {
  using L = QuadLanes<4>;
  using Doubles = L::Doubles;
  using Mask = L::Mask;
  const Doubles zero = L::splat(0.0), top = L::splat(double(width - 1));
  // rasteriseQuads' covered() for x; the rows' range is the same for every triangle (checked by the caller).
  Doubles firstX = zero, lastX = top;
  Mask inX = ~Mask{};
  if constexpr (kBox) {
    const Doubles lo = leastLanes(x0, leastLanes(x1, x2)), hi = mostLanes(x0, mostLanes(x1, x2));
    const Mask some = ~((hi < -1e-9) | (lo > width - 1 + 1e-9));
    Doubles l = lo - 1e-9, h = hi + 1e-9;
    l = l < zero ? zero : l;
    h = top < h ? top : h;
    firstX = L::ceil(l);
    lastX = L::floor(h);
    inX = some & Mask(firstX <= lastX);
  }
  // rasteriseQuads' area, (x1 - x0) (y2 - y0) - (x2 - x0) (y1 - y0), and coefficients with the rows' differences
  // y2 - y0 = 1 and y1 - y0 = 0 (T0) or 1 (T1), exact: a product by 1 is its factor, by +0 a zero, and x1 - x0
  // less a zero is x1 - x0 (not 0: the positions increase).
  const Doubles dx1 = x1 - x0, dx2 = x2 - x0;
  const Doubles area = kSecond ? dx1 - dx2 : dx1;
  const Mask magnitude = Mask(area) & INT64_MAX;  // fabs
  const Mask valid = drawn & inX & ~(Doubles(magnitude) < 1e-12);
  const Doubles inv = 1.0 / area;
  const Doubles a1 = inv, c1 = -dx2 * inv;
  const Doubles a2 = kSecond ? -inv : L::splat(-0.0) * inv, c2 = dx1 * inv;
  const Doubles y0 = L::splat(rowY);  // as the row holds it (-0 for a row at -0)
  const Doubles k1 = -(a1 * x0 + c1 * y0), k2 = -(a2 * x0 + c2 * y0);
  RectifiedTriangles t;
  t.a1 = a1;
  t.a2 = a2;
  t.w0 = w0;
  t.dw1 = w1 - w0;
  t.dw2 = w2 - w0;
  t.from = valid ? firstX : L::splat(1e300);
  t.to = lastX;
  for (int r = 0; r < 2; ++r) {
    if (!(rows >> r & 1)) {
      t.r1[r] = t.r2[r] = zero;  // not evaluated
      continue;
    }
    const Doubles row = L::splat(rowY + 0.0 + r);  // rasteriseQuads' rows: +0 for row 0
    t.r1[r] = c1 * row + k1;
    t.r2[r] = c2 * row + k2;
  }
  return t;
}

// The bits to raise centres px (lanes) with from the triangles in the same lanes of a1 .. to (taken from a
// RectifiedTriangles on row r, in place or moved by permutes): rasteriseQuads' test and value; INT64_MIN
// (the bits of -0, which raise nothing) where a triangle does not cover its centre or where `use` is clear.
[[gnu::always_inline]] inline __m512i rectifiedTest(QuadLanes<4>::Doubles a1, QuadLanes<4>::Doubles r1,
                                                    QuadLanes<4>::Doubles a2, QuadLanes<4>::Doubles r2,
                                                    QuadLanes<4>::Doubles w0, QuadLanes<4>::Doubles dw1,
                                                    QuadLanes<4>::Doubles dw2, QuadLanes<4>::Doubles from,
                                                    QuadLanes<4>::Doubles to, QuadLanes<4>::Doubles px, __mmask8 use) {
  using Doubles = QuadLanes<4>::Doubles;
  using Mask = QuadLanes<4>::Mask;
  const Doubles b1 = a1 * px + r1, b2 = a2 * px + r2, b0 = 1.0 - b1 - b2;
  const Mask inside = (px >= from) & (px <= to) & ~((b0 < -1e-9) | (b1 < -1e-9) | (b2 < -1e-9));
  const Doubles value = w0 + b1 * dw1 + b2 * dw2;
  const __mmask8 covered = __mmask8(use & _mm512_movepi64_mask(__m512i(inside)));
  return _mm512_mask_blend_epi64(covered, _mm512_set1_epi64(INT64_MIN), __m512i(value));
}

// rectifiedTest of centre px (lanes) with triangle idx (lanes) of t on row r.
[[gnu::always_inline]] inline __m512i rectifiedValue(const RectifiedTriangles& t, int r, __m512i idx,
                                                     QuadLanes<4>::Doubles px, __mmask8 use) {
  using Doubles = QuadLanes<4>::Doubles;
  auto take = [&](Doubles v) { return Doubles(_mm512_maskz_permutexvar_pd(0xff, idx, __m512d(v))); };
  return rectifiedTest(take(t.a1), take(t.r1[r]), take(t.a2), take(t.r2[r]), take(t.w0), take(t.dw1), take(t.dw2),
                       take(t.from), take(t.to), px, use);
}

// rectifiedTest of each lane's own triangle of t on row r at centres px.
[[gnu::always_inline]] inline __m512i rectifiedOwnValue(const RectifiedTriangles& t, int r, QuadLanes<4>::Doubles px,
                                                        __mmask8 use) {
  return rectifiedTest(t.a1, t.r1[r], t.a2, t.r2[r], t.w0, t.dw1, t.dw2, t.from, t.to, px, use);
}

// One row of centres (row r: 0 for Y, 1 for Y + 1) between positions pos[0] < ... < pos[n] of the n
// quads drawn (pos[8] is read too): the edges' triangles `edges` (T0 on row Y, T1 on Y + 1) and, near a
// position (only where `nearAny`: some position lies within kRectifiedNear of a centre), the triangles
// `corners` meeting there (T1 on row Y, T0 on Y + 1). On row Y the corner triangle at position i is T1
// of quad i; on row Y + 1 it is T0 of quad i - 1 (`cornerShift` 0 or 1). Lanes of quads from n on are
// not drawn in `edges` and `corners`.
[[gnu::always_inline]] inline void rectifiedCentres(double* cells, int width, const double* pos, int n, bool nearAny,
                                                    const RectifiedTriangles& edges,
                                                    const RectifiedTriangles& corners, int r, int cornerShift) {
  using Doubles = QuadLanes<4>::Doubles;
  const double near = kRectifiedNear;
  const double startAt = std::max(std::ceil(pos[0] - near), 0.0),
               endAt = std::min(std::floor(pos[n] + near), double(width - 1));
  if (!(startAt <= endAt)) return;
  const __m512d positions = _mm512_loadu_pd(pos), last = _mm512_set1_pd(pos[8]);
  const __m512i one = _mm512_set1_epi64(1), seven = _mm512_set1_epi64(7);
  const __m512d iota = _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7);
  for (double c = startAt; c <= endAt; c += 8.0) {
    const __m512d centre = _mm512_add_pd(_mm512_set1_pd(c), iota);
    const __mmask8 in = _mm512_cmp_pd_mask(centre, _mm512_set1_pd(endAt), _CMP_LE_OQ);
    // j: the positions 1 .. 7 below the centre, so that pos[j] < centre <= pos[j + 1] where it lies
    // within the eight quads.
    __m512i j = _mm512_setzero_si512();
    for (int i = 1; i < 8; ++i)
      j = _mm512_mask_add_epi64(j, _mm512_cmp_pd_mask(_mm512_set1_pd(pos[i]), centre, _CMP_LT_OQ), j, one);
    const Doubles px = Doubles(centre);
    __m512i best = rectifiedValue(edges, r, j, px, in);
    const __m512i next = _mm512_add_epi64(j, one);
    const __m512d absMask = _mm512_castsi512_pd(_mm512_set1_epi64(INT64_MAX));
    __mmask8 nearLow = 0, nearHigh = 0;
    if (nearAny) {
      const __m512d low = _mm512_maskz_permutexvar_pd(0xff, j, positions),
                    high = _mm512_permutex2var_pd(positions, next, last);
      nearLow = _mm512_mask_cmp_pd_mask(in, _mm512_and_pd(_mm512_sub_pd(centre, low), absMask), _mm512_set1_pd(near),
                                        _CMP_LE_OQ);
      nearHigh = _mm512_mask_cmp_pd_mask(in, _mm512_and_pd(_mm512_sub_pd(high, centre), absMask),
                                         _mm512_set1_pd(near), _CMP_LE_OQ);
    }
    if (nearLow | nearHigh) {
      const __mmask8 firstQuad = _mm512_cmpeq_epi64_mask(j, _mm512_setzero_si512());
      const __mmask8 lastQuad = _mm512_cmpeq_epi64_mask(j, seven);
      // The other edge meeting at the position: quad j - 1's (near pos[j]) or quad j + 1's (near pos[j + 1]).
      const __m512i other = _mm512_mask_sub_epi64(next, nearLow, j, one);
      best = _mm512_maskz_max_epi64(0xff, best, rectifiedValue(edges, r, other, px,
                                                   __mmask8((nearLow & ~firstQuad) | (nearHigh & ~lastQuad))));
      // The corner triangle at position i (j or j + 1): quad i - cornerShift's.
      const __m512i at = _mm512_mask_mov_epi64(next, nearLow, j);
      const __m512i quad = _mm512_sub_epi64(at, _mm512_set1_epi64(cornerShift));
      const __mmask8 exists = __mmask8(_mm512_cmpge_epi64_mask(quad, _mm512_setzero_si512()) &
                                       _mm512_cmple_epi64_mask(quad, seven));
      best = _mm512_maskz_max_epi64(0xff, best, rectifiedValue(corners, r, quad, px, __mmask8((nearLow | nearHigh) & exists)));
    }
    double* at = cells + size_t(c);
    _mm512_mask_storeu_epi64(at, in, _mm512_maskz_max_epi64(0xff, _mm512_maskz_loadu_epi64(in, at), best));
  }
}

// Whether the quads' first centres follow each other, as they do where each quad is about a pixel wide:
// with L_i = ceil(pos[i] - kRectifiedNear) (`first`: L_0 .. L_7, `next`: L_1 .. L_8), L_(i + 1) = L_i + 1
// for the n quads drawn, and L_0 lies in the view.
[[gnu::always_inline]] inline bool rectifiedInOrder(QuadLanes<4>::Doubles first, QuadLanes<4>::Doubles next, int n,
                                                    int width) {
  const __mmask8 owned = __mmask8((1u << n) - 1);
  if ((_mm512_cmp_pd_mask(__m512d(next - first), _mm512_set1_pd(1.0), _CMP_EQ_OQ) & owned) != owned) return false;
  return first[0] >= 0.0 && first[0] <= double(width - 1);
}

// rectifiedCentres where rectifiedInOrder holds. By the coverage argument quad i's edge triangle then
// reaches only centre L_i, and L_i + 1 = L_(i + 1) where pos[i + 1] lies within kRectifiedNear of it; the
// corner triangle at position i only L_i. So the centres are lanes 0 .. 7 from L_0 on, and each quad's
// triangles are evaluated in the quad's own lanes, at L_i, and (only where `nearAny`) at L_i + 1, moved one
// lane up: no look-up of the quad holding a centre. Each evaluation is rasteriseQuads' (rectifiedTest),
// and the cells raised are rectifiedCentres' (L_0 to `lastCentre`, floor(pos[n] + kRectifiedNear), at
// most eight by the choice of n).
[[gnu::always_inline]] inline void rectifiedCentresInOrder(double* cells, int width, QuadLanes<4>::Doubles first,
                                                           double lastCentre, int n, bool nearAny,
                                                           const RectifiedTriangles& edges,
                                                           const RectifiedTriangles& corners, int r, int cornerShift) {
  using Doubles = QuadLanes<4>::Doubles;
  const __mmask8 owned = __mmask8((1u << n) - 1);
  const double startAt = first[0];
  const double endAt = std::min(lastCentre, double(width - 1));
  // rectifiedCentres' centres are c + k, whole numbers, +0 for 0: L + 0 (-0 becomes +0).
  const Doubles px = first + 0.0;
  const __mmask8 in = _mm512_cmp_pd_mask(_mm512_add_pd(_mm512_set1_pd(startAt), _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7)),
                                         _mm512_set1_pd(endAt), _CMP_LE_OQ);
  __m512i best = rectifiedOwnValue(edges, r, px, owned);
  if (nearAny) {
    if (cornerShift == 0) best = _mm512_maskz_max_epi64(0xff, best, rectifiedOwnValue(corners, r, px, owned));
    const Doubles after = px + 1.0;
    __m512i right = rectifiedOwnValue(edges, r, after, owned);
    if (cornerShift == 1) right = _mm512_maskz_max_epi64(0xff, right, rectifiedOwnValue(corners, r, after, owned));
    // Lane k takes lane k - 1's evaluations at L_(k - 1) + 1 = L_k.
    best = _mm512_maskz_max_epi64(0xff, best, _mm512_maskz_alignr_epi64(0xff, right, _mm512_set1_epi64(INT64_MIN), 7));
  }
  double* at = cells + size_t(startAt);
  _mm512_mask_storeu_epi64(at, in, _mm512_maskz_max_epi64(0xff, _mm512_maskz_loadu_epi64(in, at), best));
}

// Quads x .. x + n - 1 between rectified rows rowY (top) and rowY + 1 (bottom) into one thread's
// z-buffer (rows `cellsY` and `cellsY1`, the latter null where row Y + 1 lies outside the view), n up to
// 8, as many as keep each row's centres within one register of eight; returns n, or 0, drawing nothing,
// where quads x .. x + 7 do not qualify. Samples x to x + 8 of both rows are read.
[[gnu::always_inline]] inline int rasteriseRectifiedQuads(double* cellsY, double* cellsY1, int width,
                                                           double discontinuity, double rowY, const double* xTop,
                                                           const double* wTop, const double* xBottom,
                                                           const double* wBottom, int x) {
  using L = QuadLanes<4>;
  using Doubles = L::Doubles;
  using Mask = L::Mask;
  const double near2 = 2.0 * kRectifiedNear;
  Doubles p0, p1, q0, q1, wp0, wp1, wq0, wq1;
  std::memcpy(&p0, xTop + x, sizeof p0);
  std::memcpy(&p1, xTop + x + 1, sizeof p1);
  std::memcpy(&q0, xBottom + x, sizeof q0);
  std::memcpy(&q1, xBottom + x + 1, sizeof q1);
  // Increasing by more than 2 kRectifiedNear (NaN fails), top and bottom within 32 of each other,
  // eight quads within 15 and within 2^16 of the origin: the bounds the coverage argument takes.
  const Doubles magnitude = Doubles(Mask(p0 - q0) & INT64_MAX), endMagnitude = Doubles(Mask(p1 - q1) & INT64_MAX);
  const Mask fits = Mask(p1 - p0 > near2) & Mask(q1 - q0 > near2) & Mask(magnitude <= 32.0) & Mask(endMagnitude <= 32.0);
  if (_mm512_movepi64_mask(__m512i(fits)) != 0xff) return 0;
  const double first[2] = {xTop[x], xBottom[x]}, lastOnes[2] = {xTop[x + 8], xBottom[x + 8]};
  for (int r = 0; r < 2; ++r)
    if (!(lastOnes[r] - first[r] <= 15.0 && first[r] >= -65536.0 && lastOnes[r] <= 65536.0)) return 0;
  // For each position, the first centre from it less kRectifiedNear on, ceil(pos - kRectifiedNear), and
  // the last up to it plus kRectifiedNear, floor(pos + kRectifiedNear): lanes 0 .. 7 of positions 0 .. 7
  // (from) and 1 .. 8 (to), on both rows.
  constexpr int kCeil = _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC, kFloor = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
  const auto ceilLanes = [](Doubles v) { return Doubles(_mm512_maskz_roundscale_pd(0xff, __m512d(v), kCeil)); };
  const auto floorLanes = [](Doubles v) { return Doubles(_mm512_maskz_roundscale_pd(0xff, __m512d(v), kFloor)); };
  const Doubles firstTop = ceilLanes(p0 - kRectifiedNear), nextTop = ceilLanes(p1 - kRectifiedNear);
  const Doubles firstBottom = ceilLanes(q0 - kRectifiedNear), nextBottom = ceilLanes(q1 - kRectifiedNear);
  const Doubles lastTop = floorLanes(p1 + kRectifiedNear), lastBottom = floorLanes(q1 + kRectifiedNear);
  // The quads drawn: as many as keep the centres from the first position to the last within eight on
  // both rows (quads a little wider than a pixel reach nine centres in eight quads). Lane k holds the
  // centres of quads 0 .. k, which grow with k.
  const auto within8 = [](Doubles last, Doubles first) {
    return _mm512_movepi64_mask(__m512i(last - L::splat(first[0]) + 1.0 <= 8.0));
  };
  const int n = __builtin_ctz(~unsigned(within8(lastTop, firstTop) & within8(lastBottom, firstBottom)));
  if (n == 0) return 0;
  // Whether any position of a row lies within kRectifiedNear of a pixel centre: where the last centre up
  // to it plus kRectifiedNear is not before the first from it less kRectifiedNear (position 0 from the
  // `from` lanes, the others from the `to` lanes).
  const auto nearCentre = [&](Doubles from, Doubles firstFrom, Doubles next, Doubles last) {
    return std::floor(from[0] + kRectifiedNear) >= firstFrom[0] || L::any(Mask(last >= next));
  };
  const bool nearTop = nearCentre(p0, firstTop, nextTop, lastTop);
  const bool nearBottom = nearCentre(q0, firstBottom, nextBottom, lastBottom);
  std::memcpy(&wp0, wTop + x, sizeof wp0);
  std::memcpy(&wp1, wTop + x + 1, sizeof wp1);
  std::memcpy(&wq0, wBottom + x, sizeof wq0);
  std::memcpy(&wq1, wBottom + x + 1, sizeof wq1);
  // drawnTriangles' rule: T0's corners 0 and 3 are top x and bottom x + 1, its third top x + 1; T1's third bottom x.
  auto drawn = [&](Doubles corner0, Doubles corner3, Doubles third) {
    const Doubles lo03 = leastLanes(corner0, corner3), hi03 = mostLanes(corner0, corner3);
    const Mask warped = ~(corner0 < 0) & ~(corner3 < 0) & (third >= 0);
    return warped & Mask(mostLanes(hi03, third) - leastLanes(lo03, third) <= discontinuity);
  };
  Mask owned;
  for (int k = 0; k < 8; ++k) owned[k] = -int64_t(k < n);
  const Mask drawn0 = drawn(wp0, wq1, wp1) & owned, drawn1 = drawn(wp0, wq1, wq0) & owned;
  if (!L::any(drawn0 | drawn1)) return n;  // nothing to draw: what rasteriseQuads would do
  // T0 is evaluated on row Y + 1 only near a bottom position, T1 on row Y only near a top position; their
  // boxes are needed only near a position (with none, every centre evaluated lies strictly between the two
  // positions of its edge, the quad's own in rectifiedCentresInOrder and the one enclosing it in
  // rectifiedCentres, and in the view).
  const bool orderTop = rectifiedInOrder(firstTop, nextTop, n, width);
  const bool orderBottom = cellsY1 && rectifiedInOrder(firstBottom, nextBottom, n, width);
  RectifiedTriangles t0, t1;
  if (nearTop || nearBottom) {
    t0 = rectifiedSetUp<false, true>(p0, p1, q1, wp0, wp1, wq1, drawn0, width, rowY, nearBottom ? 3 : 1);
    t1 = rectifiedSetUp<true, true>(p0, q1, q0, wp0, wq1, wq0, drawn1, width, rowY, nearTop ? 3 : 2);
  } else {
    t0 = rectifiedSetUp<false, false>(p0, p1, q1, wp0, wp1, wq1, drawn0, width, rowY, 1);
    t1 = rectifiedSetUp<true, false>(p0, q1, q0, wp0, wq1, wq0, drawn1, width, rowY, 2);
  }
  if (orderTop) rectifiedCentresInOrder(cellsY, width, firstTop, lastTop[n - 1], n, nearTop, t0, t1, 0, 0);
  else rectifiedCentres(cellsY, width, xTop + x, n, nearTop, t0, t1, 0, 0);
  if (orderBottom)
    rectifiedCentresInOrder(cellsY1, width, firstBottom, lastBottom[n - 1], n, nearBottom, t1, t0, 1, 1);
  else if (cellsY1)
    rectifiedCentres(cellsY1, width, xBottom + x, n, nearBottom, t1, t0, 1, 1);
  return n;
}
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
  const int quads = width - 1;
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  // Rectified rows, one writer: groups of eight quads drawn centre by centre (rasteriseRectifiedQuads),
  // those that do not qualify as below.
  double *rectifiedY = nullptr, *rectifiedY1 = nullptr;
  double rowY = 0;
  if constexpr (std::is_same<Raise, LoneRaise>::value) {
    int k = 0;
    while (k < width && !(wTop[k] >= 0)) ++k;
    if (quads >= 8 && k < width) {
      rowY = yTop[k];
      if (rowY >= 0 && rowY < 65535.0 && rowY == std::floor(rowY) && samplesOnRow(yTop, wTop, width, rowY) &&
          samplesOnRow(yBottom, wBottom, width, rowY + 1.0)) {
        if (rowY > outHeight - 1) return;  // every triangle's rows lie below the view
        rectifiedY = put.cells + size_t(rowY) * size_t(outWidth);
        if (rowY + 1.0 <= outHeight - 1) rectifiedY1 = rectifiedY + outWidth;
      }
    }
  }
  int plainFrom = 0;
#endif
  for (int x = 0; x < quads; x += kQuadsAtOnce) {
#if defined(__AVX512F__) && defined(__AVX512DQ__)
    if (rectifiedY && x >= plainFrom) {
      const int taken = x + 8 <= quads ? rasteriseRectifiedQuads(rectifiedY, rectifiedY1, outWidth, discontinuity,
                                                                 rowY, xTop, wTop, xBottom, wBottom, x)
                                       : 0;
      if (taken > 0) {
        x += taken - kQuadsAtOnce;
        continue;
      }
      plainFrom = x + 8;
    }
#endif
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
