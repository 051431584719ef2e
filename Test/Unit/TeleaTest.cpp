// Synth/Telea.h against OpenCV's cv::inpaint(..., INPAINT_TELEA): the same floats, bit for bit, for
// each of the four interleaved planes, on random pictures and masks of every shape we meet (thin
// strips as the 1D path leaves, blobs, scattered samples, masks on the picture's edges), radii 1 to
// 8 and radii OpenCV rounds. Luma's cheaper inpainting (likeOpenCv off) against a plain
// implementation of it (TeleaReference.h) on the same cases, and against what a weighted mean must
// satisfy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "Synth/Telea.h"
#include "TeleaReference.h"

namespace vs {
namespace {

struct Case {
  int width, height;
  cv::Mat mask;                // CV_8UC1
  std::vector<cv::Mat> planes;  // four CV_32FC1
  double radius;
};

Case randomCase(std::mt19937& random, int kind) {
  Case c;
  c.width = 2 + int(random() % 90);
  c.height = 2 + int(random() % 90);
  const int w = c.width, h = c.height;
  for (int p = 0; p < 4; ++p) {
    cv::Mat plane(h, w, CV_32FC1);
    cv::randu(plane, p == 1 ? -300.0 : 0.0, p == 2 ? 1.0 : 255.0);
    if (p == 0) cv::GaussianBlur(plane, plane, cv::Size(5, 5), 2.0);  // smooth, so gradients matter
    c.planes.push_back(plane);
  }
  c.mask = cv::Mat::zeros(h, w, CV_8UC1);
  auto at = [&](int n) { return int(random() % unsigned(n)); };
  switch (kind % 5) {
    case 0:  // blobs, some across the edges
      for (int k = 0, n = 1 + at(5); k < n; ++k) cv::circle(c.mask, {at(w), at(h)}, 1 + at(9), 255, -1);
      break;
    case 1:  // scattered samples
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (at(6) == 0) c.mask.at<uint8_t>(y, x) = 1;
      break;
    case 2: {  // full-height strips, as the 1D path leaves them
      for (int k = 0, n = 1 + at(3); k < n; ++k) {
        const int x0 = at(w);
        cv::rectangle(c.mask, {x0, 0}, {std::min(w - 1, x0 + at(7)), h - 1}, 1, -1);
      }
      break;
    }
    case 3:  // a rectangle, possibly a single row or column
      cv::rectangle(c.mask, {at(w), at(h)}, {at(w), at(h)}, 7, -1);
      break;
    default:  // the picture's border rows and columns
      c.mask.row(0).setTo(1);
      c.mask.col(w - 1).setTo(1);
      if (at(2)) c.mask.col(0).setTo(1);
      if (at(2)) c.mask.row(h - 1).setTo(1);
      cv::circle(c.mask, {w / 2, h / 2}, 1 + at(4), 1, -1);
      break;
  }
  const double radii[] = {1, 2, 3, 3, 4, 5, 6, 8, 2.5, 3.5, 0.2};
  c.radius = radii[at(int(sizeof radii / sizeof radii[0]))];
  return c;
}

// Runs teleaInpaint on the case's four planes interleaved and returns them apart.
std::vector<cv::Mat> ours(const Case& c, TeleaScratch& scratch, bool likeOpenCv = true) {
  const int w = c.width, h = c.height;
  std::vector<float> samples(size_t(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int p = 0; p < 4; ++p) samples[(size_t(y) * w + x) * 4 + p] = c.planes[size_t(p)].at<float>(y, x);
  teleaInpaint(c.mask.ptr<uint8_t>(), c.mask.step, w, h, samples.data(), size_t(w), c.radius, scratch, likeOpenCv);
  std::vector<cv::Mat> out;
  for (int p = 0; p < 4; ++p) {
    cv::Mat plane(h, w, CV_32FC1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) plane.at<float>(y, x) = samples[(size_t(y) * w + x) * 4 + p];
    out.push_back(plane);
  }
  return out;
}

// The number of samples whose float bits differ.
int differing(const cv::Mat& a, const cv::Mat& b) {
  int n = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) n += std::memcmp(&a.at<float>(y, x), &b.at<float>(y, x), sizeof(float)) != 0;
  return n;
}

TEST(Telea, EqualsOpenCvInpaintingBitForBitOnRandomPicturesAndMasks) {
  std::mt19937 random(2026);
  TeleaScratch scratch;  // reused across sizes, as the hole filling reuses it
  int inpainted = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Case c = randomCase(random, trial);
    const std::vector<cv::Mat> got = ours(c, scratch);
    for (int p = 0; p < 4; ++p) {
      cv::Mat expected;
      cv::inpaint(c.planes[size_t(p)], c.mask, expected, c.radius, cv::INPAINT_TELEA);
      ASSERT_EQ(differing(got[size_t(p)], expected), 0)
          << "trial " << trial << " plane " << p << " " << c.width << "x" << c.height << " radius " << c.radius;
      inpainted += differing(got[size_t(p)], c.planes[size_t(p)]) > 0;
    }
  }
  EXPECT_GT(inpainted, 1000);  // the cases did fill something
}

TEST(Telea, LeavesThePictureAsItIsWithoutMaskOrWithoutAKnownSample) {
  const int w = 12, h = 9;
  std::vector<float> samples(size_t(w) * h * 4);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = float(i % 97) * 1.5f;
  const std::vector<float> before = samples;
  TeleaScratch scratch;
  const std::vector<uint8_t> none(size_t(w) * h, 0), all(size_t(w) * h, 1);
  teleaInpaint(none.data(), size_t(w), w, h, samples.data(), size_t(w), 3, scratch);
  EXPECT_EQ(samples, before);
  // OpenCV has no band to start from and returns the input; so do we.
  teleaInpaint(all.data(), size_t(w), w, h, samples.data(), size_t(w), 3, scratch);
  EXPECT_EQ(samples, before);
  cv::Mat plane(h, w, CV_32FC1), expected;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) plane.at<float>(y, x) = before[(size_t(y) * w + x) * 4];
  cv::inpaint(plane, cv::Mat(h, w, CV_8UC1, cv::Scalar(1)), expected, 3, cv::INPAINT_TELEA);
  EXPECT_EQ(differing(plane, expected), 0);
}

