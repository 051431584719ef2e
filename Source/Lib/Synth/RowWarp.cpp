#include "Synth/RowWarp.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "Synth/Kernels/Rows.h"
#include "Synth/Layer.h"
#include "Synth/Raster.h"

namespace vs {

static_assert(kKernelNoDepth == kNoDepth, "the row kernels' hole is the layers' hole");

namespace {

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

}  // namespace

RowDepthWarp::RowDepthWarp(const ViewProjection& projection, const std::vector<double>& levelToRowDepth,
                           double discontinuity, int splatting)
    : projection_(projection), discontinuity_(discontinuity), splatting_(splatting) {
  levels_.reserve(2 * (levelToRowDepth.size() + 1));
  for (double depth : levelToRowDepth) {
    levels_.push_back(std::isnan(depth) ? depth : projection.rowDisplacement(depth));
    levels_.push_back(std::isnan(depth) ? kNoDepth : depth);
  }
  levels_.push_back(std::nan(""));
  levels_.push_back(kNoDepth);
}

void RowDepthWarp::warp(const uint16_t* levels, int width, const uint8_t* nearBoundary, double* z, int outWidth,
                        Scratch& scratch) const {
  // Locals for everything the loops read: their stores (doubles) could alias members.
  const double discontinuity = discontinuity_;
  const int splatting = splatting_;
  // One row's positions and depths, and the segments left to draw, kept by the caller between rows.
  std::vector<double>& xsRow = scratch.xs;
  std::vector<double>& wsRow = scratch.ws;
  std::vector<int>& segmentsRow = scratch.segments;
  xsRow.resize(size_t(width));
  wsRow.resize(size_t(width));
  double* xs = xsRow.data();
  double* ws = wsRow.data();
  // The level's displacement is rowTarget's second term: this is rowTarget(x, depth), bit for bit; a
  // level that is not warped has a NaN displacement, so its position is not finite either. A loop
  // compiled for the CPU's x86-64 level (Synth/Kernels/Rows.h).
  rowKernels().rowTargets(levels, width, levels_.data(), levels_.size() / 2 - 1, projection_.rowScale(),
                          projection_.rowOffset(), xs, ws);
  // Every sample lands as a point, so thin foreground keeps its width (raiseCell at its nearest pixel
  // centre, in the kernel).
  rowKernels().rowPoints(xs, ws, width, z, outWidth);
  if (splatting == 0) return;
  // The segments between horizontal neighbours on one surface (within BoundaryGrowth samples of a
  // reference depth edge with SplattingOption 2), rasterised at the pixel centres they cover. Those
  // that add nothing to the points are dropped first in a branch-free pass: the rest, about one in
  // ten on real depth maps, are drawn with the branches of the full test.
  segmentsRow.resize(size_t(width));
  int* segments = segmentsRow.data();
  int count = 0, pair = 0;
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
  for (int k = 0; k < count; ++k) {
    const int x = segments[k];
    const double w0 = ws[x], w1 = ws[x + 1];
    const bool near = splatting == 1 || nearBoundary[x] || nearBoundary[x + 1];
    if (w0 < 0 || w1 < 0 || std::fabs(w0 - w1) > discontinuity || !near) continue;
    double x0 = xs[x], x1 = xs[x + 1], a = w0, b = w1;
    if (x1 < x0) {
      std::swap(x0, x1);
      std::swap(a, b);
    }
    int first, last;
    if (!coveredRange(x0, x1, outWidth, first, last)) continue;
    const double span = x1 - x0;
    for (int px = first; px <= last; ++px) {
      const double t = span > 0 ? (px - x0) / span : 0.0;
      raiseCell(z[px], a + t * (b - a));
    }
  }
}

}  // namespace vs
