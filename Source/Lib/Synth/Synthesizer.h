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
// The 1D path (a rectified rig, Plan/Rectification.h) warps rows into rows instead. Every decision (path, weights,
// tolerances, which stages run) comes from the plan. The stages live in files of their own:
//   ReferenceEdges.cpp  reference depth edges: which reference samples are unreliable
//   DepthWarp.cpp       the general path's depth warp (triangles and points into a z-buffer)
//   RowPath.cpp         the 1D path: row depth warp, noise cleaning, crowded holes, row texture look-up
//   TextureWarp.cpp     the general texture look-up, boundary noise, samples occluded in other views
//   ChromaWarp.cpp      U and V at their own sample positions, from the luma depth
//   TemporalFill.h      1D TemporalImprovementOption: static holes keep the previous frame's fill
//   Synthesizer.cpp     the frame: the stages in order, on the threads, with their times
#include <chrono>
#include <memory>
#include <vector>

#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Common/Timing.h"
#include "Plan/MissingDepth.h"
#include "Plan/Plan.h"
#include "Synth/EdgeAlign.h"
#include "Synth/HoleFill.h"
#include "Synth/Interpolation.h"
#include "Synth/Layer.h"
#include "Synth/Occlusion.h"
#include "Synth/Parallel.h"
#include "Synth/RowWarp.h"
#include "Synth/ScratchPool.h"
#include "Synth/TemporalFill.h"
#include "Synth/Warp.h"

namespace vs {

// Statistics of the last frame, for the log and tests.
struct FrameStats {
  size_t holesAfterBlend = 0;      // luma samples no view covered, filled by the hole filler
  size_t alignedDepthSamples = 0;  // reference depth samples DepthEdgeAlignment moved to the near side
};

class Synthesizer {
public:
  // `plan`: makePlan(scene)'s decisions; its mode (General or Parallel1D) is the path taken. A plan
  // that copies a view (copyOf) is synthesized on its path all the same: copying is the caller's.
  Synthesizer(const Scene& scene, const Plan& plan);

  // Synthesizes the virtual view of one frame into `output` (reset to the texture format).
  void synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times);
  const FrameStats& lastStats() const { return stats_; }
  // The last frame's virtual depth (after hole filling) as levels of `range`, with the scene's
  // DepthType; samples nothing covered get level 0.
  void virtualDepth(const DepthRange& range, Plane& levels) const;
  // The last frame's mask (plan.virtualMaskOutput): 255 where no reference view gave the luma sample
  // (the holes after blending, which hole filling made up), 0 elsewhere.
  void virtualMask(Plane& mask) const;
  const Plan& plan() const { return plan_; }
  // MissingDepthLevel auto: the first frame's filled maps decideMissingDepth made for its counts (one
  // per view, or none). The next synthesize(), called with that same frame, takes a view's map instead
  // of filling and testing its depth again where the view's depth is the one it was made from; then
  // they are dropped.
  void takeFirstFrameFill(std::vector<FilledDepth> fills) { firstFrameFill_ = std::move(fills); }
  // For a run of one frame: each step's buffers are freed once the step is over, so that the later
  // steps take that memory from the heap again instead of first-touching fresh pages (doc/speed.md).
  // By default (a sequence) the depth steps' and the occlusion rule's buffers are freed after their
  // steps and the chroma layers once the frame is rounded, each taking the others' memory at the
  // heap's top, and the rest is kept for the next frame.
  void releaseBuffersAfterEachStep() { releaseSpent_ = true; }
  // For a run whose next synthesize() is its last: nothing is kept for a frame after it
  // (TemporalImprovementOption's holes and fill, which change nothing on a first frame).
  void noNextFrame() { noNextFrame_ = true; }

private:
  struct ViewState {
    explicit ViewState(ViewProjection p) : projection(p) {}
    ViewProjection projection;
    std::vector<double> levelToInverseDepth;  // per depth level; NaN for the missing level
    std::vector<double> levelToRowDepth;      // 1D: inverse camera depth per level; NaN: not warped
    WarpedLayer luma;                         // or RGB in ColorSpace 1
    WarpedLayer chroma;                       // U, V at chroma resolution (ColorSpace 0 with colour)
    std::vector<uint8_t> referenceStep;             // reference samples at a depth discontinuity (1D,
                                                    // SplattingOption 2, which reads them; else empty)
    std::vector<uint8_t> referenceEdge;             // the steps dilated by one sample: mixed colours
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

