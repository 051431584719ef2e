// The row kernels (Synth/Kernels/Rows.h) of every x86-64 level this binary has and this CPU runs give
// the bits of plain one-sample-at-a-time loops written here from the formulas they implement, on
// rows that include the awkward values: holes, NaN, infinities, -0, ties of the rounding, positions
// far outside any picture, widths that leave vector lanes unfilled. (The golden-output test checks
// the same for whole syntheses, once per level, in scripts/test.sh.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "Common/CpuLevel.h"
#include "Synth/Kernels/Rows.h"

namespace vs {
namespace {

// The kernels of every level this CPU runs that the binary has.
std::vector<const RowKernels*> levels() {
  std::vector<const RowKernels*> kernels;
  for (int level = 0; level <= cpuX86Level(); ++level)
    if (rowKernelsFor(level)) kernels.push_back(rowKernelsFor(level));
  return kernels;
}

uint64_t bitsOf(double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}
uint32_t bitsOf(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// A position rounded to 2^-30 px, as Synth/Warp.h's snapPosition states it: to the nearest multiple
// (ties to even, the default rounding), by division.
double snapPlainly(double position) { return std::nearbyint(position * 1073741824.0) / 1073741824.0; }

constexpr double kInf = std::numeric_limits<double>::infinity();

// Inverse depths and positions with the values that test each branch of the kernels.
std::vector<double> awkwardRow(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> row(static_cast<size_t>(n));
  for (double& value : row) {
    const double u = unit(rng);
    value = u < 0.05   ? -1.0
            : u < 0.08 ? std::nan("")
            : u < 0.10 ? kInf
            : u < 0.12 ? -0.0
            : u < 0.14 ? 0.0
            : u < 0.16 ? 1e300
            : u < 0.18 ? std::round(scale * unit(rng)) + 0.5  // a tie of floor(x + 0.5)
            : u < 0.20 ? -0.5 - 0.5 * unit(rng)  // x + 0.5 in [-0.5, 0]: floor -1 (or -0 at 0)
                       : scale * (2.0 * unit(rng) - 0.5);
  }
  return row;
}

ProjectionCoefficients randomProjection(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ProjectionCoefficients c{};
  for (auto& row : c.m)
    for (double& m : row) m = unit(rng);
  c.m[0][0] += 1.0;
  c.m[1][1] += 1.0;
  c.m[2][2] = 1.0 + 0.01 * unit(rng);
  c.m[2][0] *= 1e-3;
  c.m[2][1] *= 1e-3;
  for (double& o : c.o) o = 50.0 * unit(rng);
  return c;
}

const std::vector<int> kWidths = {1, 2, 3, 7, 8, 9, 15, 16, 17, 33, 100};

TEST(RowKernels, EveryLevelThisCpuRunsIsTested) {
  const std::vector<const RowKernels*> kernels = levels();
  ASSERT_FALSE(kernels.empty());
  for (const RowKernels* k : kernels) EXPECT_LE(k->level, cpuX86Level());
  EXPECT_EQ(&rowKernels(), rowKernelsFor(rowKernels().level));
}

TEST(RowKernels, ForwardRowIsThePlainProjection) {
  std::mt19937 rng(5);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (int trial = 0; trial < 20; ++trial) {
        const ProjectionCoefficients c = randomProjection(rng);
        const double v = double(trial) - 3.0;
        const std::vector<double> w = awkwardRow(rng, n, 0.5);
        std::vector<double> x(static_cast<size_t>(n)), y(static_cast<size_t>(n)), wv(static_cast<size_t>(n));
        kernels->forwardRow(c, w.data(), n, v, x.data(), y.data(), wv.data());
        for (int u = 0; u < n; ++u) {
          const double px = (c.m[0][0] * u + c.m[0][1] * v + c.m[0][2]) + c.o[0] * w[size_t(u)];
          const double py = (c.m[1][0] * u + c.m[1][1] * v + c.m[1][2]) + c.o[1] * w[size_t(u)];
          const double pz = (c.m[2][0] * u + c.m[2][1] * v + c.m[2][2]) + c.o[2] * w[size_t(u)];
          const double ex = snapPlainly(px / pz), ey = snapPlainly(py / pz), ew = w[size_t(u)] / pz;
          const bool ok = w[size_t(u)] >= 0 && pz > 0 && std::fabs(px) <= 1e9 * pz && std::fabs(py) <= 1e9 * pz &&
                          std::isfinite(ex) && std::isfinite(ey) && std::isfinite(ew);
          SCOPED_TRACE(testing::Message() << "level " << kernels->level << " n " << n << " u " << u);
          ASSERT_EQ(bitsOf(wv[size_t(u)]), bitsOf(ok ? ew : -1.0));
          if (ok) {
            ASSERT_EQ(bitsOf(x[size_t(u)]), bitsOf(ex));
            ASSERT_EQ(bitsOf(y[size_t(u)]), bitsOf(ey));
          }
        }
      }
}

TEST(RowKernels, BackwardRowIsThePlainProjection) {
  std::mt19937 rng(6);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const int step : {1, 2})
        for (int trial = 0; trial < 20; ++trial) {
          const ProjectionCoefficients c = randomProjection(rng);
          const double y = 2.5 * trial, start = step == 2 ? 0.5 : 0.0;
          const std::vector<double> w = awkwardRow(rng, n, 0.5);
          std::vector<double> u(static_cast<size_t>(n)), v(static_cast<size_t>(n));
          std::vector<uint8_t> ok(static_cast<size_t>(n));
          kernels->backwardRow(c, w.data(), n, y, u.data(), v.data(), ok.data(), step, start);
          for (int i = 0; i < n; ++i) {
            const double x = i * step + start, wi = w[size_t(i)];
            const double qx = c.m[0][0] * x + c.m[0][1] * y + c.m[0][2] + c.o[0] * wi;
            const double qy = c.m[1][0] * x + c.m[1][1] * y + c.m[1][2] + c.o[1] * wi;
            const double qz = c.m[2][0] * x + c.m[2][1] * y + c.m[2][2] + c.o[2] * wi;
            const double eu = snapPlainly(qx / qz), ev = snapPlainly(qy / qz);
            const bool expected = qz > 0 && std::fabs(qx) <= 1e9 * qz && std::fabs(qy) <= 1e9 * qz &&
                                  std::isfinite(eu) && std::isfinite(ev);
            SCOPED_TRACE(testing::Message() << "level " << kernels->level << " n " << n << " i " << i);
            ASSERT_EQ(ok[size_t(i)], uint8_t(expected));
            if (expected) {
              ASSERT_EQ(bitsOf(u[size_t(i)]), bitsOf(eu));
              ASSERT_EQ(bitsOf(v[size_t(i)]), bitsOf(ev));
            }
          }
        }
}

TEST(RowKernels, RowSourcesAndTargetsAreThePlainRowFormulas) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const double scale : {1.0, 0.5, 0.75}) {  // 0.75: no exact reciprocal, divided
        const double offset = 10.0 * unit(rng) - 5.0, shift = 200.0 * unit(rng) - 100.0;
        const double inverse = scale == 0.75 ? 0.0 : 1.0 / scale;
        const std::vector<double> w = awkwardRow(rng, n, 0.5);
        std::vector<double> u(static_cast<size_t>(n));
        kernels->rowSources(offset, shift, inverse, scale, w.data(), n, u.data(), 2, 0.5);
        for (int i = 0; i < n; ++i) {
          const double shifted = double(i * 2) + 0.5 - offset - shift * w[size_t(i)];
          const double expected = snapPlainly(inverse != 0 ? shifted * inverse : shifted / scale);
          ASSERT_EQ(bitsOf(u[size_t(i)]), bitsOf(expected)) << "level " << kernels->level << " i " << i;
        }
        // Levels 0 .. 9 and one past the table; levels beyond read the last pair.
        std::vector<double> table;
        for (int level = 0; level < 10; ++level) {
          const bool warped = level % 4 != 3;
          table.push_back(warped ? shift * (0.1 * level) : std::nan(""));
          table.push_back(warped ? 0.1 * level : kKernelNoDepth);
        }
        table.push_back(std::nan(""));
        table.push_back(kKernelNoDepth);
        std::vector<uint16_t> levels(static_cast<size_t>(n));
        // Scattered levels in half the rows, runs of one level (up to 20 samples) in the others.
        const bool runs = unit(rng) < 0.5;
        for (size_t i = 0; i < levels.size();) {
          const uint16_t level = uint16_t(unit(rng) < 0.1 ? 60000 : 12 * unit(rng));
          for (size_t run = runs ? 1 + size_t(20 * unit(rng)) : 1; run > 0 && i < levels.size(); --run) levels[i++] = level;
        }
        std::vector<double> xs(static_cast<size_t>(n)), ws(static_cast<size_t>(n));
        kernels->rowTargets(levels.data(), n, table.data(), 10, scale, offset, xs.data(), ws.data());
        for (int x = 0; x < n; ++x) {
          const size_t level = std::min<size_t>(levels[size_t(x)], 10);
          const double target = snapPlainly(scale * x + offset + table[2 * level]);
          ASSERT_EQ(bitsOf(xs[size_t(x)]), bitsOf(target));
          ASSERT_EQ(ws[size_t(x)], std::isfinite(target) ? table[2 * level + 1] : kKernelNoDepth);
        }
      }
}

