#pragma once
// Reader and writer of VSRS camera parameter files (user manual: doc/formats-camera.md).
//
// A file is a sequence of blocks: a line holding one token (the camera name) followed by exactly 23
// numbers spread over lines in any way: K (3x3, row major), two distortion values, then three rows
// "r r r t". '#' starts a comment anywhere; CRLF, tabs and blank lines are fine. Lines of several
// tokens outside a block are header lines: skipped, with a warning.
#include <string>
#include <vector>

#include "Common/Camera.h"

namespace vs {

// What an MPEG-I camera JSON says about a camera beyond the pinhole model (a VSRS text file says
// none of it: every field is then unset).
struct CameraInfo {
  bool hasDepthRange = false;
  double znear = 0, zfar = 0;  // Depth_range; zfar may be +inf
  int bitDepthColor = 0;       // 0: not given
  int bitDepthDepth = 0;
  int width = 0, height = 0;   // Resolution; 0: not given
  std::string colorSpace, depthColorSpace;  // "YUV420", "YUV400", ...
};

class CameraFile {
public:
  CameraFile() = default;
  CameraFile(std::string path, std::vector<Camera> cameras, std::vector<std::string> warnings);
  CameraFile(std::string path, std::vector<Camera> cameras, std::vector<CameraInfo> info, std::vector<std::string> warnings);
  // Per-camera extras, same order as cameras(); unset fields for VSRS text files.
  const CameraInfo& info(const std::string& name) const;

  // In file order of first appearance; a name defined twice holds its last definition.
  const std::vector<Camera>& cameras() const { return cameras_; }
  bool contains(const std::string& name) const;
  // Throws InputError naming the file and listing every camera name it has when `name` is missing.
  const Camera& find(const std::string& name) const;
  // Non-fatal notes: skipped header lines, redefined names, rotations that are only nearly
  // orthonormal, non-zero distortion.
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& path() const { return path_; }

private:
  std::string path_;
  std::vector<Camera> cameras_;
  std::vector<CameraInfo> info_;
  std::vector<std::string> warnings_;
};

// Reads and validates (validateCamera) every camera of a file; a name ending in ".json" is read as an
// MPEG-I camera JSON (CameraJson.h), anything else as the VSRS text format. Throws InputError "<file>:<line>: ..."
// for a block with fewer than 23 numbers, a token that is not a finite number where a number is
// expected, a name line inside a block, numbers left over after a block, a file without any camera,
// and for every camera validateCamera refuses.
CameraFile readCameraFile(const std::string& path, RotationConvention convention = RotationConvention::WorldToCamera);

// The same parser on text already in memory; `sourceName` stands for the file name in messages.
CameraFile parseCameraText(const std::string& text, const std::string& sourceName,
                           RotationConvention convention = RotationConvention::WorldToCamera);

// Writes the cameras in the VSRS 4.x layout (R world to camera) with the shortest decimal form that
// reads back to the identical double, so write -> read is exact. Throws InputError when the file
// cannot be written, a name is not one token free of '#', a number is not finite, or a camera is
// equirectangular (the VSRS format knows pinhole cameras only; MPEG-I JSON holds both).
void writeCameraFile(const std::string& path, const std::vector<Camera>& cameras);

// One camera block exactly as writeCameraFile writes it (name line, then 8 lines of numbers), for
// printing and logs.
std::string formatCamera(const Camera& camera);

}  // namespace vs
