// MeshRender through OpenGL (headless EGL; on a CPU-only machine Mesa's llvmpipe): the GL camera against
// the pinhole model, self-rendering, a generated two-view scene against its truth, and the executable.
// Tests that need OpenGL are skipped with the reason when no EGL context can be created.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/CameraFile.h"
#include "Common/Depth.h"
#include "Common/Metrics.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/EglContext.h"
#include "Mesh/GlMeshRenderer.h"
#include "Mesh/MeshProjection.h"
#include "Mesh/MeshSynthesizer.h"
#include "Synth/Warp.h"
#include "Process.h"
#include "TestPaths.h"
#include "TestPlan.h"


namespace fs = std::filesystem;

namespace {

// One renderer for the whole test program: creating contexts again and again is slow on llvmpipe.
// Null with the reason in `eglFailure` when EGL cannot give a context here.
std::string eglFailure;
vs::GlMeshRenderer* sharedRenderer() {
  static std::unique_ptr<vs::GlMeshRenderer> renderer;
  static bool tried = false;
  if (!tried) {
    tried = true;
    try {
      renderer = std::make_unique<vs::GlMeshRenderer>();
    } catch (const vs::InputError& e) {
      eglFailure = e.what();
    }
  }
  return renderer.get();
}

#define REQUIRE_GL()                                                                                 \
  vs::GlMeshRenderer* renderer = sharedRenderer();                                                    \
  if (!renderer) GTEST_SKIP() << "no OpenGL 3.3 core context through EGL on this machine: " << eglFailure; \
  renderer->setSampling(nullptr)

vs::Mat3 rotation(double ax, double ay, double az) {
  vs::Mat3 x = vs::Mat3::identity(), y = vs::Mat3::identity(), z = vs::Mat3::identity();
  x[1][1] = std::cos(ax), x[1][2] = -std::sin(ax), x[2][1] = std::sin(ax), x[2][2] = std::cos(ax);
  y[0][0] = std::cos(ay), y[0][2] = std::sin(ay), y[2][0] = -std::sin(ay), y[2][2] = std::cos(ay);
  z[0][0] = std::cos(az), z[0][1] = -std::sin(az), z[1][0] = std::sin(az), z[1][1] = std::cos(az);
  return z * y * x;
}

constexpr int kWidth = 160, kHeight = 120;
const vs::Vec3 kWorldOffset(5.0e4, -3.0e4, 0.0);  // far from the origin: precision must not suffer

vs::Camera makeCamera(const std::string& name, const vs::Vec3& centre, double ax, double ay, double az, double skew) {
  vs::Camera camera;
  camera.name = name;
  camera.K[0][0] = 200.0, camera.K[0][1] = skew, camera.K[0][2] = 80.3;
  camera.K[1][1] = 190.0, camera.K[1][2] = 59.6;
  camera.R = rotation(ax, ay, az);
  camera.t = kWorldOffset + centre;
  return camera;
}

// A textured slanted plane seen by three cameras (left, right, virtual between them) with skew and
// small rotations. Depth is generated exactly, then quantised to 8-bit levels.
struct PlaneScene {
  vs::Scene scene;
  std::vector<vs::Frame> textures;
  std::vector<vs::Plane> depths;
  vs::Frame truth;  // the virtual view, rendered from the same plane and texture
  vs::Vec3 planePoint, planeNormal;