  // Working buffers of one parallel loop body (ScratchPool.h), one kind per stage.
  struct DepthRows {  // warpDepth: a row's inverse depths, and positions and depths of two rows
    std::vector<double> inverse, positions;
  };
  struct RowWarpRows {  // warpDepthRows: boundary flags and isolated samples of a row, and the row warp's
    std::vector<uint8_t> nearEdge, isolated;
    RowDepthWarp::Scratch warp;
  };
  struct TextureRows {  // warpTexture, warpTextureRows: each channel's row table, a row's source positions
    SampledRow sampled[3];
    std::vector<double> sourceU, sourceV, grid;
    std::vector<uint8_t> sourceOk;
    std::vector<int> rest;  // warpTexture: a row's samples left to its general look-up
  };
  struct ChromaRows {  // warpChroma: U and V row tables, a row's block depths, edges and source positions
    SampledRow sampledU, sampledV;
    std::vector<double> blockDepth, sourceU, sourceV, grid;
    std::vector<uint8_t> blockEdge, sourceOk;
  };

  enum class Spent { depthSteps, textureSteps, viewLayers, chromaLayers };
  void releaseSpentBuffers(Spent spent);
  // The blended layers hold the first view's planes since the last frame's blend (blendLayersIntoFirst):
  // they go back to the view, the view's former planes to the blended layers, for the view's warp.
  void takeBackFirstViewLayers();
  // The buffers kept past the depth steps that the steps would first allocate among those they free
  // (the views' luma layers, the reference edges, the depth warps' row sets) are placed before the
  // steps, so that what the steps free lies together for the next steps: in a sequence at the heap's
  // top, in a run of one frame in room taken for them below the kept ones (Synthesizer.cpp).
  void keepAheadOfSpentBuffers(const std::vector<ReferenceFrame>& references);
  bool reuseFirstFrameFill(size_t k, const Plane& depth);  // view k's fill from firstFrameFill_; false: none fits
  void markReferenceEdges(ViewState& view, const Plane& depth);               // ReferenceEdges.cpp
  void warpDepth(ViewState& view, const Plane& depth);                        // DepthWarp.cpp
  void warpDepthRows(ViewState& view, const Plane& depth);                    // RowPath.cpp
  void flagCrowdedHoles(ViewState& view);                                     // RowPath.cpp
  void warpTextureRows(ViewState& view, const std::vector<const Plane*>& planes);  // RowPath.cpp
  void warpTexture(ViewState& view, const std::vector<const Plane*>& planes);  // TextureWarp.cpp
  void removeBoundaryNoise(ViewState& view);                                  // TextureWarp.cpp
  void rejectOccludedInOtherViews();                                          // TextureWarp.cpp
  void warpChroma(ViewState& view, const Frame& texture);                     // ChromaWarp.cpp
  // Calls step(k) for every view k: the views side by side on the threads where that balances (see
  // synthesize), else one after the other with each step's loops on the threads.
  template <class Step>
  void forEachView(const Step& step);
  bool viewsSideBySide() const;  // forEachView runs the views side by side on the threads

  const Scene& scene_;
  const Plan plan_;
  const bool rowPath_;  // the 1D path: rows warp into rows (plan_.mode == Parallel1D)
  bool releaseSpent_ = false;  // releaseBuffersAfterEachStep()
  bool noNextFrame_ = false;   // noNextFrame()
  bool blendedInFirstView_ = false;  // the blended layers hold views_[0]'s planes (takeBackFirstViewLayers)
  FrameFormat outputFormat_;
  SubPixelSampler sampler_;
  DepthEdgeAligner aligner_;
  std::vector<ViewState> views_;
  std::vector<FilledDepth> firstFrameFill_;  // takeFirstFrameFill, until the next frame has used them
  BlendedLayer blendedLuma_, blendedChroma_;
  // Per-frame working buffers, kept so that a sequence allocates nothing once they have grown.
  HoleFillScratch lumaFill_, chromaFill_;
  OcclusionScratch occlusionScratch_;
  std::vector<Frame> rgbReferences_;
  Frame rgbOutput_;  // ColorSpace 1: the rounded R, G, B before conversion
  ScratchPool<DepthRows> depthRows_;
  ScratchPool<RowWarpRows> rowWarpRows_;
  ScratchPool<std::vector<uint8_t>> byteRows_;  // crack closing's flags, crowded holes' counts
  ScratchPool<TextureRows> textureRows_;
  ScratchPool<ChromaRows> chromaRows_;
  TemporalFill temporalFill_;
  FrameStats stats_;
  std::vector<uint8_t> uncovered_;  // the last frame's holes after blending (plan_.virtualMaskOutput)
};

}  // namespace vs
