#pragma once
// PSNR between frames, and its mean over a sequence (doc/formats-yuv.md, "PSNR").
//   MSE  = sum((a - b)^2) / samples            over one plane
//   PSNR = 10 log10(peak^2 / MSE) dB,  peak = 2^bitDepth - 1;  +inf when MSE == 0 (identical planes)
//   YUV  = (6 Y + U + V) / 8 of the plane PSNRs in dB (MPEG common test conditions); by IEEE arithmetic
//          it is +inf as soon as one plane is identical. 4:0:0 has no chroma: YUV = Y.
#include <cstdint>
#include <string>

#include "Common/Frame.h"

namespace vs {

// Mean squared error of two planes of the same size (VS_CHECK), exact sums in integers.
double planeMse(const Plane& a, const Plane& b);
// 10 log10((2^bitDepth - 1)^2 / mse); +infinity for mse == 0. bitDepth in 1..16, mse >= 0 (VS_CHECK).
double psnrFromMse(double mse, int bitDepth);
// (6 y + u + v) / 8; +inf when any of them is +inf.
double weightedYuvPsnr(double y, double u, double v);
// "inf" for +infinity, else fixed with `decimals` digits ("38.1234"), the form YuvPsnr and reports print.
std::string formatPsnr(double db, int decimals = 4);

struct FramePsnr {
  double y = 0, u = 0, v = 0;           // dB, +inf for identical planes; u = v = 0 when !hasChroma
  double yuv = 0;                       // weightedYuvPsnr(y, u, v); == y when !hasChroma
  double mseY = 0, mseU = 0, mseV = 0;  // the MSEs behind them (0 for absent chroma)
  bool hasChroma = true;                // false for 4:0:0
};

// PSNR of `test` against `ref`; their formats must be equal (VS_CHECK).
FramePsnr framePsnr(const Frame& ref, const Frame& test);

// Means over a sequence, two ways, for Y, U, V and YUV:
// - frame mean: the mean of the per-frame PSNRs over the frames whose PSNR is finite. Frames with an
//   identical plane (inf) are counted in `identicalFrames` and left out; when every frame is identical
//   the frame mean is +inf.
// - PSNR of the mean MSE: psnrFromMse(mean of per-frame MSEs); +inf only when every frame is identical.
//   For YUV it is weightedYuvPsnr of the three planes' values.
class PsnrAccumulator {
public:
  struct Mean {
    double frameMean = 0;         // dB, see above
    double psnrOfMeanMse = 0;     // dB, see above
    int64_t identicalFrames = 0;  // frames with PSNR +inf, left out of frameMean
  };

  PsnrAccumulator(int bitDepth, bool hasChroma);
  void add(const FramePsnr& frame);  // frame.hasChroma must match (VS_CHECK)
  int64_t frames() const { return frames_; }
  bool hasChroma() const { return hasChroma_; }
  // Need frames() > 0 (VS_CHECK). u() and v() need hasChroma() (VS_CHECK); yuv() == y() without chroma.
  Mean y() const;
  Mean u() const;
  Mean v() const;
  Mean yuv() const;

private:
  struct Sums {
    double finitePsnrSum = 0;
    int64_t identicalFrames = 0;
    double mseSum = 0;
    void add(double psnr, double mse);
  };
  Mean mean(const Sums& sums) const;

  int bitDepth_;
  bool hasChroma_;
  int64_t frames_ = 0;
  Sums planes_[3];
  Sums yuv_;  // per-frame weighted PSNR; its mseSum is unused
};

}  // namespace vs
