#pragma once
// RVS (MPEG-I Reference View Synthesizer 4.0) synthesis configs: a JSON object naming camera files,
// cameras and sequences, read by ViewSyn and MeshRender in place of a VSRS config (user manual:
// doc/manual.md, "RVS synthesis configs"; the key mapping: doc/formats-camera.md).
//
// A config is recognised by its content (a JSON object), never by its name. It is translated into our
// own keys, one set per virtual camera (RVS writes one output per virtual camera; so do we, in one run),
// so that everything after Config (Scene, Plan, the frame loop, --print-config, Key=Value overrides)
// is the same for both kinds of config. RVS's path rule is kept: file names in an RVS config are used
// as written, so relative names are relative to the working folder (RVS's own configs name
// "config_files/..." and are run from the folder above), not to the config's folder.
//
// Also here: RVS's camera overrides (InputOverrides, VirtualOverrides: camera JSON keys that replace
// those of every camera of that role) and its pose traces (VirtualPoseTraceName).
#include <string>
#include <vector>

#include "Common/CameraFile.h"

namespace vs {

class OptionTable;

// True when `text` is JSON: its first byte that is not blank (after a UTF-8 BOM) is '{' or '['. A
// VSRS config cannot start so (a key is a word); an array is then refused as not an RVS config.
bool looksLikeJsonConfig(const std::string& text);

// One of our keys with its value and where it came from ("rvs.json:12"); `baseDir` is the folder a
// relative path resolves against (RVS: the working folder).
struct TranslatedSetting {
  std::string key;
  std::string value;
  std::string where;
  std::string baseDir;
};

// Translates the RVS config `text` (read from `path`) into our keys for `table`: one list per virtual
// camera, in VirtualCameraNames order. Reads the camera files it names (with their overrides) for the
// formats and depth ranges. Throws InputError naming the file, the line and the key for every problem
// found (unknown keys, values we cannot honour, lists of the wrong length, cameras that do not fit
// together), all at once.
std::vector<std::vector<TranslatedSetting>> translateRvsConfig(const std::string& text, const std::string& path,
                                                               const OptionTable& table);

// The camera file `path` with `overrides` (a JSON object of camera keys, as InputOverrides; empty: none)
// replacing those keys in every camera; VSRS text files take no overrides. `key` names the overrides
// in messages.
CameraFile readCameraFileWithOverrides(const std::string& path, RotationConvention convention,
                                       const std::string& overrides, const std::string& key);

// One row of an RVS pose trace (CSV with the header "X, Y, Z, Yaw, Pitch, Roll"): a position in MPEG-I
// axes (metres) and yaw, pitch, roll in degrees.
struct Pose {
  double x = 0, y = 0, z = 0;
  double yaw = 0, pitch = 0, roll = 0;
};

// Reads a pose trace; throws InputError "file:line: ..." for a wrong header, a row without six numbers
// or a row after blank lines. Blank lines at the end are allowed.
std::vector<Pose> readPoseTrace(const std::string& path);
std::vector<Pose> parsePoseTrace(const std::string& text, const std::string& source);

// The camera `base` moved by `pose` as RVS moves its virtual camera: the pose's position is added to
// the camera's (MPEG-I axes), and its yaw, pitch and roll replace the camera's rotation.
Camera posedCamera(const Camera& base, const Pose& pose);

}  // namespace vs
