#pragma once
// Small analytic scenes for synthesis tests, built in code: cameras of a parallel rig looking down +z
// at a textured plane z = planeZ (and optionally a nearer textured square), with exact depth. The
// texture is a smooth function of the world point, so any camera's true view is known everywhere.
#include <cmath>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Synth/Synthesizer.h"
#include "TestPlan.h"

namespace vs::test {

struct AnalyticScene {
  int width = 64;
  int height = 48;
  double focal = 60.0;
  double planeZ = 100.0;
  bool square = false;         // a square at z = squareZ covering |X|, |Y| < squareHalf
  double squareZ = 60.0;
  double squareHalf = 8.0;
  DepthRange range{50.0, 120.0, 8};
  int bitDepth = 8;
  int depthType = 0;           // 0: levels code camera z; 1: levels code world z
  ChromaFormat chroma = ChromaFormat::Yuv420;

  Camera camera(const std::string& name, double centreX, double centreY = 0, double centreZ = 0) const {
    Camera c;
    c.name = name;
    c.K = Mat3::identity();
    c.K[0][0] = c.K[1][1] = focal;
    c.K[0][2] = (width - 1) / 2.0;
    c.K[1][2] = (height - 1) / 2.0;
    c.t = Vec3(centreX, centreY, centreZ);
    return c;
  }

  // Texture value in [0, 1] at a world point on a surface: smooth, so interpolation error is small.
  static double texture(const Vec3& X, bool onSquare) {
    if (onSquare) return 0.8 + 0.1 * std::sin(0.9 * X.x) * std::cos(0.7 * X.y);
    return 0.45 + 0.2 * std::sin(0.35 * X.x + 0.2 * X.y) + 0.1 * std::cos(0.23 * X.y);
  }

  // First surface hit by the ray of pixel (u, v); false if none.
  bool trace(const Camera& c, double u, double v, Vec3& hit, bool& onSquare) const {
    const Vec3 origin = c.centre(), direction = c.rayDirectionWorld(u, v);
    if (square && direction.z > 0) {
      const double s = (squareZ - origin.z) / direction.z;
      const Vec3 p = origin + direction * s;
      if (s > 0 && std::fabs(p.x) < squareHalf && std::fabs(p.y) < squareHalf) {
        hit = p;
        onSquare = true;
        return true;
      }
    }
    if (direction.z <= 0) return false;
    const double s = (planeZ - origin.z) / direction.z;
    if (s <= 0) return false;
    hit = origin + direction * s;
    onSquare = false;
    return true;
  }

  // Texture (luma from the texture function, chroma a gentle function too) and depth levels.
  void render(const Camera& c, Frame& texture, Plane& depth) const {
    const FrameFormat format{width, height, bitDepth, chroma};
    texture.reset(format);
    texture.fill(0);
    depth.resize(width, height);
    const int maxValue = format.maxValue();
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        Vec3 hit;
        bool onSquare = false;
        if (!trace(c, x, y, hit, onSquare)) continue;
        texture.planes[0].at(x, y) = uint16_t(std::lround(maxValue * this->texture(hit, onSquare)));
        const double z = depthType == 1 ? hit.z : c.worldToCamera(hit).z;
        depth.at(x, y) = uint16_t(zToLevelRounded(z, range));
      }
    if (chroma == ChromaFormat::Yuv400) return;
    const int scale = chroma == ChromaFormat::Yuv420 ? 2 : 1;
    for (int j = 0; j < texture.planes[1].height; ++j)
      for (int i = 0; i < texture.planes[1].width; ++i) {
        Vec3 hit;
        bool onSquare = false;
        const double offset = 0.5 * (scale - 1);
        if (!trace(c, i * scale + offset, j * scale + offset, hit, onSquare)) continue;
        texture.planes[1].at(i, j) = uint16_t(std::lround(maxValue * (0.5 + 0.2 * std::sin(0.3 * hit.x))));
        texture.planes[2].at(i, j) = uint16_t(std::lround(maxValue * (0.5 + 0.2 * std::cos(0.25 * hit.y))));
      }
  }

  // A Scene for the Synthesizer: left and right references, the virtual camera, default settings as
  // VSRS's general-mode configs use them (Precision 4, Filter 1).
  Scene scene(const Camera& left, const Camera& virtualCamera, const Camera& right) const {
    Scene s;
    SynthesisSettings& settings = s.settings;
    settings.textureFormat = FrameFormat{width, height, bitDepth, chroma};
    settings.depthFormat = FrameFormat{width, height, range.bitDepth, ChromaFormat::Yuv420};
    settings.depthType = depthType;
    settings.precision = 4;
    settings.filter = 1;
    for (const Camera* c : {&left, &right}) {
      ReferenceView view;
      view.label = c == &left ? "Left" : "Right";
      view.cameraName = c->name;
      view.depthRange = range;
      view.camera = *c;
      settings.references.push_back(view);
    }
    settings.virtualCameraName = virtualCamera.name;
    s.virtualCamera = virtualCamera;
    return s;
  }
};

// The renders of `scene`'s reference cameras; a test may edit the depths before it synthesizes.
// frames() points into the two vectors: keep this object where it is while they are in use.
struct RenderedReferences {
  std::vector<Frame> textures;
  std::vector<Plane> depths;
  std::vector<ReferenceFrame> frames() {
    std::vector<ReferenceFrame> references;
    for (size_t k = 0; k < textures.size(); ++k) references.push_back(ReferenceFrame{&textures[k], &depths[k]});
    return references;
  }
};

inline RenderedReferences renderReferences(const AnalyticScene& analytic, const Scene& scene) {
  RenderedReferences rendered;
  rendered.textures.resize(scene.settings.references.size());
  rendered.depths.resize(scene.settings.references.size());
  for (size_t k = 0; k < rendered.textures.size(); ++k)
    analytic.render(scene.settings.references[k].camera, rendered.textures[k], rendered.depths[k]);
  return rendered;
}

// Synthesizes one frame of `scene` from the references' renders.
inline Frame synthesizeOnce(const AnalyticScene& analytic, const Scene& scene) {
  RenderedReferences rendered = renderReferences(analytic, scene);
  Synthesizer synthesizer(scene, planOnPath(scene));
  Frame output;
  StageTimes times;
  synthesizer.synthesize(rendered.frames(), output, times);
  return output;
}

}  // namespace vs::test
