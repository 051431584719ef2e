// Depth levels <-> Z, validation of depth ranges, and back-projection with DepthType 0 and 1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Error.h"

namespace {

using vs::Camera;
using vs::DepthRange;
using vs::Mat3;
using vs::Vec3;

constexpr double kInf = std::numeric_limits<double>::infinity();

DepthRange range(double znear, double zfar, int bits = 8) {
  DepthRange r;
  r.znear = znear;
  r.zfar = zfar;
  r.bitDepth = bits;
  return r;
}

std::string validationMessage(const DepthRange& r, int depthType, const std::string& prefix = "Left") {
  try {
    vs::validateDepthRange(r, depthType, prefix);
  } catch (const vs::InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Mat3 rotationY(double angle) {
  Mat3 R;
  R[0][0] = std::cos(angle);
  R[0][2] = -std::sin(angle);
  R[1][1] = 1.0;
  R[2][0] = std::sin(angle);
  R[2][2] = std::cos(angle);
  return R;
}

Camera camera(const Mat3& R, const Vec3& centre) {
  Camera c;
  c.name = "c";
  c.K[0][0] = 1600.0;
  c.K[0][1] = 1.5;
  c.K[0][2] = 640.0;
  c.K[1][1] = 1590.0;
  c.K[1][2] = 384.0;
  c.R = R;
  c.t = centre;
  return c;
}

}  // namespace

TEST(DepthTest, AnalyticLevelValues) {
  // 1/Z = (L/255)(1/1 - 1/2) + 1/2
  const DepthRange r = range(1.0, 2.0);
  EXPECT_EQ(vs::maxDepthLevel(r), 255);
  EXPECT_EQ(vs::levelToZ(255, r), 1.0);
  EXPECT_EQ(vs::levelToZ(0, r), 2.0);
  EXPECT_EQ(vs::levelToInverseZ(255, r), 1.0);
  EXPECT_EQ(vs::levelToInverseZ(0, r), 0.5);
  EXPECT_NEAR(vs::levelToInverseZ(127.5, r), 0.75, 1e-16);
  EXPECT_NEAR(vs::levelToZ(127.5, r), 4.0 / 3.0, 1e-15);
  EXPECT_NEAR(vs::levelToZ(51, r), 1.0 / (0.2 * 0.5 + 0.5), 1e-15);
  EXPECT_NEAR(vs::zToLevel(4.0 / 3.0, r), 127.5, 1e-12);
  // Larger levels are nearer.
  EXPECT_LT(vs::levelToZ(200, r), vs::levelToZ(100, r));

  // Art (middlebury2005): Znear 1315.1648351648353, Zfar 2992 at 8 bits.
  const DepthRange art = range(1315.1648351648353, 2992.0);
  EXPECT_EQ(vs::levelToZ(255, art), 1315.1648351648353);
  EXPECT_EQ(vs::levelToZ(0, art), 2992.0);
  EXPECT_NEAR(1.0 / vs::levelToZ(100, art), (100.0 / 255.0) * (1 / 1315.1648351648353 - 1 / 2992.0) + 1 / 2992.0,
              1e-18);

  // 16 bits: Lmax = 65535.
  const DepthRange deep = range(0.5, 8.0, 16);
  EXPECT_EQ(vs::maxDepthLevel(deep), 65535);
  EXPECT_EQ(vs::levelToZ(65535, deep), 0.5);
  EXPECT_EQ(vs::levelToZ(0, deep), 8.0);
}

TEST(DepthTest, InfiniteZfar) {
  // 1/Z = (L/255)(1/10) : level 0 is at infinity, level 51 at Z = 50.
  const DepthRange r = range(10.0, kInf);
  EXPECT_EQ(vs::levelToInverseZ(0, r), 0.0);
  EXPECT_EQ(vs::levelToZ(0, r), kInf);
  EXPECT_EQ(vs::levelToZ(255, r), 10.0);
  EXPECT_NEAR(vs::levelToZ(51, r), 50.0, 1e-12);
  EXPECT_EQ(vs::zToLevel(kInf, r), 0.0);
  EXPECT_EQ(vs::zToLevelRounded(kInf, r), 0);
  EXPECT_NEAR(vs::zToLevel(50.0, r), 51.0, 1e-12);
  EXPECT_NO_THROW(vs::validateDepthRange(r, 0, "Left"));
  EXPECT_NO_THROW(vs::validateDepthRange(r, 1, "Left"));
}

TEST(DepthTest, LevelZRoundTripForEveryLevel) {
  const std::vector<DepthRange> ranges = {
      range(1.0, 2.0),     range(1315.1648351648353, 2992.0), range(10.0, kInf),
      range(0.3, 1e5, 10), range(0.464901, -2.424092),        range(42.0, 4200.0, 16),
      range(0.7, kInf, 16)};
  for (const DepthRange& r : ranges) {
    const int maxLevel = vs::maxDepthLevel(r);
    for (int level = 0; level <= maxLevel; ++level) {
      const double z = vs::levelToZ(level, r);
      ASSERT_NEAR(vs::zToLevel(z, r), level, 1e-9) << r.znear << " " << r.zfar << " level " << level;
      ASSERT_EQ(vs::zToLevelRounded(z, r), level);
    }
  }
}

TEST(DepthTest, RoundedLevelsAreClamped) {
  const DepthRange r = range(1.0, 2.0);
  EXPECT_EQ(vs::zToLevelRounded(0.5, r), 255);  // nearer than Znear
  EXPECT_EQ(vs::zToLevelRounded(1e-300, r), 255);
  EXPECT_EQ(vs::zToLevelRounded(3.0, r), 0);  // farther than Zfar
  EXPECT_EQ(vs::zToLevelRounded(kInf, r), 0);
  EXPECT_EQ(vs::zToLevelRounded(std::nan(""), r), 0);
  // 1/Z halfway between levels 100 and 101 rounds up; just below rounds down.
  const double z100_5 = 1.0 / ((100.5 / 255.0) * 0.5 + 0.5);
  EXPECT_EQ(vs::zToLevelRounded(z100_5 * (1 - 1e-9), r), 101);
  EXPECT_EQ(vs::zToLevelRounded(z100_5 * (1 + 1e-9), r), 100);
  // The continuous level is not clamped.
  EXPECT_NEAR(vs::zToLevel(0.5, r), 255.0 * (2.0 - 0.5) / 0.5, 1e-9);
}

TEST(DepthTest, InverseZTableMatchesTheFormula) {
  for (const DepthRange& r : {range(1.0, 2.0), range(10.0, kInf, 16), range(0.464901, -2.424092)}) {
    const std::vector<double> table = vs::inverseZTable(r);
    ASSERT_EQ(table.size(), static_cast<std::size_t>(vs::maxDepthLevel(r)) + 1);
    for (std::size_t level = 0; level < table.size(); ++level) {
      ASSERT_EQ(table[level], vs::levelToInverseZ(static_cast<double>(level), r));
      const double fraction = static_cast<double>(level) / vs::maxDepthLevel(r);
      const double expected = fraction * (1.0 / r.znear - 1.0 / r.zfar) + 1.0 / r.zfar;
      ASSERT_NEAR(table[level], expected, 1e-15 * (std::fabs(1.0 / r.znear) + std::fabs(1.0 / r.zfar)));
      if (level > 0) {
        ASSERT_GT(table[level], table[level - 1]);  // larger levels nearer
      }
    }
  }
  EXPECT_EQ(vs::inverseZTable(range(1.0, 2.0)).size(), 256u);
  EXPECT_EQ(vs::inverseZTable(range(1.0, 2.0, 16)).size(), 65536u);
}

TEST(DepthTest, ValidationErrors) {
  std::string message = validationMessage(range(5.0, 5.0), 0);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue and LeftFarthestDepthValue are both 5")) << message;
  message = validationMessage(range(-2.0, -2.0), 1, "Right");
  EXPECT_TRUE(contains(message, "RightNearestDepthValue and RightFarthestDepthValue are both -2")) << message;

  message = validationMessage(range(std::nan(""), 10.0), 0);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = nan")) << message;
  EXPECT_TRUE(contains(message, "finite")) << message;
  message = validationMessage(range(kInf, 10.0), 1);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = inf")) << message;
  message = validationMessage(range(1.0, -kInf), 1);
  EXPECT_TRUE(contains(message, "LeftFarthestDepthValue = -inf")) << message;
  message = validationMessage(range(1.0, std::nan("")), 0);
  EXPECT_TRUE(contains(message, "LeftFarthestDepthValue = nan")) << message;

  message = validationMessage(range(0.0, 10.0), 0);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = 0: with DepthType 0")) << message;
  message = validationMessage(range(1.0, -10.0), 0);
  EXPECT_TRUE(contains(message, "LeftFarthestDepthValue = -10: with DepthType 0")) << message;
  // Every problem in one message.
  message = validationMessage(range(-1.0, -2.0), 0);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = -1")) << message;
  EXPECT_TRUE(contains(message, "LeftFarthestDepthValue = -2")) << message;
  message = validationMessage(range(20.0, 10.0), 0);
  EXPECT_TRUE(contains(message, "farther than")) << message;

  message = validationMessage(range(0.0, -2.0), 1);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = 0")) << message;
  message = validationMessage(range(1.0, 2.0, 7), 0);
  EXPECT_TRUE(contains(message, "bit depth 7")) << message;
  message = validationMessage(range(1.0, 2.0, 17), 0);
  EXPECT_TRUE(contains(message, "bit depth 17")) << message;
  message = validationMessage(range(1.0, 2.0), 2);
  EXPECT_TRUE(contains(message, "DepthType 2")) << message;

  // A range nobody set is refused, naming both keys.
  message = validationMessage(DepthRange(), 0);
  EXPECT_TRUE(contains(message, "LeftNearestDepthValue = nan")) << message;
  EXPECT_TRUE(contains(message, "LeftFarthestDepthValue = nan")) << message;
}

TEST(DepthTest, ValidRangesPass) {
  EXPECT_NO_THROW(vs::validateDepthRange(range(1315.1648351648353, 2992.0), 0, "Left"));
  // The butterfly arc config: DepthType 1, world z, Znear 0.464901 and Zfar -2.424092.
  EXPECT_NO_THROW(vs::validateDepthRange(range(0.464901, -2.424092), 1, "Left"));
  EXPECT_NO_THROW(vs::validateDepthRange(range(-5.0, -20.0), 1, "Right"));
  EXPECT_NO_THROW(vs::validateDepthRange(range(0.1, kInf, 16), 0, ""));
}

TEST(DepthTest, DepthType0BackProjectionIsAtCameraDepth) {
  const Camera c = camera(rotationY(0.3), {1.0, -2.0, 5.0});
  for (double u : {0.0, 321.0, 1279.0}) {
    for (double v : {0.0, 500.0, 767.0}) {
      for (double z : {0.5, 7.0, 1e4}) {
        bool ok = false;
        const Vec3 X = vs::backProjectDepth(c, u, v, z, vs::kDepthTypeCamera, ok);
        ASSERT_TRUE(ok);
        EXPECT_NEAR(c.worldToCamera(X).z, z, z * 1e-14);
        double u2 = 0, v2 = 0, z2 = 0;
        ASSERT_TRUE(c.project(X, u2, v2, z2));
        EXPECT_NEAR(u2, u, 1e-9);
        EXPECT_NEAR(v2, v, 1e-9);
        EXPECT_EQ(vs::depthToCameraZ(c, u, v, z, 0, ok), z);
        EXPECT_TRUE(ok);
      }
    }
  }
  bool ok = true;
  vs::backProjectDepth(c, 10, 10, -1.0, 0, ok);
  EXPECT_FALSE(ok);
  ok = true;
  vs::backProjectDepth(c, 10, 10, kInf, 0, ok);  // no finite point
  EXPECT_FALSE(ok);
  EXPECT_EQ(vs::depthToCameraZ(c, 10, 10, kInf, 0, ok), kInf);
  EXPECT_TRUE(ok);
}

TEST(DepthTest, DepthType1BackProjectionLandsOnThePlane) {
  // An arc camera like the butterfly set: rotated about y, centre at world z = -1.46, depths are world z.
  const Camera c = camera(rotationY(-0.35), {-0.53, 0.0, -1.46});
  for (double u : {0.0, 640.0, 1279.0}) {
    for (double v : {0.0, 384.0, 767.0}) {
      for (double Z : {0.464901, 0.0, -0.9, 3.0}) {
        bool ok = false;
        const Vec3 X = vs::backProjectDepth(c, u, v, Z, vs::kDepthTypeWorld, ok);
        ASSERT_TRUE(ok) << u << " " << v << " " << Z;
        EXPECT_EQ(X.z, Z);
        double u2 = 0, v2 = 0, zCam = 0;
        ASSERT_TRUE(c.project(X, u2, v2, zCam));
        EXPECT_NEAR(u2, u, 1e-9);
        EXPECT_NEAR(v2, v, 1e-9);
        EXPECT_NEAR(vs::depthToCameraZ(c, u, v, Z, 1, ok), zCam, 1e-12 * zCam);
      }
    }
  }
}

TEST(DepthTest, DepthType1MatchesDepthType0ForAnAxisAlignedCamera) {
  // Camera at world z = -2 looking along +z: world z = Z is at camera depth Z + 2.
  const Camera c = camera(Mat3::identity(), {0.25, -0.5, -2.0});
  bool ok0 = false, ok1 = false;
  const Vec3 a = vs::backProjectDepth(c, 100.0, 700.0, 3.0, 1, ok1);
  const Vec3 b = vs::backProjectDepth(c, 100.0, 700.0, 5.0, 0, ok0);
  ASSERT_TRUE(ok0 && ok1);
  EXPECT_LT(vs::norm(a - b), 1e-14);
  EXPECT_EQ(a.z, 3.0);
  EXPECT_EQ(vs::depthToCameraZ(c, 100.0, 700.0, 3.0, 1, ok1), 5.0);
}

TEST(DepthTest, DepthType1RejectsParallelRaysAndPointsBehind) {
  // Looking along +x: the optical axis is parallel to every plane z = Z.
  Mat3 R;
  R[0][2] = -1.0;
  R[1][1] = 1.0;
  R[2][0] = 1.0;
  Camera side = camera(R, {0.0, 0.0, 0.0});
  side.K[0][1] = 0.0;
  bool ok = true;
  vs::backProjectDepth(side, 640.0, 100.0, 1.0, 1, ok);  // column through the principal point
  EXPECT_FALSE(ok);
  ok = false;
  vs::backProjectDepth(side, 100.0, 100.0, 1.0, 1, ok);  // a ray leaning towards +z meets z = 1
  EXPECT_TRUE(ok);

  // Looking along +z from z = 0: the plane z = -1 is behind, z = 0 is the camera plane.
  const Camera forward = camera(Mat3::identity(), {0.0, 0.0, 0.0});
  ok = true;
  vs::backProjectDepth(forward, 10.0, 10.0, -1.0, 1, ok);
  EXPECT_FALSE(ok);
  ok = true;
  vs::backProjectDepth(forward, 10.0, 10.0, 0.0, 1, ok);
  EXPECT_FALSE(ok);
  ok = true;
  vs::backProjectDepth(forward, 10.0, 10.0, std::nan(""), 1, ok);
  EXPECT_FALSE(ok);
  // Infinite world z: ahead for +inf, behind for -inf; neither is a finite point.
  EXPECT_EQ(vs::depthToCameraZ(forward, 10.0, 10.0, kInf, 1, ok), kInf);
  EXPECT_TRUE(ok);
  vs::depthToCameraZ(forward, 10.0, 10.0, -kInf, 1, ok);
  EXPECT_FALSE(ok);
  vs::backProjectDepth(forward, 10.0, 10.0, kInf, 1, ok);
  EXPECT_FALSE(ok);
}

// MissingDepthFill: runs of the missing level between two valid samples take the farther one's level
// (rows first, then columns for what is left); runs reaching the border both ways stay missing.
TEST(DepthTest, MissingRunsTakeTheFartherBoundingLevel) {
  const vs::DepthRange range{10.0, 100.0, 8};
  const std::vector<double> inverseZ = vs::inverseZTable(range);
  vs::Plane depth(7, 4, 0);
  const uint16_t rows[4][7] = {
      {0, 0, 0, 0, 0, 0, 0},          // all missing: the column pass fills what it can
      {90, 0, 0, 200, 0, 40, 0},      // two bounded runs (farther: 90, then 40) and one at the border
      {0, 0, 50, 50, 50, 0, 0},       // runs at both borders
      {120, 120, 0, 120, 120, 120, 7}};
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 7; ++x) depth.at(x, y) = rows[y][x];
  vs::Plane out;
  std::vector<uint8_t> filled;
  const size_t count = vs::fillMissingDepthRuns(depth, 0, inverseZ, out, filled);
  // Rows: (1..2, 1) between 90 and 200 -> 90; (4, 1) between 200 and 40 -> 40; (3, 0) between 120s.
  // Columns, for what is left: x 0..5 of row 2 lie between row 1 and row 3 -> the farther of the two;
  // column 6 has missing samples above row 3 only, row 0 has nothing above: they stay.
  const uint16_t fixed[4][7] = {
      {0, 0, 0, 0, 0, 0, 0},
      {90, 90, 90, 200, 40, 40, 0},
      {90, 90, 50, 50, 50, 40, 0},
      {120, 120, 120, 120, 120, 120, 7}};
  size_t marked = 0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 7; ++x) {
      EXPECT_EQ(out.at(x, y), fixed[y][x]) << x << ", " << y;
      EXPECT_EQ(filled[size_t(y) * 7 + x] != 0, depth.at(x, y) == 0 && fixed[y][x] != 0) << x << ", " << y;
      marked += filled[size_t(y) * 7 + x];
    }
  EXPECT_EQ(count, marked);
  EXPECT_EQ(depth.at(1, 1), 0);  // the input is untouched
  // Off: a copy.
  EXPECT_EQ(vs::fillMissingDepthRuns(depth, -1, inverseZ, out, filled), 0u);
  EXPECT_TRUE(out.samples == depth.samples);
}

