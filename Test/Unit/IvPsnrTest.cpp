// IV-PSNR and WS-PSNR: hand-computed cases, and random pairs against plain double-precision loops
// written here from the published definitions (doc/metrics.md), not from our implementation.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "TestFormat.h"

#include "Common/Frame.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"

namespace {

const double kInf = std::numeric_limits<double>::infinity();
const double kPi = 3.14159265358979323846;

using test::makeFormat;

// A smooth texture with detail: no two neighbouring samples alike, so a shift shows in PSNR.
void texture(vs::Frame& frame, unsigned seed) {
  std::mt19937 random(seed);
  const int maxValue = frame.format.maxValue();
  std::uniform_int_distribution<int> sample(0, maxValue);
  for (int p = 0; p < vs::planeCount(frame.format.chroma); ++p)
    for (uint16_t& s : frame.planes[p].samples) s = uint16_t(sample(random));
}

// Sample (x, y) at luma resolution of plane p: 4:2:0 chroma repeated over 2x2.
int fullSample(const vs::Frame& frame, int p, int x, int y) {
  if (p > 0 && frame.format.chroma == vs::ChromaFormat::Yuv420) return frame.planes[p].at(x / 2, y / 2);
  return frame.planes[p].at(x, y);
}

// The definition, sample by sample: for each sample of `from` (plus the offset), the candidate of `to`
// within +-range (coordinates clamped to the picture) with the smallest weighted squared difference,
// the first in raster order on a tie; per-plane sums of that candidate's squared differences.
void plainDirection(const vs::Frame& from, const vs::Frame& to, const int offset[3], int range,
                    const int weights[3], double ssd[3]) {
  const int w = from.format.width, h = from.format.height, planes = vs::planeCount(from.format.chroma);
  for (int p = 0; p < 3; ++p) ssd[p] = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double best = kInf;
      double bestSq[3] = {0, 0, 0};
      for (int dy = -range; dy <= range; ++dy)
        for (int dx = -range; dx <= range; ++dx) {
          const int cx = std::clamp(x + dx, 0, w - 1), cy = std::clamp(y + dy, 0, h - 1);
          double sq[3] = {0, 0, 0}, error = 0;
          for (int p = 0; p < planes; ++p) {
            const double d = double(fullSample(from, p, x, y) + offset[p]) - double(fullSample(to, p, cx, cy));
            sq[p] = d * d;
            error += weights[p] * sq[p];
          }
          if (error < best) {
            best = error;
            std::copy(sq, sq + 3, bestSq);
          }
        }
      for (int p = 0; p < planes; ++p) ssd[p] += bestSq[p];
    }
}

double plainIvPsnr(const vs::Frame& ref, const vs::Frame& test, const vs::IvPsnrOptions& options) {
  const int w = ref.format.width, h = ref.format.height, planes = vs::planeCount(ref.format.chroma);
  const double peak = ref.format.maxValue(), area = double(w) * h;
  int offset[3] = {0, 0, 0}, negative[3] = {0, 0, 0};
  for (int p = 0; p < planes; ++p) {
    double sum = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) sum += fullSample(test, p, x, y) - fullSample(ref, p, x, y);
    const int limit = int(std::nearbyint(float(options.unnoticeable[p]) * float(peak)));
    offset[p] = std::clamp(int(std::nearbyint(sum / area)), -limit, limit);
    negative[p] = -offset[p];
  }
  double result = kInf;
  for (int d = 0; d < 2; ++d) {
    double ssd[3];
    if (d == 0) plainDirection(ref, test, offset, options.searchRange, options.searchWeights, ssd);
    else plainDirection(test, ref, negative, options.searchRange, options.searchWeights, ssd);
    bool exact = true;
    double sum = 0, weightSum = 0;
    for (int p = 0; p < planes; ++p) {
      exact = exact && ssd[p] == 0;
      sum += options.averageWeights[p] * 10.0 * std::log10(area * peak * peak / std::max(ssd[p], 1.0));
      weightSum += options.averageWeights[p];
    }
    result = std::min(result, exact ? kInf : sum / weightSum);
  }
  return result;
}

