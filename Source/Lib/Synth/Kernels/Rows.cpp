// Compiled once per x86-64 level (Source/Lib/Synth/area.cmake): -march=x86-64[-vN], VS_LEVEL_NS=vN,
// VS_KERNEL_LEVEL=N. Only Rows.h (plain structs), Raster.h (whose code then lies in vs::vN) and
// standard headers are included: nothing of a shared header is compiled here at a level another
// file could pick up (CTest KernelSymbols_vN). The loops are those of the files that call them (Rows.h names each), with the
// same operations in the same order: the compiler vectorises them as wide as the level allows, and
// from x86-64-v2 on floor() and nearbyint() are single instructions.
#include "Synth/Kernels/Rows.h"

#include "Synth/Raster.h"  // its code lies in vs::vN here (VS_LEVEL_NS)

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#if defined(__AVX512F__)
#include <immintrin.h>
#elif defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#if !defined(VS_LEVEL_NS) || !defined(VS_KERNEL_LEVEL)
#error "compile Rows.cpp with VS_LEVEL_NS and VS_KERNEL_LEVEL (Source/Lib/Synth/area.cmake)"
#endif

namespace vs {
inline namespace VS_LEVEL_NS {

namespace {

// ViewProjection::snapPosition (Synth/Warp.h): the position rounded to 2^-30 px.
inline double snap(double position) {
  constexpr double grid = 1073741824.0, cell = 1.0 / 1073741824.0;
  return std::nearbyint(position * grid) * cell;
}

// std::floor(y), bit for bit. GCC 12 vectorises nearbyint() but not floor(): from SSE4.1 on, floor is
// taken from the nearest integer r (ties to even: the rounding mode every computation here assumes),
// one less where r lies above y. r is within 1/2 of y, so r - 1 <= y < r there, and r - 1 is exact
// (an r of 2^52 or more is y itself, never above it); NaN and the infinities come back as they are,
// and -0.0 too (it is not below its r), while a y in [-1/2, 0) gets -0 - 1 = -1.
inline double floorOf(double y) {
#if defined(__SSE4_1__)
  const double r = std::nearbyint(y);
  return r > y ? r - 1.0 : r;
#else
  return std::floor(y);  // inline SSE2 code at the baseline, where nearbyint() is a call
#endif
}

constexpr double kFarthest = std::numeric_limits<double>::max();
constexpr double kMaxPixelRadius = 1e9;  // ViewProjection::kMaxPixelRadius

void forwardRow(const ProjectionCoefficients& c, const double* inverseDepth, int n, double v, double* xs, double* ys,
                double* ws) {
  const double m00 = c.m[0][0], m01 = c.m[0][1], m02 = c.m[0][2], m10 = c.m[1][0], m11 = c.m[1][1], m12 = c.m[1][2];
  const double m20 = c.m[2][0], m21 = c.m[2][1], m22 = c.m[2][2];
  const double ox = c.o[0], oy = c.o[1], oz = c.o[2], most = kMaxPixelRadius;
  for (int u = 0; u < n; ++u) {
    const double w = inverseDepth[u], fu = u;
    const double px = (m00 * fu + m01 * v + m02) + ox * w;
    const double py = (m10 * fu + m11 * v + m12) + oy * w;
    const double pz = (m20 * fu + m21 * v + m22) + oz * w;
    const double x = snap(px / pz), y = snap(py / pz), wv = w / pz;
    const bool ok = (w >= 0.0) & (pz > 0.0) & (std::fabs(px) <= most * pz) & (std::fabs(py) <= most * pz) &
                    (std::fabs(x) <= kFarthest) & (std::fabs(y) <= kFarthest) & (std::fabs(wv) <= kFarthest);
    xs[u] = x;
    ys[u] = y;
    ws[u] = ok ? wv : -1.0;
  }
}

void backwardRow(const ProjectionCoefficients& c, const double* wv, int n, double y, double* us, double* vs,
                 uint8_t* ok, int step, double start) {
  const double m00 = c.m[0][0], m01 = c.m[0][1], m02 = c.m[0][2], m10 = c.m[1][0], m11 = c.m[1][1], m12 = c.m[1][2];
  const double m20 = c.m[2][0], m21 = c.m[2][1], m22 = c.m[2][2];
  const double ox = c.o[0], oy = c.o[1], oz = c.o[2], most = kMaxPixelRadius;
  for (int i = 0; i < n; ++i) {
    const double x = double(i * step) + start, w = wv[i];
    const double qx = m00 * x + m01 * y + m02 + ox * w;
    const double qy = m10 * x + m11 * y + m12 + oy * w;
    const double qz = m20 * x + m21 * y + m22 + oz * w;
    const double u = snap(qx / qz), v = snap(qy / qz);
    us[i] = u;
    vs[i] = v;
    ok[i] = uint8_t((qz > 0.0) & (std::fabs(qx) <= most * qz) & (std::fabs(qy) <= most * qz) &
                    (std::fabs(u) <= kFarthest) & (std::fabs(v) <= kFarthest));
  }
}

void rowSources(double offset, double shift, double inverse, double scale, const double* wv, int n, double* u, int step,
                double start) {
  if (inverse != 0) {
    for (int i = 0; i < n; ++i) u[i] = snap((double(i * step) + start - offset - shift * wv[i]) * inverse);
  } else {
    for (int i = 0; i < n; ++i) u[i] = snap((double(i * step) + start - offset - shift * wv[i]) / scale);
  }
}

void rowTargets(const uint16_t* __restrict levels, int width, const double* __restrict table, size_t beyond,
                double scale, double offset, double* __restrict xs, double* __restrict ws) {
  // Finite as a comparison (NaN compares false) and __restrict, so that GCC vectorises the loop (the
  // table read by gathers where the level has them).
  for (int x = 0; x < width; ++x) {
    const size_t level = size_t(levels[x]) < beyond ? size_t(levels[x]) : beyond;
    const double displacement = table[2 * level], depth = table[2 * level + 1];
    const double target = snap((scale * double(x) + offset) + displacement);
    ws[x] = std::fabs(target) <= kFarthest ? depth : kKernelNoDepth;
    xs[x] = target;
  }
}

void rowPoints(const double* xs, const double* ws, int width, double* z, int outWidth) {
  int x = 0;
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  // Eight samples at a time. Where all eight land on consecutive cells (a run of one level, as most
  // samples of a row are), raiseConsecutiveCells (Raster.h); otherwise the samples that land are raised
  // one by one.
  const __m512d half8 = _mm512_set1_pd(0.5), zero8 = _mm512_setzero_pd(), right8 = _mm512_set1_pd(double(outWidth));
  for (; x + 8 <= width; x += 8) {
    const __m512d pw = _mm512_loadu_pd(ws + x);
    // floor (the zero-masking forms of the intrinsics: GCC 12's plain ones warn, as in Raster.h)
    const __m512d px = _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_loadu_pd(xs + x), half8),
                                                  _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __mmask8 lands = __mmask8(~(_mm512_cmp_pd_mask(pw, zero8, _CMP_LT_OQ) |
                                      _mm512_cmp_pd_mask(px, zero8, _CMP_LT_OQ) |
                                      _mm512_cmp_pd_mask(px, right8, _CMP_GE_OQ)));
    if (lands == 0xff && raiseConsecutiveCells(z, px, (long long)std::floor(xs[x] + 0.5), pw)) continue;
    alignas(64) double centres[8];
    _mm512_store_pd(centres, px);
    for (unsigned m = lands; m; m &= m - 1) {
      const int k = __builtin_ctz(m);
      raiseCell(z[size_t(centres[k])], ws[x + k]);
    }
  }
#elif defined(__SSE4_1__)
  // A register of samples at a time, as Raster.h's points: their centres and whether each lands in
  // lanes (the same double operations per lane), then every lane raised without a branch, one that does
  // not land with -0 at cell 0, the least value in the z-buffer's order, which changes nothing. (A
  // sample with ws >= 0 has a finite position: rowTargets.)
  using L = QuadLanes<kQuadsAtOnce>;
  using Doubles = typename L::Doubles;
  using Mask = typename L::Mask;
  const Doubles half = L::splat(0.5), zero = L::splat(0.0), right = L::splat(double(outWidth)),
                nothing = L::splat(-0.0);
  for (; x + L::kLanes <= width; x += L::kLanes) {
    Doubles px, pw;
    std::memcpy(&px, xs + x, sizeof px);
    std::memcpy(&pw, ws + x, sizeof pw);
    px = L::floor(px + half);
    const Mask lands = ~((pw < zero) | (px < zero) | (px >= right));
    const Mask cells = __builtin_convertvector(lands ? px : zero, Mask);
    const Doubles values = lands ? pw : nothing;
    for (int k = 0; k < L::kLanes; ++k) raiseCell(z[size_t(cells[k])], values[k]);
  }
#endif
  for (; x < width; ++x) {
    if (ws[x] < 0) continue;
    const double px = std::floor(xs[x] + 0.5);
    if (px < 0 || px >= outWidth) continue;
    raiseCell(z[size_t(px)], ws[x]);
  }
}

// Whether the segment between neighbours (x0, a) and (x1, b) adds nothing to their two points: true
// when both have the same inverse depth a (not -0) and lie at most one pixel apart, as neighbours of
// one level do; most segments are such. Every centre c the segment covers then gets a + t * 0 = a
// (t is finite), and c is one of the points' pixels floor(x0 + 0.5), floor(x1 + 0.5), which get a
// too. Positions lie on the 2^-30 grid (snapPosition), and below 2^22 a double's step is at most
// 2^-30, so (x0 <= x1) the covered centres are the whole c in [x0 - 2^-30, x1 + 2^-30]: the 1e-9
// margin is just over one grid step. A c below x0 or above x1 lies within a step of it and is that
// point's pixel; a c between them is the first point's when c - x0 <= 0.5 and else the second's,
// as x1 - c < 0.5. Clipping to the row and coveredRange's early returns only take centres away, and
// a point inside the row always lands. (-0 is left out: -0 + t * 0 can be +0, a larger value.)
inline bool addsNothing(double x0, double x1, double a, double b) {
  int64_t bitsA, bitsB;
  std::memcpy(&bitsA, &a, sizeof bitsA);
  std::memcpy(&bitsB, &b, sizeof bitsB);
  // Bitwise operators: one test of the whole condition, no branch per term.
  return (bitsA == bitsB) & (bitsA >= 0) & (std::fabs(x1 - x0) <= 1.0) & (std::fabs(x0) < 4194304.0);
}

// Two doubles, and two 64-bit integers, in one register (GCC's and Clang's vector extensions).
typedef double TwoDoubles __attribute__((vector_size(16)));
typedef int64_t TwoInts __attribute__((vector_size(16)));

// addsNothing for the pairs (x, x + 1) and (x + 1, x + 2) at once, from the row's positions and depths
// at x: all-ones in a lane where it holds. The same operations lane by lane (fabs clears the sign
// bit), in half the instructions.
inline TwoInts addsNothingTwice(const double* xs, const double* ws) {
  TwoDoubles x0, x1;
  TwoInts a, b;
  std::memcpy(&x0, xs, sizeof x0);
  std::memcpy(&x1, xs + 1, sizeof x1);
  std::memcpy(&a, ws, sizeof a);
  std::memcpy(&b, ws + 1, sizeof b);
  const TwoDoubles span = x1 - x0, one = {1.0, 1.0}, limit = {4194304.0, 4194304.0};
  const TwoInts magnitude = {INT64_MAX, INT64_MAX};
  TwoInts spanBits, x0Bits;
  std::memcpy(&spanBits, &span, sizeof spanBits);
  std::memcpy(&x0Bits, &x0, sizeof x0Bits);
  spanBits &= magnitude;
  x0Bits &= magnitude;
  TwoDoubles spanSize, x0Size;
  std::memcpy(&spanSize, &spanBits, sizeof spanSize);
  std::memcpy(&x0Size, &x0Bits, sizeof x0Size);
  return (a == b) & (a >= 0) & (spanSize <= one) & (x0Size < limit);
}


void rowSegments(const double* xs, const double* ws, int width, const uint8_t* nearBoundary, int splatting,
                 double discontinuity, double* z, int outWidth, int* segments) {
  if (splatting == 0) return;
  // Those that add nothing to the points are dropped first in a branch-free pass: the rest, about one
  // in ten on real depth maps, are drawn with the branches of the full test.
  int count = 0, pair = 0;
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
  // Eight pairs at a time: addsNothing's test in lanes (the same comparisons: the bits of the depths
  // as signed integers, the positions' magnitudes as doubles, NaN comparing false), the pairs kept
  // packed in a register (a compress in a register: to memory it is slow on some CPUs) and stored
  // whole: segments[count, count + 8) lies within the row's width ints, as count <= pair and pair + 9
  // <= width.
  {
    const __m512d one = _mm512_set1_pd(1.0), limit = _mm512_set1_pd(4194304.0);
    const __m512i zeroBits = _mm512_setzero_si512();
    const __m256i eight = _mm256_set1_epi32(8);
    __m256i index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (; pair + 9 <= width; pair += 8) {
      const __m512d x0 = _mm512_loadu_pd(xs + pair), x1 = _mm512_loadu_pd(xs + pair + 1);
      const __m512i a = _mm512_loadu_si512(ws + pair), b = _mm512_loadu_si512(ws + pair + 1);
      const __mmask8 nothing = __mmask8(_mm512_cmpeq_epi64_mask(a, b) & _mm512_cmpge_epi64_mask(a, zeroBits) &
                                        _mm512_cmp_pd_mask(_mm512_abs_pd(_mm512_sub_pd(x1, x0)), one, _CMP_LE_OQ) &
                                        _mm512_cmp_pd_mask(_mm512_abs_pd(x0), limit, _CMP_LT_OQ));
      const __mmask8 kept = __mmask8(~nothing);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(segments + count), _mm256_maskz_compress_epi32(kept, index));
      count += __builtin_popcount(unsigned(kept));
      index = _mm256_add_epi32(index, eight);
    }
  }
#endif
  for (; pair + 2 < width; pair += 2) {
    const TwoInts nothing = addsNothingTwice(xs + pair, ws + pair);
    segments[count] = pair;
    count += nothing[0] == 0;
    segments[count] = pair + 1;
    count += nothing[1] == 0;
  }
  for (; pair + 1 < width; ++pair) {
    segments[count] = pair;
    count += !addsNothing(xs[pair], xs[pair + 1], ws[pair], ws[pair + 1]);
  }
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
  // Eight segments at a time: the full test below, coveredRange and the depths along the segments in
  // lanes (the same operations in the same order, NaN comparing as there; the blends are the ternaries
  // and std::min, std::max of the scalar code), each lane's centres in turn, the raises one by one
  // (neighbouring segments share cells; a max does not depend on the order). The zero-masking forms
  // of the intrinsics: GCC 12's plain ones warn, as in Raster.h.
  {
    const __m512d zero = _mm512_setzero_pd(), margin = _mm512_set1_pd(1e-9), below = _mm512_set1_pd(-1e-9);
    const __m512d lastCentre = _mm512_set1_pd(double(outWidth - 1)), beyond = _mm512_set1_pd(outWidth - 1 + 1e-9);
    const __m512d jump = _mm512_set1_pd(discontinuity);
    const __m256i one = _mm256_set1_epi32(1);
    alignas(64) double values[8];
    alignas(32) int cells[8];
    for (int k = 0; k < count; k += 8) {
      const int lanes = count - k < 8 ? count - k : 8;
      const __mmask8 live = __mmask8((1u << lanes) - 1);
      __mmask8 near = live;
      if (splatting != 1) {
        near = 0;
        for (int i = 0; i < lanes; ++i) {
          const int x = segments[k + i];
          near = __mmask8(near | (unsigned((nearBoundary[x] | nearBoundary[x + 1]) != 0) << i));
        }
      }
      const __m256i at = _mm256_maskz_loadu_epi32(live, segments + k);
      const __m512d p0 = _mm512_mask_i32gather_pd(zero, live, at, xs, 8);
      const __m512d p1 = _mm512_mask_i32gather_pd(zero, live, at, xs + 1, 8);
      const __m512d w0 = _mm512_mask_i32gather_pd(zero, live, at, ws, 8);
      const __m512d w1 = _mm512_mask_i32gather_pd(zero, live, at, ws + 1, 8);
      __mmask8 drawn = __mmask8(near & ~(_mm512_cmp_pd_mask(w0, zero, _CMP_LT_OQ) | _mm512_cmp_pd_mask(w1, zero, _CMP_LT_OQ) |
                                         _mm512_cmp_pd_mask(_mm512_abs_pd(_mm512_sub_pd(w0, w1)), jump, _CMP_GT_OQ)));
      const __mmask8 reversed = _mm512_cmp_pd_mask(p1, p0, _CMP_LT_OQ);
      const __m512d x0 = _mm512_mask_blend_pd(reversed, p0, p1), x1 = _mm512_mask_blend_pd(reversed, p1, p0);
      const __m512d a = _mm512_mask_blend_pd(reversed, w0, w1), b = _mm512_mask_blend_pd(reversed, w1, w0);
      // coveredRange(x0, x1, outWidth, first, last)
      drawn = __mmask8(drawn & ~(_mm512_cmp_pd_mask(x1, below, _CMP_LT_OQ) | _mm512_cmp_pd_mask(x0, beyond, _CMP_GT_OQ)));
      const __m512d lo0 = _mm512_sub_pd(x0, margin), hi0 = _mm512_add_pd(x1, margin);
      const __m512d lo = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(lo0, zero, _CMP_LT_OQ), lo0, zero);
      const __m512d hi = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(lastCentre, hi0, _CMP_LT_OQ), hi0, lastCentre);
      __m256i first = _mm512_maskz_cvttpd_epi32(drawn, lo);
      first = _mm256_mask_add_epi32(first, _mm512_cmp_pd_mask(_mm512_maskz_cvtepi32_pd(0xff, first), lo, _CMP_LT_OQ),
                                    first, one);
      const __m256i last = _mm512_maskz_cvttpd_epi32(drawn, hi);
      drawn = __mmask8(drawn & _mm256_cmp_epi32_mask(first, last, _MM_CMPINT_LE));
      if (!drawn) continue;
      const __m512d span = _mm512_sub_pd(x1, x0), slope = _mm512_sub_pd(b, a);
      const __mmask8 spread = _mm512_cmp_pd_mask(span, zero, _CMP_GT_OQ);
      __m256i px = first;
      for (__mmask8 going = drawn; going;) {
        const __m512d t = _mm512_maskz_div_pd(spread, _mm512_sub_pd(_mm512_maskz_cvtepi32_pd(0xff, px), x0), span);
        _mm512_store_pd(values, _mm512_add_pd(a, _mm512_mul_pd(t, slope)));
        _mm256_store_si256(reinterpret_cast<__m256i*>(cells), px);
        for (unsigned m = going; m; m &= m - 1) {
          const int i = __builtin_ctz(m);
          raiseCell(z[cells[i]], values[i]);
        }
        px = _mm256_add_epi32(px, one);
        going = __mmask8(going & _mm256_cmp_epi32_mask(px, last, _MM_CMPINT_LE));
      }
    }
    return;
  }
