// blendLayers' two-view path against its any-number-of-views path, and the per-frame helpers around
// the blend (holeCount, roundLayersToFrame) against their plain definitions: bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <random>

#include "Synth/Colour.h"
#include "Synth/Layer.h"

namespace vs {
namespace {

// A layer that exercises every decision of the blend: holes (kNoDepth, other negatives, NaN), -0, +0,
// depths on one of a few surfaces (so that the two views agree within the tolerance, or one is
// nearer by more), a few beyond any tolerance (+inf), edge flags (1 and another non-zero value).
WarpedLayer randomLayer(int w, int h, int channels, std::mt19937& random) {
  WarpedLayer layer;
  layer.reset(w, h, channels);
  std::uniform_int_distribution<int> kind(0, 19), surface(0, 3), flag(0, 5);
  std::uniform_real_distribution<double> offset(-0.004, 0.004);
  std::uniform_real_distribution<float> colour(0.0f, 255.0f);
  for (size_t i = 0; i < layer.inverseDepth.size(); ++i) {
    const int k = kind(random);
    double depth = 0.02 * (1 + surface(random)) + offset(random);  // tolerance 0.005 in the tests
    if (k < 5) depth = kNoDepth;
    else if (k == 5) depth = -0.25;
    else if (k == 6) depth = std::numeric_limits<double>::quiet_NaN();
    else if (k == 7) depth = -0.0;
    else if (k == 9) depth = 0.0;
    else if (k == 8 && flag(random) == 0) depth = HUGE_VAL;
    layer.inverseDepth[i] = depth;
    const int f = flag(random);
    layer.edge[i] = f == 0 ? 1 : f == 1 ? 2 : 0;
    for (int c = 0; c < channels; ++c) layer.colour[c][i] = colour(random);
  }
  return layer;
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  // memcmp must not see the null data() of an empty vector (a channel the layers do not have).
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectSameBits(const BlendedLayer& a, const BlendedLayer& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.channels, b.channels);
  EXPECT_TRUE(sameBits(a.inverseDepth, b.inverseDepth));
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(sameBits(a.colour[c], b.colour[c])) << "channel " << c;
  EXPECT_TRUE(sameBits(a.hole, b.hole));
}

// Two views take a path of their own; a third view that is a hole everywhere, with weight 0, changes
// nothing in the result but sends the blend down the path for any number of views.
TEST(Blend, TwoViewPathMatchesTheGeneralPathBitForBit) {
  std::mt19937 random(12345);
  const int w = 97, h = 61;
  WarpedLayer none;
  const std::vector<std::vector<double>> weightSets = {{0.5, 0.5}, {0.3, 0.7}, {0.7, 0.3}, {1.0, 0.0},
                                                       {0.0, 1.0}, {1.0, 1.0}, {0.0, 0.0}};
  size_t holes = 0, mixed = 0;
  for (int channels = 1; channels <= 3; ++channels) {
    const WarpedLayer a = randomLayer(w, h, channels, random), b = randomLayer(w, h, channels, random);
    none.reset(w, h, channels);
    for (const std::vector<double>& weights : weightSets)
      for (double tolerance : {0.005, 0.0})
        for (bool nearestViewOnly : {false, true}) {
          SCOPED_TRACE(testing::Message() << channels << " channels, weights " << weights[0] << " " << weights[1]
                                          << ", tolerance " << tolerance << ", nearestViewOnly " << nearestViewOnly);
          BlendOptions two;
          two.weights = weights;
          two.depthTolerance = tolerance;
          two.nearestViewOnly = nearestViewOnly;
          BlendOptions three = two;
          three.weights.push_back(0.0);
          BlendedLayer fast, general;
          blendLayers({&a, &b}, two, fast);
          blendLayers({&a, &b, &none}, three, general);
          expectSameBits(fast, general);
          holes += fast.holeCount();
          // Samples that are neither view's own: mixed by weight.
          for (size_t i = 0; i < fast.hole.size(); ++i)
            if (!fast.hole[i] && fast.colour[0][i] != a.colour[0][i] && fast.colour[0][i] != b.colour[0][i]) ++mixed;
        }
  }
  // The random layers reach the holes and the mixing, not only the copies.
  EXPECT_GT(holes, 0u);
  EXPECT_GT(mixed, 0u);
}

// The blend writes every sample, holes included: a layer that held another blend (other size, more
// channels) comes out as a fresh one does, holes as reset() leaves them.
TEST(Blend, ReusedOutputMatchesAFreshOne) {
  std::mt19937 random(777);
  for (size_t viewCount : {size_t(2), size_t(3)}) {
    const WarpedLayer big0 = randomLayer(40, 30, 3, random), big1 = randomLayer(40, 30, 3, random), big2 = randomLayer(40, 30, 3, random);
    const WarpedLayer small0 = randomLayer(23, 17, 2, random), small1 = randomLayer(23, 17, 2, random), small2 = randomLayer(23, 17, 2, random);
    BlendOptions options;
    options.weights.assign(viewCount, 1.0 / double(viewCount + 1));
    options.depthTolerance = 0.005;
    std::vector<const WarpedLayer*> big = {&big0, &big1, &big2}, small = {&small0, &small1, &small2};
    big.resize(viewCount);
    small.resize(viewCount);
    BlendedLayer reused, fresh;
    blendLayers(big, options, reused);
    blendLayers(small, options, reused);
    blendLayers(small, options, fresh);
    expectSameBits(reused, fresh);
    EXPECT_TRUE(reused.colour[2].empty());
    size_t holes = 0;
    for (size_t i = 0; i < fresh.hole.size(); ++i) {
      if (!fresh.hole[i]) continue;
      ++holes;
      EXPECT_EQ(fresh.inverseDepth[i], kNoDepth);
      EXPECT_EQ(fresh.colour[0][i], 0.0f);
      EXPECT_EQ(fresh.colour[1][i], 0.0f);
    }
    EXPECT_GT(holes, 0u);
  }
}

// Blending over the first view's planes (what ViewSyn's frames do) gives blendLayers' result bit for
// bit on both paths (two views, and three), every weight set and channel count, with the blended
// layer taking the first view's memory; the first view gets the blended layer's former planes.
TEST(Blend, BlendingOverTheFirstViewMatchesBlendingIntoALayerOfItsOwn) {
  std::mt19937 random(4242);
  const int w = 53, h = 37;
  const std::vector<std::vector<double>> weightSets = {{0.5, 0.5, 0.0}, {0.3, 0.7, 0.2}, {1.0, 0.0, 0.0},
                                                       {0.0, 1.0, 0.5}, {0.0, 0.0, 1.0}};
  for (size_t viewCount : {size_t(2), size_t(3)})
    for (int channels = 1; channels <= 3; ++channels)
      for (const std::vector<double>& weights : weightSets)
        for (bool nearestViewOnly : {false, true}) {
          SCOPED_TRACE(testing::Message() << viewCount << " views, " << channels << " channels, weights " << weights[0]
                                          << " " << weights[1] << ", nearestViewOnly " << nearestViewOnly);
          BlendOptions options;
          options.weights.assign(weights.begin(), weights.begin() + std::ptrdiff_t(viewCount));
          options.depthTolerance = 0.005;
          options.nearestViewOnly = nearestViewOnly;
          std::vector<WarpedLayer> layers;
          for (size_t k = 0; k < viewCount; ++k) layers.push_back(randomLayer(w, h, channels, random));
          std::vector<const WarpedLayer*> in;
          for (const WarpedLayer& layer : layers) in.push_back(&layer);
          BlendedLayer apart;
          blendLayers(in, options, apart);
          std::vector<WarpedLayer> copies = layers;
          std::vector<WarpedLayer*> over;
          for (WarpedLayer& layer : copies) over.push_back(&layer);
          const double* firstDepth = copies[0].inverseDepth.data();
          BlendedLayer blended;
          blended.reset(5, 4, 1);  // former planes of another size: they go to the first view
          blendLayersIntoFirst(over, options, blended);
          expectSameBits(blended, apart);
          EXPECT_EQ(blended.inverseDepth.data(), firstDepth);
          EXPECT_EQ(copies[0].inverseDepth.size(), 20u);
          for (size_t k = 1; k < viewCount; ++k) EXPECT_TRUE(sameBits(copies[k].inverseDepth, layers[k].inverseDepth));
        }
}

TEST(Blend, HoleCountCountsTheFlagsThatAreOne) {
  std::mt19937 random(99);
  std::uniform_int_distribution<int> flag(0, 2);
  BlendedLayer layer;
  for (size_t n : {size_t(0), size_t(1), size_t(65535), size_t(65536), size_t(200003)}) {
    layer.hole.resize(n);
    for (uint8_t& h : layer.hole) h = uint8_t(flag(random));
    EXPECT_EQ(layer.holeCount(), size_t(std::count(layer.hole.begin(), layer.hole.end(), uint8_t(1)))) << n;
  }
  layer.hole.assign(200003, 1);  // more than a 16-bit count holds
  EXPECT_EQ(layer.holeCount(), 200003u);
}

TEST(Blend, RoundingToSamplesMatchesFloorOfHalfUpClamped) {
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(), -HUGE_VALF, -1.0f, -0.0f, 0.0f, 1e-30f, 0.49999997f,
                            0.5f, 1.5f, 2.5f, 254.49998f, 254.5f, 255.0f, 255.5f, 1022.6f, 1023.49994f, 1023.5f,
                            65534.5f, 65535.0f, 70000.0f, 1e30f, HUGE_VALF};
  std::mt19937 random(5);
  std::uniform_real_distribution<float> spread(-10.0f, 70000.0f);
  for (int bitDepth : {8, 10, 16}) {
    const int maxValue = (1 << bitDepth) - 1;
    Frame output(FrameFormat{16, 8, bitDepth, ChromaFormat::Yuv420}), scratch;
    BlendedLayer luma, chroma;
    luma.reset(16, 8, 1);
    chroma.reset(8, 4, 2);
    std::vector<float*> values = {luma.colour[0].data(), chroma.colour[0].data(), chroma.colour[1].data()};
    size_t k = 0;
    for (int p = 0; p < 3; ++p)
      for (size_t i = 0; i < output.planes[p].samples.size(); ++i, ++k)
        values[p][i] = k < std::size(specials) ? specials[k] : spread(random);
    roundLayersToFrame(luma, chroma, false, scratch, output);
    for (int p = 0; p < 3; ++p)
      for (size_t i = 0; i < output.planes[p].samples.size(); ++i) {
        const float v = values[p][i];
        const float rounded = std::floor(v + 0.5f);
        const uint16_t expected = !(v > 0.0f) ? 0 : rounded >= float(maxValue) ? uint16_t(maxValue) : uint16_t(rounded);
        EXPECT_EQ(output.planes[p].samples[i], expected) << "bit depth " << bitDepth << ", value " << v;
      }
  }
}

}  // namespace
}  // namespace vs
