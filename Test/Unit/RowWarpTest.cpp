// The 1D path's row warp (Synth/RowWarp.h) against the plain per-row algorithm it replaced: every
// sample's position and depth into arrays, then the segments between neighbours, then the points.
// The outputs must be the same bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "Common/Camera.h"
#include "PlainRaster.h"
#include "Synth/Layer.h"
#include "Synth/RowWarp.h"
#include "Synth/Warp.h"

namespace vs {
namespace {

void warpRowPlainly(const ViewProjection& projection, const std::vector<double>& rowDepth, double discontinuity,
                    int splatting, const uint16_t* levels, int width, const uint8_t* nearBoundary, double* z,
                    int outWidth) {
  std::vector<double> xs(static_cast<size_t>(width)), ws(static_cast<size_t>(width));
  for (int x = 0; x < width; ++x) {
    const double wv = levels[x] < rowDepth.size() ? rowDepth[levels[x]] : std::nan("");
    const double target = std::isnan(wv) ? wv : projection.rowTarget(x, wv);
    ws[x] = std::isfinite(target) ? wv : kNoDepth;
    xs[x] = target;
  }
  if (splatting != 0) {
    for (int x = 0; x + 1 < width; ++x) {
      const double w0 = ws[x], w1 = ws[x + 1];
      const bool near = splatting == 1 || nearBoundary[x] || nearBoundary[x + 1];
      if (w0 < 0 || w1 < 0 || std::fabs(w0 - w1) > discontinuity || !near) continue;
      double x0 = xs[x], x1 = xs[x + 1], a = w0, b = w1;
      if (x1 < x0) {
        std::swap(x0, x1);
        std::swap(a, b);
      }
      int first, last;
      if (!plain::coveredRange(x0, x1, outWidth, first, last)) continue;
      const double span = x1 - x0;
      for (int px = first; px <= last; ++px) {
        const double t = span > 0 ? (px - x0) / span : 0.0;
        plain::raise(z[px], a + t * (b - a));
      }
    }
  }
  for (int x = 0; x < width; ++x) {
    if (ws[x] < 0) continue;
    const double px = std::floor(xs[x] + 0.5);
    if (px < 0 || px >= outWidth) continue;
    plain::raise(z[size_t(px)], ws[x]);
  }
}

TEST(RowWarp, EqualsThePlainPerRowAlgorithm) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto pick = [&](int n) { return int(unit(rng) * n) % n; };
  size_t raised = 0, segmentCells = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    // A rectified pair: focal lengths equal or in a ratio (segments spanning several pixel centres,
    // or none), principal points on whole or half pixels, a step or two of the 2^-30 position grid
    // off whole pixels (where the 1e-9 margins of the covered ranges decide), or anywhere; baselines
    // either way.
    const double ratios[] = {1.0, 1.0, 1.0, 2.0, 0.5, 1.37, 0.8};
    Camera reference, target;
    const double focal = std::round(500 + 1500 * unit(rng));
    reference.K[0][0] = reference.K[1][1] = focal;
    target.K[0][0] = target.K[1][1] = focal * ratios[pick(7)];
    const int centreKind = pick(4);
    auto centre = [&] {
      const double c = 300 * unit(rng);
      return centreKind == 0 || centreKind == 3 ? std::round(c) : centreKind == 1 ? std::round(2 * c) / 2 : c;
    };
    reference.K[0][2] = centre();
    target.K[0][2] = centreKind == 3 ? std::round(reference.K[0][2]) + (pick(5) - 2) * std::ldexp(1.0, -30) : centre();
    target.t.x = (unit(rng) < 0.5 ? -1 : 1) * (unit(rng) < 0.1 ? 0.0 : 1 + 100 * unit(rng));
    const ViewProjection projection(reference, target, 0, true);