  std::vector<vs::ReferenceFrame> frames() const {
    std::vector<vs::ReferenceFrame> references;
    for (size_t k = 0; k < textures.size(); ++k) references.push_back({&textures[k], &depths[k]});
    return references;
  }
};

// Smooth texture on the plane, a function of the world point (periods of 10 to 40 pixels).
double textureLuma(const vs::Vec3& X) {
  const vs::Vec3 p = X - kWorldOffset;
  return 120.0 + 45.0 * std::sin(0.23 * p.x + 0.3) * std::cos(0.19 * p.y) + 25.0 * std::sin(0.09 * p.x - 0.07 * p.y);
}
double textureU(const vs::Vec3& X) { return 128.0 + 30.0 * std::sin(0.11 * (X - kWorldOffset).x); }
double textureV(const vs::Vec3& X) { return 128.0 + 30.0 * std::cos(0.08 * (X - kWorldOffset).y); }

uint16_t toLevel(double value) { return uint16_t(std::clamp(std::lround(value), 0L, 255L)); }

// The plane point on pixel (u, v)'s ray (false when the ray misses it).
bool hitPlane(const PlaneScene& s, const vs::Camera& camera, double u, double v, vs::Vec3& X, double& zCam) {
  const vs::Vec3 ray = vs::inverse(camera.R) * camera.pixelToCamera(u, v, 1.0);
  const double denominator = vs::dot(s.planeNormal, ray);
  if (std::fabs(denominator) < 1e-12) return false;
  zCam = vs::dot(s.planeNormal, s.planePoint - camera.t) / denominator;
  X = camera.t + ray * zCam;
  return zCam > 0;
}

// Renders the plane's texture into `camera` by ray casting (luma at pixel centres, chroma at chroma
// sample centres), and its depth levels.
void castView(const PlaneScene& s, const vs::Camera& camera, int depthType, const vs::DepthRange& range,
              vs::Frame& texture, vs::Plane* depth) {
  texture.reset(s.scene.settings.textureFormat);
  if (depth) *depth = vs::Plane(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      vs::Vec3 X;
      double zCam = 0;
      const bool hit = hitPlane(s, camera, x, y, X, zCam);
      texture.planes[0].at(x, y) = hit ? toLevel(textureLuma(X)) : 16;
      if (depth) depth->at(x, y) = uint16_t(vs::zToLevelRounded(depthType == 0 ? zCam : X.z, range));
    }
  for (int j = 0; j < kHeight / 2; ++j)
    for (int i = 0; i < kWidth / 2; ++i) {
      vs::Vec3 X;
      double zCam = 0;
      const bool hit = hitPlane(s, camera, 2 * i + 0.5, 2 * j + 0.5, X, zCam);
      texture.planes[1].at(i, j) = hit ? toLevel(textureU(X)) : 128;
      texture.planes[2].at(i, j) = hit ? toLevel(textureV(X)) : 128;
    }
}

PlaneScene makePlaneScene(int depthType, double zfar = 450.0) {
  PlaneScene s;
  vs::SynthesisSettings& settings = s.scene.settings;
  settings.depthType = depthType;
  settings.textureFormat = vs::FrameFormat{kWidth, kHeight, 8, vs::ChromaFormat::Yuv420};
  settings.depthFormat = settings.textureFormat;
  settings.precision = 4;
  settings.filter = 1;
  settings.ivsrsInpaint = true;
  const vs::Camera left = makeCamera("left", {0, 0, 0}, 0.02, -0.03, 0.01, 2.5);
  const vs::Camera right = makeCamera("right", {20, 1, 0}, 0.01, 0.04, -0.01, 2.5);
  s.scene.virtualCamera = makeCamera("virtual", {10, 0.5, 0}, 0.015, 0.005, 0.0, -1.5);
  s.planePoint = kWorldOffset + vs::Vec3(0, 0, 300);
  s.planeNormal = vs::Vec3(0.25, -0.1, 1.0) / vs::norm(vs::Vec3(0.25, -0.1, 1.0));
  vs::DepthRange range;
  range.znear = 200;
  range.zfar = zfar;
  range.bitDepth = 8;
  const vs::Camera cameras[2] = {left, right};
  const char* labels[2] = {"Left", "Right"};
  s.textures.resize(2);
  s.depths.resize(2);
  for (int k = 0; k < 2; ++k) {
    vs::ReferenceView view;
    view.label = labels[k];
    view.cameraName = cameras[k].name;
    view.camera = cameras[k];
    view.depthRange = range;
    settings.references.push_back(view);
    castView(s, cameras[k], depthType, range, s.textures[k], &s.depths[k]);
  }
  castView(s, s.scene.virtualCamera, depthType, range, s.truth, nullptr);
  return s;
}

// Builds a mesh of view k of the scene and renders it into `virtualCamera` (luma, exact bilinear).
void renderView(vs::GlMeshRenderer& renderer, const PlaneScene& s, size_t k, const vs::Camera& virtualCamera,
                vs::DepthMesh& mesh, vs::WarpedLayer& layer, vs::RenderExtras& extras) {
  const vs::ReferenceView& view = s.scene.settings.references[k];
  vs::MeshOptions options;
  options.depthType = s.scene.settings.depthType;
  vs::DepthMeshBuilder(view.camera, view.depthRange, kWidth, kHeight, options).build(s.depths[k], mesh);
  vs::InverseDepthRange range;
  ASSERT_TRUE(vs::sceneInverseDepthRange(view.camera, view.depthRange, options.depthType, kWidth, kHeight,
                                         virtualCamera, range));
  const vs::RenderGrid grid = vs::lumaGrid(virtualCamera, kWidth, kHeight);
  renderer.uploadMesh(mesh);
  renderer.uploadTexture({&s.textures[k].planes[0]});
  renderer.render(vs::meshClipMatrix(view.camera, virtualCamera, grid, vs::clipPlanes(range)), grid, vs::TexelMap{},
                  layer, &extras);
}

// The client extension strings are those of real EGL implementations: Mesa 22 (Debian 12) names
// device enumeration on its own, NVIDIA's driver 580 (seen on an H100 machine) only the older
// EGL_EXT_device_base, which holds enumeration and query; without EGL_EXT_platform_device no display
// can be opened on a device, and query alone enumerates nothing.
TEST(MeshRenderEgl, DevicePlatformIsOfferedUnderEitherExtensionName) {
  EXPECT_TRUE(vs::eglOffersDevicePlatform(
      "EGL_EXT_device_base EGL_EXT_device_enumeration EGL_EXT_device_query EGL_EXT_platform_base "
      "EGL_EXT_platform_device EGL_MESA_platform_surfaceless"));
  EXPECT_TRUE(vs::eglOffersDevicePlatform(
      "EGL_EXT_platform_base EGL_EXT_device_base EGL_KHR_client_get_all_proc_addresses EGL_EXT_client_extensions "
      "EGL_KHR_debug EGL_KHR_platform_x11 EGL_EXT_platform_x11 EGL_EXT_platform_device "
      "EGL_MESA_platform_surfaceless EGL_EXT_explicit_device"));
  EXPECT_FALSE(vs::eglOffersDevicePlatform("EGL_EXT_device_query EGL_EXT_platform_device"));
  EXPECT_FALSE(vs::eglOffersDevicePlatform("EGL_EXT_device_base EGL_EXT_device_enumeration EGL_MESA_platform_surfaceless"));
  EXPECT_FALSE(vs::eglOffersDevicePlatform("EGL_EXT_device_base_x EGL_EXT_platform_device"));  // whole names only
  EXPECT_FALSE(vs::eglOffersDevicePlatform(nullptr));
}

TEST(MeshRenderGl, ContextIsOpenGl33CoreWithoutADisplay) {
  REQUIRE_GL();
  std::printf("OpenGL: %s\n", renderer->description().c_str());
  EXPECT_NE(renderer->description().find("OpenGL"), std::string::npos);
}

// Known 3D points through the OpenGL path: each point P gets a small planar triangle mesh around it
// whose vertices carry their own reference pixel positions; the renderer reads back, per fragment, the
// reference position of the surface point under the fragment's centre. Where that read-back position
// equals P's own reference position is where OpenGL put P (solved to sub-pixel precision from the
// fragments around it, where the map is linear to well under 1e-4 px). It must agree with the pinhole
// projection of P to 0.01 px.
TEST(MeshRenderGl, KnownPointsLandWhereThePinholeModelPutsThem) {
  REQUIRE_GL();
  const vs::Camera reference = makeCamera("reference", {0, 0, 0}, 0.05, -0.08, 0.03, 4.0);
  const vs::Camera virtualCamera = makeCamera("virtual", {35, -12, 20}, -0.06, 0.11, -0.04, -3.0);
  const vs::RenderGrid grid = vs::lumaGrid(virtualCamera, kWidth, kHeight);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0;
  int tested = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // A point in front of both cameras, inside the virtual picture away from its border.
    const vs::Vec3 P = virtualCamera.backProject(80 + 60 * unit(random), 60 + 45 * unit(random), 250 + 80 * unit(random));
    double px, py, pz, ru, rv, rz;
    ASSERT_TRUE(virtualCamera.project(P, px, py, pz));
    ASSERT_TRUE(reference.project(P, ru, rv, rz));
    // Triangle around P, about 40 units (30 virtual pixels) across, in a random plane; P lies at
    // barycentric (0.27, 0.40, 0.33), several pixels inside every edge.
    vs::Vec3 e1(unit(random), unit(random), 0.3 * unit(random));
    e1 = e1 * (20.0 / vs::norm(e1));
    vs::Vec3 e2(-e1.y, e1.x, 0.2 * unit(random) * 20.0);
    e2 = e2 * (20.0 / vs::norm(e2));
    const vs::Vec3 corners[3] = {P + e1 + e2, P - e1 + e2 * 0.3, P - e2 * 1.2 + e1 * 0.4};
    vs::DepthMesh mesh;
    mesh.columns = 3;
    mesh.rows = 1;
    mesh.triangles = {0, 1, 2};
    for (const vs::Vec3& corner : corners) {
      double u, v, z;
      ASSERT_TRUE(reference.project(corner, u, v, z));
      mesh.vertices.insert(mesh.vertices.end(), {float(u), float(v), 1.0f, float(1.0 / z)});
      mesh.boundary.push_back(0);
      mesh.valid.push_back(1);
    }
    const vs::Mat4 clip = vs::meshClipMatrix(reference, virtualCamera, grid, vs::clipPlanes({1.0 / 400, 1.0 / 150}));
    vs::WarpedLayer layer;
    vs::RenderExtras extras;
    renderer->uploadMesh(mesh);
    const vs::Plane blank(4, 4, 0);
    renderer->uploadTexture({&blank});
    renderer->render(clip, grid, vs::TexelMap{}, layer, &extras);
    // Least-squares fit of the read-back reference position over the 3x3 fragments around P:
    // r(x, y) = r0 + J (x - x0, y - y0), then solve r = (ru, rv).
    const int x0 = int(std::lround(px)), y0 = int(std::lround(py));
    double sxx = 0, sxy = 0, syy = 0, n = 0, su[3] = {0, 0, 0}, sv[3] = {0, 0, 0};
    bool complete = true;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const size_t i = size_t(y0 + dy) * kWidth + size_t(x0 + dx);
        if (!layer.valid(i)) {
          complete = false;
          continue;
        }
        const double u = extras.referenceU[i], v = extras.referenceV[i];
        sxx += dx * dx, sxy += dx * dy, syy += dy * dy, n += 1;
        su[0] += u, su[1] += u * dx, su[2] += u * dy;
        sv[0] += v, sv[1] += v * dx, sv[2] += v * dy;
      }
    ASSERT_TRUE(complete) << "the triangle around point " << trial << " does not cover the 3x3 fragments around it";
    // The 3x3 grid is symmetric: the normal equations decouple (sums of dx, dy and dx dy vanish).
    ASSERT_EQ(sxy, 0.0);
    const double u0 = su[0] / n, ux = su[1] / sxx, uy = su[2] / syy;
    const double v0 = sv[0] / n, vx = sv[1] / sxx, vy = sv[2] / syy;
    const double det = ux * vy - uy * vx;
    const double dx = ((ru - u0) * vy - uy * (rv - v0)) / det;
    const double dy = (ux * (rv - v0) - (ru - u0) * vx) / det;
    const double glX = x0 + dx, glY = y0 + dy;
    const double error = std::hypot(glX - px, glY - py);
    worst = std::max(worst, error);
    EXPECT_LT(error, 0.01) << "point " << trial << ": OpenGL (" << glX << ", " << glY << "), pinhole (" << px << ", "
                           << py << ")";
    // The read-back inverse depth is the pinhole's 1 / z_virtual there.
    EXPECT_NEAR(layer.inverseDepth[size_t(y0) * kWidth + size_t(x0)] * pz, 1.0, 0.01);
    ++tested;
  }
  std::printf("%d points: largest distance between OpenGL and the pinhole model %.5f px\n", tested, worst);
}

