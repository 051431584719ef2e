#pragma once
// 1D TemporalImprovementOption (doc/algorithms.md, "Hole filling"): hole filling guesses; where a row
// of every reference is unchanged since the previous frame, a sample that was a hole then and is one
// now keeps the previous guess, so static disocclusions do not flicker. Holds the previous frame's
// reference depth and luma, holes and filled colours.
#include <cstdint>
#include <vector>

#include "Common/Frame.h"
#include "Synth/Layer.h"

namespace vs {

class TemporalFill {
public:
  // Before hole filling: which samples of the blended layers are holes this frame.
  void noteHoles(const BlendedLayer& luma, const BlendedLayer& chroma);
  // After hole filling: static holes take the previous frame's fill; then this frame (every view's
  // depth and texture luma, and the filled layers) becomes the previous one. `withChroma`: the
  // chroma layer is filled too (YUV with colour planes).
  void keepStaticFill(const std::vector<const Plane*>& depths, const std::vector<const Plane*>& lumas,
                      BlendedLayer& luma, BlendedLayer& chroma, bool withChroma, int chromaRowsPerSample);

private:
  std::vector<Plane> previousDepth_, previousLuma_;
  std::vector<uint8_t> holes_, chromaHoles_;  // this frame's holes before filling
  std::vector<uint8_t> previousHoles_, previousChromaHoles_;
  std::vector<float> previousColour_[3], previousChromaColour_[3];
  bool havePrevious_ = false;
};

}  // namespace vs
