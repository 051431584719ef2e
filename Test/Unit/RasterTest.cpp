// The general depth warp's triangle rasteriser (Synth/Raster.h): rasteriseTriangle and two quads'
// triangles side by side (rasteriseQuadPair) against a plain copy of the per-triangle loop the warp
// used before them. The z-buffers must hold the same bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "Common/CpuLevel.h"
#include "PlainRaster.h"
#include "Synth/Kernels/QuadRow.h"
#include "Synth/Parallel.h"
#include "Synth/Raster.h"

namespace vs {
namespace {

constexpr double kEmpty = -1.0;  // the z-buffer's kNoDepth

using plain::bitsOf;

// AtomicMaxBuffer's order, as a rasteriser's raise(i, value).
struct PlainRaise {
  std::vector<double>* cells;
  void operator()(size_t i, double value) const { plain::raise((*cells)[i], value); }
};

void rasterisePlainly(std::vector<double>& cells, int width, int height, const double* x, const double* y,
                      const double* w) {
  const double minX = std::min(x[0], std::min(x[1], x[2])), maxX = std::max(x[0], std::max(x[1], x[2]));
  const double minY = std::min(y[0], std::min(y[1], y[2])), maxY = std::max(y[0], std::max(y[1], y[2]));
  int x0, x1, y0, y1;
  if (!plain::coveredRange(minX, maxX, width, x0, x1) || !plain::coveredRange(minY, maxY, height, y0, y1))
    return;
  const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (std::fabs(area) < 1e-12) return;
  const double inv = 1.0 / area;
  const double a1 = (y[2] - y[0]) * inv, c1 = -(x[2] - x[0]) * inv;
  const double a2 = -(y[1] - y[0]) * inv, c2 = (x[1] - x[0]) * inv;
  const double k1 = -(a1 * x[0] + c1 * y[0]), k2 = -(a2 * x[0] + c2 * y[0]);
  const PlainRaise raise{&cells};
  for (int py = y0; py <= y1; ++py)
    for (int px = x0; px <= x1; ++px) {
      const double b1 = a1 * px + (c1 * py + k1), b2 = a2 * px + (c2 * py + k2), b0 = 1.0 - b1 - b2;
      if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) continue;
      raise(size_t(py) * width + px, w[0] + b1 * (w[1] - w[0]) + b2 * (w[2] - w[0]));
    }
}

// The quads between two rows of warped samples (top row 0, bottom row 1) as the plain rule draws them:
// triangles (0, 1, 3) and (0, 3, 2) of quad q's corners (top q, top q + 1, bottom q, bottom q + 1),
// each where its three corners are warped and their depths span at most `discontinuity`.
void rasteriseQuadRowPlainly(std::vector<double>& plain, int width, int outWidth, int outHeight, double discontinuity,
                             const std::vector<double>* x, const std::vector<double>* y,
                             const std::vector<double>* w) {
  for (int q = 0; q + 1 < width; ++q) {
    const double d[4] = {w[0][size_t(q)], w[0][size_t(q) + 1], w[1][size_t(q)], w[1][size_t(q) + 1]};
    const double cx[4] = {x[0][size_t(q)], x[0][size_t(q) + 1], x[1][size_t(q)], x[1][size_t(q) + 1]};
    const double cy[4] = {y[0][size_t(q)], y[0][size_t(q) + 1], y[1][size_t(q)], y[1][size_t(q) + 1]};
    const int triangle[2][3] = {{0, 1, 3}, {0, 3, 2}};
    for (const auto& corners : triangle) {
      double tx[3], ty[3], tw[3], lo = HUGE_VAL, hi = -HUGE_VAL;
      bool warped = true;
      for (int c = 0; c < 3; ++c) {
        tx[c] = cx[corners[c]];
        ty[c] = cy[corners[c]];
        tw[c] = d[corners[c]];
        warped = warped && tw[c] >= 0;
        lo = std::min(lo, tw[c]);
        hi = std::max(hi, tw[c]);
      }
      if (warped && hi - lo <= discontinuity) rasterisePlainly(plain, outWidth, outHeight, tx, ty, tw);
    }
  }
}

// Quads of warped samples as the general depth warp makes them: a grid's samples moved by a random
// shift, with corners put exactly on pixel centres or 1e-9 and 2e-9 off them (where the tolerances
// decide), large quads whose pixels span more than a 2 x 2 square, quads across the picture's
// borders, and degenerate ones. Depths span zero so that interpolated values go slightly negative.
struct Quad {
  double x[4], y[4], w[4];
};

Quad randomQuad(std::mt19937& rng, int width, int height) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 9);
  const int shape = kind(rng);
  // Shape 1: areas about the 1e-12 below which a triangle is degenerate.
  const double scale = shape == 0 ? 1.0 + 6.0 * unit(rng) : shape == 1 ? 1e-6 * (0.5 + unit(rng)) : 1.0;
  double baseX = -2.0 + (width + 3.0) * unit(rng), baseY = -2.0 + (height + 3.0) * unit(rng);
  if (shape == 1) {  // around a pixel centre
    baseX = std::round(baseX) - scale * unit(rng);
    baseY = std::round(baseY) - scale * unit(rng);
  }
  const double jitter = shape == 1 || shape == 2 ? 0.0 : 0.3;
  Quad q;
  for (int c = 0; c < 4; ++c) {
    double x = baseX + scale * (c & 1) + jitter * (unit(rng) - 0.5);
    double y = baseY + scale * (c >> 1) + jitter * (unit(rng) - 0.5);
    if (shape != 1 && kind(rng) < 4) {  // onto a pixel centre, or just off it
      const double off[5] = {0.0, 1e-9, -1e-9, 2e-9, -2e-9};
      x = std::round(x) + off[kind(rng) % 5];
      y = std::round(y) + off[kind(rng) % 5];
    }
    q.x[c] = x;
    q.y[c] = y;
    q.w[c] = kind(rng) == 0 ? 0.0 : unit(rng) * (kind(rng) < 5 ? 1e-3 : 1.0);
  }
  return q;
}