TEST(IvPsnr, OneSampleShiftIsInfiniteWherePsnrIsNot) {
  // 4:4:4 so that every plane shifts by one whole sample; column 0 repeats column 1 so that the
  // shifted picture's every sample has its match (the last column repeats in the shifted one).
  vs::Frame ref(makeFormat(40, 24, 8, vs::ChromaFormat::Yuv444));
  texture(ref, 1);
  // The last column repeats the first too, so that the shift leaves every plane's mean (and so the
  // colour offset, 0) unchanged.
  for (int p = 0; p < 3; ++p)
    for (int y = 0; y < 24; ++y) ref.planes[p].at(0, y) = ref.planes[p].at(39, y) = ref.planes[p].at(1, y);
  vs::Frame test = ref;
  for (int p = 0; p < 3; ++p)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 40; ++x) test.planes[p].at(x, y) = ref.planes[p].at(std::min(x + 1, 39), y);
  EXPECT_LT(vs::framePsnr(ref, test).yuv, 20.0);
  const vs::IvPsnrResult result = vs::ivPsnr(ref, test);
  EXPECT_EQ(result.ivpsnr, kInf);
  // The search range bounds it: with range 0 IV-PSNR is the weighted PSNR.
  vs::IvPsnrOptions none;
  none.searchRange = 0;
  none.unnoticeable[0] = none.unnoticeable[1] = none.unnoticeable[2] = 0;
  const vs::FramePsnr psnr = vs::framePsnr(ref, test);
  EXPECT_NEAR(vs::ivPsnr(ref, test, none).ivpsnr, (4 * psnr.y + psnr.u + psnr.v) / 6, 1e-9);
}

TEST(IvPsnr, TwoSampleShiftOf420IsInfinite) {
  // 4:2:0: two luma samples are one chroma sample, within the default range of 2.
  vs::Frame ref(makeFormat(32, 16, 8, vs::ChromaFormat::Yuv420));
  texture(ref, 2);
  // Repeated first and last columns: every sample keeps a match and the means stay (offset 0).
  for (int y = 0; y < 16; ++y)
    ref.planes[0].at(0, y) = ref.planes[0].at(1, y) = ref.planes[0].at(31, y) = ref.planes[0].at(2, y);
  for (int p = 1; p < 3; ++p)
    for (int y = 0; y < 8; ++y) ref.planes[p].at(0, y) = ref.planes[p].at(15, y) = ref.planes[p].at(1, y);
  vs::Frame test = ref;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) test.planes[0].at(x, y) = ref.planes[0].at(std::min(x + 2, 31), y);
  for (int p = 1; p < 3; ++p)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) test.planes[p].at(x, y) = ref.planes[p].at(std::min(x + 1, 15), y);
  EXPECT_TRUE(std::isfinite(vs::framePsnr(ref, test).y));
  EXPECT_EQ(vs::ivPsnr(ref, test).ivpsnr, kInf);
}

TEST(IvPsnr, GlobalOffsetOfThreeLevels) {
  // A flat picture and the same +3: the offset correction (0.01 of 255 rounds to 3) removes it all;
  // without it every sample is 3 off in every plane: 10 log10(255^2 / 9) dB.
  vs::Frame ref(makeFormat(16, 12, 8, vs::ChromaFormat::Yuv420));
  ref.fill(100);
  vs::Frame test = ref;
  for (int p = 0; p < 3; ++p)
    for (uint16_t& s : test.planes[p].samples) s = uint16_t(s + 3);
  const vs::IvPsnrResult corrected = vs::ivPsnr(ref, test);
  EXPECT_EQ(corrected.ivpsnr, kInf);
  EXPECT_EQ(corrected.colourOffset[0], 3);
  vs::IvPsnrOptions off;
  off.unnoticeable[0] = off.unnoticeable[1] = off.unnoticeable[2] = 0;
  EXPECT_NEAR(vs::ivPsnr(ref, test, off).ivpsnr, 10 * std::log10(255.0 * 255.0 / 9.0), 1e-9);
  // +4 is beyond the unnoticeable limit of 3: one level remains, 10 log10(255^2) dB.
  for (int p = 0; p < 3; ++p)
    for (uint16_t& s : test.planes[p].samples) s = uint16_t(s + 1);
  EXPECT_NEAR(vs::ivPsnr(ref, test).ivpsnr, 10 * std::log10(255.0 * 255.0), 1e-9);
  // 10 bit: the limit is round(0.01 * 1023) = 10 levels.
  vs::Frame ref10(makeFormat(16, 12, 10, vs::ChromaFormat::Yuv420));
  ref10.fill(400);
  vs::Frame test10 = ref10;
  for (int p = 0; p < 3; ++p)
    for (uint16_t& s : test10.planes[p].samples) s = uint16_t(s + 12);
  EXPECT_NEAR(vs::ivPsnr(ref10, test10).ivpsnr, 10 * std::log10(1023.0 * 1023.0 / 4.0), 1e-9);
}

