// Reference depth edges (doc/algorithms.md, "Warping"): the reference samples at a depth discontinuity
// (the "step"), and the same dilated by one sample (the "edge"): their colours mix both surfaces, so a
// view that has a clean sample of the same surface wins over them when the views are blended.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "Synth/Interpolation.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Synthesizer.h"

namespace vs {

namespace {

// Row y of the step flags of `depth`: a sample is a step when it is missing, or a neighbour (left,
// right, above, below) is missing or differs by minStep levels or more. A neighbour beyond the border
// is read as the sample itself, which adds nothing; for an ERP reference (`sphere`) round its wrap the
// neighbour of the last column is the first, and beyond a pole the first (last) row half a turn round.
// `turned`: working space (width samples where y is a pole's row). `out`: width flags.
void referenceStepRow(const Plane& depth, int y, const SphereEdges& sphere, int missing, int minStep,
                      std::vector<uint16_t>& turned, uint8_t* out) {
  const int w = depth.width, h = depth.height;
  const uint16_t* row = depth.row(y);
  auto halfTurn = [&](int r) {  // row r half a turn round: what lies beyond a pole
    turned.resize(size_t(w));
    for (int x = 0; x < w; ++x) turned[size_t(x)] = depth.at((x + w / 2) % w, r);
    return turned.data();
  };
  const uint16_t* above = y > 0 ? depth.row(y - 1) : sphere.north ? halfTurn(0) : row;
  // (at most one of the two is turned: a row of one sample's picture has both poles, and there the
  // row turned half round is the row itself)
  const uint16_t* below = y + 1 < h ? depth.row(y + 1) : sphere.south ? (h == 1 && sphere.north ? above : halfTurn(h - 1)) : row;
  // In the loop compiled for the CPU's x86-64 level (Kernels/Rows.h); round the wrap the two edge
  // columns are redone.
  rowKernels().referenceSteps(row, above, below, w, missing, minStep, out);
  if (sphere.wrap && w > 1) {
    auto at = [&](int x, int left, int right) {
      const int level = row[x];
      auto differs = [&](int other) { return (other == missing) | (std::abs(level - other) >= minStep); };
      return uint8_t((level == missing) | differs(row[left]) | differs(row[right]) | differs(above[x]) |
                     differs(below[x]));
    };
    out[0] = at(0, w - 1, 1);
    out[w - 1] = at(w - 1, w - 2, 0);
  }
}

}  // namespace

void Synthesizer::markReferenceEdges(ViewState& view, const Plane& depth) {
  const int w = depth.width, h = depth.height;
  // Dilated by one sample: the colours on both sides of an edge are mixed by the camera's optics.
  // (1D mode with WarpEnhancementOption 0 does without these reliability flags.)
  std::vector<uint8_t>& edge = view.referenceEdge;
  const int missing = plan_.missingDepthLevel, minStep = plan_.edgeLevelStep;
  const SphereEdges sphere = view.projection.referenceSphere();
  // The 1D depth warp with SplattingOption 2 reads the steps themselves, row by row: they are kept in
  // a plane for it (the one place they are).
  std::vector<uint8_t>& steps = view.referenceStep;
  const bool keepSteps = rowPath_ && scene_.settings.oneD.splatting == 2;
  if (keepSteps) steps.resize(size_t(w) * h);
  if (!plan_.referenceEdgeFlags) {
    edge.assign(size_t(w) * h, 0);
    if (keepSteps)
      parallelRanges(h, [&](int y0, int y1) {
        std::vector<uint16_t> turnedDepth;
        for (int y = y0; y < y1; ++y)
          referenceStepRow(depth, y, sphere, missing, minStep, turnedDepth, steps.data() + size_t(y) * w);
      });
    return;
  }
  edge.resize(size_t(w) * h);  // every sample is written below
  // Separable: the step flags (referenceStepRow) ORed over three samples along rows, then along
  // columns. Each loop body keeps the rows it needs dilated along the row (the row above, the row, the
  // row below) in three rolling buffers, so that no plane of the steps or of the rows is written: a
  // row's steps are found and dilated once per body, the two rows round a body's range twice.
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w, height = h;
    const int wrapLeft = sphere.wrap ? width - 1 : 0, wrapRight = sphere.wrap ? 0 : width - 1;
    const auto scratch = byteRows_.take();
    std::vector<uint8_t>& buffers = *scratch;
    buffers.resize(5 * size_t(width));
    uint8_t* slot[3] = {buffers.data(), buffers.data() + width, buffers.data() + 2 * size_t(width)};
    uint8_t* turned = buffers.data() + 3 * size_t(width);  // beyond a pole: a dilated row half a turn round
    uint8_t* ownSteps = buffers.data() + 4 * size_t(width);  // a row's step flags
    std::vector<uint16_t> turnedDepth;
    // Row r of the step flags dilated along the row; border samples read themselves for the missing
    // neighbour (round the wrap for an ERP reference), the rest run without branches.
    auto dilate = [&](int r, uint8_t* out) {
      // (a kept row of the body's own range found into the plane; the two beyond it, which other
      // bodies keep, into the body's row)
      uint8_t* const in = keepSteps && r >= y0 && r < y1 ? steps.data() + size_t(r) * width : ownSteps;
      referenceStepRow(depth, r, sphere, missing, minStep, turnedDepth, in);
      out[0] = in[wrapLeft] | in[0] | in[std::min(1, width - 1)];
      for (int x = 1; x + 1 < width; ++x) out[x] = in[x - 1] | in[x] | in[x + 1];
      if (width > 1) out[width - 1] = in[width - 2] | in[width - 1] | in[wrapRight];
    };
    auto turn = [&](const uint8_t* row) {
      for (int x = 0; x < width; ++x) turned[x] = row[(x + width / 2) % width];
      return turned;
    };
    // slot[0]: row y - 1, slot[1]: row y, slot[2]: row y + 1 (those inside the picture).
    if (y0 > 0) dilate(y0 - 1, slot[0]);
    dilate(y0, slot[1]);
    for (int y = y0; y < y1; ++y) {
      if (y + 1 < height) dilate(y + 1, slot[2]);
      const uint8_t* mid = slot[1];
      const uint8_t* up = y > 0 ? slot[0] : sphere.north ? turn(mid) : mid;
      const uint8_t* down = y + 1 < height ? slot[2] : sphere.south ? turn(mid) : mid;
      uint8_t* out = edge.data() + size_t(y) * width;
      for (int x = 0; x < width; ++x) out[x] = mid[x] | up[x] | down[x];
      std::swap(slot[0], slot[1]);
      std::swap(slot[1], slot[2]);
    }
  });
}

}  // namespace vs