TEST(RowKernels, RowLookupsAndChromaPositionsRoundToTheNearestGridPosition) {
  std::mt19937 rng(8);
  const int width = 41;
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const double precision : {1.0, 2.0, 4.0}) {
        std::vector<double> x = awkwardRow(rng, n, 40.0), g(static_cast<size_t>(n)), nearest(static_cast<size_t>(n));
        kernels->rowLookups(x.data(), n, precision, width, g.data(), nearest.data());
        std::vector<double> chroma = x, chromaGrid(static_cast<size_t>(n));
        kernels->chromaGridIndices(chroma.data(), n, 0.5, 2.0, precision, chromaGrid.data());
        for (int i = 0; i < n; ++i) {
          // floor(p + 0.5): the grid position at or below p + 1/2 (ties go up).
          const double p = x[size_t(i)] * precision;
          ASSERT_EQ(bitsOf(g[size_t(i)]), bitsOf(std::floor(p + 0.5))) << "level " << kernels->level;
          if (std::isfinite(p) && std::fabs(p) < 1e15) {
            EXPECT_LE(g[size_t(i)], p + 0.5);
            EXPECT_GT(g[size_t(i)] + 1.0, p + 0.5);
          }
          if (x[size_t(i)] >= -0.5 && x[size_t(i)] <= width - 0.5) {
            ASSERT_EQ(nearest[size_t(i)], double(std::clamp(int(std::floor(x[size_t(i)] + 0.5)), 0, width - 1)));
          }
          ASSERT_GE(nearest[size_t(i)], 0.0);
          ASSERT_LE(nearest[size_t(i)], double(width - 1));
          const double position = (x[size_t(i)] - 0.5) / 2.0;
          ASSERT_EQ(bitsOf(chroma[size_t(i)]), bitsOf(position));
          ASSERT_EQ(bitsOf(chromaGrid[size_t(i)]), bitsOf(std::floor(position * precision + 0.5)));
        }
      }
}

TEST(RowKernels, TextureLookupsAreTheGridIndicesAndTheNearestSample) {
  std::mt19937 rng(11);
  const int width = 37, height = 23;
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const double precision : {1.0, 2.0, 4.0}) {
        const std::vector<double> u = awkwardRow(rng, n, width), v = awkwardRow(rng, n, height);
        std::vector<double> gridU(static_cast<size_t>(n)), gridV(static_cast<size_t>(n)), nearest(static_cast<size_t>(n));
        kernels->textureLookups(u.data(), v.data(), n, precision, width, height, gridU.data(), gridV.data(),
                                nearest.data());
        for (int i = 0; i < n; ++i) {
          ASSERT_EQ(bitsOf(gridU[size_t(i)]), bitsOf(std::floor(u[size_t(i)] * precision + 0.5)));
          ASSERT_EQ(bitsOf(gridV[size_t(i)]), bitsOf(std::floor(v[size_t(i)] * precision + 0.5)));
          // The nearest sample of a position in the picture (within half a sample of its border).
          const double x = u[size_t(i)], y = v[size_t(i)];
          if (x >= -0.5 && y >= -0.5 && x <= width - 0.5 && y <= height - 0.5) {
            const int nx = std::clamp(int(std::floor(x + 0.5)), 0, width - 1);
            const int ny = std::clamp(int(std::floor(y + 0.5)), 0, height - 1);
            ASSERT_EQ(nearest[size_t(i)], double(ny * width + nx)) << "level " << kernels->level;
          }
          ASSERT_GE(nearest[size_t(i)], 0.0);
          ASSERT_LT(nearest[size_t(i)], double(width * height));
        }
      }
}

