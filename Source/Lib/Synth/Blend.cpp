#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "Common/Error.h"
#include "Synth/Layer.h"
#include "Synth/Parallel.h"

namespace vs {

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
// its branches (at silhouettes and holes the outcome changes from sample to sample, too often for a
// branch to be predicted), two samples at a time where SSE4.1 is there. The sums are blendViews' own,
// in its order, from the same zeros; a view left out adds +0.0, which leaves a sum that starts from
// +0.0 as it is; the vector instructions round as the scalar ones do (IEEE, the same MXCSR), so every
// bit is the same.
template <int Channels, bool NearestViewOnly>
struct TwoViewBlend {
  const double* depth0;
  const double* depth1;
  const uint8_t* edge0;
  const uint8_t* edge1;
  const float* colour0[3];
  const float* colour1[3];
  double weight0, weight1, tolerance;
  float floatWeight0, floatWeight1;
  bool dominantFirst, dominantSecond;                         // weight >= 1: copied where it is valid
  bool pickSecondOfBoth, pickSecondAlone, pickFirstAlone;   // blendViews' bestView, from the weights
  float* colourOut[3];
  double* depthOut;
  uint8_t* holeOut;

  // Sample i; true where blendViews finds no bestView (its VS_CHECK).
  bool sample(size_t i) const {
    const double d0 = depth0[i], d1 = depth1[i];
    const bool valid0 = d0 >= 0.0, valid1 = d1 >= 0.0;
    const bool hole = !(valid0 | valid1);
    // blendViews' nearest: std::max(-1, d) is d for a valid d, std::max(d0, d1) is d0 < d1 ? d1 : d0.
    const double nearest = valid0 ? (valid1 ? (d0 < d1 ? d1 : d0) : d0) : d1;
    const double gap0 = nearest - d0, gap1 = nearest - d1;
    const bool onEdge0 = edge0[i] != 0, onEdge1 = edge1[i] != 0;
    const bool anyClean = (valid0 & (gap0 <= tolerance) & !onEdge0) | (valid1 & (gap1 <= tolerance) & !onEdge1);
    const bool use0 = valid0 & !(gap0 > tolerance) & !(anyClean & onEdge0);
    const bool use1 = valid1 & !(gap1 > tolerance) & !(anyClean & onEdge1);
    const bool takeSecond = use1 & ((use0 & pickSecondOfBoth) | (!use0 & pickSecondAlone));
    const bool takeFirst = !takeSecond & use0 & pickFirstAlone;
    const bool dominantCopy = (dominantFirst & valid0) | (dominantSecond & valid1);
    const bool copy = NearestViewOnly | dominantCopy;
    const bool fromSecond = dominantCopy ? dominantSecond : takeSecond;
    const double weightSum = (0.0 + (use0 ? weight0 : 0.0)) + (use1 ? weight1 : 0.0);
    const double depthSum = (0.0 + (use0 ? weight0 * d0 : 0.0)) + (use1 ? weight1 * d1 : 0.0);
    for (int c = 0; c < Channels; ++c) {
      const float a = colour0[c][i], b = colour1[c][i];
      const float colourSum = (0.0f + (use0 ? floatWeight0 * a : 0.0f)) + (use1 ? floatWeight1 * b : 0.0f);
      colourOut[c][i] = hole ? 0.0f : copy ? (fromSecond ? b : a) : float(colourSum / weightSum);
    }
    depthOut[i] = hole ? kNoDepth : copy ? (fromSecond ? d1 : d0) : depthSum / weightSum;
    holeOut[i] = hole;
    return !(dominantCopy | hole | takeFirst | takeSecond);
  }

#if defined(__SSE4_1__)
  // Samples i and i + 1, as sample() does them, in the two lanes of SSE registers (masks: all ones
  // for true); the lanes where blendViews finds no bestView come back set. Plain: no view has weight
  // 1 and both weights are numbers, so nothing is copied but for NearestViewOnly, and bestView is
  // the heavier of the views used (the first of equal ones), found wherever one is used.
  template <bool Plain>
  __m128d pair(size_t i) const {
    const __m128d zero = _mm_setzero_pd(), ones = _mm_castsi128_pd(_mm_set1_epi32(-1));
    auto flag = [&](bool b) { return b ? ones : zero; };
    const __m128d d0 = _mm_loadu_pd(depth0 + i), d1 = _mm_loadu_pd(depth1 + i);
    const __m128d valid0 = _mm_cmpge_pd(d0, zero), valid1 = _mm_cmpge_pd(d1, zero);
    const __m128d hole = _mm_xor_pd(_mm_or_pd(valid0, valid1), ones);
    // sample()'s nearest: with x0 = -1 where the first view is not valid, max(d1, x0), which is
    // d1 > x0 ? d1 : x0, is std::max(d0, d1) where both are valid (-0 included) and the valid one
    // where one is: a d1 not valid (negative, or NaN, which compares false) never wins.
    const __m128d nearest = _mm_max_pd(d1, _mm_blendv_pd(_mm_set1_pd(-1.0), d0, valid0));
    const __m128d gap0 = _mm_sub_pd(nearest, d0), gap1 = _mm_sub_pd(nearest, d1);
    const __m128d surface = _mm_set1_pd(tolerance);
    uint16_t edgePair0, edgePair1;
    std::memcpy(&edgePair0, edge0 + i, sizeof edgePair0);
    std::memcpy(&edgePair1, edge1 + i, sizeof edgePair1);
    const __m128d clean0 = _mm_castsi128_pd(_mm_cmpeq_epi64(_mm_cvtepu8_epi64(_mm_cvtsi32_si128(edgePair0)), _mm_setzero_si128()));
    const __m128d clean1 = _mm_castsi128_pd(_mm_cmpeq_epi64(_mm_cvtepu8_epi64(_mm_cvtsi32_si128(edgePair1)), _mm_setzero_si128()));
    const __m128d anyClean = _mm_or_pd(_mm_and_pd(_mm_and_pd(valid0, _mm_cmple_pd(gap0, surface)), clean0),
                                       _mm_and_pd(_mm_and_pd(valid1, _mm_cmple_pd(gap1, surface)), clean1));
    // use = valid & !(gap > tolerance) & !(anyClean & onEdge)
    const __m128d use0 = _mm_andnot_pd(_mm_andnot_pd(clean0, anyClean), _mm_andnot_pd(_mm_cmpgt_pd(gap0, surface), valid0));
    const __m128d use1 = _mm_andnot_pd(_mm_andnot_pd(clean1, anyClean), _mm_andnot_pd(_mm_cmpgt_pd(gap1, surface), valid1));
    __m128d lost, copy, fromSecond;
    if constexpr (Plain) {
      lost = _mm_andnot_pd(_mm_or_pd(hole, _mm_or_pd(use0, use1)), ones);
      copy = NearestViewOnly ? ones : zero;
      fromSecond = _mm_and_pd(use1, _mm_or_pd(flag(pickSecondOfBoth), _mm_andnot_pd(use0, ones)));
    } else {
      const __m128d takeSecond =
          _mm_and_pd(use1, _mm_or_pd(_mm_and_pd(use0, flag(pickSecondOfBoth)), _mm_andnot_pd(use0, flag(pickSecondAlone))));
      const __m128d takeFirst = _mm_andnot_pd(takeSecond, _mm_and_pd(use0, flag(pickFirstAlone)));
      const __m128d dominantCopy = _mm_or_pd(_mm_and_pd(flag(dominantFirst), valid0), _mm_and_pd(flag(dominantSecond), valid1));
      lost = _mm_andnot_pd(_mm_or_pd(_mm_or_pd(dominantCopy, hole), _mm_or_pd(takeFirst, takeSecond)), ones);
      copy = NearestViewOnly ? ones : dominantCopy;
      fromSecond = _mm_blendv_pd(takeSecond, flag(dominantSecond), dominantCopy);
    }
    // Plain without NearestViewOnly copies nothing: the selects of copies are left out.
    constexpr bool copies = NearestViewOnly || !Plain, mixes = !NearestViewOnly;
    const __m128d w0 = _mm_set1_pd(weight0), w1 = _mm_set1_pd(weight1);
    const __m128d weightSum = _mm_add_pd(_mm_add_pd(zero, _mm_and_pd(use0, w0)), _mm_and_pd(use1, w1));
    __m128d depth = zero;
    if (copies) depth = _mm_blendv_pd(d0, d1, fromSecond);
    if (mixes) {
      const __m128d depthSum =
          _mm_add_pd(_mm_add_pd(zero, _mm_and_pd(use0, _mm_mul_pd(w0, d0))), _mm_and_pd(use1, _mm_mul_pd(w1, d1)));
      depth = copies ? _mm_blendv_pd(_mm_div_pd(depthSum, weightSum), depth, copy) : _mm_div_pd(depthSum, weightSum);
    }
    _mm_storeu_pd(depthOut + i, _mm_blendv_pd(depth, _mm_set1_pd(kNoDepth), hole));
    // The colours: two floats in the low lanes, with the masks narrowed to 32 bits.
    auto narrow = [](__m128d mask) { return _mm_shuffle_ps(_mm_castpd_ps(mask), _mm_castpd_ps(mask), _MM_SHUFFLE(2, 0, 2, 0)); };
    const __m128 use0f = narrow(use0), use1f = narrow(use1), copyf = narrow(copy), holef = narrow(hole);
    const __m128 fromSecondf = narrow(fromSecond);
    const __m128 fw0 = _mm_set1_ps(floatWeight0), fw1 = _mm_set1_ps(floatWeight1);
    for (int c = 0; c < Channels; ++c) {
      const __m128 a = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(colour0[c] + i)));
      const __m128 b = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(colour1[c] + i)));
      __m128 value = _mm_setzero_ps();
      if (copies) value = _mm_blendv_ps(a, b, fromSecondf);
      if (mixes) {
        const __m128 colourSum =
            _mm_add_ps(_mm_add_ps(_mm_setzero_ps(), _mm_and_ps(use0f, _mm_mul_ps(fw0, a))), _mm_and_ps(use1f, _mm_mul_ps(fw1, b)));
        const __m128 mixed = _mm_cvtpd_ps(_mm_div_pd(_mm_cvtps_pd(colourSum), weightSum));
        value = copies ? _mm_blendv_ps(mixed, value, copyf) : mixed;
      }
      _mm_storel_epi64(reinterpret_cast<__m128i*>(colourOut[c] + i), _mm_castps_si128(_mm_andnot_ps(holef, value)));
    }
    const int holes = _mm_movemask_pd(hole);
    holeOut[i] = uint8_t(holes & 1);
    holeOut[i + 1] = uint8_t(holes >> 1);
    return lost;
  }
