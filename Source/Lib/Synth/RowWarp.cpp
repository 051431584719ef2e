#include "Synth/RowWarp.h"

#include <algorithm>
#include <cmath>

#include "Synth/Kernels/Rows.h"
#include "Synth/Layer.h"

namespace vs {

static_assert(kKernelNoDepth == kNoDepth, "the row kernels' hole is the layers' hole");

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
  // reference depth edge with SplattingOption 2), rasterised at the pixel centres they cover, in the
  // kernel.
  std::vector<int>& segmentsRow = scratch.segments;
  segmentsRow.resize(size_t(width));
  rowKernels().rowSegments(xs, ws, width, nearBoundary, splatting, discontinuity, z, outWidth, segmentsRow.data());
}

}  // namespace vs
