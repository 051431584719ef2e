#include "Common/Error.h"
#include "Plan/Rectification.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vs {

namespace {

// Tolerances of a rectified rig: calibration files print 6 to 17 digits.
constexpr double kMaxRotationDegrees = 1e-4;
constexpr double kMaxOffAxis = 1e-6;
constexpr double kMaxFyDifference = 1e-9;
constexpr double kMaxCyDifference = 1e-6;
constexpr double kMaxSkew = 1e-9;


}  // namespace

bool Rectification::rectified() const {
  return rotationDegrees <= kMaxRotationDegrees && offAxis <= kMaxOffAxis && fyDifference <= kMaxFyDifference &&
         cyDifference <= kMaxCyDifference && skew <= kMaxSkew && depthTypeOk &&
         !equirectangular;
}

std::string Rectification::describe() const {
  if (equirectangular)
    return "an equirectangular camera (pixels of an ERP picture do not move along rows by a disparity; "
           "only the general path maps them)";
  std::string text = formatNumber("rotation differs by %.3g deg", rotationDegrees) +
                     formatNumber(", centre off the x axis by %.3g of the baseline", offAxis) +
                     formatNumber(", fy differs by %.3g (relative)", fyDifference) + formatNumber(", cy differs by %.3g px", cyDifference) +
                     formatNumber(", skew %.3g px", skew);
  if (!depthTypeOk) text += ", DepthType 1 with a camera z axis that is not the world z axis";
  return text;
}

Rectification checkRectification(const Camera& reference, const Camera& virtualCamera, int depthType) {
  Rectification r;
  r.equirectangular = reference.isEquirectangular() || virtualCamera.isEquirectangular();
  const RelativePose pose = relativePose(reference, virtualCamera);
  const double trace = pose.R[0][0] + pose.R[1][1] + pose.R[2][2];
  r.rotationDegrees = std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
  const double baseline = norm(pose.t);
  r.offAxis = baseline > 0 ? std::hypot(pose.t.y, pose.t.z) / baseline : 0.0;
  r.fyDifference = std::fabs(reference.K[1][1] - virtualCamera.K[1][1]) / virtualCamera.K[1][1];
  r.cyDifference = std::fabs(reference.K[1][2] - virtualCamera.K[1][2]);
  r.skew = std::max(std::fabs(reference.K[0][1]), std::fabs(virtualCamera.K[0][1]));
  if (depthType == 1) {
    const Vec3 zAxis = reference.R.row(2);
    r.depthTypeOk = zAxis.x == 0 && zAxis.y == 0 && zAxis.z == 1;
  }
  return r;
}

bool rectifiedRig(const Scene& scene) {
  for (const ReferenceView& view : scene.settings.references)
    if (!checkRectification(view.camera, scene.virtualCamera, scene.settings.depthType).rectified()) return false;
  return true;
}

}  // namespace vs
