// SceneGen's geometry against analytic truth: depth levels of a fronto-parallel plane, the silhouette
// of a sphere, reprojection between cameras, exact primitive intersections, BT.601 conversion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Depth.h"
#include "Common/Yuv.h"
#include "Scene/Primitives.h"
#include "Scene/RayCaster.h"
#include "Scene/Rig.h"
#include "Scene/SceneGen.h"
#include "Scene/Scenes.h"
#include "TestPaths.h"

namespace vs {
namespace {

SceneGenSettings settingsFrom(const std::vector<std::string>& overrides) {
  return readSceneGenSettings(Config::load(sceneGenOptionTable(), "", overrides));
}

SceneGenResult generate(const std::vector<std::string>& overrides, const std::filesystem::path& folder) {
  std::vector<std::string> all = overrides;
  all.push_back("OutputFolder=" + folder.string());
  std::ostringstream log;
  return generateScene(settingsFrom(all), log);
}

// The level DESIGN.md's formula gives, computed here independently of Depth.cpp.
double exactLevel(double z, double znear, double zfar, int bits) {
  const double maxLevel = std::pow(2.0, bits) - 1.0;
  return maxLevel * (1.0 / z - 1.0 / zfar) / (1.0 / znear - 1.0 / zfar);
}

double luma(const Rgb& c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; }

// ---------------------------------------------------------------------------------------------------

class SceneGenPlaneDepthTest : public ::testing::TestWithParam<int> {};

TEST_P(SceneGenPlaneDepthTest, FrontoParallelPlaneGetsTheFormulaLevelOnEveryPixel) {
  const int bits = GetParam();
  const double z = 3.9, znear = 2.0, zfar = 10.0;  // levels 99.71 and 25625.87: rounding, not truncation
  const double continuous = exactLevel(z, znear, zfar, bits);
  const double fraction = continuous - std::floor(continuous);
  ASSERT_GT(std::fabs(fraction - 0.5), 0.01) << "pick a plane depth away from a rounding boundary";
  const int expected = int(std::lround(continuous));

  const auto folder = test::scratchDir("scenegen_plane_" + std::to_string(bits));
  const SceneGenResult result = generate({"Scene=plane", "BackgroundDepth=3.9", "NearestDepthValue=2",
                                          "FarthestDepthValue=10", "DepthBitDepth=" + std::to_string(bits)},
                                         folder);
  ASSERT_EQ(result.cameras.size(), 3u);
  EXPECT_EQ(result.trueNearest, z);  // the centre ray's parameter is the camera z, exactly
  EXPECT_EQ(result.trueFarthest, z);
  EXPECT_EQ(result.clampedSamples, 0);
  EXPECT_EQ(result.emptySamples, 0);

  const FrameFormat format{128, 96, bits, ChromaFormat::Yuv420};
  for (const std::string& path : result.depthPaths) {
    YuvReader reader(path, format);
    ASSERT_EQ(reader.frameCount(), 2);
    ASSERT_EQ(reader.trailingBytes(), 0u);
    Frame frame;
    for (int64_t n = 0; n < reader.frameCount(); ++n) {
      reader.read(n, frame);
      int wrong = 0;
      for (uint16_t level : frame.planes[0].samples) wrong += level != expected;
      EXPECT_EQ(wrong, 0) << path << " frame " << n << ": expected level " << expected << " everywhere";
      for (int p = 1; p < 3; ++p)
        for (uint16_t c : frame.planes[p].samples) ASSERT_EQ(c, 1 << (bits - 1)) << "chroma is mid grey";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SceneGen, SceneGenPlaneDepthTest, ::testing::Values(8, 16));

TEST(SceneGenGeometryTest, TiltedPlaneDepthIsTheRayPlaneIntersection) {
  // A rectangle turned 30 degrees about y: camera z on pixel (u, v) solves n . (z K^-1 (u, v, 1)) = n . P.
  Primitive plane;
  plane.shape = Shape::Rectangle;
  plane.halfSize = {100.0, 100.0, 0.0};
  plane.position = {0.2, -0.1, 5.0};
  plane.orientation = axisAngleRotation({0, 1, 0}, 30.0);
  const Camera camera = lookAtCamera("c", pinholeIntrinsics(80.0, 31.5, 23.5), {0.1, 0.0, 0.0}, {0.3, 0.1, 5.0});
  RenderOptions options;
  options.samplesPerPixel = 1;
  const RenderedView view = renderView({plane}, camera, 64, 48, 0, options);
  const Vec3 normal = plane.orientation.col(2);
  double worst = 0.0;
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) {
      const Vec3 ray = camera.backProject(u, v, 1.0) - camera.t;  // world offset of camera z = 1
      const double z = dot(normal, plane.position - camera.t) / dot(normal, ray);
      worst = std::max(worst, std::fabs(view.depthAt(u, v) - z) / z);
    }
  EXPECT_LT(worst, 1e-12);
}

TEST(SceneGenGeometryTest, SphereSilhouetteRadiusMatchesThePinholeProjection) {
  // Sphere of radius r at distance d on the optical axis: the silhouette is a circle of radius
  // f r / sqrt(d^2 - r^2) pixels around the principal point.
  struct Case {
    double radius, depth, focal, cx, cy;
  };
  for (const Case& c :
       {Case{0.5, 3.0, 150.0, 80.0, 60.0}, Case{0.8, 2.5, 120.0, 79.5, 59.5}, Case{0.3, 4.0, 200.0, 70.25, 63.75}}) {
    SCOPED_TRACE("radius " + std::to_string(c.radius) + " depth " + std::to_string(c.depth));
    const SceneGenSettings s =
        settingsFrom({"Scene=sphere", "CameraCount=1", "SourceWidth=160", "SourceHeight=120",
                      "SphereRadius=" + exactNumberText(c.radius), "SphereDepth=" + exactNumberText(c.depth),
                      "FocalLength=" + exactNumberText(c.focal), "PrincipalPointX=" + exactNumberText(c.cx),
                      "PrincipalPointY=" + exactNumberText(c.cy)});
    const std::vector<Camera> cameras = buildCameras(s);
    ASSERT_EQ(cameras.size(), 1u);
    ASSERT_EQ(cameras[0].t, Vec3());
    RenderOptions options;
    options.samplesPerPixel = 1;
    const RenderedView view = renderView(buildScene(s), cameras[0], s.width, s.height, 0, options);
    const double expectedRadius = c.focal * c.radius / std::sqrt(c.depth * c.depth - c.radius * c.radius);

    int sphereCount = 0, misplaced = 0;
    for (int v = 0; v < view.height; ++v)
      for (int u = 0; u < view.width; ++u) {
        const bool onSphere = view.depthAt(u, v) < s.backgroundDepth - 1e-9;
        sphereCount += onSphere;
        const double distance = std::hypot(u - c.cx, v - c.cy);
        if ((distance < expectedRadius - 1e-6 && !onSphere) || (distance > expectedRadius + 1e-6 && onSphere))
          ++misplaced;
      }
    EXPECT_EQ(misplaced, 0) << "every pixel centre inside the analytic circle is on the sphere, none outside";
    const double measuredRadius = std::sqrt(sphereCount / 3.14159265358979323846);
    EXPECT_NEAR(measuredRadius, expectedRadius, 0.5);
    EXPECT_NEAR(measuredRadius, expectedRadius, 0.1) << "area estimate is usually far better than 0.5 px";
    if (c.cx == std::floor(c.cx) && c.cy == std::floor(c.cy)) {
      EXPECT_DOUBLE_EQ(view.depthAt(int(c.cx), int(c.cy)), c.depth - c.radius);  // the sphere's nearest point
    }
  }
}

// Projecting a pixel's 3D point (from its depth) into another camera lands on that camera's render of
// the same surface point: same depth exactly, same colour within the anti-aliasing error.
void checkReprojection(const std::vector<std::string>& overrides, int from, int to) {
  const SceneGenSettings s = settingsFrom(overrides);
  const std::vector<Camera> cameras = buildCameras(s);
  const std::vector<Primitive> primitives = buildScene(s);
  const int frame = 2;
  RenderOptions options;
  const RenderedView a = renderView(primitives, cameras[from], s.width, s.height, frame, options);
  const RenderedView b = renderView(primitives, cameras[to], s.width, s.height, frame, options);
  const PlacedScene placed(primitives, frame);
  const Camera& target = cameras[to];
  const Mat3 targetToWorld = inverse(target.R);

  int landed = 0, occluded = 0, depthMismatch = 0, compared = 0, colourMismatch = 0;
  double colourErrorSum = 0.0;
  for (int v = 1; v + 1 < a.height; ++v)
    for (int u = 1; u + 1 < a.width; ++u) {
      const double z = a.depthAt(u, v);
      if (z == kNoSurface) continue;
      const Vec3 X = cameras[from].backProject(u, v, z);
      double ub = 0, vb = 0, zb = 0;
      if (!target.project(X, ub, vb, zb) || ub < 1 || vb < 1 || ub > b.width - 2 || vb > b.height - 2) continue;
      ++landed;
      // Geometry: camera `to`'s own ray through (ub, vb) meets the scene at depth zb unless occluded.
      double t = 0.0;
      ASSERT_TRUE(placed.cast(target.t, targetToWorld * target.pixelToCamera(ub, vb, 1.0), 1e-9, t, nullptr));
      if (t < zb * (1.0 - 1e-6)) {
        ++occluded;
        continue;
      }
      if (std::fabs(t - zb) > 1e-6 * zb) ++depthMismatch;
      // Colour: bilinear in camera `to`'s image, only where both neighbourhoods are one smooth surface.
      const int u0 = int(std::floor(ub)), v0 = int(std::floor(vb));
      const double fu = ub - u0, fv = vb - v0;
      bool smooth = true;
      double lo = 1e9, hi = -1e9;
      for (int dv = 0; dv <= 1; ++dv)
        for (int du = 0; du <= 1; ++du) {
          smooth &= std::fabs(b.depthAt(u0 + du, v0 + dv) - zb) < 0.01 * zb;
          lo = std::min(lo, luma(b.colourAt(u0 + du, v0 + dv)));
          hi = std::max(hi, luma(b.colourAt(u0 + du, v0 + dv)));
        }
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          smooth &= std::fabs(a.depthAt(u + du, v + dv) - z) < 0.01 * z;
          lo = std::min(lo, luma(a.colourAt(u + du, v + dv)));
          hi = std::max(hi, luma(a.colourAt(u + du, v + dv)));
        }
      if (!smooth || hi - lo > 0.06) continue;  // texture edges: interpolation is not the truth there
      const double interpolated =
          (1 - fv) * ((1 - fu) * luma(b.colourAt(u0, v0)) + fu * luma(b.colourAt(u0 + 1, v0))) +
          fv * ((1 - fu) * luma(b.colourAt(u0, v0 + 1)) + fu * luma(b.colourAt(u0 + 1, v0 + 1)));
      const double error = std::fabs(interpolated - luma(a.colourAt(u, v)));
      ++compared;
      colourErrorSum += error;
      colourMismatch += error > 0.03;
    }
  EXPECT_GT(landed, a.width * a.height / 2);
  EXPECT_LT(occluded, landed / 5);
  EXPECT_EQ(depthMismatch, 0);
  ASSERT_GT(compared, landed / 4) << "enough smooth pixels to compare";
  EXPECT_LT(colourErrorSum / compared, 0.003) << "mean |luma error| over " << compared << " pixels";
  EXPECT_LT(colourMismatch, compared / 500) << colourMismatch << " of " << compared << " differ by more than 0.03";
}

TEST(SceneGenGeometryTest, ReprojectionIntoAParallelNeighbourLandsOnTheSameSurfacePoint) {
  checkReprojection({"Scene=demo", "SourceWidth=256", "SourceHeight=192"}, 0, 2);
}

TEST(SceneGenGeometryTest, ReprojectionIntoARotatedArcCameraLandsOnTheSameSurfacePoint) {
  checkReprojection({"Scene=arc", "SourceWidth=240", "SourceHeight=180", "CameraCount=3", "ArcAngle=8"}, 2, 0);
}

TEST(SceneGenGeometryTest, ReprojectionThroughWritten16BitDepthLandsWithinAHundredthOfAPixel) {
  // The same check through the files: quantised 16-bit levels back to Z (Depth.h), then into the
  // other camera; compared with the exact projection of the exact depth.
  const auto folder = test::scratchDir("scenegen_reproject16");
  const SceneGenResult result = generate(
      {"Scene=tiny", "SourceWidth=128", "SourceHeight=96", "DepthBitDepth=16", "TotalNumberOfFrames=1"}, folder);
  const SceneGenSettings s = settingsFrom({"Scene=tiny", "SourceWidth=128", "SourceHeight=96"});
  RenderOptions options;
  const RenderedView exact = renderView(buildScene(s), result.cameras[0], s.width, s.height, 0, options);
  YuvReader reader(result.depthPaths[0], FrameFormat{128, 96, 16, ChromaFormat::Yuv420});
  Plane levels;
  reader.readLuma(0, levels);
  double worst = 0.0;
  for (int v = 0; v < 96; ++v)
    for (int u = 0; u < 128; ++u) {
      const double zExact = exact.depthAt(u, v);
      const double zFile = levelToZ(levels.at(u, v), result.depthRange);
      double u1 = 0, v1 = 0, z1 = 0, u2 = 0, v2 = 0, z2 = 0;
      ASSERT_TRUE(result.cameras[2].project(result.cameras[0].backProject(u, v, zExact), u1, v1, z1));
      ASSERT_TRUE(result.cameras[2].project(result.cameras[0].backProject(u, v, zFile), u2, v2, z2));
      worst = std::max(worst, std::hypot(u1 - u2, v1 - v2));
    }
  EXPECT_LT(worst, 0.01);
}

// ---------------------------------------------------------------------------------------------------

TEST(SceneGenGeometryTest, PrimitiveIntersectionsAreExact) {
  double t = 0;
  Vec3 p;
  // Sphere of radius 1 from z = -5 along +z: enters at t = 4; from inside it leaves at t = 1.
  ASSERT_TRUE(intersectObject(Shape::Sphere, {1, 1, 1}, {0, 0, -5}, {0, 0, 1}, 0.0, 1e9, t, p));
  EXPECT_DOUBLE_EQ(t, 4.0);
  EXPECT_DOUBLE_EQ(p.z, -1.0);
  ASSERT_TRUE(intersectObject(Shape::Sphere, {1, 1, 1}, {0, 0, 0}, {0, 0, 2}, 0.0, 1e9, t, p));
  EXPECT_DOUBLE_EQ(t, 0.5);
  EXPECT_FALSE(intersectObject(Shape::Sphere, {1, 1, 1}, {0, 1.0001, -5}, {0, 0, 1}, 0.0, 1e9, t, p));
  EXPECT_FALSE(intersectObject(Shape::Sphere, {1, 1, 1}, {0, 0, 5}, {0, 0, 1}, 0.0, 1e9, t, p)) << "behind";
  // Box: the face hit is snapped exactly onto the face.
  ASSERT_TRUE(intersectObject(Shape::Box, {1, 2, 3}, {0.3, 0.1, -10}, {0.01, 0.02, 1}, 0.0, 1e9, t, p));
  EXPECT_DOUBLE_EQ(t, 7.0);
  EXPECT_EQ(p.z, -3.0);
  EXPECT_FALSE(intersectObject(Shape::Box, {1, 2, 3}, {1.5, 0, -10}, {0, 0, 1}, 0.0, 1e9, t, p));
  ASSERT_TRUE(intersectObject(Shape::Box, {1, 2, 3}, {0, 0, 0}, {1, 0, 0}, 0.0, 1e9, t, p)) << "from inside";
  EXPECT_DOUBLE_EQ(t, 1.0);
  // Rectangle: inside and just outside its edge; tMax cuts off farther hits.
  ASSERT_TRUE(intersectObject(Shape::Rectangle, {1, 1, 0}, {0.999, 0, -2}, {0, 0, 1}, 0.0, 1e9, t, p));
  EXPECT_EQ(p.z, 0.0);
  EXPECT_FALSE(intersectObject(Shape::Rectangle, {1, 1, 0}, {1.001, 0, -2}, {0, 0, 1}, 0.0, 1e9, t, p));
  EXPECT_FALSE(intersectObject(Shape::Rectangle, {1, 1, 0}, {0, 0, -2}, {0, 0, 1}, 0.0, 1.5, t, p));
}

TEST(SceneGenGeometryTest, NearerObjectOccludesFartherOne) {
  Primitive wall;
  wall.shape = Shape::Rectangle;
  wall.halfSize = {10, 10, 0};
  wall.position = {0, 0, 5};
  Primitive ball;
  ball.shape = Shape::Sphere;
  ball.halfSize = {0.5, 0.5, 0.5};
  ball.position = {0, 0, 3};
  for (const auto& order : {std::vector<Primitive>{wall, ball}, std::vector<Primitive>{ball, wall}}) {
    const PlacedScene scene(order, 0.0);
    double t = 0;
    ASSERT_TRUE(scene.cast({0, 0, 0}, {0, 0, 1}, 1e-9, t, nullptr));
    EXPECT_DOUBLE_EQ(t, 2.5);
    ASSERT_TRUE(scene.cast({0, 0, 0}, {0.2, 0, 1}, 1e-9, t, nullptr));
    EXPECT_DOUBLE_EQ(t, 5.0);
  }
}

TEST(SceneGenGeometryTest, MotionMovesAndTurnsObjects) {
  Primitive box;
  box.shape = Shape::Box;
  box.position = {1, 2, 3};
  box.motion.velocity = {0.5, 0, 0};
  box.motion.spinAxis = {0, 0, 1};
  box.motion.spinDegrees = 90.0;
  const PlacedPrimitive at2 = placePrimitive(box, 2.0);
  EXPECT_EQ(at2.centre, Vec3(2, 2, 3));
  // Two quarter turns about z: the object's x axis points along world -x.
  const Vec3 objectX = transpose(at2.worldToObject).col(0);
  EXPECT_NEAR(objectX.x, -1.0, 1e-12);
  EXPECT_NEAR(objectX.y, 0.0, 1e-12);
  const PlacedPrimitive frozen = placePrimitive(box, 2.0, 0.0);
  EXPECT_EQ(frozen.centre, box.position);
  EXPECT_EQ(frozen.worldToObject, Mat3::identity());
}

TEST(SceneGenGeometryTest, RigsFollowTheCameraConvention) {
  const Mat3 K = pinholeIntrinsics(100, 63.5, 47.5);
  const std::vector<Camera> parallel = parallelRig(3, 0.2, K);
  EXPECT_EQ(parallel[0].t, Vec3(-0.2, 0, 0));
  EXPECT_EQ(parallel[1].t, Vec3(0, 0, 0));
  EXPECT_EQ(parallel[2].t, Vec3(0.2, 0, 0));
  // A point in front of the rig: the right camera sees it further left (smaller u).
  double u0 = 0, v0 = 0, z0 = 0, u2 = 0, v2 = 0, z2 = 0;
  ASSERT_TRUE(parallel[0].project({0, 0, 4}, u0, v0, z0));
  ASSERT_TRUE(parallel[2].project({0, 0, 4}, u2, v2, z2));
  EXPECT_DOUBLE_EQ(u0 - u2, 100 * 0.4 / 4);
  EXPECT_DOUBLE_EQ(v0, 47.5);

  const std::vector<Camera> arc = arcRig(3, 5.0, 10.0, K);
  for (const Camera& c : arc) {
    double u = 0, v = 0, z = 0;
    ASSERT_TRUE(c.project({0, 0, 5}, u, v, z)) << c.name;  // every camera looks at the focus
    EXPECT_NEAR(u, 63.5, 1e-9);
    EXPECT_NEAR(v, 47.5, 1e-9);
    EXPECT_NEAR(z, 5.0, 1e-12);
    EXPECT_NEAR(maxAbs(c.R * transpose(c.R) - Mat3::identity()), 0.0, 1e-15);
    EXPECT_NEAR(determinant(c.R), 1.0, 1e-15);
  }
  EXPECT_LT(arc[0].t.x, 0.0) << "cam0 is the leftmost";
  EXPECT_GT(arc[2].t.x, 0.0);
  EXPECT_EQ(arc[1].R, Mat3::identity());
}

TEST(SceneGenGeometryTest, Bt601LimitedRangeConversionAndChromaMean) {
  RenderedView view;
  view.width = 4;
  view.height = 2;
  view.colour = {{1, 1, 1}, {1, 1, 1}, {0, 0, 0}, {1, 0, 0},  // row 0
                 {1, 1, 1}, {1, 1, 1}, {0, 0, 0}, {1, 0, 0}};
  view.depth.assign(8, kNoSurface);
  Frame frame;
  colourToYuv420(view, frame);
  EXPECT_EQ(frame.format.bitDepth, 8);
  EXPECT_EQ(frame.planes[0].at(0, 0), 235);  // white
  EXPECT_EQ(frame.planes[0].at(2, 1), 16);   // black
  EXPECT_EQ(frame.planes[0].at(3, 0), 81);   // red: 16 + 219 * 0.299 = 81.48
  EXPECT_EQ(frame.planes[1].at(0, 0), 128);  // white block: neutral chroma
  EXPECT_EQ(frame.planes[2].at(0, 0), 128);
  // Black and red block: Cb = 128 + 224 * mean(0, 0, -0.299, -0.299) / 1.772 = 109.1,
  // Cr = 128 + 224 * mean(0, 0, 0.701, 0.701) / 1.402 = 184.
  EXPECT_EQ(frame.planes[1].at(1, 0), 109);
  EXPECT_EQ(frame.planes[2].at(1, 0), 184);
}

TEST(SceneGenGeometryTest, TexturesHaveDetailAndStayInRange) {
  const SceneGenSettings s = settingsFrom({"Scene=demo"});
  for (const Primitive& p : buildScene(s)) {
    double lo = 1, hi = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 q{std::sin(i * 1.3) * p.halfSize.x, std::cos(i * 0.7) * p.halfSize.y,
                   std::sin(i * 2.1) * p.halfSize.z};
      const Rgb c = p.texture.colourAt(q);
      for (float channel : {c.r, c.g, c.b}) {
        ASSERT_GE(channel, 0.0f);
        ASSERT_LE(channel, 1.0f);
      }
      lo = std::min(lo, luma(c));
      hi = std::max(hi, luma(c));
    }
    EXPECT_GT(hi - lo, 0.1) << p.name << " has texture detail";
  }
  for (int i = 0; i < 1000; ++i) {
    const double n = fractalNoise({i * 0.173, i * 0.071, -i * 0.05}, 4, 7);
    ASSERT_GE(n, 0.0);
    ASSERT_LE(n, 1.0);
  }
}

}  // namespace
}  // namespace vs