// Every fragment of a rendered depth mesh shows the reference pixel that ViewSyn's pinhole warp
// (ViewProjection::backward) gives for that virtual pixel at the read-back depth: DepthType 0 and 1.
TEST(MeshRenderGl, ReadBackPositionsAgreeWithViewSynsWarp) {
  REQUIRE_GL();
  for (int depthType : {0, 1}) {
    const PlaneScene s = makePlaneScene(depthType);
    vs::DepthMesh mesh;
    vs::WarpedLayer layer;
    vs::RenderExtras extras;
    renderView(*renderer, s, 0, s.scene.virtualCamera, mesh, layer, extras);
    EXPECT_TRUE(mesh.points.empty());  // a plane: nothing dropped
    const vs::ViewProjection projection(s.scene.settings.references[0].camera, s.scene.virtualCamera, depthType);
    double worst = 0;
    size_t drawn = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = size_t(y) * kWidth + x;
        if (!layer.valid(i)) continue;
        double u, v;
        ASSERT_TRUE(projection.backward(x, y, layer.inverseDepth[i], u, v));
        const double difference = std::max(std::fabs(u - extras.referenceU[i]), std::fabs(v - extras.referenceV[i]));
        EXPECT_LT(difference, 0.01) << "DepthType " << depthType << ", fragment (" << x << ", " << y << "): q "
                                    << layer.inverseDepth[i] << ", warp (" << u << ", " << v << "), read back ("
                                    << extras.referenceU[i] << ", " << extras.referenceV[i] << ")";
        worst = std::max(worst, difference);
        ++drawn;
      }
    EXPECT_GT(drawn, size_t(kWidth * kHeight * 9 / 10));
    std::printf("DepthType %d: %zu fragments, largest difference to ViewSyn's warp %.5f px\n", depthType, drawn, worst);
  }
}

