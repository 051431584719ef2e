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
//
// Equirectangular cameras (either side or both; Common/Camera.h): the same homogeneous point, with the
// reference ray d the unit direction of the pixel and w = 1 / distance (an ERP depth is the distance
// along the ray); for an ERP target wv = 1 / distance too. These pairs take a separate, out-of-line
// mapping (forwardSpherical, backwardSpherical) chosen by one flag, so that the pinhole pair's code and
// results stay as they were. Across an ERP triangle wv is interpolated linearly as well: exact at the
// vertices, an approximation inside, as fine as the grid is.
#include <cmath>
#include <cstdint>
#include <limits>

#include "Common/Camera.h"
#include "Common/Geometry.h"
#include "Synth/Interpolation.h"
#include "Synth/Kernels/Rows.h"

namespace vs {

class ViewProjection {
public:
  // `parallel`: the two cameras form a rectified pair (Plan/Rectification.h's checkRectification), so a pixel moves
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
  // An equirectangular camera on either side.
  bool spherical() const { return spherical_; }
  // The virtual camera is equirectangular: the width in its pixels of a whole turn of longitude (its
  // picture's width for a full circle; 0 for a pinhole camera). A point maps within half a turn of the
  // picture's middle, so a triangle whose corners land more than half a turn apart straddles the wrap
  // (or, for a partial circle, the meridian straight behind) and must be drawn a turn to either side.
  double wrapWidth() const { return wrapWidth_; }
  // The reference camera is equirectangular with a full circle: its last column's quads close up
  // with its first column's.
  bool referenceWraps() const { return referenceWraps_; }
  // The virtual camera is equirectangular (wrapWidth() > 0): the row coordinate of
  // its north (top) or south pole, -0.5 or height - 0.5 where the picture reaches it (beyond the
  // picture otherwise), and the inverse depth at which the plane through three warped points (x[i],
  // y[i], wv[i]) meets that pole's ray (the mean of the three where the plane does not meet it in front).
  double poleRow(bool north) const;
  double poleInverseDepth(const double* x, const double* y, const double* wv, bool north) const;
  // How the reference's texture continues beyond its edges (Synth/Interpolation.h): round the wrap for a
  // full circle, and across a pole the picture reaches; nothing (clamped) for a pinhole reference.
  const SphereEdges& referenceSphere() const { return referenceSphere_; }
  // The parallel forms, inline for the 1D path's row loops: the same values forward() and backward()
  // give when parallel(). rowTarget's inverseDepth is the inverse camera depth (DepthType 0).
  double rowTarget(double u, double inverseDepth) const {
    return snapPosition(rowBase(u) + rowDisplacement(inverseDepth));
  }
  // rowTarget's two terms, for a warp that computes the second once per depth level (Synth/RowWarp.h):
  // snapPosition(rowBase(u) + rowDisplacement(w)) is rowTarget(u, w), bit for bit.
  double rowBase(double u) const { return rowScale_ * u + rowOffset_; }
  double rowScale() const { return rowScale_; }    // rowBase(u) is rowScale() * u + rowOffset()
  double rowOffset() const { return rowOffset_; }
  double rowDisplacement(double inverseDepth) const { return rowShift_ * inverseDepth; }
  double rowSource(double x, double wv) const {
    // Dividing by a power of two (rowScale 1 when the focal lengths are equal) is multiplying by its
    // reciprocal, which is exact: the same bits without a division per sample.
    const double shifted = x - rowOffset_ - rowShift_ * wv;
    return snapPosition(rowScaleInverse_ != 0 ? shifted * rowScaleInverse_ : shifted / rowScale_);
  }

  // forward(x, v, inverseDepth[x], ...) for the reference pixels (x, v), x in [0, n): where it
  // succeeds x[x], y[x], wv[x] get its results, elsewhere wv[x] = -1 (x[x] and y[x] are then
  // undefined). A NaN inverse depth fails. For the general projection with DepthType 0 the loop has no
  // branch and vectorises (the same operations in the same order as forward(): the same bits), in a
  // kernel compiled for the CPU's x86-64 level (Synth/Kernels/Rows.h); otherwise it calls forward()
  // sample by sample.
  void forwardRow(const double* inverseDepth, int n, double v, double* x, double* y, double* wv) const;

