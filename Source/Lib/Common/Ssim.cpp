#include "Common/Ssim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "Common/ParallelRows.h"

namespace vs {

namespace {

constexpr int kRadius = 5;  // the 11x11 window's half size
constexpr int kScales = 5;
const double kScaleWeights[kScales] = {0.0448, 0.2856, 0.3001, 0.2363, 0.1333};

// The Gaussian (sigma 1.5) normalised over 11 taps; the window's weight at (dx, dy) is g[dx] g[dy].
struct Window {
  int taps = 11;        // offsets -5 .. -5 + taps - 1 (10 for Qmiv: -5..4)
  double g[11] = {};    // g[k]: weight of offset k - 5
  explicit Window(SsimConvention convention) {
    taps = convention == SsimConvention::Qmiv ? 10 : 11;
    double sum = 0;
    for (int k = 0; k < 11; ++k) sum += std::exp(-double((k - kRadius) * (k - kRadius)) / (2.0 * 1.5 * 1.5));
    for (int k = 0; k < 11; ++k)
      g[k] = std::exp(-double((k - kRadius) * (k - kRadius)) / (2.0 * 1.5 * 1.5)) / sum;
  }
};

struct PlaneScore {
  double sum = 0;    // of the per-centre index over the evaluated centres
  double count = 0;  // evaluated centres
};

// Sum of SSIM (withLuminance) or of contrast-structure over the centres 5 <= x < W-5, 5 <= y < H-5,
// by a separable filter in double; per-row sums combined in row order.
PlaneScore planeScore(const Plane& a, const Plane& b, int bitDepth, const Window& window, bool withLuminance,
                      int threads) {
  PlaneScore score;
  const int width = a.width, height = a.height;
  const int n = width - 2 * kRadius;   // centres per row
  const int rows = height - 2 * kRadius;
  if (n <= 0 || rows <= 0) return score;
  const double peak = double((1 << bitDepth) - 1);
  const double c1 = (0.01 * peak) * (0.01 * peak);
  const double c2 = (0.03 * peak) * (0.03 * peak);
  const int taps = window.taps;
  std::vector<double> rowSum(size_t(rows), 0.0);
  parallelRows(rows, threads, [&](int r0, int r1) {
    // ring[t][m]: horizontally filtered moment m (a, b, aa, bb, ab) of input row (y - 5 + t) for the
    // output row y being computed, kept for `taps` rows.
    std::vector<double> ring(size_t(taps) * 5 * size_t(n));
    std::vector<double> moment(5 * size_t(width));
    auto slot = [&](int inputRow, int m) { return ring.data() + (size_t(inputRow % taps) * 5 + size_t(m)) * size_t(n); };
    auto filterRow = [&](int inputRow) {
      const uint16_t* pa = a.row(inputRow);
      const uint16_t* pb = b.row(inputRow);
      double* va = moment.data();
      double* vb = va + width;
      double* vaa = vb + width;
      double* vbb = vaa + width;
      double* vab = vbb + width;
      for (int x = 0; x < width; ++x) {
        const double sa = pa[x], sb = pb[x];
        va[x] = sa;
        vb[x] = sb;
        vaa[x] = sa * sa;
        vbb[x] = sb * sb;
        vab[x] = sa * sb;
      }
      for (int m = 0; m < 5; ++m) {
        double* __restrict out = slot(inputRow, m);
        const double* __restrict in = moment.data() + size_t(m) * size_t(width);
        std::fill(out, out + n, 0.0);
        for (int k = 0; k < taps; ++k) {
          const double g = window.g[k];
          for (int i = 0; i < n; ++i) out[i] += g * in[i + k];
        }
      }
    };
    std::vector<double> v(5 * size_t(n));
    for (int r = r0; r < r0 + taps - 1; ++r) filterRow(r);
    for (int r = r0; r < r1; ++r) {
      filterRow(r + taps - 1);
      std::fill(v.begin(), v.end(), 0.0);
      for (int k = 0; k < taps; ++k) {
        const double g = window.g[k];
        for (int m = 0; m < 5; ++m) {
          const double* __restrict in = slot(r + k, m);
          double* __restrict out = v.data() + size_t(m) * size_t(n);
          for (int i = 0; i < n; ++i) out[i] += g * in[i];
        }
      }
      const double* ma = v.data();
      const double* mb = ma + n;
      const double* maa = mb + n;
      const double* mbb = maa + n;
      const double* mab = mbb + n;
      double sum = 0;
      if (withLuminance) {
        for (int i = 0; i < n; ++i) {
          const double varA = maa[i] - ma[i] * ma[i];
          const double varB = mbb[i] - mb[i] * mb[i];
          const double cov = mab[i] - ma[i] * mb[i];
          const double l = (2 * ma[i] * mb[i] + c1) / (ma[i] * ma[i] + mb[i] * mb[i] + c1);
          const double cs = (2 * cov + c2) / (varA + varB + c2);
          sum += l * cs;
        }
      } else {
        for (int i = 0; i < n; ++i) {
          const double varA = maa[i] - ma[i] * ma[i];
          const double varB = mbb[i] - mb[i] * mb[i];
          const double cov = mab[i] - ma[i] * mb[i];
          sum += (2 * cov + c2) / (varA + varB + c2);
        }
      }
      rowSum[size_t(r)] = sum;
    }
  });
  for (double s : rowSum) score.sum += s;
  score.count = double(n) * double(rows);
  return score;
}

// The index of one plane at one scale under the convention's averaging rule.
double planeIndex(const Plane& a, const Plane& b, int bitDepth, SsimConvention convention, bool withLuminance,
                  int threads) {
  const Window window(convention);
  const PlaneScore score = planeScore(a, b, bitDepth, window, withLuminance, threads);
  if (convention == SsimConvention::Qmiv) return score.sum / (double(a.width) * double(a.height));
  if (score.count == 0) return std::numeric_limits<double>::quiet_NaN();
  return score.sum / score.count;
}

// Half size (rounded down), each sample the rounded mean of a 2x2 block.
Plane halve(const Plane& plane) {
  Plane out(plane.width / 2, plane.height / 2);
  for (int y = 0; y < out.height; ++y) {
    const uint16_t* r0 = plane.row(2 * y);
    const uint16_t* r1 = plane.row(2 * y + 1);
    uint16_t* dst = out.row(y);
    for (int x = 0; x < out.width; ++x)
      dst[x] = uint16_t((uint32_t(r0[2 * x]) + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1] + 2) >> 2);
  }
  return out;
}

// The frames whose planes are scored: luma-size planes for Qmiv, the planes as stored for Wang.
void scoredFrames(const Frame& ref, const Frame& test, SsimConvention convention, Frame& a, Frame& b) {
  VS_CHECK_MSG(ref.format == test.format, "SSIM of frames of different formats");
  if (convention == SsimConvention::Qmiv) {
    a = toLumaResolution(ref);
    b = toLumaResolution(test);
  } else {
    a = ref;
    b = test;
  }
}

}  // namespace

