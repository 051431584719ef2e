#include "Common/Camera.h"

#include <cmath>
#include <cstdio>

#include "Common/Error.h"

namespace vs {

namespace {

std::string prefix(const Camera& camera, const std::string& where) {
  return (where.empty() ? std::string() : where + ": ") + "camera '" + camera.name + "': ";
}

// Max |R R^T - I|: how far R is from an orthonormal matrix.
double orthonormalityDeviation(const Mat3& R) { return maxAbs(R * transpose(R) - Mat3::identity()); }

}  // namespace

Vec3 Camera::worldToCamera(const Vec3& X) const { return R * (X - t); }

Vec3 Camera::cameraToWorld(const Vec3& xc) const { return inverse(R) * xc + t; }

namespace {

constexpr double kRadians = M_PI / 180.0;

// Longitude of pixel column u and latitude of row v (radians), and back.
double longitudeOf(const EquirectangularRange& e, double u) {
  return (e.lonMax - (u + 0.5) * (e.lonMax - e.lonMin) / e.width) * kRadians;
}
double latitudeOf(const EquirectangularRange& e, double v) {
  return (e.latMax - (v + 0.5) * (e.latMax - e.latMin) / e.height) * kRadians;
}

}  // namespace

Vec3 Camera::rayCamera(double u, double v) const {
  if (isEquirectangular()) {
    const double phi = longitudeOf(erp, u), theta = latitudeOf(erp, v);
    const double c = std::cos(theta);
    return {-c * std::sin(phi), -std::sin(theta), c * std::cos(phi)};
  }
  return pixelToCamera(u, v, 1.0);
}

double Camera::depthOf(const Vec3& xc) const { return isEquirectangular() ? norm(xc) : xc.z; }

Vec3 Camera::pixelToCamera(double u, double v, double zCam) const {
  if (isEquirectangular()) return rayCamera(u, v) * zCam;
  // Solve the upper 2x2 block of K for the normalised coordinates (xn, yn) of the ray z = 1; the last
  // row of K is (0, 0, 1) (validateCamera). The usual K has K[1][0] = 0, which keeps this exact-ish.
  const double p = u - K[0][2];
  const double q = v - K[1][2];
  double xn;
  double yn;
  if (K[1][0] == 0.0) {
    yn = q / K[1][1];
    xn = (p - K[0][1] * yn) / K[0][0];
  } else {
    const double det = K[0][0] * K[1][1] - K[0][1] * K[1][0];
    xn = (K[1][1] * p - K[0][1] * q) / det;
    yn = (K[0][0] * q - K[1][0] * p) / det;
  }
  return {xn * zCam, yn * zCam, zCam};
}

bool Camera::cameraToPixel(const Vec3& xc, double& u, double& v) const {
  if (isEquirectangular()) {
    const double horizontal = std::hypot(xc.x, xc.z);
    if (!(horizontal > 0.0 || xc.y != 0.0)) return false;  // the centre itself (or NaN)
    const double phi = std::atan2(-xc.x, xc.z), theta = std::atan2(-xc.y, horizontal);
    const double span = (erp.lonMax - erp.lonMin) * kRadians;
    // Longitude measured from the left edge, taken within half a turn of the range's middle: [0, 2 pi)
    // for a full circle, so that the wrap lies exactly at the picture's edges.
    double fromLeft = erp.lonMax * kRadians - phi;
    const double low = 0.5 * span - M_PI;
    fromLeft -= 2.0 * M_PI * std::floor((fromLeft - low) / (2.0 * M_PI));
    u = fromLeft * erp.width / span - 0.5;
    v = (erp.latMax * kRadians - theta) * erp.height / ((erp.latMax - erp.latMin) * kRadians) - 0.5;
    return std::isfinite(u) && std::isfinite(v);
  }
  if (!(xc.z > 0.0)) return false;
  const double xn = xc.x / xc.z;
  const double yn = xc.y / xc.z;
  u = K[0][0] * xn + K[0][1] * yn + K[0][2];
  v = K[1][0] * xn + K[1][1] * yn + K[1][2];
  return true;
}

bool Camera::project(const Vec3& X, double& u, double& v, double& zCam) const {
  const Vec3 xc = worldToCamera(X);
  zCam = depthOf(xc);
  return cameraToPixel(xc, u, v);
}

Vec3 Camera::backProject(double u, double v, double zCam) const { return cameraToWorld(pixelToCamera(u, v, zCam)); }

Vec3 Camera::rayDirectionWorld(double u, double v) const {
  const Vec3 d = inverse(R) * rayCamera(u, v);
  return d / norm(d);
}

void applyRotationConvention(Camera& camera, RotationConvention convention) {
  if (convention == RotationConvention::CameraToWorld) camera.R = transpose(camera.R);
}

void validateCamera(const Camera& camera, const std::string& where, std::vector<std::string>& warnings) {
  constexpr double kRotationRounding = 1e-5;
  const std::string at = prefix(camera, where);
  const auto checkFinite = [&](double value, const std::string& what) {
    if (!std::isfinite(value))
      throw InputError(at + what + " is " + formatNumber("%g", value) + ", expected a finite number");
  };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const std::string index = "[" + std::to_string(r) + "][" + std::to_string(c) + "]";
      checkFinite(camera.K[r][c], "K" + index);
      checkFinite(camera.R[r][c], "R" + index);
    }
  for (int i = 0; i < 2; ++i) checkFinite(camera.distortion[i], "distortion[" + std::to_string(i) + "]");
  for (int i = 0; i < 3; ++i) checkFinite(camera.t[i], "t[" + std::to_string(i) + "]");
  // Distances between centres are squared on the way (norms, baselines, rectification tests): beyond
  // 1e100 a square overflows to inf and the tests read NaN as "fine" (a centre at 1e200 crashed the
  // edge alignment, one at 1e300 passed as a rectified rig; issue 24). No scene is that large.
  constexpr double kMaxCoordinate = 1e100;
  for (int i = 0; i < 3; ++i)
    if (std::fabs(camera.t[i]) > kMaxCoordinate)
      throw InputError(at + "t[" + std::to_string(i) + "] (the camera centre) is " + formatNumber("%g", camera.t[i]) +
                       ", expected a coordinate within +-1e100 (distances between cameras would overflow)");