// Each drawn sample's colour is ViewSyn's sampler at the sample's read-back reference position, to the
// bit (GlMeshRenderer samples with its own faster code where the kernel lies inside the plane): every
// Precision and Filter, on a noisy texture, seen from a camera that puts samples at every phase and
// some kernels across the plane's edges.
TEST(MeshRenderGl, ColourIsViewSynsSamplerAtTheReadBackPosition) {
  REQUIRE_GL();
  PlaneScene s = makePlaneScene(0);
  std::mt19937 random(11);
  for (uint16_t& sample : s.textures[0].planes[0].samples) sample = uint16_t(random() % 256);
  for (int precision : {1, 2, 4})
    for (int filter : {0, 1, 2}) {
      const vs::SubPixelSampler sampler(precision, filter);
      renderer->setSampling(&sampler);
      vs::DepthMesh mesh;
      vs::WarpedLayer layer;
      vs::RenderExtras extras;
      renderView(*renderer, s, 0, s.scene.virtualCamera, mesh, layer, extras);
      size_t drawn = 0, nearEdge = 0, differing = 0;
      for (size_t i = 0; i < layer.inverseDepth.size(); ++i) {
        if (!layer.valid(i)) continue;
        ++drawn;
        const double u = extras.referenceU[i], v = extras.referenceV[i];
        nearEdge += vs::SubPixelSampler::nearEdge(u, v, kWidth, kHeight) ? 1 : 0;
        const float expected = sampler.sample(s.textures[0].planes[0], u, v);
        if (std::memcmp(&expected, &layer.colour[0][i], sizeof expected) != 0 && ++differing <= 5)
          ADD_FAILURE() << "Precision " << precision << ", Filter " << filter << ", sample " << i << " at (" << u << ", "
                        << v << "): " << layer.colour[0][i] << ", the sampler " << expected;
      }
      EXPECT_EQ(differing, size_t(0)) << "Precision " << precision << ", Filter " << filter;
      EXPECT_GT(drawn, size_t(kWidth * kHeight / 2));
      EXPECT_GT(nearEdge, size_t(0));
    }
  renderer->setSampling(nullptr);
}

bool sameLayers(const vs::WarpedLayer& a, const vs::WarpedLayer& b) {
  return a.width == b.width && a.height == b.height && a.inverseDepth == b.inverseDepth && a.colour[0] == b.colour[0] &&
         a.edge == b.edge;
}

