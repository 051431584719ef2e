#pragma once
// Depth levels <-> depth values (user manual: doc/depth.md; ../shared/DESIGN.md, "Depth").
//
// A depth sample is a level L in [0, Lmax], Lmax = 2^bitDepth - 1, larger L nearer:
//   1/Z = (L / Lmax) (1/Znear - 1/Zfar) + 1/Zfar        with 1/inf = 0, so Zfar may be +inf.
// What Z is depends on DepthType: 0, the z coordinate in the camera's own frame; 1, the world z
// coordinate of the point (the pixel's ray meets the world plane z = Z).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/Frame.h"
#include "Common/Geometry.h"

namespace vs {

constexpr int kDepthTypeCamera = 0;  // DepthType 0: Z is the camera-frame z (VSRS "depth from camera")
constexpr int kDepthTypeWorld = 1;   // DepthType 1: Z is the world z coordinate ("from the origin")

// Unset values are NaN, which validateDepthRange refuses.
struct DepthRange {
  double znear = std::numeric_limits<double>::quiet_NaN();  // Z of level Lmax
  double zfar = std::numeric_limits<double>::quiet_NaN();   // Z of level 0; may be +inf
  int bitDepth = 8;                                         // bits per depth sample, 8 to 16
};

// 2^bitDepth - 1.
int maxDepthLevel(const DepthRange& range);

// Throws one InputError listing every problem: bit depth outside 8..16, DepthType other than 0 or 1,
// non-finite Znear, Zfar NaN or -inf, Znear == Zfar, Znear or Zfar equal to 0, and with DepthType 0
// Znear <= 0, Zfar <= 0 or Znear > Zfar. With DepthType 1 negative values are allowed. Messages name
// the config keys keyPrefix + "NearestDepthValue" and keyPrefix + "FarthestDepthValue" (VSRS uses
// the prefixes "Left" and "Right").
void validateDepthRange(const DepthRange& range, int depthType, const std::string& keyPrefix);

// 1/Z of a level (continuous; levels outside [0, Lmax] extrapolate). Exactly 1/Zfar at 0 and 1/Znear
// at Lmax.
double levelToInverseZ(double level, const DepthRange& range);
// Z of a level. Returns +inf where 1/Z is 0 (level 0 with Zfar = inf, or the level where a DepthType 1
// range with Znear and Zfar of opposite signs crosses infinity): callers must handle it, for instance
// by warping with 1/Z. Exactly Zfar at 0 and Znear at Lmax.
double levelToZ(double level, const DepthRange& range);
// The continuous, unclamped level of a depth value: the inverse of levelToZ. Z = +inf gives the level
// of 1/Z = 0.
double zToLevel(double z, const DepthRange& range);
// zToLevel rounded to the nearest integer and clamped to [0, Lmax]; NaN gives 0.
int zToLevelRounded(double z, const DepthRange& range);

// levelToInverseZ for every level 0..Lmax (256 entries at 8 bits, 65536 at 16), for per-pixel lookup.
std::vector<double> inverseZTable(const DepthRange& range);

// The camera-frame z of the point a depth value describes on pixel (u, v)'s ray. DepthType 0: the
// value itself. DepthType 1: the ray is intersected with the world plane z = depthValue. ok is false
// when the ray is parallel to that plane, the point is behind the camera or on its plane, or the value
// is NaN. An infinite value is returned as +inf with ok true when that infinity lies in front of the
// camera (DepthType 0: +inf; DepthType 1: the ray heads towards that infinite z).
double depthToCameraZ(const Camera& camera, double u, double v, double depthValue, int depthType, bool& ok);

// The world point a depth value describes on pixel (u, v)'s ray (see depthToCameraZ). With DepthType 1
// the result's z is exactly depthValue. ok is false (and the result meaningless) where depthToCameraZ
// fails and for infinite depth, which has no finite world point.
Vec3 backProjectDepth(const Camera& camera, double u, double v, double depthValue, int depthType, bool& ok);

// MissingDepthFill 1 (doc/algorithms.md, "Depth"): in a copy of `depth`, every run of
// `missingLevel` samples along a row that has a valid sample at both ends takes the level of the
// farther end (the smaller of the two 1/Z in `inverseZ`, the map's level table): a sample one camera
// saw without a depth is mostly background its neighbour hid from the other camera. Then the same
// along the columns for what is still missing. Runs that reach the picture's border both ways keep
// the missing level. `filled` (same size) marks the samples given a level. Returns their number.
size_t fillMissingDepthRuns(const Plane& depth, int missingLevel, const std::vector<double>& inverseZ, Plane& out,
                            std::vector<uint8_t>& filled);

}  // namespace vs
