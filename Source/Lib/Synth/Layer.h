#pragma once
// What one reference view contributes to the virtual view at one resolution (luma, or chroma), and
// the blended result. ViewSyn's warper and MeshRender's renderer both produce WarpedLayers; blending
// and hole filling work on them alike (doc/algorithms.md, "Blending" and "Hole filling").
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "Plan/StageOptions.h"

namespace vs {

constexpr double kNoDepth = -1.0;  // inverse depth of a sample that received nothing

struct WarpedLayer {
  int width = 0;
  int height = 0;
  int channels = 1;                  // 1 (luma), 2 (U, V) or 3 (RGB)
  std::vector<double> inverseDepth;  // 1 / z_virtual; kNoDepth where the view left a hole
  std::vector<float> colour[3];      // per channel, not rounded
  std::vector<uint8_t> edge;         // 1 where the colour comes from next to a depth edge in the reference

  void reset(int w, int h, int c);
  // Sizes the planes for w x h samples of c channels and leaves what they hold: for a writer that
  // writes every sample anyway (reset's fill would only be written over).
  void resize(int w, int h, int c);
  // Places the planes' memory for w x h samples of c channels without writing it (their size is
  // unchanged): resize() then writes only where it grows, on the thread that calls it.
  void reserve(int w, int h, int c) {
    const size_t n = size_t(w) * size_t(h);
    inverseDepth.reserve(n);
    for (int k = 0; k < c && k < 3; ++k) colour[k].reserve(n);
    edge.reserve(n);
  }
  bool valid(size_t i) const { return inverseDepth[i] >= 0.0; }
};

// What WarpedLayer::reset leaves in rows [y0, y1): no depth, colour 0, no edge. The warps size their
// layers with resize() and clear each row in their parallel loops, where the row is about to be
// written anyway, instead of in one pass on one thread over the whole layer before.
inline void clearRows(WarpedLayer& layer, int y0, int y1) {
  const size_t begin = size_t(y0) * size_t(layer.width), end = size_t(y1) * size_t(layer.width);
  std::fill(layer.inverseDepth.data() + begin, layer.inverseDepth.data() + end, kNoDepth);
  for (int k = 0; k < layer.channels; ++k) std::fill(layer.colour[k].data() + begin, layer.colour[k].data() + end, 0.0f);
  std::fill(layer.edge.data() + begin, layer.edge.data() + end, uint8_t(0));
}

struct BlendedLayer {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<double> inverseDepth;  // kNoDepth in holes
  std::vector<float> colour[3];
  std::vector<uint8_t> hole;         // 1 where no view contributed

  void reset(int w, int h, int c);
  void resize(int w, int h, int c);  // as WarpedLayer::resize
  size_t holeCount() const;
};

// Blends the views sample by sample: one valid view is taken as it is; where several are valid, the
// nearest surface wins when their depths differ by more than depthTolerance, else the agreeing views
// are mixed by weight, leaving out those whose sample lies on a reference depth edge when another
// agreeing view has a clean one.
void blendLayers(const std::vector<const WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out);
// The same blend written over the first view's planes, which `out` takes (its own planes go to the
// first view in exchange): every blend reads a sample's inputs before it writes that sample's output,
// and reads and writes nothing else of it, so the result is blendLayers' bit for bit, without a third
// layer's memory. The first view's layer holds out's former planes afterwards (contents unspecified).
void blendLayersIntoFirst(const std::vector<WarpedLayer*>& views, const BlendOptions& options, BlendedLayer& out);

}  // namespace vs
