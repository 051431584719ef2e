#pragma once
// ColorSpace 1: processing in RGB. YUV is converted with the full-range BT.601 matrix that VSRS uses
// (through OpenCV's YCrCb conversion); 4:2:0 chroma is upsampled bilinearly from its sample centres
// (the middle of each 2x2 luma block) and downsampled back as the mean of each 2x2 block.
#include "Common/Frame.h"
#include "Synth/Layer.h"

namespace vs {

// `rgb` becomes a 4:4:4 frame of the same size and bit depth whose planes are R, G, B.
void yuvToRgb(const Frame& yuv, Frame& rgb);
// Converts the R, G, B planes of `rgb` into `yuv`, whose format (already set) gives the chroma format.
void rgbToYuv(const Frame& rgb, Frame& yuv);

// The last step of a synthesis: the blended, filled layers rounded into `output` (its format already
// set). ColorSpace 1 (`rgb`): `luma` holds R, G, B, rounded into `rgbScratch` and converted to
// output's YUV. Otherwise `luma` holds Y and, when the format has chroma, `chroma` U and V. Colours
// round to the nearest sample in [0, maxValue]; NaN becomes 0.
void roundLayersToFrame(const BlendedLayer& luma, const BlendedLayer& chroma, bool rgb, Frame& rgbScratch, Frame& output);

}  // namespace vs
