#pragma once
// Equirectangular test cameras and directions shared by the ERP tests, written independently of
// Common/Camera.cpp so that the tests check it rather than repeat it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "Common/Camera.h"
#include "Common/CameraJson.h"
#include "Common/Frame.h"

namespace vs::test {

constexpr double kPi = 3.14159265358979323846;

// A full-sphere ERP camera of width x height samples at `centre`, axes of the world.
inline Camera erpCamera(const std::string& name, int width, int height, const Vec3& centre) {
  Camera c;
  c.name = name;
  c.projection = Projection::Equirectangular;
  c.erp.width = width;
  c.erp.height = height;
  c.t = centre;
  return c;
}

// Our camera axes of MPEG's longitude and latitude (radians; degrees converted by the caller).
inline Vec3 sphereDirection(double lon, double lat) {
  return {-std::cos(lat) * std::sin(lon), -std::sin(lat), std::cos(lat) * std::cos(lon)};
}

// A pinhole camera of width x height, horizontal field of view `degrees`, turned `yaw` degrees to the
// left (MPEG's yaw), at `centre`: the perspective viewports and references of the room scene's tests.
inline Camera pinholeCamera(const std::string& name, double degrees, double yaw, const Vec3& centre, int width,
                            int height) {
  Camera c;
  c.name = name;
  c.K[0][0] = c.K[1][1] = (width / 2.0) / std::tan(degrees / 2 * kPi / 180);
  c.K[0][2] = (width - 1) / 2.0;
  c.K[1][2] = (height - 1) / 2.0;
  c.R = rotationFromYawPitchRoll(yaw, 0, 0);
  c.t = centre;
  return c;
}

// The direction of ERP sample position (u, v) of a full-sphere width x height picture (integers are
// sample centres, column 0 starts at longitude 180, row 0 at latitude 90), from MPEG's formulas.
inline Vec3 erpPixelDirection(double u, double v, int width, int height) {
  return sphereDirection(kPi - (u + 0.5) * 2 * kPi / width, kPi / 2 - (v + 0.5) * kPi / height);
}

// A smooth texture on the sphere, steep enough (about 20 code values a sample at 128 x 64) that a
// look-up half a sample off shows; continuous round the wrap and across the poles, where a picture is not.
inline double sphereLuma(const Vec3& d) { return 128.0 + 45.0 * std::sin(9.0 * d.x + 1.0) + 45.0 * std::sin(9.0 * d.z + 2.0); }
inline double sphereChroma(const Vec3& d) { return 128.0 + 60.0 * std::sin(5.0 * d.x - 5.0 * d.y + 0.5); }

// The function sampled at an ERP picture's sample centres; `scale` its samples per luma sample (0.5 for
// 4:2:0 chroma, whose sample c covers luma (c + 0.5) / scale - 0.5).
inline Plane sphereTexture(int width, int height, double (*f)(const Vec3&), double scale) {
  Plane plane(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double value = f(erpPixelDirection((x + 0.5) / scale - 0.5, (y + 0.5) / scale - 0.5, int(width / scale),
                                               int(height / scale)));
      plane.at(x, y) = uint16_t(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  return plane;
}

}  // namespace vs::test