#endif
  for (int k = 0; k < count; ++k) {
    const int x = segments[k];
    const double w0 = ws[x], w1 = ws[x + 1];
    const bool near = splatting == 1 || nearBoundary[x] || nearBoundary[x + 1];
    if (w0 < 0 || w1 < 0 || std::fabs(w0 - w1) > discontinuity || !near) continue;
    const bool reversed = xs[x + 1] < xs[x];
    const double x0 = reversed ? xs[x + 1] : xs[x], x1 = reversed ? xs[x] : xs[x + 1];
    const double a = reversed ? w1 : w0, b = reversed ? w0 : w1;
    int first, last;
    if (!coveredRange(x0, x1, outWidth, first, last)) continue;
    const double span = x1 - x0;
    for (int px = first; px <= last; ++px) {
      const double t = span > 0 ? (px - x0) / span : 0.0;
      raiseCell(z[px], a + t * (b - a));
    }
  }
}

// floor(x + 0.5) clamped to [0, last]; 0 for NaN.
inline double nearestClamped(double x, double last) {
  const double nearest = floorOf(x + 0.5);
  return nearest >= 0.0 ? (nearest <= last ? nearest : last) : 0.0;
}

void textureLookups(const double* u, const double* v, int n, double precision, int width, int height, double* gridU,
                    double* gridV, double* nearest) {
  const double lastColumn = width - 1, lastRow = height - 1, rowLength = width;
  for (int i = 0; i < n; ++i) {
    gridU[i] = floorOf(u[i] * precision + 0.5);
    gridV[i] = floorOf(v[i] * precision + 0.5);
    nearest[i] = nearestClamped(v[i], lastRow) * rowLength + nearestClamped(u[i], lastColumn);
  }
}