TEST(Raster, TriangleEqualsPlainLoop) {
  std::mt19937 rng(7);
  const int width = 23, height = 17;
  std::vector<double> plain(size_t(width) * height, kEmpty), ours = plain;
  const PlainRaise raise{&ours};
  for (int t = 0; t < 20000; ++t) {
    const Quad q = randomQuad(rng, width, height);
    rasterisePlainly(plain, width, height, q.x, q.y, q.w);
    rasteriseTriangle(raise, width, height, q.x, q.y, q.w);
  }
  size_t raised = 0;
  for (size_t i = 0; i < plain.size(); ++i) {
    ASSERT_EQ(bitsOf(plain[i]), bitsOf(ours[i])) << "cell " << i;
    raised += plain[i] != kEmpty;
  }
  EXPECT_GT(raised, plain.size() / 2);
}

#if defined(__SSE4_1__)
// Quads as the warp passes neighbours to rasteriseQuads: lanes 2q and 2q + 1 quad q's triangles,
// corners (0, 1, 3) and (0, 3, 2).
template <int kQuads>
void checkQuadsEqualPlainTriangles(uint32_t seed) {
  using Doubles = typename QuadLanes<kQuads>::Doubles;
  std::mt19937 rng(seed);
  std::bernoulli_distribution often(0.8);
  // Small pictures, so that quads often reach the last row and column (the square's clamped cells).
  for (const int size : {1, 2, 5, 31}) {
    const int width = size, height = size + 1;
    std::vector<double> plain(size_t(width) * height, kEmpty), ours = plain;
    const PlainRaise raise{&ours};
    for (int t = 0; t < 20000; ++t) {
      Quad quads[kQuads];
      for (Quad& q : quads) q = randomQuad(rng, width, height);
      bool draw[2 * kQuads];
      for (bool& d : draw) d = often(rng);
      const int corner[2][3] = {{0, 1, 3}, {0, 3, 2}};
      Doubles x[3] = {}, y[3] = {}, w[3] = {};
      for (int k = 0; k < 2 * kQuads; ++k) {
        const Quad& q = quads[k / 2];
        double tx[3], ty[3], tw[3];
        for (int c = 0; c < 3; ++c) {
          tx[c] = x[c][k] = q.x[corner[k % 2][c]];
          ty[c] = y[c][k] = q.y[corner[k % 2][c]];
          tw[c] = w[c][k] = q.w[corner[k % 2][c]];
        }
        if (draw[k]) rasterisePlainly(plain, width, height, tx, ty, tw);
        // A corner of a triangle not drawn may be anything (the warp's samples that did not land).
        else x[2][k] = y[1][k] = std::nan("");
      }
      rasteriseQuads<kQuads>(raise, width, height, x, y, w, QuadLanes<kQuads>::lanes(draw));
    }
    size_t raised = 0;
    for (size_t i = 0; i < plain.size(); ++i) {
      ASSERT_EQ(bitsOf(plain[i]), bitsOf(ours[i]))
          << kQuads << " quads, picture " << width << " x " << height << ", cell " << i;
      raised += plain[i] != kEmpty;
    }
    EXPECT_GT(raised, plain.size() / 2);
  }
}

