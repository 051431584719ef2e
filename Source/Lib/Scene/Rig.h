#pragma once
// Camera rigs for SceneGen (doc/scenegen.md): a 1D parallel rectified rig, a converging arc rig, and
// helpers to build cameras in the project's convention (../shared/DESIGN.md, "Camera model"):
// x_cam = R (X - t), t the centre, (u, v, 1) ~ K x_cam, axes x right, y down, z forward.
#include <string>
#include <vector>

#include "Common/Camera.h"

namespace vs {

// "cam0", "cam1", ...
std::string rigCameraName(int index);

// K with focal length `focal` (pixels, square pixels, no skew) and principal point (cx, cy).
Mat3 pinholeIntrinsics(double focal, double cx, double cy);

// A camera at `centre` looking at `target`, image rows running along `down` (projected onto the image
// plane; must not be parallel to the viewing direction).
Camera lookAtCamera(const std::string& name, const Mat3& K, const Vec3& centre, const Vec3& target,
                    const Vec3& down = Vec3(0.0, 1.0, 0.0));

// `count` cameras with identity rotation on the world x axis, `baseline` apart, centred on the origin:
// camera i at x = (i - (count - 1) / 2) * baseline. cam0 is the leftmost.
std::vector<Camera> parallelRig(int count, double baseline, const Mat3& K);

// `count` cameras on a horizontal circle of radius `radius` around the point (0, 0, radius), all looking
// at it, `stepDegrees` apart: camera i at angle (i - (count - 1) / 2) * stepDegrees, the angle 0 camera
// at the origin looking along +z. Positive angles are to the right (+x). cam0 is the leftmost.
std::vector<Camera> arcRig(int count, double radius, double stepDegrees, const Mat3& K);

}  // namespace vs