// The renderer uploads only the vertices a mesh's lists use, renumbered: a mesh whose triangles use a
// scattered few of its grid's vertices renders the same with every unused vertex set to NaN. Meshes
// uploaded into slots of their own (uploadMesh(mesh, slot), useMesh) render as each alone in slot 0.
TEST(MeshRenderGl, UnusedVerticesAndSlotsLeaveTheRenderAsItWas) {
  REQUIRE_GL();
  const PlaneScene s = makePlaneScene(0);
  vs::DepthMesh meshes[2];
  vs::WarpedLayer alone[2];
  vs::Mat4 clips[2];
  const vs::RenderGrid grid = vs::lumaGrid(s.scene.virtualCamera, kWidth, kHeight);
  for (size_t k = 0; k < 2; ++k) {
    vs::WarpedLayer full;
    vs::RenderExtras extras;
    renderView(*renderer, s, k, s.scene.virtualCamera, meshes[k], full, extras);
    vs::DepthMesh& mesh = meshes[k];
    // Every 25th triangle: holes between them, and most vertices unused.
    std::vector<uint32_t> kept;
    for (size_t t = 0; t < mesh.triangles.size() / 3; t += 25) kept.insert(kept.end(), &mesh.triangles[3 * t], &mesh.triangles[3 * t + 3]);
    mesh.triangles = kept;
    const vs::ReferenceView& view = s.scene.settings.references[k];
    vs::InverseDepthRange range;
    ASSERT_TRUE(vs::sceneInverseDepthRange(view.camera, view.depthRange, 0, kWidth, kHeight, s.scene.virtualCamera, range));
    clips[k] = vs::meshClipMatrix(view.camera, s.scene.virtualCamera, grid, vs::clipPlanes(range));
    renderer->uploadMesh(mesh);
    renderer->uploadTexture({&s.textures[k].planes[0]});
    renderer->render(clips[k], grid, vs::TexelMap{}, alone[k]);
    size_t drawn = 0;
    for (size_t i = 0; i < alone[k].inverseDepth.size(); ++i) drawn += alone[k].valid(i) ? 1 : 0;
    EXPECT_GT(drawn, size_t(kWidth * kHeight / 100));
    EXPECT_LT(drawn, size_t(kWidth * kHeight / 10));

    std::vector<uint8_t> used(mesh.vertexCount(), 0);
    for (const std::vector<uint32_t>* list : {&mesh.triangles, &mesh.points, &mesh.farthestOrphans})
      for (uint32_t v : *list) used[v] = 1;
    vs::DepthMesh poisoned = mesh;
    for (size_t v = 0; v < used.size(); ++v)
      if (!used[v])
        for (int c = 0; c < 4; ++c) poisoned.vertices[4 * v + size_t(c)] = std::nanf("");
    EXPECT_LT(size_t(std::count(used.begin(), used.end(), 1)), used.size() / 2);
    vs::WarpedLayer layer;
    renderer->uploadMesh(poisoned);
    renderer->render(clips[k], grid, vs::TexelMap{}, layer);
    EXPECT_TRUE(sameLayers(layer, alone[k])) << "view " << k << ": unused vertices changed the render";
  }
  // Both meshes in slots 1 and 2, then each drawn: as alone.
  renderer->uploadMesh(meshes[0], 1);
  renderer->uploadMesh(meshes[1], 2);
  for (size_t k = 0; k < 2; ++k) {
    vs::WarpedLayer layer;
    renderer->useMesh(k + 1);
    renderer->uploadTexture({&s.textures[k].planes[0]});
    renderer->render(clips[k], grid, vs::TexelMap{}, layer);
    EXPECT_TRUE(sameLayers(layer, alone[k])) << "view " << k << " from slot " << k + 1;
  }
}

// warmUp() draws a mesh of its own, as render() draws, into a small framebuffer: a renderer that warmed
// up renders a scene (whose framebuffer is larger) as one that did not, to the bit, and so it does with
// a read-back that took over a larger array of NaNs (reuseForReadBack).
TEST(MeshRenderGl, WarmUpAndAReusedReadBackLeaveTheRenderAsItWas) {
  REQUIRE_GL();
  const PlaneScene s = makePlaneScene(1);
  vs::DepthMesh mesh;
  vs::WarpedLayer expected;
  vs::RenderExtras extras;
  renderView(*renderer, s, 0, s.scene.virtualCamera, mesh, expected, extras);
  size_t drawn = 0;
  for (size_t i = 0; i < expected.inverseDepth.size(); ++i) drawn += expected.valid(i) ? 1 : 0;
  EXPECT_GT(drawn, size_t(kWidth * kHeight / 2));

  vs::GlMeshRenderer warm;
  warm.warmUp();
  const vs::ReferenceView& view = s.scene.settings.references[0];
  vs::InverseDepthRange range;
  ASSERT_TRUE(vs::sceneInverseDepthRange(view.camera, view.depthRange, s.scene.settings.depthType, kWidth, kHeight,
                                         s.scene.virtualCamera, range));
  const vs::RenderGrid grid = vs::lumaGrid(s.scene.virtualCamera, kWidth, kHeight);
  const vs::Mat4 clip = vs::meshClipMatrix(view.camera, s.scene.virtualCamera, grid, vs::clipPlanes(range));
  warm.uploadMesh(mesh);
  warm.uploadTexture({&s.textures[0].planes[0]});
  vs::WarpedLayer layer;
  warm.render(clip, grid, vs::TexelMap{}, layer);
  EXPECT_TRUE(sameLayers(layer, expected)) << "after warmUp";

  warm.reuseForReadBack(std::vector<float>(size_t(kWidth + 2) * (kHeight + 2) * 4, std::nanf("")));
  warm.render(clip, grid, vs::TexelMap{}, layer);
  EXPECT_TRUE(sameLayers(layer, expected)) << "with the reused read-back";
  renderer->uploadMesh(mesh);  // the shared renderer current again on this thread, for the next tests
}

