// Crack closing (Synth/Cracks.h) against the plain sequential pass it must equal: every row from
// left to right, then every column from top to bottom, each sample tested on the current values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>


#include "Synth/Parallel.h"
#include "Synth/Cracks.h"
#include "Synth/Layer.h"

namespace vs {
namespace {

void closeCracksOneByOne(std::vector<double>& z, int width, int height, double tolerance) {
  auto close = [&](size_t a, size_t gap1, size_t gap2, size_t b, bool two) {
    const double wa = z[a], wb = z[b];
    if (wa < 0 || wb < 0 || std::fabs(wa - wb) > tolerance) return false;
    const double behind = std::min(wa, wb) - tolerance;
    if (!(z[gap1] < behind) || (two && !(z[gap2] < behind))) return false;
    if (two) {
      z[gap1] = (2 * wa + wb) / 3;
      z[gap2] = (wa + 2 * wb) / 3;
    } else {
      z[gap1] = 0.5 * (wa + wb);
    }
    return true;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (!(z[i] < z[i - 1] - tolerance)) continue;
      if (!close(i - 1, i, i, i + 1, false) && x + 2 < width) close(i - 1, i, i + 1, i + 2, true);
    }
  for (int x = 0; x < width; ++x)
    for (int y = 1; y + 1 < height; ++y) {
      const size_t i = size_t(y) * width + x, up = i - width, down = i + width;
      if (!(z[i] < z[up] - tolerance)) continue;
      if (!close(up, i, i, down, false) && y + 2 < height) close(up, i, down, down + width, true);
    }
}

TEST(Cracks, ClosingEqualsTheSequentialPassForAnyThreadCount) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int defaultThreads = vs::workerThreads();
  size_t changed = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int w = 1 + int(unit(rng) * 50), h = 1 + int(unit(rng) * 40);
    // Surfaces on a 1/32 grid (ties with the tolerance occur), with holes and far slivers of one to
    // three samples along rows and columns, and runs of cracks next to each other.
    std::vector<double> z(size_t(w) * h);
    const double base = std::round(8 + 16 * unit(rng)) / 32;
    for (double& v : z) v = base + std::round(4 * unit(rng)) / 32;
    const int gaps = int(unit(rng) * w * h / 3);
    for (int g = 0; g < gaps; ++g) {
      const int x = int(unit(rng) * w), y = int(unit(rng) * h), length = 1 + int(unit(rng) * 3);
      const bool alongRow = unit(rng) < 0.5;
      const double value = unit(rng) < 0.5 ? kNoDepth : std::round(4 * unit(rng)) / 32;
      for (int k = 0; k < length; ++k) {
        const int px = alongRow ? x + k : x, py = alongRow ? y : y + k;
        if (px < w && py < h) z[size_t(py) * w + px] = value;
      }
    }
    const double tolerance = std::round(1 + 4 * unit(rng)) / 32;
    std::vector<double> expected = z;
    closeCracksOneByOne(expected, w, h, tolerance);
    for (size_t i = 0; i < z.size(); ++i) changed += std::memcmp(&z[i], &expected[i], sizeof(double)) != 0;
    for (int threads : {1, 2}) {
      vs::setWorkerThreads(threads);
      std::vector<double> actual = z;
      ScratchPool<std::vector<uint8_t>> flagRows;
      closeCracks(actual, w, h, tolerance, flagRows);
      ASSERT_EQ(0, std::memcmp(actual.data(), expected.data(), z.size() * sizeof(double)))
          << "trial " << trial << ", " << w << "x" << h << ", " << threads << " threads";
      // In its two parts, as the 1D warp calls them: each row by itself, then the columns.
      std::vector<double> parts = z;
      std::vector<uint8_t> flags(static_cast<size_t>(w));
      for (int y = 0; y < h; ++y) closeRowCracks(parts.data() + size_t(y) * w, w, tolerance, flags.data());
      closeColumnCracks(parts, w, h, tolerance, flagRows);
      ASSERT_EQ(0, std::memcmp(parts.data(), expected.data(), z.size() * sizeof(double)))
          << "trial " << trial << ", " << w << "x" << h << ", " << threads << " threads, in parts";
    }
  }
  vs::setWorkerThreads(defaultThreads);
  EXPECT_GT(changed, 2000u);  // the cases close many cracks
}

}  // namespace
}  // namespace vs
