#pragma once
// Whether the rig is rectified: every reference camera forms a rectified pair with the virtual camera,
// so a pixel moves along its row by a disparity that depends on its depth only (the 1D path), and
// disocclusions lie along rows (hole filling by row runs).
#include <string>

#include "Common/Scene.h"

namespace vs {

// How far a reference camera is from forming a rectified pair with the virtual camera.
struct Rectification {
  double rotationDegrees = 0;  // angle of R_ref R_virtual^-1
  double offAxis = 0;          // |(y, z)| of the centre offset in the virtual camera frame, relative to |offset|
  double fyDifference = 0;     // |fy_ref - fy_virtual| / fy_virtual
  double cyDifference = 0;     // |cy_ref - cy_virtual| in pixels
  double skew = 0;             // largest |K[0][1]| of the two cameras, pixels
  bool depthTypeOk = true;     // DepthType 1 maps to camera depth only when the camera z axis is world z
  // An equirectangular camera on either side: its rows are circles of latitude, and a point's
  // displacement between two ERP (or ERP and pinhole) pictures is not a shift along a row by a
  // function of depth, however the cameras are placed. Never rectified.
  bool equirectangular = false;
  bool rectified() const;
  std::string describe() const;  // "rotation 0.3 deg, centre off the x axis by 2%, ..."
};

Rectification checkRectification(const Camera& reference, const Camera& virtualCamera, int depthType);

// Every reference camera forms a rectified pair with the virtual camera.
bool rectifiedRig(const Scene& scene);

}  // namespace vs
