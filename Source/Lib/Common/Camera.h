#pragma once
// Camera model (../shared/DESIGN.md, "Camera model"; user manual: doc/formats-camera.md): a pinhole
// camera, or an equirectangular (ERP) one, the 360-degree projection of MPEG-I content.
//
//   x_cam = R (X - t)          R rotates world to camera, t is the camera centre in world coordinates
//   (u, v, 1)^T ~ K x_cam      integer (u, v) are pixel centres, u the column, v the row, origin top-left
//
// All math is double. Where the model needs R^-1 (camera to world) we use the true inverse of R, not
// R^T: rotations read from 6-digit files are orthonormal only to about 1e-6, and the inverse keeps a
// camera consistent with itself (back-projecting a pixel and projecting it again gives the same pixel).
//
// Equirectangular cameras (Projection::Equirectangular) share R and t; K is unused (identity). In our
// camera axes (x right, y down, z forward) the ray of longitude phi and latitude theta is
//   d = (-cos(theta) sin(phi), -sin(theta), cos(theta) cos(phi))
// which is MPEG's (x forward, y left, z up) (cos(theta) cos(phi), cos(theta) sin(phi), sin(theta)):
// longitude grows to the left, latitude upwards. Pixel centres (integer u, v) sit at
//   phi = lonMax - (u + 0.5) (lonMax - lonMin) / width,  theta = latMax - (v + 0.5) (latMax - latMin) / height
// so column 0 starts at lonMax (the left edge) and row 0 at latMax (the top). An ERP camera's depth is
// the distance from the centre along the ray, not z: "depth" below means camera z for a pinhole camera
// and that distance for an ERP one.
#include <string>
#include <vector>

#include "Common/Geometry.h"

namespace vs {

// How the rotation matrix in a camera file is to be read.
enum class RotationConvention {
  WorldToCamera,  // VSRS 4.x and this project (default): R maps world to camera coordinates
  CameraToWorld,  // VSRS 3.5: R in the file maps camera to world, so it is transposed when read
};

enum class Projection { Perspective, Equirectangular };

// The picture and the angles an equirectangular camera covers (degrees, as MPEG's Hor_range and
// Ver_range): lonMin < lonMax, lonMax - lonMin <= 360; -90 <= latMin < latMax <= 90.
struct EquirectangularRange {
  int width = 0, height = 0;
  double lonMin = -180, lonMax = 180;
  double latMin = -90, latMax = 90;

  // Whether the columns close up around the sphere (a 360-degree longitude range): the last column's
  // right edge is the first column's left edge.
  bool wraps() const { return lonMax - lonMin >= 360.0; }
  bool operator==(const EquirectangularRange& o) const {
    return width == o.width && height == o.height && lonMin == o.lonMin && lonMax == o.lonMax && latMin == o.latMin &&
           latMax == o.latMax;
  }
};

struct Camera {
  std::string name;
  Projection projection = Projection::Perspective;
  EquirectangularRange erp;           // Equirectangular only
  Mat3 K = Mat3::identity();          // intrinsics; K[0][1] is skew, row 2 must be (0, 0, 1)
  double distortion[2] = {0.0, 0.0};  // read and written, otherwise ignored
  Mat3 R = Mat3::identity();          // world -> camera rotation
  Vec3 t;                             // camera centre in world coordinates

  Vec3 centre() const { return t; }
  bool isEquirectangular() const { return projection == Projection::Equirectangular; }

  Vec3 worldToCamera(const Vec3& X) const;   // R (X - t)
  Vec3 cameraToWorld(const Vec3& xc) const;  // R^-1 xc + t

  // Camera frame <-> pixel. pixelToCamera gives the point on the pixel's ray at depth zCam (camera z,
  // or for ERP the distance); cameraToPixel returns false (u, v untouched) when xc.z <= 0 (pinhole) or
  // xc is the centre itself (ERP). An ERP point maps to the longitude nearest the range's middle: for
  // a partial range a point outside it lands outside [-0.5, width - 0.5) on the side it is closer to;
  // for a full circle u is in [-0.5, width - 0.5).
  Vec3 pixelToCamera(double u, double v, double zCam) const;
  bool cameraToPixel(const Vec3& xc, double& u, double& v) const;
  // The camera-frame ray of pixel (u, v): K^-1 (u, v, 1) (z = 1) for a pinhole camera, the unit
  // direction for ERP; pixelToCamera(u, v, d) is rayCamera(u, v) * d.
  Vec3 rayCamera(double u, double v) const;
  // The depth of camera-frame point xc in this camera's measure: xc.z, or |xc| for ERP.
  double depthOf(const Vec3& xc) const;

  // World point -> pixel. zCam is always set (depthOf the camera-frame point); returns false when the
  // point cannot be projected (cameraToPixel), in which case u and v are left untouched.
  bool project(const Vec3& X, double& u, double& v, double& zCam) const;
  // The world point at depth zCam on pixel (u, v)'s ray. Handles skew.
  Vec3 backProject(double u, double v, double zCam) const;
  // Unit direction, in world coordinates, of the ray from the centre through pixel (u, v), pointing
  // forward (towards positive camera z).
  Vec3 rayDirectionWorld(double u, double v) const;
};

// R becomes R^T for RotationConvention::CameraToWorld; nothing happens for WorldToCamera.
void applyRotationConvention(Camera& camera, RotationConvention convention);

// Checks a camera read from outside. Throws InputError ("<where>: camera '<name>': ...") for non-finite
// numbers, fx or fy <= 0, a K whose last row is not (0, 0, 1), a singular K, an R that is not a
// rotation (max |R R^T - I| > 1e-3 or det(R) < 0), and for ERP a missing picture size or a range
// outside the limits of EquirectangularRange. Appends one warning for an R that is a rotation only to
// within 1e-3 (deviation > 1e-9) and one for non-zero distortion (ignored).
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
