#pragma once
// IV-PSNR and WS-PSNR as the MPEG-I reference software (IV-PSNR 7.1, jstankowski/ivpsnr) defines them;
// doc/metrics.md gives the definitions, the options and the measured agreement.
//
// Both work on the picture at luma resolution: 4:2:0 chroma counts as repeated over its 2x2 luma
// samples (cropped at an odd width or height), as the reference software reads it.
// 4:0:0 has the luma plane only. Bit depth 8 to 16.
#include <cstdint>
#include <memory>
#include <string>

#include "Common/Frame.h"

namespace vs {

struct IvPsnrOptions {
  int searchRange = 2;                         // candidates within +-searchRange samples: a 5x5 window
  double unnoticeable[3] = {0.01, 0.01, 0.01};  // largest colour offset corrected, as a fraction of the
                                               // peak level (2^bitDepth - 1); 0 turns the correction off
  int searchWeights[3] = {4, 1, 1};            // Y:U:V weights of squared differences in the search
  int averageWeights[3] = {4, 1, 1};           // Y:U:V weights of the plane PSNRs in the result
  int threads = 0;                             // 0: every hardware thread; the result does not depend on it
};

struct IvPsnrResult {
  double ivpsnr = 0;               // dB: min(direction[0], direction[1]); +inf when both match exactly
  double direction[2] = {0, 0};    // [0]: reference samples matched in the test picture, [1]: the reverse;
                                   // (w0 Y + w1 U + w2 V) / (w0 + w1 + w2) of the plane PSNRs, an exact
                                   // plane counting as an SSD of 1 (10 log10(W H peak^2)) unless every
                                   // plane is exact, then +inf
  double planePsnr[2][3] = {};     // per direction and plane; +inf for a plane matched exactly
  int colourOffset[3] = {0, 0, 0};  // the correction: mean(test - reference), rounded, clipped
  bool hasChroma = true;
};

// The padded copies of both pictures IV-PSNR works on (12 bytes a luma sample for 4:2:0 and 4:4:4).
// A caller that scores frame after frame keeps one and passes it to every call, so that the memory is
// reused (no page faults on every frame); one scratch serves one call at a time.
class IvPsnrScratch {
public:
  IvPsnrScratch();
  ~IvPsnrScratch();
  IvPsnrScratch(IvPsnrScratch&&) noexcept;
  IvPsnrScratch& operator=(IvPsnrScratch&&) noexcept;
  struct Pictures;  // defined in IvPsnr.cpp
  Pictures& pictures() { return *pictures_; }

private:
  std::unique_ptr<Pictures> pictures_;
};

// IV-PSNR of `test` against `ref` (formats equal, VS_CHECK). Options out of range: VS_CHECK (callers
// validate user input first, see validateIvPsnrOptions). The padded copies go into `scratch`.
IvPsnrResult ivPsnr(const Frame& ref, const Frame& test, const IvPsnrOptions& options, IvPsnrScratch& scratch);
// The same with a scratch of its own, freed on return (for a single picture).
IvPsnrResult ivPsnr(const Frame& ref, const Frame& test, const IvPsnrOptions& options = {});
// Empty when the options are usable, else what is wrong with them.
std::string validateIvPsnrOptions(const IvPsnrOptions& options);

struct FrameQuality {
  double plane[3] = {0, 0, 0};  // Y, U, V (U = V = 0 without chroma)
  double yuv = 0;               // planes combined with the average weights (4:1:1 by default); = Y for 4:0:0
  bool hasChroma = true;
};

// WS-PSNR for equirectangular pictures: each row's squared error weighted by the cosine of its
// latitude, the picture covering `latitudeRangeDeg` degrees (180: the whole sphere) centred on the
// equator. +inf for an exactly matched plane. yuv: (w0 Y + w1 U + w2 V) / (w0 + w1 + w2).
FrameQuality wsPsnr(const Frame& ref, const Frame& test, double latitudeRangeDeg = 180.0,
                    const int averageWeights[3] = nullptr);

// (w0 a[0] + w1 a[1] + w2 a[2]) / (w0 + w1 + w2), or a[0] without chroma. Default weights 4:1:1.
double weightedPlanes(const double value[3], bool hasChroma, const int weights[3] = nullptr);

}  // namespace vs
