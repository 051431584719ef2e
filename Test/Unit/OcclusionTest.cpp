// The occlusion rule (Synth/Occlusion.h) against its definition, evaluated sample by sample with
// plain scans along rows and columns.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>


#include "Synth/Parallel.h"
#include "Synth/Occlusion.h"

namespace vs {
namespace {

// The rule as Occlusion.h states it, one sample at a time.
// `candidates` counts the samples the rule looks at (exactly one view, of weight below 1).
std::vector<WarpedLayer> byDefinition(const std::vector<WarpedLayer>& views, const std::vector<double>& weights,
                                      double behind, size_t& candidates) {
  std::vector<WarpedLayer> out = views;
  const int w = views[0].width, h = views[0].height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      int count = 0, only = -1;
      for (size_t k = 0; k < views.size(); ++k)
        if (views[k].inverseDepth[i] >= 0) {
          ++count;
          only = int(k);
        }
      if (count != 1 || weights[size_t(only)] >= 1.0) continue;
      ++candidates;
      bool misplaced = true;
      for (size_t o = 0; o < views.size() && misplaced; ++o) {
        if (int(o) == only) continue;
        const std::vector<double>& d = views[o].inverseDepth;
        auto nearest = [&](int dx, int dy) {  // the first valid sample from (x, y) in direction (dx, dy)
          for (int px = x + dx, py = y + dy; px >= 0 && py >= 0 && px < w && py < h; px += dx, py += dy)
            if (d[size_t(py) * w + px] >= 0) return d[size_t(py) * w + px];
          return -1.0;
        };
        double around = HUGE_VAL;
        const double left = nearest(-1, 0), right = nearest(1, 0), up = nearest(0, -1), down = nearest(0, 1);
        if (left >= 0 && right >= 0) around = std::min(around, std::min(left, right));
        if (up >= 0 && down >= 0) around = std::min(around, std::min(up, down));
        misplaced = around != HUGE_VAL && views[size_t(only)].inverseDepth[i] < around - behind;
      }
      if (misplaced) out[size_t(only)].inverseDepth[i] = kNoDepth;
    }
  return out;
}

// A view's layer: a surface with a random slope, holes as random rectangles (strips along the
// borders among them), and some samples pushed far back (misplaced, as unknown depth would be).
// Depths are multiples of 1/64, so that a sample can lie exactly `behind` behind its surroundings.
WarpedLayer randomView(std::mt19937& rng, int w, int h) {
  WarpedLayer layer;
  layer.reset(w, h, 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double base = 0.2 + 0.6 * unit(rng), slopeX = 0.01 * (unit(rng) - 0.5), slopeY = 0.01 * (unit(rng) - 0.5);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double depth = base + slopeX * x + slopeY * y;
      if (unit(rng) < 0.15) depth = 0.05 * unit(rng);  // far behind
      if (unit(rng) < 0.05) depth += 0.3;              // nearer
      layer.inverseDepth[size_t(y) * w + x] = std::round(depth * 64) / 64;  // exact ties with `behind`
    }
  const int holes = int(unit(rng) * 8);
  for (int k = 0; k < holes; ++k) {
    const int x0 = int(unit(rng) * w), y0 = int(unit(rng) * h);
    const int x1 = std::min(w, x0 + 1 + int(unit(rng) * w / 2)), y1 = std::min(h, y0 + 1 + int(unit(rng) * h / 2));
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) layer.inverseDepth[size_t(y) * w + x] = kNoDepth;
  }
  if (unit(rng) < 0.3)  // a strip along the left or right border that this view cannot see
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < std::max(1, w / 5); ++x) layer.inverseDepth[size_t(y) * w + (unit(rng) < 0.5 ? x : w - 1 - x)] = kNoDepth;
  return layer;
}

TEST(Occlusion, DropsExactlyTheSamplesTheDefinitionDropsWithAnyNumberOfViewsAndThreads) {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int defaultThreads = vs::workerThreads();
  size_t candidates = 0, dropped = 0;
  OcclusionScratch scratch;  // reused across sizes, as a sequence reuses it
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + int(unit(rng) * 48), h = 1 + int(unit(rng) * 40);
    const size_t viewCount = 2 + size_t(unit(rng) * 3);
    std::vector<WarpedLayer> views;
    for (size_t k = 0; k < viewCount; ++k) views.push_back(randomView(rng, w, h));
    std::vector<double> weights(viewCount, 1.0 / double(viewCount));
    if (trial % 7 == 0) weights.assign(viewCount, 0.0), weights[size_t(trial) % viewCount] = 1.0;  // on a view
    const double behind = std::round(3 + 12 * unit(rng)) / 64;  // ties: depth == surroundings - behind
    const std::vector<WarpedLayer> expected = byDefinition(views, weights, behind, candidates);
    for (size_t k = 0; k < viewCount; ++k)
      for (size_t i = 0; i < views[k].inverseDepth.size(); ++i) dropped += expected[k].inverseDepth[i] != views[k].inverseDepth[i];
    for (int threads : {1, 2}) {
      vs::setWorkerThreads(threads);
      std::vector<WarpedLayer> actual = views;
      std::vector<WarpedLayer*> layers;
      for (WarpedLayer& layer : actual) layers.push_back(&layer);
      rejectMisplacedSamples(layers, weights, behind, scratch);
      for (size_t k = 0; k < viewCount; ++k)
        ASSERT_EQ(0, std::memcmp(actual[k].inverseDepth.data(), expected[k].inverseDepth.data(),
                                 expected[k].inverseDepth.size() * sizeof(double)))
            << "trial " << trial << ", view " << k << " of " << viewCount << ", " << w << "x" << h << ", "
            << threads << " threads";
    }
  }
  vs::setWorkerThreads(defaultThreads);
  // The cases reach both outcomes, many times.
  EXPECT_GT(dropped, 1000u);
  EXPECT_GT(candidates - dropped, 1000u);
}

}  // namespace
}  // namespace vs
