#include "Synth/Synthesizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <utility>

#include "Common/Depth.h"
#include "Common/Error.h"
#include "Plan/MissingDepth.h"
#include "Synth/Colour.h"

namespace vs {

Synthesizer::Synthesizer(const Scene& scene, const Plan& plan)
    : scene_(scene),
      plan_(plan),
      rowPath_(plan.mode == SynthesisMode::Parallel1D),
      outputFormat_(scene.settings.virtualFormat()),
      sampler_(plan.precision, plan.filter),
      aligner_(scene.settings, plan.missingDepthLevel) {
  VS_CHECK(plan_.tool == Tool::ViewSyn && plan_.mode != SynthesisMode::Auto);
  VS_CHECK(plan_.blending.weights.size() == scene.settings.references.size());
  const SynthesisSettings& s = scene.settings;
  for (const ReferenceView& reference : s.references) {
    ViewState view(ViewProjection(reference.camera, scene.virtualCamera, s.depthType, rowPath_));
    view.levelToInverseDepth = inverseZTable(reference.depthRange);
    if (plan_.missingDepthLevel >= 0) view.levelToInverseDepth[size_t(plan_.missingDepthLevel)] = std::nan("");
    if (rowPath_) {
      // The 1D warp's inverse camera depth per level, NaN where forward() refuses the level (missing,
      // behind, infinite): on a rectified pair it does not depend on the pixel.
      view.levelToRowDepth.resize(view.levelToInverseDepth.size());
      for (size_t level = 0; level < view.levelToRowDepth.size(); ++level) {
        double x, y, wv;
        const double inverseDepth = view.levelToInverseDepth[level];
        view.levelToRowDepth[level] =
            !std::isnan(inverseDepth) && view.projection.forward(0.0, 0.0, inverseDepth, x, y, wv) ? wv : std::nan("");
      }
    }
    views_.push_back(std::move(view));
  }
}

bool Synthesizer::reuseFirstFrameFill(size_t k, const Plane& depth) {
  FilledDepth& fill = firstFrameFill_[k];
  if (fill.depth.width != depth.width || fill.depth.height != depth.height ||
      fill.depth.samples.size() != depth.samples.size() || fill.filled.size() != depth.samples.size())
    return false;
  // Made from this map: equal to it where nothing was filled, and the missing level where it was
  // (the fill and the run test change only those samples). The differences ORed in 16-bit lanes,
  // with each mark (0 or 1) as a mask: a loop without branches that vectorises.
  const uint16_t missing = uint16_t(plan_.missingDepthLevel);
  const uint16_t* source = depth.samples.data();
  const uint16_t* made = fill.depth.samples.data();
  const uint8_t* marks = fill.filled.data();
  uint16_t differ = 0;
  for (size_t i = 0, n = depth.samples.size(); i < n; ++i) {
    const uint16_t filled = uint16_t(-uint16_t(marks[i] != 0));
    differ |= uint16_t(uint16_t((source[i] ^ made[i]) & ~filled) | uint16_t((source[i] ^ missing) & filled));
  }
  if (differ != 0) return false;
  ViewState& view = views_[k];
  std::swap(view.filledDepth, fill.depth);
  std::swap(view.filledSamples, fill.filled);
  return true;
}

void Synthesizer::virtualDepth(const DepthRange& range, Plane& levels) const {
  const int w = outputFormat_.width, h = outputFormat_.height;
  levels.resize(w, h);
  const Camera& camera = scene_.virtualCamera;
  parallelRanges(h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        const double inverse = blendedLuma_.inverseDepth[size_t(y) * w + x];
        double z = inverse > 0 ? 1.0 / inverse : HUGE_VAL;
        if (scene_.settings.depthType == 1 && std::isfinite(z)) z = camera.backProject(x, y, z).z;  // world z
        levels.at(x, y) = inverse < 0 ? 0 : uint16_t(zToLevelRounded(z, range));
      }
  });
}

void Synthesizer::virtualMask(Plane& mask) const {
  const int w = outputFormat_.width, h = outputFormat_.height;
  VS_CHECK(plan_.virtualMaskOutput && uncovered_.size() == size_t(w) * size_t(h));
  mask.resize(w, h);
  for (size_t i = 0; i < uncovered_.size(); ++i) mask.samples[i] = uncovered_[i] ? 255 : 0;
}

