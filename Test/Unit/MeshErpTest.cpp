// MeshRender with equirectangular (ERP) cameras (Mesh/MeshErp.h): the mesh of an ERP depth map (its
// vertices on the camera's rays at the distance, the wrap column, the poles) against formulas written
// here; then, through OpenGL, an ERP reference rendered into itself, and the room scene
// (cfg/scenes/room.scene) from two ERP references into an ERP and perspective virtual cameras against
// SceneGen's exact render, as EquirectangularSynthTest does for ViewSyn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "Common/CameraJson.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "ErpTestCameras.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/GlMeshRenderer.h"
#include "Mesh/MeshErp.h"
#include "Mesh/MeshSynthesizer.h"
#include "Plan/Plan.h"
#include "StabilityScene.h"
#include "TestPaths.h"

namespace vs {
namespace {

using test::erpCamera;
using test::erpPixelDirection;
using test::pinholeCamera;
using test::sphereChroma;
using test::sphereLuma;
using test::sphereTexture;
using test::sphereDirection;

using test::kPi;



// The camera-frame point of mesh vertex i (ERP: (ray, 1 / distance)).
Vec3 vertexPoint(const DepthMesh& mesh, size_t i) {
  const float* v = &mesh.vertices[i * 4];
  return Vec3(v[0], v[1], v[2]) * (1.0 / double(v[3]));
}

TEST(MeshErp, VerticesLieOnTheRaysAtTheDistanceAndTheWrapJoinsOnlyContinuousDepth) {
  const int width = 48, height = 24;
  const Camera camera = erpCamera("e", width, height, Vec3(0.3, -0.2, 1.0));
  const DepthRange range{1.0, 10.0, 8};
  MeshOptions options;
  options.maxError = 0;
  const DepthMeshBuilder builder(camera, range, width, height, options);
  // Distance grows with the column; the last three columns jump far behind (a depth step at the wrap in rows < 12).
  Plane depth(width, height, 0);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) depth.at(u, v) = uint16_t(200 - u / 16 - (v < 12 && u >= width - 3 ? 150 : 0));
  DepthMesh mesh;
  builder.build(depth, mesh);
  // A full circle: columns 0 .. W-1 and the wrap column W (no half-pixel borders); rows -0.5 .. H-0.5.
  ASSERT_EQ(mesh.columns, width + 1);
  ASSERT_EQ(mesh.rows, height + 2);
  EXPECT_EQ(mesh.gridU.front(), 0.0);
  EXPECT_EQ(mesh.gridU.back(), double(width));
  for (int r = 1; r + 1 < mesh.rows; ++r)
    for (int c = 0; c + 1 < mesh.columns; ++c) {
      const size_t i = size_t(r) * size_t(mesh.columns) + size_t(c);
      ASSERT_TRUE(mesh.valid[i]);
      const double u = mesh.gridU[size_t(c)], v = mesh.gridV[size_t(r)];
      const double lon = (180.0 - (u + 0.5) * 360.0 / width) * kPi / 180, lat = (90.0 - (v + 0.5) * 180.0 / height) * kPi / 180;
      const double distance = levelToZ(depth.at(int(u), int(v)), range);
      const Vec3 expected = sphereDirection(lon, lat) * distance, got = vertexPoint(mesh, i);
      EXPECT_NEAR(norm(got - expected), 0.0, 1e-5 * distance) << u << ", " << v;
      // The wrap column is the first column's vertex, a whole turn on.
      if (c == 0) {
        const size_t wrap = i + size_t(width);
        for (int k = 0; k < 4; ++k) EXPECT_EQ(mesh.vertices[wrap * 4 + size_t(k)], mesh.vertices[i * 4 + size_t(k)]);
      }
    }
  // Each pole row is one point: the pole's ray at one distance, the median of the row.
  for (int r : {0, mesh.rows - 1}) {
    const size_t first = size_t(r) * size_t(mesh.columns);
    const Vec3 pole = vertexPoint(mesh, first);
    EXPECT_NEAR(std::fabs(pole.y), norm(pole), 1e-9) << r;
    EXPECT_EQ(pole.x, 0.0);
    EXPECT_EQ(pole.z, 0.0);
    EXPECT_LT(pole.y * (r == 0 ? 1 : -1), 0.0) << "north is -y, at row -0.5";
    for (int c = 1; c < mesh.columns; ++c)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(mesh.vertices[(first + size_t(c)) * 4 + size_t(k)], mesh.vertices[first * 4 + size_t(k)]);
  }
  // Triangles: the quads between the last pixel column and the wrap column are kept where the depth is
  // continuous (rows >= 12) and dropped across the step (rows < 12); no triangle has two distinct pole
  // points, and no other triangle is dropped besides those at the step.
  size_t wrapKept = 0, wrapRowsAbove = 0;
  for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
    int columnsSeen[3], rowsSeen[3];
    for (int k = 0; k < 3; ++k) {
      columnsSeen[k] = int(mesh.triangles[t + size_t(k)] % uint32_t(mesh.columns));
      rowsSeen[k] = int(mesh.triangles[t + size_t(k)] / uint32_t(mesh.columns));
    }
    const bool wrapQuad = std::max({columnsSeen[0], columnsSeen[1], columnsSeen[2]}) == width;
    if (!wrapQuad) continue;
    ++wrapKept;
    // Rows 0 .. 11 of the picture are grid rows 1 .. 12.
    if (std::min({rowsSeen[0], rowsSeen[1], rowsSeen[2]}) >= 1 && std::max({rowsSeen[0], rowsSeen[1], rowsSeen[2]}) <= 12)
      ++wrapRowsAbove;
  }
  EXPECT_EQ(wrapRowsAbove, 0u) << "a triangle across the depth step at the wrap";
  EXPECT_GE(wrapKept, size_t(2 * (height - 12)));  // rows 12 .. H-1 and down to the south pole join
  // A partial range keeps its half-pixel border columns and has no pole rows.
  Camera partial = camera;
  partial.erp.lonMin = -90;
  partial.erp.lonMax = 90;
  partial.erp.latMin = -45;
  partial.erp.latMax = 45;
  DepthMesh partialMesh;
  DepthMeshBuilder(partial, range, width, height, options).build(depth, partialMesh);
  EXPECT_EQ(partialMesh.gridU.front(), -0.5);
  EXPECT_EQ(partialMesh.gridU.back(), width - 0.5);
  const Vec3 corner = vertexPoint(partialMesh, 0);
  EXPECT_GT(std::hypot(corner.x, corner.z), 0.5 * norm(corner));
}

