// The 1D path (doc/algorithms.md, "The 1D path"): on a rectified rig a reference row maps to the same
// row of the virtual view, so depth and texture are warped row by row. VSRS's 1D keys act here:
// SplattingOption and BoundaryGrowth (the row depth warp), CleanNoiseOption (isolated samples),
// MergingOption 2's hole counting (crowded holes), WarpEnhancementOption (ReferenceEdges.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "Synth/Cracks.h"
#include "Synth/Flags.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Synthesizer.h"

namespace vs {

namespace {

// clearRows (Layer.h) split in two: the depth rows, cleared by the depth warp, and the colours and
// edge flags, cleared by the texture warp before its look-ups write them.
void clearDepthRows(WarpedLayer& layer, int y0, int y1) {
  const size_t begin = size_t(y0) * size_t(layer.width), end = size_t(y1) * size_t(layer.width);
  std::fill(layer.inverseDepth.data() + begin, layer.inverseDepth.data() + end, kNoDepth);
}

void clearColourRows(WarpedLayer& layer, int y0, int y1) {
  const size_t begin = size_t(y0) * size_t(layer.width), end = size_t(y1) * size_t(layer.width);
  for (int k = 0; k < layer.channels; ++k) std::fill(layer.colour[k].data() + begin, layer.colour[k].data() + end, 0.0f);
  std::fill(layer.edge.data() + begin, layer.edge.data() + end, uint8_t(0));
}

// CleanNoiseOption on one row of a layer's depth: a sample with holes on both sides along its row is
// a stray point of a surface seen elsewhere, removed before it picks up colour. Removing a sample
// never changes the decision for the next one (it is removed only when the next is a hole, which is
// then not removed either), so the decisions are taken on the row as it was: a branch-free pass
// compiled for the CPU's x86-64 level (Synth/Kernels/Rows.h) flags the samples (in `isolated`, width
// bytes), and only those are then cleared.
void cleanIsolatedSamples(double* row, int width, uint8_t* isolated) {
  if (width < 3) return;
  rowKernels().isolatedSamples(row, width, isolated);
  forEachFlag(isolated + 1, width - 2, [&](int x) { row[x + 1] = kNoDepth; });
}

}  // namespace

void Synthesizer::warpDepthRows(ViewState& view, const Plane& depth) {
  // 1D: rows map to rows, so each thread warps whole rows straight into the layer (RowDepthWarp):
  // samples move along the row by the disparity of their level, the depth grid is rasterised as
  // segments between horizontal neighbours on one surface, and every sample also lands as a point.
  // SplattingOption 2 draws segments only within BoundaryGrowth samples of a reference depth edge.
  const int w = depth.width, h = depth.height;
  const int outW = outputFormat_.width, outH = outputFormat_.height;
  const OneDOptions& oneD = scene_.settings.oneD;
  // Only the depth plane here, cleared row by row below: the colours and edge flags are sized by the
  // texture warp, which writes them, so that in a run of one frame they take the memory the depth
  // steps' maps give back in between (Synthesizer::releaseSpentBuffers) instead of fresh pages.
  WarpedLayer& layer = view.luma;
  layer.width = outW;
  layer.height = outH;
  layer.channels = plan_.rgb ? 3 : 1;
  // A plane allocated here (a run's first frame) is filled with "no depth" as it is allocated: the
  // fill that zeroing it would be, and no clearing of its rows after.
  const bool cleared = layer.inverseDepth.size() != size_t(outW) * size_t(outH);
  if (cleared) layer.inverseDepth.assign(size_t(outW) * size_t(outH), kNoDepth);
  // Rows below the reference (an output taller than it) receive nothing.
  if (outH > h && !cleared) clearDepthRows(layer, h, outH);
  const RowDepthWarp rowWarp(view.projection, view.levelToRowDepth, plan_.discontinuity, oneD.splatting);
  parallelRanges(std::min(h, outH), [&](int y0, int y1) {
    const int width = w, outWidth = outW, growth = oneD.boundaryGrowth;
    const bool nearEdges = oneD.splatting == 2;
    const bool cleanNoise = plan_.cleanNoise;
    const double discontinuity = plan_.discontinuity;
    // The row's boundary flags and isolated samples, and the row warp's buffers.
    const auto scratch = rowWarpRows_.take();
    std::vector<uint8_t>& nearRow = scratch->nearEdge;
    std::vector<uint8_t>& isolatedRow = scratch->isolated;
    nearRow.resize(size_t(width));
    isolatedRow.resize(size_t(outWidth));
    for (int y = y0; y < y1; ++y) {
      if (!cleared) clearDepthRows(layer, y, y + 1);
      // Within BoundaryGrowth samples of a reference depth edge.
      if (nearEdges) markWithinReach(view.referenceStep.data() + size_t(y) * width, width, growth, nearRow.data());
      double* row = view.luma.inverseDepth.data() + size_t(y) * outWidth;
      rowWarp.warp(depth.row(y), width, nearRow.data(), row, outWidth, scratch->warp);
      // A row is all its own warp writes: it is cleaned, and its cracks closed (closeCracks' row pass,
      // which takes each row by itself), while it is at hand.
      if (cleanNoise) cleanIsolatedSamples(row, outWidth, isolatedRow.data());
      closeRowCracks(row, outWidth, discontinuity, isolatedRow.data());
    }
  });
  // Rows below the reference hold no depth: no crack. Then closeCracks' column pass.
  closeColumnCracks(view.luma.inverseDepth, outW, outH, plan_.discontinuity, byteRows_);
}

void Synthesizer::flagCrowdedHoles(ViewState& view) {
  WarpedLayer& layer = view.luma;
  // MergingOption 2's hole counting: a sample with more than HoleCountThreshold holes in its 7x7
  // neighbourhood is unreliable; where another view agrees and is not, that view is used.
  const int w = layer.width, h = layer.height, threshold = scene_.settings.oneD.holeCountThreshold;
  // Separable counts: holes among the 7 samples of each row around x (clipped at the borders), then
  // the sum of those over the 7 rows around y.
  std::vector<uint8_t>& rowHoles = view.rowHoleScratch;
  rowHoles.resize(size_t(w) * h);
  parallelRanges(h, [&](int y0, int y1) {
    // The row's hole flags with three clear flags on either side (beyond the border), then seven
    // shifted sums: both loops are branch-free byte loops that vectorise.
    const auto scratch = byteRows_.take();
    std::vector<uint8_t>& paddedRow = *scratch;
    paddedRow.assign(size_t(w) + 6, 0);
    uint8_t* padded = paddedRow.data();
    const int width = w;
    const RowKernels& kernels = rowKernels();  // the loops compiled for the CPU's x86-64 level
    for (int y = y0; y < y1; ++y)
      kernels.holeCounts(layer.inverseDepth.data() + size_t(y) * width, width, padded,
                         rowHoles.data() + size_t(y) * width);
  });
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
    const int width = w, height = h, most = threshold;  // locals: see markReferenceEdges
    // The 7 rows' sum (at most 49) as a window that slides down the thread's rows: the row entering
    // added, the one leaving taken away (byte arithmetic, exact as the sums stay below 256).
    const auto scratch = byteRows_.take();
    std::vector<uint8_t>& sumRow = *scratch;
    sumRow.assign(size_t(width), 0);
    uint8_t* sum = sumRow.data();
    const RowKernels& kernels = rowKernels();  // the loops compiled for the CPU's x86-64 level
    auto counts = [&](int r) { return rowHoles.data() + size_t(r) * width; };
    // Rows rowBegin - 4 to rowBegin + 2: the first step takes row rowBegin - 4 away again.
    for (int r = std::max(0, rowBegin - 4); r < std::min(height, rowBegin + 3); ++r)
      kernels.windowStep(sum, counts(r), nullptr, nullptr, width, most);
    for (int y = rowBegin; y < rowEnd; ++y)
      kernels.windowStep(sum, y + 3 < height ? counts(y + 3) : nullptr, y - 4 >= 0 ? counts(y - 4) : nullptr,
                         layer.edge.data() + size_t(y) * width, width, most);
  });
}

