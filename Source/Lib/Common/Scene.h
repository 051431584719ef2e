#pragma once
// The scene a synthesizer works on, read from a Config: typed settings, the cameras from the camera
// file, the reference views and the virtual view. Everything ViewSyn and MeshRender share up to the
// frame loop (../shared/DESIGN.md, "Data flow").
#include <cstdint>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/Config.h"
#include "Common/Depth.h"
#include "Common/Frame.h"

namespace vs {

enum class SynthesisMode { General, Parallel1D, Auto };
const char* synthesisModeName(SynthesisMode mode);

// VSRS's 1D-mode options, with VSRS's meaning (doc/manual.md).
struct OneDOptions {
  int splatting = 2;            // 0 off, 1 every pixel, 2 near depth boundaries only
  int boundaryGrowth = 40;      // pixels a boundary area grows by (splatting 2)
  int merging = 2;              // 0 z-buffer, 1 averaging, 2 adaptive
  int depthThreshold = -1;      // 8-bit depth levels within which views are mixed (merging 2); -1: DepthBlendDifference
  int holeCountThreshold = 30;  // (merging 2)
  bool temporalImprovement = true;
  bool warpEnhancement = true;
  bool cleanNoise = false;
};

constexpr size_t kMaxReferenceViews = 32;  // RVS's own configs name up to 24 input cameras

struct ReferenceView {
  std::string label;          // "Left", "Right" or "Reference k": for messages
  std::string cameraName;
  std::string texturePath;
  std::string depthPath;
  DepthRange depthRange;      // Znear, Zfar and bit depth of this view's depth maps
  bool depthRangeFromKeys = false;  // given in the config (else from a JSON camera file)
  FrameFormat depthFormat;    // of this view's depth file (bit depth may differ per view)
  Camera camera;              // filled by loadScene()
};

struct SynthesisSettings {
  int depthType = 0;                         // 0 camera z, 1 world z
  FrameFormat textureFormat;                 // inputs (and the output unless VirtualWidth/VirtualHeight say otherwise)
  int virtualWidth = 0, virtualHeight = 0;   // VirtualWidth, VirtualHeight; 0: the inputs' size
  FrameFormat depthFormat;                   // depth files (luma only is used)
  int64_t startFrame = 0;
  int64_t frameCount = 1;
  std::string configFile;                    // the config file read (empty: none); an input like the others
  std::string cameraFile;
  std::string virtualCameraFile;             // VirtualCameraParameterFile; empty: cameraFile
  std::string inputCameraOverrides;          // InputCameraOverrides: JSON object text; empty: none
  std::string virtualCameraOverrides;        // VirtualCameraOverrides
  std::string poseTracePath;                 // VirtualPoseTraceName; empty: a fixed virtual camera
  RotationConvention rotationConvention = RotationConvention::WorldToCamera;
  std::string virtualCameraName;
  std::vector<ReferenceView> references;     // left then right, or the Reference list (1 to 16)
  std::string outputPath;
  std::string referenceViewPath;             // ground truth of the virtual view; empty: none
  std::vector<std::string> qualityMetrics;   // QualityMetrics: scored against it besides PSNR
  std::string virtualDepthPath;              // output of the virtual depth; empty: none
  DepthRange virtualDepthRange;              // levels of that output
  bool virtualDepthRangeSet = false;         // given by the Virtual*DepthValue keys
  std::string virtualMaskPath;               // OutputVirtualMaskName (RVS's OutputMasks); empty: none
  std::string maskedVirtualDepthPath;        // OutputMaskedVirtualDepthMapName (RVS's MaskedDepthOutputFiles)
  int colorSpace = 0;                        // 0 YUV, 1 RGB
  int precision = 2;                         // 1, 2, 4
  int filter = 1;                            // 0 bilinear, 1 bicubic, 2 AVC 6-tap
  SynthesisMode mode = SynthesisMode::General;
  bool boundaryNoiseRemoval = false;
  int viewBlending = 0;                      // 0 blend by baseline weights, 1 mainly the nearer view
  int depthBlendDifference = 5;              // depth levels
  bool ivsrsInpaint = true;
  int missingDepthLevel = -1;                // -1 off
  bool missingDepthAuto = false;             // MissingDepthLevel auto: the plan decides on the first frame
  bool missingDepthFillAuto = false;         // MissingDepthFill auto: filled when auto finds level 0 missing
  bool missingDepthFill = false;             // MissingDepthFill: runs between valid samples take the farther level
  int depthEdgeAlignment = 4;                // DepthEdgeAlignment: reach in samples; 0 off
  OneDOptions oneD;
  int threads = 0;                           // 0 all cores
  std::string reportPath;                    // CSV report; empty: none
  std::string summaryPath;                   // JSON summary (SummaryFile); empty: none

  // Every file the run reads; the output must be none of them.
  std::vector<std::string> inputPaths() const;
  // The virtual view has another size than the reference views (VirtualWidth, VirtualHeight).
  bool virtualResized() const {
    return virtualFormat().width != textureFormat.width || virtualFormat().height != textureFormat.height;
  }
  // The format of the output, its ground truth, depth and masks: the texture format at the virtual size.
  FrameFormat virtualFormat() const {
    FrameFormat format = textureFormat;
    if (virtualWidth > 0) format.width = virtualWidth;
    if (virtualHeight > 0) format.height = virtualHeight;
    return format;
  }
  // A mask of the virtual view is written (OutputVirtualMaskName or OutputMaskedVirtualDepthMapName).
  bool wantsMask() const { return !virtualMaskPath.empty() || !maskedVirtualDepthPath.empty(); }
};

// Reads and checks the settings; throws InputError listing every problem (missing keys, values that
// do not fit together, sizes too large to allocate).
SynthesisSettings readSynthesisSettings(const Config& config);

struct Scene {
  SynthesisSettings settings;
  Camera virtualCamera;
  // VirtualPoseTraceName: the virtual camera of each frame (StartFrame on); empty: virtualCamera throughout.
  std::vector<Camera> virtualCameraPerFrame;
  std::vector<std::string> warnings;  // from the camera file (checkInputs and the run add their own)
};

// Settings plus cameras from the camera file; throws InputError (missing cameras list the names the
// file has). Opens no YUV file.
Scene loadScene(const Config& config);

// True when the two names are the same file (existing files: the same inode; else the same canonical
// name). Outputs use it to refuse overwriting an input.
bool samePath(const std::string& a, const std::string& b);

// Human-readable summary of the cameras (name, K, R, centre), for --check and the log: "left",
// "virtual", "right" for the Left/Right keys, else every reference view by its label, then "virtual".
std::string describeCameras(const Scene& scene);

}  // namespace vs