// A floor seen at a grazing angle steps by far more than 2 % from ray to ray towards the horizon; on it
// the levels follow A sin + B cos + C of the angle along each grid line (MeshErp.h), so its triangles
// are kept; where a raised part of the floor begins, the step is not on that curve and is dropped.
TEST(MeshErp, AFloorSeenAtAGrazingAngleStaysWholeAndAStepOnItIsCut) {
  const int width = 96, height = 64;
  const Camera camera = erpCamera("e", width, height, Vec3());
  const DepthRange range{1.0, 40.0, 16};
  Plane depth(width, height, 0);  // level 0: nothing (the upper half)
  auto floorHeight = [&](int u) { return u >= 40 && u < 56 ? 1.0 : 1.5; };  // our y points down
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const double lon = (180.0 - (u + 0.5) * 360.0 / width) * kPi / 180, lat = (90.0 - (v + 0.5) * 180.0 / height) * kPi / 180;
      const Vec3 ray = sphereDirection(lon, lat);
      if (ray.y > 0.05) depth.at(u, v) = uint16_t(zToLevelRounded(floorHeight(u) / ray.y, range));
    }
  MeshOptions options;
  options.missingDepthLevel = 0;
  DepthMesh mesh;
  DepthMeshBuilder(camera, range, width, height, options).build(depth, mesh);
  // Cells (grid columns c, c + 1; rows r, r + 1) of pixel rows 35 .. 60 (latitudes -9 to -81 degrees).
  std::vector<int> kept(size_t(mesh.columns) * size_t(mesh.rows), 0);
  for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
    uint32_t lowest = mesh.triangles[t];
    for (int k = 1; k < 3; ++k) {
      const uint32_t i = mesh.triangles[t + size_t(k)];
      if (i % uint32_t(mesh.columns) <= lowest % uint32_t(mesh.columns) && i / uint32_t(mesh.columns) <= lowest / uint32_t(mesh.columns))
        lowest = i;
    }
    ++kept[lowest];
  }
  size_t whole = 0, cut = 0;
  for (int row = 36; row <= 60; ++row)  // grid row = pixel row + 1
    for (int c = 0; c + 1 < mesh.columns; ++c) {
      const int triangles = kept[size_t(row) * size_t(mesh.columns) + size_t(c)];
      const bool acrossStep = c == 39 || c == 55;  // grid column c is pixel column c (full circle)
      if (acrossStep) {
        cut += triangles == 0;
      } else {
        whole += triangles == 2;
        EXPECT_EQ(triangles, 2) << "pixel row " << row - 1 << ", column " << c;
      }
    }
  EXPECT_EQ(cut, 2u * 25u) << "every cell across the step's two edges is dropped";
  // The relative step between neighbouring rows there is far above the threshold (1 - z_min / z_max).
  const double lat35 = (90.0 - 35.5 * 180.0 / height) * kPi / 180, lat36 = (90.0 - 36.5 * 180.0 / height) * kPi / 180;
  EXPECT_GT(1.0 - std::sin(lat35) / std::sin(lat36), 0.2);
  test::recordFigure("floor cells kept whole", double(whole));
}