FrameQuality ssim(const Frame& ref, const Frame& test, const SsimOptions& options) {
  Frame a, b;
  scoredFrames(ref, test, options.convention, a, b);
  FrameQuality result;
  result.hasChroma = a.format.chroma != ChromaFormat::Yuv400;
  const int threads = metricThreads(options.threads);
  for (int p = 0; p < planeCount(a.format.chroma); ++p)
    result.plane[p] = planeIndex(a.planes[p], b.planes[p], a.format.bitDepth, options.convention, true, threads);
  result.yuv = weightedPlanes(result.plane, result.hasChroma, options.averageWeights);
  return result;
}

FrameQuality msSsim(const Frame& ref, const Frame& test, const SsimOptions& options) {
  Frame a, b;
  scoredFrames(ref, test, options.convention, a, b);
  FrameQuality result;
  result.hasChroma = a.format.chroma != ChromaFormat::Yuv400;
  const int threads = metricThreads(options.threads);
  for (int p = 0; p < planeCount(a.format.chroma); ++p) {
    Plane pa = a.planes[p], pb = b.planes[p];
    double product = 1;
    for (int s = 0; s < kScales; ++s) {
      if (s > 0) {
        pa = halve(pa);
        pb = halve(pb);
      }
      const bool withLuminance = options.convention == SsimConvention::Qmiv ? (s > 0 && s < kScales - 1)
                                                                             : s == kScales - 1;
      const double index = planeIndex(pa, pb, a.format.bitDepth, options.convention, withLuminance, threads);
      product *= std::pow(index, kScaleWeights[s]);
    }
    result.plane[p] = product;
  }
  result.yuv = weightedPlanes(result.plane, result.hasChroma, options.averageWeights);
  return result;
}

}  // namespace vs
