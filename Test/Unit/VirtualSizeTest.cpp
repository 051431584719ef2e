// A virtual view of another size than the reference views (VirtualWidth, VirtualHeight; RVS: the
// virtual camera's Resolution), on the general path, and the virtual view's mask (OutputVirtualMaskName):
//   - the room scene (cfg/scenes/room.scene) from two references into virtual cameras larger, smaller
//     and of another aspect than the references, scored against SceneGen's exact render of each camera
//     at its own size: as good as the same camera at the references' size, within a margin
//   - an invariance: a reference warped into itself with K scaled by 2 (twice the resolution) gives,
//     at every even sample, exactly the reference's own sample; with K scaled by 1/2, every sample is
//     the reference's sample at twice its coordinates
//   - the plan: the 1D path and MeshRender refuse another size, auto takes the general path, no copy
//   - the mask against the disocclusions ray casting finds: a virtual sample whose surface the reference
//     camera does not see must be masked, one it sees clearly must not
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Common/CameraJson.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "Plan/Plan.h"
#include "ErpTestCameras.h"
#include "StabilityScene.h"
#include "TestPaths.h"

namespace vs {
namespace {

using test::erpCamera;

using test::kPi;

// The room scene rendered in process at 256x128 (the references' size).
const test::GeneratedScene& room() {
  static const test::GeneratedScene scene(std::vector<std::string>{
      "SceneFile=" + (std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene").string(),
      "SourceWidth=256", "SourceHeight=128"});
  return scene;
}

// The room with smooth textures: every pattern a one-octave noise of period 2 or more, without fine
// detail. A picture of the room's own textures at another resolution than the references' holds
// detail they do not (larger) or averages detail they alias (smaller): its score then measures the
// content, not the warp. Smooth, the scores of every size measure the warp (positions, depth edges,
// holes), and a wrong scale or offset of the virtual picture's grid costs dBs.
const test::GeneratedScene& smoothRoom() {
  static const test::GeneratedScene scene = [] {
    const std::filesystem::path source = std::filesystem::path(VS_SOURCE_DIR) / "cfg" / "scenes" / "room.scene";
    const std::filesystem::path smooth = test::scratchDir("virtual_size_scene") / "smooth_room.scene";
    std::ifstream in(source);
    std::ofstream out(smooth);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (key == "Octaves" || key == "Detail" || key == "DetailScale") continue;
      if (key == "Texture") {
        out << "  Texture noise\n  Octaves 1\n";
      } else if (key == "Scale") {
        double scale = 1;
        words >> scale;
        out << "  Scale " << std::max(2.0, 4 * scale) << "\n";
      } else {
        out << line << "\n";
      }
    }
    out.close();
    return test::GeneratedScene(
        std::vector<std::string>{"SceneFile=" + smooth.string(), "SourceWidth=256", "SourceHeight=128"});
  }();
  return scene;
}

// A pinhole camera with focal length `focal` (pixels), its principal point in the middle of a
// width x height picture, turned `yaw` degrees to the left (MPEG's yaw), at `centre`.
Camera pinhole(const std::string& name, double focal, int width, int height, double yaw, const Vec3& centre) {
  Camera c;
  c.name = name;
  c.K[0][0] = c.K[1][1] = focal;
  c.K[0][2] = (width - 1) / 2.0;
  c.K[1][2] = (height - 1) / 2.0;
  c.R = rotationFromYawPitchRoll(yaw, 0, 0);
  c.t = centre;
  return c;
}


// Focal length of a horizontal field of view of `degrees` across `width` samples.
double focalFor(double degrees, int width) { return (width / 2.0) / std::tan(degrees / 2 * kPi / 180); }

Scene sizedScene(const std::vector<Camera>& references, const Camera& target, int width, int height,
                 const DepthRange& range) {
  Scene s = test::makeScene(references, target, room().textureFormat(), range);
  s.settings.virtualWidth = width;
  s.settings.virtualHeight = height;
  return s;
}

struct Synthesized {
  Frame output;
  Plane mask;
};

Synthesized synthesizeWithMask(const Scene& s, const test::SynthesisInputs& inputs) {
  Plan plan = test::planOnPath(s);
  plan.virtualMaskOutput = true;
  Synthesizer synthesizer(s, plan);
  Synthesized result;
  StageTimes times;
  synthesizer.synthesize(inputs.frames(), result.output, times);
  synthesizer.virtualMask(result.mask);
  return result;
}

double psnrY(const Frame& truth, const Frame& output) { return framePsnr(truth, output).y; }

// The baseline a resized view must match: the view synthesized at the references' size (`same`, by
// camera `sameCamera`) resampled onto `target`'s grid, luma by plain bilinear interpolation written here.
// Both cameras share centre and rotation, so each target pixel's ray meets `sameCamera`'s picture at one
// position. Chroma is the resized output's own (`like`): only luma is compared.
Frame resampledLuma(const Frame& same, const Camera& sameCamera, const Camera& target, const Frame& like) {
  Frame out = like;
  const Plane& in = same.planes[0];
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) {
      double u = 0, v = 0;
      EXPECT_TRUE(sameCamera.cameraToPixel(target.rayCamera(x, y), u, v));
      u = std::clamp(u, 0.0, in.width - 1.0);
      v = std::clamp(v, 0.0, in.height - 1.0);
      const int u0 = std::min(int(u), in.width - 2), v0 = std::min(int(v), in.height - 2);
      const double fu = u - u0, fv = v - v0;
      const double value = (1 - fu) * (1 - fv) * in.at(u0, v0) + fu * (1 - fv) * in.at(u0 + 1, v0) +
                           (1 - fu) * fv * in.at(u0, v0 + 1) + fu * fv * in.at(u0 + 1, v0 + 1);
      out.planes[0].at(x, y) = uint16_t(std::lround(value));
    }
  return out;
}

TEST(VirtualSize, PerspectiveViewsOfOtherSizesScoreAsTheSameSizeAgainstSceneGen) {
  const test::GeneratedScene& scene = smoothRoom();
  const int width = 256, height = 128;
  // Two references 0.3 apart, 110 degrees wide, looking 30 degrees left; the virtual camera between
  // them, 90 degrees wide at every size but the cropped one.
  const Vec3 middle(0.05, 0.02, 0.04);
  const Camera left = pinhole("left", focalFor(110, width), width, height, 30, Vec3(-0.15, 0, 0));
  const Camera right = pinhole("right", focalFor(110, width), width, height, 30, Vec3(0.15, 0, 0));
  const DepthRange range = scene.cameraRange({left, right, pinhole("v", focalFor(90, width), width, height, 30, middle)}, 16);
  const Scene sameSize = sizedScene({left, right}, pinhole("v", focalFor(90, width), width, height, 30, middle), width,
                                    height, range);
  const test::SynthesisInputs inputs = test::renderInputs(scene, sameSize);
  const Frame sameOutput = test::synthesize(sameSize, inputs).output;
  const double base = psnrY(scene.texture(sameSize.virtualCamera), sameOutput);
  test::recordFigure("same_size_psnr_y", base);
  EXPECT_GE(base, 40.0);  // a real synthesis of the smooth room (the references are 0.15 from the camera)
  struct Case {
    const char* name;
    int width, height;
    double focal;
  };
  // Larger (1.5x), smaller (0.5x) with the same field of view, and another aspect: the same-size
  // camera's focal length on a 192x128 picture (the middle 192 columns of its view).
  const Case cases[] = {{"larger_384x192", 384, 192, focalFor(90, 384)},
                        {"smaller_128x64", 128, 64, focalFor(90, 128)},
                        {"aspect_192x128", 192, 128, focalFor(90, width)}};
  for (const Case& c : cases) {
    const Scene s = sizedScene({left, right}, pinhole("v", c.focal, c.width, c.height, 30, middle), c.width, c.height, range);
    const Plan plan = test::planOnPath(s);
    EXPECT_TRUE(plan.resized);
    const Frame output = test::synthesize(s, inputs).output;
    ASSERT_EQ(output.format, (FrameFormat{c.width, c.height, 8, ChromaFormat::Yuv420})) << c.name;
    const Frame truth = scene.texture(s.virtualCamera, c.width, c.height);
    const double psnr = psnrY(truth, output), psnrU = framePsnr(truth, output).u;
    const double resampled = psnrY(truth, resampledLuma(sameOutput, sameSize.virtualCamera, s.virtualCamera, output));
    test::recordFigure(std::string(c.name) + "_psnr_y", psnr);
    test::recordFigure(std::string(c.name) + "_psnr_y_same_size_resampled", resampled);
    test::recordFigure(std::string(c.name) + "_psnr_u", psnrU);
    // Near the same-size score (another grid sees the silhouettes' edges otherwise), and, where the
    // virtual grid is not coarser than the references', within 1 dB of synthesizing at the references'
    // size and resampling: a wrong scale or offset of the grid costs far more. A coarser grid is not
    // prefiltered: each sample is one look-up, where resampling the finer picture averages (a limit
    // measured here, and in doc/manual.md).
    EXPECT_GE(psnr, base - 2.0) << c.name;
    if (c.width >= width * 3 / 4) {
      EXPECT_GE(psnr, resampled - 1.0) << c.name;
    }
    EXPECT_GE(psnrU, 40.0) << c.name;  // chroma looked up at the right reference positions
  }
}

TEST(VirtualSize, ErpViewsOfOtherSizesScoreAsTheSameSizeAgainstSceneGen) {
  const test::GeneratedScene& scene = smoothRoom();
  const int width = 256, height = 128;
  const Camera left = erpCamera("ring0", width, height, Vec3(-0.15, 0, 0));
  const Camera right = erpCamera("ring1", width, height, Vec3(0.15, 0, 0));
  const Vec3 middle(0.05, 0.02, 0.04);
  const DepthRange range = scene.cameraRange({left, right, erpCamera("centre", width, height, middle)}, 16);
  const Scene sameSize = sizedScene({left, right}, erpCamera("centre", width, height, middle), width, height, range);
  const test::SynthesisInputs inputs = test::renderInputs(scene, sameSize);
  const Frame sameOutput = test::synthesize(sameSize, inputs).output;
  const double base = wsPsnr(scene.texture(sameSize.virtualCamera), sameOutput).plane[0];
  test::recordFigure("erp_same_size_wspsnr_y", base);
  EXPECT_GE(base, 40.0);
  for (const auto& [w, h] : {std::pair<int, int>{512, 256}, std::pair<int, int>{128, 64}, std::pair<int, int>{384, 128}}) {
    const Scene s = sizedScene({left, right}, erpCamera("centre", w, h, middle), w, h, range);
    const Frame output = test::synthesize(s, inputs).output;
    ASSERT_EQ(output.width(), w);
    ASSERT_EQ(output.height(), h);
    const Frame truth = scene.texture(s.virtualCamera, w, h);
    const double ws = wsPsnr(truth, output).plane[0];
    const double resampled =
        wsPsnr(truth, resampledLuma(sameOutput, sameSize.virtualCamera, s.virtualCamera, output)).plane[0];
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    test::recordFigure("erp_" + size + "_wspsnr_y", ws);
    test::recordFigure("erp_" + size + "_wspsnr_y_same_size_resampled", resampled);
    // The 512x256 truth holds silhouette edges twice as sharp as any 256x128 picture can: -4.5 dB for
    // it and for the resampled same-size view alike; the coarser grid (128x64) is not prefiltered.
    EXPECT_GE(ws, base - 5.0) << size;
    if (w >= width) {
      EXPECT_GE(ws, resampled - 1.0) << size;
    } else {
      EXPECT_GE(ws, base - 3.0) << size;
    }
  }
}

// A reference rendered into a camera that is itself with K scaled: the virtual camera has the
// reference's centre and rotation, so every virtual sample sees along a ray of the reference camera,
// whatever the depth (no parallax). With K' = diag(2, 2, 1) K, virtual sample (2u, 2v) is reference
// sample (u, v)'s own ray (pixel centres are integers: u' = 2u exactly), so the look-up lands on the
// reference's sample itself, whose interpolation is the sample (every kernel is (0, .., 1, .., 0) at
// phase 0): exact. With K' = diag(1/2, 1/2, 1) K, virtual sample (u, v) is reference sample (2u, 2v).
TEST(VirtualSize, ReferenceIntoItselfWithScaledKIsExactAtTheSharedRays) {
  const test::GeneratedScene& scene = room();
  const int width = 256, height = 128;
  const Camera reference = pinhole("ref", focalFor(100, width), width, height, 20, Vec3(0.1, 0, 0));
  const DepthRange range = scene.cameraRange({reference}, 16);
  for (const double scale : {2.0, 0.5}) {
    Camera scaled = reference;
    scaled.name = "scaled";
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 3; ++c) scaled.K[r][c] *= scale;
    const int w = int(width * scale), h = int(height * scale);
    const Scene s = sizedScene({reference}, scaled, w, h, range);
    const test::SynthesisInputs inputs = test::renderInputs(scene, s);
    EXPECT_LT(test::planOnPath(s).copyOf, 0);
    const Frame output = test::synthesize(s, inputs).output;
    ASSERT_EQ(output.width(), w);
    const Plane &out = output.planes[0], &in = inputs.textures[0].planes[0];
    size_t checked = 0, differing = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (scale == 2.0 && (x % 2 || y % 2)) continue;
        const int u = scale == 2.0 ? x / 2 : 2 * x, v = scale == 2.0 ? y / 2 : 2 * y;
        ++checked;
        differing += out.at(x, y) != in.at(u, v);
      }
    EXPECT_EQ(checked, size_t(width) * height / (scale == 2.0 ? 1 : 4));
    EXPECT_EQ(differing, 0u) << "scale " << scale;
  }
}