// textureTableRow's rule for sample x: 0 when done (a hole, a failed look-up, a table's), 1 when left to
// the caller, -1 when it lies on the row's own reference row and the tables are not ready (nothing done).
// CHROMA: chromaTableRow's (a low bound of -1, the edge flag edges[x]).
template <bool CHROMA>
inline int textureTableSample(const TextureTableRow& r, int x, bool ready) {
  if (r.depth[x] < 0) return 0;
  const double u = r.u[x], v = r.v[x];
  constexpr double kLow = CHROMA ? -1.0 : -0.5;
  if (!r.ok[x] || u < kLow || v < kLow || u > r.lastU || v > r.lastV) {
    r.depth[x] = kKernelNoDepth;
    return 0;
  }
  const double gridV = CHROMA ? r.gridV[x] : floorOf(v * r.precision + 0.5);
  if (!(gridV == r.rowGrid)) return 1;
  if (!ready) return -1;
  const double g = CHROMA ? r.gridU[x] : floorOf(u * r.precision + 0.5);
  if (!(std::fabs(g) < 4503599627370496.0)) return 1;  // 2^52
  const long long index = (long long)g, ix = index >> r.shift;
  if (ix < r.first || ix > r.last) return 1;
  const long long at = (index & r.mask) * r.stride + (ix - r.first);
  for (int c = 0; c < r.channels; ++c) r.colour[c][x] = r.table[c][at];
  if (CHROMA) {
    r.edgeOut[x] = r.edges[x];
  } else {
    const double width = r.lastU + 0.5, height = r.lastV + 0.5;
    const double nearest = nearestClamped(v, height - 1) * width + nearestClamped(u, width - 1);
    r.edgeOut[x] = r.edges[size_t((long long)nearest)];
  }
  return 0;
}

template <bool CHROMA>
int tableRow(const TextureTableRow& r, int from, int width, bool ready, int* rest, int& count) {
  int x = from;
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
  // Eight samples at a time: the rule's tests as lane masks, the table reads as gathers, the colours
  // and failed depths as masked stores; the edge flags and the samples left over one by one. (The
  // zero-masking forms of the intrinsics: GCC 12's plain ones warn, as in Raster.h.)
  const __m512d zero = _mm512_setzero_pd(), low = _mm512_set1_pd(CHROMA ? -1.0 : -0.5), lastU = _mm512_set1_pd(r.lastU),
                lastV = _mm512_set1_pd(r.lastV), rowGrid = _mm512_set1_pd(r.rowGrid),
                limit = _mm512_set1_pd(4503599627370496.0), noDepth = _mm512_set1_pd(kKernelNoDepth);
  const __m512i first = _mm512_set1_epi64(r.first), last = _mm512_set1_epi64(r.last),
                stride = _mm512_set1_epi64(r.stride), mask = _mm512_set1_epi64(r.mask);
  const __m128i shift = _mm_cvtsi32_si128(r.shift);
  const __m512d half = _mm512_set1_pd(0.5), precision = _mm512_set1_pd(r.precision),
                rowLength = _mm512_set1_pd(r.lastU + 0.5), lastColumn = _mm512_set1_pd(r.lastU - 0.5),
                lastRow = _mm512_set1_pd(r.lastV - 0.5);
  constexpr int kFloor = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
  // Locals: a byte store could alias the row's fields, which would then be loaded again per flag.
  const uint8_t* const edges = r.edges;
  uint8_t* const edgeOut = r.edgeOut;
#if defined(__AVX512BW__)
  const __m512i three = _mm512_set1_epi64(3);
  const __m256i lowByte = _mm256_set1_epi32(0xff);
  const bool wordGathers = (r.lastU + 0.5) * (r.lastV + 0.5) >= 4.0;  // a picture of four samples or more
#endif
  for (; x + 8 <= width; x += 8) {
    const __mmask8 live = _mm512_cmp_pd_mask(_mm512_loadu_pd(r.depth + x), zero, _CMP_NLT_UQ);  // !(d < 0)
    if (!live) continue;
    const __m512d u = _mm512_loadu_pd(r.u + x), v = _mm512_loadu_pd(r.v + x);
    __m128i okBytes;
    std::memcpy(&okBytes, r.ok + x, 8);  // the low eight bytes
    const __m512i okLanes = _mm512_maskz_cvtepu8_epi64(0xff, okBytes);
    const __mmask8 fails = __mmask8(~_mm512_test_epi64_mask(okLanes, okLanes) | _mm512_cmp_pd_mask(u, low, _CMP_LT_OQ) |
                                    _mm512_cmp_pd_mask(v, low, _CMP_LT_OQ) |
                                    _mm512_cmp_pd_mask(u, lastU, _CMP_GT_OQ) |
                                    _mm512_cmp_pd_mask(v, lastV, _CMP_GT_OQ));
    const __mmask8 keep = live & __mmask8(~fails);
    // The grid indices: chroma's given, the texture's floor(v * precision + 0.5) and floor(u * precision +
    // 0.5), each operation rounded as the scalar one.
    const __m512d gridV = CHROMA ? _mm512_loadu_pd(r.gridV + x)
                                 : _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_mul_pd(v, precision), half), kFloor);
    const __mmask8 onRow = _mm512_mask_cmp_pd_mask(keep, gridV, rowGrid, _CMP_EQ_OQ);
    if (onRow && !ready) return x;
    _mm512_mask_storeu_pd(r.depth + x, live & fails, noDepth);
    const __m512d g = CHROMA ? _mm512_loadu_pd(r.gridU + x)
                             : _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_mul_pd(u, precision), half), kFloor);
    const __mmask8 small = _mm512_mask_cmp_pd_mask(onRow, _mm512_abs_pd(g), limit, _CMP_LT_OQ);
    const __m512i index = _mm512_maskz_cvttpd_epi64(small, g);
    const __m512i ix = _mm512_maskz_sra_epi64(0xff, index, shift);
    const __mmask8 inTable = _mm512_mask_cmp_epi64_mask(small, ix, first, _MM_CMPINT_NLT) &
                             _mm512_cmp_epi64_mask(ix, last, _MM_CMPINT_LE);
    if (inTable) {
      const __m512i at = _mm512_add_epi64(_mm512_mullo_epi64(_mm512_and_si512(index, mask), stride),
                                          _mm512_sub_epi64(ix, first));
      for (int c = 0; c < r.channels; ++c)
        _mm256_mask_storeu_ps(r.colour[c] + x, inTable,
                              _mm512_mask_i64gather_ps(_mm256_setzero_ps(), inTable, at, r.table[c], 4));
      if (CHROMA) {
#if defined(__AVX512BW__)
        _mm_mask_storeu_epi8(edgeOut + x, inTable, _mm_loadl_epi64(reinterpret_cast<const __m128i*>(edges + x)));
#else
        for (unsigned m = inTable; m; m &= m - 1) edgeOut[x + __builtin_ctz(m)] = edges[x + __builtin_ctz(m)];
#endif
      } else {
        // The nearest reference sample: (clamp(floor(v + 0.5)) * width + clamp(floor(u + 0.5)), exact
        // whole numbers (u and v lie in the picture here).
        const __m512d column = _mm512_maskz_min_pd(
            0xff, _mm512_maskz_max_pd(0xff, _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(u, half), kFloor), zero),
            lastColumn);
        const __m512d row = _mm512_maskz_min_pd(
            0xff, _mm512_maskz_max_pd(0xff, _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(v, half), kFloor), zero),
            lastRow);
        const __m512i nearest =
            _mm512_maskz_cvttpd_epi64(inTable, _mm512_add_pd(_mm512_mul_pd(row, rowLength), column));
