// U and V at their own sample positions (doc/algorithms.md, "Chroma"): each chroma sample takes the
// depth of the front-most surface in its block of luma samples (the final luma depth of the view) and
// looks its colour up in the reference's chroma planes, on the general or the 1D path.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "Synth/Kernels/Rows.h"
#include "Synth/Synthesizer.h"

namespace vs {

void Synthesizer::warpChroma(ViewState& view, const Frame& texture) {
  const int cw = chromaWidth(outputFormat_.width, outputFormat_.chroma);
  const int ch = chromaHeight(outputFormat_.height, outputFormat_.chroma);
  const WarpedLayer& luma = view.luma;
  WarpedLayer& layer = view.chroma;
  layer.resize(cw, ch, 2);  // cleared row by row below (clearRows)
  const double tolerance = plan_.lumaFill.depthTolerance;
  // The block size (2 for 4:2:0, 1 for 4:4:4) and the kernel as compile-time constants: the block
  // loops unroll and the division by the block size is exact as a multiplication.
  auto warp = [&](auto blockSize, auto taps) {
    constexpr int kBlock = decltype(blockSize)::value, kTaps = decltype(taps)::value;
    parallelRanges(ch, [&](int j0, int j1) {
      // Locals, as in warpTexture: the byte and double stores below could alias what the loop reads.
      const ViewProjection projection = view.projection;
      const SubPixelSampler sampler = sampler_;
      const int lumaWidth = luma.width, lumaHeight = luma.height, chromaW = cw;
      // The reference's chroma size: the general path's look-ups may land anywhere in it (the virtual
      // picture may have another size, VirtualWidth); the 1D path has one size for both.
      const int sourceW = texture.planes[1].width, sourceH = texture.planes[1].height;
      const double surface = tolerance;
      const double* lumaDepth = luma.inverseDepth.data();
      const uint8_t* lumaEdge = luma.edge.data();
      double* depthOut = layer.inverseDepth.data();
      uint8_t* edgeOut = layer.edge.data();
      float* uOut = layer.colour[0].data();
      float* vOut = layer.colour[1].data();
      const bool rows = rowPath_;
      // As in warpTexture: an ERP reference's chroma continues round the wrap and across its poles.
      const SphereEdges sphere = projection.referenceSphere();
      const bool sphereEdges = sphere.any();
      // Chroma sample centres sit in the middle of their luma block (doc/formats-yuv.md).
      const double offset = 0.5 * (kBlock - 1);
      // 1D: each reference chroma row sampled once at every grid position (SampledRow, as in
      // warpTexture); positions in [-1, chromaW] have integer parts in [-1, chromaW].
      const auto scratch = chromaRows_.take();
      SampledRow &sampledU = scratch->sampledU, &sampledV = scratch->sampledV;  // looked up once
      // A row's block depths and edges first; then its source positions (and on the 1D path its grid
      // indices) in passes that vectorise (as in warpTexture), before the look-ups.
      for (auto* buffer : {&scratch->blockDepth, &scratch->sourceU, &scratch->sourceV}) buffer->resize(size_t(chromaW));
      scratch->grid.resize(2 * size_t(chromaW));  // the grid indices of cu, then of cv
      for (auto* buffer : {&scratch->blockEdge, &scratch->sourceOk}) buffer->resize(size_t(chromaW));
      double* sourcesV = scratch->sourceV.data();
      uint8_t* sourceOk = scratch->sourceOk.data();
      double* blockDepth = scratch->blockDepth.data();
      double* sources = scratch->sourceU.data();
      double* grid = scratch->grid.data();
      double* gridV = grid + chromaW;
      uint8_t* blockEdge = scratch->blockEdge.data();
      int tableRow = -1;  // the row sampledU and sampledV hold (the general path builds them when needed)
      std::vector<int> rest(static_cast<size_t>(chromaW));  // the general path's samples left to the per-sample code
      for (int j = j0; j < j1; ++j) {
        clearRows(layer, j, j + 1);
        const double rowGrid = double(j) * sampler.precision();
        if (rows) {
          sampledU.build<kTaps>(sampler, texture.planes[1], j, -1, chromaW);
          sampledV.build<kTaps>(sampler, texture.planes[2], j, -1, chromaW);
          tableRow = j;
        }
        // The chroma sample covers a block x block square of luma samples; it takes the depth of the
        // front-most surface there (the mean inverse depth of the block's samples on it). Luma samples
        // beyond the picture (an odd size) are not part of the block (bw x bh of it are inside): they
        // read as holes here, which neither the maximum nor the sum below takes.
        auto block = [&](int i, int bw, int bh) __attribute__((always_inline)) {
          const size_t corner = size_t(j) * kBlock * lumaWidth + size_t(i) * kBlock;
          double depths[kBlock * kBlock];
          uint8_t edges[kBlock * kBlock];
          double front = kNoDepth;
          for (int dy = 0; dy < kBlock; ++dy)
            for (int dx = 0; dx < kBlock; ++dx) {
              const bool inside = dx < bw && dy < bh;
              const size_t k = corner + size_t(dy) * lumaWidth + size_t(dx);
              depths[dy * kBlock + dx] = inside ? lumaDepth[k] : kNoDepth;
              edges[dy * kBlock + dx] = inside ? lumaEdge[k] : 0;
              front = std::max(front, depths[dy * kBlock + dx]);
            }
          // Without branches, in the same order: adding +0.0 leaves the sum unchanged (it is never
          // -0.0, as it starts at +0.0 and only grows by non-negative depths). A block without a
          // sample (front < 0) is a hole.
          double sum = 0;
          int count = 0;
          uint8_t edge = 0;
          for (int k = 0; k < kBlock * kBlock; ++k) {
            const bool onFront = depths[k] >= 0 && front - depths[k] <= surface;
            sum += onFront ? depths[k] : 0.0;
            count += int(onFront);
            edge |= onFront ? edges[k] : uint8_t(0);
          }
          blockDepth[i] = front < 0 ? kNoDepth : sum / std::max(count, 1);
          blockEdge[i] = edge;
        };
        // Whole blocks first, in a loop whose body knows it (and which the compiler can vectorise), or
        // for 2x2 blocks a row kernel; then those the picture's edge cuts.
        const int whole = (j + 1) * kBlock <= lumaHeight ? std::min(chromaW, lumaWidth / kBlock) : 0;
        if constexpr (kBlock == 2) {
          // 4:2:0: the whole blocks in a kernel compiled for the CPU's level (Kernels/Rows.h), the same rule.
          if (whole > 0) {
            const size_t top = size_t(j) * kBlock * lumaWidth;
            rowKernels().chromaBlocks(lumaDepth + top, lumaDepth + top + lumaWidth, lumaEdge + top,
                                      lumaEdge + top + lumaWidth, whole, surface, blockDepth, blockEdge);
          }
        } else {
          for (int i = 0; i < whole; ++i) block(i, kBlock, kBlock);
        }
        for (int i = whole; i < chromaW; ++i)
          block(i, std::min(kBlock, lumaWidth - i * kBlock), std::min(kBlock, lumaHeight - j * kBlock));
        if (rows) {
          // backward() on a rectified pair: u = rowSource(x, wv), v = y; then cv is the integer j.
          projection.rowSources(blockDepth, chromaW, sources, kBlock, offset);
          // sources[i] = (sources[i] - offset) / kBlock, grid[i] = sampledU.gridIndex(sources[i]).
          rowKernels().chromaGridIndices(sources, chromaW, offset, kBlock, sampler.precision(), grid);
        } else {
          projection.backwardRow(blockDepth, chromaW, double(j * kBlock) + offset, sources, sourcesV, sourceOk, kBlock,
                                 offset);
          // The chroma positions cu = (u - offset) / kBlock, cv likewise, in place, and their grid indices.
          rowKernels().chromaGridIndices(sources, chromaW, offset, kBlock, sampler.precision(), grid);
          rowKernels().chromaGridIndices(sourcesV, chromaW, offset, kBlock, sampler.precision(), gridV);
        }
        if (rows) {
          // The look-ups in a kernel compiled for the CPU's x86-64 level (Kernels/Rows.h's
          // chromaRowTableRow, as warpTextureRows does): the row's depths start as its blocks' (a hole's
          // is kNoDepth, as cleared), the kernel sets the failed look-ups' to kNoDepth. Positions in
          // [-1, chromaW] read the tables; any other sample is left to the code below.
          const size_t rowStart = size_t(j) * chromaW;
          std::copy(blockDepth, blockDepth + chromaW, depthOut + rowStart);
          const RowTableRow row = {sources, double(sampler.precision()), double(chromaW), 0.0,
                                   {sampledU.values(), sampledV.values(), nullptr}, sampledU.first(), sampledU.last(),
                                   sampledU.stride(), sampledU.shift(), sampledU.mask(), 2, blockEdge,
                                   depthOut + rowStart, {uOut + rowStart, vOut + rowStart, nullptr},
                                   edgeOut + rowStart};
          int restCount = 0;
          rowKernels().chromaRowTableRow(row, chromaW, rest.data(), restCount);
          for (int k = 0; k < restCount; ++k) {
            const int i = rest[size_t(k)];
            uOut[rowStart + size_t(i)] = sampledU.atGrid<kTaps>(sources[i], grid[i]);
            vOut[rowStart + size_t(i)] = sampledV.atGrid<kTaps>(sources[i], grid[i]);
          }
          continue;
        }
        if (!sphereEdges) {
          // The holes, the failed look-ups and those read from the row's tables in a kernel compiled for
          // the CPU's x86-64 level (Kernels/Rows.h's chromaTableRow, as warpTexture does; the tables are
          // built where it first finds one that reads them), the rest below. The row's depths start as its
          // blocks' (a hole's is kNoDepth, as cleared); the kernel sets the failed look-ups' to kNoDepth.
          const size_t rowStart = size_t(j) * chromaW;
          std::copy(blockDepth, blockDepth + chromaW, depthOut + rowStart);
          TextureTableRow row = {sources, sourcesV, sourceOk, grid, gridV, nullptr, double(sampler.precision()), rowGrid,
                                 double(sourceW),
                                 double(sourceH), {nullptr, nullptr, nullptr}, 0, 0, 0, 0, 0, 2, blockEdge,
                                 depthOut + rowStart, {uOut + rowStart, vOut + rowStart, nullptr}, edgeOut + rowStart};
          int restCount = 0;
          for (int i = 0; (i = rowKernels().chromaTableRow(row, i, chromaW, tableRow == j, rest.data(), restCount)) <
                          chromaW;) {
            sampledU.build<kTaps>(sampler, texture.planes[1], j, -1, sourceW);
            sampledV.build<kTaps>(sampler, texture.planes[2], j, -1, sourceW);
            tableRow = j;
            row.table[0] = sampledU.values();  // both tables have one shape (the planes have one size)
            row.table[1] = sampledV.values();
            row.first = sampledU.first();
            row.last = sampledU.last();
            row.stride = sampledU.stride();
            row.shift = sampledU.shift();
            row.mask = sampledU.mask();
          }
          for (int k = 0; k < restCount; ++k) {
            const int i = rest[size_t(k)];
            const size_t c = rowStart + size_t(i);
            const double cu = sources[i], cv = sourcesV[i];
            edgeOut[c] = blockEdge[i];
            if (gridV[i] == rowGrid) {  // outside the tables' range (they are built: the kernel read them)
              uOut[c] = sampledU.atGrid<kTaps>(cu, grid[i]);
              vOut[c] = sampledV.atGrid<kTaps>(cu, grid[i]);
            } else {
              uOut[c] = sampler.sampleTaps<kTaps>(texture.planes[1], cu, cv);
              vOut[c] = sampler.sampleTaps<kTaps>(texture.planes[2], cu, cv);
            }
          }
          continue;
        }
        for (int i = 0; i < chromaW; ++i) {
          const double inverseDepth = blockDepth[i];
          if (inverseDepth < 0) continue;
          const size_t c = size_t(j) * chromaW + i;
          if (!sourceOk[i]) continue;  // backward() refuses it
          const double cu = sources[i], cv = sourcesV[i];
          if (cu < -1.0 || cv < -1.0 || cu > sourceW || cv > sourceH) continue;
          depthOut[c] = inverseDepth;
          edgeOut[c] = blockEdge[i];
          if (sphereEdges && SubPixelSampler::nearEdge(cu, cv, sourceW, sourceH)) {
            uOut[c] = sampler.sampleSphereTaps<kTaps>(texture.planes[1], cu, cv, sphere);
            vOut[c] = sampler.sampleSphereTaps<kTaps>(texture.planes[2], cu, cv, sphere);
            continue;
          }
          // As in warpTexture: a look-up on this row's own reference row reads the row's table
          // (sampler.wholeRow(cv, row) && row == j: cv's grid index is j's).
          if (gridV[i] == rowGrid) {
            if (tableRow != j) {
              sampledU.build<kTaps>(sampler, texture.planes[1], j, -1, sourceW);
              sampledV.build<kTaps>(sampler, texture.planes[2], j, -1, sourceW);
              tableRow = j;
            }
            uOut[c] = sampledU.atGrid<kTaps>(cu, grid[i]);
            vOut[c] = sampledV.atGrid<kTaps>(cu, grid[i]);
            continue;
          }
          uOut[c] = sampler.sampleTaps<kTaps>(texture.planes[1], cu, cv);
          vOut[c] = sampler.sampleTaps<kTaps>(texture.planes[2], cu, cv);
        }
      }
    });
  };
  sampler_.withTaps([&](auto taps) {
    if (outputFormat_.chroma == ChromaFormat::Yuv420) warp(std::integral_constant<int, 2>(), taps);
    else warp(std::integral_constant<int, 1>(), taps);
  });
}

}  // namespace vs
