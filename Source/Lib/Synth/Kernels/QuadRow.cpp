// Compiled once per x86-64 level (Source/Lib/Synth/area.cmake): -march=x86-64[-vN], VS_LEVEL_NS=vN,
// VS_KERNEL_LEVEL=N. Only Raster.h (whose code then lies in vs::vN) and standard headers are included:
// no inline function of a shared header is compiled here at a level another file could pick up.
#include "Synth/Kernels/QuadRow.h"

#include "Synth/Raster.h"

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

template <class Raise>
void raisePoints(const Raise& raise, int width, int outWidth, int outHeight, const double* xs, const double* ys,
                 const double* ws) {
  for (int x = 0; x < width; ++x) {
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