// --- Through OpenGL --------------------------------------------------------------------------------

std::string eglFailure;
bool haveGl() {
  static int state = -1;
  if (state < 0) {
    try {
      GlMeshRenderer renderer;
      state = 1;
    } catch (const InputError& e) {
      eglFailure = e.what();
      state = 0;
    }
  }
  return state == 1;
}
#define REQUIRE_GL() \
  if (!haveGl()) GTEST_SKIP() << "no OpenGL 3.3 core context through EGL on this machine: " << eglFailure

const test::GeneratedScene& room() {
  static const test::GeneratedScene scene(std::vector<std::string>{
      "SceneFile=" + (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string(),
      "SourceWidth=256", "SourceHeight=128"});
  return scene;
}

struct MeshResult {
  Frame output;
  std::vector<WarpedLayer> luma;  // each view's render (q = 1 / virtual depth)
};

MeshResult meshRender(const Scene& scene, const test::SynthesisInputs& inputs, const MeshSettings& settings = {}) {
  MeshSynthesizer synthesizer(scene, makePlan(scene, Tool::MeshRender), settings);
  MeshResult result;
  StageTimes times;
  synthesizer.synthesize(inputs.frames(), result.output, times);
  for (size_t k = 0; k < scene.settings.references.size(); ++k) result.luma.push_back(synthesizer.lumaLayer(k));
  return result;
}

TEST(MeshErpGl, ErpReferenceRenderedIntoItselfIsExact) {
  REQUIRE_GL();
  const test::GeneratedScene& scene = room();
  // A full sphere, the same turned, and a partial range (180 x 120 degrees, as some of RVS's cameras).
  for (double yaw : {0.0, 97.0, -1.0}) {
    Camera reference = erpCamera("ring0", 256, 128, Vec3(-0.15, 0, 0));
    if (yaw >= 0) reference.R = rotationFromYawPitchRoll(yaw, yaw / 10, 0);
    else reference.erp = EquirectangularRange{256, 128, -90, 90, -60, 60};
    const DepthRange range = scene.cameraRange({reference}, 16);
    const Scene s = test::makeScene({reference}, reference, scene.textureFormat(), range);
    const test::SynthesisInputs inputs = test::renderInputs(scene, s);
    const MeshResult result = meshRender(s, inputs);
    const test::FrameDifference diff = test::compareFrames(result.output, inputs.textures[0]);
    EXPECT_TRUE(result.output == inputs.textures[0]) << "yaw " << yaw << ": " << diff.differing << " samples differ";
  }
}

double wsPsnrY(const Frame& truth, const Frame& output) { return wsPsnr(truth, output).plane[0]; }
double psnrY(const Frame& truth, const Frame& output) { return framePsnr(truth, output).y; }

// PSNR of the luma columns within 4 of the wrap, and of the 4 rows at each pole, of an ERP picture.
double bandPsnr(const Frame& truth, const Frame& output, bool seam) {
  double sum = 0;
  int count = 0;
  const Plane &a = truth.planes[0], &b = output.planes[0];
  const int w = a.width, h = a.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in = seam ? (x < 4 || x >= w - 4) : (y < 4 || y >= h - 4);
      if (!in) continue;
      const double d = double(a.at(x, y)) - double(b.at(x, y));
      sum += d * d;
      ++count;
    }
  return psnrFromMse(sum / count, 8);
}