// The general texture warp's row (textureTableRow) against its rule written plainly: holes (depth
// below 0; NaN is not) untouched, failed look-ups (not ok, outside the picture by more than half a
// sample) made holes, look-ups on the row's own reference row whose integer part the tables hold read
// from every channel's table with the nearest sample's edge flag, every other one left to the caller
// in order. Tables narrower than the row (so that some integer parts fall outside), grid indices of
// 2^52 and more, NaN positions; then the same row with the tables not ready: the kernel stops at or
// before the first sample that would read them, having done exactly the samples before, and goes on
// from there once they are. chromaTableRow likewise, with its bounds and edge flags.
TEST(RowKernels, TextureTableRowIsThePlainRule) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int width = 37, height = 23, y = 5;
  int tableReads = 0, restSamples = 0;
  for (const RowKernels* kernels : levels())
    for (const bool chroma : {false, true})  // chromaTableRow: bounds -1 to the size, the edge flag edges[x]
    for (const int n : kWidths)
      for (const int channels : {1, 3})
        for (const int shift : {0, 1, 2}) {
          const double low = chroma ? -1.0 : -0.5, highU = chroma ? width : width - 0.5;
          const double highV = chroma ? height : height - 0.5;
          const auto kernel = chroma ? kernels->chromaTableRow : kernels->textureTableRow;
          const double precision = double(1 << shift), rowGrid = y * precision;
          // Sample positions: a third on the row (v rounds to row y's grid index), the rest awkward.
          std::vector<double> u = awkwardRow(rng, n, width), v = awkwardRow(rng, n, height);
          std::vector<double> depth = awkwardRow(rng, n, 1.0);
          std::vector<uint8_t> ok(static_cast<size_t>(n));
          std::vector<double> gridU(static_cast<size_t>(n)), gridV = gridU, nearest = gridU;
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(i);
            if (unit(rng) < 0.4) v[k] = y + (unit(rng) - 0.5) / precision * 0.99;
            if (unit(rng) < 0.4) u[k] = (width + 1.0) * unit(rng) - 1.0;
            if (unit(rng) < 0.05) u[k] = unit(rng) < 0.5 ? low : highU;  // the picture's bounds exactly
            if (unit(rng) < 0.03) v[k] = unit(rng) < 0.5 ? low : highV;
            if (unit(rng) < 0.03) u[k] = unit(rng) < 0.5 ? -0.75 : width - 0.25;  // inside chroma's only
            ok[k] = unit(rng) < 0.9;
            gridU[k] = std::floor(u[k] * precision + 0.5);
            // Chroma's grid indices are given (the texture's follow from u): some of 2^52 and more.
            if (chroma && unit(rng) < 0.05) gridU[k] = (unit(rng) < 0.5 ? -1.0 : 1.0) * 4503599627370496.0 * (1.0 + unit(rng));
            gridV[k] = std::floor(v[k] * precision + 0.5);
            const double nx = std::isnan(u[k]) ? 0.0 : std::clamp(std::floor(u[k] + 0.5), 0.0, width - 1.0);
            const double ny = std::isnan(v[k]) ? 0.0 : std::clamp(std::floor(v[k] + 0.5), 0.0, height - 1.0);
            nearest[k] = ny * width + nx;
          }
          // Tables holding integer parts 2 to width - 5 (the row's -1 to width - 1 reach past them).
          const long long first = 2, last = width - 5, stride = last - first + 1;
          std::vector<float> tables[3];
          for (std::vector<float>& table : tables)
            for (long long t = 0; t < stride * (1 << shift); ++t) table.push_back(float(255.0 * unit(rng)));
          std::vector<uint8_t> edges(size_t(width) * height);
          for (uint8_t& e : edges) e = uint8_t(unit(rng) < 0.3);
          // The rule, plainly.
          const float unset = -7.0f;
          std::vector<double> plainDepth = depth;
          std::vector<float> plainColour[3];
          for (std::vector<float>& c : plainColour) c.assign(size_t(n), unset);
          std::vector<uint8_t> plainEdge(size_t(n), 9);
          std::vector<int> plainRest;
          int firstOnRow = n;
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(i);
            if (depth[k] < 0) continue;
            if (!ok[k] || u[k] < low || v[k] < low || u[k] > highU || v[k] > highV) {
              plainDepth[k] = -1.0;
              continue;
            }
            if (gridV[k] == rowGrid) firstOnRow = std::min(firstOnRow, i);
            const double g = gridU[k];
            const long long index = std::fabs(g) < 4503599627370496.0 ? (long long)g : 0;
            const long long ix = index / (1 << shift) - (index % (1 << shift) < 0 ? 1 : 0);  // floor division
            if (gridV[k] != rowGrid || !(std::fabs(g) < 4503599627370496.0) || ix < first || ix > last) {
              plainRest.push_back(i);
              continue;
            }
            const long long phase = index - ix * (1 << shift);
            for (int c = 0; c < channels; ++c) plainColour[c][k] = tables[c][size_t(phase * stride + ix - first)];
            plainEdge[k] = chroma ? edges[k] : edges[size_t(nearest[k])];
            ++tableReads;
          }
          // The kernel, first with the tables not ready.
          std::vector<double> ourDepth = depth;
          std::vector<float> ourColour[3];
          for (std::vector<float>& c : ourColour) c.assign(size_t(n), unset);
          std::vector<uint8_t> ourEdge(size_t(n), 9);
          std::vector<int> rest(size_t(n) + 1, -1);
          // The texture's kernel computes its grid indices and nearest samples: it is given none to read.
          TextureTableRow row = {u.data(), v.data(), ok.data(), chroma ? gridU.data() : nullptr,
                                 chroma ? gridV.data() : nullptr, nullptr, precision, rowGrid, highU, highV, {nullptr, nullptr, nullptr}, first, last, stride, shift,
                                 (1 << shift) - 1, channels, edges.data(), ourDepth.data(),
                                 {ourColour[0].data(), ourColour[1].data(), ourColour[2].data()}, ourEdge.data()};
          int count = 0;
          const int stop = kernel(row, 0, n, false, rest.data(), count);
          ASSERT_LE(stop, firstOnRow) << "level " << kernels->level;
          if (firstOnRow == n) {
            ASSERT_EQ(stop, n);
          }
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(i);
            ASSERT_EQ(bitsOf(ourDepth[k]), bitsOf(i < stop ? plainDepth[k] : depth[k])) << "level " << kernels->level;
            ASSERT_EQ(ourEdge[k], i < stop ? plainEdge[k] : 9);
          }
          ASSERT_EQ(std::vector<int>(rest.begin(), rest.begin() + count),
                    std::vector<int>(plainRest.begin(), std::lower_bound(plainRest.begin(), plainRest.end(), stop)));
          // Then ready, from where it stopped.
          for (int c = 0; c < 3; ++c) row.table[c] = tables[c].data();
          ASSERT_EQ(kernel(row, stop, n, true, rest.data(), count), n);
          ASSERT_EQ(std::vector<int>(rest.begin(), rest.begin() + count), plainRest) << "level " << kernels->level;
          ASSERT_EQ(rest[size_t(count)], -1);
          restSamples += count;
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(i);
            ASSERT_EQ(bitsOf(ourDepth[k]), bitsOf(plainDepth[k])) << "level " << kernels->level << ", sample " << i;
            ASSERT_EQ(ourEdge[k], plainEdge[k]) << "level " << kernels->level << ", sample " << i;
            for (int c = 0; c < 3; ++c)
              ASSERT_EQ(bitsOf(ourColour[c][k]), bitsOf(plainColour[c][k]))
                  << "level " << kernels->level << ", channel " << c << ", sample " << i;
          }
        }
  // Every branch reached (per level and kernel, of 1266 samples: about 150 read the tables, 240 are left
  // over).
  EXPECT_GT(tableReads, 2 * 100 * int(levels().size()));
  EXPECT_GT(restSamples, 2 * 150 * int(levels().size()));
}

