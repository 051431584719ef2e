#pragma once
// MissingDepthLevel auto (doc/algorithms.md, "Depth level 0: far or missing"): depth level 0 is read
// as Zfar by VSRS and as "no depth" by MPEG-I's RVS and by our real data sets. The first frame's views
// tell which: each level-0 sample of a reference view is taken at Zfar and projected into the other
// reference views. Where such a view sees a valid, nearer surface there, or also level 0 but a colour
// that differs by more than the tolerance, "far" is contradicted. The plan then reads level 0 as
// missing and filled when most tested samples contradict it, and keeps VSRS's far reading otherwise.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Plan/Plan.h"

namespace vs {

// The evidence against the far reading in one reference view.
struct FarEvidence {
  size_t samples = 0;       // samples of the view
  size_t level0 = 0;        // of them at level 0
  size_t tested = 0;        // level-0 samples (on the test grid) seen by another reference view at Zfar
  size_t contradicted = 0;  // of those, hidden behind a nearer valid surface or of another colour
  double level0Fraction() const { return samples ? double(level0) / double(samples) : 0.0; }
  double contradictedFraction() const { return tested ? double(contradicted) / double(tested) : 0.0; }
};

// Luma difference, as a fraction of the largest sample value, beyond which two views see different
// surfaces; and the share of tested samples that must contradict Zfar for level 0 to be missing.
constexpr double kFarColourTolerance = 0.08;
constexpr double kFarContradictedShare = 0.65;

// Calls body(begin, end) on sub-ranges of [0, count) that together cover it, each once: the reference
// views' tests below are independent, so a caller with threads (the synthesizer's pool) runs them side
// by side. Empty: one call on the calling thread.
using ViewRangeRunner = std::function<void(int count, const std::function<void(int, int)>& body)>;

// Tests level 0's far reading in every reference view against the others (every second sample in
// both directions). `references`: the first frame's inputs, in the scene's order.
std::vector<FarEvidence> testFarReading(const Scene& scene, const std::vector<ReferenceFrame>& references,
                                        const ViewRangeRunner& runner = {});

// The per-run test that follows the fill under auto (doc/algorithms.md, "Depth level 0: far or
// missing"): each run of filled samples along a row (one level, the farther end's) is tested in the
// other reference views, in two steps.
// 1. The nearer end. The run may be an unmatched strip of the nearer surface (the occluder), not
//    background. It is taken for one when either (a) its samples, taken at the nearer neighbour's
//    level and projected into the other views, find colours there (whatever depth those views give
//    them) that differ from their own by less than kRunNearDifferenceRatio times the difference at
//    the filled level and by less than kFarColourTolerance on average; or (b) in its own view, the
//    run's mean luma is that close to the kRunSideSamples samples beyond its nearer end, against
//    those beyond its farther end. Then, from the nearer end inwards, samples take the nearer level
//    while each matches the other views there within kFarColourTolerance and at least as well as at
//    the filled level; the rest goes to step 2. Runs of at least kRunNearMinSamples only.
// 2. The filled level: every sample is taken at its filled level and projected into them: hidden
// there behind a nearer valid surface (what a half-occlusion looks like) or seen at that depth with the
// same colour (within kFarColourTolerance) agrees; seen behind it (the other view looks through where
// the sample would be), or at that depth with another colour, contradicts; missing there or outside
// tells nothing. Where more than kRunContradictedShare of the samples that tell something contradict
// the fill, the run is read as VSRS reads level 0: it is warped at the far end of the range (level 1,
// as level 0 stays the missing mark), still marked filled.
constexpr double kRunContradictedShare = 0.5;
constexpr double kRunNearDifferenceRatio = 0.3;
constexpr int kRunNearMinSamples = 2;
constexpr int kRunSideSamples = 3;
constexpr int kRunLevelTolerance8Bit = 3;  // levels of 255 within which two depths are one surface

struct RunTestCounts {
  size_t runs = 0, toNear = 0, toFar = 0;  // runs of filled samples, of them given the near or far level
  size_t samples = 0, near = 0, far = 0;   // filled samples, of them given the near or far level
};

// `filledDepth` and `filled`: view k's map after fillMissingDepthRuns with `missingLevel` and its
// marks; runs take the near level or the far level as the test says. `references`: this frame's inputs.
RunTestCounts testFilledRuns(const Scene& scene, size_t k, const std::vector<ReferenceFrame>& references,
                             int missingLevel, Plane& filledDepth, const std::vector<uint8_t>& filled);

// One reference view's depth map after fillMissingDepthRuns and testFilledRuns, and its marks.
struct FilledDepth {
  Plane depth;
  std::vector<uint8_t> filled;
};

// With plan.missingDepthAuto: sets plan.missingDepthLevel, missingDepthFill, missingDepthRunTest and
// missingDepthEvidence
// from testFarReading on the first frame, and marks the plan decided. Without it: nothing.
// With the run test chosen, its per-view counts are computed on the first frame's filled maps; given
// `firstFrameFill`, those maps (one per reference view, in the scene's order) are handed over, so that
// a renderer that draws this frame next need not fill and test them again. Otherwise it is left empty.
void decideMissingDepth(const Scene& scene, const std::vector<ReferenceFrame>& references, Plan& plan,
                        std::vector<FilledDepth>* firstFrameFill = nullptr, const ViewRangeRunner& runner = {});

}  // namespace vs
