// Numerical stability, part 1 (doc/stability.md): transforms of the whole scene that must not change
// the output (identity, origin shift, unit change, left/right swap, world rotated by quarter turns),
// and determinism (the same input twice, any thread count). Scenes: SceneGen's `tiny` (parallel rig)
// and `arc` (converging, rotated cameras) rendered in process, and a real Middlebury scene when
// ../shared/data is present.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <string>
#include <vector>


#include "Synth/Parallel.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "Common/Yuv.h"
#include "StabilityScene.h"
#include "SynthTestScene.h"
#include "TestPaths.h"
#if __has_include("Mesh/MeshSynthesizer.h")
#include "Mesh/MeshSynthesizer.h"
#include "TestPlan.h"
#define VS_STABILITY_HAVE_MESH 1
#endif

namespace vs {
namespace {

using test::allCases;
using test::arcCase;
using test::Case;
using test::compareFrames;
using test::FrameDifference;
using test::GeneratedScene;
using test::recordFigure;
using test::SynthesisInputs;
using test::tinyCase;

Frame baseline(const Case& c) { return test::synthesize(c.scene, c.inputs).output; }

void recordDifference(const std::string& prefix, const FrameDifference& d) {
  recordFigure(prefix + " max |difference|", d.maxAbs);
  recordFigure(prefix + " samples differing", double(d.differing));
}

// --- 1. Identity -----------------------------------------------------------------------------------

// SynthTest covers the analytic plane; here the SceneGen scenes with occlusions, both references, every
// Precision and Filter on the general and the 1D path, DepthType 1, and 10-bit 4:4:4.
TEST(StabilityIdentity, ViewSynReproducesEachReferenceBitExactlyForEveryPrecisionFilterPathAndDepthType) {
  int combinations = 0;
  size_t differing = 0;
  for (const Case* c : allCases())
    for (int depthType : {0, 1}) {
      Scene scene = c->scene;
      scene.settings.depthType = depthType;
      // World z of what the arc's (slightly rotated) cameras see lies within 1 to 12.
      if (depthType == 1)
        for (ReferenceView& view : scene.settings.references) view.depthRange = DepthRange{1.0, 12.0, 8};
      const SynthesisInputs inputs = depthType == 0 ? c->inputs : test::renderInputs(*c->generated, scene);
      std::vector<SynthesisMode> modes{SynthesisMode::General};
      if (c->name == "tiny") modes.push_back(SynthesisMode::Parallel1D);
      for (size_t k = 0; k < scene.settings.references.size(); ++k)
        for (SynthesisMode mode : modes)
          for (int precision : {1, 2, 4})
            for (int filter : {0, 1, 2}) {
              // Precision and Filter act on the texture look-up, DepthType on the depth warp: every
              // pair with DepthType 0, the configs' own (4, 1) with DepthType 1.
              if (depthType == 1 && (precision != 4 || filter != 1)) continue;
              Scene identity = scene;
              identity.virtualCamera = scene.settings.references[k].camera;
              identity.settings.precision = precision;
              identity.settings.filter = filter;
              const Frame output = test::synthesize(identity, inputs, mode).output;
              const FrameDifference d = compareFrames(output, inputs.textures[k]);
              ++combinations;
              differing += d.differing;
              EXPECT_EQ(d.differing, 0u) << c->name << " DepthType " << depthType << " reference " << k << " Precision "
                                         << precision << " Filter " << filter << " mode " << synthesisModeName(mode);
            }
    }
  // 10-bit 4:4:4 (chroma at luma positions) on the analytic scene with an occluding square.
  test::AnalyticScene analytic;
  analytic.square = true;
  analytic.bitDepth = 10;
  analytic.chroma = ChromaFormat::Yuv444;
  const Camera left = analytic.camera("left", -5), right = analytic.camera("right", 5);
  Frame truth;
  Plane depth;
  analytic.render(left, truth, depth);
  for (int precision : {1, 2, 4})
    for (int filter : {0, 1, 2}) {
      Scene scene = analytic.scene(left, left, right);
      scene.settings.precision = precision;
      scene.settings.filter = filter;
      const FrameDifference d = compareFrames(test::synthesizeOnce(analytic, scene), truth);
      ++combinations;
      differing += d.differing;
      EXPECT_EQ(d.differing, 0u) << "10-bit 4:4:4 Precision " << precision << " Filter " << filter;
    }
  recordFigure("combinations", combinations);
  recordFigure("samples differing from the reference view", double(differing));
}

#ifdef VS_STABILITY_HAVE_MESH
// Lowest PSNR (dB) of Y, U and V over both references (and every Precision and Filter, or the
// configs' 4 and 1) of MeshRender's synthesizer with the virtual camera on a reference. NaN: no OpenGL
// here (the reason in `why`). Each run creates an OpenGL context: slow on llvmpipe.
double meshIdentityPsnr(const MeshSettings& settings, bool everyPrecisionAndFilter, std::string& why) {
  const Case& c = tinyCase();
  double worst = HUGE_VAL;
  for (size_t k = 0; k < c.scene.settings.references.size(); ++k)
    for (int precision : {1, 2, 4})
      for (int filter : {0, 1, 2}) {
        if (!everyPrecisionAndFilter && (precision != 4 || filter != 1)) continue;
        Scene identity = c.scene;
        identity.virtualCamera = c.scene.settings.references[k].camera;
        identity.settings.precision = precision;
        identity.settings.filter = filter;
        std::unique_ptr<MeshSynthesizer> mesh;
        try {
          mesh = std::make_unique<MeshSynthesizer>(identity, makePlan(identity, Tool::MeshRender), settings);
          mesh->rendererDescription();  // waits for the context (made on its own thread): throws without one
        } catch (const InputError& e) {
          why = e.what();
          return std::nan("");
        }
        Frame output;
        StageTimes times;
        mesh->synthesize(c.inputs.frames(), output, times);
        const FramePsnr psnr = framePsnr(c.inputs.textures[k], output);
        worst = std::min({worst, psnr.y, psnr.u, psnr.v});
      }
  return worst;
}

TEST(StabilityIdentity, MeshRenderKeepingEveryTriangleReproducesEachReferenceAbove60dB) {
  MeshSettings settings;
  settings.discontinuityThreshold = 1.0;  // no triangle dropped
  std::string why;
  const double worst = meshIdentityPsnr(settings, true, why);
  if (std::isnan(worst)) GTEST_SKIP() << "no OpenGL context through EGL here: " << why;
  recordFigure("lowest PSNR of Y, U, V over 18 runs (dB; inf: identical)", worst);
  EXPECT_GE(worst, 60.0);
}

TEST(StabilityIdentity, MeshRenderAtDefaultSettingsReproducesEachReferenceAbove60dB) {
  std::string why;
  const double worst = meshIdentityPsnr(MeshSettings{}, false, why);
  if (std::isnan(worst)) GTEST_SKIP() << "no OpenGL context through EGL here: " << why;
  recordFigure("lowest PSNR of Y, U, V over both references (dB)", worst);
  // BUG-2 (fixed): 27.23 dB before planes at a grazing angle kept their triangles, orphan vertices
  // were drawn and points sampled along their own fragments' rays.
  EXPECT_GE(worst, 60.0);
}
#endif

// --- 2. Origin shift -------------------------------------------------------------------------------

TEST(StabilityInvariance, WorldOriginShiftedBy1e6ChangesNoSampleByMoreThanOne) {
  for (const Case* c : allCases()) {
    const Frame reference = baseline(*c);
    for (const Vec3& offset : {Vec3(1e6, 0, 0), Vec3(0, 0, 1e6), Vec3(1e6, -1e6, 1e6), Vec3(1e9, 1e9, 1e9)}) {
      Scene shifted = c->scene;
      test::shiftOrigin(shifted, offset);
      const FrameDifference d = compareFrames(test::synthesize(shifted, c->inputs).output, reference);
      char label[96];
      std::snprintf(label, sizeof label, "%s shift (%g, %g, %g)", c->name.c_str(), offset.x, offset.y, offset.z);
      recordDifference(label, d);
      EXPECT_LE(d.maxAbs, 1) << label;
    }
  }
}

// --- 3. Unit change --------------------------------------------------------------------------------

// A level step in 1/Z is 1/255 of the range, and the pipeline's thresholds (DepthBlendDifference, the
// 8-level discontinuity step) are counted in levels: on a parallel rig warped inverse depths keep their
// level spacing, so a threshold on the level grid would tie with them and the last bit of the scaled
// numbers would decide (BUG-1 in doc/stability.md, fixed: thresholds sit half a level off the grid).
// Powers of two scale exactly and must give the identical output.
TEST(StabilityInvariance, UnitChangeOfTranslationsAndDepthRangeChangesNoSampleByMoreThanOne) {
  for (const Case* c : allCases()) {
    const Frame reference = baseline(*c);
    for (double factor : {1024.0, 1.0 / 1024.0, 1000.0, 0.001}) {
      Scene scaled = c->scene;
      test::scaleUnits(scaled, factor);
      const FrameDifference d = compareFrames(test::synthesize(scaled, c->inputs).output, reference);
      char label[64];
      std::snprintf(label, sizeof label, "%s units x%g", c->name.c_str(), factor);
      recordDifference(label, d);
      if (factor == 1024.0 || factor == 1.0 / 1024.0) {
        EXPECT_EQ(d.differing, 0u) << label;
      }
      EXPECT_LE(d.maxAbs, 1) << label;
    }
  }
  // DepthBlendDifference 0 (the blend threshold right next to every tie), and 16-bit depth (levels
  // 257 times finer than the 8-bit levels the thresholds count).
  const Case& tiny = tinyCase();
  Scene zero = tiny.scene;
  zero.settings.depthBlendDifference = 0;
  Scene zeroScaled = zero;
  test::scaleUnits(zeroScaled, 1000.0);
  FrameDifference d = compareFrames(test::synthesize(zeroScaled, tiny.inputs).output, test::synthesize(zero, tiny.inputs).output);
  recordDifference("tiny DepthBlendDifference 0 units x1000", d);
  EXPECT_LE(d.maxAbs, 1);
  Scene deep = tiny.scene;
  for (ReferenceView& view : deep.settings.references) view.depthRange.bitDepth = view.depthFormat.bitDepth = 16;
  deep.settings.depthFormat.bitDepth = 16;
  const SynthesisInputs deepInputs = test::renderInputs(*tiny.generated, deep);
  Scene deepScaled = deep;
  test::scaleUnits(deepScaled, 1000.0);
  d = compareFrames(test::synthesize(deepScaled, deepInputs).output, test::synthesize(deep, deepInputs).output);
  recordDifference("tiny 16-bit depth units x1000", d);
  EXPECT_LE(d.maxAbs, 1);
}

// --- 4. Left/right swap ----------------------------------------------------------------------------

TEST(StabilityInvariance, SwappingLeftAndRightWithViewBlending0ChangesNoSampleByMoreThanOne) {
  for (const Case* c : allCases()) {
    ASSERT_EQ(c->scene.settings.viewBlending, 0);
    const Frame reference = baseline(*c);
    Scene swapped = c->scene;
    std::swap(swapped.settings.references[0], swapped.settings.references[1]);
    SynthesisInputs inputs = c->inputs;
    std::swap(inputs.textures[0], inputs.textures[1]);
    std::swap(inputs.depths[0], inputs.depths[1]);
    const FrameDifference d = compareFrames(test::synthesize(swapped, inputs).output, reference);
    recordDifference(c->name + " swapped", d);
    EXPECT_LE(d.maxAbs, 1) << c->name;
  }
}

// --- 6. Cameras: the whole rig turned by quarter turns (DepthType 0 does not see world axes) ---------

TEST(StabilityInvariance, WorldRotatedByQuarterTurnsChangesNoSampleByMoreThanOne) {
  for (const Case* c : allCases()) {
    const Frame reference = baseline(*c);
    int worst = 0;
    for (int axis = 0; axis < 3; ++axis)
      for (int turns = 1; turns <= 3; ++turns) {
        Scene rotated = c->scene;
        test::rotateWorld(rotated, test::quarterTurn(axis, turns));
        const FrameDifference d = compareFrames(test::synthesize(rotated, c->inputs).output, reference);
        worst = std::max(worst, d.maxAbs);
        EXPECT_LE(d.maxAbs, 1) << c->name << " axis " << axis << " turns " << turns;
      }
    recordFigure(c->name + " worst max |difference| over 9 quarter-turn rotations", worst);
  }
}

// --- 8. Determinism --------------------------------------------------------------------------------

// Threads that the pool's parallel loops really use now.
int threadsInUse() {
  std::mutex mutex;
  std::set<std::thread::id> ids;
  vs::parallelRanges(64, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      std::this_thread::sleep_for(std::chrono::microseconds(500));
      std::lock_guard<std::mutex> lock(mutex);
      ids.insert(std::this_thread::get_id());
    }
  });
  return int(ids.size());
}

