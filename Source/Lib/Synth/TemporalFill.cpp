#include "Synth/TemporalFill.h"

#include <algorithm>

#include "Synth/Parallel.h"

namespace vs {

void TemporalFill::noteHoles(const BlendedLayer& luma, const BlendedLayer& chroma) {
  copyOnThreads(luma.hole, holes_);  // same size every frame: no allocation once grown
  copyOnThreads(chroma.hole, chromaHoles_);
}

void TemporalFill::keepStaticFill(const std::vector<const Plane*>& depths, const std::vector<const Plane*>& lumas,
                                  BlendedLayer& luma, BlendedLayer& chroma, bool withChroma, int chromaRowsPerSample) {
  // This frame's holes become the previous ones (swapped: noteHoles refills the buffer next frame),
  // and its filled colours are kept (only the colours: the rest of the layer is not needed).
  const int h = luma.height, w = luma.width;
  std::vector<uint8_t> rowStatic(size_t(h), havePrevious_ ? 1 : 0);
  if (havePrevious_)
    parallelRanges(h, [&](int y0, int y1) {
      for (size_t k = 0; k < depths.size(); ++k)
        for (int y = y0; y < y1; ++y)
          rowStatic[size_t(y)] &= uint8_t(std::equal(depths[k]->row(y), depths[k]->row(y) + w, previousDepth_[k].row(y)) &&
                                          std::equal(lumas[k]->row(y), lumas[k]->row(y) + w, previousLuma_[k].row(y)));
    });
  auto keep = [&](BlendedLayer& layer, std::vector<uint8_t>& holes, std::vector<uint8_t>& previousHoles,
                  std::vector<float>* previousColour, int rowsPerSample) {
    if (havePrevious_ && previousHoles.size() == holes.size())
      parallelRanges(layer.height, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
          bool unchanged = true;
          for (int r = y * rowsPerSample; r < std::min(h, (y + 1) * rowsPerSample); ++r) unchanged = unchanged && rowStatic[size_t(r)];
          if (!unchanged) continue;
          for (int x = 0; x < layer.width; ++x) {
            const size_t i = size_t(y) * layer.width + x;
            if (holes[i] && previousHoles[i])
              for (int c = 0; c < layer.channels; ++c) layer.colour[c][i] = previousColour[c][i];
          }
        }
      });
    previousHoles.swap(holes);
    for (int c = 0; c < layer.channels; ++c) copyOnThreads(layer.colour[c], previousColour[c]);
  };
  keep(luma, holes_, previousHoles_, previousColour_, 1);
  if (withChroma) keep(chroma, chromaHoles_, previousChromaHoles_, previousChromaColour_, chromaRowsPerSample);
  previousDepth_.resize(depths.size());
  previousLuma_.resize(depths.size());
  auto keepPlane = [](const Plane& from, Plane& to) {
    to.width = from.width;
    to.height = from.height;
    copyOnThreads(from.samples, to.samples);
  };
  for (size_t k = 0; k < depths.size(); ++k) {
    keepPlane(*depths[k], previousDepth_[k]);
    keepPlane(*lumas[k], previousLuma_[k]);
  }
  havePrevious_ = true;
}

}  // namespace vs