// Share of the ERP picture's samples in the 2 columns at each side of the wrap (seam) or in the 2 rows at
// each pole that no view's render covers: a triangle across the wrap drawn on one side only, or a
// triangle around a pole not drawn as a cap, leaves them to the hole filler.
double uncoveredShare(const MeshResult& result, bool seam) {
  const WarpedLayer& first = result.luma[0];
  const int w = first.width, h = first.height;
  size_t uncovered = 0, count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!(seam ? (x < 2 || x >= w - 2) : (y < 2 || y >= h - 2))) continue;
      ++count;
      bool drawn = false;
      for (const WarpedLayer& layer : result.luma) drawn = drawn || layer.inverseDepth[size_t(y) * size_t(w) + size_t(x)] != kNoDepth;
      uncovered += !drawn;
    }
  return double(uncovered) / double(count);
}

// Share of the samples drawn by view renders whose distance is more than 5 % off the truth's.
double wrongDepthShare(const test::GeneratedScene& scene, const Camera& target, const MeshResult& result) {
  const std::vector<double> truth = scene.depth(target);
  size_t wrong = 0, drawn = 0;
  for (const WarpedLayer& layer : result.luma)
    for (size_t i = 0; i < truth.size(); ++i) {
      const double q = layer.inverseDepth[i];
      if (q == kNoDepth || !(q > 0) || truth[i] == kNoSurface) continue;
      ++drawn;
      wrong += std::fabs(1.0 / q - truth[i]) > 0.05 * truth[i];
    }
  return drawn ? double(wrong) / double(drawn) : 1.0;
}

// The room's rig (as ViewSyn's EquirectangularSynthTest has it): two ERP references on a ring of radius
// 0.15, virtual cameras off the ring's centre: an ERP one, the same turned half a turn (its wrap where
// the references' middle columns land), perspective viewports turned 30 degrees left (144 degrees, the
// ERP pictures' angular resolution at its centre, and 90), and perspective references of the same
// pixel count at the ring's cameras.
struct RoomRig {
  static constexpr int width = 256, height = 128;
  const test::GeneratedScene& scene = room();
  Vec3 middle{0.05, 0.02, 0.04};
  Camera left = erpCamera("ring0", width, height, Vec3(-0.15, 0, 0));
  Camera right = erpCamera("ring1", width, height, Vec3(0.15, 0, 0));
  Camera erpVirtual = erpCamera("centre", width, height, middle);
  Camera turned = erpVirtual;
  double wideDegrees = 2 * std::atan((width / 2.0) / (width / (2 * kPi))) * 180 / kPi;
  Camera wide = pinholeCamera("wide", wideDegrees, 30, middle, width, height);
  Camera narrow = pinholeCamera("narrow", 90, 30, middle, width, height);
  Camera perspectiveLeft = pinholeCamera("left", wideDegrees + 10, 30, left.t, width, height);
  Camera perspectiveRight = pinholeCamera("right", wideDegrees + 10, 30, right.t, width, height);
  DepthRange range;

  RoomRig() {
    turned.R = rotationFromYawPitchRoll(180, 0, 0);
    range = scene.cameraRange({left, right, erpVirtual, wide, perspectiveLeft, perspectiveRight}, 16);
  }
  // MeshRender at default settings (MeshDiscontinuityThreshold 0.02 with the ERP form of the
  // grazing-plane rule) from references a and b into `target`.
  MeshResult run(const Camera& a, const Camera& b, const Camera& target) const {
    const Scene s = test::makeScene({a, b}, target, scene.textureFormat(), range);
    return meshRender(s, test::renderInputs(scene, s));
  }
};