// The 1D texture warp's row: positions along a reference row of refW samples (some of them 1 to 3
// samples: the edge flags are then not read by four-byte gathers), tables that hold every integer part
// the row reaches ([-1, refW], as the 1D path builds them) or fewer (the rest left to the caller).
// chromaRowTableRow: the bounds -1 and refW (the chroma width), the edge flag the row's own.
TEST(RowKernels, RowTableRowIsThePlainRule) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int tableReads = 0, restSamples = 0, failed = 0;
  for (const RowKernels* kernels : levels())
    for (const bool chroma : {false, true})
    for (const int refW : {1, 2, 3, 4, 37})
      for (const int n : kWidths)
        for (const int channels : {1, 3})
          for (const int shift : {0, 1, 2})
            for (const bool narrow : {false, true}) {
              const int precision = 1 << shift;
              const double low = chroma ? -1.0 : -0.5, lastU = chroma ? refW : refW - 0.5;
              const auto kernel = chroma ? kernels->chromaRowTableRow : kernels->rowTableRow;
              std::vector<double> u = awkwardRow(rng, n, refW), depth = awkwardRow(rng, n, 1.0);
              for (double& x : u) {
                if (unit(rng) < 0.4) x = (refW + 1.0) * unit(rng) - 1.0;
                if (unit(rng) < 0.06) x = unit(rng) < 0.5 ? low : lastU;  // the bounds exactly
                if (unit(rng) < 0.03) x = unit(rng) < 0.5 ? -0.75 : refW - 0.25;  // inside chroma's only
              }
              const long long first = narrow ? 1 : -1, last = narrow ? refW - 2 : refW;
              const long long stride = std::max(1LL, last - first + 1);
              std::vector<float> tables[3];
              for (std::vector<float>& table : tables)
                for (long long t = 0; t < stride * precision; ++t) table.push_back(float(255.0 * unit(rng)));
              std::vector<uint8_t> edges(static_cast<size_t>(refW));  // exactly the row: a read past it is a fault under ASan
              for (uint8_t& e : edges) e = uint8_t(1 + 254 * unit(rng));
              std::vector<uint8_t> blockEdges(static_cast<size_t>(n));  // chroma's: the row's own
              for (uint8_t& e : blockEdges) e = uint8_t(1 + 254 * unit(rng));
              // The rule, plainly.
              const float unset = -7.0f;
              std::vector<double> plainDepth = depth;
              std::vector<float> plainColour[3];
              for (std::vector<float>& c : plainColour) c.assign(size_t(n), unset);
              std::vector<uint8_t> plainEdge(size_t(n), 0);
              std::vector<int> plainRest;
              for (int i = 0; i < n; ++i) {
                const size_t k = size_t(i);
                if (depth[k] < 0) continue;
                if (std::isnan(u[k]) || u[k] < low || u[k] > lastU) {
                  plainDepth[k] = -1.0;
                  ++failed;
                  continue;
                }
                plainEdge[k] = chroma ? blockEdges[k] : edges[size_t(std::clamp(std::floor(u[k] + 0.5), 0.0, refW - 1.0))];
                const double g = std::floor(u[k] * precision + 0.5);
                const double ix = std::floor(g / precision), phase = g - ix * precision;
                if (ix < double(first) || ix > double(last)) {
                  plainRest.push_back(i);
                  continue;
                }
                for (int c = 0; c < channels; ++c)
                  plainColour[c][k] = tables[c][size_t(phase * double(stride) + ix - double(first))];
                ++tableReads;
              }
              std::vector<double> ourDepth = depth;
              std::vector<float> ourColour[3];
              for (std::vector<float>& c : ourColour) c.assign(size_t(n), unset);
              std::vector<uint8_t> ourEdge(size_t(n), 0);
              std::vector<int> rest(size_t(n) + 1, -1);
              const RowTableRow row = {u.data(), double(precision), lastU, refW - 1.0,
                                       {tables[0].data(), tables[1].data(), tables[2].data()}, first, last, stride,
                                       shift, precision - 1, channels, chroma ? blockEdges.data() : edges.data(),
                                       ourDepth.data(),
                                       {ourColour[0].data(), ourColour[1].data(), ourColour[2].data()}, ourEdge.data()};
              int count = 0;
              kernel(row, n, rest.data(), count);
              ASSERT_EQ(std::vector<int>(rest.begin(), rest.begin() + count), plainRest) << "level " << kernels->level;
              ASSERT_EQ(rest[size_t(count)], -1);
              restSamples += count;
              for (int i = 0; i < n; ++i) {
                const size_t k = size_t(i);
                ASSERT_EQ(bitsOf(ourDepth[k]), bitsOf(plainDepth[k])) << "level " << kernels->level << ", sample " << i;
                ASSERT_EQ(ourEdge[k], plainEdge[k]) << "level " << kernels->level << ", sample " << i << ", u " << u[k];
                for (int c = 0; c < 3; ++c)
                  ASSERT_EQ(bitsOf(ourColour[c][k]), bitsOf(plainColour[c][k]))
                      << "level " << kernels->level << ", channel " << c << ", sample " << i;
              }
            }
  // Every branch reached on every level.
  const int levelCount = int(levels().size());
  EXPECT_GT(tableReads, 2 * 1000 * levelCount);
  EXPECT_GT(restSamples, 2 * 100 * levelCount);
  EXPECT_GT(failed, 2 * 100 * levelCount);
}

