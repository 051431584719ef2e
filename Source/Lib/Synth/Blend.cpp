#include <algorithm>
#include <cmath>
#include <utility>

#include "Common/Error.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Layer.h"
#include "Synth/Parallel.h"

namespace vs {

static_assert(kKernelNoDepth == kNoDepth, "the row kernels' hole is the layers' hole");

namespace {

// Sizes a layer (WarpedLayer or BlendedLayer, whose byte flags are `flags`) for w x h samples of c
// channels. `clear`: no depth, colour 0 and the flags `flagValue` everywhere; else what the planes
// hold is left for a writer that writes every sample.
template <class Layer>
void shapeLayer(Layer& layer, std::vector<uint8_t>& flags, int w, int h, int c, bool clear, uint8_t flagValue) {
  layer.width = w;
  layer.height = h;
  layer.channels = c;
  const size_t n = size_t(w) * size_t(h);
  if (clear) {
    layer.inverseDepth.assign(n, kNoDepth);
    for (int k = 0; k < 3; ++k) layer.colour[k].assign(k < c ? n : 0, 0.0f);
    flags.assign(n, flagValue);
  } else {
    layer.inverseDepth.resize(n);
    for (int k = 0; k < 3; ++k) layer.colour[k].resize(k < c ? n : 0);
    flags.resize(n);
  }
}

}  // namespace

void WarpedLayer::reset(int w, int h, int c) { shapeLayer(*this, edge, w, h, c, true, 0); }
void WarpedLayer::resize(int w, int h, int c) { shapeLayer(*this, edge, w, h, c, false, 0); }
void BlendedLayer::reset(int w, int h, int c) { shapeLayer(*this, hole, w, h, c, true, 1); }
void BlendedLayer::resize(int w, int h, int c) { shapeLayer(*this, hole, w, h, c, false, 1); }

size_t BlendedLayer::holeCount() const {
  // Counted in blocks whose count fits 16 bits: the compiler then compares and adds 16 flags at a
  // time, where std::count adds them one by one to a 64-bit count.
  const uint8_t* const flags = hole.data();
  const size_t n = hole.size();
  size_t count = 0;
  for (size_t begin = 0; begin < n; begin += 65535) {
    const size_t end = std::min(n, begin + 65535);
    uint16_t blockCount = 0;
    for (size_t i = begin; i < end; ++i) blockCount += flags[i] == 1;
    count += blockCount;
  }
  return count;
}

namespace {

// One view's planes, read straight (the loops below run for every sample).
struct ViewPlanes {
  const double* depth;
  const float* colour[3];
  const uint8_t* edge;
  double weight;  // a tiny floor keeps a view with weight 0 usable where it is the only one on the surface
};


// Any number of views.
void blendViews(const std::vector<ViewPlanes>& planes, int dominant, const BlendOptions& options, BlendedLayer& out) {
  // Every sample on its own: rows in parallel. (Locals throughout: the byte stores to the hole mask
  // may alias anything the loop would otherwise read through a reference.)
  parallelRanges(out.height, [&](int rowBegin, int rowEnd) {
  const ViewPlanes* sources = planes.data();
  const size_t sourceCount = planes.size();
  const int channelCount = out.channels, dominantView = dominant, width = out.width;
  const bool nearestViewOnly = options.nearestViewOnly;
  const double tolerance = options.depthTolerance;
  float* const colourOut[3] = {out.colour[0].data(), out.colour[1].data(), out.colour[2].data()};
  double* const depthOut = out.inverseDepth.data();
  uint8_t* const holeOut = out.hole.data();
  for (size_t i = size_t(rowBegin) * width; i < size_t(rowEnd) * width; ++i) {
    if (dominantView >= 0 && sources[size_t(dominantView)].depth[i] >= 0.0) {
      const ViewPlanes& view = sources[size_t(dominantView)];
      for (int c = 0; c < channelCount; ++c) colourOut[c][i] = view.colour[c][i];
      depthOut[i] = view.depth[i];
      holeOut[i] = 0;
      continue;
    }
    // The nearest surface among the valid views.
    double nearest = kNoDepth;
    for (size_t k = 0; k < sourceCount; ++k)
      if (sources[k].depth[i] >= 0.0) nearest = std::max(nearest, sources[k].depth[i]);
    if (nearest < 0.0) {  // a hole in every view
      for (int c = 0; c < channelCount; ++c) colourOut[c][i] = 0.0f;
      depthOut[i] = kNoDepth;
      holeOut[i] = 1;
      continue;
    }
    // Views on that surface; clean samples (not on a reference depth edge) are preferred.
    bool anyClean = false;
    for (size_t k = 0; k < sourceCount; ++k)
      if (sources[k].depth[i] >= 0.0 && nearest - sources[k].depth[i] <= tolerance && !sources[k].edge[i]) anyClean = true;
    double weightSum = 0, depthSum = 0, best = -1;
    float colourSum[3] = {0, 0, 0};
    int bestView = -1;
    for (size_t k = 0; k < sourceCount; ++k) {
      const ViewPlanes& view = sources[k];
      const double depth = view.depth[i];
      if (!(depth >= 0.0) || nearest - depth > tolerance) continue;
      if (anyClean && view.edge[i]) continue;
      const double w = view.weight;
      if (w > best) {
        best = w;
        bestView = int(k);
      }
      weightSum += w;
      depthSum += w * depth;
      for (int c = 0; c < channelCount; ++c) colourSum[c] += float(w) * view.colour[c][i];
    }
    VS_CHECK(bestView >= 0);
    if (nearestViewOnly) {
      const ViewPlanes& view = sources[size_t(bestView)];
      for (int c = 0; c < channelCount; ++c) colourOut[c][i] = view.colour[c][i];
      depthOut[i] = view.depth[i];
    } else {
      for (int c = 0; c < channelCount; ++c) colourOut[c][i] = float(colourSum[c] / weightSum);
      depthOut[i] = depthSum / weightSum;
    }
    holeOut[i] = 0;
  }
  });
}

// Exactly two views, the usual case: blendViews' decisions and arithmetic unrolled, with selects for
// its branches, in a kernel compiled for the CPU's x86-64 level (Synth/Kernels/Rows.h, which explains
// why every bit is blendViews' own).
template <int Channels, bool NearestViewOnly>
void blendTwoViews(const ViewPlanes& first, const ViewPlanes& second, int dominant, double tolerance, BlendedLayer& out) {
  TwoViewBlendRows blend;
  blend.depth0 = first.depth;
  blend.depth1 = second.depth;
  blend.edge0 = first.edge;
  blend.edge1 = second.edge;
  for (int c = 0; c < 3; ++c) {
    blend.colour0[c] = first.colour[c];
    blend.colour1[c] = second.colour[c];
    blend.colourOut[c] = out.colour[c].data();
  }
  blend.weight0 = first.weight;
  blend.weight1 = second.weight;
  blend.tolerance = tolerance;
  blend.floatWeight0 = float(first.weight);
  blend.floatWeight1 = float(second.weight);
  blend.dominantFirst = dominant == 0;
  blend.dominantSecond = dominant == 1;
  // blendViews' bestView is the first used view heavier than all before it (and than -1).
  blend.pickFirstAlone = first.weight > -1.0;
  blend.pickSecondAlone = second.weight > -1.0;
  blend.pickSecondOfBoth = second.weight > (blend.pickFirstAlone ? first.weight : -1.0);
  blend.plain = dominant < 0 && blend.pickFirstAlone && blend.pickSecondAlone;
  blend.depthOut = out.inverseDepth.data();
  blend.holeOut = out.hole.data();
  const auto kernel = rowKernels().blendTwoViews[Channels - 1][NearestViewOnly ? 1 : 0];
  const size_t width = size_t(out.width);
  parallelRanges(out.height, [&](int rowBegin, int rowEnd) {
    VS_CHECK(!kernel(blend, size_t(rowBegin) * width, size_t(rowEnd) * width));  // blendViews' VS_CHECK(bestView >= 0)
  });
}

template <int Channels>
void blendTwoViews(const ViewPlanes& first, const ViewPlanes& second, int dominant, const BlendOptions& options, BlendedLayer& out) {
  if (options.nearestViewOnly) blendTwoViews<Channels, true>(first, second, dominant, options.depthTolerance, out);
  else blendTwoViews<Channels, false>(first, second, dominant, options.depthTolerance, out);
}

}  // namespace

namespace {

// blendLayers' work; `inFirst`: out takes the first view's planes and the blend writes over them.
void blend(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out,
           WarpedLayer* inFirst) {
  VS_CHECK(!views.empty() && views.size() == options.weights.size());
  const int width = views[0]->width, height = views[0]->height, channels = views[0]->channels;
  for (const WarpedLayer* view : views) VS_CHECK(view->width == width && view->height == height && view->channels == channels);
  const size_t viewCount = views.size();
  int dominant = -1;
  for (size_t k = 0; k < viewCount; ++k)
    if (options.weights[k] >= 1.0) dominant = int(k);

  std::vector<ViewPlanes> planes(viewCount);
  for (size_t k = 0; k < viewCount; ++k) {
    planes[k].depth = views[k]->inverseDepth.data();
    for (int c = 0; c < 3; ++c) planes[k].colour[c] = c < channels ? views[k]->colour[c].data() : nullptr;
    planes[k].edge = views[k]->edge.data();
    planes[k].weight = std::max(options.weights[k], 1e-9);
  }
  if (inFirst) {
    // The planes' pointers stay valid: swapping vectors moves their memory, it does not copy it.
    std::swap(out.inverseDepth, inFirst->inverseDepth);
    for (int c = 0; c < 3; ++c) std::swap(out.colour[c], inFirst->colour[c]);
    std::swap(out.hole, inFirst->edge);
    out.width = width;
    out.height = height;
    out.channels = channels;
  } else {
    out.resize(width, height, channels);  // the blend writes every sample, holes included
  }
  if (viewCount != 2 || channels < 1 || channels > 3) blendViews(planes, dominant, options, out);
  else if (channels == 1) blendTwoViews<1>(planes[0], planes[1], dominant, options, out);
  else if (channels == 2) blendTwoViews<2>(planes[0], planes[1], dominant, options, out);
  else blendTwoViews<3>(planes[0], planes[1], dominant, options, out);
}

}  // namespace

void blendLayers(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out) {
  blend(views, options, out, nullptr);
}

void blendLayersIntoFirst(const std::vector<WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out) {
  VS_CHECK(!views.empty());
  blend(std::vector<const WarpedLayer*>(views.begin(), views.end()), options, out, views[0]);
}

}  // namespace vs
