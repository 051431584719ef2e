#include "Common/Ssim.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "Common/ParallelRows.h"

namespace vs {

namespace {

constexpr int kRadius = 5;  // the 11x11 window's half size
constexpr int kScales = 5;
const double kScaleWeights[kScales] = {0.0448, 0.2856, 0.3001, 0.2363, 0.1333};

// A plane as scored: `repeat` reads a 4:2:0 chroma plane as if repeated over 2x2 luma samples
// (width x height is then the luma size), without making that picture.
struct PlaneView {
  const Plane* plane = nullptr;
  bool repeat = false;
  int width = 0, height = 0;
};

// The Gaussian (sigma 1.5) normalised over 11 taps; the window's weight at (dx, dy) is g[dx] g[dy].
// Taps: offsets -5 .. -5 + Taps - 1 (10 for Qmiv: -5..4, 11 for Wang: -5..5).
struct Window {
  int taps = 11;
  double g[11] = {};  // g[k]: weight of offset k - 5
  explicit Window(SsimConvention convention) {
    taps = convention == SsimConvention::Qmiv ? 10 : 11;
    double sum = 0;
    for (int k = 0; k < 11; ++k) sum += std::exp(-double((k - kRadius) * (k - kRadius)) / (2.0 * 1.5 * 1.5));
    for (int k = 0; k < 11; ++k)
      g[k] = std::exp(-double((k - kRadius) * (k - kRadius)) / (2.0 * 1.5 * 1.5)) / sum;
  }
};

// sum over k of g[k] x(k), the symmetric taps k and 10 - k added before they are weighted.
template <int Taps, class Sample>
inline float symmetricSum(const float* g, const Sample& x) {
  float s = g[kRadius] * x(kRadius);
#pragma GCC unroll 5
  for (int k = 0; k < kRadius; ++k) {
    if (10 - k < Taps) s += g[k] * (x(k) + x(10 - k));
    else s += g[k] * x(k);
  }
  return s;
}

// One row of the horizontal pass: the five moments (a, b, aa, bb, ab) of centred samples filtered
// with g over Taps samples; output i covers input i .. i + Taps - 1. Free functions with restrict
// pointers so that the compiler vectorises over i.
template <int Taps>
void filterHorizontal(const float* __restrict ca, const float* __restrict cb, const float* __restrict caa,
                      const float* __restrict cbb, const float* __restrict cab, int n, const float* __restrict g,
                      float* __restrict oa, float* __restrict ob, float* __restrict oaa, float* __restrict obb,
                      float* __restrict oab) {
  for (int i = 0; i < n; ++i) {
    oa[i] = symmetricSum<Taps>(g, [&](int k) { return ca[i + k]; });
    ob[i] = symmetricSum<Taps>(g, [&](int k) { return cb[i + k]; });
    oaa[i] = symmetricSum<Taps>(g, [&](int k) { return caa[i + k]; });
    obb[i] = symmetricSum<Taps>(g, [&](int k) { return cbb[i + k]; });
    oab[i] = symmetricSum<Taps>(g, [&](int k) { return cab[i + k]; });
  }
}

struct IndexConstants {
  float c1, c2;    // (0.01 L)^2, (0.03 L)^2
  float centreS;   // c S: the mean of the centring offset through the window
  float linear;    // c (1 - S)
  float constant;  // c^2 S (1 - S)
};

// The vertical pass and the index per centre: in[m * Taps + k] is moment m of the k-th input row.
template <int Taps, bool WithLuminance>
void filterVertical(const float* const* in, int n, const float* __restrict g, const IndexConstants& k0,
                    float* __restrict out) {
  const float c1 = k0.c1, c2 = k0.c2, linear = k0.linear, constant = k0.constant, centreS = k0.centreS;
  for (int i = 0; i < n; ++i) {
    const float ma = symmetricSum<Taps>(g, [&](int k) { return in[k][i]; });
    const float mb = symmetricSum<Taps>(g, [&](int k) { return in[Taps + k][i]; });
    const float qaa = symmetricSum<Taps>(g, [&](int k) { return in[2 * Taps + k][i]; });
    const float qbb = symmetricSum<Taps>(g, [&](int k) { return in[3 * Taps + k][i]; });
    const float qab = symmetricSum<Taps>(g, [&](int k) { return in[4 * Taps + k][i]; });
    const float varA = qaa - ma * ma + 2.0f * linear * ma + constant;
    const float varB = qbb - mb * mb + 2.0f * linear * mb + constant;
    const float cov = qab - ma * mb + linear * (ma + mb) + constant;
    const float csNum = 2.0f * cov + c2, csDen = varA + varB + c2;
    if constexpr (WithLuminance) {
      const float meanA = ma + centreS, meanB = mb + centreS;
      out[i] = ((2.0f * meanA * meanB + c1) * csNum) / ((meanA * meanA + meanB * meanB + c1) * csDen);
    } else {
      out[i] = csNum / csDen;
    }
  }
}

struct PlaneScore {
  double sum = 0;    // of the per-centre index over the evaluated centres
  double count = 0;  // evaluated centres
};

// Sum of SSIM (withLuminance) or of contrast-structure over the centres 5 <= x < W-5, 5 <= y < H-5.
// A separable filter in float on samples centred on mid-grey (c = 2^(bitDepth-1)), so that no moment
// is much larger than the variances it yields; the uncentred moments of the formula follow exactly:
// with S = sum of the window's weights (1 for Wang, about 0.998 for Qmiv's 10x10),
//   mean = m + c S,  E[a b] - mean_a mean_b = q_ab - m_a m_b + c (m_a + m_b)(1 - S) + c^2 S (1 - S).
// Per-row sums in double, combined in row order: no result depends on the thread count.
template <int Taps>
PlaneScore planeScoreTaps(const PlaneView& a, const PlaneView& b, int bitDepth, const Window& window,
                          bool withLuminance, int threads) {
  PlaneScore score;
  const int width = a.width, height = a.height;
  const int n = width - 2 * kRadius;  // centres per row
  const int rows = height - 2 * kRadius;
  if (n <= 0 || rows <= 0) return score;
  const double peak = double((1 << bitDepth) - 1);
  const float centre = float(1 << (bitDepth - 1));
  float g[11];
  double sumWeights1D = 0;
  for (int k = 0; k < 11; ++k) g[k] = float(window.g[k]);
  for (int k = 0; k < Taps; ++k) sumWeights1D += double(g[k]);
  const double s = sumWeights1D * sumWeights1D;
  IndexConstants constants;
  constants.c1 = float((0.01 * peak) * (0.01 * peak));
  constants.c2 = float((0.03 * peak) * (0.03 * peak));
  constants.centreS = float(double(centre) * s);
  constants.linear = float(double(centre) * (1.0 - s));
  constants.constant = float(double(centre) * double(centre) * s * (1.0 - s));
  std::vector<double> rowSum(static_cast<size_t>(rows), 0.0);
  parallelRows(rows, threads, [&](int r0, int r1) {
    // ring[t][m]: horizontally filtered moment m (a, b, aa, bb, ab) of input row (row % Taps).
    const size_t stride = size_t(n) + 16;
    std::vector<float> ring(static_cast<size_t>(Taps) * 5 * stride);
    std::vector<float> centred(5 * (size_t(width) + 16));
    std::vector<int> ringRow(Taps, -1);  // which input row each slot holds
    auto slot = [&](int inputRow, int m) { return ring.data() + (size_t(inputRow % Taps) * 5 + size_t(m)) * stride; };
    auto filterRow = [&](int inputRow) {
      // Repeated chroma: rows 2k and 2k+1 are the same samples, so the second copies the first.
      if (a.repeat && inputRow % 2 == 1 && ringRow[size_t((inputRow - 1) % Taps)] == inputRow - 1) {
        for (int m = 0; m < 5; ++m) std::memcpy(slot(inputRow, m), slot(inputRow - 1, m), sizeof(float) * size_t(n));
        ringRow[size_t(inputRow % Taps)] = inputRow;
        return;
      }
      const size_t w = size_t(width) + 16;
      float* ca = centred.data();
      float* cb = ca + w;
      float* caa = cb + w;
      float* cbb = caa + w;
      float* cab = cbb + w;
      const uint16_t* pa = a.plane->row(a.repeat ? inputRow / 2 : inputRow);
      const uint16_t* pb = b.plane->row(b.repeat ? inputRow / 2 : inputRow);
      if (a.repeat) {
        for (int x = 0; x < width; ++x) {
          ca[x] = float(pa[x / 2]) - centre;
          cb[x] = float(pb[x / 2]) - centre;
        }
      } else {
        for (int x = 0; x < width; ++x) {
          ca[x] = float(pa[x]) - centre;
          cb[x] = float(pb[x]) - centre;
        }
      }
      for (int x = 0; x < width; ++x) {
        caa[x] = ca[x] * ca[x];
        cbb[x] = cb[x] * cb[x];
        cab[x] = ca[x] * cb[x];
      }
      filterHorizontal<Taps>(ca, cb, caa, cbb, cab, n, g, slot(inputRow, 0), slot(inputRow, 1), slot(inputRow, 2),
                             slot(inputRow, 3), slot(inputRow, 4));
      ringRow[size_t(inputRow % Taps)] = inputRow;
    };
    std::vector<float> pixel(static_cast<size_t>(n));
    for (int r = r0; r < r0 + Taps - 1; ++r) filterRow(r);
    for (int r = r0; r < r1; ++r) {
      filterRow(r + Taps - 1);
      const float* in[5 * Taps];
      for (int m = 0; m < 5; ++m)
        for (int k = 0; k < Taps; ++k) in[m * Taps + k] = slot(r + k, m);
      float* out = pixel.data();
      if (withLuminance) filterVertical<Taps, true>(in, n, g, constants, out);
      else filterVertical<Taps, false>(in, n, g, constants, out);
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += double(out[i]);
      rowSum[size_t(r)] = sum;
    }
  });
  for (double v : rowSum) score.sum += v;
  score.count = double(n) * double(rows);
  return score;
}

// The index of one plane at one scale under the convention's averaging rule.
double planeIndex(const PlaneView& a, const PlaneView& b, int bitDepth, SsimConvention convention,
                  bool withLuminance, int threads) {
  const Window window(convention);
  const PlaneScore score = window.taps == 10 ? planeScoreTaps<10>(a, b, bitDepth, window, withLuminance, threads)
                                             : planeScoreTaps<11>(a, b, bitDepth, window, withLuminance, threads);
  if (convention == SsimConvention::Qmiv) return score.sum / (double(a.width) * double(a.height));
  if (score.count == 0) return std::numeric_limits<double>::quiet_NaN();
  return score.sum / score.count;
}

// Half size (rounded down), each sample the rounded mean of a 2x2 block of the view.
Plane halve(const PlaneView& view) {
  Plane out(view.width / 2, view.height / 2);
  if (view.repeat) {
    // Every 2x2 block of repeated chroma is one chroma sample: the mean is that sample.
    for (int y = 0; y < out.height; ++y) std::copy(view.plane->row(y), view.plane->row(y) + out.width, out.row(y));
    return out;
  }
  for (int y = 0; y < out.height; ++y) {
    const uint16_t* r0 = view.plane->row(2 * y);
    const uint16_t* r1 = view.plane->row(2 * y + 1);
    uint16_t* dst = out.row(y);
    for (int x = 0; x < out.width; ++x)
      dst[x] = uint16_t((uint32_t(r0[2 * x]) + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1] + 2) >> 2);
  }
  return out;
}

// Plane p as scored: at luma size (4:2:0 chroma repeated) for Qmiv, as stored for Wang.
PlaneView scoredPlane(const Frame& frame, int p, SsimConvention convention) {
  PlaneView view;
  view.plane = &frame.planes[p];
  view.repeat = convention == SsimConvention::Qmiv && p > 0 && frame.format.chroma == ChromaFormat::Yuv420;
  view.width = view.repeat ? frame.format.width : frame.planes[p].width;
  view.height = view.repeat ? frame.format.height : frame.planes[p].height;
  return view;
}

PlaneView wholePlane(const Plane& plane) {
  PlaneView view;
  view.plane = &plane;
  view.width = plane.width;
  view.height = plane.height;
  return view;
}

}  // namespace

