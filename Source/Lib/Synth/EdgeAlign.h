#pragma once
// Depth edges moved onto the texture's edges (doc/algorithms.md, "Depth edges on texture edges").
//
// A depth map's edge and its texture's edge often disagree by a few samples: stereo and structured
// light lose the last samples of a foreground object (Middlebury codes them as level 0, "unknown"),
// and the far surface's depth then carries the foreground's colour. Warped, that colour lands far from
// the object, and the object comes out narrower. Here the nearer surface's depth grows along the line
// onto its colour: up to `reach` samples, as far as the strongest luma edge there, when
// - that edge is at least `minContrast` strong and twice as strong as the luma step at the depth edge,
//   and no luma step between the two is half as strong (one clear texture edge, not texture), and
// - every sample it takes over looks like the near side's last sample more than like the far side's
//   first sample beyond the texture edge, and
// - another reference view (the witness) sees the samples' colours where the near surface's depth
//   puts them better than where their own depth does, by a quarter of minContrast per sample.
// Rows first, then columns of the result. The near surface never shrinks: a foreground depth that
// reaches past its colour is left as it is.
#include <cstddef>
#include <optional>
#include <vector>

#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Plan/StageOptions.h"
#include "Synth/Warp.h"

namespace vs {

struct EdgeAlignOptions {
  int reach = 4;          // samples; 0: off
  int minStep = 8;        // depth-level step that makes a depth edge (depthEdgeStep)
  int minContrast = 16;   // luma step (texture levels) that makes a texture edge
  int missingLevel = -1;  // MissingDepthLevel: such samples are neither edges nor taken over; -1: none
};

// Another reference view that judges each move: it must see the moved samples' colours where the
// near depth puts them better than where their own depth does.
struct EdgeWitness {
  const Plane* luma = nullptr;                        // the witness texture's luma
  const ViewProjection* projection = nullptr;         // aligned view -> witness view
  const std::vector<double>* inverseDepth = nullptr;  // aligned view: level -> inverse depth (NaN: missing)
};

// `depth`'s edges aligned (see above) in place, each move judged by `witness`; returns how many
// samples changed level. Depth and luma of different sizes, or reach 0, leave it unchanged. Each
// pass reads its lines as they were before it from copies of a row (rows) or of a few rows (columns),
// so that no second map is needed.
size_t alignDepthEdgesInPlace(Plane& depth, const Plane& luma, const EdgeAlignOptions& options,
                              const EdgeWitness& witness);
// The same into `out`, a copy of `depth`.
size_t alignDepthEdges(const Plane& depth, const Plane& luma, const EdgeAlignOptions& options,
                       const EdgeWitness& witness, Plane& out);

// DepthEdgeAlignment for a scene's reference views: each view is judged by the nearest other one
// (camera centres). Off with one reference view (nothing to judge by) or DepthEdgeAlignment 0.
class DepthEdgeAligner {
public:
  // `missingLevel`: the level that carries no depth (the plan's; MissingDepthLevel auto decides it on
  // the first frame), -1: none. Without it: the settings' MissingDepthLevel.
  DepthEdgeAligner(const SynthesisSettings& settings, int missingLevel);
  explicit DepthEdgeAligner(const SynthesisSettings& settings)
      : DepthEdgeAligner(settings, settings.missingDepthLevel) {}
  bool enabled() const { return !views_.empty(); }
  int witness(size_t view) const { return enabled() ? views_[view].witness : -1; }
  // View k's depth map aligned, given every view's texture luma this frame; `depth` itself when off.
  // The result stays valid until the next call for the same view. Adds the samples moved to `moved`.
  const Plane& align(size_t view, const Plane& depth, const std::vector<const Plane*>& lumas, size_t& moved);
  // The same in `depth` itself (a map of the caller's that nothing else reads): no copy is made.
  void alignInPlace(size_t view, Plane& depth, const std::vector<const Plane*>& lumas, size_t& moved);
  // Frees the aligned maps (a run of one frame, once the depth warp has read them).
  void releaseMemory() {
    for (View& view : views_) std::vector<uint16_t>().swap(view.aligned.samples);
  }

private:
  struct View {
    int witness = -1;
    std::optional<ViewProjection> projection;  // this view -> its witness
    std::vector<double> inverseDepth;           // level -> inverse depth, NaN at the missing level
    EdgeAlignOptions options;
    Plane aligned;
  };
  std::vector<View> views_;
};

}  // namespace vs
