#pragma once
// SceneGen: renders built-in analytic scenes from a camera rig into multi-view video plus depth with
// exact ground truth, and writes ready ViewSyn and MeshRender configs (doc/scenegen.md).
//
//   SceneGen FILE.cfg [Key=Value ...]    same config syntax and option machinery as ViewSyn
#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/Config.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Scene/RayCaster.h"

namespace vs {

enum class RigType { Parallel, Arc, File };
const char* rigTypeName(RigType rig);

// Every setting of a run. Keys left unset take the chosen scene's value (scenePreset in Scenes.h).
struct SceneGenSettings {
  std::string scene = "demo";  // built-in scene name, or the scene file's name without extension
  std::string sceneFile;       // the scene file it came from; empty: a built-in scene
  std::string description;     // a scene file's Description line
  std::vector<Primitive> objects;  // a scene file's objects; empty: the built-in scene's (buildScene)
  int width = 1024;            // luma samples; even (4:2:0)
  int height = 768;
  int frames = 10;
  double motionScale = 1.0;      // multiplies every object's motion; 0 freezes the scene
  double backgroundDepth = 8.0;  // z of the backdrop (world units; the rig looks along +z)
  double sphereRadius = 0.5;     // `sphere` scene only
  double sphereDepth = 3.0;      // `sphere` scene only: z of the sphere's centre

  RigType rig = RigType::Parallel;
  int cameraCount = 3;          // parallel and arc rigs
  double baseline = 0.1;        // parallel rig: distance between neighbouring camera centres
  double focalLength = 1000.0;  // pixels
  double principalX = std::numeric_limits<double>::quiet_NaN();  // NaN: image centre (width - 1) / 2
  double principalY = std::numeric_limits<double>::quiet_NaN();  // NaN: image centre (height - 1) / 2
  double arcRadius = 4.0;       // arc rig: distance of every camera from the point it looks at
  double arcStepDegrees = 5.0;  // arc rig: angle between neighbouring cameras, seen from that point
  std::string cameraFile;       // file rig: cameras read from this VSRS camera parameter file

  int depthBitDepth = 8;                                    // 8 or 16
  double znear = std::numeric_limits<double>::quiet_NaN();  // NaN: automatic
  double zfar = std::numeric_limits<double>::quiet_NaN();   // NaN: automatic; may be +inf
  double autoDepthMargin = 0.02;  // automatic range: Znear = zmin / (1 + m), Zfar = zmax * (1 + m)

  int samplesPerPixel = 4;  // colour rays per pixel: 1, 4 (rotated grid) or 16
  int threads = 0;          // 0: every core
  std::string outputFolder = "scenegen_out";
  std::string synthesisMode = "0";  // written into the generated ViewSyn configs
};

// Reads the settings: the scene's preset, then every key that is set. Throws InputError listing every
// problem.
SceneGenSettings readSceneGenSettings(const Config& config);

// The cameras of the rig (parallel, arc) or of the camera file, in order (neighbours adjacent).
std::vector<Camera> buildCameras(const SceneGenSettings& settings);

// What a run produced.
struct SceneGenResult {
  std::vector<Camera> cameras;
  DepthRange depthRange;  // the range the depth files are quantised with (also in the configs)
  double trueNearest = std::numeric_limits<double>::infinity();  // smallest rendered depth, any camera, any frame
  double trueFarthest = 0.0;                                     // largest finite rendered depth
  int64_t clampedSamples = 0;  // depth samples outside [Znear, Zfar] (only with a given range)
  int64_t emptySamples = 0;    // pixel centres whose ray hits nothing (written as level 0)
  std::string cameraFile;
  std::vector<std::string> texturePaths;  // per camera
  std::vector<std::string> depthPaths;    // per camera
  std::vector<std::string> viewSynConfigs;
  std::vector<std::string> meshRenderConfigs;
  double seconds = 0.0;
};

// Renders every camera and frame and writes the output folder. Progress lines go to `log`.
SceneGenResult generateScene(const SceneGenSettings& settings, std::ostream& log);

// Texture frame (8-bit 4:2:0, BT.601 limited range) of a rendered view: Y = 16 + 219 Y', Cb = 128 +
// 224 (B' - Y') / 1.772, Cr = 128 + 224 (R' - Y') / 1.402 with Y' = 0.299 R' + 0.587 G' + 0.114 B';
// chroma is the mean of the full-resolution chroma of each 2x2 block (sample sited at its centre).
// Width and height must be even.
void colourToYuv420(const RenderedView& view, Frame& texture);

// Depth frame (4:2:0, range.bitDepth bits, chroma mid-grey) of a rendered view: luma is the depth level
// of the camera-frame z, rounded to nearest (DepthType 0; doc/depth.md); no surface gives level 0.
// Returns how many finite depths fell outside [Znear, Zfar] and were clamped.
int64_t depthToYuv420(const RenderedView& view, const DepthRange& range, Frame& depth);

// SceneGen's option table (doc/scenegen.md lists every key).
OptionTable sceneGenOptionTable();

// The built-in scenes with their preset values, for --help.
std::string sceneListText();

// SceneGen's run(): settings, render, write; prints the effective settings and progress to stdout.
// Returns the exit code; bad input throws InputError.
int runSceneGen(const Config& config);

// The numbers the configs carry, written so that they read back to the identical double ("inf" for
// infinity).
std::string exactNumberText(double value);

}  // namespace vs
