#pragma once
// The general depth warp's rasteriser (rasteriseQuadRow, Synth/Raster.h) and its points compiled for each x86-64
// level the binary has (QuadRow.cpp, once per level) and chosen at start by the CPU (x86Level(),
// Common/CpuLevel.h). Plain functions on plain pointers: nothing of one level's code crosses into
// another's. Every level raises the same cells with the same values.
#include <atomic>
#include <cstdint>

namespace vs {

struct QuadRowKernels {
  // rasteriseQuadRow into a z-buffer of doubles that one thread writes (LoneRaise) ...
  void (*lone)(double* cells, int width, int outWidth, int outHeight, double discontinuity, const double* xTop,
               const double* yTop, const double* wTop, const double* xBottom, const double* yBottom,
               const double* wBottom);
  // ... or that threads raise at once (AtomicMaxBuffer::cells(), AtomicRaise).
  void (*atomic)(std::atomic<int64_t>* cells, int width, int outWidth, int outHeight, double discontinuity,
                 const double* xTop, const double* yTop, const double* wTop, const double* xBottom,
                 const double* yBottom, const double* wBottom);
  // A row of warped samples (x, y, w) raised as points, each at its nearest pixel centre (floor(x +
  // 0.5), floor(y + 0.5)) where w >= 0 and that centre lies in the outWidth x outHeight view: into
  // one thread's z-buffer (LoneRaise) or the threads' (AtomicRaise).
  void (*pointsLone)(double* cells, int width, int outWidth, int outHeight, const double* x, const double* y,
                     const double* w);
  void (*pointsAtomic)(std::atomic<int64_t>* cells, int width, int outWidth, int outHeight, const double* x,
                       const double* y, const double* w);
  int level;  // the x86-64 level they are compiled for (0: not x86-64)
};

// The kernels for x86Level().
const QuadRowKernels& quadRowKernels();
// The kernels compiled for `level`; nullptr when this binary has none for it (tests compare levels).
const QuadRowKernels* quadRowKernelsFor(int level);

}  // namespace vs
