// The general path's depth warp (doc/algorithms.md, "Warping"): every reference sample is projected
// into the virtual camera; the depth grid is rasterised as triangles (those spanning a depth
// discontinuity are dropped) and as points into a z-buffer of inverse depth; then cracks are closed.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "Synth/Cracks.h"
#include "Synth/Kernels/QuadRow.h"
#include "Synth/Raster.h"
#include "Synth/Synthesizer.h"

namespace vs {

void Synthesizer::warpDepth(ViewState& view, const Plane& depth) {
  const int w = depth.width, h = depth.height;
  const int outW = outputFormat_.width, outH = outputFormat_.height;
  view.luma.resize(outW, outH, plan_.rgb ? 3 : 1);  // cleared row by row (clearRows)
  // Where the views run side by side, or there is one thread (the pool then runs every loop on the
  // calling thread), this view's thread is the only writer: the triangles are drawn straight into the
  // layer's depth. Otherwise into an atomic z-buffer, then copied.
  const bool lone = viewsSideBySide() || workerThreads() <= 1;
  if (lone) parallelRanges(outH, [&](int y0, int y1) { clearRows(view.luma, y0, y1); });
  else view.zbuffer.reset(size_t(outW) * outH, kNoDepth);
  // Row by row: each reference row is projected into the virtual view (forwardRow), its samples are
  // raised as points, and the quads between it and the row above are rasterised while both rows are
  // at hand (two rows of positions, not the whole picture's). A range of rows also projects the row
  // after its last, for the quads between them; that row's points are raised by the range holding it.
  // The quads go to the rasteriser compiled for the CPU's x86-64 level (Synth/Kernels/QuadRow.h).
  const QuadRowKernels& kernels = quadRowKernels();
  auto drawInto = [&](const auto& raise, const auto& rasteriseRow) {
    parallelRanges(h, [&](int y0, int y1) {
      // Locals: the stores below are doubles, which may alias the projection's and the table's.
      const ViewProjection projection = view.projection;
      const double* levelToInverseDepth = view.levelToInverseDepth.data();
      const int width = w, height = h, outWidth = outW, outHeight = outH;
      const double discontinuity = plan_.discontinuity;
      const auto put = raise;  // a copy no store can change: what it holds stays in registers
      // A row's inverse depths first (a look-up per sample), then its projection in a loop that
      // vectorises. A level declared missing has a NaN inverse depth: not warped.
      const auto scratch = depthRows_.take();
      std::vector<double>& inverseRow = scratch->inverse;
      std::vector<double>& rowBuffers = scratch->positions;
      inverseRow.resize(size_t(width));
      rowBuffers.resize(size_t(width) * 6);
      double* inverse = inverseRow.data();
      // Positions and inverse depths of two rows: the one above (the quads' top) and the current.
      double *xAbove = rowBuffers.data(), *yAbove = xAbove + width, *wAbove = yAbove + width;
      double *xs = wAbove + width, *ys = xs + width, *ws = ys + width;
      auto project = [&](int y) {
        const uint16_t* levels = depth.row(y);
        for (int x = 0; x < width; ++x) inverse[x] = levelToInverseDepth[levels[x]];
        projection.forwardRow(inverse, width, y, xs, ys, ws);
      };
      for (int y = y0; y <= y1 && y < height; ++y) {
        project(y);
        // Every sample also lands as a point, so thin foreground keeps its width.
        if (y < y1) {
          for (int x = 0; x < width; ++x) {
            if (ws[x] < 0) continue;
            const double px = std::floor(xs[x] + 0.5), py = std::floor(ys[x] + 0.5);
            if (px < 0 || py < 0 || px >= outWidth || py >= outHeight) continue;
            put(size_t(py) * outWidth + size_t(px), ws[x]);
          }
        }
        if (y > y0)
          rasteriseRow(width, outWidth, outHeight, discontinuity, xAbove, yAbove, wAbove, xs, ys, ws);
        std::swap(xAbove, xs);
        std::swap(yAbove, ys);
        std::swap(wAbove, ws);
      }
    });
  };
  if (lone) {
    double* cells = view.luma.inverseDepth.data();
    drawInto(LoneRaise{cells}, [&](auto... rows) { kernels.lone(cells, rows...); });
  } else {
    AtomicMaxBuffer& zbuffer = view.zbuffer;
    std::atomic<int64_t>* cells = zbuffer.cells();
    drawInto([&zbuffer](size_t i, double value) { zbuffer.raise(i, value); },
             [&](auto... rows) { kernels.atomic(cells, rows...); });
    // The z-buffer becomes the layer's depth, and the rest of the layer is cleared, row by row.
    parallelRanges(outH, [&](int y0, int y1) {
      clearRows(view.luma, y0, y1);
      zbuffer.copyTo(size_t(y0) * outW, size_t(y1) * outW, view.luma.inverseDepth.data() + size_t(y0) * outW);
    });
  }
  closeCracks(view.luma.inverseDepth, outW, outH, plan_.discontinuity, byteRows_);
}

}  // namespace vs