// QuadLanes::corners puts quad q's corners (samples q[k] and q[k] + 1 of the two rows) in lanes 2k
// and 2k + 1 as triangles (0, 1, 3) and (0, 3, 2), corner 0 top left, 3 bottom right.
template <int kQuads>
void checkCornerLanes() {
  using L = QuadLanes<kQuads>;
  std::vector<double> top(16), bottom(16);
  for (int i = 0; i < 16; ++i) {
    top[size_t(i)] = 100 + i;
    bottom[size_t(i)] = 200 + i;
  }
  const int quads[4] = {3, 0, 9, 14};
  typename L::Doubles lanes[3];
  L::corners(top.data(), bottom.data(), quads, lanes);
  for (int k = 0; k < kQuads; ++k) {
    const int q = quads[k];
    const double corner[4] = {top[size_t(q)], top[size_t(q) + 1], bottom[size_t(q)], bottom[size_t(q) + 1]};
    const int triangle[2][3] = {{0, 1, 3}, {0, 3, 2}};
    for (int t = 0; t < 2; ++t)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(lanes[c][2 * k + t], corner[triangle[t][c]]) << kQuads << " quads, quad " << k << ", triangle " << t;
  }
}

// QuadLanes::cornersInRow, for quads x to x + kQuads - 1, gives what corners() gives for them, at
// every x the rows allow.
template <int kQuads>
void checkCornersInRow() {
  using L = QuadLanes<kQuads>;
  std::vector<double> top(16), bottom(16);
  for (int i = 0; i < 16; ++i) {
    top[size_t(i)] = 100 + i * 1.5;
    bottom[size_t(i)] = -200 - i * 0.25;
  }
  for (int x = 0; x + kQuads < 16; ++x) {
    int quads[kQuads];
    for (int q = 0; q < kQuads; ++q) quads[q] = x + q;
    typename L::Doubles gathered[3], loaded[3];
    L::corners(top.data(), bottom.data(), quads, gathered);
    L::cornersInRow(top.data(), bottom.data(), x, loaded);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < L::kLanes; ++k)
        EXPECT_EQ(loaded[c][k], gathered[c][k]) << kQuads << " quads from " << x << ", corner " << c << ", lane " << k;
  }
}

TEST(Raster, CornersOfQuadsSideBySideEqualTheirGatheredCorners) {
  checkCornersInRow<1>();
#if defined(__AVX__)
  checkCornersInRow<2>();
#endif
#if defined(__AVX512F__)
  checkCornersInRow<4>();
#endif
}

// drawnTriangles decides as the per-quad rule written out plainly (the rule of the warp's quads
// before it was evaluated in lanes): depths not warped (-1), -0 and +0, NaN, spans exactly at the
// discontinuity.
template <int kQuads>
void checkDrawnTriangles() {
  using L = QuadLanes<kQuads>;
  const double values[] = {-1.0, -0.0, 0.0, 0.3, 0.5, 0.8, std::nan(""), 1e300};
  std::mt19937 rng(29);
  std::uniform_int_distribution<size_t> pick(0, std::size(values) - 1);
  for (const double discontinuity : {0.3, 0.2, HUGE_VAL})
    for (int t = 0; t < 4000; ++t) {
      std::vector<double> top(kQuads + 1), bottom(kQuads + 1);
      for (int i = 0; i <= kQuads; ++i) {
        top[size_t(i)] = values[pick(rng)];
        bottom[size_t(i)] = values[pick(rng)];
      }
      typename L::Doubles w[3];
      L::cornersInRow(top.data(), bottom.data(), 0, w);
      const typename L::Mask drawn = drawnTriangles<kQuads>(w, discontinuity);
      for (int q = 0; q < kQuads; ++q) {
        const double d0 = top[size_t(q)], d1 = top[size_t(q) + 1], d2 = bottom[size_t(q)], d3 = bottom[size_t(q) + 1];
        bool draw[2] = {false, false};
        if (!(d0 < 0 || d3 < 0 || (d1 < 0 && d2 < 0))) {
          const double lo03 = std::min(d0, d3), hi03 = std::max(d0, d3);
          draw[0] = d1 >= 0 && std::max(hi03, d1) - std::min(lo03, d1) <= discontinuity;
          draw[1] = d2 >= 0 && std::max(hi03, d2) - std::min(lo03, d2) <= discontinuity;
        }
        for (int k = 0; k < 2; ++k)
          EXPECT_EQ(drawn[2 * q + k] != 0, draw[k]) << "depths " << d0 << " " << d1 << " " << d2 << " " << d3
                                                    << ", discontinuity " << discontinuity << ", triangle " << k;
      }
    }
}