#if defined(__AVX512BW__)
        if (wordGathers) {
          // Each flag as a byte of a four-byte gather that stays in the picture: the word at the flag
          // itself, or, from the fourth on, the word ending with it (as rowTableRow).
          const __mmask8 high = _mm512_cmp_epi64_mask(nearest, three, _MM_CMPINT_NLT);
          const __m256i words = _mm512_mask_i64gather_epi32(
              _mm256_setzero_si256(), inTable, _mm512_mask_sub_epi64(nearest, high, nearest, three), edges, 1);
          const __m256i flags = _mm256_and_si256(_mm256_mask_srli_epi32(words, high, words, 24), lowByte);
          _mm_mask_storeu_epi8(edgeOut + x, inTable, _mm256_maskz_cvtepi32_epi8(0xff, flags));
        } else
#endif
        {
          alignas(64) long long at[8];
          _mm512_store_si512(at, nearest);
          for (unsigned m = inTable; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            edgeOut[x + k] = edges[size_t(at[k])];
          }
        }
      }
    }
    for (unsigned m = keep & __mmask8(~inTable); m; m &= m - 1) rest[count++] = x + __builtin_ctz(m);
  }
#endif
  for (; x < width; ++x) {
    const int done = textureTableSample<CHROMA>(r, x, ready);
    if (done < 0) return x;
    if (done) rest[count++] = x;
  }
  return width;
}

int textureTableRow(const TextureTableRow& r, int from, int width, bool ready, int* rest, int& count) {
  return tableRow<false>(r, from, width, ready, rest, count);
}

int chromaTableRow(const TextureTableRow& r, int from, int width, bool ready, int* rest, int& count) {
  return tableRow<true>(r, from, width, ready, rest, count);
}

void rowLookups(const double* u, int n, double precision, int width, double* gridU, double* nearest) {
  const double lastColumn = width - 1;
  for (int i = 0; i < n; ++i) {
    gridU[i] = floorOf(u[i] * precision + 0.5);
    nearest[i] = nearestClamped(u[i], lastColumn);
  }
}

// rowTableRow's rule for sample x: false when its colour is left to the caller. CHROMA:
// chromaRowTableRow's (a low bound of -1, the edge flag edges[x]).
template <bool CHROMA>
inline bool rowTableSample(const RowTableRow& r, int x) {
  if (r.depth[x] < 0) return true;
  const double u = r.u[x];
  constexpr double kLow = CHROMA ? -1.0 : -0.5;
  if (!(u >= kLow && u <= r.lastU)) {  // NaN fails both
    r.depth[x] = kKernelNoDepth;
    return true;
  }
  r.edgeOut[x] = CHROMA ? r.edges[x] : r.edges[size_t(nearestClamped(u, r.lastColumn))];
  const long long index = (long long)floorOf(u * r.precision + 0.5), ix = index >> r.shift;
  if (ix < r.first || ix > r.last) return false;
  const long long at = (index & r.mask) * r.stride + (ix - r.first);
  for (int c = 0; c < r.channels; ++c) r.colour[c][x] = r.table[c][at];
  return true;
}

template <bool CHROMA>
void rowTable(const RowTableRow& r, int width, int* rest, int& count) {
  int x = 0;
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__) && defined(__AVX512BW__)
  // Eight samples at a time: the tests as lane masks, the grid indices and nearest samples in lanes,
  // the tables and the edge flags read by gathers, the colours, flags and failed depths by masked
  // stores. (u in [-0.5, lastU] keeps every index far below 2^52: the conversions are exact.)
  const __m512d zero = _mm512_setzero_pd(), low = _mm512_set1_pd(CHROMA ? -1.0 : -0.5), lastU = _mm512_set1_pd(r.lastU),
                half = _mm512_set1_pd(0.5), precision = _mm512_set1_pd(r.precision),
                lastColumn = _mm512_set1_pd(r.lastColumn), noDepth = _mm512_set1_pd(kKernelNoDepth);
  const __m512i first = _mm512_set1_epi64(r.first), last = _mm512_set1_epi64(r.last),
                stride = _mm512_set1_epi64(r.stride), mask = _mm512_set1_epi64(r.mask);
  const __m128i shift = _mm_cvtsi32_si128(r.shift);
  const __m512i three = _mm512_set1_epi64(3);
  const __m256i lowByte = _mm256_set1_epi32(0xff);
  const bool wordGathers = r.lastColumn >= 3.0;  // a row of four flags or more
  constexpr int kFloor = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
  for (; x + 8 <= width; x += 8) {
    const __mmask8 live = _mm512_cmp_pd_mask(_mm512_loadu_pd(r.depth + x), zero, _CMP_NLT_UQ);  // !(d < 0)
    if (!live) continue;
    const __m512d u = _mm512_loadu_pd(r.u + x);
    const __mmask8 inside = _mm512_cmp_pd_mask(u, low, _CMP_GE_OQ) & _mm512_cmp_pd_mask(u, lastU, _CMP_LE_OQ);
    _mm512_mask_storeu_pd(r.depth + x, live & __mmask8(~inside), noDepth);
    const __mmask8 keep = live & inside;
    if (!keep) continue;
    // floor(u * precision + 0.5) and floor(u + 0.5), each operation rounded as the scalar one.
    const __m512d g = _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_mul_pd(u, precision), half), kFloor);
    const __m512d nearest = _mm512_maskz_min_pd(
        0xff, _mm512_maskz_max_pd(0xff, _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(u, half), kFloor), zero),
        lastColumn);
    const __m512i index = _mm512_maskz_cvttpd_epi64(keep, g);
    const __m512i ix = _mm512_maskz_sra_epi64(0xff, index, shift);
    const __mmask8 inTable = _mm512_mask_cmp_epi64_mask(keep, ix, first, _MM_CMPINT_NLT) &
                             _mm512_cmp_epi64_mask(ix, last, _MM_CMPINT_LE);
    const __m512i at = _mm512_add_epi64(_mm512_mullo_epi64(_mm512_and_si512(index, mask), stride),
                                        _mm512_sub_epi64(ix, first));
    for (int c = 0; c < r.channels; ++c)
      _mm256_mask_storeu_ps(r.colour[c] + x, inTable,
                            _mm512_mask_i64gather_ps(_mm256_setzero_ps(), inTable, at, r.table[c], 4));
    const __m512i near = _mm512_maskz_cvttpd_epi64(keep, nearest);
    if (CHROMA) {
      _mm_mask_storeu_epi8(r.edgeOut + x, keep, _mm_loadl_epi64(reinterpret_cast<const __m128i*>(r.edges + x)));
    } else if (wordGathers) {
      // Each flag as a byte of a four-byte gather that stays in the row: the word at the flag itself,
      // or, from the fourth on, the word ending with it.
      const __mmask8 high = _mm512_cmp_epi64_mask(near, three, _MM_CMPINT_NLT);
      const __m256i words = _mm512_mask_i64gather_epi32(_mm256_setzero_si256(), keep,
                                                        _mm512_mask_sub_epi64(near, high, near, three), r.edges, 1);
      const __m256i flags = _mm256_and_si256(_mm256_mask_srli_epi32(words, high, words, 24), lowByte);
      _mm_mask_storeu_epi8(r.edgeOut + x, keep, _mm256_maskz_cvtepi32_epi8(0xff, flags));
    } else {
      alignas(64) long long at[8];
      _mm512_store_si512(at, near);
      for (unsigned m = keep; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        r.edgeOut[x + k] = r.edges[size_t(at[k])];
      }
    }
    for (unsigned m = keep & __mmask8(~inTable); m; m &= m - 1) rest[count++] = x + __builtin_ctz(m);
  }
#endif
  for (; x < width; ++x)
    if (!rowTableSample<CHROMA>(r, x)) rest[count++] = x;
}

void rowTableRow(const RowTableRow& r, int width, int* rest, int& count) { rowTable<false>(r, width, rest, count); }

void chromaRowTableRow(const RowTableRow& r, int width, int* rest, int& count) {
  rowTable<true>(r, width, rest, count);
}

void chromaGridIndices(double* x, int n, double offset, double block, double precision, double* g) {
  for (int i = 0; i < n; ++i) {
    const double position = (x[i] - offset) / block;
    x[i] = position;
    g[i] = floorOf(position * precision + 0.5);
  }
}

void sampleRowPhase0(const uint16_t* taps, long long count, float* out) {
  for (long long n = 0; n < count; ++n) out[n] = float(taps[n]);
}

void holeCounts(const double* depth, int width, uint8_t* padded, uint8_t* count) {
  for (int x = 0; x < width; ++x) padded[x + 3] = uint8_t(depth[x] < 0);
  for (int x = 0; x < width; ++x)
    count[x] = uint8_t(padded[x] + padded[x + 1] + padded[x + 2] + padded[x + 3] + padded[x + 4] + padded[x + 5] +
                       padded[x + 6]);
}

void windowStep(uint8_t* sum, const uint8_t* entering, const uint8_t* leaving, uint8_t* edge, int width, int most) {
  if (entering)
    for (int x = 0; x < width; ++x) sum[x] = uint8_t(sum[x] + entering[x]);
  if (leaving)
    for (int x = 0; x < width; ++x) sum[x] = uint8_t(sum[x] - leaving[x]);
  if (edge)
    for (int x = 0; x < width; ++x) edge[x] |= uint8_t(sum[x] > most);
}

