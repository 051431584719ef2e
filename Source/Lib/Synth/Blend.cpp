#include <algorithm>
#include <cmath>

#include "Common/Error.h"
#include "Synth/Layer.h"
#include "Synth/Parallel.h"

namespace vs {

void WarpedLayer::reset(int w, int h, int c) {
  width = w;
  height = h;
  channels = c;
  const size_t n = size_t(w) * size_t(h);
  inverseDepth.assign(n, kNoDepth);
  for (int k = 0; k < 3; ++k) colour[k].assign(k < c ? n : 0, 0.0f);
  edge.assign(n, 0);
}

void BlendedLayer::reset(int w, int h, int c) {
  width = w;
  height = h;
  channels = c;
  const size_t n = size_t(w) * size_t(h);
  inverseDepth.assign(n, kNoDepth);
  for (int k = 0; k < 3; ++k) colour[k].assign(k < c ? n : 0, 0.0f);
  hole.assign(n, 1);
}

size_t BlendedLayer::holeCount() const { return size_t(std::count(hole.begin(), hole.end(), uint8_t(1))); }

std::vector<double> baselineWeights(const std::vector<double>& distances) {
  std::vector<double> weights(distances.size(), 0.0);
  if (distances.empty()) return weights;
  // Views the virtual camera sits on share all the weight: they alone decide where they are valid.
  // "On" means closer than 1e-6 of the farthest view's distance: a baseline of 1e-9 against one of 1
  // is the same camera for every purpose, and must not leave the other view a weight of 5e-9 with
  // which it still wins wherever it sees a nearer surface.
  double farthest = 0;
  for (double d : distances)
    if (std::isfinite(d)) farthest = std::max(farthest, d);
  std::vector<bool> on(distances.size());
  size_t onCamera = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    on[k] = distances[k] <= 1e-6 * farthest;
    onCamera += on[k] ? 1 : 0;
  }
  if (onCamera > 0) {
    for (size_t k = 0; k < distances.size(); ++k) weights[k] = on[k] ? 1.0 / double(onCamera) : 0.0;
    return weights;
  }
  double sum = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    weights[k] = std::isfinite(distances[k]) ? 1.0 / distances[k] : 0.0;
    sum += weights[k];
  }
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    std::fill(weights.begin(), weights.end(), 1.0 / double(distances.size()));
    return weights;
  }
  for (double& w : weights) w /= sum;
  return weights;
}

void blendLayers(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out) {
  VS_CHECK(!views.empty() && views.size() == options.weights.size());
  const int width = views[0]->width, height = views[0]->height, channels = views[0]->channels;
  for (const WarpedLayer* view : views) VS_CHECK(view->width == width && view->height == height && view->channels == channels);
  out.reset(width, height, channels);
  const size_t viewCount = views.size();
  int dominant = -1;
  for (size_t k = 0; k < viewCount; ++k)
    if (options.weights[k] >= 1.0) dominant = int(k);

  // The views' planes, read straight (the loops below run for every sample).
  struct ViewPlanes {
    const double* depth;
    const float* colour[3];
    const uint8_t* edge;
    double weight;  // a tiny floor keeps a view with weight 0 usable where it is the only one on the surface
  };
  std::vector<ViewPlanes> planes(viewCount);
  for (size_t k = 0; k < viewCount; ++k) {
    planes[k].depth = views[k]->inverseDepth.data();
    for (int c = 0; c < 3; ++c) planes[k].colour[c] = c < channels ? views[k]->colour[c].data() : nullptr;
    planes[k].edge = views[k]->edge.data();
    planes[k].weight = std::max(options.weights[k], 1e-9);
  }

  // Every sample on its own: rows in parallel. (Locals throughout: the byte stores to the hole mask
  // may alias anything the loop would otherwise read through a reference.)
  parallelRanges(height, [&](int rowBegin, int rowEnd) {
  const ViewPlanes* sources = planes.data();
  const size_t sourceCount = planes.size();
  const int channelCount = out.channels, dominantView = dominant;
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
    if (nearest < 0.0) continue;  // a hole in every view
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

}  // namespace vs
