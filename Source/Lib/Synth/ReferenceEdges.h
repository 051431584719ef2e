#pragma once
// Reference depth steps one row at a time (ReferenceEdges.cpp): the 1D depth warp reads them per row
// (SplattingOption 2), and the reference edge flags are dilated from them, so that no plane of them
// is kept.
#include <cstdint>
#include <vector>

#include "Common/Frame.h"
#include "Synth/Interpolation.h"

namespace vs {

// Row y of the step flags of `depth`: a sample is a step when it is missing, or a neighbour (left,
// right, above, below) is missing or differs by minStep levels or more. A neighbour beyond the border
// is read as the sample itself, which adds nothing; for an ERP reference (`sphere`) round its wrap the
// neighbour of the last column is the first, and beyond a pole the first (last) row half a turn round.
// `turned`: working space (width samples where y is a pole's row). `out`: width flags.
void referenceStepRow(const Plane& depth, int y, const SphereEdges& sphere, int missing, int minStep,
                      std::vector<uint16_t>& turned, uint8_t* out);

}  // namespace vs
