// The general path's texture look-up (doc/algorithms.md, "Warping"): every virtual sample with depth
// looks its colour up in the reference at the sub-pixel position its depth gives; then the samples
// that carry colour bled across a depth edge (BoundaryNoiseRemoval) and those occluded in the other
// views are dropped, for the other view or the hole filler to supply.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "Synth/Kernels/Rows.h"
#include "Synth/Occlusion.h"
#include "Synth/Synthesizer.h"

namespace vs {

static_assert(kKernelNoDepth == kNoDepth, "the row kernels' hole is the layers' hole");

namespace {

// A sample seen by one view only is dropped when it lies this many discontinuity steps behind every
// surface the other view shows around that spot (rejectOccludedInOtherViews).
constexpr double kBehindHoleSteps = 3.0;

}  // namespace

void Synthesizer::warpTexture(ViewState& view, const std::vector<const Plane*>& planes) {
  WarpedLayer& layer = view.luma;
  const int refW = planes[0]->width, refH = planes[0]->height;
  sampler_.withTaps([&](auto taps) {
    constexpr int kTaps = decltype(taps)::value;
    parallelRanges(layer.height, [&](int y0, int y1) {
      // Locals, as in warpTextureRows (RowPath.cpp).
      const ViewProjection projection = view.projection;
      const SubPixelSampler sampler = sampler_;
      const int width = layer.width, channels = layer.channels, referenceWidth = refW, referenceHeight = refH;
      double* depth = layer.inverseDepth.data();
      float* colour[3] = {layer.colour[0].data(), layer.colour[1].data(), layer.colour[2].data()};
      uint8_t* edgeOut = layer.edge.data();
      const uint8_t* edges = view.referenceEdge.data();
      // A look-up that lands on this row's own reference row (a whole row of the grid: every one on a
      // rectified rig) is the row sampler's value, read from the row's table (SampledRow, as on the 1D
      // path), built the first time one does; any other goes through the 2D kernel.
      const auto scratch = textureRows_.take();
      SampledRow* sampledRows = scratch->sampled;
      int tableRow = -1;
      // The row's backward projections first, in a loop that vectorises (holes too: not read), compiled
      // for the CPU's x86-64 level (Synth/Kernels/Rows.h).
      scratch->sourceU.resize(size_t(width));
      scratch->sourceV.resize(size_t(width));
      scratch->sourceOk.resize(size_t(width));
      // Their addresses in locals: read through the scratch set they would be looked up again for
      // every sample.
      double* us = scratch->sourceU.data();
      double* vs = scratch->sourceV.data();
      uint8_t* ok = scratch->sourceOk.data();
      scratch->rest.resize(size_t(width));
      int* rest = scratch->rest.data();
      const double precision = sampler.precision();
      // An ERP reference's texture continues round the wrap and across its poles: a look-up near its
      // edges reads there (sampleSphereTaps); every other one is read as from a pinhole reference.
      const SphereEdges sphere = projection.referenceSphere();
      const bool sphereEdges = sphere.any();
      const RowKernels& kernels = rowKernels();
      for (int y = y0; y < y1; ++y) {
        projection.backwardRow(depth + size_t(y) * width, width, y, us, vs, ok);
        // sampler.wholeRow(v, row) && row == y: the grid index of v is y's (a row's grid index is
        // y * precision, and one of 2^52 or more is no row's).
        const double rowGrid = double(y) * precision;
        // Sample x's look-up, as a whole. Its grid indices (SampledRow::gridIndex) and nearest reference
        // sample as Kernels/Rows.h's textureLookups gives them (the position is in the picture there).
        const auto lookUp = [&](int x) {
          const size_t i = size_t(y) * width + x;
          if (depth[i] < 0) return;
          const double u = us[x], v = vs[x];
          if (!ok[x] || u < -0.5 || v < -0.5 || u > referenceWidth - 0.5 || v > referenceHeight - 0.5) {
            depth[i] = kNoDepth;
            return;
          }
          if (sphereEdges && SubPixelSampler::nearEdge(u, v, referenceWidth, referenceHeight)) {
            for (int c = 0; c < channels; ++c)
              colour[c][i] = sampler.sampleSphereTaps<kTaps>(*planes[size_t(c)], u, v, sphere);
          } else if (std::floor(v * precision + 0.5) == rowGrid) {
            if (tableRow != y) {
              for (int c = 0; c < channels; ++c) sampledRows[c].build<kTaps>(sampler, *planes[size_t(c)], y, -1, referenceWidth);
              tableRow = y;
            }
            const double gridU = std::floor(u * precision + 0.5);
            for (int c = 0; c < channels; ++c) colour[c][i] = sampledRows[c].atGrid<kTaps>(u, gridU);
          } else {
            for (int c = 0; c < channels; ++c) colour[c][i] = sampler.sampleTaps<kTaps>(*planes[size_t(c)], u, v);
          }
          const double nearest = std::clamp(std::floor(v + 0.5), 0.0, referenceHeight - 1.0) * referenceWidth +
                                 std::clamp(std::floor(u + 0.5), 0.0, referenceWidth - 1.0);
          edgeOut[i] = edges[size_t(nearest)];
        };
        if (sphereEdges) {
          for (int x = 0; x < width; ++x) lookUp(x);
          continue;
        }
        // The holes, the failed look-ups and those read from the row's tables in a kernel compiled for
        // the CPU's x86-64 level (Synth/Kernels/Rows.h; the tables are built where it first finds one
        // that reads them), the rest here.
        const size_t rowStart = size_t(y) * width;
        TextureTableRow row = {us, vs, ok, nullptr, nullptr, nullptr, precision, rowGrid, referenceWidth - 0.5,
                               referenceHeight - 0.5,
                               {nullptr, nullptr, nullptr}, 0, 0, 0, 0, 0, channels, edges, depth + rowStart,
                               {nullptr, nullptr, nullptr}, edgeOut + rowStart};
        for (int c = 0; c < channels; ++c) row.colour[c] = colour[c] + rowStart;
        int restCount = 0;
        for (int x = 0; (x = kernels.textureTableRow(row, x, width, tableRow == y, rest, restCount)) < width;) {
          for (int c = 0; c < channels; ++c) sampledRows[c].build<kTaps>(sampler, *planes[size_t(c)], y, -1, referenceWidth);
          tableRow = y;
          const SampledRow& table = sampledRows[0];  // every channel's has the same shape
          for (int c = 0; c < channels; ++c) row.table[c] = sampledRows[c].values();
          row.first = table.first();
          row.last = table.last();
          row.stride = table.stride();
          row.shift = table.shift();
          row.mask = table.mask();
        }
        for (int k = 0; k < restCount; ++k) lookUp(rest[k]);
      }
    });
  });
}

void Synthesizer::removeBoundaryNoise(ViewState& view) {
  WarpedLayer& layer = view.luma;
  // Samples on a reference depth edge within two samples of this view's own hole carry foreground
  // colour bled onto background: drop them, so the other view or the hole filler supplies them.
  const int w = layer.width, h = layer.height;
  std::vector<uint8_t>& drop = view.dropScratch;
  drop.assign(size_t(w) * h, 0);
  parallelRanges(h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        if (!layer.edge[size_t(y) * w + x] || layer.inverseDepth[size_t(y) * w + x] < 0) continue;
        bool nearHole = false;
        for (int ny = std::max(0, y - 2); ny <= std::min(h - 1, y + 2) && !nearHole; ++ny)
          for (int nx = std::max(0, x - 2); nx <= std::min(w - 1, x + 2); ++nx) nearHole |= layer.inverseDepth[size_t(ny) * w + nx] < 0;
        drop[size_t(y) * w + x] = nearHole;
      }
  });
  for (size_t i = 0; i < drop.size(); ++i)
    if (drop[i]) layer.inverseDepth[i] = kNoDepth;
}

void Synthesizer::rejectOccludedInOtherViews() {
  // A sample only one view shows fills a hole of the other views; one farther than the surroundings
  // every other view shows there is a misplaced one (Occlusion.h).
  std::vector<WarpedLayer*> layers;
  for (ViewState& view : views_) layers.push_back(&view.luma);
  rejectMisplacedSamples(layers, plan_.blending.weights, kBehindHoleSteps * plan_.discontinuity, occlusionScratch_);
}

}  // namespace vs