// A plane's result does not depend on what the other planes hold (they are only computed alongside).
TEST(Telea, EachPlaneIsFilledAsIfAlone) {
  std::mt19937 random(11);
  TeleaScratch scratch;
  for (int trial = 0; trial < 40; ++trial) {
    Case c = randomCase(random, trial);
    const std::vector<cv::Mat> together = ours(c, scratch);
    for (int p = 1; p < 4; ++p) c.planes[size_t(p)].setTo(0);
    const std::vector<cv::Mat> alone = ours(c, scratch);
    ASSERT_EQ(differing(together[0], alone[0]), 0) << "trial " << trial;
  }
}

// Luma's inpainting (likeOpenCv off: no outward march, no colour-gradient term): each plane equals
// a plain implementation of it (TeleaReference.h), up to the order of the float sums.
TEST(Telea, LumasInpaintingEqualsAPlainImplementation) {
  std::mt19937 random(2031);
  TeleaScratch scratch;
  for (int trial = 0; trial < 150; ++trial) {
    const Case c = randomCase(random, trial);
    const std::vector<cv::Mat> got = ours(c, scratch, false);
    const int w = c.width, h = c.height;
    const int radius = std::min(std::max(int(std::lrint(c.radius)), 1), 100);
    std::vector<uint8_t> mask(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) mask[size_t(y) * w + x] = c.mask.at<uint8_t>(y, x);
    for (int p = 0; p < 4; ++p) {
      std::vector<float> plane(size_t(w) * h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) plane[size_t(y) * w + x] = c.planes[size_t(p)].at<float>(y, x);
      const std::vector<float> expected = reference::plainTeleaMean(mask, w, h, plane, radius);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const float e = expected[size_t(y) * w + x];
          ASSERT_NEAR(got[size_t(p)].at<float>(y, x), e, 1e-4f * (1.0f + std::fabs(e)))
              << "trial " << trial << " plane " << p << " " << w << "x" << h << " at " << x << "," << y;
        }
    }
  }
}

