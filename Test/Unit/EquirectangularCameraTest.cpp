// Equirectangular (ERP) cameras: the pixel <-> ray mapping against the angles written out by hand,
// round trips at every pixel centre (the wrap column and the pole rows included), partial ranges,
// depth as the distance along the ray, and the MPEG-I JSON reader and writer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "Common/Camera.h"
#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/Error.h"

namespace vs {
namespace {

constexpr double kPi = 3.14159265358979323846;

Camera erpCamera(int width, int height, double lonMin = -180, double lonMax = 180, double latMin = -90, double latMax = 90) {
  Camera c;
  c.name = "erp";
  c.projection = Projection::Equirectangular;
  c.erp.width = width;
  c.erp.height = height;
  c.erp.lonMin = lonMin;
  c.erp.lonMax = lonMax;
  c.erp.latMin = latMin;
  c.erp.latMax = latMax;
  return c;
}

// MPEG's axes (x forward, y left, z up) -> ours (x right, y down, z forward), written independently.
Vec3 fromMpeg(double forward, double left, double up) { return {-left, -up, forward}; }

TEST(EquirectangularCamera, PixelCentresHaveTheDocumentedAngles) {
  const Camera c = erpCamera(8, 4);
  // Column 0's centre is half a column (22.5 degrees) right of +180 (the left edge): longitude 157.5;
  // row 0's centre is 22.5 degrees below the north pole: latitude 67.5.
  auto expectRay = [&](double u, double v, double lonDegrees, double latDegrees) {
    const double lon = lonDegrees * kPi / 180, lat = latDegrees * kPi / 180;
    const Vec3 expected = fromMpeg(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
    const Vec3 ray = c.rayCamera(u, v);
    EXPECT_NEAR(ray.x, expected.x, 1e-15) << u << "," << v;
    EXPECT_NEAR(ray.y, expected.y, 1e-15) << u << "," << v;
    EXPECT_NEAR(ray.z, expected.z, 1e-15) << u << "," << v;
    EXPECT_NEAR(norm(ray), 1.0, 1e-15);
  };
  expectRay(0, 0, 157.5, 67.5);
  expectRay(7, 3, -157.5, -67.5);
  expectRay(3.5, 1.5, 0, 0);     // the picture's centre looks forward (MPEG +x, our +z)
  expectRay(1.5, 1.5, 90, 0);    // a quarter turn left of it: MPEG +y, our -x
  expectRay(3.5, -0.5, 0, 90);   // the top edge is the north pole: MPEG +z, our -y
  // Forward in ours is +z; left is -x; up is -y.
  EXPECT_NEAR(c.rayCamera(3.5, 1.5).z, 1.0, 1e-15);
  EXPECT_NEAR(c.rayCamera(1.5, 1.5).x, -1.0, 1e-15);
  EXPECT_NEAR(c.rayCamera(3.5, -0.5).y, -1.0, 1e-15);
}

TEST(EquirectangularCamera, EveryPixelCentreRoundTripsIncludingWrapAndPoles) {
  for (const Camera& c : {erpCamera(64, 32), erpCamera(37, 23, -90, 90, -90, 90), erpCamera(40, 20, -30, 150, -45, 60),
                          erpCamera(20, 10, 0, 360, -90, 90)}) {
    for (int v = 0; v < c.erp.height; ++v)
      for (int u = 0; u < c.erp.width; ++u) {
        const double distance = 0.5 + 0.25 * ((u * 7 + v * 3) % 11);
        const Vec3 point = c.pixelToCamera(u, v, distance);
        EXPECT_NEAR(norm(point), distance, 1e-14 * distance);  // depth is the distance along the ray
        EXPECT_NEAR(c.depthOf(point), distance, 1e-14 * distance);
        double x = -1, y = -1;
        ASSERT_TRUE(c.cameraToPixel(point, x, y));
        EXPECT_NEAR(x, u, 1e-9) << c.erp.lonMin << " " << u << "," << v;
        EXPECT_NEAR(y, v, 1e-9) << c.erp.lonMin << " " << u << "," << v;
      }
  }
}

TEST(EquirectangularCamera, WrapLiesAtThePictureEdges) {
  const Camera c = erpCamera(360, 180);
  double u, v;
  // Straight behind (longitude 180) is the left edge u = -0.5 of the full circle, never the right one.
  ASSERT_TRUE(c.cameraToPixel(fromMpeg(-1, 0, 0), u, v));
  EXPECT_NEAR(u, -0.5, 1e-12);
  EXPECT_NEAR(v, 89.5, 1e-12);
  // A hair to the right of straight behind (longitude -179.9): near the right edge.
  const double a = -179.9 * kPi / 180;
  ASSERT_TRUE(c.cameraToPixel(fromMpeg(std::cos(a), std::sin(a), 0), u, v));
  EXPECT_NEAR(u, 359.4, 1e-9);
  // Longitude +179.9: near the left edge.
  ASSERT_TRUE(c.cameraToPixel(fromMpeg(std::cos(-a), std::sin(-a), 0), u, v));
  EXPECT_NEAR(u, -0.4, 1e-9);
  // The ray of a column beyond the last is the ray of the column a whole turn earlier.
  const Vec3 beyond = c.rayCamera(360.25, 40), inside = c.rayCamera(0.25, 40);
  EXPECT_NEAR(norm(beyond - inside), 0.0, 1e-14);
}

TEST(EquirectangularCamera, PolesMapToTheTopAndBottomEdges) {
  const Camera c = erpCamera(64, 32);
  double u, v;
  ASSERT_TRUE(c.cameraToPixel(fromMpeg(0, 0, 2.0), u, v));  // north pole: any longitude, row edge -0.5
  EXPECT_NEAR(v, -0.5, 1e-12);
  EXPECT_TRUE(u >= -0.5 && u < 63.5);
  ASSERT_TRUE(c.cameraToPixel(fromMpeg(0, 0, -3.0), u, v));  // south pole
  EXPECT_NEAR(v, 31.5, 1e-12);
  // The pole rows' rays are all 2.8125 degrees (half a row) from the pole, whatever the column.
  for (int x = 0; x < 64; ++x) {
    EXPECT_NEAR(c.rayCamera(x, 0).y, -std::cos(2.8125 * kPi / 180), 1e-15);
    EXPECT_NEAR(c.rayCamera(x, 31).y, std::cos(2.8125 * kPi / 180), 1e-15);
  }
  // The centre itself has no direction.
  EXPECT_FALSE(c.cameraToPixel(Vec3(0, 0, 0), u, v));
}

TEST(EquirectangularCamera, PartialRangePutsOutsidePointsOnTheNearerSide) {
  // 90 degrees wide, centred on longitude 30 (MPEG: 30 degrees to the left of forward).
  const Camera c = erpCamera(90, 60, -15, 75, -30, 30);
  double u, v;
  const auto at = [](double lonDegrees, double latDegrees) {
    const double lon = lonDegrees * kPi / 180, lat = latDegrees * kPi / 180;
    return fromMpeg(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
  };
  ASSERT_TRUE(c.cameraToPixel(at(30, 0), u, v));
  EXPECT_NEAR(u, 44.5, 1e-9);
  EXPECT_NEAR(v, 29.5, 1e-9);
  ASSERT_TRUE(c.cameraToPixel(at(80, 10), u, v));  // 5 degrees left of the left edge
  EXPECT_NEAR(u, -5.5, 1e-9);
  EXPECT_NEAR(v, 19.5, 1e-9);
  ASSERT_TRUE(c.cameraToPixel(at(-20, -40), u, v));  // 5 degrees right of the right edge, below the bottom
  EXPECT_NEAR(u, 94.5, 1e-9);
  EXPECT_NEAR(v, 69.5, 1e-9);
  ASSERT_TRUE(c.cameraToPixel(at(-140, 0), u, v));  // 170 degrees right of the middle: 215 from the left edge
  EXPECT_NEAR(u, 214.5, 1e-9);
  ASSERT_TRUE(c.cameraToPixel(at(-160, 0), u, v));  // 190 degrees right of the middle is 170 left of it
  EXPECT_NEAR(u, -125.5, 1e-9);
}

TEST(EquirectangularCamera, WorldProjectionUsesTheDistanceAsDepth) {
  Camera c = erpCamera(64, 32);
  c.R = rotationFromYawPitchRoll(30, 10, -5);
  c.t = Vec3(1.5, -2.0, 0.25);
  for (int v = 0; v < 32; v += 3)
    for (int u = 0; u < 64; u += 5) {
      const Vec3 world = c.backProject(u, v, 4.0);
      EXPECT_NEAR(norm(world - c.centre()), 4.0, 1e-12);
      double x, y, depth;
      ASSERT_TRUE(c.project(world, x, y, depth));
      EXPECT_NEAR(depth, 4.0, 1e-12);
      EXPECT_NEAR(x, u, 1e-9);
      EXPECT_NEAR(y, v, 1e-9);
      EXPECT_NEAR(norm(c.rayDirectionWorld(u, v) * 4.0 + c.centre() - world), 0.0, 1e-12);
    }
}

TEST(EquirectangularCamera, JsonReadsWritesAndRefuses) {
  const std::string text = R"({"cameras": [
    {"Name": "c", "Position": [1, 2, 3], "Rotation": [10, 0, 0], "Projection": "Equirectangular",
     "Hor_range": [-90, 90], "Ver_range": [-45, 60], "Resolution": [400, 200], "Depth_range": [0.5, 25]},
    {"Name": "p", "Position": [0, 0, 0], "Rotation": [0, 0, 0], "Projection": "Perspective",
     "Focal": [100, 100], "Principle_point": [50, 40], "Resolution": [100, 80]}]})";
  const CameraFile file = parseCameraJson(text, "erp.json");
  const Camera& c = file.find("c");
  ASSERT_TRUE(c.isEquirectangular());
  EXPECT_FALSE(file.find("p").isEquirectangular());
  EXPECT_EQ(c.erp.width, 400);
  EXPECT_EQ(c.erp.height, 200);
  EXPECT_EQ(c.erp.lonMin, -90);
  EXPECT_EQ(c.erp.latMax, 60);
  EXPECT_FALSE(c.erp.wraps());
  EXPECT_EQ(file.info("c").znear, 0.5);
  // Position (1, 2, 3) in MPEG's axes is (-2, -3, 1) in ours.
  EXPECT_EQ(c.t, Vec3(-2, -3, 1));

