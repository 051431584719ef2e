// The general path's depth warp (doc/algorithms.md, "Warping"): every reference sample is projected
// into the virtual camera; the depth grid is rasterised as triangles (those spanning a depth
// discontinuity are dropped) and as points into a z-buffer of inverse depth; then cracks are closed.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "Synth/Cracks.h"
#include "Synth/Kernels/QuadRow.h"
#include "Synth/Raster.h"
#include "Synth/Synthesizer.h"

namespace vs {

namespace {

// Equirectangular cameras (Synth/Warp.h): the quads between two projected rows, drawn so that none
// spans the virtual ERP picture across its longitude wrap. The row is rasterised in runs that stop
// at a quad whose warped corners land on both sides of the wrap (more than half the picture apart);
// such a quad is drawn twice, once with its left-side corners a whole turn to the right and once
// with its right-side corners a turn to the left, each clipped by the picture. With a full-circle
// reference, the quad closing its rows (last column to first) is drawn the same way.
template <class Rasterise>
void rasteriseSphericalRow(const Rasterise& rasteriseRow, int width, int wrapWidth, bool closeReference,
                           const double* xTop, const double* yTop, const double* wTop, const double* xBottom,
                           const double* yBottom, const double* wBottom) {
  const double half = 0.5 * wrapWidth;
  const auto crosses = [&](int c0, int c1) {
    if (wrapWidth == 0) return false;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const int c : {c0, c1}) {
      if (wTop[c] >= 0) lo = std::min(lo, xTop[c]), hi = std::max(hi, xTop[c]);
      if (wBottom[c] >= 0) lo = std::min(lo, xBottom[c]), hi = std::max(hi, xBottom[c]);
    }
    return hi - lo > half;
  };
  const auto drawQuad = [&](int c0, int c1) {
    double x[4] = {xTop[c0], xTop[c1], xBottom[c0], xBottom[c1]};
    const double y[4] = {yTop[c0], yTop[c1], yBottom[c0], yBottom[c1]};
    const double w[4] = {wTop[c0], wTop[c1], wBottom[c0], wBottom[c1]};
    if (!crosses(c0, c1)) {
      rasteriseRow(2, x, y, w, x + 2, y + 2, w + 2);
      return;
    }
    double shifted[4];
    for (int i = 0; i < 4; ++i) shifted[i] = x[i] < half ? x[i] + wrapWidth : x[i];
    rasteriseRow(2, shifted, y, w, shifted + 2, y + 2, w + 2);
    for (int i = 0; i < 4; ++i) shifted[i] = x[i] >= half ? x[i] - wrapWidth : x[i];
    rasteriseRow(2, shifted, y, w, shifted + 2, y + 2, w + 2);
  };
  int start = 0;
  for (int c = 0; c + 1 < width && wrapWidth > 0; ++c)
    if (crosses(c, c + 1)) {
      if (c > start) rasteriseRow(c + 1 - start, xTop + start, yTop + start, wTop + start, xBottom + start,
                                  yBottom + start, wBottom + start);
      drawQuad(c, c + 1);
      start = c + 1;
    }
  if (width - start >= 2)
    rasteriseRow(width - start, xTop + start, yTop + start, wTop + start, xBottom + start, yBottom + start,
                 wBottom + start);
  if (closeReference && width >= 2) drawQuad(width - 1, 0);
}

}  // namespace

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
  // The points and the quads go to the kernels compiled for the CPU's x86-64 level
  // (Synth/Kernels/QuadRow.h).
  const QuadRowKernels& kernels = quadRowKernels();
  auto drawInto = [&](const auto& raisePoints, const auto& rasteriseRow) {
    parallelRanges(h, [&](int y0, int y1) {
      // Locals: the stores below are doubles, which may alias the projection's and the table's.
      const ViewProjection projection = view.projection;
      const double* levelToInverseDepth = view.levelToInverseDepth.data();
      const int width = w, height = h, outWidth = outW, outHeight = outH;
      const double discontinuity = plan_.discontinuity;
      const bool spherical = projection.spherical();
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
        if (y < y1) raisePoints(width, outWidth, outHeight, xs, ys, ws);
        if (y > y0 && !spherical)
          rasteriseRow(width, outWidth, outHeight, discontinuity, xAbove, yAbove, wAbove, xs, ys, ws);
        else if (y > y0)
          rasteriseSphericalRow(
              [&](int n, auto... rows) { rasteriseRow(n, outWidth, outHeight, discontinuity, rows...); }, width,
              projection.wrapWidth(), projection.referenceWraps(), xAbove, yAbove, wAbove, xs, ys, ws);
        std::swap(xAbove, xs);
        std::swap(yAbove, ys);
        std::swap(wAbove, ws);
      }
    });
  };
  if (lone) {
    double* cells = view.luma.inverseDepth.data();
    drawInto([&](auto... row) { kernels.pointsLone(cells, row...); }, [&](auto... rows) { kernels.lone(cells, rows...); });
  } else {
    AtomicMaxBuffer& zbuffer = view.zbuffer;
    std::atomic<int64_t>* cells = zbuffer.cells();
    drawInto([&](auto... row) { kernels.pointsAtomic(cells, row...); }, [&](auto... rows) { kernels.atomic(cells, rows...); });
    // The z-buffer becomes the layer's depth, and the rest of the layer is cleared, row by row.
    parallelRanges(outH, [&](int y0, int y1) {
      clearRows(view.luma, y0, y1);
      zbuffer.copyTo(size_t(y0) * outW, size_t(y1) * outW, view.luma.inverseDepth.data() + size_t(y0) * outW);
    });
  }
  closeCracks(view.luma.inverseDepth, outW, outH, plan_.discontinuity, byteRows_);
}

}  // namespace vs