TEST(StabilityDeterminism, SameInputTwiceAndAnyThreadCountGiveBitIdenticalOutput) {
  const int defaultThreads = vs::workerThreads();
  // Many threads first, one last: asking TBB for more workers after limiting it to one only warns.
  std::vector<int> threadCounts{vs::availableCores()};
  if (threadCounts[0] > 2) threadCounts.push_back(2);
  threadCounts.push_back(1);
  std::map<int, std::vector<Frame>> outputs;  // per thread count, one output per case and path
  int used = 0;
  for (int threads : threadCounts) {
    vs::setWorkerThreads(threads);
    used = std::max(used, threadsInUse());
    for (const Case* c : allCases()) {
      std::vector<SynthesisMode> modes{SynthesisMode::General};
      if (c->name == "tiny") modes.push_back(SynthesisMode::Parallel1D);
      for (SynthesisMode mode : modes) {
        // Twice through one Synthesizer (it keeps state between frames on the 1D path), then a new one.
        Synthesizer synthesizer(c->scene, test::planOnPath(c->scene, mode));
        Frame first, second;
        StageTimes times;
        synthesizer.synthesize(c->inputs.frames(), first, times);
        synthesizer.synthesize(c->inputs.frames(), second, times);
        EXPECT_TRUE(second == first) << c->name << " " << synthesisModeName(mode) << ": second call";
        EXPECT_TRUE(test::synthesize(c->scene, c->inputs, mode).output == first)
            << c->name << " " << synthesisModeName(mode) << ": second Synthesizer";
        outputs[threads].push_back(first);
      }
    }
  }
  vs::setWorkerThreads(defaultThreads);
  for (int threads : threadCounts)
    for (size_t k = 0; k < outputs[threads].size(); ++k)
      EXPECT_TRUE(outputs[threads][k] == outputs[1][k]) << "output " << k << ": " << threads << " threads against 1";
  recordFigure("most threads in use", used);
  recordFigure("outputs compared bit for bit", double(outputs.size() * outputs[1].size() * 3));
}