TEST(IvPsnr, SingleOutlierByHand) {
  // Flat 100 everywhere, one test luma sample at 150 (16x16 4:4:4). Mean offset 50/256 rounds to 0.
  // Reference -> test: every sample finds a 100 in its window: exact. Test -> reference: the outlier
  // finds only 100s: luma SSD 2500; chroma exact, counting as an SSD of 1. Hence
  //   IV-PSNR = (4 * 10 log10(256 * 255^2 / 2500) + 2 * 10 log10(256 * 255^2)) / 6.
  vs::Frame ref(makeFormat(16, 16, 8, vs::ChromaFormat::Yuv444));
  ref.fill(100);
  for (int p = 1; p < 3; ++p) std::fill(ref.planes[p].samples.begin(), ref.planes[p].samples.end(), 100);
  vs::Frame test = ref;
  test.planes[0].at(7, 9) = 150;
  const double byHand =
      (4 * 10 * std::log10(256 * 255.0 * 255.0 / 2500) + 2 * 10 * std::log10(256 * 255.0 * 255.0)) / 6;
  const vs::IvPsnrResult result = vs::ivPsnr(ref, test);
  EXPECT_NEAR(result.ivpsnr, byHand, 1e-9);
  EXPECT_EQ(result.direction[0], kInf);
  EXPECT_EQ(result.colourOffset[0], 0);
}

struct RandomCase {
  int width, height, bitDepth;
  vs::ChromaFormat chroma;
  int range;
  int searchWeights[3];
};

TEST(IvPsnr, RandomPairsMatchThePlainDefinition) {
  const RandomCase cases[] = {
      {37, 23, 8, vs::ChromaFormat::Yuv420, 2, {4, 1, 1}},   // odd size: chroma cropped
      {30, 20, 10, vs::ChromaFormat::Yuv444, 1, {4, 1, 1}},
      {24, 18, 12, vs::ChromaFormat::Yuv400, 3, {4, 1, 1}},
      {20, 14, 16, vs::ChromaFormat::Yuv420, 2, {2, 3, 5}},  // 16 bit: the 64-bit sums
      {300, 9, 8, vs::ChromaFormat::Yuv444, 2, {1, 1, 1}},   // rows longer than one chunk
  };
  unsigned seed = 10;
  // One scratch kept over every case, as a caller scoring frame after frame keeps it: pictures of other
  // sizes, formats and search ranges before must not change a result.
  vs::IvPsnrScratch scratch;
  for (const RandomCase& c : cases) {
    SCOPED_TRACE(std::to_string(c.width) + "x" + std::to_string(c.height) + " " + std::to_string(c.bitDepth) +
                 "-bit " + vs::chromaFormatName(c.chroma));
    const vs::FrameFormat format = makeFormat(c.width, c.height, c.bitDepth, c.chroma);
    vs::Frame ref(format), test(format);
    texture(ref, seed++);
    // The test picture: the reference shifted, offset by 2% of the range, plus noise.
    std::mt19937 random(seed++);
    std::normal_distribution<double> noise(0, format.maxValue() * 0.02);
    for (int p = 0; p < vs::planeCount(c.chroma); ++p)
      for (int y = 0; y < ref.planes[p].height; ++y)
        for (int x = 0; x < ref.planes[p].width; ++x) {
          const double v = ref.planes[p].at(std::min(x + 1, ref.planes[p].width - 1), y) +
                           format.maxValue() * 0.02 + noise(random);
          test.planes[p].at(x, y) = uint16_t(std::clamp(std::lround(v), 0L, long(format.maxValue())));
        }
    vs::IvPsnrOptions options;
    options.searchRange = c.range;
    std::copy(c.searchWeights, c.searchWeights + 3, options.searchWeights);
    const double expected = plainIvPsnr(ref, test, options);
    EXPECT_NEAR(vs::ivPsnr(ref, test, options).ivpsnr, expected, 1e-9);
    EXPECT_NEAR(vs::ivPsnr(ref, test, options, scratch).ivpsnr, expected, 1e-9);
    options.threads = 3;
    EXPECT_EQ(vs::ivPsnr(ref, test, options).ivpsnr, vs::ivPsnr(ref, test, [&] {
                auto one = options;
                one.threads = 1;
                return one;
              }()).ivpsnr);
  }
}

