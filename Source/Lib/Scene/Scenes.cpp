#include "Scene/Scenes.h"

#include <algorithm>

#include "Common/Error.h"

namespace vs {

namespace {

Texture checker(Rgb a, Rgb b, double cell, double detail, uint32_t seed) {
  Texture t;
  t.pattern = Pattern::Checker;
  t.colourA = a;
  t.colourB = b;
  t.scale = cell;
  t.detail = detail;
  t.detailScale = cell / 6.0;
  t.seed = seed;
  return t;
}

Texture noise(Rgb a, Rgb b, double period, int octaves, double detail, uint32_t seed) {
  Texture t;
  t.pattern = Pattern::Noise;
  t.colourA = a;
  t.colourB = b;
  t.scale = period;
  t.octaves = octaves;
  t.detail = detail;
  t.detailScale = period / 40.0;
  t.seed = seed;
  return t;
}

Texture stripes(Rgb a, Rgb b, double period, Vec3 across, Vec3 bands, double bandWidth, double detail, uint32_t seed) {
  Texture t;
  t.pattern = Pattern::Stripes;
  t.colourA = a;
  t.colourB = b;
  t.scale = period;
  t.direction = across;
  t.bandDirection = bands;
  t.bandWidth = bandWidth;
  t.detail = detail;
  t.detailScale = period / 3.0;
  t.seed = seed;
  return t;
}

Texture gradient(Rgb a, Rgb b, double length, Vec3 along, double detail, uint32_t seed) {
  Texture t;
  t.pattern = Pattern::Gradient;
  t.colourA = a;
  t.colourB = b;
  t.scale = length;
  t.direction = along;
  t.detail = detail;
  t.detailScale = length / 30.0;
  t.seed = seed;
  return t;
}

Texture rings(Rgb a, Rgb b, double period, double detail, uint32_t seed) {
  Texture t;
  t.pattern = Pattern::Rings;
  t.colourA = a;
  t.colourB = b;
  t.scale = period;
  t.detail = detail;
  t.detailScale = period / 2.0;
  t.seed = seed;
  return t;
}

Primitive primitive(const char* name, Shape shape, Vec3 halfSize, Vec3 position, Texture texture) {
  Primitive p;
  p.name = name;
  p.shape = shape;
  p.halfSize = halfSize;
  p.position = position;
  p.texture = texture;
  return p;
}

// Object axes x -> world x, y -> world z, z (the normal) -> world -y: a horizontal rectangle.
Mat3 horizontal() {
  Mat3 m;
  m[0][0] = 1.0;
  m[2][1] = 1.0;
  m[1][2] = -1.0;
  return m;
}

// A fronto-parallel backdrop at z = depth, wide enough for every camera of the presets.
Primitive backdrop(double depth, Texture texture) {
  const double half = std::max(4.0, depth * 1.2);
  return primitive("backdrop", Shape::Rectangle, {half, half, 0.0}, {0.0, 0.0, depth}, texture);
}

// The floor: horizontal, 1.3 below the cameras, from z = 1.5 to the backdrop.
Primitive floorRectangle(double farZ) {
  const double nearZ = 1.5;
  const double length = std::max(farZ - nearZ, 0.1);
  Primitive p =
      primitive("floor", Shape::Rectangle, {std::max(4.0, farZ * 1.2), length / 2.0, 0.0},
                {0.0, 1.3, nearZ + length / 2.0}, checker({0.78f, 0.74f, 0.66f}, {0.30f, 0.26f, 0.22f}, 0.4, 0.35, 11));
  p.orientation = horizontal();
  return p;
}

// Several objects at different depths, some moving: the demo and tiny scenes.
std::vector<Primitive> demoObjects(const SceneGenSettings& s) {
  std::vector<Primitive> scene;
  scene.push_back(backdrop(s.backgroundDepth, noise({0.20f, 0.32f, 0.55f}, {0.88f, 0.78f, 0.58f}, 1.5, 5, 0.25, 3)));
  scene.push_back(floorRectangle(s.backgroundDepth));

  Primitive panel =
      primitive("panel", Shape::Rectangle, {1.0, 0.6, 0.0}, {0.3, -0.9, 5.8},
                stripes({0.08f, 0.08f, 0.10f}, {0.95f, 0.93f, 0.88f}, 0.16, {1, 0, 0}, {0, 1, 0}, 0.4, 0.15, 5));
  panel.orientation = axisAngleRotation({0, 1, 0}, -20.0);
  scene.push_back(panel);

  Primitive pillar = primitive("pillar", Shape::Box, {0.25, 2.0, 0.25}, {2.4, -0.3, 6.5},
                               gradient({0.95f, 0.85f, 0.30f}, {0.25f, 0.55f, 0.30f}, 4.0, {0, 1, 0}, 0.2, 7));
  scene.push_back(pillar);

  Primitive globe = primitive("globe", Shape::Sphere, {0.8, 0.8, 0.8}, {-1.1, 0.2, 4.5},
                              noise({0.75f, 0.22f, 0.12f}, {0.98f, 0.80f, 0.35f}, 0.35, 4, 0.2, 13));
  globe.motion.spinAxis = {0, 1, 0};
  globe.motion.spinDegrees = 3.0;
  scene.push_back(globe);

  Primitive cube = primitive("cube", Shape::Box, {0.45, 0.45, 0.45}, {1.2, 0.4, 3.6},
                             checker({0.15f, 0.25f, 0.70f}, {0.95f, 0.85f, 0.25f}, 0.15, 0.25, 17));
  cube.orientation = axisAngleRotation({1, 0, 0}, 15.0) * axisAngleRotation({0, 1, 0}, 30.0);
  cube.motion.velocity = {-0.01, 0.0, 0.0};
  cube.motion.spinAxis = {0.3, 1.0, 0.2};
  cube.motion.spinDegrees = 2.0;
  scene.push_back(cube);

  Primitive ball = primitive("ball", Shape::Sphere, {0.3, 0.3, 0.3}, {-0.2, -0.3, 2.4},
                             rings({0.10f, 0.50f, 0.25f}, {0.92f, 0.95f, 0.90f}, 0.08, 0.2, 19));
  ball.orientation = axisAngleRotation({1, 0, 0}, 70.0);
  ball.motion.velocity = {0.035, 0.01, 0.0};
  ball.motion.spinAxis = {1, 0, 0};
  ball.motion.spinDegrees = 4.0;
  scene.push_back(ball);
  return scene;
}

// Objects around the arc rig's focus (0, 0, 5).
std::vector<Primitive> arcObjects(const SceneGenSettings& s) {
  std::vector<Primitive> scene;
  scene.push_back(backdrop(s.backgroundDepth, noise({0.35f, 0.30f, 0.25f}, {0.75f, 0.85f, 0.90f}, 1.2, 5, 0.25, 23)));
  scene.push_back(floorRectangle(s.backgroundDepth));

  Primitive tower = primitive("tower", Shape::Box, {0.5, 0.9, 0.5}, {0.0, 0.4, 5.0},
                              checker({0.85f, 0.20f, 0.20f}, {0.95f, 0.95f, 0.85f}, 0.2, 0.25, 29));
  tower.orientation = axisAngleRotation({0, 1, 0}, 20.0);
  tower.motion.spinAxis = {0, 1, 0};
  tower.motion.spinDegrees = 3.0;
  scene.push_back(tower);

  Primitive moon = primitive("moon", Shape::Sphere, {0.6, 0.6, 0.6}, {-1.3, -0.2, 6.0},
                             noise({0.45f, 0.22f, 0.55f}, {0.98f, 0.75f, 0.85f}, 0.3, 4, 0.2, 31));
  moon.motion.spinAxis = {0.2, 1, 0};
  moon.motion.spinDegrees = 4.0;
  scene.push_back(moon);

  Primitive marble = primitive("marble", Shape::Sphere, {0.35, 0.35, 0.35}, {1.0, 0.2, 3.8},
                               rings({0.20f, 0.35f, 0.80f}, {0.95f, 0.90f, 0.60f}, 0.1, 0.2, 37));
  marble.motion.velocity = {-0.03, 0.0, 0.01};
  scene.push_back(marble);

  Primitive sign =
      primitive("sign", Shape::Rectangle, {0.8, 0.5, 0.0}, {1.6, -1.0, 7.0},
                stripes({0.05f, 0.05f, 0.05f}, {0.95f, 0.95f, 0.95f}, 0.2, {1, 0, 0}, {0, 1, 0}, 0.33, 0.1, 41));
  sign.orientation = axisAngleRotation({0, 1, 0}, 25.0);
  scene.push_back(sign);
  return scene;
}

}  // namespace

const std::vector<std::string>& builtInSceneNames() {
  static const std::vector<std::string> names{"demo", "arc", "plane", "sphere", "tiny"};
  return names;
}

std::string sceneDescription(const std::string& name) {
  if (name == "demo")
    return "3-camera parallel rig, 1024x768, 10 frames: a noise-textured backdrop, a checkered floor, a striped "
           "panel, a gradient pillar, a spinning globe, a moving cube and a moving ringed ball";
  if (name == "arc")
    return "5 cameras on an arc converging on (0, 0, 5), 640x480, 10 frames: backdrop, floor, a spinning tower, "
           "spheres (one moving) and a slanted striped sign";
  if (name == "plane")
    return "one fronto-parallel textured plane at BackgroundDepth filling every view, 3 cameras, 128x96, "
           "2 frames (the texture slides)";
  if (name == "sphere")
    return "a sphere of SphereRadius at SphereDepth on the middle camera's optical axis in front of a checkered "
           "plane at BackgroundDepth, 3 cameras, 160x120, 2 frames (the sphere spins)";
  if (name == "tiny") return "the demo's objects at 64x48, 3 cameras, 3 frames";
  return "?";
}

SceneGenSettings scenePreset(const std::string& name) {
  SceneGenSettings s;  // the in-class defaults are the demo's
  s.scene = name;
  if (name == "demo") return s;
  if (name == "arc") {
    s.width = 640;
    s.height = 480;
    s.rig = RigType::Arc;
    s.cameraCount = 5;
    s.focalLength = 600.0;
    s.arcRadius = 5.0;
    s.arcStepDegrees = 6.0;
    s.backgroundDepth = 10.0;
    return s;
  }
  if (name == "plane") {
    s.width = 128;
    s.height = 96;
    s.frames = 2;
    s.focalLength = 120.0;
    s.backgroundDepth = 5.0;
    return s;
  }
  if (name == "sphere") {
    s.width = 160;
    s.height = 120;
    s.frames = 2;
    s.focalLength = 150.0;
    s.backgroundDepth = 6.0;
    s.sphereRadius = 0.5;
    s.sphereDepth = 3.0;
    return s;
  }
  if (name == "tiny") {
    s.width = 64;
    s.height = 48;
    s.frames = 3;
    s.focalLength = 62.5;  // the demo's field of view
    return s;
  }
  VS_CHECK_MSG(false, "unknown built-in scene name");
  return s;
}

std::vector<Primitive> buildScene(const SceneGenSettings& s) {
  // A scene file's objects, copied through a named local: `return s.objects;` beside the named
  // returns of the built-in scenes inlined here made GCC 12's AddressSanitizer build (with
  // detect_stack_use_after_return) fault in arcObjects' return; this form runs clean.
  std::vector<Primitive> objects;
  if (!s.objects.empty()) {
    objects = s.objects;
    return objects;
  }
  if (s.scene == "demo" || s.scene == "tiny") return demoObjects(s);
  if (s.scene == "arc") return arcObjects(s);
  if (s.scene == "plane") {
    // Large enough to fill any preset camera's view; it slides sideways in its own plane.
    Primitive plane = primitive("plane", Shape::Rectangle, {1e3, 1e3, 0.0}, {0.0, 0.0, s.backgroundDepth},
                                checker({0.85f, 0.80f, 0.70f}, {0.20f, 0.30f, 0.45f}, 0.25, 0.3, 43));
    plane.motion.velocity = {0.01, 0.0, 0.0};
    return {plane};
  }
  if (s.scene == "sphere") {
    std::vector<Primitive> scene;
    Primitive wall = primitive("backdrop", Shape::Rectangle, {1e3, 1e3, 0.0}, {0.0, 0.0, s.backgroundDepth},
                               checker({0.80f, 0.80f, 0.75f}, {0.25f, 0.25f, 0.30f}, 0.3, 0.2, 47));
    scene.push_back(wall);
    Primitive ball =
        primitive("sphere", Shape::Sphere, {s.sphereRadius, s.sphereRadius, s.sphereRadius}, {0.0, 0.0, s.sphereDepth},
                  noise({0.80f, 0.25f, 0.15f}, {0.95f, 0.85f, 0.40f}, 0.25, 4, 0.2, 53));
    ball.motion.spinAxis = {0, 1, 0};
    ball.motion.spinDegrees = 5.0;
    scene.push_back(ball);
    return scene;
  }
  VS_CHECK_MSG(false, "unknown built-in scene name");
  return {};
}

}  // namespace vs