  if (camera.isEquirectangular()) {
    const EquirectangularRange& e = camera.erp;
    const std::string range = "Hor_range [" + formatNumber("%g", e.lonMin) + ", " + formatNumber("%g", e.lonMax) +
                              "], Ver_range [" + formatNumber("%g", e.latMin) + ", " + formatNumber("%g", e.latMax) + "]";
    if (!(e.width > 0 && e.height > 0))
      throw InputError(at + "an equirectangular camera needs its Resolution (width and height in pixels)");
    if (!(std::isfinite(e.lonMin) && std::isfinite(e.lonMax) && e.lonMin < e.lonMax && e.lonMax - e.lonMin <= 360.0 &&
          std::fabs(e.lonMin) <= 360.0 && std::fabs(e.lonMax) <= 360.0))
      throw InputError(at + range + ": expected a longitude range min < max spanning at most 360 degrees, within +-360");
    if (!(e.latMin >= -90.0 && e.latMin < e.latMax && e.latMax <= 90.0))
      throw InputError(at + range + ": expected a latitude range -90 <= min < max <= 90 degrees");
  }
  const Mat3& K = camera.K;
  if (!(K[0][0] > 0.0))
    throw InputError(at + "focal length fx = K[0][0] = " + formatNumber("%.17g", K[0][0]) +
                     ", expected a positive number");
  if (!(K[1][1] > 0.0))
    throw InputError(at + "focal length fy = K[1][1] = " + formatNumber("%.17g", K[1][1]) +
                     ", expected a positive number");
  if (K[2][0] != 0.0 || K[2][1] != 0.0 || K[2][2] != 1.0)
    throw InputError(at + "the last row of K is (" + formatNumber("%.17g", K[2][0]) + ", " +
                     formatNumber("%.17g", K[2][1]) + ", " + formatNumber("%.17g", K[2][2]) + "), expected (0, 0, 1)");
  // With the last row (0, 0, 1), det K is the determinant of the upper 2x2 block.
  const double a = K[0][0] * K[1][1];
  const double b = K[0][1] * K[1][0];
  if (!(std::fabs(a - b) > 1e-12 * std::fmax(std::fabs(a), std::fabs(b))))
    throw InputError(at + "K is singular (fx*fy - K[0][1]*K[1][0] = " + formatNumber("%g", a - b) +
                     "), expected an invertible intrinsic matrix");

  const double deviation = orthonormalityDeviation(camera.R);
  const double det = determinant(camera.R);
  if (!(deviation <= 1e-3) || det < 0.0)
    throw InputError(at + "R is not a rotation matrix: max |R R^T - I| = " + formatNumber("%.3g", deviation) +
                     " (at most 1e-3 allowed), det(R) = " + formatNumber("%.6g", det) + " (expected +1)");
  // Rotations written with 6 or 7 significant digits (open3d, most VSRS camera files) deviate by up
  // to about 1e-6: that is rounding, not a problem worth a line per camera.
  if (deviation > kRotationRounding)
    warnings.push_back(at + "R is a rotation only to within " + formatNumber("%.3g", deviation) +
                       " (max |R R^T - I|); it is used as given, with its exact inverse for camera to world");
  if (camera.distortion[0] != 0.0 || camera.distortion[1] != 0.0)
    warnings.push_back(at + "distortion (" + formatNumber("%g", camera.distortion[0]) + ", " +
                       formatNumber("%g", camera.distortion[1]) + ") is not zero; it is ignored");
}

RelativePose relativePose(const Camera& reference, const Camera& target) {
  RelativePose pose;
  // Differences of centres first: for two cameras near 1e6 this subtraction is exact (or nearly so),
  // and only the small baseline is rotated.
  const Vec3 baseline = reference.t - target.t;
  pose.R = reference.R == target.R ? Mat3::identity() : target.R * inverse(reference.R);
  pose.t = target.R * baseline;
  return pose;
}

}  // namespace vs
