#include "Common/Scene.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "Common/CameraFile.h"
#include "Common/Error.h"

namespace vs {

namespace {

constexpr int64_t kMaxPixels = int64_t(1) << 26;  // 64 Mpixel: larger frames are refused before allocating

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
  return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}

}  // namespace

const char* synthesisModeName(SynthesisMode mode) {
  switch (mode) {
    case SynthesisMode::General: return "general (3D warping)";
    case SynthesisMode::Parallel1D: return "1D parallel";
    case SynthesisMode::Auto: return "auto";
  }
  return "?";
}

std::vector<std::string> SynthesisSettings::inputPaths() const {
  std::vector<std::string> paths{cameraFile};
  for (const ReferenceView& view : references) {
    paths.push_back(view.texturePath);
    paths.push_back(view.depthPath);
  }
  if (!referenceViewPath.empty()) paths.push_back(referenceViewPath);
  return paths;
}

SynthesisSettings readSynthesisSettings(const Config& config) {
  ProblemList problems;
  config.requireKeys(problems);
  const std::string where = config.configPath().empty() ? std::string("configuration") : config.configPath();

  SynthesisSettings s;
  s.depthType = int(config.getInt("DepthType"));
  const int width = int(config.getInt("SourceWidth"));
  const int height = int(config.getInt("SourceHeight"));
  s.textureFormat.width = s.depthFormat.width = width;
  s.textureFormat.height = s.depthFormat.height = height;
  s.textureFormat.bitDepth = int(config.getInt("TextureBitDepth"));
  s.depthFormat.bitDepth = int(config.getInt("DepthBitDepth"));
  parseChromaFormat(config.getString("ChromaFormat"), s.textureFormat.chroma);
  parseChromaFormat(config.getString("DepthChromaFormat"), s.depthFormat.chroma);
  if (int64_t(width) * height > kMaxPixels)
    problems.add(where + ": SourceWidth x SourceHeight = " + std::to_string(width) + " x " + std::to_string(height) +
                 " is more than " + std::to_string(kMaxPixels) + " pixels; refused before allocating memory");
  for (const FrameFormat* format : {&s.textureFormat, &s.depthFormat})
    if (format->chroma == ChromaFormat::Yuv420 && (width % 2 || height % 2)) {
      problems.add(where + ": 4:2:0 " + std::string(format == &s.textureFormat ? "texture" : "depth") +
                   " needs an even SourceWidth and SourceHeight, got " + std::to_string(width) + " x " +
                   std::to_string(height));
    }

  s.startFrame = config.getInt("StartFrame");
  s.frameCount = config.getInt("TotalNumberOfFrames");
  s.cameraFile = config.getPath("CameraParameterFile");
  s.rotationConvention = config.getInt("CameraRotationConvention") == 1 ? RotationConvention::CameraToWorld
                                                                         : RotationConvention::WorldToCamera;
  s.virtualCameraName = config.getString("VirtualCameraName");
  // The right view is optional: all five of its keys, or none (extrapolation from the left view).
  static const char* const rightKeys[] = {"RightCameraName", "RightViewImageName", "RightDepthMapName",
                                          "RightNearestDepthValue", "RightFarthestDepthValue"};
  int rightKeysSet = 0;
  for (const char* key : rightKeys) rightKeysSet += config.isSet(key) ? 1 : 0;
  if (rightKeysSet > 0 && rightKeysSet < 5)
    for (const char* key : rightKeys)
      if (!config.isSet(key))
        problems.add(where + ": missing key '" + key + "': give every Right key for two reference views, or none to " +
                     "extrapolate from the left view alone");
  std::vector<std::string> sides{"Left"};
  if (rightKeysSet == 5) sides.push_back("Right");
  for (const std::string& prefix : sides) {
    ReferenceView view;
    view.label = prefix;
    view.cameraName = config.getString(prefix + "CameraName");
    view.texturePath = config.getPath(prefix + "ViewImageName");
    view.depthPath = config.getPath(prefix + "DepthMapName");
    view.depthRange.bitDepth = s.depthFormat.bitDepth;
    const std::string nearKey = prefix + "NearestDepthValue", farKey = prefix + "FarthestDepthValue";
    if (config.isSet(nearKey) && config.isSet(farKey)) {
      view.depthRange.znear = config.getDouble(nearKey);
      view.depthRange.zfar = config.getDouble(farKey);
      try {
        validateDepthRange(view.depthRange, s.depthType, prefix);
      } catch (const InputError& e) {
        std::string hint;
        if (s.depthType == 0 && view.depthRange.znear < 0 && view.depthRange.zfar < 0)
          hint = " (both are negative: if they are world z coordinates, as in VSRS 3.5 data whose cameras look "
                 "along -z, set DepthType 1)";
        problems.add(where + ": " + e.what() + hint);
      }
    }
    s.references.push_back(view);
  }
  s.outputPath = config.getPath("OutputVirtualViewImageName");
  s.referenceViewPath = config.getPath("ReferenceVirtualViewImageName");

  s.colorSpace = int(config.getInt("ColorSpace"));
  if (s.colorSpace == 1 && s.textureFormat.chroma == ChromaFormat::Yuv400)
    problems.add(where + ": ColorSpace 1 (RGB) needs colour input; ChromaFormat is 400");
  s.precision = std::stoi(config.getString("Precision"));
  s.filter = std::stoi(config.getString("Filter"));
  const std::string mode = config.getString("SynthesisMode");
  s.mode = mode == "auto" ? SynthesisMode::Auto : (mode == "1" ? SynthesisMode::Parallel1D : SynthesisMode::General);
  s.boundaryNoiseRemoval = config.getInt("BoundaryNoiseRemoval") != 0;
  s.viewBlending = int(config.getInt("ViewBlending"));
  s.depthBlendDifference = int(config.getInt("DepthBlendDifference"));
  s.ivsrsInpaint = config.getInt("IvsrsInpaint") != 0;
  s.missingDepthLevel = int(config.getInt("MissingDepthLevel"));
  if (s.missingDepthLevel > s.depthFormat.maxValue())
    problems.add(where + ": MissingDepthLevel " + std::to_string(s.missingDepthLevel) + " is above the largest " +
                 std::to_string(s.depthFormat.bitDepth) + "-bit depth level " + std::to_string(s.depthFormat.maxValue()));
  s.oneD.splatting = int(config.getInt("SplattingOption"));
  s.oneD.boundaryGrowth = int(config.getInt("BoundaryGrowth"));
  s.oneD.merging = int(config.getInt("MergingOption"));
  s.oneD.depthThreshold = int(config.getInt("DepthThreshold"));
  s.oneD.holeCountThreshold = int(config.getInt("HoleCountThreshold"));
  s.oneD.temporalImprovement = config.getInt("TemporalImprovementOption") != 0;
  s.oneD.warpEnhancement = config.getInt("WarpEnhancementOption") != 0;
  s.oneD.cleanNoise = config.getInt("CleanNoiseOption") != 0;
  s.threads = int(config.getInt("Threads"));
  s.reportPath = config.getPath("ReportFile");

  if (!s.outputPath.empty())
    for (const std::string& input : s.inputPaths())
      if (!input.empty() && samePath(input, s.outputPath))
        problems.add(where + ": OutputVirtualViewImageName '" + s.outputPath + "' is also an input (" + input +
                     "); refusing to overwrite it");

  problems.throwIfAny(where + ": invalid configuration:");
  return s;
}