TEST(RowKernels, SampleRowPhaseIsTheWeightedSumInTapOrder) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> sample(0, 65535);
  std::uniform_real_distribution<float> weight(-0.3f, 1.0f);
  for (const RowKernels* kernels : levels())
    for (const int taps : {2, 4, 6})
      for (const int n : kWidths) {
        std::vector<uint16_t> row(size_t(n + taps));
        for (uint16_t& s : row) s = uint16_t(sample(rng));
        float k[6];
        for (float& w : k) w = weight(rng);
        std::vector<float> out(static_cast<size_t>(n));
        std::vector<float> copy(static_cast<size_t>(n));
        kernels->sampleRowPhase0(row.data(), n, copy.data());
        for (int i = 0; i < n; ++i) ASSERT_EQ(copy[size_t(i)], float(row[size_t(i)]));
        auto phase = taps == 2 ? kernels->sampleRowPhase2 : taps == 4 ? kernels->sampleRowPhase4 : kernels->sampleRowPhase6;
        phase(row.data(), k, n, out.data());
        for (int i = 0; i < n; ++i) {
          float sum = 0.0f;
          for (int t = 0; t < taps; ++t) {
            const float term = k[t] * float(row[size_t(i + t)]);
            sum = sum + term;
          }
          ASSERT_EQ(bitsOf(out[size_t(i)]), bitsOf(sum)) << "level " << kernels->level << " taps " << taps;
        }
        // From the taps as floats (a table's phase 0): the same sums, bit for bit.
        std::vector<float> fromFloats(static_cast<size_t>(n), -1.0f), floats(row.begin(), row.end());
        auto floatPhase = taps == 2   ? kernels->sampleFloatRowPhase2
                          : taps == 4 ? kernels->sampleFloatRowPhase4
                                      : kernels->sampleFloatRowPhase6;
        floatPhase(floats.data(), k, n, fromFloats.data());
        for (int i = 0; i < n; ++i)
          ASSERT_EQ(bitsOf(fromFloats[size_t(i)]), bitsOf(out[size_t(i)])) << "level " << kernels->level << " taps " << taps;
      }
}

TEST(RowKernels, HoleCountsAndTheWindowCountHolesAroundEachSample) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const RowKernels* kernels : levels())
    for (const int width : kWidths) {
      // Seven rows of depths, a hole in about half the samples; their counts, then the window's sum.
      const int rows = 7;
      std::vector<double> depth(size_t(rows) * width);
      for (double& d : depth) d = unit(rng) < 0.5 ? -1.0 : unit(rng);
      std::vector<uint8_t> counts(depth.size()), padded(size_t(width) + 6, 0), sum(size_t(width), 0);
      for (int r = 0; r < rows; ++r)
        kernels->holeCounts(depth.data() + size_t(r) * width, width, padded.data(), counts.data() + size_t(r) * width);
      for (int r = 0; r < rows; ++r)
        for (int x = 0; x < width; ++x) {
          int holes = 0;
          for (int k = std::max(0, x - 3); k <= std::min(width - 1, x + 3); ++k) holes += depth[size_t(r) * width + k] < 0;
          ASSERT_EQ(counts[size_t(r) * width + x], holes) << "level " << kernels->level;
        }
      // Rows 0 .. 5 entered, then row 6 enters and row 0 leaves: the sum of rows 1 .. 6, marked above 20.
      for (int r = 0; r < 6; ++r) kernels->windowStep(sum.data(), counts.data() + size_t(r) * width, nullptr, nullptr, width, 20);
      std::vector<uint8_t> edge(static_cast<size_t>(width));
      for (int x = 0; x < width; ++x) edge[size_t(x)] = uint8_t(x % 5 == 0);
      const std::vector<uint8_t> before = edge;
      kernels->windowStep(sum.data(), counts.data() + 6 * size_t(width), counts.data(), edge.data(), width, 20);
      for (int x = 0; x < width; ++x) {
        int total = 0;
        for (int r = 1; r < rows; ++r) total += counts[size_t(r) * width + x];
        ASSERT_EQ(sum[size_t(x)], total);
        ASSERT_EQ(edge[size_t(x)], uint8_t(before[size_t(x)] | (total > 20)));
      }
    }
}

// The reference depth steps against the rule written plainly (a neighbour beyond the row's ends is the
// sample itself), on rows of levels that differ by about the step, with missing samples, at 8 and 16
// bits, with a missing level of 0, of another value and none (-1), and steps the 16-bit loop cannot
// hold.
TEST(RowKernels, ReferenceStepsAreThePlainRule) {
  std::mt19937 rng(14);
  for (const RowKernels* kernels : levels())
    for (const int width : kWidths)
      for (const int maxLevel : {255, 65535})
        for (const int missing : {0, 7, -1, 65535})
          for (const int minStep : {1, 10, 3000, 0, 70000}) {
            std::uniform_int_distribution<int> level(0, maxLevel), small(0, 2 * std::min(minStep, 20) + 1);
            std::vector<uint16_t> rows(3 * size_t(width));
            for (size_t i = 0; i < rows.size(); ++i) {
              // Mostly near the previous level (within about the step), sometimes far or missing.
              const int roll = small(rng);
              const int previous = i > 0 ? rows[i - 1] : level(rng);
              int value = roll == 0 ? level(rng) : std::min(maxLevel, std::max(0, previous + roll - std::min(minStep, 20)));
              if (roll == 1 && missing >= 0 && missing <= maxLevel) value = missing;
              rows[i] = uint16_t(value);
            }
            const uint16_t* above = rows.data();
            const uint16_t* row = above + width;
            const uint16_t* below = row + width;
            std::vector<uint8_t> step(size_t(width), 99);
            kernels->referenceSteps(row, above, below, width, missing, minStep, step.data());
            for (int x = 0; x < width; ++x) {
              const int self = row[x];
              const int neighbours[4] = {x > 0 ? row[x - 1] : self, x + 1 < width ? row[x + 1] : self, above[x], below[x]};
              bool expected = self == missing;
              for (const int other : neighbours) expected = expected || other == missing || std::abs(self - other) >= minStep;
              ASSERT_EQ(step[size_t(x)], uint8_t(expected))
                  << "level " << kernels->level << " width " << width << " x " << x << " missing " << missing
                  << " minStep " << minStep;
            }
          }
}

// Depth edge alignment's edge pairs against the rule written plainly, with the same levels as above.
TEST(RowKernels, DepthEdgePairsAreThePlainRule) {
  std::mt19937 rng(15);
  for (const RowKernels* kernels : levels())
    for (const int width : kWidths)
      for (const int maxLevel : {255, 65535})
        for (const int missing : {0, 7, -1, 65535})
          for (const int minStep : {1, 10, 3000, 0, 70000}) {
            std::uniform_int_distribution<int> level(0, maxLevel), small(0, 2 * std::min(minStep, 20) + 1);
            std::vector<uint16_t> a(static_cast<size_t>(width)), b(static_cast<size_t>(width));
            for (int x = 0; x < width; ++x) {
              a[size_t(x)] = uint16_t(small(rng) == 0 ? level(rng) : x > 0 ? a[size_t(x) - 1] : level(rng));
              const int roll = small(rng);
              int value = roll == 0 ? level(rng) : std::min(maxLevel, std::max(0, a[size_t(x)] + roll - std::min(minStep, 20)));
              if (roll == 1 && missing >= 0 && missing <= maxLevel) value = missing;
              b[size_t(x)] = uint16_t(value);
              if (small(rng) == 1 && missing >= 0 && missing <= maxLevel) a[size_t(x)] = uint16_t(missing);
            }
            std::vector<uint8_t> flags(static_cast<size_t>(width), 99);
            kernels->depthEdgePairs(a.data(), b.data(), width, missing, minStep, flags.data());
            for (int x = 0; x < width; ++x) {
              const int p = a[size_t(x)], q = b[size_t(x)];
              const bool expected = p != missing && q != missing && std::abs(p - q) >= minStep;
              ASSERT_EQ(flags[size_t(x)], uint8_t(expected))
                  << "level " << kernels->level << " width " << width << " x " << x << " missing " << missing
                  << " minStep " << minStep;
            }
          }
}