// One sample's step as referenceSteps states it, in int arithmetic (the row's ends, and any
// `missing` or minStep the 16-bit loop below cannot hold).
inline uint8_t stepAt(int level, int left, int right, int up, int down, int missing, int minStep) {
  auto differs = [=](int other) { return (other == missing) | ((level > other ? level - other : other - level) >= minStep); };
  return uint8_t((level == missing) | differs(left) | differs(right) | differs(up) | differs(down));
}

void referenceSteps(const uint16_t* row, const uint16_t* above, const uint16_t* below, int width, int missing,
                    int minStep, uint8_t* step) {
  if (width <= 0) return;
  step[0] = stepAt(row[0], row[0], row[width > 1 ? 1 : 0], above[0], below[0], missing, minStep);
  if (width == 1) return;
  step[width - 1] = stepAt(row[width - 1], row[width - 2], row[width - 1], above[width - 1], below[width - 1], missing,
                           minStep);
  if (missing >= -1 && missing <= 0xffff && minStep >= 1 && minStep <= 0xffff) {
    // In 16-bit lanes: the distance of two levels as the larger less the smaller (exact), a missing
    // level of -1 as a mask that is never set.
    const uint16_t miss = uint16_t(missing < 0 ? 0 : missing), any = uint16_t(missing < 0 ? 0 : 0xffff);
    const uint16_t least = uint16_t(minStep);
    for (int x = 1; x + 1 < width; ++x) {
      const uint16_t level = row[x];
      auto differs = [=](uint16_t other) {
        const uint16_t distance = uint16_t(level > other ? level - other : other - level);
        return uint16_t((uint16_t(-uint16_t(other == miss)) & any) | uint16_t(-uint16_t(distance >= least)));
      };
      const uint16_t hit = uint16_t((uint16_t(-uint16_t(level == miss)) & any) | differs(row[x - 1]) |
                                    differs(row[x + 1]) | differs(above[x]) | differs(below[x]));
      step[x] = uint8_t(hit & 1);
    }
    return;
  }
  for (int x = 1; x + 1 < width; ++x)
    step[x] = stepAt(row[x], row[x - 1], row[x + 1], above[x], below[x], missing, minStep);
}

void depthEdgePairs(const uint16_t* a, const uint16_t* b, int n, int missing, int minStep, uint8_t* flags) {
  if (missing >= -1 && missing <= 0xffff && minStep >= 1 && minStep <= 0xffff) {
    // In 16-bit lanes, as referenceSteps.
    const uint16_t miss = uint16_t(missing < 0 ? 0 : missing), any = uint16_t(missing < 0 ? 0 : 0xffff);
    const uint16_t least = uint16_t(minStep);
    for (int x = 0; x < n; ++x) {
      const uint16_t p = a[x], q = b[x];
      const uint16_t distance = uint16_t(p > q ? p - q : q - p);
      const uint16_t missingOne = uint16_t((uint16_t(-uint16_t(p == miss)) | uint16_t(-uint16_t(q == miss))) & any);
      flags[x] = uint8_t(uint16_t(~missingOne & uint16_t(-uint16_t(distance >= least))) & 1);
    }
    return;
  }
  for (int x = 0; x < n; ++x) {
    const int p = a[x], q = b[x];
    flags[x] = uint8_t((p != missing) & (q != missing) & ((p > q ? p - q : q - p) >= minStep));
  }
}

void behindFlags(const double* front, const double* behind, int n, double limit, uint8_t* flags) {
  for (int i = 0; i < n; ++i) flags[i] = uint8_t(behind[i] < front[i] - limit);
}

template <int TAPS>
void sampleRowPhase(const uint16_t* taps, const float* kernel, long long count, float* out) {
  float k[TAPS];
  for (int t = 0; t < TAPS; ++t) k[t] = kernel[t];
  for (long long n = 0; n < count; ++n) {
    float sum = 0.0f;
    for (int t = 0; t < TAPS; ++t) sum += k[t] * float(taps[n + t]);
    out[n] = sum;
  }
}

template <int TAPS>
void sampleFloatRowPhase(const float* __restrict taps, const float* kernel, long long count, float* __restrict out) {
  float k[TAPS];
  for (int t = 0; t < TAPS; ++t) k[t] = kernel[t];
  for (long long n = 0; n < count; ++n) {
    float sum = 0.0f;
    for (int t = 0; t < TAPS; ++t) sum += k[t] * taps[n + t];
    out[n] = sum;
  }
}

// The two-view blend (Synth/Blend.cpp's blendViews for two views): its decisions and arithmetic
// unrolled, with selects for its branches (at silhouettes and holes the outcome changes from sample
// to sample, too often for a branch to be predicted), two samples at a time where SSE4.1 is there.
// The sums are blendViews' own, in its order, from the same zeros; a view left out adds +0.0, which
// leaves a sum that starts from +0.0 as it is; the vector instructions round as the scalar ones do
// (IEEE, the same MXCSR), so every bit is the same.
template <int Channels, bool NearestViewOnly>
struct TwoViewBlend {
  TwoViewBlendRows rows;

