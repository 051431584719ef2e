#include "Scene/Rig.h"

#include <cmath>

#include "Common/Error.h"

namespace vs {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

std::string rigCameraName(int index) { return "cam" + std::to_string(index); }

Mat3 pinholeIntrinsics(double focal, double cx, double cy) {
  Mat3 K = Mat3::identity();
  K[0][0] = focal;
  K[1][1] = focal;
  K[0][2] = cx;
  K[1][2] = cy;
  return K;
}

Camera lookAtCamera(const std::string& name, const Mat3& K, const Vec3& centre, const Vec3& target, const Vec3& down) {
  const Vec3 forward = target - centre;
  VS_CHECK_MSG(norm(forward) > 0.0, "camera looks at its own centre");
  const Vec3 z = forward / norm(forward);
  const Vec3 xRaw = cross(down, z);
  VS_CHECK_MSG(norm(xRaw) > 1e-12, "camera 'down' direction parallel to the viewing direction");
  const Vec3 x = xRaw / norm(xRaw);
  const Vec3 y = cross(z, x);
  Camera camera;
  camera.name = name;
  camera.K = K;
  for (int c = 0; c < 3; ++c) {
    camera.R[0][c] = x[c];
    camera.R[1][c] = y[c];
    camera.R[2][c] = z[c];
  }
  camera.t = centre;
  return camera;
}

std::vector<Camera> parallelRig(int count, double baseline, const Mat3& K) {
  std::vector<Camera> cameras;
  for (int i = 0; i < count; ++i) {
    Camera camera;
    camera.name = rigCameraName(i);
    camera.K = K;
    camera.R = Mat3::identity();
    // Twice the offset is an integer, so symmetric rigs get exactly opposite centres.
    camera.t = Vec3((2 * i - (count - 1)) * baseline / 2.0, 0.0, 0.0);
    cameras.push_back(camera);
  }
  return cameras;
}

std::vector<Camera> arcRig(int count, double radius, double stepDegrees, const Mat3& K) {
  std::vector<Camera> cameras;
  const Vec3 target(0.0, 0.0, radius);
  for (int i = 0; i < count; ++i) {
    const double angle = (2 * i - (count - 1)) * stepDegrees / 2.0 * (kPi / 180.0);
    const Vec3 centre = target + Vec3(std::sin(angle), 0.0, -std::cos(angle)) * radius;
    Camera camera = lookAtCamera(rigCameraName(i), K, centre, target);
    if (angle == 0.0) {  // exactly the canonical camera, free of rounding
      camera.R = Mat3::identity();
      camera.t = Vec3();
    }
    cameras.push_back(camera);
  }
  return cameras;
}

}  // namespace vs
