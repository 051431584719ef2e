#include "Synth/Warp.h"

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
}

}  // namespace vs
