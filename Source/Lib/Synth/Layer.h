#pragma once
// What one reference view contributes to the virtual view at one resolution (luma, or chroma), and
// the blended result. ViewSyn's warper and MeshRender's renderer both produce WarpedLayers; blending
// and hole filling work on them alike (doc/algorithms.md, "Blending" and "Hole filling").
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vs {

constexpr double kNoDepth = -1.0;  // inverse depth of a sample that received nothing

struct WarpedLayer {
  int width = 0;
  int height = 0;
  int channels = 1;                  // 1 (luma), 2 (U, V) or 3 (RGB)
  std::vector<double> inverseDepth;  // 1 / z_virtual; kNoDepth where the view left a hole
  std::vector<float> colour[3];      // per channel, not rounded
  std::vector<uint8_t> edge;         // 1 where the colour comes from next to a depth edge in the reference

  void reset(int w, int h, int c);
  // Sizes the planes for w x h samples of c channels and leaves what they hold: for a writer that
  // writes every sample anyway (reset's fill would only be written over).
  void resize(int w, int h, int c);
  bool valid(size_t i) const { return inverseDepth[i] >= 0.0; }
};

struct BlendedLayer {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<double> inverseDepth;  // kNoDepth in holes
  std::vector<float> colour[3];
  std::vector<uint8_t> hole;         // 1 where no view contributed

  void reset(int w, int h, int c);
  void resize(int w, int h, int c);  // as WarpedLayer::resize
  size_t holeCount() const;
};

struct BlendOptions {
  std::vector<double> weights;  // one per view, summing to 1; a weight of 1 makes that view win where it is valid
  double depthTolerance = 0;    // inverse depths closer than this are the same surface (blended)
  bool nearestViewOnly = false; // ViewBlending 1: where views agree, take the heaviest view, not a mix
};

// Blends the views sample by sample: one valid view is taken as it is; where several are valid, the
// nearest surface wins when their depths differ by more than depthTolerance, else the agreeing views
// are mixed by weight, leaving out those whose sample lies on a reference depth edge when another
// agreeing view has a clean one.
void blendLayers(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out);

// Baseline weights for views at distances d_k from the virtual camera: proportional to 1 / d_k
// (closer weighs more; for two views this is VSRS's d_other / (d_left + d_right)). Views at distance
// 0, or below 1e-6 of the largest distance, share the whole weight equally (one such view gets weight
// 1 and decides alone where it is valid); no division by zero whatever the distances.
std::vector<double> baselineWeights(const std::vector<double>& distances);

}  // namespace vs