TEST(Raster, TrianglesDrawnFromVectorLanesFollowThePlainRule) {
  checkDrawnTriangles<1>();
#if defined(__AVX__)
  checkDrawnTriangles<2>();
#endif
#if defined(__AVX512F__)
  checkDrawnTriangles<4>();
#endif
}

TEST(Raster, CornersFillEachQuadsLanes) {
  checkCornerLanes<1>();
#if defined(__AVX__)
  checkCornerLanes<2>();
#endif
#if defined(__AVX512F__)
  checkCornerLanes<4>();
#endif
}

TEST(Raster, OneQuadInVectorLanesEqualsTwoPlainTriangles) { checkQuadsEqualPlainTriangles<1>(11); }
#if defined(__AVX__)
TEST(Raster, TwoQuadsInVectorLanesEqualFourPlainTriangles) { checkQuadsEqualPlainTriangles<2>(13); }
#endif
#if defined(__AVX512F__)
TEST(Raster, FourQuadsInVectorLanesEqualEightPlainTriangles) { checkQuadsEqualPlainTriangles<4>(17); }
#endif
#endif

// The quad-row kernels the binary has for each level this CPU runs (Synth/Kernels/QuadRow.h).
std::vector<const QuadRowKernels*> quadRowKernelsThisCpuRuns() {
  std::vector<const QuadRowKernels*> kernels;
  for (int level = 0; level <= cpuX86Level(); ++level)
    if (quadRowKernelsFor(level)) kernels.push_back(quadRowKernelsFor(level));
  return kernels;
}

// Every level's quad-row kernels drawing the same row pairs, each into a z-buffer of its own for one
// writer (lone) and one for threads (atomic), to be compared with the plain triangles' cells.
class KernelBuffers {
 public:
  KernelBuffers(const std::vector<const QuadRowKernels*>& kernels, size_t cells)
      : kernels_(kernels), lone_(kernels.size(), std::vector<double>(cells, kEmpty)), shared_(kernels.size()) {
    for (AtomicMaxBuffer& buffer : shared_) buffer.reset(cells, kEmpty);
  }
  void draw(int width, int outWidth, int outHeight, double discontinuity, const std::vector<double> (&x)[2],
            const std::vector<double> (&y)[2], const std::vector<double> (&w)[2]) {
    for (size_t k = 0; k < kernels_.size(); ++k) {
      kernels_[k]->lone(lone_[k].data(), width, outWidth, outHeight, discontinuity, x[0].data(), y[0].data(),
                        w[0].data(), x[1].data(), y[1].data(), w[1].data());
      kernels_[k]->atomic(shared_[k].cells(), width, outWidth, outHeight, discontinuity, x[0].data(), y[0].data(),
                          w[0].data(), x[1].data(), y[1].data(), w[1].data());
    }
  }
  // Whether every kernel's cells hold plain's bits; the first that differs is named.
  ::testing::AssertionResult equal(const std::vector<double>& plain) const {
    for (size_t k = 0; k < kernels_.size(); ++k) {
      std::vector<double> fromAtomic(plain.size());
      shared_[k].copyTo(0, plain.size(), fromAtomic.data());
      for (size_t i = 0; i < plain.size(); ++i) {
        if (bitsOf(plain[i]) != bitsOf(lone_[k][i]))
          return ::testing::AssertionFailure() << "level " << kernels_[k]->level << ", cell " << i << ": "
                                               << lone_[k][i] << " against the plain " << plain[i];
        if (bitsOf(plain[i]) != bitsOf(fromAtomic[i]))
          return ::testing::AssertionFailure() << "level " << kernels_[k]->level << " atomic, cell " << i << ": "
                                               << fromAtomic[i] << " against the plain " << plain[i];
      }
    }
    return ::testing::AssertionSuccess();
  }
  // Every buffer, plain's too, back to empty.
  void clear(std::vector<double>& plain) {
    std::fill(plain.begin(), plain.end(), kEmpty);
    for (std::vector<double>& cells : lone_) std::fill(cells.begin(), cells.end(), kEmpty);
    for (AtomicMaxBuffer& buffer : shared_) buffer.reset(plain.size(), kEmpty);
  }