// A weighted mean whose weights do not depend on the colours, plus 0.5 (OpenCV's, meant for rounding
// to 8 bits; on floats it adds up as filled samples feed later ones): a plane shifted by a constant
// is filled shifted by that constant, and no filled value is below the least known one plus 0.5.
TEST(Telea, LumasInpaintingIsAWeightedMeanPlusAHalf) {
  std::mt19937 random(5);
  TeleaScratch scratch;
  for (int trial = 0; trial < 60; ++trial) {
    Case c = randomCase(random, trial);
    if (cv::countNonZero(c.mask == 0) == 0) continue;
    const std::vector<cv::Mat> got = ours(c, scratch, false);
    Case shifted = c;
    for (int p = 0; p < 4; ++p) {
      cv::Mat plane = c.planes[size_t(p)] + 37.0;  // a new buffer (the copied Case shares c's)
      shifted.planes[size_t(p)] = plane;
    }
    const std::vector<cv::Mat> gotShifted = ours(shifted, scratch, false);
    for (int p = 0; p < 4; ++p) {
      double least;
      cv::minMaxLoc(c.planes[size_t(p)], &least, nullptr, nullptr, nullptr, c.mask == 0);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
          if (!c.mask.at<uint8_t>(y, x)) continue;
          const float v = got[size_t(p)].at<float>(y, x);
          ASSERT_NEAR(gotShifted[size_t(p)].at<float>(y, x) - v, 37.0f, 1e-3f * (1.0f + std::fabs(v)))
              << "trial " << trial << " plane " << p;
          ASSERT_GE(v, float(least) + 0.5f - 1e-4f * (1.0f + std::fabs(float(least))))
              << "trial " << trial << " plane " << p;
        }
    }
  }
}

// OpenCV reads outside a picture one sample high or wide; ours stays inside it, fills every mask
// sample with a value between the known ones, and leaves the known samples as they are.
TEST(Telea, FillsPicturesOneSampleHighOrWide) {
  TeleaScratch scratch;
  for (const auto& size : {std::pair<int, int>{17, 1}, {1, 13}, {1, 1}, {3, 1}}) {
    const int w = size.first, h = size.second, n = w * h;
    std::vector<float> samples(size_t(n) * 4);
    std::vector<uint8_t> mask(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
      mask[size_t(i)] = i % 4 == 2;  // not next to the first sample, which OpenCV reads for its neighbour
      for (int p = 0; p < 4; ++p) samples[size_t(i) * 4 + p] = mask[size_t(i)] ? 1000.0f : 100.0f + 10.0f * float(i % 3) + float(p);
    }
    const std::vector<float> before = samples;
    teleaInpaint(mask.data(), size_t(w), w, h, samples.data(), size_t(w), 3, scratch);
    for (int i = 0; i < n; ++i)
      for (int p = 0; p < 4; ++p) {
        const float v = samples[size_t(i) * 4 + p];
        if (!mask[size_t(i)]) {
          EXPECT_EQ(v, before[size_t(i) * 4 + p]);
        } else {  // between the known samples (and OpenCV's added 0.5)
          EXPECT_GE(v, 99.0f) << w << "x" << h << " sample " << i;
          EXPECT_LE(v, 124.0f) << w << "x" << h << " sample " << i;
        }
      }
  }
}

}  // namespace
}  // namespace vs