  // Sample i; true where blendViews finds no bestView (its VS_CHECK).
  bool sample(size_t i) const {
    const TwoViewBlendRows& b = rows;
    const double d0 = b.depth0[i], d1 = b.depth1[i];
    const bool valid0 = d0 >= 0.0, valid1 = d1 >= 0.0;
    const bool hole = !(valid0 | valid1);
    // blendViews' nearest: std::max(-1, d) is d for a valid d, std::max(d0, d1) is d0 < d1 ? d1 : d0.
    const double nearest = valid0 ? (valid1 ? (d0 < d1 ? d1 : d0) : d0) : d1;
    const double gap0 = nearest - d0, gap1 = nearest - d1;
    const bool onEdge0 = b.edge0[i] != 0, onEdge1 = b.edge1[i] != 0;
    const double tolerance = b.tolerance;
    const bool anyClean = (valid0 & (gap0 <= tolerance) & !onEdge0) | (valid1 & (gap1 <= tolerance) & !onEdge1);
    const bool use0 = valid0 & !(gap0 > tolerance) & !(anyClean & onEdge0);
    const bool use1 = valid1 & !(gap1 > tolerance) & !(anyClean & onEdge1);
    const bool takeSecond = use1 & ((use0 & b.pickSecondOfBoth) | (!use0 & b.pickSecondAlone));
    const bool takeFirst = !takeSecond & use0 & b.pickFirstAlone;
    const bool dominantCopy = (b.dominantFirst & valid0) | (b.dominantSecond & valid1);
    const bool copy = NearestViewOnly | dominantCopy;
    const bool fromSecond = dominantCopy ? b.dominantSecond : takeSecond;
    const double weightSum = (0.0 + (use0 ? b.weight0 : 0.0)) + (use1 ? b.weight1 : 0.0);
    const double depthSum = (0.0 + (use0 ? b.weight0 * d0 : 0.0)) + (use1 ? b.weight1 * d1 : 0.0);
    for (int c = 0; c < Channels; ++c) {
      const float x0 = b.colour0[c][i], x1 = b.colour1[c][i];
      const float colourSum = (0.0f + (use0 ? b.floatWeight0 * x0 : 0.0f)) + (use1 ? b.floatWeight1 * x1 : 0.0f);
      b.colourOut[c][i] = hole ? 0.0f : copy ? (fromSecond ? x1 : x0) : float(colourSum / weightSum);
    }
    b.depthOut[i] = hole ? kKernelNoDepth : copy ? (fromSecond ? d1 : d0) : depthSum / weightSum;
    b.holeOut[i] = hole;
    return !(dominantCopy | hole | takeFirst | takeSecond);
  }

#if defined(__SSE4_1__)
  // Samples i and i + 1, as sample() does them, in the two lanes of SSE registers (masks: all ones
  // for true); the lanes where blendViews finds no bestView come back set. Plain: no view has weight
  // 1 and both weights are numbers, so nothing is copied but for NearestViewOnly, and bestView is
  // the heavier of the views used (the first of equal ones), found wherever one is used.
  template <bool Plain>
  __m128d pair(size_t i) const {
    const TwoViewBlendRows& b = rows;
    const __m128d zero = _mm_setzero_pd(), ones = _mm_castsi128_pd(_mm_set1_epi32(-1));
    auto flag = [&](bool f) { return f ? ones : zero; };
    const __m128d d0 = _mm_loadu_pd(b.depth0 + i), d1 = _mm_loadu_pd(b.depth1 + i);
    const __m128d valid0 = _mm_cmpge_pd(d0, zero), valid1 = _mm_cmpge_pd(d1, zero);
    const __m128d hole = _mm_xor_pd(_mm_or_pd(valid0, valid1), ones);
    // sample()'s nearest: with x0 = -1 where the first view is not valid, max(d1, x0), which is
    // d1 > x0 ? d1 : x0, is std::max(d0, d1) where both are valid (-0 included) and the valid one
    // where one is: a d1 not valid (negative, or NaN, which compares false) never wins.
    const __m128d nearest = _mm_max_pd(d1, _mm_blendv_pd(_mm_set1_pd(-1.0), d0, valid0));
    const __m128d gap0 = _mm_sub_pd(nearest, d0), gap1 = _mm_sub_pd(nearest, d1);
    const __m128d surface = _mm_set1_pd(b.tolerance);
    uint16_t edgePair0, edgePair1;
    std::memcpy(&edgePair0, b.edge0 + i, sizeof edgePair0);
    std::memcpy(&edgePair1, b.edge1 + i, sizeof edgePair1);
    const __m128d clean0 = _mm_castsi128_pd(_mm_cmpeq_epi64(_mm_cvtepu8_epi64(_mm_cvtsi32_si128(edgePair0)), _mm_setzero_si128()));
    const __m128d clean1 = _mm_castsi128_pd(_mm_cmpeq_epi64(_mm_cvtepu8_epi64(_mm_cvtsi32_si128(edgePair1)), _mm_setzero_si128()));
    const __m128d anyClean = _mm_or_pd(_mm_and_pd(_mm_and_pd(valid0, _mm_cmple_pd(gap0, surface)), clean0),
                                       _mm_and_pd(_mm_and_pd(valid1, _mm_cmple_pd(gap1, surface)), clean1));
    // use = valid & !(gap > tolerance) & !(anyClean & onEdge)
    const __m128d use0 = _mm_andnot_pd(_mm_andnot_pd(clean0, anyClean), _mm_andnot_pd(_mm_cmpgt_pd(gap0, surface), valid0));
    const __m128d use1 = _mm_andnot_pd(_mm_andnot_pd(clean1, anyClean), _mm_andnot_pd(_mm_cmpgt_pd(gap1, surface), valid1));
    __m128d lost, copy, fromSecond;
    if constexpr (Plain) {
      lost = _mm_andnot_pd(_mm_or_pd(hole, _mm_or_pd(use0, use1)), ones);
      copy = NearestViewOnly ? ones : zero;
      fromSecond = _mm_and_pd(use1, _mm_or_pd(flag(b.pickSecondOfBoth), _mm_andnot_pd(use0, ones)));
    } else {
      const __m128d takeSecond = _mm_and_pd(
          use1, _mm_or_pd(_mm_and_pd(use0, flag(b.pickSecondOfBoth)), _mm_andnot_pd(use0, flag(b.pickSecondAlone))));
      const __m128d takeFirst = _mm_andnot_pd(takeSecond, _mm_and_pd(use0, flag(b.pickFirstAlone)));
      const __m128d dominantCopy =
          _mm_or_pd(_mm_and_pd(flag(b.dominantFirst), valid0), _mm_and_pd(flag(b.dominantSecond), valid1));
      lost = _mm_andnot_pd(_mm_or_pd(_mm_or_pd(dominantCopy, hole), _mm_or_pd(takeFirst, takeSecond)), ones);
      copy = NearestViewOnly ? ones : dominantCopy;
      fromSecond = _mm_blendv_pd(takeSecond, flag(b.dominantSecond), dominantCopy);
    }
    // Plain without NearestViewOnly copies nothing: the selects of copies are left out.
    constexpr bool copies = NearestViewOnly || !Plain, mixes = !NearestViewOnly;
    const __m128d w0 = _mm_set1_pd(b.weight0), w1 = _mm_set1_pd(b.weight1);
    const __m128d weightSum = _mm_add_pd(_mm_add_pd(zero, _mm_and_pd(use0, w0)), _mm_and_pd(use1, w1));
    __m128d depth = zero;
    if (copies) depth = _mm_blendv_pd(d0, d1, fromSecond);
    if (mixes) {
      const __m128d depthSum =
          _mm_add_pd(_mm_add_pd(zero, _mm_and_pd(use0, _mm_mul_pd(w0, d0))), _mm_and_pd(use1, _mm_mul_pd(w1, d1)));
      depth = copies ? _mm_blendv_pd(_mm_div_pd(depthSum, weightSum), depth, copy) : _mm_div_pd(depthSum, weightSum);
    }
    _mm_storeu_pd(b.depthOut + i, _mm_blendv_pd(depth, _mm_set1_pd(kKernelNoDepth), hole));
    // The colours: two floats in the low lanes, with the masks narrowed to 32 bits.
    auto narrow = [](__m128d mask) { return _mm_shuffle_ps(_mm_castpd_ps(mask), _mm_castpd_ps(mask), _MM_SHUFFLE(2, 0, 2, 0)); };
    const __m128 use0f = narrow(use0), use1f = narrow(use1), copyf = narrow(copy), holef = narrow(hole);
    const __m128 fromSecondf = narrow(fromSecond);
    const __m128 fw0 = _mm_set1_ps(b.floatWeight0), fw1 = _mm_set1_ps(b.floatWeight1);
    for (int c = 0; c < Channels; ++c) {
      const __m128 x0 = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(b.colour0[c] + i)));
      const __m128 x1 = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(b.colour1[c] + i)));
      __m128 value = _mm_setzero_ps();
      if (copies) value = _mm_blendv_ps(x0, x1, fromSecondf);
      if (mixes) {
        const __m128 colourSum = _mm_add_ps(_mm_add_ps(_mm_setzero_ps(), _mm_and_ps(use0f, _mm_mul_ps(fw0, x0))),
                                            _mm_and_ps(use1f, _mm_mul_ps(fw1, x1)));
        const __m128 mixed = _mm_cvtpd_ps(_mm_div_pd(_mm_cvtps_pd(colourSum), weightSum));
        value = copies ? _mm_blendv_ps(mixed, value, copyf) : mixed;
      }
      _mm_storel_epi64(reinterpret_cast<__m128i*>(b.colourOut[c] + i), _mm_castps_si128(_mm_andnot_ps(holef, value)));
    }
    const int holes = _mm_movemask_pd(hole);
    b.holeOut[i] = uint8_t(holes & 1);
    b.holeOut[i + 1] = uint8_t(holes >> 1);
    return lost;
  }
#endif

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
  // Samples i to i + 7, as pair() does them, with the masks as bit masks (a set bit for true); the
  // bits where blendViews finds no bestView come back set. The quiet forms of pair()'s comparisons
  // (they differ in the exception flags only, which nothing reads); the zero-masking forms of the
  // intrinsics, as GCC 12 warns of the plain ones' undefined operand.
  template <bool Plain>
  __mmask8 octet(size_t i) const {
    const TwoViewBlendRows& b = rows;
    const __m512d zero = _mm512_setzero_pd();
    auto flag = [](bool f) { return __mmask8(f ? 0xff : 0); };
    const __m512d d0 = _mm512_loadu_pd(b.depth0 + i), d1 = _mm512_loadu_pd(b.depth1 + i);
    const __mmask8 valid0 = _mm512_cmp_pd_mask(d0, zero, _CMP_GE_OQ), valid1 = _mm512_cmp_pd_mask(d1, zero, _CMP_GE_OQ);
    const __mmask8 hole = __mmask8(~(valid0 | valid1));
    // pair()'s nearest: d1 > x0 ? d1 : x0, with x0 = -1 where the first view is not valid.
    const __m512d nearest = _mm512_maskz_max_pd(0xff, d1, _mm512_mask_blend_pd(valid0, _mm512_set1_pd(-1.0), d0));
    const __m512d gap0 = _mm512_sub_pd(nearest, d0), gap1 = _mm512_sub_pd(nearest, d1);
    const __m512d surface = _mm512_set1_pd(b.tolerance);
    const __m128i noEdge = _mm_setzero_si128();
    auto edgeFree = [&](const uint8_t* edge) {
      return __mmask8(_mm_cmpeq_epi8_mask(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(edge + i)), noEdge));
    };
    const __mmask8 clean0 = edgeFree(b.edge0), clean1 = edgeFree(b.edge1);
    const __mmask8 anyClean = __mmask8((valid0 & _mm512_cmp_pd_mask(gap0, surface, _CMP_LE_OQ) & clean0) |
                                       (valid1 & _mm512_cmp_pd_mask(gap1, surface, _CMP_LE_OQ) & clean1));
    // use = valid & !(gap > tolerance) & !(anyClean & onEdge)
    const __mmask8 use0 =
        __mmask8(valid0 & ~_mm512_cmp_pd_mask(gap0, surface, _CMP_GT_OQ) & ~(anyClean & __mmask8(~clean0)));
    const __mmask8 use1 =
        __mmask8(valid1 & ~_mm512_cmp_pd_mask(gap1, surface, _CMP_GT_OQ) & ~(anyClean & __mmask8(~clean1)));
    __mmask8 lost, copy, fromSecond;
    if constexpr (Plain) {
      lost = __mmask8(~(hole | use0 | use1));
      copy = flag(NearestViewOnly);
      fromSecond = __mmask8(use1 & (flag(b.pickSecondOfBoth) | __mmask8(~use0)));
    } else {
      const __mmask8 takeSecond =
          __mmask8(use1 & ((use0 & flag(b.pickSecondOfBoth)) | (__mmask8(~use0) & flag(b.pickSecondAlone))));
      const __mmask8 takeFirst = __mmask8(~takeSecond & use0 & flag(b.pickFirstAlone));
      const __mmask8 dominantCopy = __mmask8((flag(b.dominantFirst) & valid0) | (flag(b.dominantSecond) & valid1));
      lost = __mmask8(~(dominantCopy | hole | takeFirst | takeSecond));
      copy = NearestViewOnly ? flag(true) : dominantCopy;
      fromSecond = __mmask8((dominantCopy & flag(b.dominantSecond)) | (__mmask8(~dominantCopy) & takeSecond));
    }
    constexpr bool copies = NearestViewOnly || !Plain, mixes = !NearestViewOnly;
    const __m512d w0 = _mm512_set1_pd(b.weight0), w1 = _mm512_set1_pd(b.weight1);
    const __m512d weightSum =
        _mm512_add_pd(_mm512_add_pd(zero, _mm512_maskz_mov_pd(use0, w0)), _mm512_maskz_mov_pd(use1, w1));
    __m512d depth = zero;
    if (copies) depth = _mm512_mask_blend_pd(fromSecond, d0, d1);
    if (mixes) {
      const __m512d depthSum = _mm512_add_pd(_mm512_add_pd(zero, _mm512_maskz_mov_pd(use0, _mm512_mul_pd(w0, d0))),
                                             _mm512_maskz_mov_pd(use1, _mm512_mul_pd(w1, d1)));
      const __m512d mixed = _mm512_div_pd(depthSum, weightSum);
      depth = copies ? _mm512_mask_blend_pd(copy, mixed, depth) : mixed;
    }
    _mm512_storeu_pd(b.depthOut + i, _mm512_mask_blend_pd(hole, depth, _mm512_set1_pd(kKernelNoDepth)));
    const __m256 fw0 = _mm256_set1_ps(b.floatWeight0), fw1 = _mm256_set1_ps(b.floatWeight1);
    for (int c = 0; c < Channels; ++c) {
      const __m256 x0 = _mm256_loadu_ps(b.colour0[c] + i), x1 = _mm256_loadu_ps(b.colour1[c] + i);
      __m256 value = _mm256_setzero_ps();
      if (copies) value = _mm256_mask_blend_ps(fromSecond, x0, x1);
      if (mixes) {
        const __m256 colourSum =
            _mm256_add_ps(_mm256_add_ps(_mm256_setzero_ps(), _mm256_maskz_mov_ps(use0, _mm256_mul_ps(fw0, x0))),
                          _mm256_maskz_mov_ps(use1, _mm256_mul_ps(fw1, x1)));
        const __m256 mixed =
            _mm512_maskz_cvtpd_ps(0xff, _mm512_div_pd(_mm512_maskz_cvtps_pd(0xff, colourSum), weightSum));
        value = copies ? _mm256_mask_blend_ps(copy, mixed, value) : mixed;
      }
      _mm256_storeu_ps(b.colourOut[c] + i, _mm256_maskz_mov_ps(__mmask8(~hole), value));
    }
    _mm_storel_epi64(reinterpret_cast<__m128i*>(b.holeOut + i), _mm_maskz_set1_epi8(hole, 1));
    return lost;
  }