#endif
};

template <int Channels, bool NearestViewOnly>
void blendTwoViews(const ViewPlanes& first, const ViewPlanes& second, int dominant, double tolerance, BlendedLayer& out) {
  TwoViewBlend<Channels, NearestViewOnly> blend;
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
  blend.depthOut = out.inverseDepth.data();
  blend.holeOut = out.hole.data();
  // Read by the SSE4.1 pairs only.
  [[maybe_unused]] const bool plain = dominant < 0 && blend.pickFirstAlone && blend.pickSecondAlone;
  const size_t width = size_t(out.width);
  parallelRanges(out.height, [&](int rowBegin, int rowEnd) {
    const TwoViewBlend<Channels, NearestViewOnly> local = blend;  // a local: the stores cannot alias it
    const size_t end = size_t(rowEnd) * width;
    size_t i = size_t(rowBegin) * width;
    bool lost = false;
#if defined(__SSE4_1__)
    __m128d lostPairs = _mm_setzero_pd();
    if (plain)
      for (; i + 2 <= end; i += 2) lostPairs = _mm_or_pd(lostPairs, local.template pair<true>(i));
    else
      for (; i + 2 <= end; i += 2) lostPairs = _mm_or_pd(lostPairs, local.template pair<false>(i));
    lost = _mm_movemask_pd(lostPairs) != 0;
#endif
    for (; i < end; ++i) lost |= local.sample(i);
    VS_CHECK(!lost);  // blendViews' VS_CHECK(bestView >= 0)
  });
}

template <int Channels>
void blendTwoViews(const ViewPlanes& first, const ViewPlanes& second, int dominant, const BlendOptions& options, BlendedLayer& out) {
  if (options.nearestViewOnly) blendTwoViews<Channels, true>(first, second, dominant, options.depthTolerance, out);
  else blendTwoViews<Channels, false>(first, second, dominant, options.depthTolerance, out);
}

}  // namespace

void blendLayers(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out) {
  VS_CHECK(!views.empty() && views.size() == options.weights.size());
  const int width = views[0]->width, height = views[0]->height, channels = views[0]->channels;
  for (const WarpedLayer* view : views) VS_CHECK(view->width == width && view->height == height && view->channels == channels);
  out.resize(width, height, channels);  // the blend writes every sample, holes included
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
  if (viewCount != 2 || channels < 1 || channels > 3) blendViews(planes, dominant, options, out);
  else if (channels == 1) blendTwoViews<1>(planes[0], planes[1], dominant, options, out);
  else if (channels == 2) blendTwoViews<2>(planes[0], planes[1], dominant, options, out);
  else blendTwoViews<3>(planes[0], planes[1], dominant, options, out);
}

}  // namespace vs