// Crack closing's candidates against the comparison written plainly, on rows with holes, NaN,
// infinities and -0 (awkwardRow), limits of 0 and above.
TEST(RowKernels, BehindFlagsAreThePlainComparison) {
  std::mt19937 rng(16);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const double limit : {0.0, 0.01, 0.5, kInf}) {
        const std::vector<double> front = awkwardRow(rng, n, 3.0), behind = awkwardRow(rng, n, 3.0);
        std::vector<uint8_t> flags(static_cast<size_t>(n), 99);
        kernels->behindFlags(front.data(), behind.data(), n, limit, flags.data());
        for (int i = 0; i < n; ++i)
          ASSERT_EQ(flags[size_t(i)], uint8_t(behind[size_t(i)] < front[size_t(i)] - limit))
              << "level " << kernels->level << " n " << n << " i " << i;
      }
}

// The chroma warp's 2x2 blocks against its rule written plainly: the front is the largest depth of the
// block (a hole's -1 if none is larger); the samples within `surface` of it (holes and NaN never) give
// their mean depth, added in the block's order, and their edge flags OR-ed.
TEST(RowKernels, ChromaBlocksAreTheFrontSurfacesMean) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const double surface : {0.0, 0.25, 0.5, kInf}) {
        // Awkward rows, and rows of quarters (front - d == surface exactly) with holes.
        for (const bool quarters : {false, true}) {
          std::vector<double> top = awkwardRow(rng, 2 * n, 3.0), bottom = awkwardRow(rng, 2 * n, 3.0);
          if (quarters)
            for (auto* row : {&top, &bottom})
              for (double& d : *row) d = unit(rng) < 0.2 ? -1.0 : 0.25 * std::floor(8.0 * unit(rng));
          std::vector<uint8_t> edgeTop(size_t(2 * n)), edgeBottom(size_t(2 * n));
          for (auto* row : {&edgeTop, &edgeBottom})
            for (uint8_t& e : *row) e = uint8_t(unit(rng) < 0.5 ? 0 : unit(rng) < 0.5 ? 1 : byte(rng));
          std::vector<double> depth(static_cast<size_t>(n), 99.0);
          std::vector<uint8_t> edge(static_cast<size_t>(n), 99);
          kernels->chromaBlocks(top.data(), bottom.data(), edgeTop.data(), edgeBottom.data(), n, surface, depth.data(),
                                edge.data());
          for (int i = 0; i < n; ++i) {
            const double d[4] = {top[size_t(2 * i)], top[size_t(2 * i + 1)], bottom[size_t(2 * i)],
                                 bottom[size_t(2 * i + 1)]};
            const uint8_t e[4] = {edgeTop[size_t(2 * i)], edgeTop[size_t(2 * i + 1)], edgeBottom[size_t(2 * i)],
                                  edgeBottom[size_t(2 * i + 1)]};
            double front = -1.0;
            for (const double value : d)
              if (value > front) front = value;
            double sum = 0.0;
            int count = 0;
            uint8_t flags = 0;
            for (int k = 0; k < 4; ++k)
              if (d[k] >= 0 && front - d[k] <= surface) {
                sum += d[k];
                ++count;
                flags = uint8_t(flags | e[k]);
              }
            const double expected = front < 0 ? -1.0 : count == 0 ? sum : sum / count;
            ASSERT_EQ(bitsOf(depth[size_t(i)]), bitsOf(expected)) << "level " << kernels->level << " n " << n << " i " << i;
            ASSERT_EQ(edge[size_t(i)], flags) << "level " << kernels->level << " n " << n << " i " << i;
          }
        }
      }
}

// The two-view blend against blendViews' rule written plainly: the nearest valid view's surface,
// clean samples preferred, the weighted mean of the views on it (or the heaviest alone, or a view of
// weight 1 wherever it is valid).
TEST(RowKernels, TwoViewBlendIsThePlainRule) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<const RowKernels*> kernels = levels();
  for (const int channels : {1, 2, 3})
    for (const bool nearestOnly : {false, true})
      for (const int dominant : {-1, 0, 1})
        for (const int n : kWidths) {
          std::vector<double> depth[2];
          std::vector<uint8_t> edge[2];
          std::vector<float> colour[2][3];
          for (int view = 0; view < 2; ++view) {
            for (int i = 0; i < n; ++i) {
              const double u = unit(rng);
              depth[view].push_back(u < 0.2 ? -1.0 : u < 0.3 ? 0.5 : u < 0.35 ? 0.501 : unit(rng));
              edge[view].push_back(uint8_t(unit(rng) < 0.3));
              for (int c = 0; c < 3; ++c) colour[view][c].push_back(float(255.0 * unit(rng)));
            }
          }
          const double weight[2] = {dominant == 0 ? 1.0 : 0.3 + 0.2 * unit(rng), dominant == 1 ? 1.0 : 0.3 + 0.2 * unit(rng)};
          const double tolerance = 0.01;
          TwoViewBlendRows rows{};
          rows.depth0 = depth[0].data();
          rows.depth1 = depth[1].data();
          rows.edge0 = edge[0].data();
          rows.edge1 = edge[1].data();
          for (int c = 0; c < 3; ++c) {
            rows.colour0[c] = colour[0][c].data();
            rows.colour1[c] = colour[1][c].data();
          }
          rows.weight0 = weight[0];
          rows.weight1 = weight[1];
          rows.tolerance = tolerance;
          rows.floatWeight0 = float(weight[0]);
          rows.floatWeight1 = float(weight[1]);
          rows.dominantFirst = dominant == 0;
          rows.dominantSecond = dominant == 1;
          rows.pickFirstAlone = true;
          rows.pickSecondAlone = true;
          rows.pickSecondOfBoth = weight[1] > weight[0];
          rows.plain = dominant < 0;
          for (const RowKernels* k : kernels) {
            std::vector<float> out[3];
            for (auto& plane : out) plane.assign(size_t(n), -7.0f);
            std::vector<double> depthOut(size_t(n), -7.0);
            std::vector<uint8_t> holeOut(size_t(n), 7);
            for (int c = 0; c < 3; ++c) rows.colourOut[c] = out[c].data();
            rows.depthOut = depthOut.data();
            rows.holeOut = holeOut.data();
            ASSERT_FALSE(k->blendTwoViews[channels - 1][nearestOnly](rows, 0, size_t(n)));
            for (int i = 0; i < n; ++i) {
              SCOPED_TRACE(testing::Message() << "level " << k->level << " channels " << channels << " nearest "
                                              << nearestOnly << " dominant " << dominant << " i " << i);
              const double d[2] = {depth[0][size_t(i)], depth[1][size_t(i)]};
              if (d[0] < 0 && d[1] < 0) {
                ASSERT_EQ(holeOut[size_t(i)], 1);
                ASSERT_EQ(depthOut[size_t(i)], kKernelNoDepth);
                for (int c = 0; c < channels; ++c) ASSERT_EQ(out[c][size_t(i)], 0.0f);
                continue;
              }
              ASSERT_EQ(holeOut[size_t(i)], 0);
              if (dominant >= 0 && d[dominant] >= 0) {
                ASSERT_EQ(depthOut[size_t(i)], d[dominant]);
                for (int c = 0; c < channels; ++c) ASSERT_EQ(out[c][size_t(i)], colour[dominant][c][size_t(i)]);
                continue;
              }
              const double nearest = std::max(d[0], d[1]);
              bool on[2], anyClean = false;
              for (int v = 0; v < 2; ++v) {
                on[v] = d[v] >= 0 && nearest - d[v] <= tolerance;
                anyClean = anyClean || (on[v] && !edge[v][size_t(i)]);
              }
              for (int v = 0; v < 2; ++v) on[v] = on[v] && !(anyClean && edge[v][size_t(i)]);
              ASSERT_TRUE(on[0] || on[1]);
              const int best = on[0] && on[1] ? (weight[1] > weight[0] ? 1 : 0) : on[0] ? 0 : 1;
              if (nearestOnly) {
                ASSERT_EQ(depthOut[size_t(i)], d[best]);
                for (int c = 0; c < channels; ++c) ASSERT_EQ(out[c][size_t(i)], colour[best][c][size_t(i)]);
                continue;
              }
              double weightSum = 0, depthSum = 0;
              float colourSum[3] = {0, 0, 0};
              for (int v = 0; v < 2; ++v) {
                if (!on[v]) continue;
                weightSum += weight[v];
                depthSum += weight[v] * d[v];
                for (int c = 0; c < channels; ++c) colourSum[c] += float(weight[v]) * colour[v][c][size_t(i)];
              }
              ASSERT_EQ(bitsOf(depthOut[size_t(i)]), bitsOf(depthSum / weightSum));
              for (int c = 0; c < channels; ++c)
                ASSERT_EQ(bitsOf(out[c][size_t(i)]), bitsOf(float(colourSum[c] / weightSum)));
            }
          }
        }
}

