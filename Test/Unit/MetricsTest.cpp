// PSNR: checked against a straightforward computation written here, on random data.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "TestFormat.h"

#include "Common/Frame.h"
#include "Common/Metrics.h"

namespace {

const double kInf = std::numeric_limits<double>::infinity();

// The textbook formula, sample by sample through at(x, y), in double.
double referenceMse(const vs::Plane& a, const vs::Plane& b) {
  double sum = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) sum += std::pow(double(a.at(x, y)) - double(b.at(x, y)), 2.0);
  return sum / (double(a.width) * double(a.height));
}

// 20 log10(peak) - 10 log10(mse): the same PSNR by another road.
double referencePsnr(double mse, int bitDepth) {
  return 20.0 * std::log10(std::pow(2.0, bitDepth) - 1.0) - 10.0 * std::log10(mse);
}

using test::makeFormat;

void randomize(vs::Plane& plane, int maxValue, std::mt19937& random) {
  std::uniform_int_distribution<int> sample(0, maxValue);
  for (uint16_t& s : plane.samples) s = uint16_t(sample(random));
}

// `test` = `ref` plus noise of +-amplitude, clamped.
void addNoise(const vs::Plane& ref, vs::Plane& test, int amplitude, int maxValue, std::mt19937& random) {
  std::uniform_int_distribution<int> noise(-amplitude, amplitude);
  test = ref;
  for (uint16_t& s : test.samples) s = uint16_t(std::clamp(int(s) + noise(random), 0, maxValue));
}

}  // namespace

TEST(MetricsTest, PlaneMseAndPsnrMatchAnIndependentComputation) {
  std::mt19937 random(2024);
  for (int bitDepth : {8, 10, 16}) {
    const int maxValue = (1 << bitDepth) - 1;
    vs::Plane a(37, 23), b(37, 23);
    randomize(a, maxValue, random);
    addNoise(a, b, maxValue / 20 + 1, maxValue, random);
    const double expectedMse = referenceMse(a, b);
    ASSERT_GT(expectedMse, 0);
    EXPECT_NEAR(vs::planeMse(a, b), expectedMse, 1e-9 * expectedMse) << bitDepth;
    EXPECT_DOUBLE_EQ(vs::planeMse(a, b), vs::planeMse(b, a));
    EXPECT_NEAR(vs::psnrFromMse(vs::planeMse(a, b), bitDepth), referencePsnr(expectedMse, bitDepth), 1e-9)
        << bitDepth;
    // Fully random planes: 16-bit squared differences near 2^32 must not overflow.
    randomize(b, maxValue, random);
    EXPECT_NEAR(vs::planeMse(a, b), referenceMse(a, b), 1e-9 * referenceMse(a, b)) << bitDepth;
  }
}

TEST(MetricsTest, KnownValuesAndInfinityForIdenticalPlanes) {
  EXPECT_NEAR(vs::psnrFromMse(1.0, 8), 48.130803608679, 1e-9);  // 10 log10(255^2)
  EXPECT_NEAR(vs::psnrFromMse(1.0, 10), 60.197512674243, 1e-9);  // 10 log10(1023^2)
  EXPECT_NEAR(vs::psnrFromMse(255.0 * 255.0, 8), 0.0, 1e-12);
  EXPECT_EQ(vs::psnrFromMse(0.0, 8), kInf);

  vs::Plane a(5, 3, 200);
  vs::Plane b = a;
  EXPECT_EQ(vs::planeMse(a, b), 0.0);
  b.at(4, 2) = 203;  // one sample off by 3: MSE 9/15
  EXPECT_DOUBLE_EQ(vs::planeMse(a, b), 9.0 / 15.0);

  EXPECT_EQ(vs::formatPsnr(kInf), "inf");
  EXPECT_EQ(vs::formatPsnr(48.130803608679), "48.1308");
  EXPECT_EQ(vs::formatPsnr(7.25, 1), "7.2");
}

TEST(MetricsTest, FramePsnrWeightsYuvSixOneOne) {
  std::mt19937 random(7);
  const vs::FrameFormat format = makeFormat(9, 7, 10, vs::ChromaFormat::Yuv420);
  vs::Frame ref(format), test(format);
  const int amplitude[3] = {4, 30, 90};  // a different PSNR per plane
  for (int p = 0; p < 3; ++p) {
    randomize(ref.planes[p], format.maxValue(), random);
    addNoise(ref.planes[p], test.planes[p], amplitude[p], format.maxValue(), random);
  }
  const vs::FramePsnr psnr = vs::framePsnr(ref, test);
  const double y = referencePsnr(referenceMse(ref.planes[0], test.planes[0]), 10);
  const double u = referencePsnr(referenceMse(ref.planes[1], test.planes[1]), 10);
  const double v = referencePsnr(referenceMse(ref.planes[2], test.planes[2]), 10);
  EXPECT_TRUE(psnr.hasChroma);
  EXPECT_NEAR(psnr.y, y, 1e-9);
  EXPECT_NEAR(psnr.u, u, 1e-9);
  EXPECT_NEAR(psnr.v, v, 1e-9);
  EXPECT_NEAR(psnr.yuv, (6 * y + u + v) / 8, 1e-9);
  EXPECT_GT(psnr.y, psnr.u);
  EXPECT_GT(psnr.u, psnr.v);
  EXPECT_NEAR(psnr.mseU, referenceMse(ref.planes[1], test.planes[1]), 1e-9);

  // Identical chroma: U and V are inf, and so is the weighted YUV; Y stays finite.
  test.planes[1] = ref.planes[1];
  test.planes[2] = ref.planes[2];
  const vs::FramePsnr sameChroma = vs::framePsnr(ref, test);
  EXPECT_NEAR(sameChroma.y, y, 1e-9);
  EXPECT_EQ(sameChroma.u, kInf);
  EXPECT_EQ(sameChroma.v, kInf);
  EXPECT_EQ(sameChroma.yuv, kInf);

  const vs::FramePsnr identical = vs::framePsnr(ref, ref);
  EXPECT_EQ(identical.y, kInf);
  EXPECT_EQ(identical.yuv, kInf);
}

