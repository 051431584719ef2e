// Reference depth edges (doc/algorithms.md, "Warping"): the reference samples at a depth discontinuity
// (the "step"), and the same dilated by one sample (the "edge"): their colours mix both surfaces, so a
// view that has a clean sample of the same surface wins over them when the views are blended.
#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "Synth/Kernels/Rows.h"
#include "Synth/Synthesizer.h"

namespace vs {

void Synthesizer::markReferenceEdges(ViewState& view, const Plane& depth) {
  const int w = depth.width, h = depth.height;
  std::vector<uint8_t>& step = view.referenceStep;
  step.resize(size_t(w) * h);
  const int missing = plan_.missingDepthLevel, minStep = plan_.edgeLevelStep;
  // A sample is a step when it is missing, or a neighbour (left, right, above, below) is missing or
  // differs by minStep levels or more. A neighbour beyond the border is read as the sample itself,
  // which adds nothing (a sample differs from itself only by being missing). A row at a time, in the
  // loop compiled for the CPU's x86-64 level (Kernels/Rows.h).
  parallelRanges(h, [&](int y0, int y1) {
    const RowKernels& kernels = rowKernels();
    for (int y = y0; y < y1; ++y) {
      const uint16_t* row = depth.row(y);
      const uint16_t* above = y > 0 ? depth.row(y - 1) : row;
      const uint16_t* below = y + 1 < h ? depth.row(y + 1) : row;
      kernels.referenceSteps(row, above, below, w, missing, minStep, step.data() + size_t(y) * w);
    }
  });
  // Dilated by one sample: the colours on both sides of an edge are mixed by the camera's optics.
  // (1D mode with WarpEnhancementOption 0 does without these reliability flags.)
  std::vector<uint8_t>& edge = view.referenceEdge;
  if (!plan_.referenceEdgeFlags) {
    edge.assign(size_t(w) * h, 0);
    return;
  }
  edge.resize(size_t(w) * h);  // every sample is written below
  // Separable: OR over three samples along rows, then along columns.
  std::vector<uint8_t>& rows = view.referenceStepRows;
  rows.resize(size_t(w) * h);
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w;
    for (int y = y0; y < y1; ++y) {
      const uint8_t* in = step.data() + size_t(y) * width;
      uint8_t* out = rows.data() + size_t(y) * width;
      // Border samples read themselves for the missing neighbour; the rest run without branches.
      out[0] = in[0] | in[std::min(1, width - 1)];
      for (int x = 1; x + 1 < width; ++x) out[x] = in[x - 1] | in[x] | in[x + 1];
      if (width > 1) out[width - 1] = in[width - 2] | in[width - 1];
    }
  });
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w, height = h;
    for (int y = y0; y < y1; ++y) {
      const uint8_t* mid = rows.data() + size_t(y) * width;
      const uint8_t* up = y > 0 ? mid - width : mid;
      const uint8_t* down = y + 1 < height ? mid + width : mid;
      uint8_t* out = edge.data() + size_t(y) * width;
      for (int x = 0; x < width; ++x) out[x] = mid[x] | up[x] | down[x];
    }
  });
}

}  // namespace vs
