#include "Synth/Warp.h"

#include <cmath>

namespace vs {

namespace {

constexpr double kMaxPixelRadius = 1e9;  // projections farther than this from pixel (0, 0) are dropped

inline double snap(double position) { return ViewProjection::snapPosition(position); }

}  // namespace

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
  if (parallel_) {
    // x_tgt = x_ref + (b, 0, 0) with b = pose.t.x; u_tgt = fx_t (X_ref + b) / Z + cx_t.
    rowScale_ = target.K[0][0] / reference.K[0][0];
    rowOffset_ = target.K[0][2] - rowScale_ * reference.K[0][2];
    rowShift_ = target.K[0][0] * pose.t.x;
  }
}

bool ViewProjection::forward(double u, double v, double inverseDepth, double& x, double& y, double& wv) const {
  if (parallel_) {
    // DepthType 1 here has the camera z axis along world z (checked by the plan): z_cam = Z - C_z.
    const double w = depthType_ == 1 ? inverseDepth / (1.0 - centreZ_ * inverseDepth) : inverseDepth;
    if (!(w >= 0.0) || !std::isfinite(w)) return false;
    x = rowTarget(u, w);
    y = v;
    wv = w;
    return std::isfinite(x);
  }
  double a = 1.0, w = inverseDepth;
  if (depthType_ == 1) {
    const double rayZ = worldRayZ_.x * u + worldRayZ_.y * v + worldRayZ_.z;
    if (rayZ == 0.0) return false;
    a = (1.0 - w * centreZ_) / rayZ;
  }
  if (w < 0.0) {
    a = -a;
    w = -w;
  }
  if (!(a > 0.0)) return false;  // behind the reference camera (or NaN)
  const Mat3& m = forwardMatrix_;
  const double px = a * (m[0][0] * u + m[0][1] * v + m[0][2]) + forwardOffset_.x * w;
  const double py = a * (m[1][0] * u + m[1][1] * v + m[1][2]) + forwardOffset_.y * w;
  const double pz = a * (m[2][0] * u + m[2][1] * v + m[2][2]) + forwardOffset_.z * w;
  // Behind the target camera, never wrapped around to the front; and a point (numerically) on its image
  // plane projects beyond 1e9 pixels: not drawn either, or its triangles would cover the whole view.
  if (!(pz > 0.0) || std::fabs(px) > kMaxPixelRadius * pz || std::fabs(py) > kMaxPixelRadius * pz) return false;
  x = snap(px / pz);
  y = snap(py / pz);
  wv = w / pz;
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(wv);
}

bool ViewProjection::backward(double x, double y, double wv, double& u, double& v) const {
  if (parallel_) {
    u = rowSource(x, wv);
    v = y;
    return std::isfinite(u);
  }
  const Mat3& m = backwardMatrix_;
  const double qx = m[0][0] * x + m[0][1] * y + m[0][2] + backwardOffset_.x * wv;
  const double qy = m[1][0] * x + m[1][1] * y + m[1][2] + backwardOffset_.y * wv;
  const double qz = m[2][0] * x + m[2][1] * y + m[2][2] + backwardOffset_.z * wv;
  if (!(qz > 0.0) || std::fabs(qx) > kMaxPixelRadius * qz || std::fabs(qy) > kMaxPixelRadius * qz) return false;
  u = snap(qx / qz);
  v = snap(qy / qz);
  return std::isfinite(u) && std::isfinite(v);
}

}  // namespace vs