double planePsnr(const vs::Plane& a, const vs::Plane& b) { return vs::psnrFromMse(vs::planeMse(a, b), 8); }

// A reference view's mesh rendered into its own camera gives the view back: PSNR-Y >= 60 dB (it is
// exact up to float rounding), chroma too, every sample covered by the view's own mesh.
// With `specks`, isolated depth samples of view 0 are set to level 0 (the far end): each is a
// locally farthest orphan of the mesh (no triangle, every neighbour nearer), which the mesh draws only
// into a lone hole of its own view; into its own camera it must still come back.
void expectSelfRender(PlaneScene s, int gridStep, const std::string& what, bool specks = false) {
  // A noisy texture: any misplaced sample would show.
  std::mt19937 random(5);
  for (vs::Frame& texture : s.textures)
    for (vs::Plane& plane : texture.planes)
      for (uint16_t& sample : plane.samples) sample = uint16_t(16 + random() % 220);
  size_t speckCount = 0;
  if (specks)  // where the plane is well inside the depth range, so that every neighbour is nearer
    for (int y = 3; y + 3 < kHeight; y += 7)
      for (int x = 3 + y % 5; x + 3 < kWidth; x += 9)
        if (s.depths[0].at(x, y) >= 20) {
          s.depths[0].at(x, y) = 0;
          ++speckCount;
        }
  s.scene.virtualCamera = s.scene.settings.references[0].camera;
  vs::MeshSettings settings;
  settings.gridStep = gridStep;
  vs::MeshSynthesizer synthesizer(s.scene, vs::makePlan(s.scene, vs::Tool::MeshRender), settings);
  vs::Frame output;
  vs::StageTimes times;
  synthesizer.synthesize(s.frames(), output, times);
  const vs::WarpedLayer& own = synthesizer.lumaLayer(0);
  if (specks) {
    EXPECT_GT(speckCount, size_t(50));
    // Most stay isolated (DepthEdgeAlignment may move a few onto the noisy texture's edges).
    EXPECT_GT(synthesizer.mesh(0).farthestOrphans.size(), speckCount / 2) << what;
  }
  EXPECT_EQ(size_t(std::count_if(own.inverseDepth.begin(), own.inverseDepth.end(), [](double q) { return q >= 0; })),
            own.inverseDepth.size())
      << what;
  const double y = planePsnr(s.textures[0].planes[0], output.planes[0]);
  const double u = planePsnr(s.textures[0].planes[1], output.planes[1]);
  const double v = planePsnr(s.textures[0].planes[2], output.planes[2]);
  EXPECT_GE(y, 60.0) << what;
  EXPECT_GE(u, 60.0) << what;
  EXPECT_GE(v, 60.0) << what;
  std::printf("%s: self-render PSNR Y %s U %s V %s dB\n", what.c_str(), vs::formatPsnr(y, 2).c_str(),
              vs::formatPsnr(u, 2).c_str(), vs::formatPsnr(v, 2).c_str());
}

TEST(MeshRenderGl, ReferenceRenderedIntoItselfReproducesTheView) {
  REQUIRE_GL();
  expectSelfRender(makePlaneScene(0), 1, "DepthType 0");
  expectSelfRender(makePlaneScene(1), 1, "DepthType 1");
  expectSelfRender(makePlaneScene(0, std::numeric_limits<double>::infinity()), 1, "DepthType 0, Zfar inf");
  expectSelfRender(makePlaneScene(0), 4, "DepthType 0, MeshGridStep 4");
  expectSelfRender(makePlaneScene(0), 1, "DepthType 0, isolated far samples", true);
  // 4:4:4: U and V looked up at the luma samples' own positions (the texture is noise, any format).
  PlaneScene full = makePlaneScene(0);
  full.scene.settings.textureFormat.chroma = vs::ChromaFormat::Yuv444;
  for (vs::Frame& texture : full.textures) texture.reset(full.scene.settings.textureFormat);
  expectSelfRender(full, 1, "DepthType 0, 4:4:4");
}

// The whole pipeline on the generated plane: the virtual view against its ray-cast truth, and against
// what ViewSyn's synthesizer makes of the same input.
TEST(MeshRenderGl, TwoViewSynthesisMatchesTheTruth) {
  REQUIRE_GL();
  for (int depthType : {0, 1}) {
    const PlaneScene s = makePlaneScene(depthType);
    vs::MeshSynthesizer synthesizer(s.scene, vs::makePlan(s.scene, vs::Tool::MeshRender), vs::MeshSettings{});
    vs::Frame output;
    vs::StageTimes times;
    synthesizer.synthesize(s.frames(), output, times);
    EXPECT_EQ(synthesizer.blendOptions().weights.size(), 2u);
    // The truth's border columns are seen by one view or none; compare the part both see.
    vs::Plane inner(kWidth - 40, kHeight - 20), innerTruth(kWidth - 40, kHeight - 20);
    for (int y = 0; y < inner.height; ++y)
      for (int x = 0; x < inner.width; ++x) {
        inner.at(x, y) = output.planes[0].at(x + 20, y + 10);
        innerTruth.at(x, y) = s.truth.planes[0].at(x + 20, y + 10);
      }
    const double mesh = planePsnr(innerTruth, inner);
    vs::Synthesizer viewSyn(s.scene, vs::test::planOnPath(s.scene));
    vs::Frame viewSynOutput;
    viewSyn.synthesize(s.frames(), viewSynOutput, times);
    for (int y = 0; y < inner.height; ++y)
      for (int x = 0; x < inner.width; ++x) inner.at(x, y) = viewSynOutput.planes[0].at(x + 20, y + 10);
    const double dibr = planePsnr(innerTruth, inner);
    std::printf("DepthType %d: PSNR-Y against the truth: MeshRender %.2f dB, ViewSyn %.2f dB\n", depthType, mesh, dibr);
    EXPECT_GE(mesh, 38.0);
    EXPECT_GE(mesh, dibr - 1.0);
  }
}