// The 1D depth warp's points against the rule written plainly: a sample with depth not below 0 (NaN
// included) raises the cell of its nearest pixel centre floor(x + 0.5) when that lies in [0, outWidth),
// keeping the larger bits as a signed 64-bit integer. Positions are finite where the depth is not below
// 0 (rowTargets makes them so), with ties at x.5 and centres just outside the row; z holds holes,
// values and negative values already.
TEST(RowKernels, RowPointsRaiseTheNearestCentre) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths)
      for (const int outWidth : {1, 5, n, n + 9})
        for (const bool runs : {false, true}) {
          // Scattered positions, or runs of one displacement (consecutive cells, as a level's run gives:
          // shifts of whole, half and quarter pixels, some past either end of the row) with few holes.
          const double shift = std::round(unit(rng) * 8 - 4) + 0.25 * std::round(unit(rng) * 3);
          std::vector<double> xs(static_cast<size_t>(n)), ws(static_cast<size_t>(n));
          for (int x = 0; x < n; ++x) {
            const double u = unit(rng);
            xs[size_t(x)] = runs       ? x + shift
                            : u < 0.2 ? std::round(unit(rng) * (outWidth + 4) - 2) + 0.5  // ties
                                      : unit(rng) * (outWidth + 4) - 2;
            const double v = runs ? 0.2 + 0.8 * unit(rng) + (unit(rng) < 0.05 ? -1.0 : 0.0) : unit(rng);
            ws[size_t(x)] = v < 0.2 ? kKernelNoDepth : v < 0.25 ? -0.0 : v < 0.3 ? 0.0 : v < 0.33 ? std::nan("")
                                                                                       : unit(rng);
            if (ws[size_t(x)] < 0) xs[size_t(x)] = v < 0.1 ? std::nan("") : kInf;  // not read
          }
          std::vector<double> z(static_cast<size_t>(outWidth));
          for (double& v : z) {
            const double u = unit(rng);
            v = u < 0.5 ? kKernelNoDepth : u < 0.6 ? -unit(rng) : unit(rng);
          }
          std::vector<double> expected = z;
          for (int x = 0; x < n; ++x) {
            if (ws[size_t(x)] < 0) continue;
            const double px = std::floor(xs[size_t(x)] + 0.5);
            if (px < 0 || px >= outWidth) continue;
            double& cell = expected[size_t(px)];
            if (int64_t(bitsOf(ws[size_t(x)])) > int64_t(bitsOf(cell))) cell = ws[size_t(x)];
          }
          kernels->rowPoints(xs.data(), ws.data(), n, z.data(), outWidth);
          for (int i = 0; i < outWidth; ++i)
            ASSERT_EQ(bitsOf(z[size_t(i)]), bitsOf(expected[size_t(i)]))
                << "level " << kernels->level << " n " << n << " out " << outWidth << " i " << i;
        }
}

// CleanNoiseOption's isolated samples against the rule written plainly, on rows with holes, NaN,
// infinities and -0; the row's first and last flags are left as they were.
TEST(RowKernels, IsolatedSamplesAreThePlainRule) {
  std::mt19937 rng(22);
  for (const RowKernels* kernels : levels())
    for (const int n : kWidths) {
      const std::vector<double> row = awkwardRow(rng, n, 3.0);
      std::vector<uint8_t> flags(static_cast<size_t>(n), 99);
      kernels->isolatedSamples(row.data(), n, flags.data());
      for (int x = 0; x < n; ++x) {
        const bool inside = x >= 1 && x + 1 < n;
        const uint8_t expected = inside ? uint8_t(row[size_t(x)] >= 0 && row[size_t(x) - 1] < 0 && row[size_t(x) + 1] < 0)
                                        : 99;
        ASSERT_EQ(flags[size_t(x)], expected) << "level " << kernels->level << " n " << n << " x " << x;
      }
    }
}

// Inverse depths for the occlusion rule's scans: holes, NaN, -0, +0 and others.
std::vector<double> occlusionRow(std::mt19937& rng, int n, double holes) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> row(static_cast<size_t>(n));
  for (double& d : row) {
    const double u = unit(rng);
    d = u < holes ? kKernelNoDepth : u < holes + 0.05 ? std::nan("") : u < holes + 0.1 ? -0.0 : u < holes + 0.12 ? 0.0 : unit(rng);
  }
  return row;
}