bool Synthesizer::viewsSideBySide() const {
  const size_t count = views_.size();
  const int threads = workerThreads();
  return count >= 2 && threads >= 2 && count % size_t(threads) == 0;
}

template <class Step>
void Synthesizer::forEachView(const Step& step) {
  // With as many views per thread on every thread (two views, two threads: the usual case), each
  // thread runs whole views: one hand-over per stage instead of one per loop inside it, and no thread
  // waits at the end of every loop for the other's last rows. The loops inside then run on the
  // calling thread (OpenCV runs a parallel_for_ inside another one sequentially). Each view's steps
  // write only that view's state, so the output is the same either way.
  const size_t count = views_.size();
  if (viewsSideBySide()) {
    parallelRanges(int(count), [&](int k0, int k1) {
      for (int k = k0; k < k1; ++k) step(size_t(k));
    });
    return;
  }
  for (size_t k = 0; k < count; ++k) step(k);
}

// Frees what the steps before `spent` used and nothing after reads: the later steps' buffers then take
// that memory from the heap again instead of fresh pages (doc/speed.md). A sequence frees the depth
// and texture steps' (keepAheadOfSpentBuffers placed what it keeps below them) but keeps the occlusion
// rule's sparse mapping, and the chroma layers once the frame is rounded; a run of one frame frees
// the views' layers after the blend.
void Synthesizer::releaseSpentBuffers(Spent spent) {
  auto releaseLayer = [](auto& layer) {
    releaseMemory(layer.inverseDepth);
    for (std::vector<float>& channel : layer.colour) releaseMemory(channel);
  };
  for (ViewState& view : views_) {
    switch (spent) {
      case Spent::depthSteps:
        releaseMemory(view.filledDepth.samples);
        releaseMemory(view.filledSamples);
        releaseMemory(view.referenceStep);
        break;
      case Spent::textureSteps:
        releaseMemory(view.referenceEdge);
        releaseMemory(view.dropScratch);
        releaseMemory(view.rowHoleScratch);
        break;
      case Spent::chromaLayers:
        releaseLayer(view.chroma);
        releaseMemory(view.chroma.edge);
        break;
      case Spent::viewLayers:
        for (WarpedLayer* layer : {&view.luma, &view.chroma}) {
          releaseLayer(*layer);
          releaseMemory(layer->edge);
        }
        break;
    }
  }
  if (spent == Spent::chromaLayers) {  // the first view's chroma planes, blended (blendLayersIntoFirst)
    releaseLayer(blendedChroma_);
    releaseMemory(blendedChroma_.hole);
  }
  if (spent == Spent::depthSteps) aligner_.releaseMemory();
  if (spent == Spent::textureSteps) {
    releaseMemory(occlusionScratch_.soleView);
    releaseMemory(occlusionScratch_.stillBehind);
    releaseMemory(occlusionScratch_.above);
    if (releaseSpent_) occlusionScratch_.around.release();  // a sequence keeps its mapping
  }
}

void Synthesizer::takeBackFirstViewLayers() {
  if (!blendedInFirstView_) return;
  blendedInFirstView_ = false;
  const bool yuvChroma = !plan_.rgb && plan_.chroma;  // blended as in synthesize
  for (auto [layer, blended] : {std::pair{&views_[0].luma, &blendedLuma_}, std::pair{&views_[0].chroma, &blendedChroma_}}) {
    if (blended == &blendedChroma_ && !yuvChroma) continue;
    std::swap(layer->inverseDepth, blended->inverseDepth);
    for (int c = 0; c < 3; ++c) std::swap(layer->colour[c], blended->colour[c]);
    std::swap(layer->edge, blended->hole);
  }
}