  // backward(i * step + start, y, wv[i], u[i], v[i]) for i in [0, n), ok[i] = whether it succeeds (u[i]
  // and v[i] undefined where not). For the general projection the loop has no branch and vectorises
  // (the same operations in the same order: the same bits; a kernel, as forwardRow's); the rectified
  // form calls backward().
  void backwardRow(const double* wv, int n, double y, double* u, double* v, uint8_t* ok, int step = 1,
                   double start = 0.0) const;

  // u[i] = rowSource(i * step + start, wv[i]) for every i in [0, n), in a loop without branches that
  // is vectorised (the same operations in the same order: the same bits), compiled for the CPU's
  // x86-64 level (Synth/Kernels/Rows.h).
  void rowSources(const double* wv, int n, double* u, int step = 1, double start = 0.0) const {
    rowKernels().rowSources(rowOffset_, rowShift_, rowScaleInverse_, rowScale_, wv, n, u, step, start);
  }

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
  static constexpr double kMaxPixelRadius = 1e9;  // projections farther than this from pixel (0, 0) are dropped

  bool forwardSpherical(double u, double v, double inverseDepth, double& x, double& y, double& wv) const;
  bool backwardSpherical(double x, double y, double wv, double& u, double& v) const;

  int depthType_;
  bool parallel_;
  bool spherical_ = false;
  double wrapWidth_ = 0;
  bool referenceWraps_ = false;
  SphereEdges referenceSphere_;
  Camera referenceCamera_, targetCamera_;  // spherical only: their pixel <-> ray mappings
  RelativePose pose_;                      // spherical only
  Mat3 poseRotationInverse_;
  double rowScale_ = 1, rowOffset_ = 0, rowShift_ = 0;  // parallel: x = rowScale u + rowOffset + rowShift w
  double rowScaleInverse_ = 1;  // exactReciprocal(rowScale): 1 / rowScale for a power of two, else 0
  Mat3 forwardMatrix_;   // K_tgt R K_ref^-1
  Vec3 forwardOffset_;   // K_tgt t
  Mat3 backwardMatrix_;  // K_ref R^-1 K_tgt^-1
  Vec3 backwardOffset_;  // -K_ref R^-1 t
  Vec3 worldRayZ_;       // row 2 of R_ref^-1 K_ref^-1: D_z = worldRayZ . (u, v, 1)
  double centreZ_;       // C_z of the reference camera
  // The matrices and offsets above as the row kernels take them.
  ProjectionCoefficients forwardRow_{}, backwardRow_{};
};

// forward() and backward() run for every sample: inline, so that they inline into the warps' loops.
inline bool ViewProjection::forward(double u, double v, double inverseDepth, double& x, double& y, double& wv) const {
  if (spherical_) return forwardSpherical(u, v, inverseDepth, x, y, wv);
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
  x = snapPosition(px / pz);
  y = snapPosition(py / pz);
  wv = w / pz;
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(wv);
}

inline void ViewProjection::forwardRow(const double* inverseDepth, int n, double v, double* xs, double* ys,
                                       double* ws) const {
  if (parallel_ || depthType_ != 0 || spherical_) {
    for (int u = 0; u < n; ++u) {
      double x, y, w;
      const bool ok = !std::isnan(inverseDepth[u]) && forward(u, v, inverseDepth[u], x, y, w);
      xs[u] = ok ? x : 0.0;
      ys[u] = ok ? y : 0.0;
      ws[u] = ok ? w : -1.0;
    }
    return;
  }
  // forward() with a = 1 (DepthType 0): a negative or NaN inverse depth fails (a NaN one is refused
  // before forward() is called), 1 * t is t, and the tests are taken on every lane.
  rowKernels().forwardRow(forwardRow_, inverseDepth, n, v, xs, ys, ws);
}

inline void ViewProjection::backwardRow(const double* wv, int n, double y, double* us, double* vs, uint8_t* ok,
                                        int step, double start) const {
  if (parallel_ || spherical_) {
    for (int i = 0; i < n; ++i) ok[i] = uint8_t(backward(double(i * step) + start, y, wv[i], us[i], vs[i]));
    return;
  }
  rowKernels().backwardRow(backwardRow_, wv, n, y, us, vs, ok, step, start);
}

inline bool ViewProjection::backward(double x, double y, double wv, double& u, double& v) const {
  if (spherical_) return backwardSpherical(x, y, wv, u, v);
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
  u = snapPosition(qx / qz);
  v = snapPosition(qy / qz);
  return std::isfinite(u) && std::isfinite(v);
}

}  // namespace vs
