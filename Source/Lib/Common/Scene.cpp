#include "Common/Scene.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "Common/CameraFile.h"
#include "Common/Error.h"
#include "Common/QualityReport.h"
#include "Common/RvsConfig.h"

namespace vs {

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
  // Where either name cannot be made canonical (too long, a loop of links), compare the names as
  // written: two failures must not read as the same (empty) path.
  std::error_code ecA, ecB;
  const std::filesystem::path canonicalA = std::filesystem::weakly_canonical(a, ecA);
  const std::filesystem::path canonicalB = std::filesystem::weakly_canonical(b, ecB);
  if (ecA || ecB) return std::filesystem::path(a).lexically_normal() == std::filesystem::path(b).lexically_normal();
  return canonicalA == canonicalB;
}

namespace {

constexpr int64_t kMaxPixels = int64_t(1) << 26;  // 64 Mpixel: larger frames are refused before allocating

void checkDepthRange(const DepthRange& range, int depthType, const std::string& prefix, const std::string& where,
                     ProblemList& problems) {
  try {
    validateDepthRange(range, depthType, prefix);
  } catch (const InputError& e) {
    std::string hint;
    if (depthType == 0 && range.znear < 0 && range.zfar < 0)
      hint = " (both are negative: if they are world z coordinates, as in VSRS 3.5 data whose cameras look "
             "along -z, set DepthType 1)";
    problems.add(where + ": " + e.what() + hint);
  }
}

// The reference views: the Reference* lists, or the Left keys and (all or none of) the Right keys.
void readReferenceViews(const Config& config, SynthesisSettings& s, const std::string& where, ProblemList& problems) {
  static const char* const leftKeys[] = {"LeftCameraName", "LeftViewImageName", "LeftDepthMapName",
                                         "LeftNearestDepthValue", "LeftFarthestDepthValue"};
  static const char* const rightKeys[] = {"RightCameraName", "RightViewImageName", "RightDepthMapName",
                                          "RightNearestDepthValue", "RightFarthestDepthValue"};
  auto newView = [&](const std::string& label, const std::string& camera, const std::string& texture,
                     const std::string& depth) {
    ReferenceView view;
    view.label = label;
    view.cameraName = camera;
    view.texturePath = texture;
    view.depthPath = depth;
    view.depthFormat = s.depthFormat;
    view.depthRange.bitDepth = s.depthFormat.bitDepth;
    return view;
  };
  if (config.isSet("ReferenceCameraNames")) {
    for (const char* key : leftKeys)
      if (config.isSet(key)) problems.add(where + ": '" + key + "' and ReferenceCameraNames exclude each other");
    for (const char* key : rightKeys)
      if (config.isSet(key)) problems.add(where + ": '" + key + "' and ReferenceCameraNames exclude each other");
    const std::vector<std::string> names = config.getList("ReferenceCameraNames");
    const std::vector<std::string> textures = config.getList("ReferenceViewImageNames");
    const std::vector<std::string> depths = config.getList("ReferenceDepthMapNames");
    const std::vector<std::string> nears = config.getList("ReferenceNearestDepthValues");
    const std::vector<std::string> fars = config.getList("ReferenceFarthestDepthValues");
    if (names.size() > kMaxReferenceViews)
      problems.add(where + ": ReferenceCameraNames lists " + std::to_string(names.size()) + " cameras; at most " +
                   std::to_string(kMaxReferenceViews) + " are supported");
    auto sameLength = [&](const char* key, const std::vector<std::string>& items, bool optional) {
      if (optional && items.empty()) return true;
      if (items.size() == names.size()) return true;
      problems.add(where + ": " + key + " lists " + std::to_string(items.size()) + " items but ReferenceCameraNames " +
                   std::to_string(names.size()));
      return false;
    };
    // Every list is checked (each reports its own problem) before they are combined.
    const bool texturesOk = sameLength("ReferenceViewImageNames", textures, false);
    const bool depthsOk = sameLength("ReferenceDepthMapNames", depths, false);
    const bool nearsOk = sameLength("ReferenceNearestDepthValues", nears, true);
    const bool farsOk = sameLength("ReferenceFarthestDepthValues", fars, true);
    const bool ok = texturesOk && depthsOk && nearsOk && farsOk;
    if (nears.empty() != fars.empty())
      problems.add(where + ": give both ReferenceNearestDepthValues and ReferenceFarthestDepthValues, or neither");
    if (!ok) return;
    for (size_t k = 0; k < names.size(); ++k) {
      ReferenceView view = newView("Reference " + std::to_string(k + 1), names[k], textures[k], depths[k]);
      if (!nears.empty() && !fars.empty()) {
        const bool nearOk = parseDouble(nears[k], view.depthRange.znear, false);
        const bool farOk = parseDouble(fars[k], view.depthRange.zfar, true);
        if (!nearOk || !farOk) {
          problems.add(where + ": depth range of reference " + std::to_string(k + 1) + " ('" + nears[k] + "', '" +
                       fars[k] + "'): numbers expected (inf for an infinite far plane)");
        } else {
          view.depthRangeFromKeys = true;
          checkDepthRange(view.depthRange, s.depthType, "Reference" + std::to_string(k + 1), where, problems);
        }
      }
      s.references.push_back(view);
    }
    return;
  }
  // Left keys: camera and files required; the depth range may come from a JSON camera file.
  for (int k = 0; k < 3; ++k)
    if (!config.isSet(leftKeys[k]))
      problems.add(where + ": missing required key '" + leftKeys[k] + "' (or give the Reference keys)");
  // The right view is optional: all five of its keys, or none (extrapolation from the left view).
  int rightKeysSet = 0;
  for (const char* key : rightKeys) rightKeysSet += config.isSet(key) ? 1 : 0;
  const bool rightComplete = rightKeysSet == 5 || (rightKeysSet == 3 && config.isSet("RightCameraName") &&
                                                   config.isSet("RightViewImageName") && config.isSet("RightDepthMapName"));
  if (rightKeysSet > 0 && !rightComplete)
    for (const char* key : rightKeys)
      if (!config.isSet(key))
        problems.add(where + ": missing key '" + key + "': give every Right key for two reference views, or none to " +
                     "extrapolate from the left view alone");
  std::vector<std::string> sides{"Left"};
  if (rightKeysSet > 0 && rightComplete) sides.push_back("Right");
  for (const std::string& prefix : sides) {
    ReferenceView view = newView(prefix, config.getString(prefix + "CameraName"), config.getPath(prefix + "ViewImageName"),
                                 config.getPath(prefix + "DepthMapName"));
    const std::string nearKey = prefix + "NearestDepthValue", farKey = prefix + "FarthestDepthValue";
    if (config.isSet(nearKey) != config.isSet(farKey))
      problems.add(where + ": give both " + nearKey + " and " + farKey + ", or neither (a JSON camera file gives them)");
    if (config.isSet(nearKey) && config.isSet(farKey)) {
      view.depthRange.znear = config.getDouble(nearKey);
      view.depthRange.zfar = config.getDouble(farKey);
      view.depthRangeFromKeys = true;
      checkDepthRange(view.depthRange, s.depthType, prefix, where, problems);
    }
    s.references.push_back(view);
  }
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
  std::vector<std::string> paths{cameraFile};  // the output must be none of these
  if (!configFile.empty()) paths.push_back(configFile);
  if (!virtualCameraFile.empty()) paths.push_back(virtualCameraFile);
  if (!poseTracePath.empty()) paths.push_back(poseTracePath);
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
  // The virtual view's own size (0: the inputs'); its format is the texture's otherwise.
  s.virtualWidth = int(config.getInt("VirtualWidth"));
  s.virtualHeight = int(config.getInt("VirtualHeight"));
  if (s.virtualResized()) {
    const int vw = s.virtualFormat().width, vh = s.virtualFormat().height;
    if (int64_t(vw) * vh > kMaxPixels)
      problems.add(where + ": VirtualWidth x VirtualHeight = " + std::to_string(vw) + " x " + std::to_string(vh) +
                   " is more than " + std::to_string(kMaxPixels) + " pixels; refused before allocating memory");
    if ((s.textureFormat.chroma == ChromaFormat::Yuv420 || s.depthFormat.chroma == ChromaFormat::Yuv420) &&
        (vw % 2 || vh % 2))
      problems.add(where + ": 4:2:0 output needs an even VirtualWidth and VirtualHeight, got " + std::to_string(vw) +
                   " x " + std::to_string(vh));
  }

  s.startFrame = config.getInt("StartFrame");
  s.frameCount = config.getInt("TotalNumberOfFrames");
  s.configFile = config.configPath();
  s.cameraFile = config.getPath("CameraParameterFile");
  s.virtualCameraFile = config.getPath("VirtualCameraParameterFile");
  s.inputCameraOverrides = config.getString("InputCameraOverrides");
  s.virtualCameraOverrides = config.getString("VirtualCameraOverrides");
  s.poseTracePath = config.getPath("VirtualPoseTraceName");
  s.rotationConvention = config.getInt("CameraRotationConvention") == 1 ? RotationConvention::CameraToWorld
                                                                         : RotationConvention::WorldToCamera;
  s.virtualCameraName = config.getString("VirtualCameraName");
  readReferenceViews(config, s, where, problems);
  s.outputPath = config.getPath("OutputVirtualViewImageName");
  s.referenceViewPath = config.getPath("ReferenceVirtualViewImageName");
  s.qualityMetrics = config.getList("QualityMetrics");
  std::string metricError;
  if (!QualityReport::validate(s.qualityMetrics, metricError)) problems.add(where + ": QualityMetrics: " + metricError);
  else if (!QualityReport(s.qualityMetrics, true).empty() && s.referenceViewPath.empty())
    problems.add(where + ": QualityMetrics scores against ReferenceVirtualViewImageName, which is not set");
  s.virtualDepthPath = config.getPath("OutputVirtualDepthMapName");
  s.virtualMaskPath = config.getPath("OutputVirtualMaskName");
  s.maskedVirtualDepthPath = config.getPath("OutputMaskedVirtualDepthMapName");
  s.virtualDepthRange.bitDepth = s.depthFormat.bitDepth;
  if (config.isSet("VirtualNearestDepthValue") != config.isSet("VirtualFarthestDepthValue"))
    problems.add(where + ": give both VirtualNearestDepthValue and VirtualFarthestDepthValue, or neither");
  if (config.isSet("VirtualNearestDepthValue") && config.isSet("VirtualFarthestDepthValue")) {
    s.virtualDepthRangeSet = true;
    s.virtualDepthRange.znear = config.getDouble("VirtualNearestDepthValue");
    s.virtualDepthRange.zfar = config.getDouble("VirtualFarthestDepthValue");
    checkDepthRange(s.virtualDepthRange, s.depthType, "Virtual", where, problems);
  }

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
  s.missingDepthAuto = config.isAuto("MissingDepthLevel");
  s.missingDepthLevel = s.missingDepthAuto ? -1 : int(config.getInt("MissingDepthLevel"));
  s.missingDepthFillAuto = config.isAuto("MissingDepthFill");
  s.missingDepthFill = !s.missingDepthFillAuto && config.getInt("MissingDepthFill") != 0;
  s.depthEdgeAlignment = int(config.getInt("DepthEdgeAlignment"));
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
  s.summaryPath = config.getPath("SummaryFile");

  if (!s.outputPath.empty())
    for (const std::string& input : s.inputPaths())
      if (!input.empty() && samePath(input, s.outputPath))
        problems.add(where + ": OutputVirtualViewImageName '" + s.outputPath + "' is also an input (" + input +
                     "); refusing to overwrite it");
  // The reports are written once the output is open (the summary also after a failure): as an input
  // they would be truncated, as an output they would overwrite its frames.
  for (const auto& [key, path] : {std::pair<const char*, const std::string&>{"ReportFile", s.reportPath},
                                  std::pair<const char*, const std::string&>{"SummaryFile", s.summaryPath}}) {
    if (path.empty()) continue;
    for (const std::string& input : s.inputPaths())
      if (!input.empty() && samePath(input, path))
        problems.add(where + ": " + key + " '" + path + "' is also an input (" + input + "); refusing to overwrite it");
    if (!s.outputPath.empty() && samePath(s.outputPath, path))
      problems.add(where + ": " + key + " '" + path +
                   "' is the output sequence (OutputVirtualViewImageName); give the report a file of its own");
    if (!s.virtualDepthPath.empty() && samePath(s.virtualDepthPath, path))
      problems.add(where + ": " + key + " '" + path +
                   "' is the output depth sequence (OutputVirtualDepthMapName); give the report a file of its own");
  }
  if (!s.reportPath.empty() && !s.summaryPath.empty() && samePath(s.reportPath, s.summaryPath))
    problems.add(where + ": ReportFile and SummaryFile are the same file '" + s.reportPath + "'");
  if (!s.virtualDepthPath.empty())
    for (const std::string& input : s.inputPaths())
      if (!input.empty() && samePath(input, s.virtualDepthPath))
        problems.add(where + ": OutputVirtualDepthMapName '" + s.virtualDepthPath + "' is also an input (" + input +
                     "); refusing to overwrite it");
  if (!s.virtualDepthPath.empty() && !s.outputPath.empty() && samePath(s.virtualDepthPath, s.outputPath))
    problems.add(where + ": OutputVirtualDepthMapName and OutputVirtualViewImageName are the same file '" +
                 s.outputPath + "'");

  problems.throwIfAny(where + ": invalid configuration:");
  return s;
}

Scene loadScene(const Config& config) {
  Scene scene;
  scene.settings = readSynthesisSettings(config);
  SynthesisSettings& s = scene.settings;
  // The reference cameras, and the virtual camera (from its own file when VirtualCameraParameterFile
  // is set), each with its overrides (Common/RvsConfig.h).
  const CameraFile cameras =
      readCameraFileWithOverrides(s.cameraFile, s.rotationConvention, s.inputCameraOverrides, "InputCameraOverrides");
  const bool separateVirtual = !s.virtualCameraFile.empty() || !s.virtualCameraOverrides.empty();
  const CameraFile virtualCameras =
      separateVirtual ? readCameraFileWithOverrides(s.virtualCameraFile.empty() ? s.cameraFile : s.virtualCameraFile,
                                                    s.rotationConvention, s.virtualCameraOverrides, "VirtualCameraOverrides")
                      : cameras;
  scene.warnings = cameras.warnings();
  if (separateVirtual)
    for (const std::string& warning : virtualCameras.warnings()) scene.warnings.push_back(warning);
  ProblemList problems;
  auto lookUpIn = [&](const CameraFile& file, const std::string& key, const std::string& name, Camera& camera) {
    if (file.contains(name)) {
      camera = file.find(name);
      return;
    }
    std::string names;
    for (const Camera& c : file.cameras()) names += (names.empty() ? "" : ", ") + c.name;
    problems.add(file.path() + ": camera '" + name + "' named by " + key + " is not in the file; it has: " + names);
  };
  auto lookUp = [&](const std::string& key, const std::string& name, Camera& camera) { lookUpIn(cameras, key, name, camera); };
  for (ReferenceView& view : s.references) {
    lookUp(view.label == "Left" || view.label == "Right" ? view.label + "CameraName" : "ReferenceCameraNames",
           view.cameraName, view.camera);
    if (!cameras.contains(view.cameraName)) continue;
    // A JSON camera file gives each camera's depth range and bit depths; keys given in the config win.
    const CameraInfo& info = cameras.info(view.cameraName);
    if (info.bitDepthDepth > 0 && !config.isSet("DepthBitDepth")) {
      view.depthFormat.bitDepth = view.depthRange.bitDepth = info.bitDepthDepth;
      if (info.bitDepthDepth < 8 || info.bitDepthDepth > 16)
        problems.add(s.cameraFile + ": camera '" + view.cameraName + "': BitDepthDepth " +
                     std::to_string(info.bitDepthDepth) + " is outside 8..16");
    }
    if (!view.depthRangeFromKeys) {
      if (!info.hasDepthRange) {
        problems.add(s.cameraFile + ": no depth range for camera '" + view.cameraName + "': give the " +
                     (view.label == "Left" || view.label == "Right" ? view.label + "NearestDepthValue and " + view.label +
                                                                          "FarthestDepthValue keys"
                                                                    : std::string("Reference*DepthValues keys")) +
                     ", or a JSON camera file with Depth_range");
        continue;
      }
      view.depthRange.znear = info.znear;
      view.depthRange.zfar = info.zfar;
      checkDepthRange(view.depthRange, s.depthType, view.cameraName + " Depth_range: ", s.cameraFile, problems);
    }
  }
  lookUpIn(virtualCameras, "VirtualCameraName", s.virtualCameraName, scene.virtualCamera);
  const bool virtualKnown = virtualCameras.contains(s.virtualCameraName);
  // An equirectangular output is scored with WS-PSNR as well (its rows do not cover equal areas of the
  // sphere), whether or not QualityMetrics names it.
  if (scene.virtualCamera.isEquirectangular() && !s.referenceViewPath.empty() &&
      std::find(s.qualityMetrics.begin(), s.qualityMetrics.end(), "wspsnr") == s.qualityMetrics.end())
    s.qualityMetrics.push_back("wspsnr");
  if (!s.virtualDepthRangeSet && !s.references.empty()) {
    const bool jsonRange = virtualKnown && virtualCameras.info(s.virtualCameraName).hasDepthRange;
    s.virtualDepthRange = s.references[0].depthRange;
    if (jsonRange) {
      s.virtualDepthRange.znear = virtualCameras.info(s.virtualCameraName).znear;
      s.virtualDepthRange.zfar = virtualCameras.info(s.virtualCameraName).zfar;
    }
    s.virtualDepthRange.bitDepth = s.depthFormat.bitDepth;
  }
  // The virtual depth output takes the virtual camera's BitDepthDepth, as the references take theirs.
  if (virtualKnown && !config.isSet("DepthBitDepth")) {
    const int bits = virtualCameras.info(s.virtualCameraName).bitDepthDepth;
    if (bits >= 8 && bits <= 16) s.virtualDepthRange.bitDepth = bits;
  }
  if (!s.poseTracePath.empty() && virtualKnown) {
    const std::vector<Pose> poses = readPoseTrace(s.poseTracePath);
    const int64_t needed = s.startFrame + s.frameCount;
    if (int64_t(poses.size()) < needed)
      problems.add(s.poseTracePath + ": VirtualPoseTraceName holds " + std::to_string(poses.size()) +
                   " poses; frames " + std::to_string(s.startFrame) + " to " + std::to_string(needed - 1) +
                   " need " + std::to_string(needed) + " (row StartFrame+n moves frame n)");
    else
      for (int64_t f = s.startFrame; f < needed; ++f)
        scene.virtualCameraPerFrame.push_back(posedCamera(scene.virtualCamera, poses[size_t(f)]));
  }
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
    if (c.isEquirectangular()) {
      std::snprintf(line, sizeof line, "  equirectangular %dx%d: longitude %.10g to %.10g, latitude %.10g to %.10g deg (K unused)\n",
                    c.erp.width, c.erp.height, c.erp.lonMin, c.erp.lonMax, c.erp.latMin, c.erp.latMax);
      out << line;
    }
  };
  const SynthesisSettings& s = scene.settings;
  const bool leftRight = !s.references.empty() && s.references[0].label == "Left";
  if (leftRight) {
    describe("left", s.references[0].camera);
    describe("virtual", scene.virtualCamera);
    if (s.references.size() > 1) describe("right", s.references[1].camera);
    return out.str();
  }
  // The Reference lists: every view by its label ("reference 3"), then the virtual camera.
  for (const ReferenceView& view : s.references) {
    std::string role = view.label;
    for (char& c : role) c = char(std::tolower(static_cast<unsigned char>(c)));
    describe(role.c_str(), view.camera);
  }
  describe("virtual", scene.virtualCamera);
  return out.str();
}

}  // namespace vs