// A run of one frame frees each step's spent buffers (releaseBuffersAfterEachStep): the frame is the
// same to the bit as from a synthesizer that keeps them, and the meshes and layers are given back.
TEST(MeshRenderGl, FreeingSpentBuffersLeavesTheFrameAsItWas) {
  REQUIRE_GL();
  for (int depthType : {0, 1}) {
    const PlaneScene s = makePlaneScene(depthType);
    vs::StageTimes times;
    vs::Frame kept, freed;
    vs::MeshSynthesizer keeping(s.scene, vs::makePlan(s.scene, vs::Tool::MeshRender), vs::MeshSettings{});
    keeping.synthesize(s.frames(), kept, times);
    vs::MeshSynthesizer freeing(s.scene, vs::makePlan(s.scene, vs::Tool::MeshRender), vs::MeshSettings{});
    freeing.releaseBuffersAfterEachStep();
    freeing.synthesize(s.frames(), freed, times);
    for (size_t p = 0; p < 3; ++p)
      EXPECT_TRUE(kept.planes[p].samples == freed.planes[p].samples) << "DepthType " << depthType << ", plane " << p;
    EXPECT_EQ(keeping.holesAfterBlend(), freeing.holesAfterBlend());
    for (size_t k = 0; k < 2; ++k) {
      EXPECT_FALSE(keeping.mesh(k).vertices.empty());
      EXPECT_FALSE(keeping.lumaLayer(k).inverseDepth.empty());
      EXPECT_TRUE(freeing.mesh(k).vertices.empty() && freeing.mesh(k).triangles.empty() && freeing.mesh(k).boundary.empty())
          << "DepthType " << depthType << ", view " << k;
      EXPECT_TRUE(freeing.lumaLayer(k).inverseDepth.empty() && freeing.chromaLayer(k).inverseDepth.empty())
          << "DepthType " << depthType << ", view " << k;
    }
  }
}

// --- The executable -------------------------------------------------------------------------------

using vs::test::ToolResult;

ToolResult runMeshRender(const std::string& arguments, const fs::path& scratch, const std::string& environment = "") {
  return vs::test::runTool("MeshRender", arguments, scratch, {}, environment);
}

// One frame as a whole YUV file.
void writeFrame(const std::string& path, const vs::FrameFormat& format, const vs::Frame& frame) {
  vs::YuvWriter writer(path, format);
  writer.append(frame);
  writer.commit();
}

// Writes the plane scene as files (YUV, camera file, config) the way a user has them.
fs::path writeSceneFiles(const PlaneScene& s, const std::string& name) {
  const fs::path dir = vs::test::scratchDir(name);
  const vs::SynthesisSettings& settings = s.scene.settings;
  vs::writeCameraFile((dir / "cameras.txt").string(),
                      {settings.references[0].camera, s.scene.virtualCamera, settings.references[1].camera});
  const char* names[2] = {"left", "right"};
  for (int k = 0; k < 2; ++k) {
    writeFrame((dir / (std::string(names[k]) + ".yuv")).string(), settings.textureFormat, s.textures[k]);
    vs::Frame depth(settings.depthFormat);
    depth.fill(0);
    depth.planes[0] = s.depths[k];
    writeFrame((dir / (std::string(names[k]) + "_depth.yuv")).string(), settings.depthFormat, depth);
  }
  writeFrame((dir / "truth.yuv").string(), settings.textureFormat, s.truth);
  std::ofstream cfg(dir / "scene.cfg");
  cfg << "DepthType " << settings.depthType << "\nSourceWidth " << kWidth << "\nSourceHeight " << kHeight
      << "\nStartFrame 0\nTotalNumberOfFrames 1\n"
      << "LeftNearestDepthValue 200\nLeftFarthestDepthValue 450\nRightNearestDepthValue 200\nRightFarthestDepthValue 450\n"
      << "CameraParameterFile cameras.txt\nLeftCameraName left\nVirtualCameraName virtual\nRightCameraName right\n"
      << "LeftViewImageName left.yuv\nRightViewImageName right.yuv\n"
      << "LeftDepthMapName left_depth.yuv\nRightDepthMapName right_depth.yuv\n"
      << "OutputVirtualViewImageName virtual.yuv\nPrecision 4\nFilter 1\n";
  return dir;
}

bool haveExecutable() { return fs::exists(vs::test::binDir() / "MeshRender"); }

