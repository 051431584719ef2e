// Equirectangular (ERP) cameras in the general path: the warp's mapping against formulas written out
// here, an ERP reference warped onto itself, and the room scene (cfg/scenes/room.scene) synthesized from
// two ERP references into an ERP and a perspective virtual camera against SceneGen's exact render,
// compared with perspective references of the same pixel count (and why the 144-degree viewport is
// not: by the angle off its axis); the same output whichever way the references are stored turned;
// and the caps round the virtual camera's poles (cfg/scenes/room_poles.scene).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "Common/CameraJson.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "Common/Yuv.h"
#include "ErpTestCameras.h"
#include "Plan/Plan.h"
#include "StabilityScene.h"
#include "Synth/Warp.h"
#include "TestPaths.h"

namespace vs {
namespace {

using test::erpCamera;
using test::pinholeCamera;
using test::sphereDirection;

using test::kPi;



TEST(EquirectangularWarp, ErpOntoItselfLandsOnEveryPixelCentreExactly) {
  const Camera c = erpCamera("e", 96, 48, Vec3(0.5, -1.0, 2.0));
  const ViewProjection projection(c, c, 0);
  ASSERT_TRUE(projection.spherical());
  EXPECT_EQ(projection.wrapWidth(), 96);
  EXPECT_TRUE(projection.referenceWraps());
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 96; ++u)
      for (double distance : {0.5, 3.0, 1e6}) {
        double x, y, wv;
        ASSERT_TRUE(projection.forward(u, v, 1.0 / distance, x, y, wv));
        EXPECT_EQ(x, double(u));
        EXPECT_EQ(y, double(v));
        EXPECT_NEAR(wv, 1.0 / distance, 1e-15 / distance);
        double bu, bv;
        ASSERT_TRUE(projection.backward(u, v, wv, bu, bv));
        EXPECT_EQ(bu, double(u));
        EXPECT_EQ(bv, double(v));
      }
}

TEST(EquirectangularWarp, MixedPairsMapAsTheFormulasSay) {
  // ERP reference at (1, 0, 0) (ours), a pinhole target at the origin turned 20 degrees to the right.
  const Camera erp = erpCamera("e", 72, 36, Vec3(1.0, 0.0, 0.0));
  Camera pinhole;
  pinhole.name = "p";
  pinhole.K[0][0] = pinhole.K[1][1] = 50.0;
  pinhole.K[0][2] = 40.0;
  pinhole.K[1][2] = 30.0;
  const double turn = 20 * kPi / 180;
  pinhole.R = Mat3::identity();
  pinhole.R[0][0] = std::cos(turn);
  pinhole.R[0][2] = -std::sin(turn);
  pinhole.R[2][0] = std::sin(turn);
  pinhole.R[2][2] = std::cos(turn);
  const ViewProjection forward(erp, pinhole, 0), backward(pinhole, erp, 0);
  int checked = 0;
  for (int v = 0; v < 36; ++v)
    for (int u = 0; u < 72; ++u) {
      const double distance = 2.0 + 0.1 * (u % 7);
      const double lon = (180.0 - (u + 0.5) * 5.0) * kPi / 180, lat = (90.0 - (v + 0.5) * 5.0) * kPi / 180;
      const Vec3 world = Vec3(1.0, 0.0, 0.0) + sphereDirection(lon, lat) * distance;
      const Vec3 xc = pinhole.R * world;  // the target's centre is the origin
      double x, y, wv;
      const bool ok = forward.forward(u, v, 1.0 / distance, x, y, wv);
      EXPECT_EQ(ok, xc.z > 0) << u << "," << v;
      if (!ok || xc.z <= 0) continue;
      ++checked;
      EXPECT_NEAR(x, 50.0 * xc.x / xc.z + 40.0, 1e-8 * (1 + std::fabs(x)));
      EXPECT_NEAR(y, 50.0 * xc.y / xc.z + 30.0, 1e-8 * (1 + std::fabs(y)));
      EXPECT_NEAR(wv, 1.0 / xc.z, 1e-12 / xc.z);
      // Back from the target: the same ERP pixel.
      double bu, bv;
      ASSERT_TRUE(forward.backward(x, y, wv, bu, bv));
      EXPECT_NEAR(bu, u, 1e-6);
      EXPECT_NEAR(bv, v, 1e-6);
      // The pinhole camera as the reference: the point lands on the ERP pixel, with 1 / distance.
      double ex, ey, ew;
      ASSERT_TRUE(backward.forward(x, y, 1.0 / xc.z, ex, ey, ew));
      EXPECT_NEAR(ex, u, 1e-6);
      EXPECT_NEAR(ey, v, 1e-6);
      EXPECT_NEAR(ew, 1.0 / distance, 1e-10);  // through (x, y) snapped to 2^-30 px
    }
  EXPECT_GT(checked, 72 * 36 / 4);
}

TEST(EquirectangularWarp, PlanRefusesWhatNoStageDoesWithErp) {
  const Camera a = erpCamera("a", 64, 32, Vec3(-0.1, 0, 0)), b = erpCamera("b", 64, 32, Vec3(0.1, 0, 0));
  const Camera v = erpCamera("v", 64, 32, Vec3(0, 0, 0));
  const FrameFormat format{64, 32, 8, ChromaFormat::Yuv420};
  const DepthRange range{1.0, 10.0, 8};
  Scene scene = test::makeScene({a, b}, v, format, range);
  // Auto picks the general path and says why; the 1D path is refused with the reason.
  scene.settings.mode = SynthesisMode::Auto;
  const Plan plan = makePlan(scene);
  EXPECT_EQ(plan.mode, SynthesisMode::General);
  EXPECT_NE(plan.rigDeviations.find("equirectangular"), std::string::npos);
  scene.settings.mode = SynthesisMode::Parallel1D;
  EXPECT_THROW(makePlan(scene), InputError);
  scene.settings.mode = SynthesisMode::General;
  // MeshRender renders ERP cameras (Mesh/MeshErp.h); DepthType 1 and a picture size other than the
  // camera's Resolution are refused by both tools.
  EXPECT_NO_THROW(makePlan(scene, Tool::MeshRender));
  Scene worldZ = test::makeScene({a, b}, v, format, range, kDepthTypeWorld);
  EXPECT_THROW(makePlan(worldZ), InputError);
  EXPECT_THROW(makePlan(worldZ, Tool::MeshRender), InputError);
  Scene wrongSize = test::makeScene({a, b}, v, FrameFormat{64, 48, 8, ChromaFormat::Yuv420}, range);
  EXPECT_THROW(makePlan(wrongSize), InputError);
  EXPECT_THROW(makePlan(wrongSize, Tool::MeshRender), InputError);
}

// The room scene, rendered in process at 256x128 (SceneGen's truth, distance-along-ray depth for ERP).
const test::GeneratedScene& room() {
  static const test::GeneratedScene scene(std::vector<std::string>{
      "SceneFile=" + (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string(),
      "SourceWidth=256", "SourceHeight=128"});
  return scene;
}

double wsPsnrY(const Frame& truth, const Frame& output) { return wsPsnr(truth, output).plane[0]; }
double psnrY(const Frame& truth, const Frame& output) { return framePsnr(truth, output).y; }

TEST(EquirectangularSynth, ErpReferenceOntoItselfIsExactThroughTheWarp) {
  const test::GeneratedScene& scene = room();
  const Camera reference = erpCamera("ring0", 256, 128, Vec3(-0.15, 0, 0));
  const DepthRange range = scene.cameraRange({reference}, 16);
  const Scene s = test::makeScene({reference}, reference, scene.textureFormat(), range);
  const test::SynthesisInputs inputs = test::renderInputs(scene, s);
  // Through the copy the plan chooses, and through the whole warp with the copy switched off.
  Plan plan = test::planOnPath(s);
  EXPECT_EQ(plan.copyOf, 0);
  for (int copy : {0, -1}) {
    plan.copyOf = copy;
    Synthesizer synthesizer(s, plan);
    Frame output;
    StageTimes times;
    synthesizer.synthesize(inputs.frames(), output, times);
    EXPECT_TRUE(output == inputs.textures[0]) << "copyOf " << copy << ": " << test::compareFrames(output, inputs.textures[0]).differing
                                              << " samples differ";
  }
}

// A full-circle ERP picture turned by whole columns is the same picture shifted round: the columns of
// `picture` moved `columns` to the right, round the wrap (luma and chroma; chroma by half as many).
Plane shiftedRound(const Plane& picture, int columns) {
  Plane out(picture.width, picture.height);
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x)
      out.at((x + columns % picture.width + picture.width) % picture.width, y) = picture.at(x, y);
  return out;
}

// Where a reference's wrap lies is a matter of how its picture is stored: the references turned a
// quarter turn (their columns shifted 64 round, so that their wrap now lies in the middle of what they
// showed) must give the same output. Every stage that reads a reference across its wrap takes part:
// the depth grid (the quad closing the rows), the texture and chroma look-ups and the reference's
// depth-edge flags, and the plan's blend weights (an ERP camera's rotation says nothing of what it
// sees). Weights from the angle between the optical axes changed 13030 samples (3376 by more than 1);
// reading the edge sample beyond the wrap 43; not flagging a depth step across the wrap 1.
TEST(EquirectangularSynth, OutputDoesNotDependOnWhereTheReferencesWrapLies) {
  const test::GeneratedScene& scene = room();
  const int width = 256, height = 128;
  const Camera left = erpCamera("ring0", width, height, Vec3(-0.15, 0, 0));
  const Camera right = erpCamera("ring1", width, height, Vec3(0.15, 0, 0));
  const Camera target = erpCamera("centre", width, height, Vec3(0.05, 0.02, 0.04));
  const DepthRange range = scene.cameraRange({left, right, target}, 16);
  Scene s = test::makeScene({left, right}, target, scene.textureFormat(), range);
  s.settings.boundaryNoiseRemoval = true;  // reads the depth-edge flags too
  const test::SynthesisInputs inputs = test::renderInputs(scene, s);
  // A quarter turn to the left (MPEG's yaw): longitudes in the camera drop by 90 degrees, and longitude
  // decreases to the right, so every column moves 64 to the right.
  Scene turned = s;
  test::SynthesisInputs shifted = inputs;
  for (size_t k = 0; k < 2; ++k) {
    Camera& camera = turned.settings.references[k].camera;
    camera.R = rotationFromYawPitchRoll(90, 0, 0);
    shifted.depths[k] = shiftedRound(inputs.depths[k], width / 4);
    for (int p = 0; p < 3; ++p)
      shifted.textures[k].planes[p] = shiftedRound(inputs.textures[k].planes[p], (p == 0 ? width : width / 2) / 4);
  }
  const Frame a = test::synthesize(s, inputs).output, b = test::synthesize(turned, shifted).output;
  const test::FrameDifference difference = test::compareFrames(a, b);
  EXPECT_EQ(difference.differing, 0u) << difference.beyondOne << " by more than 1, at most " << difference.maxAbs;
}

// PSNR of the columns within 4 of the wrap (both edges) of an ERP picture's luma.
double seamPsnr(const Frame& truth, const Frame& output) {
  double sum = 0;
  int count = 0;
  const Plane &a = truth.planes[0], &b = output.planes[0];
  for (int y = 0; y < a.height; ++y)
    for (int x : {0, 1, 2, 3, a.width - 4, a.width - 3, a.width - 2, a.width - 1}) {
      const double d = double(a.at(x, y)) - double(b.at(x, y));
      sum += d * d;
      ++count;
    }
  return psnrFromMse(sum / count, 8);
}

// PSNR of the 4 rows at each pole of an ERP picture's luma.
double polePsnr(const Frame& truth, const Frame& output) {
  double sum = 0;
  int count = 0;
  const Plane &a = truth.planes[0], &b = output.planes[0];
  for (int y : {0, 1, 2, 3, a.height - 4, a.height - 3, a.height - 2, a.height - 1})
    for (int x = 0; x < a.width; ++x) {
      const double d = double(a.at(x, y)) - double(b.at(x, y));
      sum += d * d;
      ++count;
    }
  return psnrFromMse(sum / count, 8);
}

// Fraction of an ERP virtual camera's samples whose synthesized distance is off the true one by more
// than 5 %: a triangle drawn across the picture at the wrap would put its depth along whole rows.
double wrongDepthFraction(const test::GeneratedScene& scene, const Scene& s, const test::SynthesisInputs& inputs,
                          const DepthRange& range) {
  Synthesizer synthesizer(s, test::planOnPath(s));
  Frame output;
  StageTimes times;
  synthesizer.synthesize(inputs.frames(), output, times);
  Plane levels;
  synthesizer.virtualDepth(range, levels);
  const std::vector<double> truth = scene.depth(s.virtualCamera);
  size_t wrong = 0;
  for (int y = 0; y < levels.height; ++y)
    for (int x = 0; x < levels.width; ++x) {
      const double distance = levelToZ(levels.at(x, y), range), exact = truth[size_t(y) * levels.width + x];
      wrong += std::fabs(distance - exact) > 0.05 * exact;
    }
  return double(wrong) / double(truth.size());
}

// A virtual ERP camera with half a circle of longitudes (Hor_range [-90, 90]): a point behind it maps
// beyond the picture on the side nearer to it, so a triangle straddling the meridian straight behind
// has corners on both sides, a whole turn (twice the picture's width) apart. Drawn as it is, it
// would cross the whole picture; it is drawn as the wrap's triangles are, a turn to either side,
// where it lies outside the picture.
TEST(EquirectangularSynth, PartialCircleVirtualCameraGetsNoTriangleFromBehind) {
  static const test::GeneratedScene scene(std::vector<std::string>{
      "SceneFile=" + (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string(),
      "SourceWidth=128", "SourceHeight=128"});
  const int width = 128, height = 128;
  const Camera left = erpCamera("ring0", width, height, Vec3(-0.15, 0, 0));
  const Camera right = erpCamera("ring1", width, height, Vec3(0.15, 0, 0));
  Camera front = erpCamera("front", width, height, Vec3(0.05, 0.02, 0.04));
  front.erp.lonMin = -90;
  front.erp.lonMax = 90;
  const DepthRange range = scene.cameraRange({left, right, front}, 16);
  const Scene s = test::makeScene({left, right}, front, scene.textureFormat(), range);
  const double wrong = wrongDepthFraction(scene, s, test::renderInputs(scene, s), range);
  test::recordFigure("wrong_depth_fraction", wrong);
  EXPECT_LE(wrong, 0.02);
}


// PSNR of a pinhole picture's luma over the pixels whose ray is [lo, hi) degrees off the camera's axis.
double offAxisPsnr(const Frame& truth, const Frame& output, const Camera& camera, double lo, double hi) {
  double sum = 0;
  int count = 0;
  for (int y = 0; y < truth.height(); ++y)
    for (int x = 0; x < truth.width(); ++x) {
      const double px = (x - camera.K[0][2]) / camera.K[0][0], py = (y - camera.K[1][2]) / camera.K[1][1];
      const double angle = std::atan(std::hypot(px, py)) * 180 / kPi;
      if (angle < lo || angle >= hi) continue;
      const double d = double(truth.planes[0].at(x, y)) - double(output.planes[0].at(x, y));
      sum += d * d;
      ++count;
    }
  return psnrFromMse(sum / count, 8);
}

TEST(EquirectangularSynth, TwoErpReferencesScoreAtLeastAsWellAsPerspectiveOnesOfTheSamePixelCount) {
  const test::GeneratedScene& scene = room();
  const int width = 256, height = 128;
  // Two ERP references on a ring of radius 0.15 around the origin, and the virtual cameras off the
  // ring's centre: an ERP one, and perspective viewports turned 30 degrees left.
  const Camera left = erpCamera("ring0", width, height, Vec3(-0.15, 0, 0));
  const Camera right = erpCamera("ring1", width, height, Vec3(0.15, 0, 0));
  const Vec3 middle(0.05, 0.02, 0.04);
  const Camera erpVirtual = erpCamera("centre", width, height, middle);
  // The wide viewport has the ERP pictures' angular resolution at its centre (width / 2 pi pixels per
  // radian: 144 degrees across); the narrow one (90 degrees) three times more, which no ERP reference of
  // this size has.
  const double wideDegrees = 2 * std::atan((width / 2.0) / (width / (2 * kPi))) * 180 / kPi;
  const Camera wide = pinholeCamera("wide", wideDegrees, 30, middle, width, height);
  const Camera narrow = pinholeCamera("narrow", 90, 30, middle, width, height);
  // Perspective references of the same pixel count at the same centres, looking where the viewports
  // look, 10 degrees wider than the wide viewport (a margin for the parallax).
  const Camera perspectiveLeft = pinholeCamera("left", wideDegrees + 10, 30, left.t, width, height);
  const Camera perspectiveRight = pinholeCamera("right", wideDegrees + 10, 30, right.t, width, height);

  const DepthRange range = scene.cameraRange({left, right, erpVirtual, wide, perspectiveLeft, perspectiveRight}, 16);
  const auto run = [&](const Camera& a, const Camera& b, const Camera& target) {
    const Scene s = test::makeScene({a, b}, target, scene.textureFormat(), range);
    return test::synthesize(s, test::renderInputs(scene, s)).output;
  };
  const Frame erpTruth = scene.texture(erpVirtual), wideTruth = scene.texture(wide), narrowTruth = scene.texture(narrow);
  const Frame erpFromErp = run(left, right, erpVirtual), erpFromPerspective = run(perspectiveLeft, perspectiveRight, erpVirtual);
  const double erpWs = wsPsnrY(erpTruth, erpFromErp), perspectiveWs = wsPsnrY(erpTruth, erpFromPerspective);
  const double erpPsnr = psnrY(erpTruth, erpFromErp), perspectivePsnr = psnrY(erpTruth, erpFromPerspective);
  const double seam = seamPsnr(erpTruth, erpFromErp), poles = polePsnr(erpTruth, erpFromErp);
  const Frame wideErp = run(left, right, wide), widePerspective = run(perspectiveLeft, perspectiveRight, wide);
  const double wideFromErp = psnrY(wideTruth, wideErp);
  const double wideFromPerspective = psnrY(wideTruth, widePerspective);
  const double narrowFromErp = psnrY(narrowTruth, run(left, right, narrow));
  const double narrowFromPerspective = psnrY(narrowTruth, run(perspectiveLeft, perspectiveRight, narrow));
  test::recordFigure("erp_virtual_wspsnr_y_from_erp", erpWs);
  test::recordFigure("erp_virtual_wspsnr_y_from_perspective", perspectiveWs);
  test::recordFigure("erp_virtual_psnr_y_from_erp", erpPsnr);
  test::recordFigure("erp_virtual_psnr_y_from_perspective", perspectivePsnr);
  test::recordFigure("erp_virtual_seam_psnr_y_from_erp", seam);
  test::recordFigure("erp_virtual_pole_rows_psnr_y_from_erp", poles);
  test::recordFigure("wide_viewport_psnr_y_from_erp", wideFromErp);
  test::recordFigure("wide_viewport_psnr_y_from_perspective", wideFromPerspective);
  test::recordFigure("narrow_viewport_psnr_y_from_erp", narrowFromErp);
  test::recordFigure("narrow_viewport_psnr_y_from_perspective", narrowFromPerspective);
  EXPECT_GE(erpWs, perspectiveWs);
  EXPECT_GE(erpPsnr, perspectivePsnr);
  // A viewport whose pixels are no denser than the ERP's where the perspective references are (the
  // narrow one: 128 px/rad against their 35 at the centre): the ERP references win. The wide viewport
  // magnifies its edges (f / cos^2 of the angle off its axis: ten times the ERP's density at 72 degrees)
  // as the perspective references, shaped like it, do not: there they win (figures in doc/algorithms.md).
  EXPECT_GE(narrowFromErp, narrowFromPerspective);
  // Why the wide viewport differs: its pixels by their angle off its axis. The ERP references sample
  // 40.7 px/rad everywhere, the perspective ones f / cos^2 radially and f / cos across, f = 29.6: less
  // than the ERP's within 31 degrees of the axis, as much from 31 to 43, more beyond (ten times at 72).
  // Where the ERP is denser it wins, where they are alike they are alike, and 83 % of the
  // viewport's pixels lie beyond 45 degrees.
  const double centreFromErp = offAxisPsnr(wideTruth, wideErp, wide, 0, 31);
  const double centreFromPerspective = offAxisPsnr(wideTruth, widePerspective, wide, 0, 31);
  const double evenFromErp = offAxisPsnr(wideTruth, wideErp, wide, 31, 45);
  const double evenFromPerspective = offAxisPsnr(wideTruth, widePerspective, wide, 31, 45);
  test::recordFigure("wide_viewport_below_31deg_psnr_y_from_erp", centreFromErp);
  test::recordFigure("wide_viewport_below_31deg_psnr_y_from_perspective", centreFromPerspective);
  test::recordFigure("wide_viewport_31_to_45deg_psnr_y_from_erp", evenFromErp);
  test::recordFigure("wide_viewport_31_to_45deg_psnr_y_from_perspective", evenFromPerspective);
  test::recordFigure("wide_viewport_beyond_45deg_psnr_y_from_erp", offAxisPsnr(wideTruth, wideErp, wide, 45, 90));
  test::recordFigure("wide_viewport_beyond_45deg_psnr_y_from_perspective",
                     offAxisPsnr(wideTruth, widePerspective, wide, 45, 90));
  EXPECT_GE(centreFromErp, centreFromPerspective);
  EXPECT_NEAR(evenFromErp, evenFromPerspective, 1.0);
  // The sampling, not the warp: one ERP reference at the viewport's own centre (no parallax, no holes:
  // resampling alone) scores no better than the two on the ring.
  const double resampledOnly = psnrY(wideTruth, [&] {
    const Camera atViewport = erpCamera("at_viewport", width, height, middle);
    const Scene s = test::makeScene({atViewport}, wide, scene.textureFormat(), range);
    return test::synthesize(s, test::renderInputs(scene, s)).output;
  }());
  test::recordFigure("wide_viewport_psnr_y_from_one_erp_at_its_centre", resampledOnly);
  EXPECT_GE(wideFromErp, resampledOnly - 0.5);
  // Against the truth, not only against the other rig: the references are 0.15 from the ring's centre.
  EXPECT_GE(erpWs, 27.0);
  EXPECT_GE(narrowFromErp, 22.0);
  EXPECT_GE(wideFromErp, 19.0);
  // Depth: the ERP virtual camera, and one turned half a turn (its wrap then lies where the references'
  // middle columns land, so that many quads cross it).
  Camera rotated = erpVirtual;
  rotated.R = rotationFromYawPitchRoll(180, 0, 0);
  const Camera& turned = rotated;
  for (const Camera* target : {&erpVirtual, &turned}) {
    const Scene s = test::makeScene({left, right}, *target, scene.textureFormat(), range);
    const double wrong = wrongDepthFraction(scene, s, test::renderInputs(scene, s), range);
    test::recordFigure(target == &turned ? "turned_erp_virtual_wrong_depth_fraction" : "erp_virtual_wrong_depth_fraction",
                       wrong);
    EXPECT_LE(wrong, 0.02);
  }
  // The wrap: the columns beside it are synthesized as well as the picture (a triangle drawn across the
  // whole picture, or none across the wrap, costs them several dB).
  EXPECT_GE(seam, erpPsnr - 3.0);
  EXPECT_GE(poles, erpPsnr - 3.0);  // the rows at the poles likewise
}

// PSNR of `rows` rows at the top (north) or bottom (south) of an ERP picture's luma; weighted: each row
// by the cosine of its latitude (WS-PSNR's weights, written out here).
double capPsnr(const Frame& truth, const Frame& output, bool north, int rows, bool weighted = false) {
  double sum = 0, total = 0;
  const Plane &a = truth.planes[0], &b = output.planes[0];
  for (int k = 0; k < rows; ++k) {
    const int y = north ? k : a.height - 1 - k;
    const double weight = weighted ? std::cos((0.5 - (y + 0.5) / a.height) * kPi) : 1.0;
    for (int x = 0; x < a.width; ++x) {
      const double d = double(a.at(x, y)) - double(b.at(x, y));
      sum += weight * d * d;
      total += weight;
    }
  }
  return psnrFromMse(sum / total, 8);
}
double capWsPsnr(const Frame& truth, const Frame& output, bool north, int rows) {
  return capPsnr(truth, output, north, rows, true);
}

// The poles of an ERP virtual camera (cfg/scenes/room_poles.scene: checkered ceiling and floor 0.6
// above and below the cameras): with references 0.3 to either side, a reference sample seen straight
// above or below the virtual camera spans several of its rows, so that the triangles round its poles
// are large. Each covers the whole cap beyond its edges (DepthWarp.cpp); drawn as a triangle across the
// wrap, as before, it left the cap to the hole filler: 44.2 and 44.1 dB in the two rows at the north
// pole and the row at the south pole where the cap gives 54.3 and exact.
TEST(EquirectangularSynth, TrianglesAroundTheVirtualPolesCoverTheirCaps) {
  static const test::GeneratedScene scene(std::vector<std::string>{
      "SceneFile=" + (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room_poles.scene").string()});
  const int width = 256, height = 128;
  const Camera left = erpCamera("left", width, height, Vec3(-0.3, 0, 0.1));
  const Camera right = erpCamera("right", width, height, Vec3(0.3, 0, -0.1));
  const Camera centre = erpCamera("centre", width, height, Vec3(0.05, 0, 0.04));
  const DepthRange range = scene.cameraRange({left, right, centre}, 16);
  const Scene s = test::makeScene({left, right}, centre, scene.textureFormat(), range);
  const Frame truth = scene.texture(centre);
  const Frame output = test::synthesize(s, test::renderInputs(scene, s)).output;
  const double north = capPsnr(truth, output, true, 2), south = capPsnr(truth, output, false, 1);
  const double northWs = capWsPsnr(truth, output, true, 2), southWs = capWsPsnr(truth, output, false, 1);
  const double whole = psnrY(truth, output), weighted = wsPsnrY(truth, output);
  test::recordFigure("north_two_rows_psnr_y", north);
  test::recordFigure("south_row_psnr_y", south);
  test::recordFigure("north_two_rows_wspsnr_y", northWs);
  test::recordFigure("south_row_wspsnr_y", southWs);
  test::recordFigure("psnr_y", whole);
  test::recordFigure("wspsnr_y", weighted);
  EXPECT_GE(north, 50.0);
  EXPECT_GE(south, 50.0);
  EXPECT_GE(northWs, 50.0);
  EXPECT_GE(southWs, 50.0);
  EXPECT_GE(weighted, 25.0);  // and the picture as a whole (26.5, with the caps or without)
}

// SceneGen with a camera file of ERP and pinhole cameras (Rig file): the rig is written as MPEG-I JSON,
// and an ERP depth file holds the distance along each ray (here where the ray meets the floor, 1.5 below
// the camera: 1.5 / sin of the angle below the horizon).
TEST(EquirectangularSceneGen, RendersErpRigsWithDistanceDepthAndWritesJson) {
  const std::filesystem::path root = test::scratchDir("erp_scenegen");
  const std::string cameras = (root / "rig.json").string();
  const Camera erp = erpCamera("erp", 64, 32, Vec3());
  Camera pinhole;
  pinhole.name = "pinhole";
  pinhole.K[0][0] = pinhole.K[1][1] = 32.0;
  pinhole.K[0][2] = 31.5;
  pinhole.K[1][2] = 15.5;
  CameraInfo info;
  info.width = 64;
  info.height = 32;
  const Camera between = erpCamera("between", 64, 32, Vec3(0.1, 0, 0));
  writeCameraJson(cameras, {erp, between, pinhole}, {info, info, info});
  const std::string scene = (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string();
  const auto settingsWith = [&](const std::string& size) {
    return readSceneGenSettings(Config::load(sceneGenOptionTable(), "",
                                             {"SceneFile=" + scene, "Rig=file", "CameraParameterFile=" + cameras,
                                              "SourceWidth=" + size, "SourceHeight=32", "DepthBitDepth=16",
                                              "OutputFolder=" + (root / "out").string(), "Threads=1"}));
  };
  std::ostringstream log;
  try {  // a picture size other than the ERP camera's Resolution
    generateScene(settingsWith("80"), log);
    ADD_FAILURE() << "SceneGen rendered an ERP camera at another size";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'erp' is equirectangular with Resolution 64x32"), std::string::npos) << e.what();
  }
  const SceneGenResult result = generateScene(settingsWith("64"), log);
  EXPECT_EQ(std::filesystem::path(result.cameraFile).filename(), "cameras.json");
  const CameraFile written = readCameraFile(result.cameraFile);
  ASSERT_TRUE(written.find("erp").isEquirectangular());
  EXPECT_FALSE(written.find("pinhole").isEquirectangular());
  Plane levels;
  YuvReader(result.depthPaths[0], FrameFormat{64, 32, 16, ChromaFormat::Yuv420}).readLuma(0, levels);
  // Longitude -90 (our +x, away from every object), rows 25 to 29: latitudes -50.625 to -73.125 degrees.
  int checked = 0;
  for (int v = 25; v < 30; ++v) {
    const double lat = (90.0 - (v + 0.5) * 180.0 / 32) * kPi / 180;
    const int u = 47;  // longitude 180 - 47.5 * 5.625 = -87.19
    const double lon = (180.0 - (u + 0.5) * 360.0 / 64) * kPi / 180;
    const Vec3 ray = sphereDirection(lon, lat);
    const double distance = 1.5 / ray.y;  // the floor is the plane y = 1.5
    EXPECT_NEAR(levelToZ(levels.at(u, v), result.depthRange), distance, 1e-3 * distance) << v;
    ++checked;
  }
  EXPECT_EQ(checked, 5);
  // The config SceneGen writes for the ERP camera between an ERP and a pinhole one: read as a mixed rig
  // on the general path, its output scored with WS-PSNR although QualityMetrics does not name it.
  ASSERT_EQ(result.viewSynConfigs.size(), 1u);
  const Scene mixed = loadScene(Config::load(viewSynOptionTable(), result.viewSynConfigs[0], {}));
  EXPECT_TRUE(mixed.virtualCamera.isEquirectangular());
  EXPECT_FALSE(mixed.settings.references[1].camera.isEquirectangular());
  EXPECT_EQ(mixed.settings.qualityMetrics, std::vector<std::string>{"wspsnr"});
  EXPECT_EQ(makePlan(mixed).mode, SynthesisMode::General);
  std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace vs