// One reference view on several threads: the general depth warp's threads then share one z-buffer
// (atomic raises), where one thread, or two views side by side, each draw into their own.
TEST(StabilityDeterminism, OneReferenceViewGivesTheSameOutputOnSharedAndOwnZBuffers) {
  const int defaultThreads = vs::workerThreads();
  for (const Case* c : allCases()) {
    Scene scene = c->scene;
    scene.settings.references.pop_back();
    SynthesisInputs inputs = c->inputs;
    inputs.textures.pop_back();
    inputs.depths.pop_back();
    vs::setWorkerThreads(std::max(2, vs::availableCores()));
    const test::SynthesisResult shared = test::synthesize(scene, inputs);
    vs::setWorkerThreads(1);
    const test::SynthesisResult own = test::synthesize(scene, inputs);
    EXPECT_TRUE(shared.output == own.output) << c->name;
    // The view warps onto most of the picture: the comparison is not of two empty frames.
    const size_t samples = size_t(c->generated->width()) * c->generated->height();
    EXPECT_LT(own.holesAfterBlend, samples / 2) << c->name;
    EXPECT_FALSE(test::allSamplesEqual(own.output.planes[0], 16)) << c->name;
  }
  vs::setWorkerThreads(defaultThreads);
}

// --- Real data: a Middlebury scene (cameras in millimetres, 432x382) ---------------------------------

