#pragma once
// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) and MS-SSIM (Wang, Simoncelli, Bovik 2003), per plane,
// with the window, constants and scales of the MPEG-I IV-PSNR reference software 7.1 by default
// (doc/metrics.md). Bit depth 8 to 16; 4:0:0, 4:2:0, 4:4:4.
#include "Common/Frame.h"
#include "Common/IvPsnr.h"

namespace vs {

enum class SsimConvention {
  // IV-PSNR software 7.1: 4:2:0 chroma repeated to luma size; the Gaussian (sigma 1.5, normalised over
  // 11x11) applied over the 10x10 samples from -5 to +4 around the centre, not renormalised; the
  // index is evaluated at centres 5 <= x < W-5, 5 <= y < H-5 and summed over W x H, so a 5-sample
  // border counts as 0 (a picture against itself scores (W-10)(H-10)/(WH)). MS-SSIM: contrast-
  // structure at scales 1 and 5, the full index at scales 2 to 4.
  Qmiv,
  // Wang et al.: native chroma planes, the full 11x11 Gaussian window, the mean over the centres whose
  // window lies inside the picture (a picture against itself scores 1). MS-SSIM: contrast-structure
  // at scales 1 to 4, the full index at scale 5.
  Wang,
};

struct SsimOptions {
  SsimConvention convention = SsimConvention::Qmiv;
  int averageWeights[3] = {4, 1, 1};  // Y:U:V weights of FrameQuality::yuv
  int threads = 0;                    // 0: every hardware thread; the result does not depend on it
};

// Constants: C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 2^bitDepth - 1. MS-SSIM: 5 scales, each half the
// last (2x2 mean, rounded), weights 0.0448, 0.2856, 0.3001, 0.2363, 0.1333.
// A plane too small for one window (< 11 samples a side at some scale) gives NaN (Wang) or 0 (Qmiv).
FrameQuality ssim(const Frame& ref, const Frame& test, const SsimOptions& options = {});
FrameQuality msSsim(const Frame& ref, const Frame& test, const SsimOptions& options = {});

}  // namespace vs
