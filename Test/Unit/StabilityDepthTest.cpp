// Numerical stability, part 3 (doc/stability.md): depth. Znear/Zfar ratios from 1e-6 to 0.999 and an
// infinite Zfar, empty and non-positive ranges refused, the butterfly arc's DepthType 1 range whose 1/Z
// crosses zero, and 8-bit against 16-bit depth on the same scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "Common/CameraFile.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "StabilityScene.h"
#include "Synth/Warp.h"
#include "TestPaths.h"
#include "TestPlan.h"

namespace vs {
namespace {

using test::GeneratedScene;
using test::recordFigure;
using test::SynthesisInputs;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// --- Depth range ratios ----------------------------------------------------------------------------

// SceneGen `plane` at 64x48 (f = 60): a checkered plane at z = 5 filling every view; the virtual camera
// cam1 between cam0 and cam2 (0.1 each side: 1.2 px of disparity). The plane sits at the geometric
// middle of a range [5 sqrt(r), 5 / sqrt(r)] of ratio r, or in [2.5, inf).
TEST(StabilityDepthRange, RatiosFrom1e6To0999AndInfiniteZfarStayDefinedAndAsGoodAsTheirQuantisation) {
  const GeneratedScene generated({"Scene=plane", "SourceWidth=64", "SourceHeight=48"});
  const std::vector<Camera>& rig = generated.rig();
  const Frame truth = generated.texture(rig[1]);
  const double focal = rig[1].K[0][0], baseline = rig[1].t.x - rig[0].t.x, planeZ = 5.0;
  struct Result {
    std::string label;
    double disparityError;
    double psnr;
  };
  std::vector<Result> results;
  for (int bits : {8, 16})
    for (double ratio : {1e-6, 1e-4, 1e-2, 0.1, 0.5, 0.9, 0.99, 0.999, 0.0}) {
      const DepthRange range = ratio > 0 ? DepthRange{planeZ * std::sqrt(ratio), planeZ / std::sqrt(ratio), bits}
                                         : DepthRange{planeZ / 2, HUGE_VAL, bits};
      const Scene scene = test::makeScene({rig[0], rig[2]}, rig[1], generated.textureFormat(), range);
      const SynthesisInputs inputs = test::renderInputs(generated, scene);
      const test::SynthesisResult result = test::synthesize(scene, inputs);
      // The plane's level and the disparity error its quantisation makes, in pixels.
      const int level = zToLevelRounded(planeZ, range);
      const double error = focal * baseline * std::fabs(levelToInverseZ(level, range) - 1 / planeZ);
      char label[64];
      if (ratio > 0) std::snprintf(label, sizeof label, "%d-bit, Znear/Zfar %g", bits, ratio);
      else std::snprintf(label, sizeof label, "%d-bit, Znear 2.5, Zfar inf", bits);
      results.push_back({label, error, framePsnr(truth, result.output).y});
      recordFigure(std::string(label) + ": disparity error of the plane (px)", error);
      recordFigure(std::string(label) + ": PSNR-Y against the truth (dB)", results.back().psnr);
      EXPECT_EQ(test::unexplainedSamples(result.output, inputs.textures), 0u) << label;
      EXPECT_LT(result.holesAfterBlend, size_t(generated.width()) * generated.height() / 10) << label;
    }
  double best = 0;
  for (const Result& r : results) best = std::max(best, r.psnr);
  // Where quantisation moves the plane by less than 0.05 px, the range costs at most 1 dB.
  for (const Result& r : results)
    if (r.disparityError < 0.05) {
      EXPECT_GT(r.psnr, best - 1.0) << r.label;
    }
}

// --- Ranges that are refused -----------------------------------------------------------------------

std::string settingsError(const std::string& text) {
  const std::string base =
      "SourceWidth 64\nSourceHeight 48\nCameraParameterFile cams.txt\nLeftCameraName a\nVirtualCameraName b\n"
      "LeftViewImageName a.yuv\nLeftDepthMapName da.yuv\nOutputVirtualViewImageName out.yuv\n";
  try {
    readSynthesisSettings(Config::fromText(viewSynOptionTable(), base + text, "range.cfg", "/tmp"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StabilityDepthRange, EmptyAndNonPositiveRangesAreRefusedNamingTheKeysAndTheReason) {
  struct Refusal {
    std::string config;
    std::vector<std::string> expected;  // parts of the message
  };
  const std::vector<Refusal> refusals{
      {"LeftNearestDepthValue 5\nLeftFarthestDepthValue 5\n",
       {"LeftNearestDepthValue and LeftFarthestDepthValue are both 5", "empty"}},
      {"DepthType 1\nLeftNearestDepthValue -2.5\nLeftFarthestDepthValue -2.5\n",
       {"LeftNearestDepthValue and LeftFarthestDepthValue are both -2.5", "empty"}},
      {"LeftNearestDepthValue 0\nLeftFarthestDepthValue 10\n", {"LeftNearestDepthValue = 0", "greater than 0"}},
      {"LeftNearestDepthValue -1\nLeftFarthestDepthValue 10\n", {"LeftNearestDepthValue = -1", "greater than 0"}},
      {"LeftNearestDepthValue 1\nLeftFarthestDepthValue -10\n", {"LeftFarthestDepthValue = -10", "greater than 0"}},
      {"LeftNearestDepthValue 1e-300\nLeftFarthestDepthValue 0\n", {"LeftFarthestDepthValue = 0"}},
      {"DepthType 1\nLeftNearestDepthValue 0\nLeftFarthestDepthValue -2.42\n", {"LeftNearestDepthValue = 0", "infinite"}},
      {"LeftNearestDepthValue inf\nLeftFarthestDepthValue inf\n", {"LeftNearestDepthValue"}},
      {"LeftNearestDepthValue 1\nLeftFarthestDepthValue -inf\n", {"LeftFarthestDepthValue"}},
      {"LeftNearestDepthValue nan\nLeftFarthestDepthValue 10\n", {"LeftNearestDepthValue"}},
      // Every bad range of a run in one message.
      {"LeftNearestDepthValue 5\nLeftFarthestDepthValue 5\nRightCameraName c\nRightViewImageName c.yuv\n"
       "RightDepthMapName dc.yuv\nRightNearestDepthValue -1\nRightFarthestDepthValue 4\n",
       {"LeftNearestDepthValue and LeftFarthestDepthValue are both 5", "RightNearestDepthValue = -1"}},
      {"VirtualNearestDepthValue 3\nVirtualFarthestDepthValue 3\nLeftNearestDepthValue 1\nLeftFarthestDepthValue 9\n",
       {"VirtualNearestDepthValue and VirtualFarthestDepthValue are both 3"}},
  };
  for (const Refusal& refusal : refusals) {
    const std::string message = settingsError(refusal.config);
    ASSERT_FALSE(message.empty()) << "accepted:\n" << refusal.config;
    for (const std::string& part : refusal.expected) EXPECT_TRUE(contains(message, part)) << message;
  }
  // The Reference lists (keys Reference<k>...).
  const std::string lists =
      "SourceWidth 64\nSourceHeight 48\nCameraParameterFile cams.txt\nVirtualCameraName b\n"
      "ReferenceCameraNames a,c\nReferenceViewImageNames a.yuv,c.yuv\nReferenceDepthMapNames da.yuv,dc.yuv\n"
      "ReferenceNearestDepthValues 2,7\nReferenceFarthestDepthValues inf,7\nOutputVirtualViewImageName out.yuv\n";
  try {
    readSynthesisSettings(Config::fromText(viewSynOptionTable(), lists, "lists.cfg", "/tmp"));
    ADD_FAILURE() << "a Reference range with Znear == Zfar was accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "Reference2NearestDepthValue and Reference2FarthestDepthValue are both 7")) << e.what();
  }
  // SceneGen refuses them too.
  for (const std::vector<std::string>& keys : std::vector<std::vector<std::string>>{
           {"NearestDepthValue=4", "FarthestDepthValue=4"}, {"NearestDepthValue=0", "FarthestDepthValue=4"}}) {
    try {
      readSceneGenSettings(Config::load(sceneGenOptionTable(), "", keys));
      ADD_FAILURE() << "SceneGen accepted " << keys[0] << " " << keys[1];
    } catch (const InputError& e) {
      EXPECT_TRUE(contains(e.what(), "NearestDepthValue")) << e.what();
    }
  }
  recordFigure("refused configurations", double(refusals.size() + 3));
}

// --- The butterfly arc: DepthType 1, Znear 0.464901, Zfar -2.424092 --------------------------------

// Cameras param_ptm06, param_ptm10, param_ptm13 of cam_param_bbb_butterfly2_arc+Znear-far.txt
// (../shared/vsrs-samples), as ViewSynthesis_butterfly.cfg uses them, with K scaled from 1280x768 to
// 160x96.
Camera butterflyCamera(const std::string& name, double r00, double r02, double tx, double tz) {
  Camera camera;
  camera.name = name;
  camera.K = Mat3::identity();
  camera.K[0][0] = camera.K[1][1] = 1599.99266994;
  camera.K[0][2] = 640.0;
  camera.K[1][2] = 384.0;
  camera.R = Mat3::identity();
  camera.R[0][0] = camera.R[2][2] = r00;
  camera.R[0][2] = -r02;
  camera.R[2][0] = r02;
  camera.t = Vec3(tx, 0, tz);
  return camera;
}

std::vector<Camera> butterflyCameras() {
  return {butterflyCamera("param_ptm06", 0.942641491092, 0.333806859234, -0.517400631812, -1.46109431119),
          butterflyCamera("param_ptm10", 0.953716950748, 0.300705799504, -0.466093989232, -1.47826127366),
          butterflyCamera("param_ptm13", 0.961261695938, 0.275637355817, -0.427237901516, -1.4899556287)};
}

Camera scaledDown(Camera camera) {
  camera.K[0][0] = camera.K[1][1] = camera.K[0][0] / 8;
  camera.K[0][2] = 79.5;
  camera.K[1][2] = 47.5;
  return camera;
}

TEST(StabilityDepthRange, ButterflyCamerasAreTheSampleFilesOnes) {
  const std::filesystem::path file = test::samplesDir() / "cameras" / "cam_param_bbb_butterfly2_arc+Znear-far.txt";
  VS_REQUIRE_DIR(file.parent_path());
  const CameraFile cameras = readCameraFile(file.string());
  for (const Camera& camera : butterflyCameras()) {
    ASSERT_TRUE(cameras.contains(camera.name)) << camera.name;
    const Camera& read = cameras.find(camera.name);
    EXPECT_TRUE(read.K == camera.K && read.R == camera.R && read.t == camera.t) << camera.name;
  }
}

const DepthRange kButterfly8{0.464901, -2.424092, 8};

// The demo's objects seen by the butterfly cameras; synthesized at 8 and 16 bits with the butterfly
// range, and with an ordinary DepthType 0 range for comparison.
TEST(StabilityDepthRange, ButterflyRangeCrossingInfinitySynthesizesTheDemoSceneWithoutUndefinedSamples) {
  const GeneratedScene generated({"Scene=tiny", "SourceWidth=160", "SourceHeight=96"});
  std::vector<Camera> cameras;
  for (const Camera& camera : butterflyCameras()) cameras.push_back(scaledDown(camera));
  const Frame truth = generated.texture(cameras[1]);
  const FrameFormat format = generated.textureFormat();
  double psnr[2][2] = {{0, 0}, {0, 0}};  // [DepthType][8 or 16 bits]
  for (int depthType : {0, 1})
    for (int bits : {8, 16}) {
      DepthRange range = depthType == 1 ? kButterfly8 : generated.cameraRange(cameras, bits);
      range.bitDepth = bits;
      const Scene scene = test::makeScene({cameras[0], cameras[2]}, cameras[1], format, range, depthType);
      const SynthesisInputs inputs = test::renderInputs(generated, scene);
      Synthesizer synthesizer(scene, test::planOnPath(scene));
      Frame output;
      StageTimes times;
      synthesizer.synthesize(inputs.frames(), output, times);
      EXPECT_EQ(test::unexplainedSamples(output, inputs.textures), 0u) << "DepthType " << depthType << ", " << bits << " bits";
      psnr[depthType][bits == 16] = framePsnr(truth, output).y;
      char label[96];
      std::snprintf(label, sizeof label, "DepthType %d %s, %d bits: PSNR-Y (dB)", depthType,
                    depthType ? "butterfly range (0.464901, -2.424092)" : "camera range", bits);
      recordFigure(label, psnr[depthType][bits == 16]);
    }
  // With 16 bits the butterfly range is as good as a camera range; 8 bits give its 37 levels to the
  // scene's depths from 2 to 10 (the rest of the levels code z < 2 and the points behind).
  EXPECT_GT(psnr[1][1], psnr[0][1] - 1.0);
  EXPECT_GT(psnr[1][0], 20.0);
}

// Every level of the butterfly range through ViewProjection: where the level's world z lies in front of
// both cameras the warp agrees with the analytic projection; where it lies behind either, or on the
// plane at infinity in a direction behind, nothing is warped. Then a depth map holding every level is
// synthesized: no crash, no undefined sample.
TEST(StabilityDepthRange, ButterflyEveryLevelIsWarpedToItsAnalyticPlaceOrRejected) {
  std::vector<Camera> cameras;
  for (const Camera& camera : butterflyCameras()) cameras.push_back(scaledDown(camera));
  const Camera& reference = cameras[0];
  const Camera& target = cameras[1];
  const ViewProjection projection(reference, target, kDepthTypeWorld);
  DepthRange range = kButterfly8;
  range.bitDepth = 16;
  size_t warped = 0, rejected = 0, disagreements = 0;
  double worst = 0;
  for (int level = 0; level <= maxDepthLevel(range); level += 7)
    for (double v : {0.0, 47.5, 95.0})
      for (double u : {0.0, 40.0, 79.5, 120.0, 159.0}) {
        const double inverse = levelToInverseZ(level, range);
        if (inverse == 0.0) continue;  // the plane at infinity: checked below
        double x, y, wv;
        const bool ok = projection.forward(u, v, inverse, x, y, wv);
        bool analyticOk = false;
        const Vec3 X = backProjectDepth(reference, u, v, 1 / inverse, kDepthTypeWorld, analyticOk);
        double ax = 0, ay = 0, az = 0;
        analyticOk = analyticOk && target.project(X, ax, ay, az);
        if (ok) {
          ++warped;
          ASSERT_TRUE(std::isfinite(x) && std::isfinite(y) && std::isfinite(wv) && wv >= 0) << level;
        } else {
          ++rejected;
        }
        if (ok != analyticOk) {
          ++disagreements;
          continue;
        }
        if (ok && std::fabs(ax) < 1e4 && std::fabs(ay) < 1e4) {
          worst = std::max(worst, std::hypot(x - ax, y - ay));
          EXPECT_NEAR(1 / wv, az, 1e-9 * az) << level;
        }
      }
  // 1/Z = 0 exactly: the plane at infinity, in front for rays heading to +z.
  double x, y, wv;
  ASSERT_TRUE(projection.forward(79.5, 47.5, 0.0, x, y, wv));
  const Vec3 direction = inverse(reference.R) * reference.pixelToCamera(79.5, 47.5, 1.0);
  double vx, vy;
  ASSERT_TRUE(target.cameraToPixel(target.R * direction, vx, vy));
  // Within 1e-6 px: the warp may keep positions on a grid that fine (far below the 1e-3 px asked for).
  EXPECT_NEAR(x, vx, 1e-6);
  EXPECT_NEAR(y, vy, 1e-6);
  EXPECT_EQ(wv, 0.0);
  EXPECT_EQ(disagreements, 0u);
  EXPECT_LT(worst, 1e-6);
  recordFigure("samples warped", double(warped));
  recordFigure("samples rejected (behind a camera)", double(rejected));
  recordFigure("warp against analytic projection: max error (px)", worst);

  // Depth maps holding every level, scattered. Filter 0: bicubic and 6-tap filters overshoot on such
  // noise down to 0, which would hide a NaN (rounded to 0) from the check.
  const GeneratedScene generated({"Scene=tiny", "SourceWidth=160", "SourceHeight=96"});
  for (int bits : {8, 16}) {
    range.bitDepth = bits;
    Scene scene = test::makeScene({cameras[0], cameras[2]}, cameras[1], generated.textureFormat(), range, kDepthTypeWorld);
    scene.settings.filter = 0;
    SynthesisInputs inputs = test::renderInputs(generated, scene);
    for (Plane& depth : inputs.depths)
      for (size_t i = 0; i < depth.samples.size(); ++i)
        depth.samples[i] = uint16_t((i * 40503u) % (size_t(maxDepthLevel(range)) + 1));
    const test::SynthesisResult result = test::synthesize(scene, inputs);
    EXPECT_EQ(test::unexplainedSamples(result.output, inputs.textures), 0u) << bits << " bits";
    recordFigure(std::to_string(bits) + "-bit scattered levels: holes after blending", double(result.holesAfterBlend));
  }
}

// --- Quantisation: 8 against 16 bits ---------------------------------------------------------------

// SceneGen `sphere` (160x120, f = 150) with a baseline of 0.5: a sphere at z = 3 before a plane at
// z = 6; virtual cam1 from cam0 and cam2 (25 px of disparity on the sphere). Two ranges: the automatic
// one (tight around the scene) and a wide one (0.5 to 100). The warp error of quantised depth per
// reference sample against the exact depth, and the PSNR of the synthesis against the truth.
TEST(StabilityQuantisation, SixteenBitDepthRemovesTheWarpErrorOfEightBits) {
  const GeneratedScene generated({"Scene=sphere", "Baseline=0.5"});
  const std::vector<Camera>& rig = generated.rig();
  const Frame truth = generated.texture(rig[1]);
  for (bool wide : {false, true}) {
    double maxError[2] = {0, 0}, meanError[2] = {0, 0}, psnr[2] = {0, 0}, bound = 0;
    for (int b = 0; b < 2; ++b) {
      const int bits = b ? 16 : 8;
      const DepthRange range = wide ? DepthRange{0.5, 100.0, bits} : generated.cameraRange(rig, bits);
      const Scene scene = test::makeScene({rig[0], rig[2]}, rig[1], generated.textureFormat(), range);
      const SynthesisInputs inputs = test::renderInputs(generated, scene);
      psnr[b] = framePsnr(truth, test::synthesize(scene, inputs).output).y;
      // Warp error of the left reference's samples.
      const ViewProjection projection(rig[0], rig[1], kDepthTypeCamera);
      const std::vector<double> exact = generated.depth(rig[0]);
      size_t count = 0;
      for (int v = 0; v < generated.height(); ++v)
        for (int u = 0; u < generated.width(); ++u) {
          const double z = exact[size_t(v) * generated.width() + u];
          if (z == kNoSurface) continue;
          double x, y, w, qx, qy, qw;
          ASSERT_TRUE(projection.forward(u, v, 1 / z, x, y, w));
          ASSERT_TRUE(projection.forward(u, v, levelToInverseZ(inputs.depths[0].at(u, v), range), qx, qy, qw));
          const double e = std::hypot(qx - x, qy - y);
          maxError[b] = std::max(maxError[b], e);
          meanError[b] += e;
          ++count;
        }
      meanError[b] /= double(count);
      // Half a level step moves a sample by f b (1/Znear - 1/Zfar) / (2 Lmax).
      const double shift = rig[0].K[0][0] * norm(rig[0].t - rig[1].t) * (1 / range.znear - 1 / range.zfar) /
                           (2.0 * maxDepthLevel(range));
      if (b == 0) bound = shift;
      EXPECT_LE(maxError[b], shift + 1e-6) << bits << " bits";  // 1e-6: the warp's own resolution
      char prefix[96];
      std::snprintf(prefix, sizeof prefix, "range %.4g to %.4g, %d-bit", range.znear, range.zfar, bits);
      recordFigure(std::string(prefix) + ": warp error mean (px)", meanError[b]);
      recordFigure(std::string(prefix) + ": warp error max (px)", maxError[b]);
      recordFigure(std::string(prefix) + ": half-level bound (px)", shift);
      recordFigure(std::string(prefix) + ": PSNR-Y against the truth (dB)", psnr[b]);
    }
    recordFigure(std::string(wide ? "wide" : "automatic") + " range: PSNR-Y 16-bit minus 8-bit (dB)", psnr[1] - psnr[0]);
    EXPECT_LT(maxError[1], bound / 200);
    EXPECT_GE(psnr[1], psnr[0] - 0.1);
  }
}

}  // namespace
}  // namespace vs