TEST(MeshRenderApp, HelpListsTheMeshKeys) {
  if (!haveExecutable()) GTEST_SKIP() << "Bin/MeshRender is not built";
  const fs::path scratch = vs::test::scratchDir("meshrender_help");
  const ToolResult help = runMeshRender("--help", scratch);
  EXPECT_EQ(help.exitCode, 0);
  for (const char* key : {"MeshDiscontinuityThreshold", "MeshGridStep", "MeshPlyOutput", "LeftViewImageName"})
    EXPECT_NE(help.out.find(key), std::string::npos) << key;
  EXPECT_EQ(runMeshRender("", scratch).exitCode, 2);
  EXPECT_EQ(runMeshRender("--frobnicate x.cfg", scratch).exitCode, 2);
}

TEST(MeshRenderApp, SynthesizesTheGeneratedSceneAndWritesPly) {
  if (!haveExecutable()) GTEST_SKIP() << "Bin/MeshRender is not built";
  REQUIRE_GL();
  const PlaneScene s = makePlaneScene(0);
  const fs::path dir = writeSceneFiles(s, "meshrender_app");
  // Paths on the command line are relative to the working directory, not to the config file.
  const ToolResult run = runMeshRender("'" + (dir / "scene.cfg").string() + "' 'ReferenceVirtualViewImageName=" +
                                           (dir / "truth.yuv").string() + "' 'MeshPlyOutput=" + (dir / "mesh.ply").string() +
                                           "' MeshGridStep=2",
                                       dir);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const size_t at = run.out.find("mean PSNR: Y ");
  ASSERT_NE(at, std::string::npos) << run.out;
  EXPECT_GE(std::stod(run.out.substr(at + 13)), 30.0) << run.out;
  EXPECT_EQ(fs::file_size(dir / "virtual.yuv"), s.scene.settings.textureFormat.frameBytes());
  EXPECT_GT(fs::file_size(dir / "mesh_left.ply"), 1000u);
  EXPECT_GT(fs::file_size(dir / "mesh_right.ply"), 1000u);
  const ToolResult check = runMeshRender("--check '" + (dir / "scene.cfg").string() + "'", dir);
  EXPECT_EQ(check.exitCode, 0) << check.err;
  EXPECT_NE(check.out.find("OpenGL: "), std::string::npos);
}

// Without any EGL driver MeshRender stops with exit code 1 and says what it tried and what to install.
// libglvnd's EGL reads its vendor list from __EGL_VENDOR_LIBRARY_FILENAMES: pointing it at nothing
// takes every driver away.
TEST(MeshRenderApp, NoEglFailsWithAClearMessage) {
  if (!haveExecutable()) GTEST_SKIP() << "Bin/MeshRender is not built";
  const PlaneScene s = makePlaneScene(0);
  const fs::path dir = writeSceneFiles(s, "meshrender_noegl");
  const ToolResult check = runMeshRender("--check '" + (dir / "scene.cfg").string() + "'", dir,
                                         "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json");
  if (check.exitCode == 0) GTEST_SKIP() << "this libEGL ignores __EGL_VENDOR_LIBRARY_FILENAMES (not libglvnd)";
  EXPECT_EQ(check.exitCode, 1) << check.err;
  EXPECT_NE(check.err.find("MeshRender: error: MeshRender needs an OpenGL 3.3 core context through EGL"),
            std::string::npos)
      << check.err;
  EXPECT_NE(check.err.find("libegl-mesa0"), std::string::npos) << check.err;
  const ToolResult run = runMeshRender("'" + (dir / "scene.cfg").string() + "'", dir,
                                       "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json");
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_FALSE(fs::exists(dir / "virtual.yuv"));  // no output is left behind
}

// The context is created on a thread of its own while the first frame is read and its meshes built, so
// without EGL the run fails after its outputs were opened as temporaries: the error still names EGL,
// an output that was already there keeps its content, and no temporary or PLY file is left behind.
TEST(MeshRenderApp, NoEglRunLeavesEveryOutputAsItWas) {
  if (!haveExecutable()) GTEST_SKIP() << "Bin/MeshRender is not built";
  const PlaneScene s = makePlaneScene(0);
  const fs::path dir = writeSceneFiles(s, "meshrender_noegl_outputs");
  const std::string previous = "an earlier run's output\n";
  std::ofstream(dir / "virtual.yuv", std::ios::binary) << previous;
  auto listing = [&] {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("MeshRender_std", 0) != 0) names.push_back(name);  // runTool's capture of the streams
    }
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> before = listing();
  const ToolResult run = runMeshRender("'" + (dir / "scene.cfg").string() + "' MeshPlyOutput=mesh.ply", dir,
                                       "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json");
  if (run.exitCode == 0) GTEST_SKIP() << "this libEGL ignores __EGL_VENDOR_LIBRARY_FILENAMES (not libglvnd)";
  EXPECT_EQ(run.exitCode, 1) << run.err;
  EXPECT_NE(run.err.find("MeshRender needs an OpenGL 3.3 core context through EGL"), std::string::npos) << run.err;
  EXPECT_EQ(listing(), before);  // no temporary ".NAME.vs-XXXX", no mesh_left.ply or mesh_right.ply
  std::ifstream kept(dir / "virtual.yuv", std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(kept)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, previous);
}

}  // namespace