FrameQuality ssim(const Frame& ref, const Frame& test, const SsimOptions& options) {
  VS_CHECK_MSG(ref.format == test.format, "SSIM of frames of different formats");
  FrameQuality result;
  result.hasChroma = ref.format.chroma != ChromaFormat::Yuv400;
  const int threads = metricThreads(options.threads);
  for (int p = 0; p < planeCount(ref.format.chroma); ++p)
    result.plane[p] = planeIndex(scoredPlane(ref, p, options.convention), scoredPlane(test, p, options.convention),
                                 ref.format.bitDepth, options.convention, true, threads);
  result.yuv = weightedPlanes(result.plane, result.hasChroma, options.averageWeights);
  return result;
}

FrameQuality msSsim(const Frame& ref, const Frame& test, const SsimOptions& options) {
  VS_CHECK_MSG(ref.format == test.format, "MS-SSIM of frames of different formats");
  FrameQuality result;
  result.hasChroma = ref.format.chroma != ChromaFormat::Yuv400;
  const int threads = metricThreads(options.threads);
  for (int p = 0; p < planeCount(ref.format.chroma); ++p) {
    Plane pa, pb;
    PlaneView va = scoredPlane(ref, p, options.convention), vb = scoredPlane(test, p, options.convention);
    double product = 1;
    for (int s = 0; s < kScales; ++s) {
      if (s > 0) {
        pa = halve(va);
        pb = halve(vb);
        va = wholePlane(pa);
        vb = wholePlane(pb);
      }
      const bool withLuminance = options.convention == SsimConvention::Qmiv ? (s > 0 && s < kScales - 1)
                                                                             : s == kScales - 1;
      const double index = planeIndex(va, vb, ref.format.bitDepth, options.convention, withLuminance, threads);
      product *= std::pow(index, kScaleWeights[s]);
    }
    result.plane[p] = product;
  }
  result.yuv = weightedPlanes(result.plane, result.hasChroma, options.averageWeights);
  return result;
}

}  // namespace vs