void Synthesizer::warpTextureRows(ViewState& view, const std::vector<const Plane*>& planes) {
  WarpedLayer& layer = view.luma;
  const int refW = planes[0]->width, refH = planes[0]->height;
  // The colours and edge flags (the depth warp sized the depth plane only), cleared row by row below
  // unless allocated here (from empty, resize leaves them 0, the cleared value).
  bool cleared = layer.edge.empty();
  for (int c = 0; c < layer.channels; ++c) cleared = cleared && layer.colour[c].empty();
  layer.resize(layer.width, layer.height, layer.channels);
  // Rows map to rows: the look-up stays in row y (as backward() gives v = y). The tap and channel
  // counts are compile-time constants, so that the channel loop unrolls.
  auto warpRows = [&](auto taps, auto channelCount) {
    constexpr int kTaps = decltype(taps)::value, kChannels = decltype(channelCount)::value;
    parallelRanges(std::min(layer.height, refH), [&](int y0, int y1) {
      // Local copies of what the loop reads: the edge flags are bytes, and a byte store may alias
      // anything the loop would otherwise read through a pointer or a capture, reloading it per sample.
      const ViewProjection projection = view.projection;
      const SubPixelSampler sampler = sampler_;
      const int width = layer.width, referenceWidth = refW;
      double* depth = layer.inverseDepth.data();
      float* colour[3] = {layer.colour[0].data(), layer.colour[1].data(), layer.colour[2].data()};
      uint8_t* edgeOut = layer.edge.data();
      // Each reference row sampled once at every grid position (SampledRow): the look-ups below are
      // loads. Positions in [-0.5, width - 0.5] have integer parts in [-1, width].
      const auto scratch = textureRows_.take();
      SampledRow* sampledRows = scratch->sampled;
      // The row's source positions first, in a pass that vectorises (holes too: not read).
      std::vector<double>& sourceRow = scratch->sourceU;
      sourceRow.resize(size_t(width));
      scratch->rest.resize(size_t(width));
      double* sources = sourceRow.data();
      int* rest = scratch->rest.data();
      RowTableRow row = {sources, double(sampler.precision()), referenceWidth - 0.5, double(referenceWidth - 1),
                         {nullptr, nullptr, nullptr}, 0, 0, 0, 0, 0, kChannels, nullptr, nullptr,
                         {nullptr, nullptr, nullptr}, nullptr};
      const RowKernels& kernels = rowKernels();
      for (int y = y0; y < y1; ++y) {
        if (!cleared) clearColourRows(layer, y, y + 1);
        for (int c = 0; c < kChannels; ++c) sampledRows[c].build<kTaps>(sampler, *planes[size_t(c)], y, -1, referenceWidth);
        projection.rowSources(depth + size_t(y) * width, width, sources);
        // The look-ups, in a kernel compiled for the CPU's x86-64 level: every one whose grid index
        // the tables hold (on this path all but those of a table narrower than [-1, width]).
        const SampledRow& table = sampledRows[0];  // every channel's has the same shape
        for (int c = 0; c < kChannels; ++c) {
          row.table[c] = sampledRows[c].values();
          row.colour[c] = colour[c] + size_t(y) * width;
        }
        row.first = table.first();
        row.last = table.last();
        row.stride = table.stride();
        row.shift = table.shift();
        row.mask = table.mask();
        row.edges = view.referenceEdge.data() + size_t(y) * referenceWidth;
        row.depth = depth + size_t(y) * width;
        row.edgeOut = edgeOut + size_t(y) * width;
        int restCount = 0;
        kernels.rowTableRow(row, width, rest, restCount);
        for (int k = 0; k < restCount; ++k) {
          const int x = rest[k];
          const double u = sources[x];
          for (int c = 0; c < kChannels; ++c) row.colour[c][x] = sampledRows[c].at<kTaps>(u);
        }
      }
    });
  };
  sampler_.withTaps([&](auto taps) {
    if (layer.channels == 3) warpRows(taps, std::integral_constant<int, 3>());
    else warpRows(taps, std::integral_constant<int, 1>());
  });
  // Rows below the reference (an output taller than it) look up nothing.
  if (layer.height > refH && !cleared) clearColourRows(layer, refH, layer.height);
  for (size_t i = size_t(std::min(layer.height, refH)) * layer.width; i < layer.inverseDepth.size(); ++i)
    layer.inverseDepth[i] = kNoDepth;
}

}  // namespace vs
