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
// at a quad whose warped corners land on both sides of the wrap (more than half a turn apart; for a
// partial circle the "wrap" is the meridian straight behind, outside the picture); such a quad is
// drawn twice, once with its corners left of the picture's middle a whole turn to the right and once
// with those right of it a turn to the left, each clipped by the picture. With a full-circle
// reference, the quad closing its rows (last column to first) is drawn the same way.
//
// A triangle of such a quad that goes round a pole of the virtual picture (its corners' longitudes,
// each step taken the short way round, add up to a whole turn) covers the whole cap beyond its edges:
// it is drawn as three quads, each between one of its edges and the pole's row (the pole's depth the
// triangle's plane's there: ViewProjection::poleInverseDepth), shifted a turn either way as needed.
// rasteriseRow(n, discontinuity, top row, bottom row) rasterises n - 1 quads.
template <class Rasterise>
void rasteriseSphericalRow(const Rasterise& rasteriseRow, const ViewProjection& projection, int width, int outWidth,
                           int outHeight, double discontinuity, bool closeReference, const double* xTop,
                           const double* yTop, const double* wTop, const double* xBottom, const double* yBottom,
                           const double* wBottom) {
  const double wrapWidth = projection.wrapWidth();
  const double half = 0.5 * wrapWidth, middle = 0.5 * outWidth;
  const auto crosses = [&](int c0, int c1) {
    if (wrapWidth == 0) return false;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const int c : {c0, c1}) {
      if (wTop[c] >= 0) lo = std::min(lo, xTop[c]), hi = std::max(hi, xTop[c]);
      if (wBottom[c] >= 0) lo = std::min(lo, xBottom[c]), hi = std::max(hi, xBottom[c]);
    }
    return hi - lo > half;
  };
  // The step from a to b the short way round the circle.
  const auto step = [&](double a, double b) {
    double d = b - a;
    if (d > half) d -= wrapWidth;
    else if (d <= -half) d += wrapWidth;
    return d;
  };
  // The corners (of the quad's four) of its triangles (0, 1, 3) and (0, 3, 2).
  static constexpr int kTriangles[2][3] = {{0, 1, 3}, {0, 3, 2}};
  const auto drawCap = [&](const double* x, const double* y, const double* w, const int* corner) {
    double tx[3], ty[3], tw[3];
    for (int i = 0; i < 3; ++i) tx[i] = x[corner[i]], ty[i] = y[corner[i]], tw[i] = w[corner[i]];
    const bool north = ty[0] + ty[1] + ty[2] < 1.5 * outHeight;
    const double poleY = projection.poleRow(north), poleW = projection.poleInverseDepth(tx, ty, tw, north);
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      const double to = tx[i] + step(tx[i], tx[j]);
      for (const double shift : {-wrapWidth, 0.0, wrapWidth}) {
        const double qx[4] = {tx[i] + shift, to + shift, tx[i] + shift, to + shift};
        const double qy[4] = {poleY, poleY, ty[i], ty[j]};
        const double qw[4] = {poleW, poleW, tw[i], tw[j]};
        // The triangle passed the discontinuity rule; the pole's depth lies on its plane.
        rasteriseRow(2, HUGE_VAL, qx, qy, qw, qx + 2, qy + 2, qw + 2);
      }
    }
  };
  const auto drawQuad = [&](int c0, int c1) {
    double x[4] = {xTop[c0], xTop[c1], xBottom[c0], xBottom[c1]};
    const double y[4] = {yTop[c0], yTop[c1], yBottom[c0], yBottom[c1]};
    const double w[4] = {wTop[c0], wTop[c1], wBottom[c0], wBottom[c1]};
    if (!crosses(c0, c1)) {
      rasteriseRow(2, discontinuity, x, y, w, x + 2, y + 2, w + 2);
      return;
    }
    bool cap[2] = {false, false};
    for (int t = 0; t < 2; ++t) {
      const int* k = kTriangles[t];
      if (!(w[k[0]] >= 0 && w[k[1]] >= 0 && w[k[2]] >= 0)) continue;
      const double span = std::max({w[k[0]], w[k[1]], w[k[2]]}) - std::min({w[k[0]], w[k[1]], w[k[2]]});
      const double turn = step(x[k[0]], x[k[1]]) + step(x[k[1]], x[k[2]]) + step(x[k[2]], x[k[0]]);
      cap[t] = span <= discontinuity && std::fabs(turn) > half;
      if (cap[t]) drawCap(x, y, w, k);
    }
    // The rest drawn a turn to the right and a turn to the left; a triangle drawn as a cap is left out
    // (its third corner marked not warped: the quad's other triangle does not use it).
    double rest[4] = {w[0], w[1], w[2], w[3]};
    if (cap[0]) rest[1] = -1.0;
    if (cap[1]) rest[2] = -1.0;
    if (cap[0] && cap[1]) return;
    double shifted[4];
    for (int i = 0; i < 4; ++i) shifted[i] = x[i] < middle ? x[i] + wrapWidth : x[i];
    rasteriseRow(2, discontinuity, shifted, y, rest, shifted + 2, y + 2, rest + 2);
    for (int i = 0; i < 4; ++i) shifted[i] = x[i] >= middle ? x[i] - wrapWidth : x[i];
    rasteriseRow(2, discontinuity, shifted, y, rest, shifted + 2, y + 2, rest + 2);
  };
  int start = 0;
  for (int c = 0; c + 1 < width && wrapWidth > 0; ++c)
    if (crosses(c, c + 1)) {
      if (c > start)
        rasteriseRow(c + 1 - start, discontinuity, xTop + start, yTop + start, wTop + start, xBottom + start,
                     yBottom + start, wBottom + start);
      drawQuad(c, c + 1);
      start = c + 1;
    }
  if (width - start >= 2)
    rasteriseRow(width - start, discontinuity, xTop + start, yTop + start, wTop + start, xBottom + start,
                 yBottom + start, wBottom + start);
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
      // An ERP reference reaching a pole: its first (last) row's samples, carried to the pole (row -0.5
      // or height - 0.5) at their own distances, are one more row of the grid, "row" -1 (height), so
      // that the half-row cap between them and the pole is drawn too.
      const SphereEdges& sphere = projection.referenceSphere();
      auto project = [&](int y) {
        const uint16_t* levels = depth.row(std::clamp(y, 0, height - 1));
        for (int x = 0; x < width; ++x) inverse[x] = levelToInverseDepth[levels[x]];
        const double v = y < 0 ? -0.5 : y >= height ? height - 0.5 : double(y);
        projection.forwardRow(inverse, width, v, xs, ys, ws);
      };
      const int first = y0 == 0 && sphere.north ? -1 : y0, last = sphere.south ? height : height - 1;
      for (int y = first; y <= y1 && y <= last; ++y) {
        project(y);
        if (y > y0 && !spherical)
          rasteriseRow(width, outWidth, outHeight, discontinuity, xAbove, yAbove, wAbove, xs, ys, ws);
        else if (y > first)
          rasteriseSphericalRow(
              [&](int n, double jump, auto... rows) { rasteriseRow(n, outWidth, outHeight, jump, rows...); },
              projection, width, outWidth, outHeight, discontinuity, projection.referenceWraps(), xAbove, yAbove,
              wAbove, xs, ys, ws);
        // Every sample also lands as a point, so thin foreground keeps its width. After the quads
        // (the z-buffer keeps the largest whatever the order): they have just touched the cells the
        // points land on.
        if (y < y1 && y >= 0 && y < height) raisePoints(width, outWidth, outHeight, xs, ys, ws);
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