 private:
  const std::vector<const QuadRowKernels*>& kernels_;
  std::vector<std::vector<double>> lone_;
  std::vector<AtomicMaxBuffer> shared_;
};

// A row of quads as the general depth warp passes it: two rows of warped samples, some not warped
// (w < 0), depths on both sides of the discontinuity, widths odd and even (the last quads of a row
// fill only some lanes).
TEST(Raster, QuadRowEqualsPlainTrianglesOfEachQuad) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A wide discontinuity too, which no span of warped depths exceeds: then only the corners left
  // out decide.
  for (const double discontinuity : {0.3, 10.0})
  for (const int width : {2, 3, 4, 5, 8, 9, 13, 40}) {
    const int outWidth = width + 3, outHeight = 6;
    std::vector<double> plain(size_t(outWidth) * outHeight, kEmpty), ours = plain;
    const PlainRaise raise{&ours};
    // Every level's kernels, into z-buffers of their own: one thread's and the threads' (atomic) buffer.
    const std::vector<const QuadRowKernels*> kernels = quadRowKernelsThisCpuRuns();
    ASSERT_FALSE(kernels.empty());
    KernelBuffers buffers(kernels, plain.size());
    for (int t = 0; t < 3000; ++t) {
      std::vector<double> x[2], y[2], w[2];
      const double shift = 3.0 * unit(rng) - 1.0, row = 4.0 * unit(rng);
      for (int r = 0; r < 2; ++r) {
        for (int i = 0; i < width; ++i) {
          double px = i + shift + 0.4 * (unit(rng) - 0.5), py = row + r + 0.4 * (unit(rng) - 0.5);
          if (unit(rng) < 0.3) px = std::round(px);  // on a pixel centre's column
          if (unit(rng) < 0.3) py = std::round(py);
          x[r].push_back(px);
          y[r].push_back(py);
          const double u = unit(rng);
          // 0 and 0.3 span the narrow discontinuity exactly.
          w[r].push_back(u < 0.1 ? -1.0 : u < 0.2 ? 0.0 : u < 0.3 ? 0.3 : u < 0.6 ? 0.5 : unit(rng));
        }
      }
      rasteriseQuadRowPlainly(plain, width, outWidth, outHeight, discontinuity, x, y, w);
      rasteriseQuadRow(raise, width, outWidth, outHeight, discontinuity, x[0].data(), y[0].data(), w[0].data(),
                       x[1].data(), y[1].data(), w[1].data());
      buffers.draw(width, outWidth, outHeight, discontinuity, x, y, w);
    }
    ASSERT_TRUE(buffers.equal(plain)) << "rows of " << width;
    size_t raised = 0;
    for (size_t i = 0; i < plain.size(); ++i) {
      ASSERT_EQ(bitsOf(plain[i]), bitsOf(ours[i])) << "row of " << width << ", cell " << i;
      raised += plain[i] != kEmpty;
    }
    EXPECT_GT(raised, plain.size() / 2);
  }
}

