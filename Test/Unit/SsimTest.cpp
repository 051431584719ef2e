// SSIM and MS-SSIM against a plain double-precision implementation written here from the papers'
// definitions and the reference software's documented window and averaging (doc/metrics.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "TestFormat.h"

#include "Common/Frame.h"
#include "Common/Ssim.h"

namespace {

using vs::SsimConvention;

using test::makeFormat;

// A picture with structure at several scales plus noise, and a distorted copy of it.
void makePair(vs::Frame& ref, vs::Frame& test, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0, 1);
  const double peak = ref.format.maxValue();
  for (int p = 0; p < vs::planeCount(ref.format.chroma); ++p) {
    vs::Plane& a = ref.planes[p];
    vs::Plane& b = test.planes[p];
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const double v = 0.5 + 0.25 * std::sin(x * 0.13 + p) * std::cos(y * 0.07) + 0.1 * std::sin(x * 0.9 + y * 1.3) +
                         0.03 * noise(random);
        a.at(x, y) = uint16_t(std::clamp(std::lround(v * peak), 0L, long(peak)));
        const double w = 0.98 * a.at(x, y) + 0.01 * peak + 0.04 * peak * noise(random);
        b.at(x, y) = uint16_t(std::clamp(std::lround(w), 0L, long(peak)));
      }
  }
}

using PlainPlane = std::vector<std::vector<double>>;  // [y][x]

PlainPlane plainPlane(const vs::Frame& frame, int p, bool lumaSize) {
  const int w = lumaSize ? frame.format.width : frame.planes[p].width;
  const int h = lumaSize ? frame.format.height : frame.planes[p].height;
  const bool repeat = lumaSize && p > 0 && frame.format.chroma == vs::ChromaFormat::Yuv420;
  PlainPlane out(static_cast<size_t>(h), std::vector<double>(static_cast<size_t>(w)));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out[size_t(y)][size_t(x)] = repeat ? frame.planes[p].at(x / 2, y / 2) : frame.planes[p].at(x, y);
  return out;
}

PlainPlane halve(const PlainPlane& in) {
  const size_t h = in.size() / 2, w = in[0].size() / 2;
  PlainPlane out(h, std::vector<double>(w));
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x)
      out[y][x] = std::floor((in[2 * y][2 * x] + in[2 * y][2 * x + 1] + in[2 * y + 1][2 * x] + in[2 * y + 1][2 * x + 1] + 2) / 4);
  return out;
}

// The index by its definition: 2D Gaussian weights (sigma 1.5, normalised over 11x11) summed
// directly over the window, each centre's value from the weighted moments.
double plainIndex(const PlainPlane& a, const PlainPlane& b, int bitDepth, SsimConvention convention, bool luminance) {
  const int h = int(a.size()), w = int(a[0].size());
  double g[11], sum = 0;
  for (int k = 0; k < 11; ++k) sum += (g[k] = std::exp(-(k - 5) * (k - 5) / 4.5));
  for (double& v : g) v /= sum;
  const int last = convention == SsimConvention::Qmiv ? 4 : 5;  // Qmiv's window stops at +4
  const double peak = (1 << bitDepth) - 1, c1 = std::pow(0.01 * peak, 2), c2 = std::pow(0.03 * peak, 2);
  double total = 0, centres = 0;
  for (int y = 5; y < h - 5; ++y)
    for (int x = 5; x < w - 5; ++x) {
      double ma = 0, mb = 0, maa = 0, mbb = 0, mab = 0;
      for (int dy = -5; dy <= last; ++dy)
        for (int dx = -5; dx <= last; ++dx) {
          const double wt = g[dy + 5] * g[dx + 5];
          const double va = a[size_t(y + dy)][size_t(x + dx)], vb = b[size_t(y + dy)][size_t(x + dx)];
          ma += wt * va;
          mb += wt * vb;
          maa += wt * va * va;
          mbb += wt * vb * vb;
          mab += wt * va * vb;
        }
      const double cs = (2 * (mab - ma * mb) + c2) / ((maa - ma * ma) + (mbb - mb * mb) + c2);
      const double l = (2 * ma * mb + c1) / (ma * ma + mb * mb + c1);
      total += luminance ? l * cs : cs;
      centres += 1;
    }
  if (convention == SsimConvention::Qmiv) return total / (double(w) * h);
  return centres > 0 ? total / centres : std::numeric_limits<double>::quiet_NaN();
}

double plainSsim(const vs::Frame& ref, const vs::Frame& test, int p, SsimConvention convention) {
  const bool lumaSize = convention == SsimConvention::Qmiv;
  return plainIndex(plainPlane(ref, p, lumaSize), plainPlane(test, p, lumaSize), ref.format.bitDepth, convention, true);
}

