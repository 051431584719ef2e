#pragma once
// Crack closing in a warped depth layer (doc/algorithms.md, "Warping").
#include <cstdint>
#include <vector>

#include "Synth/ScratchPool.h"

namespace vs {

// Closes one- and two-sample gaps between two samples of one surface (inverse depths within the
// tolerance), along rows and columns, by interpolating between them. A gap is a sample that received
// nothing, or one that lies behind both ends by more than the tolerance: a one- or two-sample sliver
// of a far surface inside a surface is a crack through which the warp let a background sample show
// (typically unknown depth coded as the far plane), not something the virtual camera sees. A gap is
// never filled with foreground: both ends are one surface, and nearer than what they replace.
// Rows first, each from left to right, then columns, each from top to bottom; a closed gap counts as
// closed for the tests after it, as in one sequential pass (any thread count gives the same layer).
// `flagRows`: one line of flags for each loop body running at once.
void closeCracks(std::vector<double>& inverseDepth, int width, int height, double tolerance,
                 ScratchPool<std::vector<uint8_t>>& flagRows);
// closeCracks in two parts, for a warp that closes each row's cracks while the row is at hand (each row
// is closed by itself): one row (`flags`: width bytes of working space), and then all the columns.
void closeRowCracks(double* row, int width, double tolerance, uint8_t* flags);
void closeColumnCracks(std::vector<double>& inverseDepth, int width, int height, double tolerance,
                       ScratchPool<std::vector<uint8_t>>& flagRows);

}  // namespace vs