TEST(MeshErpGl, RoomIntoErpCamerasAgainstTheExactRenderWithTheWrapAndThePolesCovered) {
  REQUIRE_GL();
  const RoomRig rig;
  const test::GeneratedScene& scene = rig.scene;
  const Camera &left = rig.left, &right = rig.right, &erpVirtual = rig.erpVirtual, &turned = rig.turned;
  const auto run = [&](const Camera& a, const Camera& b, const Camera& target) { return rig.run(a, b, target); };
  for (const Camera* target : {&erpVirtual, &turned}) {
    const std::string name = target == &turned ? "turned_erp_virtual" : "erp_virtual";
    const Frame truth = scene.texture(*target);
    const MeshResult fromErp = run(left, right, *target);
    const double ws = wsPsnrY(truth, fromErp.output), psnr = psnrY(truth, fromErp.output);
    const double seam = bandPsnr(truth, fromErp.output, true), poles = bandPsnr(truth, fromErp.output, false);
    const double wrong = wrongDepthShare(scene, *target, fromErp);
    const double seamHoles = uncoveredShare(fromErp, true), poleHoles = uncoveredShare(fromErp, false);
    test::recordFigure("mesh_" + name + "_seam_uncovered_share", seamHoles);
    test::recordFigure("mesh_" + name + "_pole_rows_uncovered_share", poleHoles);
    test::recordFigure("mesh_" + name + "_wspsnr_y_from_erp", ws);
    const FrameQuality all = wsPsnr(truth, fromErp.output);
    test::recordFigure("mesh_" + name + "_wspsnr_u_from_erp", all.plane[1]);
    {
      // U in the chroma columns where the references' seam (their longitude +-180, behind them) lands.
      const Plane &a = truth.planes[1], &b = fromErp.output.planes[1];
      double sum = 0;
      int count = 0;
      const int middle = target == &turned ? a.width / 2 : 0;
      for (int y = 0; y < a.height; ++y)
        for (int dx = -3; dx <= 3; ++dx) {
          const int x = (middle + dx + a.width) % a.width;
          const double d = double(a.at(x, y)) - double(b.at(x, y));
          sum += d * d;
          ++count;
        }
      const double seamU = psnrFromMse(sum / count, 8);
      test::recordFigure("mesh_" + name + "_reference_seam_psnr_u", seamU);
      // Chroma from luma samples on both sides of the seam: their reference columns (W - e and e)
      // averaged without the wrap gave column W / 2: 44.27 dB here (48.82 with it).
      EXPECT_GE(seamU, 46.0) << name;
    }
    test::recordFigure("mesh_" + name + "_wspsnr_v_from_erp", all.plane[2]);
    test::recordFigure("mesh_" + name + "_psnr_y_from_erp", psnr);
    test::recordFigure("mesh_" + name + "_seam_psnr_y_from_erp", seam);
    test::recordFigure("mesh_" + name + "_pole_rows_psnr_y_from_erp", poles);
    test::recordFigure("mesh_" + name + "_wrong_depth_share", wrong);
    // ViewSyn's figures for the same scene (EquirectangularSynthTest): WS-PSNR 29.59, PSNR 30.06 dB.
    EXPECT_GE(ws, 28.0) << name;
    EXPECT_GE(psnr, 28.0) << name;
    // The wrap and the poles are synthesized about as well as the rest: a triangle across the whole
    // picture at the wrap, none across it, or needles at the poles cost these bands several dB.
    EXPECT_GE(seam, psnr - 2.0) << name;
    EXPECT_GE(poles, psnr - 2.0) << name;
    EXPECT_LE(wrong, 0.02) << name;
    // Every sample beside the wrap and at the poles is drawn by a view (with the wrap copies off: 2.3 %
    // and 3.3 % of the seam columns are not, and the figures above hardly move, since the hole filler
    // fills them from beside).
    EXPECT_LE(seamHoles, 0.002) << name;
    EXPECT_LE(poleHoles, 0.002) << name;
  }
}

