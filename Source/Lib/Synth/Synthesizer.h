#pragma once
// ViewSyn's per-frame pipeline, general mode (doc/algorithms.md):
//   1. depth warp: every reference pixel is projected into the virtual camera; the depth grid is
//      rasterised as triangles (those spanning a depth discontinuity are dropped) and as points into
//      a floating-point z-buffer of inverse depth; one- and two-pixel cracks between samples of one
//      surface are closed with the farther of their two sides
//   2. texture warp: every virtual sample with depth looks its colour up in the reference at the
//      sub-pixel position its depth gives (Precision, Filter), luma at luma positions and chroma at
//      chroma positions (no sample replication)
//   3. blend the views (Layer.h), 4. fill the holes (HoleFill.h), 5. round into the output frame
#include <chrono>
#include <memory>
#include <vector>

#include "Common/Frame.h"
#include "Common/Timing.h"
#include "Common/Scene.h"
#include "Synth/HoleFill.h"
#include "Synth/Interpolation.h"
#include "Synth/Layer.h"
#include "Synth/Occlusion.h"
#include "Synth/EdgeAlign.h"
#include "Synth/Parallel.h"
#include "Synth/Warp.h"

namespace vs {

// Statistics of the last frame, for the log and tests.
struct FrameStats {
  size_t holesAfterBlend = 0;      // luma samples no view covered, filled by the hole filler
  size_t alignedDepthSamples = 0;  // reference depth samples DepthEdgeAlignment moved to the near side
};

class Synthesizer {
public:
  // `mode` is General or Parallel1D (the plan's choice; Parallel1D needs a rectified rig).
  explicit Synthesizer(const Scene& scene, SynthesisMode mode = SynthesisMode::General);

  // Synthesizes the virtual view of one frame into `output` (reset to the texture format).
  void synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times);
  const FrameStats& lastStats() const { return stats_; }
  // The last frame's virtual depth (after hole filling) as levels of `range`, with the scene's
  // DepthType; samples nothing covered get level 0.
  void virtualDepth(const DepthRange& range, Plane& levels) const;
  // Hole filling as this scene gets it (MeshRender fills its holes the same way).
  const HoleFillOptions& holeFillOptions() const { return fillOptions_; }
  const std::vector<double>& blendWeights() const { return blendOptions_.weights; }

  // Inverse-depth tolerance that makes two samples one surface (DepthBlendDifference, in 8-bit levels
  // of the reference depth ranges).
  double depthTolerance() const { return blendOptions_.depthTolerance; }

private:
  struct ViewState {
    explicit ViewState(ViewProjection p) : projection(p) {}
    ViewProjection projection;
    std::vector<double> levelToInverseDepth;  // per depth level; NaN for the missing level
    std::vector<double> levelToRowDepth;      // 1D: inverse camera depth per level; NaN: not warped
    WarpedLayer luma;                         // or RGB in ColorSpace 1
    WarpedLayer chroma;                       // U, V at chroma resolution (ColorSpace 0 with colour)
    std::vector<uint8_t> referenceStep;             // reference samples at a depth discontinuity
    std::vector<uint8_t> referenceEdge;             // the same, dilated by one sample: mixed colours
    std::vector<uint8_t> referenceStepRows;         // scratch of the dilation
    Plane filledDepth;                              // MissingDepthFill: the depth map with runs filled
    std::vector<uint8_t> filledSamples;             // the samples given a level there
    // Per-frame working buffers of the view's own steps (a view's steps may run beside another's).
    std::vector<uint8_t> dropScratch;                      // removeBoundaryNoise
    std::vector<uint8_t> rowHoleScratch;                   // flagCrowdedHoles: holes along rows
    size_t alignedSamples = 0;                             // this frame's depth edge alignment count
    // The general depth warp's z-buffer where the threads of the view's warp share it (the views do
    // not run side by side); one thread draws into the layer's depth instead.
    AtomicMaxBuffer zbuffer;
  };

  void warpDepth(ViewState& view, const Plane& depth);
  void warpDepthRows(ViewState& view, const Plane& depth);
  void flagCrowdedHoles(ViewState& view);
  void keepStaticFill(const std::vector<ReferenceFrame>& references, std::vector<uint8_t>& lumaHoles,
                      std::vector<uint8_t>& chromaHoles);
  void markReferenceEdges(ViewState& view, const Plane& depth);
  void warpTexture(ViewState& view, const std::vector<const Plane*>& planes);
  void warpChroma(ViewState& view, const Frame& texture);
  void removeBoundaryNoise(ViewState& view);
  // Calls step(k) for every view k: the views side by side on the threads where that balances (see
  // synthesize), else one after the other with each step's loops on the threads.
  template <class Step>
  void forEachView(const Step& step);
  bool viewsSideBySide() const;  // forEachView runs the views side by side on the threads
  void rejectOccludedInOtherViews();

  const Scene& scene_;
  bool parallel_;          // the 1D path
  FrameFormat outputFormat_;
  bool rgb_;
  bool hasChroma_;
  SubPixelSampler sampler_;
  double discontinuity_;   // inverse-depth step that separates surfaces in the z-buffer
  int edgeLevelStep_;      // depth-level step that marks a reference depth edge
  BlendOptions blendOptions_;
  HoleFillOptions fillOptions_;
  DepthEdgeAligner aligner_;
  std::vector<ViewState> views_;
  BlendedLayer blendedLuma_, blendedChroma_;
  // Per-frame working buffers, kept so that a sequence allocates nothing once they have grown.
  HoleFillScratch lumaFill_, chromaFill_;
  OcclusionScratch occlusionScratch_;
  std::vector<Frame> rgbReferences_;
  Frame rgbOutput_;  // ColorSpace 1: the rounded R, G, B before conversion
  FrameStats stats_;
  // 1D TemporalImprovementOption: the previous frame's depth, texture luma, holes and filled colours.
  std::vector<Plane> previousDepth_, previousLuma_;
  std::vector<uint8_t> previousHoles_, previousChromaHoles_;
  std::vector<uint8_t> lumaHolesScratch_, chromaHolesScratch_;  // this frame's holes before filling
  std::vector<float> previousColour_[3], previousChromaColour_[3];
  bool havePrevious_ = false;
};

}  // namespace vs