// Rows of a rectified rig (Synth/Raster.h, rasteriseRectifiedQuads): every warped sample of the top row
// exactly on output row Y, of the bottom row on Y + 1, positions moving along the row by a disparity
// that varies smoothly, jumps both ways (disocclusions and fold-overs), squeezes and stretches the
// quads (views on either side, scales 0.4 to 3), with positions put on pixel centres and at 2^-30,
// 1e-9, 2e-9 and about the fast path's 2^-20 from them, depths at 0, -0 and exactly a discontinuity
// apart, samples not warped (some at NaN positions, as a missing depth leaves them; some far away or
// behind the camera), rows at the view's top and bottom and below it, views narrower than the rows. Every
// level's kernels (one writer's and the threads') against the plain triangles.
TEST(Raster, RectifiedRowsEqualPlainTriangles) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<const QuadRowKernels*> kernels = quadRowKernelsThisCpuRuns();
  ASSERT_FALSE(kernels.empty());
  const double offsets[] = {0.0,        0x1p-30,   -0x1p-30,        1e-9,    -1e-9,         2e-9,
                            -2e-9,      0x1p-21,   -0x1p-21,        0x1p-20, -0x1p-20,      0x1.8p-20,
                            -0x1.8p-20, 0x1p-19,   -0x1p-19,        3e-6,    -3e-6,         0.5};
  const auto snap = [](double v) { return std::nearbyint(v * 0x1p30) * 0x1p-30; };
  size_t raised = 0, cellsChecked = 0;
  for (const double discontinuity : {0.05, 10.0})
  for (const int outWidth : {16, 41, 120})
  for (const int width : {9, 10, 17, 40, 100}) {
    const int outHeight = 5;
    std::vector<double> plain(size_t(outWidth) * outHeight, kEmpty);
    KernelBuffers buffers(kernels, plain.size());
    for (int t = 0; t < 400; ++t) {
      const int row = int(unit(rng) * 6.0);  // 0 .. 5: rows 4 and 5 reach below the view
      const double scales[] = {1.0, 1.0, 1.0, 0.4, 0.9, 1.1, 2.0, 3.0, -1.0};
      const double scale = scales[int(unit(rng) * 9)];
      const double shift = (unit(rng) - 0.5) * 0.6 * outWidth, slope = (unit(rng) - 0.5) * 0.2;
      const int kind = int(unit(rng) * 4);  // 0: smooth, 1: with jumps, 2: near centres, 3: all of it
      std::vector<double> x[2], y[2], w[2];
      double jump = 0.0;
      for (int r = 0; r < 2; ++r) {
        for (int i = 0; i < width; ++i) {
          if ((kind & 1) && unit(rng) < 0.08) jump += (unit(rng) - 0.5) * 12.0;
          double px = scale * i + shift + slope * i * (1 + r) + jump + (kind == 0 ? 0.0 : 0.02 * (unit(rng) - 0.5));
          px = unit(rng) < 0.7 ? snap(px) : px;
          if (kind >= 2 && unit(rng) < 0.35) px = std::round(px) + offsets[size_t(unit(rng) * 18)];
          double py = double(row + r), pw = unit(rng);
          const double u = unit(rng);
          if (u < 0.04) pw = -1.0;
          else if (u < 0.06) pw = -1.0, px = std::nan(""), py = std::nan("");
          else if (u < 0.07) pw = -1.0, px = 1e12 * (unit(rng) - 0.5), py = -7.0;
          else if (u < 0.09) pw = 0.0;
          else if (u < 0.11) pw = -0.0;
          else if (u < 0.14) pw = discontinuity;
          else if (u < 0.5 && i > 0) pw = w[r].back() + (unit(rng) - 0.5) * 0.02;  // one surface
          if (t % 50 == 7 && i == width / 2) py += 1e-9;  // one sample off the row: not rectified
          x[r].push_back(px);
          y[r].push_back(py);
          w[r].push_back(pw);
        }
      }
      rasteriseQuadRowPlainly(plain, width, outWidth, outHeight, discontinuity, x, y, w);
      buffers.draw(width, outWidth, outHeight, discontinuity, x, y, w);
      if (t % 40 != 39) continue;  // compare every 40 rows, then start afresh
      ASSERT_TRUE(buffers.equal(plain)) << "rows of " << width << " into " << outWidth;
      for (size_t i = 0; i < plain.size(); ++i) raised += plain[i] != kEmpty;
      cellsChecked += plain.size();
      buffers.clear(plain);
    }
  }
  EXPECT_GT(raised, cellsChecked / 3);
}