TEST(VirtualSize, PlanTakesTheGeneralPathAndRefusesWhatNeedsOneSize) {
  const FrameFormat format{64, 32, 8, ChromaFormat::Yuv420};
  const DepthRange range{1.0, 10.0, 8};
  Camera a = pinhole("a", 40, 64, 32, 0, Vec3(-0.1, 0, 0)), b = pinhole("b", 40, 64, 32, 0, Vec3(0.1, 0, 0));
  // A rectified rig (the same K and R, centres on the x axis): auto takes the 1D path at one size.
  Scene scene = test::makeScene({a, b}, pinhole("v", 40, 64, 32, 0, Vec3()), format, range);
  scene.settings.mode = SynthesisMode::Auto;
  EXPECT_EQ(makePlan(scene).mode, SynthesisMode::Parallel1D);
  scene.settings.virtualWidth = 96;
  scene.settings.virtualHeight = 48;
  const Plan plan = makePlan(scene);
  EXPECT_EQ(plan.mode, SynthesisMode::General);
  EXPECT_TRUE(plan.resized);
  bool said = false;
  for (const std::string& line : plan.lines()) said |= line.find("96x48") != std::string::npos;
  EXPECT_TRUE(said);
  scene.settings.mode = SynthesisMode::Parallel1D;
  try {
    makePlan(scene);
    ADD_FAILURE() << "the 1D path accepted another virtual size";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("VirtualWidth"), std::string::npos) << e.what();
  }
  scene.settings.mode = SynthesisMode::General;
  EXPECT_THROW(makePlan(scene, Tool::MeshRender), InputError);
  // The virtual camera equal to a reference camera is a copy at one size only.
  Scene same = test::makeScene({a, b}, a, format, range);
  EXPECT_EQ(makePlan(same).copyOf, 0);
  same.settings.virtualWidth = 128;
  same.settings.virtualHeight = 64;
  EXPECT_EQ(makePlan(same).copyOf, -1);
  // An ERP virtual camera must have the virtual picture's size as its Resolution.
  Scene erp = test::makeScene({a, b}, erpCamera("e", 96, 48, Vec3()), format, range);
  EXPECT_THROW(makePlan(erp), InputError);
  erp.settings.virtualWidth = 96;
  erp.settings.virtualHeight = 48;
  EXPECT_NO_THROW(makePlan(erp));
  // MeshRender cannot write a mask.
  Scene masked = test::makeScene({a, b}, pinhole("v", 40, 64, 32, 0, Vec3()), format, range);
  masked.settings.virtualMaskPath = "mask.yuv";
  EXPECT_THROW(makePlan(masked, Tool::MeshRender), InputError);
  EXPECT_TRUE(makePlan(masked).virtualMaskOutput);
}

