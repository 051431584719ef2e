#pragma once
// Helpers of the numerical-stability suite (Test/Unit/Stability*.cpp, doc/stability.md): SceneGen
// scenes rendered in process (no files), scenes for the Synthesizer built from any cameras, the
// transforms whose invariance the suite checks (origin shift, unit change, world rotation), frame
// comparisons, and the figures each test prints for the doc.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Camera.h"
#include "Common/Config.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Scene/RayCaster.h"
#include "Scene/SceneGen.h"
#include "Scene/Scenes.h"
#include "Synth/Synthesizer.h"
#include "TestPlan.h"

namespace vs::test {

// A measured figure: recorded as a test property (in the XML report) and printed as
// "[ figure   ] Suite.Test: name = value", the lines doc/stability.md copies.
inline void recordFigure(const std::string& name, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.4g", value);
  ::testing::Test::RecordProperty(name, text);
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::cout << "[ figure   ] " << (info ? std::string(info->test_suite_name()) + "." + info->name() : std::string("?"))
            << ": " << name << " = " << text << std::endl;
}

// A SceneGen scene (doc/scenegen.md) rendered in process from any camera: texture as SceneGen writes it
// (8-bit 4:2:0, BT.601) and exact depth, quantised here with any range, DepthType 0 or 1.
class GeneratedScene {
public:
  // `overrides`: SceneGen keys, e.g. {"Scene=tiny"}; size, focal length, rig as SceneGen reads them.
  explicit GeneratedScene(const std::vector<std::string>& overrides)
      : settings_(readSceneGenSettings(Config::load(sceneGenOptionTable(), "", overrides))),
        primitives_(buildScene(settings_)),
        rig_(buildCameras(settings_)) {
    options_.samplesPerPixel = 4;
    options_.threads = 0;
    options_.motionScale = 0.0;
  }

  int width() const { return settings_.width; }
  int height() const { return settings_.height; }
  const SceneGenSettings& settings() const { return settings_; }
  const std::vector<Camera>& rig() const { return rig_; }
  FrameFormat textureFormat() const { return FrameFormat{width(), height(), 8, ChromaFormat::Yuv420}; }

  // Camera-frame z of the surface on every pixel centre's ray (kNoSurface where none), row-major.
  std::vector<double> depth(const Camera& camera) const {
    return renderDepth(primitives_, camera, width(), height(), 0, options_);
  }

  // The same for a picture of another size (a virtual camera of its own resolution).
  std::vector<double> depth(const Camera& camera, int width, int height) const {
    return renderDepth(primitives_, camera, width, height, 0, options_);
  }
  Frame texture(const Camera& camera, int width, int height) const {
    Frame texture;
    colourToYuv420(renderView(primitives_, camera, width, height, 0, options_), texture);
    return texture;
  }

  // The scene at frame 0, for casting single rays.
  PlacedScene placed() const { return PlacedScene(primitives_, 0.0, 0.0); }

  // The camera's true texture (SceneGen's output for it).
  Frame texture(const Camera& camera) const {
    Frame texture;
    colourToYuv420(renderView(primitives_, camera, width(), height(), 0, options_), texture);
    return texture;
  }

  // Depth levels of `range` for DepthType 0 (camera z) or 1 (world z); no surface gives level 0.
  Plane depthLevels(const Camera& camera, const DepthRange& range, int depthType) const {
    return quantise(camera, depth(camera), range, depthType);
  }

  Plane quantise(const Camera& camera, const std::vector<double>& z, const DepthRange& range, int depthType) const {
    Plane levels(width(), height(), 0);
    for (int v = 0; v < height(); ++v)
      for (int u = 0; u < width(); ++u) {
        const double zCam = z[size_t(v) * width() + u];
        if (zCam == kNoSurface) continue;
        const double value = depthType == kDepthTypeWorld ? camera.backProject(u, v, zCam).z : zCam;
        levels.at(u, v) = uint16_t(zToLevelRounded(value, range));
      }
    return levels;
  }

  // Camera-frame depth range of what the cameras see, widened by `margin` (as SceneGen's automatic one).
  DepthRange cameraRange(const std::vector<Camera>& cameras, int bitDepth, double margin = 0.02) const {
    double nearest = HUGE_VAL, farthest = 0;
    for (const Camera& camera : cameras)
      for (double z : depth(camera))
        if (z != kNoSurface) {
          nearest = std::min(nearest, z);
          farthest = std::max(farthest, z);
        }
    return DepthRange{nearest / (1 + margin), farthest * (1 + margin), bitDepth};
  }

private:
  SceneGenSettings settings_;
  std::vector<Primitive> primitives_;
  std::vector<Camera> rig_;
  RenderOptions options_;
};

// The reference frames of one synthesis.
struct SynthesisInputs {
  std::vector<Frame> textures;
  std::vector<Plane> depths;

