#pragma once
// Equirectangular test cameras and directions shared by the ERP tests, written independently of
// Common/Camera.cpp so that the tests check it rather than repeat it.
#include <cmath>
#include <string>

#include "Common/Camera.h"
#include "Common/CameraJson.h"

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

}  // namespace vs::test