  const std::string path = ::testing::TempDir() + "erp_roundtrip.json";
  writeCameraJson(path, file.cameras(), {file.info("c"), file.info("p")});
  const CameraFile back = readCameraJson(path);
  const Camera& c2 = back.find("c");
  ASSERT_TRUE(c2.isEquirectangular());
  EXPECT_TRUE(c2.erp == c.erp);
  EXPECT_NEAR(maxAbs(c2.R - c.R), 0.0, 1e-12);
  EXPECT_EQ(c2.t, c.t);
  EXPECT_EQ(back.info("c").zfar, 25);
  EXPECT_FALSE(back.find("p").isEquirectangular());
  std::remove(path.c_str());

  // The VSRS text format has no ERP: writing one is refused with the reason.
  try {
    writeCameraFile(::testing::TempDir() + "erp.txt", file.cameras());
    ADD_FAILURE() << "an ERP camera was written as VSRS text";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("equirectangular"), std::string::npos);
  }

  auto error = [](const std::string& camera) {
    try {
      parseCameraJson("{\"cameras\": [{\"Name\": \"e\", \"Position\": [0,0,0], \"Rotation\": [0,0,0], "
                      "\"Projection\": \"Equirectangular\", " + camera + "}]}", "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error(R"("Ver_range": [-90, 90], "Resolution": [8, 4])").find("\"Hor_range\""), std::string::npos);
  EXPECT_NE(error(R"("Hor_range": [-180, 180], "Ver_range": [-90, 90])").find("\"Resolution\""), std::string::npos);
  EXPECT_NE(error(R"("Hor_range": [-180, 200], "Ver_range": [-90, 90], "Resolution": [8, 4])").find("at most 360"),
            std::string::npos);
  EXPECT_NE(error(R"("Hor_range": [-180, 180], "Ver_range": [-95, 90], "Resolution": [8, 4])").find("-90 <= min"),
            std::string::npos);
  EXPECT_NE(error(R"("Hor_range": [10, 10], "Ver_range": [-90, 90], "Resolution": [8, 4])").find("min < max"),
            std::string::npos);
  EXPECT_EQ(error(R"("Hor_range": [0, 360], "Ver_range": [-90, 90], "Resolution": [8, 4])"), "");
}

}  // namespace
}  // namespace vs