#endif
};

template <int Channels, bool NearestViewOnly>
bool blendTwoViews(const TwoViewBlendRows& rows, size_t begin, size_t end) {
  const TwoViewBlend<Channels, NearestViewOnly> local{rows};  // a local: the stores cannot alias it
  size_t i = begin;
  bool lost = false;
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
  __mmask8 lostOctets = 0;
  if (rows.plain)
    for (; i + 8 <= end; i += 8) lostOctets = __mmask8(lostOctets | local.template octet<true>(i));
  else
    for (; i + 8 <= end; i += 8) lostOctets = __mmask8(lostOctets | local.template octet<false>(i));
  lost = lostOctets != 0;
#endif
#if defined(__SSE4_1__)
  __m128d lostPairs = _mm_setzero_pd();
  if (rows.plain)
    for (; i + 2 <= end; i += 2) lostPairs = _mm_or_pd(lostPairs, local.template pair<true>(i));
  else
    for (; i + 2 <= end; i += 2) lostPairs = _mm_or_pd(lostPairs, local.template pair<false>(i));
  lost = lost || _mm_movemask_pd(lostPairs) != 0;
#endif
  for (; i < end; ++i) lost |= local.sample(i);
  return lost;
}

void chromaBlocks(const double* top, const double* bottom, const uint8_t* edgeTop, const uint8_t* edgeBottom, int n,
                  double surface, double* depth, uint8_t* edge) {
  int i = 0;
#if defined(__AVX512F__)
  // Eight blocks at a time (GCC leaves the plain loop scalar): the rule below in lanes, each lane the
  // same operations in the same order; a block's four depths taken apart from two rows of sixteen, its
  // flags from two rows of sixteen bytes as sixteen-bit lanes.
  const __m512i evens = _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14), odds = _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15);
  const __m512d none = _mm512_set1_pd(kKernelNoDepth), zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
  const __m512d limit = _mm512_set1_pd(surface);
  const __m128i lowBytes = _mm_set1_epi16(0xFF);
  for (; i + 8 <= n; i += 8) {
    const __m512d topA = _mm512_loadu_pd(top + 2 * i), topB = _mm512_loadu_pd(top + 2 * i + 8);
    const __m512d bottomA = _mm512_loadu_pd(bottom + 2 * i), bottomB = _mm512_loadu_pd(bottom + 2 * i + 8);
    const __m512d d[4] = {_mm512_permutex2var_pd(topA, evens, topB), _mm512_permutex2var_pd(topA, odds, topB),
                          _mm512_permutex2var_pd(bottomA, evens, bottomB), _mm512_permutex2var_pd(bottomA, odds, bottomB)};
    __m512d front = none;
    for (int k = 0; k < 4; ++k) front = _mm512_mask_mov_pd(front, _mm512_cmp_pd_mask(front, d[k], _CMP_LT_OQ), d[k]);
    const __m128i flagsTop = _mm_loadu_si128(reinterpret_cast<const __m128i*>(edgeTop + 2 * i));
    const __m128i flagsBottom = _mm_loadu_si128(reinterpret_cast<const __m128i*>(edgeBottom + 2 * i));
    const __m128i e[4] = {_mm_and_si128(flagsTop, lowBytes), _mm_srli_epi16(flagsTop, 8),
                          _mm_and_si128(flagsBottom, lowBytes), _mm_srli_epi16(flagsBottom, 8)};
    __m512d sum = zero, count = zero;
    __m128i flags = _mm_setzero_si128();
    for (int k = 0; k < 4; ++k) {
      const __mmask8 on = _mm512_mask_cmp_pd_mask(_mm512_cmp_pd_mask(d[k], zero, _CMP_GE_OQ),
                                                  _mm512_sub_pd(front, d[k]), limit, _CMP_LE_OQ);
      sum = _mm512_add_pd(sum, _mm512_maskz_mov_pd(on, d[k]));
      count = _mm512_add_pd(count, _mm512_maskz_mov_pd(on, one));  // a whole number: as the int count
      flags = _mm_or_si128(flags, _mm_maskz_mov_epi16(on, e[k]));
    }
    // max(count, 1) as a blend (GCC 12 warns of _mm512_max_pd's undefined operand).
    const __m512d divisor = _mm512_mask_mov_pd(count, _mm512_cmp_pd_mask(count, one, _CMP_LT_OQ), one);
    const __m512d mean = _mm512_div_pd(sum, divisor);
    _mm512_storeu_pd(depth + i, _mm512_mask_mov_pd(mean, _mm512_cmp_pd_mask(front, zero, _CMP_LT_OQ), none));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(edge + i), _mm_packus_epi16(flags, flags));
  }
#endif
  for (; i < n; ++i) {
    const double d0 = top[2 * i], d1 = top[2 * i + 1], d2 = bottom[2 * i], d3 = bottom[2 * i + 1];
    double front = kKernelNoDepth;
    front = front < d0 ? d0 : front;
    front = front < d1 ? d1 : front;
    front = front < d2 ? d2 : front;
    front = front < d3 ? d3 : front;
    const bool on0 = d0 >= 0 && front - d0 <= surface, on1 = d1 >= 0 && front - d1 <= surface;
    const bool on2 = d2 >= 0 && front - d2 <= surface, on3 = d3 >= 0 && front - d3 <= surface;
    double sum = 0.0;
    sum += on0 ? d0 : 0.0;
    sum += on1 ? d1 : 0.0;
    sum += on2 ? d2 : 0.0;
    sum += on3 ? d3 : 0.0;
    const int count = int(on0) + int(on1) + int(on2) + int(on3);
    depth[i] = front < 0 ? kKernelNoDepth : sum / double(count > 1 ? count : 1);
    // The flags read whether or not their sample is on the front (no branch), then masked.
    const uint8_t e0 = edgeTop[2 * i], e1 = edgeTop[2 * i + 1], e2 = edgeBottom[2 * i], e3 = edgeBottom[2 * i + 1];
    edge[i] = uint8_t((e0 & -uint8_t(on0)) | (e1 & -uint8_t(on1)) | (e2 & -uint8_t(on2)) | (e3 & -uint8_t(on3)));
  }
}

void isolatedSamples(const double* row, int width, uint8_t* isolated) {
  for (int x = 1; x + 1 < width; ++x) isolated[x] = uint8_t((row[x] >= 0) & (row[x - 1] < 0) & (row[x + 1] < 0));
}

// Whether some byte of the eight is 0 or 1 (a candidate of the occlusion rule): some byte of eight &
// 0xFE..FE is zero (the exact zero-byte test: a borrow reaches the top bit of a byte only past a
// zero byte below it, which then is found first).
inline bool anyCandidate(const uint8_t* eightBytes) {
  uint64_t eight;
  std::memcpy(&eight, eightBytes, sizeof eight);
  const uint64_t high = eight & 0xFEFEFEFEFEFEFEFEull;
  return ((high - 0x0101010101010101ull) & ~high & 0x8080808080808080ull) != 0;
}