Scene loadScene(const Config& config) {
  Scene scene;
  scene.settings = readSynthesisSettings(config);
  SynthesisSettings& s = scene.settings;
  const CameraFile cameras = readCameraFile(s.cameraFile, s.rotationConvention);
  scene.warnings = cameras.warnings();
  ProblemList problems;
  auto lookUp = [&](const std::string& key, const std::string& name, Camera& camera) {
    if (cameras.contains(name)) {
      camera = cameras.find(name);
      return;
    }
    std::string names;
    for (const Camera& c : cameras.cameras()) names += (names.empty() ? "" : ", ") + c.name;
    problems.add(s.cameraFile + ": camera '" + name + "' named by " + key + " is not in the file; it has: " + names);
  };
  for (ReferenceView& view : s.references) lookUp(view.label + "CameraName", view.cameraName, view.camera);
  lookUp("VirtualCameraName", s.virtualCameraName, scene.virtualCamera);
  problems.throwIfAny(config.configPath() + ": cameras:");
  return scene;
}

std::string describeCameras(const Scene& scene) {
  std::ostringstream out;
  auto describe = [&](const char* role, const Camera& c) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "%-8s %s\n  K = [%.10g %.10g %.10g; %.10g %.10g %.10g; %.10g %.10g %.10g]\n"
                  "  R = [%.10g %.10g %.10g; %.10g %.10g %.10g; %.10g %.10g %.10g]\n  centre = (%.10g, %.10g, %.10g)\n",
                  role, c.name.c_str(), c.K[0][0], c.K[0][1], c.K[0][2], c.K[1][0], c.K[1][1], c.K[1][2], c.K[2][0],
                  c.K[2][1], c.K[2][2], c.R[0][0], c.R[0][1], c.R[0][2], c.R[1][0], c.R[1][1], c.R[1][2], c.R[2][0],
                  c.R[2][1], c.R[2][2], c.t.x, c.t.y, c.t.z);
    out << line;
  };
  const SynthesisSettings& s = scene.settings;
  if (!s.references.empty()) describe("left", s.references[0].camera);
  describe("virtual", scene.virtualCamera);
  if (s.references.size() > 1) describe("right", s.references[1].camera);
  return out.str();
}

}  // namespace vs