  std::vector<ReferenceFrame> frames() const {
    std::vector<ReferenceFrame> references;
    for (size_t k = 0; k < textures.size(); ++k) references.push_back(ReferenceFrame{&textures[k], &depths[k]});
    return references;
  }
};

// A Scene as a general-mode VSRS config has it (Precision 4, Filter 1, ViewBlending 0), every view with
// the same depth range.
inline Scene makeScene(const std::vector<Camera>& references, const Camera& virtualCamera, const FrameFormat& textureFormat,
                       const DepthRange& range, int depthType = kDepthTypeCamera) {
  Scene scene;
  SynthesisSettings& s = scene.settings;
  s.textureFormat = textureFormat;
  s.depthFormat = FrameFormat{textureFormat.width, textureFormat.height, range.bitDepth, ChromaFormat::Yuv420};
  s.depthType = depthType;
  s.precision = 4;
  s.filter = 1;
  for (size_t k = 0; k < references.size(); ++k) {
    ReferenceView view;
    view.label = references.size() == 2 ? (k == 0 ? "Left" : "Right") : "Reference " + std::to_string(k + 1);
    view.cameraName = references[k].name;
    view.depthRange = range;
    view.depthFormat = s.depthFormat;
    view.camera = references[k];
    s.references.push_back(view);
  }
  s.virtualCameraName = virtualCamera.name;
  s.virtualDepthRange = range;
  scene.virtualCamera = virtualCamera;
  return scene;
}

// Renders the references of `scene` (with its depth type and ranges) from a generated scene.
inline SynthesisInputs renderInputs(const GeneratedScene& generated, const Scene& scene) {
  SynthesisInputs inputs;
  for (const ReferenceView& view : scene.settings.references) {
    inputs.textures.push_back(generated.texture(view.camera));
    inputs.depths.push_back(generated.depthLevels(view.camera, view.depthRange, scene.settings.depthType));
  }
  return inputs;
}

struct SynthesisResult {
  Frame output;
  size_t holesAfterBlend = 0;
};

inline SynthesisResult synthesize(const Scene& scene, const SynthesisInputs& inputs,
                                  SynthesisMode mode = SynthesisMode::General) {
  Synthesizer synthesizer(scene, planOnPath(scene, mode));
  SynthesisResult result;
  StageTimes times;
  synthesizer.synthesize(inputs.frames(), result.output, times);
  result.holesAfterBlend = synthesizer.lastStats().holesAfterBlend;
  return result;
}

// Differences over every plane of two frames of one format.
struct FrameDifference {
  int maxAbs = 0;          // largest |a - b| in code values
  size_t differing = 0;    // samples that differ at all
  size_t beyondOne = 0;    // samples that differ by more than 1
};

inline FrameDifference compareFrames(const Frame& a, const Frame& b) {
  FrameDifference d;
  EXPECT_EQ(a.format, b.format);
  if (a.format != b.format) {
    d.maxAbs = std::numeric_limits<int>::max();
    return d;
  }
  for (int p = 0; p < planeCount(a.format.chroma); ++p)
    for (size_t i = 0; i < a.planes[p].samples.size(); ++i) {
      const int difference = std::abs(int(a.planes[p].samples[i]) - int(b.planes[p].samples[i]));
      d.maxAbs = std::max(d.maxAbs, difference);
      d.differing += difference != 0;
      d.beyondOne += difference > 1;
    }
  return d;
}

// Output samples that no input explains: outside [min, max] of that plane over the inputs, widened by
// `margin` (interpolation overshoot), and not the hole filler's empty value. A NaN anywhere in the
// pipeline ends as 0 (the rounding maps NaN to 0), which this counts.
inline size_t unexplainedSamples(const Frame& output, const std::vector<Frame>& inputs, int margin = 24) {
  size_t count = 0;
  const int bitShift = output.format.bitDepth - 8;
  for (int p = 0; p < planeCount(output.format.chroma); ++p) {
    int lo = output.format.maxValue(), hi = 0;
    for (const Frame& input : inputs)
      for (uint16_t s : input.planes[p].samples) {
        lo = std::min(lo, int(s));
        hi = std::max(hi, int(s));
      }
    const int empty = p == 0 ? 16 << bitShift : 128 << bitShift;
    for (uint16_t s : output.planes[p].samples)
      if (s != empty && (s < lo - margin || s > hi + margin)) ++count;
  }
  return count;
}

inline bool allSamplesEqual(const Plane& plane, uint16_t value) {
  return std::all_of(plane.samples.begin(), plane.samples.end(), [&](uint16_t s) { return s == value; });
}

// One synthesis problem: a generated scene, the Scene handed to the Synthesizer and its inputs.
struct Case {
  std::string name;
  std::shared_ptr<GeneratedScene> generated;
  Scene scene;
  SynthesisInputs inputs;
};

// SceneGen `tiny` (64x48, f = 62.5, the demo's objects at z 2.1 to 8): references cam0 and cam2
// (x = -0.1, +0.1), virtual camera off-centre at x = 0.03 so the blend weights are unequal.
inline const Case& tinyCase() {
  static const Case c = [] {
    Case k;
    k.name = "tiny";
    k.generated = std::make_shared<GeneratedScene>(std::vector<std::string>{"Scene=tiny"});
    const std::vector<Camera>& rig = k.generated->rig();
    Camera virtualCamera = rig[1];
    virtualCamera.name = "virtual";
    virtualCamera.t.x = 0.03;
    const DepthRange range = k.generated->cameraRange({rig[0], rig[2], virtualCamera}, 8);
    k.scene = makeScene({rig[0], rig[2]}, virtualCamera, k.generated->textureFormat(), range);
    k.inputs = renderInputs(*k.generated, k.scene);
    return k;
  }();
  return c;
}

// SceneGen `arc` at 160x120 (f = 150): cameras 6 degrees apart converging on (0, 0, 5); references
// cam1 and cam3, the virtual camera cam2 moved 0.05 sideways (not on the arc).
inline const Case& arcCase() {
  static const Case c = [] {
    Case k;
    k.name = "arc";
    k.generated = std::make_shared<GeneratedScene>(std::vector<std::string>{"Scene=arc", "SourceWidth=160", "SourceHeight=120"});
    const std::vector<Camera>& rig = k.generated->rig();
    Camera virtualCamera = rig[2];
    virtualCamera.name = "virtual";
    virtualCamera.t.x += 0.05;
    const DepthRange range = k.generated->cameraRange({rig[1], rig[3], virtualCamera}, 8);
    k.scene = makeScene({rig[1], rig[3]}, virtualCamera, k.generated->textureFormat(), range);
    k.inputs = renderInputs(*k.generated, k.scene);
    return k;
  }();
  return c;
}

inline std::vector<const Case*> allCases() { return {&tinyCase(), &arcCase()}; }

// --- Transforms of a whole scene that must not change a DepthType 0 synthesis ----------------------

// Every camera centre moved by `offset` (the world origin moved by -offset).
inline void shiftOrigin(Scene& scene, const Vec3& offset) {
  for (ReferenceView& view : scene.settings.references) view.camera.t += offset;
  scene.virtualCamera.t += offset;
}

// Every translation and every depth range multiplied by `factor` (metres to millimetres: 1000).
inline void scaleUnits(Scene& scene, double factor) {
  auto scale = [&](DepthRange& range) {
    range.znear *= factor;
    range.zfar *= factor;
  };
  for (ReferenceView& view : scene.settings.references) {
    view.camera.t *= factor;
    scale(view.depthRange);
  }
  scene.virtualCamera.t *= factor;
  scale(scene.settings.virtualDepthRange);
}

// The world rotated by Q (X' = Q X): every camera gets R' = R Q^T and centre Q t.
inline Camera rotateWorld(const Camera& camera, const Mat3& Q) {
  Camera c = camera;
  c.R = camera.R * transpose(Q);
  c.t = Q * camera.t;
  return c;
}

inline void rotateWorld(Scene& scene, const Mat3& Q) {
  for (ReferenceView& view : scene.settings.references) view.camera = rotateWorld(view.camera, Q);
  scene.virtualCamera = rotateWorld(scene.virtualCamera, Q);
}

// Exact quarter turns (entries 0 and +-1) about world axis 0 (x), 1 (y) or 2 (z), `turns` times.
inline Mat3 quarterTurn(int axis, int turns) {
  Mat3 q = Mat3::identity();
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  Mat3 one = Mat3::identity();
  one[a][a] = one[b][b] = 0;
  one[a][b] = -1;
  one[b][a] = 1;
  for (int k = 0; k < ((turns % 4) + 4) % 4; ++k) q = one * q;
  return q;
}

}  // namespace vs::test