void Synthesizer::keepAheadOfSpentBuffers(const std::vector<ReferenceFrame>& references) {
  // A run of one frame: room for the depth steps' own buffers (per view the aligned depth and its
  // scratch, 2 + 2 bytes per reference sample, the reference steps and the dilation's rows, 1 + 1),
  // and 9 bytes per output sample more, and 2 per view for the texture steps' flags (boundary noise,
  // crowded holes), is taken first and handed back once the buffers kept past the steps are placed
  // above it. The depth steps then allocate there, from its start, below the layers; freed after the
  // depth warp, they leave one block that the texture steps' flags and the occlusion rule's column scan
  // and surroundings (8 + 8 bytes per output sample: together more than the depth steps') fit in, then
  // the chroma layers, instead of fresh pages at the heap's top (Art: 5900 or 6650 page faults, by the
  // threads' order, doc/speed.md). Only address space: malloc writes none of it, and what nothing
  // takes is never touched.
  void* depthStepsRoom = nullptr;
  if (releaseSpent_) {
    size_t samples = 0;
    for (const ReferenceFrame& reference : references) samples += reference.depth->samples.size();
    const size_t outputSamples = size_t(outputFormat_.width) * size_t(outputFormat_.height);
    depthStepsRoom = std::malloc(6 * samples + (9 + 2 * views_.size()) * outputSamples + (size_t(64) << 10));
  }
  for (size_t k = 0; k < views_.size(); ++k) {
    ViewState& view = views_[k];
    // Placed, not written: each view's thread writes its own (the depth warp, markReferenceEdges).
    view.luma.reserve(outputFormat_.width, outputFormat_.height, plan_.rgb ? 3 : 1);
    view.referenceEdge.reserve(references[k].depth->samples.size());
  }
  // The depth warps' row buffers, which the pools keep: grown among the depth steps' buffers, one
  // thread's set split the memory those leave for the occlusion rule's in about half the runs of one
  // frame (Art: 740 more page faults). Sized as the warps size them (DepthWarp.cpp, RowPath.cpp,
  // RowWarp.cpp). (Crack closing's row flags, byteRows_, grown here too put the occlusion rule's
  // buffers at the heap's top again: 6290 page faults.)
  size_t width = 0;
  for (const ReferenceFrame& reference : references) width = std::max(width, size_t(reference.depth->width));
  const size_t outWidth = size_t(outputFormat_.width), sets = size_t(std::max(1, workerThreads()));
  if (rowPath_) {
    rowWarpRows_.prepare(sets, [&](RowWarpRows& rows) {
      rows.nearEdge.resize(width);
      rows.isolated.resize(outWidth);
      for (std::vector<double>* row : {&rows.warp.xs, &rows.warp.ws}) row->resize(width);
      rows.warp.segments.resize(width);
    });
  } else {
    depthRows_.prepare(sets, [&](DepthRows& rows) {
      rows.inverse.resize(width);
      rows.positions.resize(width * 6);
    });
  }
  std::free(depthStepsRoom);
}

