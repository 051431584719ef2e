#include "Synth/Warp.h"

#include "Common/Error.h"
#include "Synth/ExactDivision.h"

namespace vs {

ViewProjection::ViewProjection(const Camera& reference, const Camera& target, int depthType, bool parallel)
    : depthType_(depthType), parallel_(parallel) {
  const RelativePose pose = relativePose(reference, target);
  const Mat3 referenceKInverse = inverse(reference.K);
  const Mat3 targetKInverse = inverse(target.K);
  const Mat3 rotationInverse = inverse(pose.R);
  forwardMatrix_ = target.K * pose.R * referenceKInverse;
  forwardOffset_ = target.K * pose.t;
  backwardMatrix_ = reference.K * rotationInverse * targetKInverse;
  backwardOffset_ = -(reference.K * (rotationInverse * pose.t));
  worldRayZ_ = (inverse(reference.R) * referenceKInverse).row(2);
  centreZ_ = reference.t.z;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      forwardRow_.m[r][c] = forwardMatrix_[r][c];
      backwardRow_.m[r][c] = backwardMatrix_[r][c];
    }
  }
  forwardRow_.o[0] = forwardOffset_.x;
  forwardRow_.o[1] = forwardOffset_.y;
  forwardRow_.o[2] = forwardOffset_.z;
  backwardRow_.o[0] = backwardOffset_.x;
  backwardRow_.o[1] = backwardOffset_.y;
  backwardRow_.o[2] = backwardOffset_.z;
  if (parallel_) {
    // x_tgt = x_ref + (b, 0, 0) with b = pose.t.x; u_tgt = fx_t (X_ref + b) / Z + cx_t.
    rowScale_ = target.K[0][0] / reference.K[0][0];
    rowOffset_ = target.K[0][2] - rowScale_ * reference.K[0][2];
    rowShift_ = target.K[0][0] * pose.t.x;
    rowScaleInverse_ = exactReciprocal(rowScale_);
  }
  if (reference.isEquirectangular() || target.isEquirectangular()) {
    VS_CHECK(!parallel_ && depthType_ == 0);  // the plan refuses both for ERP cameras
    spherical_ = true;
    referenceCamera_ = reference;
    targetCamera_ = target;
    pose_ = pose;
    poseRotationInverse_ = rotationInverse;
    if (target.isEquirectangular())
      wrapWidth_ = target.erp.wraps() ? double(target.erp.width)
                                      : target.erp.width * 360.0 / (target.erp.lonMax - target.erp.lonMin);
    referenceWraps_ = reference.isEquirectangular() && reference.erp.wraps();
    // Across a pole lies the same picture half a turn round: only with a full circle of longitudes.
    referenceSphere_.wrap = referenceWraps_;
    referenceSphere_.north = referenceSphere_.wrap && reference.erp.latMax >= 90.0;
    referenceSphere_.south = referenceSphere_.wrap && reference.erp.latMin <= -90.0;
  }
}

bool ViewProjection::forwardSpherical(double u, double v, double inverseDepth, double& x, double& y, double& wv) const {
  // The point (d, w) ~ d / w in reference coordinates, d the pixel's ray: the unit direction (ERP,
  // w = 1 / distance) or K^-1 (u, v, 1) (pinhole, w = 1 / z). In target coordinates (R d + t w, w).
  const double w = inverseDepth;
  if (!(w >= 0.0)) return false;
  const Vec3 p = pose_.R * referenceCamera_.rayCamera(u, v) + pose_.t * w;
  const double depth = targetCamera_.depthOf(p);  // the target's depth of the point, times w
  if (!(depth > 0.0)) return false;
  double px, py;
  if (!targetCamera_.cameraToPixel(p, px, py)) return false;
  if (!(std::fabs(px) <= kMaxPixelRadius && std::fabs(py) <= kMaxPixelRadius)) return false;
  x = snapPosition(px);
  y = snapPosition(py);
  wv = w / depth;
  return std::isfinite(wv);
}

bool ViewProjection::backwardSpherical(double x, double y, double wv, double& u, double& v) const {
  if (!(wv >= 0.0)) return false;
  // The target pixel's point (d_t, wv) ~ d_t / wv; in reference coordinates (R^-1 (d_t - t wv), wv).
  const Vec3 q = poseRotationInverse_ * (targetCamera_.rayCamera(x, y) - pose_.t * wv);
  double qu, qv;
  if (!referenceCamera_.cameraToPixel(q, qu, qv)) return false;
  if (!(std::fabs(qu) <= kMaxPixelRadius && std::fabs(qv) <= kMaxPixelRadius)) return false;
  u = snapPosition(qu);
  v = snapPosition(qv);
  return true;
}

double ViewProjection::poleRow(bool north) const {
  const EquirectangularRange& e = targetCamera_.erp;
  const double pole = north ? 90.0 : -90.0;
  return (e.latMax - pole) * e.height / (e.latMax - e.latMin) - 0.5;
}

double ViewProjection::poleInverseDepth(const double* x, const double* y, const double* wv, bool north) const {
  const double mean = (wv[0] + wv[1] + wv[2]) / 3.0;
  if (!(wv[0] > 0.0 && wv[1] > 0.0 && wv[2] > 0.0)) return mean;  // a corner infinitely far
  Vec3 corner[3];
  for (int i = 0; i < 3; ++i) corner[i] = targetCamera_.rayCamera(x[i], y[i]) * (1.0 / wv[i]);
  const Vec3 normal = cross(corner[1] - corner[0], corner[2] - corner[0]);
  const Vec3 pole(0.0, north ? -1.0 : 1.0, 0.0);  // our camera axes: y points down
  const double along = dot(normal, corner[0]) / dot(normal, pole);  // the distance where the ray meets the plane
  return along > 0.0 && std::isfinite(along) ? 1.0 / along : mean;
}

}  // namespace vs
