#pragma once
// Filling what no reference view sees (doc/algorithms.md, "Hole filling").
//
// Holes are disoccluded background. With IvsrsInpaint 1 three background-only estimates are mixed
// 2 : 3 : 1 over those that reach a sample:
//   - directional: each hole sample looks in eight directions for the nearest sample with colour,
//     keeps those on the farthest surface found (within the depth tolerance) and mixes them by
//     inverse distance; it keeps texture but copies it in streaks;
//   - row runs (after iVSRS in VSRS 4.x): each run of holes along a row takes the mean colour of the
//     candidates on the farthest surface among its ends and the first samples along seven rays up
//     and down from its middle; one colour per run;
//   - inpainting: OpenCV's Telea inpainting, with the nearer surface around each hole masked too so
//     that only background propagates; it is smooth but blurs.
// The mix has a lower error than any one of them on the Middlebury scenes (doc/algorithms.md).
// IvsrsInpaint 0: OpenCV Telea inpainting of the holes alone, as VSRS does. A layer without any valid
// sample is filled with `emptyValue`.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "Synth/Layer.h"

namespace vs {

struct HoleFillOptions {
  bool backgroundFirst = true;  // IvsrsInpaint 1
  double depthTolerance = 0;    // inverse depths closer than this are one surface
  float emptyValue[3] = {0, 0, 0};
  int inpaintRadius = 3;
  int maxReach = 256;           // samples a directional search looks along
  // IvsrsInpaint 1: weights of the directional, row-run and inpainting estimates in the mix.
  float directionalWeight = 2.0f, rowRunWeight = 3.0f, inpaintWeight = 1.0f;
};

// Working buffers of fillHoles, kept by a caller that fills every frame so that nothing is allocated
// per frame once they have grown to the picture's size.
struct HoleFillScratch {
  std::vector<float> directional[3], runs[3], inpainted[3];
  std::vector<double> background, runBackground;
  std::vector<uint8_t> found, runFound, mask;
  cv::Mat grown, groups;  // the inpainting's groups of holes (HoleFill.cpp)
  struct InpaintTask {    // one group's crop and one channel to inpaint
    int group, channel;
    cv::Rect crop;
  };
  std::vector<InpaintTask> tasks;
};

// Fills every hole of `layer` (hole mask cleared, inverse depth set to the background's where
// known). Returns the number of samples that were holes. `scratch`: reused buffers (nullptr: local).
size_t fillHoles(BlendedLayer& layer, const HoleFillOptions& options, HoleFillScratch* scratch = nullptr);

}  // namespace vs