double plainMsSsim(const vs::Frame& ref, const vs::Frame& test, int p, SsimConvention convention) {
  const bool lumaSize = convention == SsimConvention::Qmiv;
  PlainPlane a = plainPlane(ref, p, lumaSize), b = plainPlane(test, p, lumaSize);
  const double weights[5] = {0.0448, 0.2856, 0.3001, 0.2363, 0.1333};
  double product = 1;
  for (int s = 0; s < 5; ++s) {
    if (s > 0) {
      a = halve(a);
      b = halve(b);
    }
    // Wang: luminance at the coarsest scale only; the reference software: at scales 2 to 4.
    const bool luminance = convention == SsimConvention::Wang ? s == 4 : (s >= 1 && s <= 3);
    product *= std::pow(plainIndex(a, b, ref.format.bitDepth, convention, luminance), weights[s]);
  }
  return product;
}

TEST(Ssim, PictureWithItself) {
  vs::Frame ref(makeFormat(40, 30, 8, vs::ChromaFormat::Yuv420)), test(ref.format);
  makePair(ref, test, 1);
  vs::SsimOptions wang;
  wang.convention = SsimConvention::Wang;
  const vs::FrameQuality self = vs::ssim(ref, ref, wang);
  for (int p = 0; p < 3; ++p) EXPECT_NEAR(self.plane[p], 1.0, 1e-6);
  // The reference software scores the 5-sample border 0 and divides by every sample.
  const vs::FrameQuality qmiv = vs::ssim(ref, ref);
  for (int p = 0; p < 3; ++p) EXPECT_NEAR(qmiv.plane[p], (30.0 * 20.0) / (40.0 * 30.0), 1e-6);
  EXPECT_LT(vs::ssim(ref, test, wang).plane[0], 0.99);
}

struct SsimCase {
  int width, height, bitDepth;
  vs::ChromaFormat chroma;
};

TEST(Ssim, RandomPairsMatchThePlainDefinition) {
  const SsimCase cases[] = {{41, 29, 8, vs::ChromaFormat::Yuv420},
                            {32, 24, 10, vs::ChromaFormat::Yuv444},
                            {30, 27, 16, vs::ChromaFormat::Yuv400}};
  unsigned seed = 5;
  for (const SsimCase& c : cases)
    for (SsimConvention convention : {SsimConvention::Qmiv, SsimConvention::Wang}) {
      SCOPED_TRACE(std::to_string(c.bitDepth) + "-bit " + vs::chromaFormatName(c.chroma) +
                   (convention == SsimConvention::Qmiv ? " qmiv" : " wang"));
      vs::Frame ref(makeFormat(c.width, c.height, c.bitDepth, c.chroma)), test(ref.format);
      makePair(ref, test, seed++);
      vs::SsimOptions options;
      options.convention = convention;
      const vs::FrameQuality result = vs::ssim(ref, test, options);
      for (int p = 0; p < vs::planeCount(c.chroma); ++p) EXPECT_NEAR(result.plane[p], plainSsim(ref, test, p, convention), 2e-6);
      if (c.chroma != vs::ChromaFormat::Yuv400) {
        EXPECT_NEAR(result.yuv, (4 * result.plane[0] + result.plane[1] + result.plane[2]) / 6, 1e-12);
      }
      options.threads = 1;
      const double one = vs::ssim(ref, test, options).plane[0];
      options.threads = 4;
      EXPECT_EQ(vs::ssim(ref, test, options).plane[0], one);
    }
}

TEST(MsSsim, RandomPairsMatchThePlainDefinition) {
  // 5 scales of an 11-sample window need 176 samples a side (the 4:2:0 chroma of Wang falls short:
  // NaN; the reference software's rule scores its chroma at luma size).
  for (vs::ChromaFormat chroma : {vs::ChromaFormat::Yuv420, vs::ChromaFormat::Yuv444})
    for (SsimConvention convention : {SsimConvention::Qmiv, SsimConvention::Wang}) {
      SCOPED_TRACE(std::string(vs::chromaFormatName(chroma)) + (convention == SsimConvention::Qmiv ? " qmiv" : " wang"));
      vs::Frame ref(makeFormat(180, 178, 10, chroma)), test(ref.format);
      makePair(ref, test, 9);
      vs::SsimOptions options;
      options.convention = convention;
      const vs::FrameQuality result = vs::msSsim(ref, test, options);
      EXPECT_NEAR(result.plane[0], plainMsSsim(ref, test, 0, convention), 2e-6);
      if (convention == SsimConvention::Wang) {
        EXPECT_NEAR(vs::msSsim(ref, ref, options).plane[0], 1.0, 1e-6);
      }
      if (chroma == vs::ChromaFormat::Yuv420 && convention == SsimConvention::Wang) {
        EXPECT_TRUE(std::isnan(result.plane[1]));
      } else {
        EXPECT_NEAR(result.plane[1], plainMsSsim(ref, test, 1, convention), 2e-6);
        EXPECT_NEAR(result.plane[2], plainMsSsim(ref, test, 2, convention), 2e-6);
      }
    }
}

}  // namespace