// The same rule written plainly (every row, then every column, one sample at a time) against
// fillMissingDepthRuns on larger maps with few and many missing samples, runs longer than the
// sixteen samples it passes at a time, runs in columns after runs in rows, and a missing level that
// is not 0.
TEST(DepthTest, MissingRunsMatchAPlainFillOnRandomMaps) {
  const vs::DepthRange range{10.0, 100.0, 8};
  const std::vector<double> inverseZ = vs::inverseZTable(range);
  auto plainLine = [&](vs::Plane& map, std::vector<uint8_t>& marks, int n, int x0, int y0, int dx, int dy,
                       uint16_t missing) {
    auto at = [&](int i) -> uint16_t& { return map.at(x0 + i * dx, y0 + i * dy); };
    for (int k = 0; k < n; ++k) {
      if (at(k) != missing) continue;
      int end = k;
      while (end < n && at(end) == missing) ++end;
      if (k > 0 && end < n) {
        const uint16_t before = at(k - 1), after = at(end);
        const uint16_t farther = inverseZ[after] < inverseZ[before] ? after : before;
        for (int j = k; j < end; ++j) {
          at(j) = farther;
          marks[size_t(y0 + j * dy) * size_t(map.width) + size_t(x0 + j * dx)] = 1;
        }
      }
      k = end;
    }
  };
  uint32_t seed = 12345;
  auto next = [&]() {
    seed = seed * 1664525u + 1013904223u;
    return seed >> 8;
  };
  for (int trial = 0; trial < 40; ++trial) {
    const int w = 17 + int(next() % 90), h = 1 + int(next() % 40);
    const uint16_t missing = trial % 4 == 3 ? 255 : 0;
    const unsigned share = 1 + next() % 90;  // percent of missing samples
    vs::Plane depth(w, h, 0);
    for (uint16_t& level : depth.samples) {
      level = uint16_t(1 + next() % 254);
      if (next() % 100 < share) level = missing;
    }
    // A few long runs along rows and columns.
    for (int r = 0; r < 3; ++r) {
      const int y = int(next() % unsigned(h)), x = int(next() % unsigned(w));
      for (int i = x; i < std::min(w, x + 40); ++i) depth.at(i, y) = missing;
      for (int j = 0; j < h; ++j) depth.at(x, j) = j % 7 == 3 ? uint16_t(1 + next() % 254) : missing;
    }
    vs::Plane expected = depth;
    std::vector<uint8_t> expectedMarks(depth.samples.size(), 0);
    for (int y = 0; y < h; ++y) plainLine(expected, expectedMarks, w, 0, y, 1, 0, missing);
    for (int x = 0; x < w; ++x) plainLine(expected, expectedMarks, h, x, 0, 0, 1, missing);
    vs::Plane out;
    std::vector<uint8_t> filled;
    const size_t count = vs::fillMissingDepthRuns(depth, missing, inverseZ, out, filled);
    size_t marked = 0;
    for (uint8_t mark : expectedMarks) marked += mark;
    ASSERT_TRUE(out.samples == expected.samples) << "trial " << trial << " (" << w << " x " << h << ")";
    ASSERT_TRUE(filled == expectedMarks) << "trial " << trial;
    EXPECT_EQ(count, marked) << "trial " << trial;
  }
}