// __restrict: the rows, the lasts and the up samples are distinct arrays, which GCC would otherwise
// have to check at run time, pair by pair, before it vectorises.
int occlusionDown(const double* __restrict row0, const double* __restrict row1, uint8_t first, uint8_t second,
                  uint8_t none, uint8_t* __restrict sole, double* __restrict last0, double* __restrict last1,
                  double* __restrict up, int n) {
  int count = 0, x = 0;
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__)
  // Eight samples at a time, all in one pass: the candidates as bit masks and their bytes, the
  // candidates' samples above packed in a register (a compress to memory is slow on some CPUs) and
  // stored whole (up[count, count + 8) lies in up[0, n), as count <= x), the lasts as blends.
  {
    const __m512d zero = _mm512_setzero_pd();
    const __m128i firstBytes = _mm_set1_epi8(char(first)), secondBytes = _mm_set1_epi8(char(second));
    const __m128i noneBytes = _mm_set1_epi8(char(none)), ones = _mm_set1_epi8(1);
    for (; x + 8 <= n; x += 8) {
      const __m512d value0 = _mm512_loadu_pd(row0 + x), value1 = _mm512_loadu_pd(row1 + x);
      const __mmask8 valid0 = _mm512_cmp_pd_mask(value0, zero, _CMP_GE_OQ);
      const __mmask8 valid1 = _mm512_cmp_pd_mask(value1, zero, _CMP_GE_OQ);
      const __mmask16 only0 = __mmask16(valid0 & ~valid1), only1 = __mmask16(valid1 & ~valid0);
      const __m128i bytes = _mm_mask_mov_epi8(_mm_mask_mov_epi8(noneBytes, only0, firstBytes), only1, secondBytes);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(sole + x), bytes);
      const __m512d below0 = _mm512_loadu_pd(last0 + x), below1 = _mm512_loadu_pd(last1 + x);
      const __mmask8 candidates = __mmask8(_mm_cmple_epu8_mask(bytes, ones));
      if (candidates) {
        const __mmask8 ofSecond = __mmask8(_mm_cmpeq_epi8_mask(bytes, ones));
        const __m512d above = _mm512_mask_blend_pd(ofSecond, below1, below0);
        _mm512_storeu_pd(up + count, _mm512_maskz_compress_pd(candidates, above));
        count += __builtin_popcount(unsigned(candidates));
      }
      _mm512_storeu_pd(last0 + x, _mm512_mask_blend_pd(valid0, below0, value0));
      _mm512_storeu_pd(last1 + x, _mm512_mask_blend_pd(valid1, below1, value1));
    }
  }
#endif
  // The candidates (byte masks instead of branches) and the lasts, in a loop that vectorises.
  for (int i = x; i < n; ++i) {
    const double value0 = row0[i], value1 = row1[i];
    const uint8_t valid0 = uint8_t(value0 >= 0.0), valid1 = uint8_t(value1 >= 0.0);
    const uint8_t only0 = uint8_t(-uint8_t(valid0 & (valid1 ^ 1))), only1 = uint8_t(-uint8_t(valid1 & (valid0 ^ 1)));
    sole[i] = uint8_t((first & only0) | (second & only1) | (none & uint8_t(~(only0 | only1))));
    last0[i] = valid0 ? value0 : last0[i];
    last1[i] = valid1 ? value1 : last1[i];
  }
  // Then the candidates' samples above, packed. A candidate of view k lies in a hole of the other
  // view, whose last the loop above left as it was: it is read after the loop. Candidates are few:
  // eight flags are tested at once.
  auto pack = [&](int at) {
    const uint8_t k = sole[at];
    if (k > 1) return;
    up[count++] = k == 1 ? last0[at] : last1[at];
  };
  for (; x + 8 <= n; x += 8)
    if (anyCandidate(sole + x))
      for (int k = 0; k < 8; ++k) pack(x + k);
  for (; x < n; ++x) pack(x);
  return count;
}

int occlusionUp(const uint8_t* __restrict sole, double* __restrict row0, double* __restrict row1,
                double* __restrict last0, double* __restrict last1, const double* __restrict upEnd,
                const double* __restrict around, double steps, int n, double* __restrict aboveRow) {
  const double* next = upEnd;
  int end = n;  // samples [end, n) are done
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__)
  // Eight samples at a time from the row's end, the rule in lanes (the same comparisons, NaN comparing
  // as in the plain loop below): the candidates' samples above taken from the packed list with an
  // expanding load, around read at the candidates only (a masked load: its pages are touched there
  // only), the drops as masked stores.
  {
    const __m512d zero = _mm512_setzero_pd(), none = _mm512_set1_pd(HUGE_VAL), hole = _mm512_set1_pd(kKernelNoDepth);
    const __m512d margin = _mm512_set1_pd(steps);
    const __m128i ones = _mm_set1_epi8(1);
    for (; end >= 8; end -= 8) {
      const int x = end - 8;
      const __m128i bytes = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(sole + x));
      const __mmask8 candidates = __mmask8(_mm_cmple_epu8_mask(bytes, ones));
      const __mmask8 ofSecond = __mmask8(_mm_cmpeq_epi8_mask(bytes, ones));
      const __m512d below0 = _mm512_loadu_pd(last0 + x), below1 = _mm512_loadu_pd(last1 + x);
      const __m512d value0 = _mm512_loadu_pd(row0 + x), value1 = _mm512_loadu_pd(row1 + x);
      _mm512_storeu_pd(last0 + x, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(value0, zero, _CMP_GE_OQ), below0, value0));
      _mm512_storeu_pd(last1 + x, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(value1, zero, _CMP_GE_OQ), below1, value1));
      if (!candidates) continue;
      next -= __builtin_popcount(unsigned(candidates));
      const __m512d above = _mm512_maskz_expandloadu_pd(candidates, next);
      const __m512d below = _mm512_mask_blend_pd(ofSecond, below1, below0);
      const __m512d own = _mm512_mask_blend_pd(ofSecond, value0, value1);
      __m512d farthest = _mm512_mask_loadu_pd(none, candidates, around + x);
      const __m512d nearer = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(above, below, _CMP_LT_OQ), below, above);
      const __m512d lowered = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(nearer, farthest, _CMP_LT_OQ), farthest, nearer);
      const __mmask8 bothValid = __mmask8(_mm512_cmp_pd_mask(below, zero, _CMP_GE_OQ) &
                                          _mm512_cmp_pd_mask(above, zero, _CMP_GE_OQ));
      farthest = _mm512_mask_blend_pd(bothValid, farthest, lowered);
      const __mmask8 drop =
          __mmask8(candidates & _mm512_cmp_pd_mask(farthest, none, _CMP_NEQ_UQ) &
                   _mm512_cmp_pd_mask(own, _mm512_sub_pd(farthest, margin), _CMP_LT_OQ));
      _mm512_mask_storeu_pd(row0 + x, __mmask8(drop & ~ofSecond), hole);
      _mm512_mask_storeu_pd(row1 + x, __mmask8(drop & ofSecond), hole);
    }
  }
#endif
  // The rest of the row's packed samples above laid out at their candidates' columns, from the
  // right; eight flags tested at once.
  auto unpack = [&](int at) {
    if (sole[at] <= 1) aboveRow[at] = *--next;
  };
  int x = end;
  for (; x >= 8; x -= 8)
    if (anyCandidate(sole + x - 8))
      for (int k = 1; k <= 8; ++k) unpack(x - k);
  for (; x > 0; --x) unpack(x - 1);
  // Every sample decided without a branch. (aboveRow is read at every sample: its values are used at
  // the candidates only.)
  for (x = 0; x < end; ++x) {
    const double below0 = last0[x], below1 = last1[x];
    const double value0 = row0[x], value1 = row1[x];
    last0[x] = value0 >= 0.0 ? value0 : below0;
    last1[x] = value1 >= 0.0 ? value1 : below1;
    const uint8_t k = sole[x];
    const bool second = k == 1;
    const double below = second ? below0 : below1, own = second ? value1 : value0, above = aboveRow[x];
    double farthest = k <= 1 ? around[x] : HUGE_VAL;  // read at the candidates only (its pages are touched there)
    const double nearer = above < below ? above : below;           // std::min(below, above)
    const double lowered = nearer < farthest ? nearer : farthest;  // std::min(farthest, nearer)
    farthest = (below >= 0.0) & (above >= 0.0) ? lowered : farthest;
    const bool drop = (k <= 1) & (farthest != HUGE_VAL) & (own < farthest - steps);
    // Stored where dropped only (masked stores where vectorised): the rows are not written back.
    if (drop & !second) row0[x] = kKernelNoDepth;
    if (drop & second) row1[x] = kKernelNoDepth;
  }
  return int(upEnd - next);
}

}  // namespace

extern const RowKernels rowKernelsOfLevel;
const RowKernels rowKernelsOfLevel = {forwardRow,
                                      backwardRow,
                                      rowSources,
                                      rowTargets,
                                      rowPoints,
                                      rowSegments,
                                      textureLookups,
                                      textureTableRow,
                                      rowLookups,
                                      chromaGridIndices,
                                      sampleRowPhase0,
                                      sampleRowPhase<2>,
                                      sampleRowPhase<4>,
                                      sampleRowPhase<6>,
                                      sampleFloatRowPhase<2>,
                                      sampleFloatRowPhase<4>,
                                      sampleFloatRowPhase<6>,
                                      holeCounts,
                                      windowStep,
                                      referenceSteps,
                                      depthEdgePairs,
                                      behindFlags,
                                      {{blendTwoViews<1, false>, blendTwoViews<1, true>},
                                       {blendTwoViews<2, false>, blendTwoViews<2, true>},
                                       {blendTwoViews<3, false>, blendTwoViews<3, true>}},
                                      chromaBlocks,
                                      chromaTableRow,
                                      isolatedSamples,
                                      occlusionDown,
                                      occlusionUp,
                                      rowTableRow,
                                      chromaRowTableRow,
                                      VS_KERNEL_LEVEL};

}  // namespace VS_LEVEL_NS
}  // namespace vs