TEST(IvPsnr, OptionValidationNamesTheProblem) {
  vs::IvPsnrOptions options;
  EXPECT_EQ(vs::validateIvPsnrOptions(options), "");
  options.searchRange = -1;
  EXPECT_NE(vs::validateIvPsnrOptions(options).find("search range"), std::string::npos);
  options = {};
  options.averageWeights[0] = options.averageWeights[1] = options.averageWeights[2] = 0;
  EXPECT_NE(vs::validateIvPsnrOptions(options).find("weights"), std::string::npos);
}

// WS-PSNR from its definition: row weights cos(latitude of the row centre), error normalised to H.
double plainWsPsnr(const vs::Frame& ref, const vs::Frame& test, int p, double latitudeRange) {
  const int w = ref.format.width, h = ref.format.height;
  double weighted = 0, weightSum = 0;
  for (int y = 0; y < h; ++y) {
    const double latitude = (y + 0.5 - h / 2.0) / h * latitudeRange * kPi / 180.0;
    double rowSsd = 0;
    for (int x = 0; x < w; ++x) rowSsd += std::pow(fullSample(ref, p, x, y) - fullSample(test, p, x, y), 2.0);
    weighted += std::cos(latitude) * rowSsd;
    weightSum += std::cos(latitude);
  }
  const double mse = weighted / weightSum / w;
  const double peak = ref.format.maxValue();
  return 10 * std::log10(peak * peak / mse);
}

TEST(WsPsnr, MatchesThePlainDefinition) {
  for (vs::ChromaFormat chroma : {vs::ChromaFormat::Yuv420, vs::ChromaFormat::Yuv444, vs::ChromaFormat::Yuv400}) {
    vs::Frame ref(makeFormat(36, 18, 10, chroma)), test(makeFormat(36, 18, 10, chroma));
    texture(ref, 30);
    texture(test, 31);
    for (double range : {180.0, 90.0}) {
      const vs::FrameQuality ws = vs::wsPsnr(ref, test, range);
      for (int p = 0; p < vs::planeCount(chroma); ++p) EXPECT_NEAR(ws.plane[p], plainWsPsnr(ref, test, p, range), 1e-9);
    }
  }
}

TEST(WsPsnr, EqualRowErrorsGivePlainPsnr) {
  // Every row with the same error: weighting cannot change the mean, WS-PSNR == PSNR.
  vs::Frame ref(makeFormat(20, 10, 8, vs::ChromaFormat::Yuv444));
  ref.fill(50);
  vs::Frame test = ref;
  for (int p = 0; p < 3; ++p)
    for (int y = 0; y < 10; ++y) test.planes[p].at(y % 20, y) = uint16_t(60 + p);
  const vs::FramePsnr psnr = vs::framePsnr(ref, test);
  const vs::FrameQuality ws = vs::wsPsnr(ref, test);
  EXPECT_NEAR(ws.plane[0], psnr.y, 1e-9);
  EXPECT_NEAR(ws.plane[1], psnr.u, 1e-9);
  EXPECT_NEAR(ws.plane[2], psnr.v, 1e-9);
  EXPECT_EQ(vs::wsPsnr(ref, ref).plane[0], kInf);
}

}  // namespace
