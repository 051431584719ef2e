#pragma once
// MPEG-I camera JSON (as used by RVS and TMIV), read as an alternative to the VSRS camera file and
// written by CameraConvert (user manual: doc/formats-camera.md, "MPEG-I JSON").
//
//   { "cameras": [ { "Name": "v0", "Position": [x, y, z], "Rotation": [yaw, pitch, roll],
//                    "Focal": [fx, fy], "Principle_point": [cx, cy], "Resolution": [w, h],
//                    "Depth_range": [near, far], "Projection": "Perspective",
//                    "BitDepthColor": 8, "BitDepthDepth": 16,
//                    "ColorSpace": "YUV420", "DepthColorSpace": "YUV420" }, ... ] }
//
// Its axes are x forward, y left, z up (OMAF), angles in degrees, and the rotation Rz(yaw) Ry(pitch)
// Rx(roll) maps camera to world. Ours (../shared/DESIGN.md) are x right, y down, z forward with R
// world to camera. With P the axis permutation (ours = P omaf: x = -y', y = -z', z = x'):
//   R = P R_omaf^T P^T,   t = P Position.
// An equirectangular camera has "Projection": "Equirectangular", "Hor_range": [lonMin, lonMax] and
// "Ver_range": [latMin, latMax] (degrees) and a required "Resolution" instead of Focal and
// Principle_point (Camera.h gives the pixel <-> ray mapping; its Depth_range is a distance along rays).
// Its pixel coordinates put the top-left pixel's corner at (0, 0), so its centre is (0.5, 0.5);
// ours put that centre at (0, 0): cx = Principle_point x - 0.5, likewise cy.
#include <string>
#include <vector>

#include "Common/CameraFile.h"

namespace vs {

CameraFile readCameraJson(const std::string& path);
CameraFile parseCameraJson(const std::string& text, const std::string& source);

// Writes cameras (with their infos, same order) as MPEG-I JSON. Throws InputError for a camera the
// format cannot hold (skew, fx != K[0][0] layout not (fx 0 cx; 0 fy cy; 0 0 1)) or an unwritable file.
void writeCameraJson(const std::string& path, const std::vector<Camera>& cameras, const std::vector<CameraInfo>& info);

// The rotation of yaw, pitch, roll (degrees) in our convention, and back. Exposed for tests.
Mat3 rotationFromYawPitchRoll(double yawDegrees, double pitchDegrees, double rollDegrees);
void yawPitchRollFromRotation(const Mat3& R, double& yawDegrees, double& pitchDegrees, double& rollDegrees);

}  // namespace vs
