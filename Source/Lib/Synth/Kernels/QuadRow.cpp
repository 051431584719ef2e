// Compiled once per x86-64 level (Source/Lib/Synth/area.cmake): -march=x86-64[-vN], VS_LEVEL_NS=vN,
// VS_KERNEL_LEVEL=N. Only Raster.h (whose code then lies in vs::vN) and standard headers are included:
// no inline function of a shared header is compiled here at a level another file could pick up.
#include "Synth/Kernels/QuadRow.h"

#include "Synth/Raster.h"

#include <cmath>
#include <type_traits>

#if !defined(VS_LEVEL_NS) || !defined(VS_KERNEL_LEVEL)
#error "compile QuadRow.cpp with VS_LEVEL_NS and VS_KERNEL_LEVEL (Source/Lib/Synth/area.cmake)"
#endif

namespace vs {
inline namespace VS_LEVEL_NS {

namespace {

void lone(double* cells, int width, int outWidth, int outHeight, double discontinuity, const double* xTop,
          const double* yTop, const double* wTop, const double* xBottom, const double* yBottom, const double* wBottom) {
  rasteriseQuadRow(LoneRaise{cells}, width, outWidth, outHeight, discontinuity, xTop, yTop, wTop, xBottom, yBottom,
                   wBottom);
}

void atomic(std::atomic<int64_t>* cells, int width, int outWidth, int outHeight, double discontinuity,
            const double* xTop, const double* yTop, const double* wTop, const double* xBottom, const double* yBottom,
            const double* wBottom) {
  rasteriseQuadRow(AtomicRaise{cells}, width, outWidth, outHeight, discontinuity, xTop, yTop, wTop, xBottom, yBottom,
                   wBottom);
}

// The points of a row: each warped sample (w >= 0, NaN included, as the scalar test reads it) raises
// the cell of its nearest pixel centre, floor(x + 0.5), floor(y + 0.5), where that lies in the view.
// Where the build has vector lanes, a register of samples at a time: their centres, whether each
// lands and their cells in lanes (the same double operations per lane; the cell, a whole number
// below 2^53, is exact as a double), then every lane raised without a branch, one that does not land
// with -0 at cell 0, the least value in the z-buffer's order, which changes nothing.
template <class Raise>
void raisePoints(const Raise& raise, int width, int outWidth, int outHeight, const double* xs, const double* ys,
                 const double* ws) {
  int x = 0;
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  if constexpr (std::is_same<Raise, LoneRaise>::value) {
    // One writer: where all eight samples land on eight consecutive cells, raiseConsecutiveCells
    // (Raster.h); otherwise the samples that land are raised one by one. (The zero-masking forms of the
    // intrinsics: GCC 12's plain ones warn.)
    const __m512d half = _mm512_set1_pd(0.5), zero = _mm512_setzero_pd(), right = _mm512_set1_pd(double(outWidth)),
                  bottom = _mm512_set1_pd(double(outHeight));
    constexpr int kFloor = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
    for (; x + 8 <= width; x += 8) {
      const __m512d pw = _mm512_loadu_pd(ws + x);
      const __m512d px = _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_loadu_pd(xs + x), half), kFloor);
      const __m512d py = _mm512_maskz_roundscale_pd(0xff, _mm512_add_pd(_mm512_loadu_pd(ys + x), half), kFloor);
      const __mmask8 lands = __mmask8(~(_mm512_cmp_pd_mask(pw, zero, _CMP_LT_OQ) |
                                        _mm512_cmp_pd_mask(px, zero, _CMP_LT_OQ) |
                                        _mm512_cmp_pd_mask(py, zero, _CMP_LT_OQ) |
                                        _mm512_cmp_pd_mask(px, right, _CMP_GE_OQ) |
                                        _mm512_cmp_pd_mask(py, bottom, _CMP_GE_OQ)));
      const __m512d cellValues = _mm512_add_pd(_mm512_mul_pd(py, right), px);  // whole numbers below 2^53: exact
      if (lands == 0xff &&
          raiseConsecutiveCells(raise.cells, cellValues,
                                (long long)(std::floor(ys[x] + 0.5) * double(outWidth) + std::floor(xs[x] + 0.5)), pw))
        continue;
      alignas(64) double cellAt[8];
      _mm512_store_pd(cellAt, cellValues);
      for (unsigned m = lands; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        raise(size_t(cellAt[k]), ws[x + k]);
      }
    }
  }
#endif
#if defined(__SSE4_1__)
  using L = QuadLanes<kQuadsAtOnce>;
  using Doubles = typename L::Doubles;
  using Mask = typename L::Mask;
  const Doubles half = L::splat(0.5), zero = L::splat(0.0), right = L::splat(double(outWidth)),
                bottom = L::splat(double(outHeight)), nothing = L::splat(-0.0);
  for (; x + L::kLanes <= width; x += L::kLanes) {
    Doubles px, py, pw;
    std::memcpy(&px, xs + x, sizeof px);
    std::memcpy(&py, ys + x, sizeof py);
    std::memcpy(&pw, ws + x, sizeof pw);
    px = L::floor(px + half);
    py = L::floor(py + half);
    const Mask lands = ~((pw < zero) | (px < zero) | (py < zero) | (px >= right) | (py >= bottom));
    const Mask cells = __builtin_convertvector(lands ? py * right + px : zero, Mask);
    const Doubles values = lands ? pw : nothing;
    for (int k = 0; k < L::kLanes; ++k) raise(size_t(cells[k]), values[k]);
  }
#endif
  for (; x < width; ++x) {
    if (ws[x] < 0) continue;
    const double px = std::floor(xs[x] + 0.5), py = std::floor(ys[x] + 0.5);
    if (px < 0 || py < 0 || px >= outWidth || py >= outHeight) continue;
    raise(size_t(py) * outWidth + size_t(px), ws[x]);
  }
}

void pointsLone(double* cells, int width, int outWidth, int outHeight, const double* x, const double* y,
                const double* w) {
  raisePoints(LoneRaise{cells}, width, outWidth, outHeight, x, y, w);
}

void pointsAtomic(std::atomic<int64_t>* cells, int width, int outWidth, int outHeight, const double* x,
                  const double* y, const double* w) {
  raisePoints(AtomicRaise{cells}, width, outWidth, outHeight, x, y, w);
}

}  // namespace

extern const QuadRowKernels quadRowKernelsOfLevel;
const QuadRowKernels quadRowKernelsOfLevel = {lone, atomic, pointsLone, pointsAtomic, VS_KERNEL_LEVEL};

}  // namespace VS_LEVEL_NS
}  // namespace vs