// The mask against ray casting: one reference (the left camera) into a virtual camera 0.3 to its right,
// at another size than the reference (384x192). For every virtual sample, the surface point SceneGen
// finds on its ray is projected into the reference camera; the reference sees it when the reference's
// own surface at the 2x2 samples around that position is at the point's depth (within 3 %), and does
// not when all four are nearer by more than 3 % (occluded) or the point falls outside the picture.
TEST(VirtualMask, MarksTheSamplesTheReferenceDoesNotSee) {
  const test::GeneratedScene& scene = room();
  const int width = 256, height = 128, vw = 384, vh = 192;
  const Camera left = pinhole("left", focalFor(100, width), width, height, 30, Vec3(-0.15, 0, 0));
  const Camera target = pinhole("v", focalFor(90, vw), vw, vh, 30, Vec3(0.15, 0.02, 0.0));
  const DepthRange range = scene.cameraRange({left, pinhole("v", focalFor(90, width), width, height, 30, target.t)}, 16);
  const Scene s = sizedScene({left}, target, vw, vh, range);
  const Synthesized result = synthesizeWithMask(s, test::renderInputs(scene, s));
  ASSERT_EQ(result.mask.width, vw);
  ASSERT_EQ(result.mask.height, vh);
  const std::vector<double> virtualDepth = scene.depth(target, vw, vh), referenceDepth = scene.depth(left);
  size_t seen = 0, seenMasked = 0, hidden = 0, hiddenMasked = 0;
  for (int y = 0; y < vh; ++y)
    for (int x = 0; x < vw; ++x) {
      const uint16_t m = result.mask.at(x, y);
      ASSERT_TRUE(m == 0 || m == 255);
      const double z = virtualDepth[size_t(y) * vw + x];
      if (!std::isfinite(z)) continue;
      const Vec3 point = target.backProject(x, y, z);
      double u, v, zRef;
      if (!left.project(point, u, v, zRef)) continue;
      const int u0 = int(std::floor(u)), v0 = int(std::floor(v));
      if (u < -0.5 || v < -0.5 || u > width - 0.5 || v > height - 0.5) {
        // Outside the reference's picture: nothing can give this sample (a margin of two samples).
        if (u < -2.5 || v < -2.5 || u > width + 1.5 || v > height + 1.5) {
          ++hidden;
          hiddenMasked += m == 255;
        }
        continue;
      }
      if (u0 < 0 || v0 < 0 || u0 + 1 >= width || v0 + 1 >= height) continue;
      int same = 0, nearer = 0;
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du) {
          const double d = referenceDepth[size_t(v0 + dv) * width + u0 + du];
          same += std::fabs(d - zRef) <= 0.03 * zRef;
          nearer += d < zRef * (1 - 0.03);
        }
      if (same == 4) {
        ++seen;
        seenMasked += m == 255;
      } else if (nearer == 4) {
        ++hidden;
        hiddenMasked += m == 255;
      }
    }
  test::recordFigure("clearly_seen_samples", double(seen));
  test::recordFigure("clearly_hidden_samples", double(hidden));
  test::recordFigure("seen_masked_fraction", double(seenMasked) / double(seen));
  test::recordFigure("hidden_masked_fraction", double(hiddenMasked) / double(hidden));
  // The scene has both in numbers: the test can fail either way.
  ASSERT_GT(seen, size_t(vw) * vh / 2);
  ASSERT_GT(hidden, size_t(vw) * vh / 200);
  EXPECT_LE(double(seenMasked) / double(seen), 0.01);
  EXPECT_GE(double(hiddenMasked) / double(hidden), 0.95);
}

}  // namespace
}  // namespace vs