// Rows of a rectified rig whose quads are about a pixel wide, as most are (Synth/Raster.h,
// rectifiedCentresInOrder: each quad's first centre one after the one before): a disparity that steps by
// a whole pixel now and then (quads 0 and 2 pixels wide among those 1 wide), the bottom row a pixel off the
// top one or not, every position a whole number plus one offset per row pair (on the centres, as
// Middlebury's disparities put them; a rounding, a tolerance or about the fast path's 2^-20 off them;
// between them), a few positions off that offset, rows at +0 and -0 (as a projection may give row 0),
// positions at -0 (with depths of -0 there), depths along a surface, across a depth edge, 0, -0 and not
// warped, rows reaching past the view's sides and its bottom. Every level's kernels against the plain
// triangles after each row pair (so that no later row's larger value hides a cell one missed).
TEST(Raster, RectifiedRowsOfPixelWideQuadsEqualPlainTriangles) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<const QuadRowKernels*> kernels = quadRowKernelsThisCpuRuns();
  ASSERT_FALSE(kernels.empty());
  const double offsets[] = {0.0,     0x1p-30,  -0x1p-30,   1e-9,        -1e-9,   2e-9,    -2e-9, 0x1p-21, -0x1p-21,
                            0x1p-20, -0x1p-20, 0x1.8p-20, -0x1.8p-20, 0x1p-19, -0x1p-19, 0.25,  0.5,     0.75};
  const auto pick = [&] { return offsets[size_t(unit(rng) * 18)]; };
  size_t raised = 0, cellsChecked = 0;
  for (const double discontinuity : {0.05, 10.0})
  for (const int outWidth : {16, 41})
  for (const int width : {9, 17, 40}) {
    const int outHeight = 4;
    std::vector<double> plain(size_t(outWidth) * outHeight, kEmpty);
    KernelBuffers buffers(kernels, plain.size());
    for (int t = 0; t < 300; ++t) {
      const int row = int(unit(rng) * 5.0);  // 0 .. 4: row 3's bottom row and row 4 lie below the view
      const bool negativeZero = row == 0 && unit(rng) < 0.5;
      const double offset = unit(rng) < 0.25 ? 0.0 : pick(), shift = std::round((unit(rng) - 0.6) * 0.5 * outWidth);
      const double stepRate = unit(rng) < 0.5 ? 0.0 : 0.1;
      std::vector<double> x[2], y[2], w[2];
      for (int r = 0; r < 2; ++r) {
        double disparity = shift + (r == 1 && unit(rng) < 0.3 ? 1.0 : 0.0), depth = unit(rng);
        for (int i = 0; i < width; ++i) {
          if (unit(rng) < stepRate) disparity += unit(rng) < 0.5 ? 1.0 : -1.0;
          double px = i + disparity + offset;
          if (unit(rng) < 0.05) px += pick();
          if (px == 0.0 && unit(rng) < 0.5) px = -0.0;
          depth += (unit(rng) - 0.5) * 0.02;
          double pw = depth;
          const double u = unit(rng);
          if (u < 0.03) pw = -1.0;
          else if (u < 0.05) pw = 0.0;
          else if (u < 0.07) pw = -0.0;
          else if (u < 0.1) pw = depth + discontinuity;
          // At column 0 of row 0 the zeros' signs of the interpolation reach a depth of -0.
          if (px == 0.0 && unit(rng) < 0.5) pw = -0.0;
          x[r].push_back(px);
          y[r].push_back(negativeZero ? -0.0 : double(row + r));
          w[r].push_back(pw);
        }
      }
      rasteriseQuadRowPlainly(plain, width, outWidth, outHeight, discontinuity, x, y, w);
      buffers.draw(width, outWidth, outHeight, discontinuity, x, y, w);
      ASSERT_TRUE(buffers.equal(plain)) << "rows of " << width << " into " << outWidth << ", row pair " << t;
      for (size_t i = 0; i < plain.size(); ++i) raised += plain[i] != kEmpty;
      cellsChecked += plain.size();
      buffers.clear(plain);
    }
  }
  EXPECT_GT(raised, cellsChecked / 20);
}