TEST(StabilityRealData, VenusIsInvariantToOriginShiftUnitsSwapAndThreads) {
  const std::filesystem::path folder = test::dataDir() / "middlebury2001" / "Venus";
  VS_REQUIRE_DIR(folder);
  const Config config = Config::load(viewSynOptionTable(), (folder / "synth_view4_general.cfg").string(), {});
  const Scene scene = loadScene(config);
  SynthesisInputs inputs;
  for (const ReferenceView& view : scene.settings.references) {
    inputs.textures.emplace_back();
    inputs.depths.emplace_back();
    YuvReader(view.texturePath, scene.settings.textureFormat).read(0, inputs.textures.back());
    YuvReader(view.depthPath, view.depthFormat).readLuma(0, inputs.depths.back());
  }
  const int defaultThreads = vs::workerThreads();
  vs::setWorkerThreads(vs::availableCores());
  const Frame reference = test::synthesize(scene, inputs).output;
  vs::setWorkerThreads(1);
  EXPECT_TRUE(test::synthesize(scene, inputs).output == reference) << "1 against every core's thread";
  vs::setWorkerThreads(defaultThreads);

  Scene shifted = scene;
  test::shiftOrigin(shifted, Vec3(1e6, 1e6, 1e6));
  FrameDifference d = compareFrames(test::synthesize(shifted, inputs).output, reference);
  recordDifference("origin shift 1e6", d);
  EXPECT_LE(d.maxAbs, 1);

  Scene scaled = scene;
  test::scaleUnits(scaled, 1e-3);  // millimetres to metres
  d = compareFrames(test::synthesize(scaled, inputs).output, reference);
  recordDifference("units x0.001", d);
  EXPECT_LE(d.maxAbs, 1);

  Scene swapped = scene;
  std::swap(swapped.settings.references[0], swapped.settings.references[1]);
  SynthesisInputs swappedInputs = inputs;
  std::swap(swappedInputs.textures[0], swappedInputs.textures[1]);
  std::swap(swappedInputs.depths[0], swappedInputs.depths[1]);
  d = compareFrames(test::synthesize(swapped, swappedInputs).output, reference);
  recordDifference("swapped", d);
  EXPECT_LE(d.maxAbs, 1);
}

}  // namespace
}  // namespace vs
