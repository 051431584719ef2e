#pragma once
// Geometry of warping one reference view into the virtual camera (doc/algorithms.md, "Warping").
//
// Points are handled in homogeneous form so that infinite depth (Zfar = inf, or a DepthType 1 range
// whose 1/Z crosses zero) needs no special case: a reference pixel (u, v) with inverse depth value w
// is the camera-frame point (a d, w) ~ a d / w, where d = K_ref^-1 (u, v, 1) and a = 1 for DepthType 0
// (Z is the camera z) or a = (1 - w C_z) / D_z for DepthType 1 (Z is the world z; C the camera centre,
// D = R_ref^-1 d the world ray). The sign is normalised so that w >= 0; the point is in front of the
// reference camera iff a > 0.
//
// Depth is carried as the inverse virtual-camera depth wv = 1 / z_virtual: larger is nearer, 0 is
// infinitely far, and it interpolates linearly across a planar triangle in screen space.
#include <cmath>

#include "Common/Camera.h"
#include "Common/Geometry.h"

namespace vs {

class ViewProjection {
public:
  // `parallel`: the two cameras form a rectified pair (Plan.h's checkRectification), so a pixel moves
  // along its row only: x = s u + o + f_x b w, with the same inverse depth in both cameras. The
  // general formulas give the same result; this form is a multiply-add per pixel.
  ViewProjection(const Camera& reference, const Camera& target, int depthType, bool parallel = false);

  // Reference pixel (u, v) with depth value Z given as inverseDepth = 1/Z (DepthType's Z) -> target
  // pixel (x, y) and inverse target depth wv. False when the point is behind (or on the plane of)
  // either camera, or its ray is parallel to the DepthType 1 plane.
  bool forward(double u, double v, double inverseDepth, double& x, double& y, double& wv) const;
  // Target pixel (x, y) with inverse target depth wv >= 0 -> reference pixel (u, v). False when the
  // point is not in front of the reference camera.
  bool backward(double x, double y, double wv, double& u, double& v) const;

  bool parallel() const { return parallel_; }
  // The parallel forms, inline for the 1D path's row loops: the same values forward() and backward()
  // give when parallel(). rowTarget's inverseDepth is the inverse camera depth (DepthType 0).
  double rowTarget(double u, double inverseDepth) const {
    return snapPosition(rowScale_ * u + rowOffset_ + rowShift_ * inverseDepth);
  }
  double rowSource(double x, double wv) const { return snapPosition((x - rowOffset_ - rowShift_ * wv) / rowScale_); }

  // Pixel positions are kept to 2^-30 px (1e-9), far finer than the quarter pel the filters resolve.
  // Rounding off the last bits makes positions that are mathematically equal bit-equal too, so that a
  // change of units or of world origin (which perturbs the last bits) cannot flip a rounding decision
  // at a tie, such as a warped sample landing exactly between two pixel centres.
  static double snapPosition(double position) {
    // 2^30 and 2^-30: scaling by a power of two is exact, so multiplying by 2^-30 gives what dividing
    // by 2^30 gives, bit for bit (both round the same real number), at a fraction of the cost.
    constexpr double grid = 1073741824.0, cell = 1.0 / 1073741824.0;
    return std::nearbyint(position * grid) * cell;
  }

private:
  int depthType_;
  bool parallel_;
  double rowScale_ = 1, rowOffset_ = 0, rowShift_ = 0;  // parallel: x = rowScale u + rowOffset + rowShift w
  Mat3 forwardMatrix_;   // K_tgt R K_ref^-1
  Vec3 forwardOffset_;   // K_tgt t
  Mat3 backwardMatrix_;  // K_ref R^-1 K_tgt^-1
  Vec3 backwardOffset_;  // -K_ref R^-1 t
  Vec3 worldRayZ_;       // row 2 of R_ref^-1 K_ref^-1: D_z = worldRayZ . (u, v, 1)
  double centreZ_;       // C_z of the reference camera
};

}  // namespace vs
