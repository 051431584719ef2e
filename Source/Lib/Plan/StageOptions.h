#pragma once
// What the plan hands the stages: the options of blending and hole filling, and the depth steps that
// separate surfaces. The plan (Plan.h) fills them for a scene; the renderers only read them.
#include <vector>

namespace vs {

struct BlendOptions {
  std::vector<double> weights;  // one per view, summing to 1; a weight of 1 makes that view win where it is valid
  double depthTolerance = 0;    // inverse depths closer than this are the same surface (blended)
  bool nearestViewOnly = false; // ViewBlending 1: where views agree, take the heaviest view, not a mix
};

struct HoleFillOptions {
  bool backgroundFirst = true;  // IvsrsInpaint 1
  double depthTolerance = 0;    // inverse depths closer than this are one surface
  float emptyValue[3] = {0, 0, 0};
  int inpaintRadius = 3;
  int maxReach = 256;           // samples a directional search looks along
  // IvsrsInpaint 1: weights of the directional, row-run and inpainting estimates in the mix.
  float directionalWeight = 2.0f, rowRunWeight = 3.0f, inpaintWeight = 1.0f;
  // IvsrsInpaint 1: the inpainting also fills the nearer surface beside each hole (chroma), or only
  // the holes (luma: better on the Middlebury scenes, and less work; doc/algorithms.md).
  bool inpaintNearerSurface = false;
  // The inpainting adds OpenCV's colour-gradient term to its weighted mean (chroma: U and V score
  // higher with it), or not (luma: as good without it, and cheaper; Synth/Telea.h).
  bool inpaintLikeOpenCv = false;
};

// Baseline weights for views at distances d_k from the virtual camera: proportional to 1 / d_k
// (closer weighs more; for two views this is VSRS's d_other / (d_left + d_right)). Views at distance
// 0, or below 1e-6 of the largest distance, share the whole weight equally (one such view gets weight
// 1 and decides alone where it is valid); no division by zero whatever the distances.
std::vector<double> baselineWeights(const std::vector<double>& distances);

// Two samples whose depth levels differ by this many 8-bit levels lie on different surfaces.
constexpr double kSurfaceStepLevels8 = 8.0;
// The same step in levels of a depth map with `maxLevel` as its largest level (at least 1).
int depthEdgeStep(int maxLevel);

}  // namespace vs