TEST(MeshErpGl, RoomIntoAnErpCameraOnAReferencesPoleAxisAndIntoAPartialRange) {
  REQUIRE_GL();
  const RoomRig rig;
  const test::GeneratedScene& scene = rig.scene;
  const int width = rig.width, height = rig.height;
  const Camera &left = rig.left, &right = rig.right;
  const Vec3& middle = rig.middle;
  const DepthRange& range = rig.range;
  const auto run = [&](const Camera& a, const Camera& b, const Camera& target) { return rig.run(a, b, target); };
  // One reference and an ERP camera 2 above it: both poles' axes are one line, so the reference's
  // pole points lie on the virtual camera's pole axis (no longitude there) and its fans around them
  // must fill the pole rows. Splitting the triangles around the pole and drawing the last piece as a
  // band to the pole row each suffice here; with both off (no splits, pole vertices drawn at some
  // longitude, no caps) 29.9 % of these rows and 9.7 % of the centre camera's are left uncovered.
  {
    Camera above = erpCamera("above", width, height, left.t + Vec3(0, -2.0, 0));  // 0.5 below the ceiling
    const Scene s = test::makeScene({left}, above, scene.textureFormat(), range);
    const MeshResult result = meshRender(s, test::renderInputs(scene, s));
    const double poleHoles = uncoveredShare(result, false);
    const double poles = bandPsnr(scene.texture(above), result.output, false);
    test::recordFigure("mesh_above_pole_rows_uncovered_share", poleHoles);
    test::recordFigure("mesh_above_pole_rows_psnr_y", poles);
    EXPECT_LE(poleHoles, 0.002);
    EXPECT_GE(poles, 28.0);
  }
  // A partial range (180 x 120 degrees, turned 30 degrees left) as the virtual camera: no wrap copies,
  // points outside its range clipped.
  {
    Camera partial = erpCamera("partial", width, height, middle);
    partial.erp = EquirectangularRange{width, height, -90, 90, -60, 60};
    partial.R = rotationFromYawPitchRoll(30, 0, 0);
    const Frame truth = scene.texture(partial);
    const double psnr = psnrY(truth, run(left, right, partial).output);
    const Scene s = test::makeScene({left, right}, partial, scene.textureFormat(), range);
    const double viewSyn = psnrY(truth, test::synthesize(s, test::renderInputs(scene, s)).output);
    test::recordFigure("mesh_partial_erp_virtual_psnr_y_from_erp", psnr);
    test::recordFigure("viewsyn_partial_erp_virtual_psnr_y_from_erp", viewSyn);
    EXPECT_GE(psnr, 23.0);
    EXPECT_GE(psnr, viewSyn - 1.0);
  }
}

TEST(MeshErpGl, RoomIntoPerspectiveViewportsAndFromPerspectiveReferences) {
  REQUIRE_GL();
  const RoomRig rig;
  const test::GeneratedScene& scene = rig.scene;
  const Camera &left = rig.left, &right = rig.right, &erpVirtual = rig.erpVirtual;
  const Camera &wide = rig.wide, &narrow = rig.narrow;
  const Camera &perspectiveLeft = rig.perspectiveLeft, &perspectiveRight = rig.perspectiveRight;
  const auto run = [&](const Camera& a, const Camera& b, const Camera& target) { return rig.run(a, b, target); };
  // ERP references into perspective viewports, and perspective references into the ERP camera (mixed).
  const double narrowFromErp = psnrY(scene.texture(narrow), run(left, right, narrow).output);
  const double wideFromErp = psnrY(scene.texture(wide), run(left, right, wide).output);
  const double erpFromPerspective = wsPsnrY(scene.texture(erpVirtual), run(perspectiveLeft, perspectiveRight, erpVirtual).output);
  test::recordFigure("mesh_narrow_viewport_psnr_y_from_erp", narrowFromErp);
  test::recordFigure("mesh_wide_viewport_psnr_y_from_erp", wideFromErp);
  test::recordFigure("mesh_erp_virtual_wspsnr_y_from_perspective", erpFromPerspective);
  // ViewSyn: 24.08 (narrow), 21.45 (wide), 17.50 (perspective references into ERP; they see 154 degrees).
  EXPECT_GE(narrowFromErp, 22.0);
  EXPECT_GE(wideFromErp, 19.0);
  EXPECT_GE(erpFromPerspective, 15.0);
}