    const int width = 1 + pick(160), outWidth = std::max(1, width + pick(80) - 30);
    // Levels' inverse depths: disparities up to a few widths, on a grid of half pixels (ties at pixel
    // centres and at half pixels) or anywhere; some levels not warped, at infinity (+0 and -0), or so
    // near that the position overflows.
    const int levelCount = std::vector<int>{1, 8, 64, 256, 1024}[size_t(pick(5))];
    const double reach = (0.5 + 3 * unit(rng)) * width / (target.K[0][0] * std::max(std::fabs(target.t.x), 1.0));
    const bool onGrid = unit(rng) < 0.5;
    std::vector<double> rowDepth(static_cast<size_t>(levelCount));
    for (double& wv : rowDepth) {
      const double u = unit(rng);
      wv = u < 0.08 ? std::nan("") : u < 0.10 ? 0.0 : u < 0.11 ? -0.0 : u < 0.115 ? 1e300 : reach * unit(rng);
      if (onGrid && wv > 0 && wv < 1e300) wv = std::round(wv / reach * 2 * width) * reach / (2 * width);
    }
    const double discontinuity = unit(rng) < 0.3 ? std::fabs(rowDepth[size_t(pick(levelCount))] -
                                                            rowDepth[size_t(pick(levelCount))])
                                                 : reach * unit(rng) * 0.3;
    const int splatting = pick(3);
    const RowDepthWarp warp(projection, rowDepth, discontinuity, splatting);
    RowDepthWarp::Scratch scratch;

    for (int row = 0; row < 3; ++row) {
      // Runs of one level, ramps of one level per sample, noise, and a few levels past the table.
      std::vector<uint16_t> levels(static_cast<size_t>(width));
      int level = pick(levelCount), step = 0;
      for (uint16_t& l : levels) {
        const double u = unit(rng);
        if (u < 0.15) level = pick(levelCount + 3);
        else if (u < 0.25) step = pick(3) - 1;
        level = std::clamp(level + step, 0, levelCount + 2);
        l = uint16_t(level);
      }
      std::vector<uint8_t> nearBoundary(static_cast<size_t>(width));
      uint8_t flag = 0;
      for (uint8_t& f : nearBoundary) {
        if (unit(rng) < 0.1) flag = !flag;
        f = flag;
      }
      // Mostly empty rows, as the warp receives them; some hold values already (the warp only raises),
      // negative ones among them, whose bit patterns order differently.
      std::vector<double> z(static_cast<size_t>(outWidth), kNoDepth);
      if (unit(rng) < 0.2)
        for (double& v : z) v = unit(rng) < 0.5 ? kNoDepth : (unit(rng) < 0.2 ? -unit(rng) : reach * unit(rng));
      std::vector<double> expected = z, actual = z;
      warpRowPlainly(projection, rowDepth, discontinuity, splatting, levels.data(), width, nearBoundary.data(),
                     expected.data(), outWidth);
      warp.warp(levels.data(), width, nearBoundary.data(), actual.data(), outWidth, scratch);
      ASSERT_EQ(0, std::memcmp(actual.data(), expected.data(), z.size() * sizeof(double)))
          << "trial " << trial << ", row " << row << ", width " << width << ", out " << outWidth << ", splatting "
          << splatting;
      for (size_t i = 0; i < z.size(); ++i) raised += std::memcmp(&z[i], &expected[i], sizeof(double)) != 0;
      if (splatting != 0) {
        // What the segments add to the points: counted so that the cases are seen to draw segments.
        std::vector<double> points = z;
        warpRowPlainly(projection, rowDepth, discontinuity, 0, levels.data(), width, nearBoundary.data(),
                       points.data(), outWidth);
        for (size_t i = 0; i < z.size(); ++i)
          segmentCells += std::memcmp(&points[i], &expected[i], sizeof(double)) != 0;
      }
    }
  }
  EXPECT_GT(raised, 200000u);
  EXPECT_GT(segmentCells, 50000u);
}

}  // namespace
}  // namespace vs