const std::vector<int> kOcclusionWidths = {1, 2, 3, 7, 8, 9, 15, 16, 17, 33, 100, 333};

// The occlusion rule's pass down the columns of two views against the rule written plainly (as
// Synth/Occlusion.cpp had it: the candidates in a pass of their own, the other view's last above each
// taken before the row updates the lasts), with either view unable to hold candidates (its "view" is
// none), rows of many and of few holes; nothing is written past up[n).
TEST(RowKernels, OcclusionPassDownIsThePlainRule) {
  std::mt19937 rng(23);
  for (const RowKernels* kernels : levels())
    for (const int n : kOcclusionWidths)
      for (const double holes : {0.02, 0.3, 0.6})
        for (const uint8_t first : {uint8_t(0), uint8_t(255)})
          for (const uint8_t second : {uint8_t(1), uint8_t(255)}) {
            const std::vector<double> row0 = occlusionRow(rng, n, holes), row1 = occlusionRow(rng, n, holes);
            const std::vector<double> last0 = occlusionRow(rng, n, 0.3), last1 = occlusionRow(rng, n, 0.3);
            std::vector<uint8_t> sole(static_cast<size_t>(n), 77);
            std::vector<double> l0 = last0, l1 = last1, up(static_cast<size_t>(n) + 1, 1234.5);
            const int count = kernels->occlusionDown(row0.data(), row1.data(), first, second, 255, sole.data(), l0.data(),
                                                     l1.data(), up.data(), n);
            std::vector<double> expectedUp;
            for (int x = 0; x < n; ++x) {
              const size_t i = size_t(x);
              const bool v0 = row0[i] >= 0.0, v1 = row1[i] >= 0.0;
              const uint8_t view = v0 && !v1 ? first : v1 && !v0 ? second : 255;
              ASSERT_EQ(sole[i], view) << "level " << kernels->level << " n " << n << " x " << x;
              if (view != 255) expectedUp.push_back(view == 1 ? last0[i] : last1[i]);
              ASSERT_EQ(bitsOf(l0[i]), bitsOf(v0 ? row0[i] : last0[i])) << "level " << kernels->level << " x " << x;
              ASSERT_EQ(bitsOf(l1[i]), bitsOf(v1 ? row1[i] : last1[i])) << "level " << kernels->level << " x " << x;
            }
            ASSERT_EQ(count, int(expectedUp.size())) << "level " << kernels->level << " n " << n;
            for (size_t k = 0; k < expectedUp.size(); ++k)
              ASSERT_EQ(bitsOf(up[k]), bitsOf(expectedUp[k])) << "level " << kernels->level << " n " << n << " k " << k;
            ASSERT_EQ(up[size_t(n)], 1234.5) << "level " << kernels->level << " n " << n;  // up[0, n) only
          }
}

// The occlusion rule's pass up the columns of two views against the loop written plainly (as
// Synth/Occlusion.cpp had it, a candidate at a time, the samples above read from a whole row): rows
// with holes and NaN, lasts with holes, surroundings of HUGE_VAL (none) and NaN where no candidate
// lies (never to be read there), candidates marked 0 and 1 among other bytes (255, 2, 128), the row's
// packed samples above after other rows' (not to be read).
TEST(RowKernels, OcclusionPassUpIsThePlainRule) {
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const RowKernels* kernels : levels())
    for (const int n : kOcclusionWidths)
      for (const double candidates : {0.02, 0.5})
        for (const double steps : {0.0, 0.1, 0.5}) {
          std::vector<uint8_t> sole(static_cast<size_t>(n));
          for (uint8_t& k : sole) {
            const double u = unit(rng);
            k = u < candidates / 2 ? 0 : u < candidates ? 1 : u < 0.8 ? 255 : u < 0.9 ? 2 : 128;
          }
          const std::vector<double> row0 = occlusionRow(rng, n, 0.3), row1 = occlusionRow(rng, n, 0.3);
          const std::vector<double> last0 = occlusionRow(rng, n, 0.3), last1 = occlusionRow(rng, n, 0.3);
          const std::vector<double> upRow = occlusionRow(rng, n, 0.3);  // the sample above each candidate
          std::vector<double> around(static_cast<size_t>(n));
          std::vector<double> packed = {std::nan(""), -7.0, 3.0};  // another row's
          for (int x = 0; x < n; ++x) {
            const bool candidate = sole[size_t(x)] <= 1;
            around[size_t(x)] = !candidate ? std::nan("") : unit(rng) < 0.2 ? HUGE_VAL : unit(rng);
            if (candidate) packed.push_back(upRow[size_t(x)]);
          }
          std::vector<double> r0 = row0, r1 = row1, l0 = last0, l1 = last1;
          std::vector<double> working(static_cast<size_t>(n), std::nan(""));
          const int used = kernels->occlusionUp(sole.data(), r0.data(), r1.data(), l0.data(), l1.data(),
                                                packed.data() + packed.size(), around.data(), steps, n, working.data());
          ASSERT_EQ(used, int(packed.size()) - 3) << "level " << kernels->level << " n " << n;
          std::vector<double> e0 = row0, e1 = row1, el0 = last0, el1 = last1;
          int dropped = 0;
          for (int x = 0; x < n; ++x) {
            const size_t i = size_t(x);
            const double below0 = el0[i], below1 = el1[i];
            const double value0 = e0[i], value1 = e1[i];
            if (value0 >= 0.0) el0[i] = value0;
            if (value1 >= 0.0) el1[i] = value1;
            const uint8_t k = sole[i];
            if (k > 1) continue;
            const double below = k == 1 ? below0 : below1, own = k == 1 ? value1 : value0, above = upRow[i];
            double farthest = around[i];
            if (below >= 0.0 && above >= 0.0) farthest = std::min(farthest, std::min(below, above));
            if (farthest != HUGE_VAL && own < farthest - steps) {
              (k == 1 ? e1 : e0)[i] = kKernelNoDepth;
              ++dropped;
            }
          }
          for (int x = 0; x < n; ++x) {
            const size_t i = size_t(x);
            ASSERT_EQ(bitsOf(r0[i]), bitsOf(e0[i])) << "level " << kernels->level << " n " << n << " x " << x;
            ASSERT_EQ(bitsOf(r1[i]), bitsOf(e1[i])) << "level " << kernels->level << " n " << n << " x " << x;
            ASSERT_EQ(bitsOf(l0[i]), bitsOf(el0[i])) << "level " << kernels->level << " n " << n << " x " << x;
            ASSERT_EQ(bitsOf(l1[i]), bitsOf(el1[i])) << "level " << kernels->level << " n " << n << " x " << x;
          }
          if (n >= 100 && candidates > 0.1) {
            EXPECT_GT(dropped, 0) << "the rows drop some candidates";
          }
        }
}

}  // namespace
}  // namespace vs