// A full-sphere ERP reference at the origin at constant distance, textured with the function above,
// rendered through GlMeshRenderer into ERP cameras at the same centre turned by fractions of a sample,
// so that samples show reference positions in the half sample beyond its wrap column and beyond its
// pole rows. Each such sample's colour is the function at the reference position it shows (rounded to
// the sampler's quarter pel), up to the interpolation and 8-bit rounding; the look-up clamped to the edge
// column or row (the plain sampler, computed here for comparison) is far off there.
TEST(MeshErpGl, ColourLookUpReadsRoundTheWrapAndAcrossThePoles) {
  REQUIRE_GL();
  const int width = 128, height = 64;
  const Camera reference = erpCamera("reference", width, height, Vec3(0, 0, 0));
  const Plane texture = sphereTexture(width, height, sphereLuma, 1.0);
  const DepthRange range{1.0, 10.0, 8};
  DepthMesh mesh;
  DepthMeshBuilder(reference, range, width, height, MeshOptions{}).build(Plane(width, height, uint16_t(255)), mesh);
  GlMeshRenderer renderer;
  renderer.setReferenceSphere(meshReferenceSphere(reference));
  const double sample = 360.0 / width;
  for (int filter : {-1, 0, 1, 2}) {  // -1: exact bilinear (no sampler)
    const SubPixelSampler sampler(4, std::max(filter, 0));
    renderer.setSampling(filter < 0 ? nullptr : &sampler);
    double wrapWorst = 0, poleWorst = 0, wrapClamped = 0, poleClamped = 0;
    size_t wrapCount = 0, poleCount = 0;
    for (const auto& [yaw, pitch] : {std::pair{0.5 * sample, 0.0}, std::pair{-0.3 * sample, 0.45 * sample},
                                     std::pair{0.4 * sample, -0.55 * sample}}) {
      Camera turned = reference;
      turned.name = "turned";
      turned.R = rotationFromYawPitchRoll(yaw, pitch, 0);
      const RenderGrid grid = lumaGrid(turned, width, height);
      ProjectedMesh projected;
      ASSERT_TRUE(projectMesh(mesh, reference, turned, grid, projected));
      renderer.uploadProjectedMesh(projected);
      renderer.uploadTexture({&texture});
      WarpedLayer layer;
      RenderExtras extras;
      renderer.renderProjected(grid, TexelMap{}, layer, &extras);
      for (size_t i = 0; i < extras.referenceU.size(); ++i) {
        double u = extras.referenceU[i], v = extras.referenceV[i];
        if (std::isnan(u)) continue;
        const bool beyondWrap = u < 0.0 || u > width - 1.0, beyondPole = v < 1.0 || v > height - 2.0;
        if (!beyondWrap && !beyondPole) continue;
        const double plain = filter < 0 ? std::nan("") : sampler.sample(texture, u, v);
        if (filter >= 0) u = std::floor(u * 4 + 0.5) / 4, v = std::floor(v * 4 + 0.5) / 4;  // the sampler's grid
        const double truth = sphereLuma(erpPixelDirection(u, v, width, height));
        const double error = std::fabs(layer.colour[0][i] - truth);
        // The clamped look-up: bilinear between the edge samples (exact positions) or the plain sampler.
        const double clamped = filter < 0 ? [&] {
          const auto at = [&](double x, double y) {
            return double(texture.at(int(std::clamp(x, 0.0, width - 1.0)), int(std::clamp(y, 0.0, height - 1.0))));
          };
          const double fx = std::floor(u), fy = std::floor(v), ax = u - fx, ay = v - fy;
          const double top = at(fx, fy) + ax * (at(fx + 1, fy) - at(fx, fy));
          const double bottom = at(fx, fy + 1) + ax * (at(fx + 1, fy + 1) - at(fx, fy + 1));
          return top + ay * (bottom - top);
        }() : plain;
        if (beyondPole) {
          poleWorst = std::max(poleWorst, error), poleClamped = std::max(poleClamped, std::fabs(clamped - truth));
          ++poleCount;
        } else {
          wrapWorst = std::max(wrapWorst, error), wrapClamped = std::max(wrapClamped, std::fabs(clamped - truth));
          ++wrapCount;
        }
      }
    }
    const std::string name = filter < 0 ? "exact_bilinear" : "filter" + std::to_string(filter);
    test::recordFigure("mesh_lookup_beyond_wrap_worst_error_" + name, wrapWorst);
    test::recordFigure("mesh_lookup_beyond_wrap_worst_error_clamped_" + name, wrapClamped);
    test::recordFigure("mesh_lookup_beyond_pole_worst_error_" + name, poleWorst);
    test::recordFigure("mesh_lookup_beyond_pole_worst_error_clamped_" + name, poleClamped);
    EXPECT_GE(wrapCount, size_t(height)) << name;
    EXPECT_GE(poleCount, size_t(width)) << name;
    // Round the wrap (measured: 1.2 at most; clamped 4.4 to 6.0).
    EXPECT_LE(wrapWorst, 2.0) << name;
    EXPECT_GE(wrapClamped, 4.0) << name;
    // At the poles the mesh shows no position beyond the pole rows: only the taps of the 4- and 6-tap
    // kernels reach across, with small weights (measured: 0.53 and 0.59; clamped 1.09 and 1.78). For
    // bilinear the two rules read the same samples there.
    if (filter >= 1) {
      EXPECT_LE(poleWorst, 0.85) << name;
      EXPECT_GE(poleClamped, 0.95) << name;
    } else {
      EXPECT_LE(poleWorst, 2.0) << name;
    }
  }
}