// The points of a row (QuadRowKernels::pointsLone, pointsAtomic) at every level this CPU runs, against
// the plain rule: a sample with w not below 0 (NaN included) raises the cell of floor(x + 0.5),
// floor(y + 0.5) when that lies inside the view. Positions round the view's borders and exactly half
// way between centres, samples not warped, rows of every length round the lane counts.
TEST(Raster, PointsEqualThePlainNearestCentreRule) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int outWidth = 9, outHeight = 5;
  const std::vector<const QuadRowKernels*> kernels = quadRowKernelsThisCpuRuns();
  ASSERT_FALSE(kernels.empty());
  for (int width = 1; width <= 19; ++width) {
    std::vector<double> plain(size_t(outWidth) * outHeight, kEmpty);
    std::vector<std::vector<double>> lone(kernels.size(), plain);
    std::vector<AtomicMaxBuffer> shared(kernels.size());
    for (AtomicMaxBuffer& buffer : shared) buffer.reset(plain.size(), kEmpty);
    for (int t = 0; t < 400; ++t) {
      std::vector<double> x(static_cast<size_t>(width)), y = x, w = x;
      // A quarter of the rows a run along one output row (consecutive cells, as a level's run gives on
      // a rectified rig: shifts of whole, half and quarter pixels, some past the row's ends), few holes.
      const bool run = t % 4 == 0;
      const double shift = std::round(unit(rng) * 4 - 3) + 0.25 * std::round(unit(rng) * 3);
      const double runRow = std::floor(unit(rng) * (outHeight + 2)) - 1.0 + 0.25 * std::round(unit(rng) * 3);
      for (int i = 0; i < width; ++i) {
        // -2 to outWidth + 1: outside on both sides; a third exactly between two centres (x.5).
        x[size_t(i)] = unit(rng) < 0.3 ? std::floor(unit(rng) * (outWidth + 3)) - 2.5 : unit(rng) * (outWidth + 3) - 2.0;
        y[size_t(i)] = unit(rng) < 0.3 ? std::floor(unit(rng) * (outHeight + 3)) - 2.5 : unit(rng) * (outHeight + 3) - 2.0;
        const double u = run ? 0.2 + 0.8 * unit(rng) + (unit(rng) < 0.05 ? -1.0 : 0.0) : unit(rng);
        w[size_t(i)] = u < 0.15 ? -1.0 : u < 0.2 ? std::nan("") : u < 0.25 ? 0.0 : unit(rng);
        if (run) {
          x[size_t(i)] = i + shift;
          y[size_t(i)] = runRow;
        }
      }
      for (int i = 0; i < width; ++i) {
        if (w[size_t(i)] < 0) continue;
        const double px = std::floor(x[size_t(i)] + 0.5), py = std::floor(y[size_t(i)] + 0.5);
        if (px < 0 || py < 0 || px >= outWidth || py >= outHeight) continue;
        plain::raise(plain[size_t(py) * outWidth + size_t(px)], w[size_t(i)]);
      }
      for (size_t k = 0; k < kernels.size(); ++k) {
        kernels[k]->pointsLone(lone[k].data(), width, outWidth, outHeight, x.data(), y.data(), w.data());
        kernels[k]->pointsAtomic(shared[k].cells(), width, outWidth, outHeight, x.data(), y.data(), w.data());
      }
    }
    size_t raised = 0;
    for (size_t i = 0; i < plain.size(); ++i) raised += bitsOf(plain[i]) != bitsOf(kEmpty);
    EXPECT_GT(raised, width >= 4 ? plain.size() / 2 : 0);
    for (size_t k = 0; k < kernels.size(); ++k) {
      std::vector<double> fromAtomic(plain.size());
      shared[k].copyTo(0, plain.size(), fromAtomic.data());
      for (size_t i = 0; i < plain.size(); ++i) {
        ASSERT_EQ(bitsOf(plain[i]), bitsOf(lone[k][i])) << "level " << kernels[k]->level << ", row of " << width
                                                        << ", cell " << i;
        ASSERT_EQ(bitsOf(plain[i]), bitsOf(fromAtomic[i])) << "level " << kernels[k]->level << " atomic, row of "
                                                           << width << ", cell " << i;
      }
    }
  }
}

TEST(Raster, LoneRaiseKeepsWhatAtomicRaiseKeeps) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  std::uniform_int_distribution<size_t> cell(0, 63);
  AtomicMaxBuffer atomic;
  atomic.reset(64, kEmpty);
  std::vector<double> lone(64, kEmpty);
  const LoneRaise writer{lone.data()};
  const double special[4] = {0.0, -0.0, 1e-300, -1e-12};
  for (int t = 0; t < 5000; ++t) {
    const size_t i = cell(rng);
    const double v = t % 7 == 0 ? special[t % 4] : value(rng);
    atomic.raise(i, v);
    writer(i, v);
  }
  std::vector<double> a(64);
  atomic.copyTo(0, 64, a.data());
  for (size_t i = 0; i < 64; ++i) EXPECT_EQ(bitsOf(a[i]), bitsOf(lone[i])) << "cell " << i;
}

}  // namespace
}  // namespace vs
