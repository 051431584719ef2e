#pragma once
// Pinhole camera model (../shared/DESIGN.md, "Camera model"; user manual: doc/formats-camera.md).
//
//   x_cam = R (X - t)          R rotates world to camera, t is the camera centre in world coordinates
//   (u, v, 1)^T ~ K x_cam      integer (u, v) are pixel centres, u the column, v the row, origin top-left
//
// All math is double. Where the model needs R^-1 (camera to world) we use the true inverse of R, not
// R^T: rotations read from 6-digit files are orthonormal only to about 1e-6, and the inverse keeps a
// camera consistent with itself (back-projecting a pixel and projecting it again gives the same pixel).
#include <string>
#include <vector>

#include "Common/Geometry.h"

namespace vs {

// How the rotation matrix in a camera file is to be read.
enum class RotationConvention {
  WorldToCamera,  // VSRS 4.x and this project (default): R maps world to camera coordinates
  CameraToWorld,  // VSRS 3.5: R in the file maps camera to world, so it is transposed when read
};

struct Camera {
  std::string name;
  Mat3 K = Mat3::identity();          // intrinsics; K[0][1] is skew, row 2 must be (0, 0, 1)
  double distortion[2] = {0.0, 0.0};  // read and written, otherwise ignored
  Mat3 R = Mat3::identity();          // world -> camera rotation
  Vec3 t;                             // camera centre in world coordinates

  Vec3 centre() const { return t; }

  Vec3 worldToCamera(const Vec3& X) const;   // R (X - t)
  Vec3 cameraToWorld(const Vec3& xc) const;  // R^-1 xc + t

  // Camera frame <-> pixel. pixelToCamera gives the point on the pixel's ray at camera depth zCam;
  // cameraToPixel returns false (u, v untouched) when xc.z <= 0.
  Vec3 pixelToCamera(double u, double v, double zCam) const;
  bool cameraToPixel(const Vec3& xc, double& u, double& v) const;

  // World point -> pixel. zCam is always set (the camera-frame z); returns false when zCam <= 0 (the
  // point is behind the camera or on its plane), in which case u and v are left untouched.
  bool project(const Vec3& X, double& u, double& v, double& zCam) const;
  // The world point at camera depth zCam on pixel (u, v)'s ray. Handles skew.
  Vec3 backProject(double u, double v, double zCam) const;
  // Unit direction, in world coordinates, of the ray from the centre through pixel (u, v), pointing
  // forward (towards positive camera z).
  Vec3 rayDirectionWorld(double u, double v) const;
};

// R becomes R^T for RotationConvention::CameraToWorld; nothing happens for WorldToCamera.
void applyRotationConvention(Camera& camera, RotationConvention convention);

// Checks a camera read from outside. Throws InputError ("<where>: camera '<name>': ...") for
// non-finite numbers, fx or fy <= 0, a K whose last row is not (0, 0, 1), a singular K, and an R that
// is not a rotation (max |R R^T - I| > 1e-3 or det(R) < 0). Appends one warning for an R that is a
// rotation only to within 1e-3 (deviation > 1e-9) and one for non-zero distortion (ignored).
void validateCamera(const Camera& camera, const std::string& where, std::vector<std::string>& warnings);

// Rigid transform from reference-camera coordinates to target-camera coordinates:
//   x_tgt = R x_ref + t,  R = R_tgt R_ref^-1,  t = R_tgt (t_ref - t_tgt).
// The centre difference is taken first, so a large common world offset cancels exactly before it
// costs precision. Cameras with bitwise equal rotations get R = identity exactly, and a camera paired
// with itself gets the exact identity transform.
struct RelativePose {
  Mat3 R = Mat3::identity();
  Vec3 t;

  Vec3 apply(const Vec3& xRef) const { return R * xRef + t; }
};

RelativePose relativePose(const Camera& reference, const Camera& target);

}  // namespace vs
