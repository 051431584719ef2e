#include "Scene/SceneGen.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/Error.h"
#include "Common/SafeOutput.h"
#include "Common/Yuv.h"
#include "Scene/Rig.h"
#include "Scene/SceneFile.h"
#include "Scene/Scenes.h"

namespace vs {

namespace {

namespace fs = std::filesystem;

// Default text of keys whose value comes from the chosen scene when unset (see --help).
constexpr const char* kFromScene = "scene";
constexpr const char* kAutomatic = "auto";

OptionSpec option(const char* key, OptionType type, const char* defaultValue, double lo, double hi, const char* help) {
  OptionSpec s;
  s.key = key;
  s.type = type;
  s.defaultValue = defaultValue;
  s.minValue = lo;
  s.maxValue = hi;
  s.vsrsDefault = "-";
  s.help = help;
  return s;
}

OptionSpec choice(const char* key, std::vector<std::string> choices, const char* defaultValue, const char* help) {
  OptionSpec s = option(key, OptionType::Choice, defaultValue, 0, 0, help);
  s.choices = std::move(choices);
  return s;
}

void addSection(OptionTable& table, const char* section, std::vector<OptionSpec> specs) {
  for (OptionSpec& spec : specs) {
    spec.section = section;
    table.add(std::move(spec));
  }
}

std::string formatFixed(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// Nearest- and farthest-safe rounding of the automatic range to 4 significant digits, so that configs
// read well; the returned value is what its text reads back as, and never crosses `limit`.
double roundedDepth(double value, bool down, double limit) {
  const double exponent = std::floor(std::log10(value));
  const double step = std::pow(10.0, exponent - 3.0);
  const double rounded = (down ? std::floor(value / step) : std::ceil(value / step)) * step;
  const double readBack = std::strtod(formatFixed("%.4g", rounded).c_str(), nullptr);
  if (!(readBack > 0.0) || (down ? readBack > limit : readBack < limit)) return value;
  return readBack;
}

// Camera names in file names: anything but letters, digits, '-', '_' and '.' becomes '_'.
std::string fileSafe(const std::string& name) {
  std::string safe = name;
  for (char& c : safe)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  return safe;
}

uint16_t roundToSample(double value, int maxValue) {
  return uint16_t(std::clamp(std::lround(value), 0L, long(maxValue)));
}

struct ViewFiles {
  std::string texture;  // file names inside the output folder
  std::string depth;
};

std::string configText(const SceneGenSettings& s, const SceneGenResult& result, const std::vector<ViewFiles>& files,
                       size_t left, size_t virtualIndex, size_t right, const std::string& outputName,
                       const std::string& tool) {
  const std::vector<Camera>& cameras = result.cameras;
  std::ostringstream out;
  out << "# " << tool << " config written by SceneGen " << VS_VERSION << ": scene " << s.scene << ", virtual camera "
      << cameras[virtualIndex].name << " from " << cameras[left].name << " and " << cameras[right].name << "\n"
      << "# File names are relative to this file's folder. " << files[virtualIndex].texture
      << " is the ground truth of the virtual camera.\n";
  auto line = [&](const std::string& key, const std::string& value) {
    out << std::left << std::setw(32) << key << " " << value << "\n";
  };
  line("DepthType", "0");
  line("SourceWidth", std::to_string(s.width));
  line("SourceHeight", std::to_string(s.height));
  line("StartFrame", "0");
  line("TotalNumberOfFrames", std::to_string(s.frames));
  line("LeftNearestDepthValue", exactNumberText(result.depthRange.znear));
  line("LeftFarthestDepthValue", exactNumberText(result.depthRange.zfar));
  line("RightNearestDepthValue", exactNumberText(result.depthRange.znear));
  line("RightFarthestDepthValue", exactNumberText(result.depthRange.zfar));
  line("CameraParameterFile", fs::path(result.cameraFile).filename().string());
  line("LeftCameraName", cameras[left].name);
  line("VirtualCameraName", cameras[virtualIndex].name);
  line("RightCameraName", cameras[right].name);
  line("LeftViewImageName", files[left].texture);
  line("RightViewImageName", files[right].texture);
  line("LeftDepthMapName", files[left].depth);
  line("RightDepthMapName", files[right].depth);
  line("OutputVirtualViewImageName", outputName);
  line("ReferenceVirtualViewImageName", files[virtualIndex].texture);
  line("ColorSpace", "0");
  line("ChromaFormat", "420");
  line("TextureBitDepth", "8");
  line("DepthBitDepth", std::to_string(s.depthBitDepth));
  line("DepthChromaFormat", "420");
  line("SynthesisMode", s.synthesisMode);
  return out.str();
}

// Through a temporary file renamed into place (Common/SafeOutput.h): a failed write keeps the previous file.
void writeTextFile(const std::string& path, const std::string& text) {
  SafeOutputFile out(path);
  out.write(text);
  out.commit();
}

// The effective settings, one "Key value" a line, as the log's first block.
std::string settingsText(const SceneGenSettings& s) {
  std::ostringstream out;
  auto line = [&](const std::string& key, const std::string& value) {
    out << std::left << std::setw(24) << key << " " << value << "\n";
  };
  line("Scene", s.scene);
  if (!s.sceneFile.empty()) line("SceneFile", s.sceneFile);
  line("SourceWidth", std::to_string(s.width));
  line("SourceHeight", std::to_string(s.height));
  line("TotalNumberOfFrames", std::to_string(s.frames));
  line("MotionScale", exactNumberText(s.motionScale));
  if (s.sceneFile.empty()) line("BackgroundDepth", exactNumberText(s.backgroundDepth));
  if (s.scene == "sphere" && s.sceneFile.empty()) {
    line("SphereRadius", exactNumberText(s.sphereRadius));
    line("SphereDepth", exactNumberText(s.sphereDepth));
  }
  line("Rig", rigTypeName(s.rig));
  if (s.rig == RigType::File) {
    line("CameraParameterFile", s.cameraFile);
  } else {
    line("CameraCount", std::to_string(s.cameraCount));
    if (s.rig == RigType::Parallel) line("Baseline", exactNumberText(s.baseline));
    if (s.rig == RigType::Arc) {
      line("ArcRadius", exactNumberText(s.arcRadius));
      line("ArcAngle", exactNumberText(s.arcStepDegrees));
    }
    line("FocalLength", exactNumberText(s.focalLength));
    line("PrincipalPointX", exactNumberText(s.principalX));
    line("PrincipalPointY", exactNumberText(s.principalY));
  }
  line("DepthBitDepth", std::to_string(s.depthBitDepth));
  line("NearestDepthValue", std::isnan(s.znear) ? std::string(kAutomatic) : exactNumberText(s.znear));
  line("FarthestDepthValue", std::isnan(s.zfar) ? std::string(kAutomatic) : exactNumberText(s.zfar));
  line("AutoDepthMargin", exactNumberText(s.autoDepthMargin));
  line("AntiAliasing", std::to_string(s.samplesPerPixel));
  line("Threads", std::to_string(s.threads));
  line("OutputFolder", s.outputFolder);
  line("SynthesisMode", s.synthesisMode);
  return out.str();
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

const char* rigTypeName(RigType rig) {
  switch (rig) {
    case RigType::Parallel:
      return "parallel";
    case RigType::Arc:
      return "arc";
    case RigType::File:
      return "file";
  }
  return "?";
}

std::string exactNumberText(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  for (int precision = 1; precision <= 17; ++precision) {
    const std::string text = formatFixed(("%." + std::to_string(precision) + "g").c_str(), value);
    if (std::strtod(text.c_str(), nullptr) == value) return text;
  }
  return formatFixed("%.17g", value);
}

OptionTable sceneGenOptionTable() {
  OptionTable table("SceneGen");
  constexpr double kMaxSize = 16384;
  addSection(
      table, "Scene",
      {
          choice("Scene", builtInSceneNames(), "demo", "Built-in scene to render (see the scene list above)"),
          option("SceneFile", OptionType::Path, "", 0, 0,
                 "Scene file to render instead of a built-in scene (cfg/scenes/*.scene: settings and objects, "
                 "doc/scenegen.md); its settings are the preset that the keys here override"),
          option("SourceWidth", OptionType::Int, kFromScene, 16, kMaxSize,
                 "Width of every view in luma samples; even (4:2:0)"),
          option("SourceHeight", OptionType::Int, kFromScene, 16, kMaxSize,
                 "Height of every view in luma samples; even (4:2:0)"),
          option("TotalNumberOfFrames", OptionType::Int, kFromScene, 1, 100000, "Number of frames to render"),
          option("MotionScale", OptionType::Double, "1", 0, 100,
                 "Multiplies every object's per-frame motion; 0 renders a static scene"),
          option("BackgroundDepth", OptionType::Double, kFromScene, 0.01, 1e6,
                 "z of the backdrop (for plane: of the plane) in world units; the rig looks along +z"),
          option("SphereRadius", OptionType::Double, kFromScene, 1e-6, 1e6, "sphere scene: radius of the sphere"),
          option("SphereDepth", OptionType::Double, kFromScene, 1e-6, 1e6,
                 "sphere scene: z of the sphere's centre, on the world z axis"),
      });
  OptionSpec cameraFile = option("CameraParameterFile", OptionType::Path, "", 0, 0,
                                 "Rig file: camera file (VSRS text, or MPEG-I JSON with pinhole and equirectangular cameras) "
                                 "whose cameras (in file order) render the scene");
  addSection(
      table, "Cameras",
      {
          choice("Rig", {"parallel", "arc", "file"}, kFromScene,
                 "parallel: 1D rectified rig along x; arc: cameras on a circle converging on a point; file: "
                 "the cameras of CameraParameterFile"),
          option("CameraCount", OptionType::Int, kFromScene, 1, 256, "Number of cameras of a parallel or arc rig"),
          option("Baseline", OptionType::Double, kFromScene, 1e-9, 1e6,
                 "Parallel rig: distance between neighbouring camera centres (world units)"),
          option("FocalLength", OptionType::Double, kFromScene, 1e-3, 1e7,
                 "Focal length in pixels (parallel and arc rigs); unset: the scene's, scaled by SourceWidth "
                 "over the scene's width (same field of view)"),
          option("PrincipalPointX", OptionType::Double, "centre", -1e7, 1e7,
                 "Principal point column (pixel centres are integers); unset: (SourceWidth - 1) / 2"),
          option("PrincipalPointY", OptionType::Double, "centre", -1e7, 1e7,
                 "Principal point row; unset: (SourceHeight - 1) / 2"),
          option("ArcRadius", OptionType::Double, kFromScene, 1e-3, 1e6,
                 "Arc rig: distance from every camera to the point (0, 0, ArcRadius) they all look at"),
          option("ArcAngle", OptionType::Double, kFromScene, 1e-3, 60,
                 "Arc rig: angle in degrees between neighbouring cameras, seen from the point they look at"),
          cameraFile,
      });
  OptionSpec farthest = option("FarthestDepthValue", OptionType::Double, kAutomatic, 1e-9, 1e12,
                               "Zfar, the camera-frame z of depth level 0 (inf allowed); unset: automatic");
  farthest.allowInfinity = true;
  addSection(table, "Depth",
             {
                 choice("DepthBitDepth", {"8", "16"}, "8", "Bits per depth sample (16: little-endian 16-bit words)"),
                 option("NearestDepthValue", OptionType::Double, kAutomatic, 1e-9, 1e12,
                        "Znear, the camera-frame z of the largest depth level; unset: automatic (the nearest "
                        "rendered depth over all cameras and frames, less the margin)"),
                 farthest,
                 option("AutoDepthMargin", OptionType::Double, "0.02", 0.0001, 1,
                        "Automatic range: Znear = nearest / (1 + margin), Zfar = farthest * (1 + margin), then "
                        "rounded outwards to 4 significant digits"),
             });
  addSection(table, "Rendering",
             {
                 choice("AntiAliasing", {"1", "4", "16"}, "4",
                        "Colour rays per pixel: 1 (centre), 4 (rotated grid) or 16 (4x4 grid); depth always comes "
                        "from the centre ray"),
                 option("Threads", OptionType::Int, "0", 0, 256, "Worker threads; 0: all cores"),
             });
  addSection(table, "Output",
             {
                 option("OutputFolder", OptionType::Path, "scenegen_out", 0, 0,
                        "Folder for every output file (created when missing; existing files are overwritten)"),
                 choice("SynthesisMode", {"0", "1", "auto"}, "0", "SynthesisMode written into the generated configs"),
             });
  return table;
}

std::string sceneListText() {
  // Descriptions wrapped at 100 columns under a 10-column name field.
  std::ostringstream out;
  for (const std::string& name : builtInSceneNames()) {
    std::istringstream words(sceneDescription(name));
    std::string word, line = "  " + name + std::string(8 - std::min<size_t>(name.size(), 7), ' ');
    size_t lineStart = 0;
    while (words >> word) {
      if (line.size() - lineStart + word.size() + 1 > 100 && line.size() - lineStart > 10) {
        line += "\n" + std::string(10, ' ');
        lineStart = line.size() - 10;
      } else if (line.size() - lineStart > 10) {
        line += ' ';
      }
      line += word;
    }
    out << line << "\n";
  }
  return out.str();
}

SceneGenSettings readSceneGenSettings(const Config& config) {
  const std::string where = config.configPath().empty() ? std::string("configuration") : config.configPath();
  ProblemList problems;
  SceneGenSettings s;
  if (config.isSet("SceneFile")) {
    const SceneFile file = readSceneFile(config.getPath("SceneFile"));
    s = file.preset;
    s.sceneFile = config.getPath("SceneFile");
    s.description = file.description;
    s.objects = file.objects;
    if (config.isSet("Scene")) problems.add("Scene and SceneFile are both set; give one of them");
    for (const char* key : {"BackgroundDepth", "SphereRadius", "SphereDepth"})
      if (config.isSet(key))
        problems.add(std::string(key) + " applies to the built-in scenes only; with SceneFile, change the objects "
                     "in the scene file");
  } else {
    s = scenePreset(config.getString("Scene"));
  }
  const int presetWidth = s.width;
  auto setInt = [&](const char* key, int& target) {
    if (config.isSet(key)) target = int(config.getInt(key));
  };
  auto setDouble = [&](const char* key, double& target) {
    if (config.isSet(key)) target = config.getDouble(key);
  };
  setInt("SourceWidth", s.width);
  setInt("SourceHeight", s.height);
  setInt("TotalNumberOfFrames", s.frames);
  s.motionScale = config.getDouble("MotionScale");
  setDouble("BackgroundDepth", s.backgroundDepth);
  setDouble("SphereRadius", s.sphereRadius);
  setDouble("SphereDepth", s.sphereDepth);
  if (config.isSet("Rig")) {
    const std::string rig = config.getString("Rig");
    s.rig = rig == "arc" ? RigType::Arc : (rig == "file" ? RigType::File : RigType::Parallel);
  }
  setInt("CameraCount", s.cameraCount);
  setDouble("Baseline", s.baseline);
  if (config.isSet("FocalLength"))
    s.focalLength = config.getDouble("FocalLength");
  else
    s.focalLength *= double(s.width) / double(presetWidth);
  s.principalX = config.isSet("PrincipalPointX") ? config.getDouble("PrincipalPointX") : (s.width - 1) / 2.0;
  s.principalY = config.isSet("PrincipalPointY") ? config.getDouble("PrincipalPointY") : (s.height - 1) / 2.0;
  setDouble("ArcRadius", s.arcRadius);
  setDouble("ArcAngle", s.arcStepDegrees);
  s.cameraFile = config.getPath("CameraParameterFile");
  s.depthBitDepth = std::stoi(config.getString("DepthBitDepth"));
  setDouble("NearestDepthValue", s.znear);
  setDouble("FarthestDepthValue", s.zfar);
  s.autoDepthMargin = config.getDouble("AutoDepthMargin");
  s.samplesPerPixel = std::stoi(config.getString("AntiAliasing"));
  s.threads = int(config.getInt("Threads"));
  s.outputFolder = config.getPath("OutputFolder");
  s.synthesisMode = config.getString("SynthesisMode");

  if (s.width % 2 || s.height % 2)
    problems.add("SourceWidth x SourceHeight = " + std::to_string(s.width) + " x " + std::to_string(s.height) +
                 ": 4:2:0 output needs even sizes");
  if (int64_t(s.width) * s.height > (int64_t(1) << 26))
    problems.add("SourceWidth x SourceHeight is more than 2^26 pixels; refused before allocating memory");
  if (s.rig == RigType::File && s.cameraFile.empty())
    problems.add("Rig file needs CameraParameterFile (the cameras to render)");
  if (s.rig != RigType::File && config.isSet("CameraParameterFile"))
    problems.add("CameraParameterFile is set but Rig is " + std::string(rigTypeName(s.rig)) +
                 "; set Rig file to use it");
  if (s.scene == "sphere" && !(s.sphereDepth > s.sphereRadius))
    problems.add("SphereDepth " + exactNumberText(s.sphereDepth) + " must exceed SphereRadius " +
                 exactNumberText(s.sphereRadius) + " (the camera would be inside the sphere)");
  if (s.rig == RigType::Arc && (s.cameraCount - 1) * s.arcStepDegrees >= 180.0)
    problems.add("the arc spans (CameraCount - 1) x ArcAngle = " +
                 exactNumberText((s.cameraCount - 1) * s.arcStepDegrees) + " degrees; less than 180 expected");
  if (!std::isnan(s.znear) && !std::isnan(s.zfar)) {  // one alone is checked once the other is derived
    DepthRange range;
    range.bitDepth = s.depthBitDepth;
    range.znear = s.znear;
    range.zfar = s.zfar;
    try {
      validateDepthRange(range, kDepthTypeCamera, "");
    } catch (const InputError& e) {
      problems.add(e.what());
    }
  }
  problems.throwIfAny(where + ": invalid configuration:");
  return s;
}

std::vector<Camera> buildCameras(const SceneGenSettings& s) {
  const Mat3 K = pinholeIntrinsics(s.focalLength, s.principalX, s.principalY);
  switch (s.rig) {
    case RigType::Parallel:
      return parallelRig(s.cameraCount, s.baseline, K);
    case RigType::Arc:
      return arcRig(s.cameraCount, s.arcRadius, s.arcStepDegrees, K);
    case RigType::File: {
      std::vector<Camera> cameras = readCameraFile(s.cameraFile).cameras();
      // An ERP picture's angles come from its camera's Resolution: it must be the picture SceneGen renders.
      for (const Camera& camera : cameras)
        if (camera.isEquirectangular() && (camera.erp.width != s.width || camera.erp.height != s.height))
          throw InputError(s.cameraFile + ": camera '" + camera.name + "' is equirectangular with Resolution " +
                           std::to_string(camera.erp.width) + "x" + std::to_string(camera.erp.height) +
                           ", but SceneGen renders " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                           " (set Width and Height to its resolution)");
      return cameras;
    }
  }
  return {};
}

void colourToYuv420(const RenderedView& view, Frame& texture) {
  VS_CHECK(view.width % 2 == 0 && view.height % 2 == 0);
  FrameFormat format;
  format.width = view.width;
  format.height = view.height;
  format.bitDepth = 8;
  format.chroma = ChromaFormat::Yuv420;
  texture.reset(format);
  for (int y = 0; y < view.height; y += 2) {
    for (int x = 0; x < view.width; x += 2) {
      double cbSum = 0.0, crSum = 0.0;
      for (int k = 0; k < 4; ++k) {
        const int u = x + (k & 1), v = y + (k >> 1);
        const Rgb& c = view.colourAt(u, v);
        const double luma = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
        texture.planes[0].at(u, v) = roundToSample(16.0 + 219.0 * luma, 255);
        cbSum += (c.b - luma) / 1.772;
        crSum += (c.r - luma) / 1.402;
      }
      texture.planes[1].at(x / 2, y / 2) = roundToSample(128.0 + 224.0 * cbSum / 4.0, 255);
      texture.planes[2].at(x / 2, y / 2) = roundToSample(128.0 + 224.0 * crSum / 4.0, 255);
    }
  }
}

int64_t depthToYuv420(const RenderedView& view, const DepthRange& range, Frame& depth) {
  FrameFormat format;
  format.width = view.width;
  format.height = view.height;
  format.bitDepth = range.bitDepth;
  format.chroma = ChromaFormat::Yuv420;
  depth.reset(format);
  depth.fill(0);
  int64_t clamped = 0;
  const int maxLevel = maxDepthLevel(range);
  Plane& luma = depth.planes[0];
  for (int v = 0; v < view.height; ++v) {
    for (int u = 0; u < view.width; ++u) {
      const double z = view.depthAt(u, v);
      if (z == kNoSurface) continue;  // level 0
      const double level = zToLevel(z, range);
      if (level < -0.5 || level > maxLevel + 0.5) ++clamped;
      luma.at(u, v) = uint16_t(zToLevelRounded(z, range));
    }
  }
  return clamped;
}

SceneGenResult generateScene(const SceneGenSettings& s, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  SceneGenResult result;
  result.cameras = buildCameras(s);
  const std::vector<Primitive> primitives = buildScene(s);
  RenderOptions options;
  options.samplesPerPixel = s.samplesPerPixel;
  options.threads = s.threads;
  options.motionScale = s.motionScale;

  std::error_code ec;
  fs::create_directories(s.outputFolder, ec);
  if (!fs::is_directory(s.outputFolder, ec))
    throw InputError("OutputFolder '" + s.outputFolder + "': cannot create the folder" +
                     (ec ? ": " + ec.message() : std::string()));

  // Automatic depth range: a first pass of centre rays only (about a fifth of the full render) over
  // every camera and frame, so the range brackets every depth that is written.
  result.depthRange.bitDepth = s.depthBitDepth;
  result.depthRange.znear = s.znear;
  result.depthRange.zfar = s.zfar;
  if (std::isnan(s.znear) || std::isnan(s.zfar)) {
    double nearest = kNoSurface, farthest = 0.0;
    for (int frame = 0; frame < s.frames; ++frame)
      for (const Camera& camera : result.cameras)
        for (double z : renderDepth(primitives, camera, s.width, s.height, frame, options))
          if (z != kNoSurface) {
            nearest = std::min(nearest, z);
            farthest = std::max(farthest, z);
          }
    if (nearest == kNoSurface)
      throw InputError("no camera sees any object of scene '" + s.scene +
                       "', so there is no depth range to derive; check the cameras, or set NearestDepthValue and "
                       "FarthestDepthValue");
    const double m = s.autoDepthMargin;
    if (std::isnan(s.znear)) result.depthRange.znear = roundedDepth(nearest / (1.0 + m), true, nearest);
    if (std::isnan(s.zfar)) result.depthRange.zfar = roundedDepth(farthest * (1.0 + m), false, farthest);
    log << "automatic depth range: rendered depths " << exactNumberText(nearest) << " to " << exactNumberText(farthest)
        << " -> Znear " << exactNumberText(result.depthRange.znear) << ", Zfar "
        << exactNumberText(result.depthRange.zfar) << " (" << formatFixed("%.2f", secondsSince(start)) << " s)\n";
  }
  validateDepthRange(result.depthRange, kDepthTypeCamera, "");

  // Files.
  const fs::path folder(s.outputFolder);
  std::vector<ViewFiles> files;
  std::vector<std::unique_ptr<YuvWriter>> textureWriters, depthWriters;
  FrameFormat textureFormat{s.width, s.height, 8, ChromaFormat::Yuv420};
  FrameFormat depthFormat{s.width, s.height, s.depthBitDepth, ChromaFormat::Yuv420};
  for (const Camera& camera : result.cameras) {
    const std::string name = fileSafe(camera.name);
    files.push_back({"texture_" + name + ".yuv", "depth_" + name + ".yuv"});
    result.texturePaths.push_back((folder / files.back().texture).string());
    result.depthPaths.push_back((folder / files.back().depth).string());
    textureWriters.push_back(std::make_unique<YuvWriter>(result.texturePaths.back(), textureFormat));
    depthWriters.push_back(std::make_unique<YuvWriter>(result.depthPaths.back(), depthFormat));
  }
  // The VSRS text format holds pinhole cameras only: a rig with an equirectangular camera is written
  // as MPEG-I JSON, which ViewSyn reads the same way.
  bool equirectangular = false;
  for (const Camera& camera : result.cameras) equirectangular = equirectangular || camera.isEquirectangular();
  result.cameraFile = (folder / (equirectangular ? "cameras.json" : "cameras.txt")).string();
  if (equirectangular) {
    std::vector<CameraInfo> info(result.cameras.size());
    for (CameraInfo& i : info) {
      i.width = s.width;
      i.height = s.height;
    }
    writeCameraJson(result.cameraFile, result.cameras, info);
  } else {
    writeCameraFile(result.cameraFile, result.cameras);
  }

  // Render and write, frame by frame.
  Frame texture, depth;
  for (int frame = 0; frame < s.frames; ++frame) {
    const auto frameStart = std::chrono::steady_clock::now();
    for (size_t c = 0; c < result.cameras.size(); ++c) {
      const RenderedView view = renderView(primitives, result.cameras[c], s.width, s.height, frame, options);
      for (double z : view.depth) {
        if (z == kNoSurface) {
          ++result.emptySamples;
          continue;
        }
        result.trueNearest = std::min(result.trueNearest, z);
        result.trueFarthest = std::max(result.trueFarthest, z);
      }
      colourToYuv420(view, texture);
      result.clampedSamples += depthToYuv420(view, result.depthRange, depth);
      textureWriters[c]->append(texture);
      depthWriters[c]->append(depth);
    }
    log << "frame " << frame << ": " << result.cameras.size() << " camera(s), "
        << formatFixed("%.3f", secondsSince(frameStart)) << " s\n";
  }
  for (auto& writer : textureWriters) writer->commit();
  for (auto& writer : depthWriters) writer->commit();

  // Configs: every camera with a neighbour on each side is a virtual camera once.
  for (size_t v = 1; v + 1 < result.cameras.size(); ++v) {
    const std::string name = fileSafe(result.cameras[v].name);
    const std::string viewSyn = (folder / ("viewsyn_" + name + ".cfg")).string();
    const std::string meshRender = (folder / ("meshrender_" + name + ".cfg")).string();
    writeTextFile(viewSyn, configText(s, result, files, v - 1, v, v + 1, "synth_" + name + ".yuv", "ViewSyn"));
    writeTextFile(meshRender,
                  configText(s, result, files, v - 1, v, v + 1, "meshrender_" + name + ".yuv", "MeshRender"));
    result.viewSynConfigs.push_back(viewSyn);
    result.meshRenderConfigs.push_back(meshRender);
  }
  result.seconds = secondsSince(start);
  return result;
}

int runSceneGen(const Config& config) {
  const SceneGenSettings settings = readSceneGenSettings(config);
  std::ostream& log = std::cout;
  log << "SceneGen " << VS_VERSION << (config.configPath().empty() ? std::string() : " " + config.configPath())
      << "\n\n"
      << settingsText(settings) << "\nscene " << settings.scene << ": "
      << (settings.sceneFile.empty() ? sceneDescription(settings.scene) : settings.description) << "\n";
  const std::vector<Primitive> primitives = buildScene(settings);
  for (const Primitive& p : primitives)
    log << "  " << std::left << std::setw(9) << p.name << " " << shapeName(p.shape)
        << (p.motion.isStatic() || settings.motionScale == 0.0 ? "" : ", moving") << "\n";
  log << "\n";
  const SceneGenResult result = generateScene(settings, log);
  log << "\nwrote " << result.cameras.size() << " camera(s) x " << settings.frames << " frame(s) to "
      << settings.outputFolder << " in " << formatFixed("%.2f", result.seconds) << " s ("
      << formatFixed("%.3f", result.seconds / settings.frames) << " s per frame)\n"
      << "  depth range: Znear " << exactNumberText(result.depthRange.znear) << ", Zfar "
      << exactNumberText(result.depthRange.zfar) << ", " << settings.depthBitDepth << " bits; rendered depths "
      << exactNumberText(result.trueNearest) << " to " << exactNumberText(result.trueFarthest) << "\n"
      << "  " << result.cameraFile << "\n";
  for (size_t c = 0; c < result.cameras.size(); ++c)
    log << "  " << result.texturePaths[c] << ", " << result.depthPaths[c] << "\n";
  for (size_t k = 0; k < result.viewSynConfigs.size(); ++k)
    log << "  " << result.viewSynConfigs[k] << ", " << result.meshRenderConfigs[k] << "\n";
  if (result.viewSynConfigs.empty())
    log << "  no synthesis configs: a virtual camera needs a neighbour on each side (3 cameras or more)\n";
  if (result.clampedSamples > 0)
    log << "warning: " << result.clampedSamples
        << " depth sample(s) lay outside [NearestDepthValue, FarthestDepthValue] and were clamped\n";
  if (result.emptySamples > 0)
    log << "note: " << result.emptySamples << " pixel centre(s) see no object: depth level 0, black texture\n";
  return 0;
}

}  // namespace vs