void Synthesizer::synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) {
  VS_CHECK(references.size() == views_.size());
  auto start = std::chrono::steady_clock::now();
  takeBackFirstViewLayers();
  const bool rgb = plan_.rgb, yuvChroma = !plan_.rgb && plan_.chroma;
  std::vector<const Plane*> lumas, depths;
  for (const ReferenceFrame& reference : references) {
    lumas.push_back(&reference.texture->planes[0]);
    depths.push_back(reference.depth);
  }
  keepAheadOfSpentBuffers(references);
  auto depthSteps = [&](size_t k) {
    ViewState& view = views_[k];
    const Plane* depth = references[k].depth;
    const bool filled = plan_.missingDepthFill;
    if (filled && !(k < firstFrameFill_.size() && reuseFirstFrameFill(k, *depth))) {
      // Missing runs between valid samples take the farther level; the inverse-depth table has NaN
      // at the missing level, which fillMissingDepthRuns never picks (both ends are valid).
      fillMissingDepthRuns(*depth, plan_.missingDepthLevel, view.levelToInverseDepth, view.filledDepth,
                           view.filledSamples);
      // Auto: each filled run is tested in the other views: kept, given the nearer side's level, or read
      // as VSRS reads level 0 (Plan/MissingDepth.h).
      if (plan_.missingDepthRunTest)
        testFilledRuns(scene_, k, references, plan_.missingDepthLevel, view.filledDepth, view.filledSamples);
    }
    view.alignedSamples = 0;
    if (filled) {  // the filled map is the view's own: aligned in place, without a copy
      aligner_.alignInPlace(k, view.filledDepth, lumas, view.alignedSamples);
      depth = &view.filledDepth;
    } else {
      depth = &aligner_.align(k, *depth, lumas, view.alignedSamples);
    }
    markReferenceEdges(view, *depth);
    // Estimated depth is unreliable: where another view has a real one on the same surface, it wins
    // (also where alignment then gave a filled sample the near side's level).
    if (filled)
      for (size_t i = 0; i < view.referenceEdge.size(); ++i) view.referenceEdge[i] |= view.filledSamples[i];
    if (rowPath_) warpDepthRows(view, *depth);
    else warpDepth(view, *depth);
  };
  forEachView(depthSteps);
  firstFrameFill_.clear();
  releaseSpentBuffers(Spent::depthSteps);
  stats_.alignedDepthSamples = 0;
  for (const ViewState& view : views_) stats_.alignedDepthSamples += view.alignedSamples;
  times.depthWarp += secondsSince(start);

  start = std::chrono::steady_clock::now();
  if (rgb) rgbReferences_.resize(views_.size());
  forEachView([&](size_t k) {
    ViewState& view = views_[k];
    const Frame& texture = *references[k].texture;
    std::vector<const Plane*> planes = {&texture.planes[0]};
    if (rgb) {
      yuvToRgb(texture, rgbReferences_[k]);
      planes = {&rgbReferences_[k].planes[0], &rgbReferences_[k].planes[1], &rgbReferences_[k].planes[2]};
    }
    if (rowPath_) warpTextureRows(view, planes);
    else warpTexture(view, planes);
    if (plan_.boundaryNoiseRemoval) removeBoundaryNoise(view);
    if (plan_.crowdedHoles) flagCrowdedHoles(view);
  });
  if (views_.size() > 1) rejectOccludedInOtherViews();
  // Before the chroma warp, which reads the luma layers and the references only: its layers take
  // this memory.
  releaseSpentBuffers(Spent::textureSteps);
  // Chroma follows the luma decisions: it is warped from the final luma depth.
  if (yuvChroma) forEachView([&](size_t k) { warpChroma(views_[k], *references[k].texture); });
  times.textureWarp += secondsSince(start);

  start = std::chrono::steady_clock::now();
  // Blended over the first view's layers: the blended layers take their memory (Layer.h), and give it
  // back at the next frame's start.
  std::vector<WarpedLayer*> lumaLayers, chromaLayers;
  for (ViewState& view : views_) {
    lumaLayers.push_back(&view.luma);
    chromaLayers.push_back(&view.chroma);
  }
  blendLayersIntoFirst(lumaLayers, plan_.blending, blendedLuma_);
  if (yuvChroma) blendLayersIntoFirst(chromaLayers, plan_.blending, blendedChroma_);
  blendedInFirstView_ = true;
  stats_.holesAfterBlend = blendedLuma_.holeCount();
  if (plan_.virtualMaskOutput) uncovered_ = blendedLuma_.hole;  // hole filling clears the flags
  if (releaseSpent_) releaseSpentBuffers(Spent::viewLayers);
  times.blend += secondsSince(start);

  start = std::chrono::steady_clock::now();
  // TemporalImprovementOption keeps this frame's holes and fill (and the references' depth and luma)
  // for the next frame, and changes nothing on the first: without a next frame (noNextFrame) none is
  // kept. In a run of one 1D frame that was a third of the hole-filling stage: copies into memory
  // touched for the first time (doc/speed.md).
  const bool temporalFill = plan_.temporalFill && !noNextFrame_;
  if (temporalFill) temporalFill_.noteHoles(blendedLuma_, blendedChroma_);
  std::vector<HoleFillJob> fills = {{&blendedLuma_, &plan_.lumaFill, &lumaFill_}};
  if (yuvChroma) fills.push_back({&blendedChroma_, &plan_.chromaFill, &chromaFill_});
  fillHoles(fills);
  if (temporalFill)
    temporalFill_.keepStaticFill(depths, lumas, blendedLuma_, blendedChroma_, yuvChroma,
                                 outputFormat_.chroma == ChromaFormat::Yuv420 ? 2 : 1);
  times.holeFill += secondsSince(start);

  // Sized here, not before the steps: a run of one frame then takes the memory the steps freed.
  output.reset(outputFormat_);
  roundLayersToFrame(blendedLuma_, blendedChroma_, rgb, rgbOutput_, output);
  if (!releaseSpent_ && yuvChroma) releaseSpentBuffers(Spent::chromaLayers);
}

}  // namespace vs