// Through MeshSynthesizer: the same reference (and 4:2:0 chroma, a function of its own) into an ERP
// camera turned half a sample in yaw, so that every sample of the wrap columns reads across the
// reference's wrap. Away from the pole rows (whose mesh is one point per pole, so its reference positions
// there are not the directions'), each output sample is the function at its own direction (measured:
// Y 0.85, U 0.72; clamped to the edge column, as before: 4.86 and 21.1).
TEST(MeshErpGl, ErpIntoAnErpCameraTurnedHalfASampleMatchesTheTextureRoundTheWrap) {
  REQUIRE_GL();
  const int width = 128, height = 64;
  const Camera reference = erpCamera("reference", width, height, Vec3(0, 0, 0));
  const FrameFormat format{width, height, 8, ChromaFormat::Yuv420};
  test::SynthesisInputs inputs;
  inputs.textures.emplace_back(format);
  inputs.textures[0].planes[0] = sphereTexture(width, height, sphereLuma, 1.0);
  inputs.textures[0].planes[1] = sphereTexture(width / 2, height / 2, sphereChroma, 0.5);
  inputs.textures[0].planes[2] = Plane(width / 2, height / 2, 128);
  inputs.depths.emplace_back(width, height, uint16_t(255));  // distance 1 everywhere
  Camera turned = reference;
  turned.name = "turned";
  const double yaw = 0.5 * 360.0 / width;
  turned.R = rotationFromYawPitchRoll(yaw, 0, 0);
  const Scene scene = test::makeScene({reference}, turned, format, DepthRange{1.0, 10.0, 8});
  const Frame output = meshRender(scene, inputs).output;
  // A virtual sample's direction in the reference's (the world's) axes: R^T times its ray.
  const auto worldDirection = [&](double u, double v) {
    const Vec3 ray = erpPixelDirection(u, v, width, height);
    const Mat3& r = turned.R;
    return Vec3(r[0][0] * ray.x + r[1][0] * ray.y + r[2][0] * ray.z, r[0][1] * ray.x + r[1][1] * ray.y + r[2][1] * ray.z,
                r[0][2] * ray.x + r[1][2] * ray.y + r[2][2] * ray.z);
  };
  double lumaWorst = 0, chromaWorst = 0;
  for (int y = 4; y < height - 4; ++y)
    for (int x : {0, 1, width - 2, width - 1})
      lumaWorst = std::max(lumaWorst, std::fabs(output.planes[0].at(x, y) - sphereLuma(worldDirection(x, y))));
  for (int y = 2; y < height / 2 - 2; ++y)
    for (int x : {0, width / 2 - 1})
      chromaWorst = std::max(chromaWorst, std::fabs(output.planes[1].at(x, y) -
                                                    sphereChroma(worldDirection(2 * x + 0.5, 2 * y + 0.5))));
  test::recordFigure("mesh_wrap_columns_worst_error_y", lumaWorst);
  test::recordFigure("mesh_wrap_columns_worst_error_u", chromaWorst);
  EXPECT_LE(lumaWorst, 2.0);
  EXPECT_LE(chromaWorst, 2.0);
}

}  // namespace
}  // namespace vs
