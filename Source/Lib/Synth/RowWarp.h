#pragma once
// The 1D path's depth warp of one reference row (doc/algorithms.md, "Warping"): on a rectified rig a
// row maps to a row, and each sample moves along it by the disparity of its depth level.
#include <cstdint>
#include <vector>

#include "Synth/Warp.h"

namespace vs {

class RowDepthWarp {
public:
  // levelToRowDepth: the inverse camera depth per level, NaN for a level that is not warped.
  // splatting: SplattingOption; 0 draws points only, 1 segments everywhere, 2 segments only where a
  // sample of the pair is near a reference depth edge. discontinuity: the largest inverse-depth step
  // between two samples of one surface.
  RowDepthWarp(const ViewProjection& projection, const std::vector<double>& levelToRowDepth, double discontinuity,
               int splatting);

  // Raises z[0, outWidth) (kept as the larger inverse depth, compared as signed 64-bit integers, as
  // AtomicMaxBuffer compares) with what reference row `levels` (width samples) puts there: the segments
  // between horizontal neighbours on one surface, rasterised at the pixel centres they cover, and
  // every sample as a point at its nearest pixel centre. nearBoundary (width flags) is read only
  // with splatting 2.
  // `scratch`: working space of the caller's thread (any content; resized here).
  struct Scratch {
    std::vector<double> xs, ws;  // the row's positions and depths
    std::vector<int> segments;   // the segments left to draw
  };
  void warp(const uint16_t* levels, int width, const uint8_t* nearBoundary, double* z, int outWidth,
            Scratch& scratch) const;

private:
  ViewProjection projection_;
  // Per level the displacement (projection.rowDisplacement(depth); NaN for a level that is not warped)
  // and the inverse depth (kNoDepth for a level that is not warped), one pair after the other (the row
  // kernel's table, Synth/Kernels/Rows.h); then one pair for every level past the table (not warped).
  std::vector<double> levels_;
  double discontinuity_;
  int splatting_;
};

}  // namespace vs