TEST(MetricsTest, LumaOnlyFramesReportYAndNoNaN) {
  std::mt19937 random(11);
  const vs::FrameFormat format = makeFormat(6, 5, 8, vs::ChromaFormat::Yuv400);
  vs::Frame ref(format), test(format);
  randomize(ref.planes[0], 255, random);
  addNoise(ref.planes[0], test.planes[0], 10, 255, random);
  const vs::FramePsnr psnr = vs::framePsnr(ref, test);
  EXPECT_FALSE(psnr.hasChroma);
  EXPECT_NEAR(psnr.y, referencePsnr(referenceMse(ref.planes[0], test.planes[0]), 8), 1e-9);
  EXPECT_EQ(psnr.yuv, psnr.y);
  EXPECT_EQ(psnr.u, 0.0);
  EXPECT_EQ(psnr.v, 0.0);
  EXPECT_FALSE(std::isnan(psnr.u) || std::isnan(psnr.v) || std::isnan(psnr.yuv));

  vs::PsnrAccumulator accumulator(8, false);
  accumulator.add(psnr);
  EXPECT_EQ(accumulator.yuv().frameMean, psnr.y);
  EXPECT_NEAR(accumulator.y().psnrOfMeanMse, psnr.y, 1e-12);
}

TEST(MetricsTest, AccumulatorLeavesIdenticalFramesOutOfTheFrameMean) {
  const int bitDepth = 8;
  auto frameWithMse = [&](double mseY, double mseU, double mseV) {
    vs::FramePsnr frame;
    frame.mseY = mseY;
    frame.mseU = mseU;
    frame.mseV = mseV;
    frame.y = vs::psnrFromMse(mseY, bitDepth);
    frame.u = vs::psnrFromMse(mseU, bitDepth);
    frame.v = vs::psnrFromMse(mseV, bitDepth);
    frame.yuv = vs::weightedYuvPsnr(frame.y, frame.u, frame.v);
    return frame;
  };
  vs::PsnrAccumulator accumulator(bitDepth, true);
  accumulator.add(frameWithMse(4.0, 0.0, 1.0));
  accumulator.add(frameWithMse(0.0, 0.0, 2.0));  // Y identical
  accumulator.add(frameWithMse(16.0, 0.0, 3.0));
  EXPECT_EQ(accumulator.frames(), 3);

  const double peak2 = 255.0 * 255.0;
  auto db = [&](double mse) { return 10 * std::log10(peak2 / mse); };
  const vs::PsnrAccumulator::Mean y = accumulator.y();
  EXPECT_EQ(y.identicalFrames, 1);
  EXPECT_NEAR(y.frameMean, (db(4) + db(16)) / 2, 1e-12);
  EXPECT_NEAR(y.psnrOfMeanMse, db(20.0 / 3.0), 1e-12);

  const vs::PsnrAccumulator::Mean u = accumulator.u();  // every frame identical
  EXPECT_EQ(u.identicalFrames, 3);
  EXPECT_EQ(u.frameMean, kInf);
  EXPECT_EQ(u.psnrOfMeanMse, kInf);

  const vs::PsnrAccumulator::Mean v = accumulator.v();
  EXPECT_EQ(v.identicalFrames, 0);
  EXPECT_NEAR(v.frameMean, (db(1) + db(2) + db(3)) / 3, 1e-12);
  EXPECT_NEAR(v.psnrOfMeanMse, db(2.0), 1e-12);

  // YUV is inf in every frame (U is), so its frame mean is inf; mean-MSE YUV weights the plane values.
  const vs::PsnrAccumulator::Mean yuv = accumulator.yuv();
  EXPECT_EQ(yuv.identicalFrames, 3);
  EXPECT_EQ(yuv.frameMean, kInf);
  EXPECT_EQ(yuv.psnrOfMeanMse, kInf);

  vs::PsnrAccumulator finite(bitDepth, true);
  finite.add(frameWithMse(4.0, 1.0, 2.0));
  finite.add(frameWithMse(8.0, 3.0, 2.0));
  const vs::PsnrAccumulator::Mean finiteYuv = finite.yuv();
  EXPECT_EQ(finiteYuv.identicalFrames, 0);
  EXPECT_NEAR(finiteYuv.frameMean,
              ((6 * db(4) + db(1) + db(2)) / 8 + (6 * db(8) + db(3) + db(2)) / 8) / 2, 1e-12);
  EXPECT_NEAR(finiteYuv.psnrOfMeanMse, (6 * db(6) + db(2) + db(2)) / 8, 1e-12);
}

TEST(MetricsDeathTest, DifferentSizesAreAProgrammingError) {
  vs::Plane a(4, 4), b(4, 5);
  EXPECT_DEATH(vs::planeMse(a, b), "different sizes");
  vs::PsnrAccumulator empty(8, true);
  EXPECT_DEATH(empty.y(), "no frames");
}
