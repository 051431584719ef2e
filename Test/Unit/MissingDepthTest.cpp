// MissingDepthLevel auto (Plan/MissingDepth.h): the plan reads depth level 0 as Zfar or as missing from
// the first frame's views. Truth: analytic scenes (Test/SynthTestScene.h) where level 0 is a real far
// plane, or where holes are cut into exact depth maps and coded as level 0.
#include <gtest/gtest.h>

#include <iostream>

#include "Common/Metrics.h"
#include "Plan/MissingDepth.h"
#include "SynthTestScene.h"
#include "TestPlan.h"

namespace vs {
namespace {

using test::AnalyticScene;

struct AutoResult {
  Plan plan;
  double psnr = 0;  // PSNR-Y against the exact virtual view
};

AutoResult synthesizeAuto(const AnalyticScene& analytic, const Scene& scene, test::RenderedReferences& references) {
  Scene configured = scene;
  configured.settings.missingDepthAuto = true;
  configured.settings.missingDepthFillAuto = true;
  AutoResult result;
  result.plan = test::planOnPath(configured);
  decideMissingDepth(configured, references.frames(), result.plan);
  Synthesizer synthesizer(configured, result.plan);
  Frame output, truth;
  Plane unused;
  StageTimes times;
  synthesizer.synthesize(references.frames(), output, times);
  analytic.render(configured.virtualCamera, truth, unused);
  result.psnr = framePsnr(truth, output).y;
  return result;
}

struct Rig {
  AnalyticScene analytic;
  Scene scene;
  explicit Rig(double planeZ) {
    analytic.square = true;
    analytic.width = 96;
    analytic.height = 72;
    analytic.squareHalf = 14.0;
    analytic.range = DepthRange{50.0, 200.0, 8};
    analytic.planeZ = planeZ;
    scene = analytic.scene(analytic.camera("left", -3), analytic.camera("virtual", 0), analytic.camera("right", 3));
  }
};

// The plane behind the square lies exactly at Zfar, so its exact depth is level 0: far is true, and
// the other view sees the same colour there; auto keeps VSRS's reading.
TEST(MissingDepthAuto, TrueFarPlaneAtLevelZeroStaysFar) {
  Rig rig(200.0);
  test::RenderedReferences references = test::renderReferences(rig.analytic, rig.scene);
  size_t level0 = 0;
  for (uint16_t level : references.depths[0].samples) level0 += level == 0;
  ASSERT_GT(level0, references.depths[0].samples.size() / 2);
  const std::vector<FarEvidence> evidence = testFarReading(rig.scene, references.frames());
  for (const FarEvidence& e : evidence) {
    EXPECT_GT(e.tested, 0u);
    EXPECT_LT(e.contradictedFraction(), 0.1);
  }
  const AutoResult result = synthesizeAuto(rig.analytic, rig.scene, references);
  EXPECT_EQ(result.plan.missingDepthLevel, -1);
  EXPECT_FALSE(result.plan.missingDepthFill);
  EXPECT_EQ(result.plan.missingDepthEvidence.size(), 2u);
  EXPECT_GT(result.psnr, 35.0);
  std::cout << "[ figure   ] far plane: PSNR-Y " << result.psnr << " dB; " << result.plan.missingDepthEvidence[0] << "\n";
}

// Exact maps of a plane at Z 150 with holes cut into them (blocks at level 0, other blocks in each
// view): taken as far, they warp the plane's colour to the wrong place; auto finds far contradicted,
// reads level 0 as missing and fills the holes, and gets close to the exact maps' result.
TEST(MissingDepthAuto, HolesCutIntoDepthAreFilled) {
  Rig rig(150.0);
  test::RenderedReferences exact = test::renderReferences(rig.analytic, rig.scene);
  test::RenderedReferences holed = exact;
  // Holes in other places in each view, as missing data is (occlusions, failed matches).
  for (size_t k = 0; k < holed.depths.size(); ++k) {
    Plane& depth = holed.depths[k];
    for (int y = 4; y < depth.height - 4; ++y)
      for (int x = 0; x < depth.width; ++x)
        if (((x + 9 * int(k)) / 6) % 3 == 1 && (y / 6) % 2 == 0) depth.at(x, y) = 0;
  }
  const AutoResult exactResult = synthesizeAuto(rig.analytic, rig.scene, exact);
  EXPECT_EQ(exactResult.plan.missingDepthLevel, -1) << "no level 0 in exact maps: nothing contradicts far";

  Scene farScene = rig.scene;
  Synthesizer far(farScene, test::planOnPath(farScene));
  Frame farOutput, truth;
  Plane unused;
  StageTimes times;
  far.synthesize(holed.frames(), farOutput, times);
  rig.analytic.render(rig.scene.virtualCamera, truth, unused);
  const double farPsnr = framePsnr(truth, farOutput).y;

  const AutoResult result = synthesizeAuto(rig.analytic, rig.scene, holed);
  EXPECT_EQ(result.plan.missingDepthLevel, 0);
  EXPECT_TRUE(result.plan.missingDepthFill);
  EXPECT_GT(result.psnr, farPsnr + 3.0) << "far " << farPsnr;
  EXPECT_GT(result.psnr, exactResult.psnr - 6.0) << "exact " << exactResult.psnr;
  std::cout << "[ figure   ] holes: PSNR-Y auto " << result.psnr << ", far " << farPsnr << ", exact maps "
            << exactResult.psnr << " dB; " << result.plan.missingDepthEvidence[0] << "\n";
}

// The first frame's filled maps that the decision made are handed to the synthesizer (as ViewSyn
// does) so that frame 0 is not filled and tested twice: the output is the same as filling afresh; a
// map is taken only for the depth it was made from (other frames are filled afresh), and it is
// really the one used (a map altered where the check cannot see it changes the output).
TEST(MissingDepthAuto, FirstFrameFillIsTakenOnlyForItsOwnDepth) {
  Rig rig(150.0);
  test::RenderedReferences exact = test::renderReferences(rig.analytic, rig.scene);
  test::RenderedReferences holed = exact;
  for (size_t k = 0; k < holed.depths.size(); ++k)
    for (int y = 4; y < holed.depths[k].height - 4; ++y)
      for (int x = 0; x < holed.depths[k].width; ++x)
        if (((x + 9 * int(k)) / 6) % 3 == 1 && (y / 6) % 2 == 0) holed.depths[k].at(x, y) = 0;
  Scene scene = rig.scene;
  scene.settings.missingDepthAuto = true;
  scene.settings.missingDepthFillAuto = true;
  Plan plan = test::planOnPath(scene);
  std::vector<FilledDepth> fills;
  decideMissingDepth(scene, holed.frames(), plan, &fills);
  ASSERT_TRUE(plan.missingDepthRunTest);
  ASSERT_EQ(fills.size(), 2u);
  auto render = [&](const std::vector<FilledDepth>* given, test::RenderedReferences& frames) {
    Synthesizer synthesizer(scene, plan);
    if (given) synthesizer.takeFirstFrameFill(*given);
    Frame output;
    StageTimes times;
    synthesizer.synthesize(frames.frames(), output, times);
    return output.planes[0].samples;
  };
  EXPECT_TRUE(render(&fills, holed) == render(nullptr, holed));
  EXPECT_TRUE(render(&fills, exact) == render(nullptr, exact)) << "made from another depth: filled afresh";
  std::vector<FilledDepth> altered = fills;
  size_t marked = 0;
  for (FilledDepth& fill : altered)
    for (size_t i = 0; i < fill.filled.size(); ++i)
      if (fill.filled[i]) {
        fill.depth.samples[i] = 255;
        ++marked;
      }
  ASSERT_GT(marked, 100u);
  EXPECT_FALSE(render(&altered, holed) == render(nullptr, holed)) << "the handed map is the one drawn";
}

// A mix in one picture: the plane behind the square truly at Zfar (level 0, most of the picture) and
// holes cut into the square, also coded as level 0. The reading is one per scene: the plane's
// agreeing samples outweigh the square's contradicted ones, so level 0 stays far, and that is the
// better of the two readings here (taking level 0 as missing would drop the whole plane).
TEST(MissingDepthAuto, MixedPictureTakesTheReadingMostSamplesSupport) {
  Rig rig(200.0);
  test::RenderedReferences mixed = test::renderReferences(rig.analytic, rig.scene);
  const int squareLevel = zToLevelRounded(rig.analytic.squareZ, rig.analytic.range);
  size_t holes = 0;
  for (size_t k = 0; k < mixed.depths.size(); ++k) {
    Plane& depth = mixed.depths[k];
    for (int y = 0; y < depth.height; ++y)
      for (int x = 0; x < depth.width; ++x)
        if (depth.at(x, y) == squareLevel && ((x + 5 * int(k)) / 4) % 3 == 0 && (y / 4) % 2 == 0) {
          depth.at(x, y) = 0;
          ++holes;
        }
  }
  ASSERT_GT(holes, 100u);
  const std::vector<FarEvidence> evidence = testFarReading(rig.scene, mixed.frames());
  for (const FarEvidence& e : evidence) {
    EXPECT_GT(e.contradicted, 0u) << "the square's holes contradict Zfar";
    EXPECT_LT(e.contradictedFraction(), kFarContradictedShare);
  }
  const AutoResult result = synthesizeAuto(rig.analytic, rig.scene, mixed);
  EXPECT_EQ(result.plan.missingDepthLevel, -1);

  Scene missingScene = rig.scene;
  missingScene.settings.missingDepthLevel = 0;
  missingScene.settings.missingDepthFill = true;
  Synthesizer missing(missingScene, test::planOnPath(missingScene));
  Frame missingOutput, truth;
  Plane unused;
  StageTimes times;
  missing.synthesize(mixed.frames(), missingOutput, times);
  rig.analytic.render(rig.scene.virtualCamera, truth, unused);
  const double missingPsnr = framePsnr(truth, missingOutput).y;
  EXPECT_GT(result.psnr, missingPsnr + 1.0) << "missing and filled " << missingPsnr;
  EXPECT_GT(result.psnr, 25.0);
  std::cout << "[ figure   ] mix: PSNR-Y auto (far) " << result.psnr << ", missing and filled " << missingPsnr << " dB; "
            << result.plan.missingDepthEvidence[0] << "\n";
}

// The grain that made auto the default, through the whole synthesizer: the square's last samples
// next to each of its vertical edges are cut to level 0 in both views (as stereo matching leaves
// an occluder's edge), together with the plane samples beside them. The plain fill draws the whole
// run at the plane's depth, so the square's edge colour lands on the plane; auto's per-run test gives
// the square's strip its level back, and must come out nearer the exact view.
TEST(MissingDepthAuto, OccluderEdgeStripsAreDrawnAtTheOccludersDepth) {
  Rig rig(150.0);
  test::RenderedReferences cut = test::renderReferences(rig.analytic, rig.scene);
  const int squareLevel = zToLevelRounded(rig.analytic.squareZ, rig.analytic.range);
  size_t strip = 0;
  for (Plane& depth : cut.depths)
    for (int y = 0; y < depth.height; ++y) {
      std::vector<int> edges;  // square samples with a plane neighbour along the row
      for (int x = 1; x + 1 < depth.width; ++x)
        if (depth.at(x, y) == squareLevel && (depth.at(x - 1, y) != squareLevel || depth.at(x + 1, y) != squareLevel))
          edges.push_back(x);
      for (int x : edges) {
        const int inwards = depth.at(x - 1, y) != squareLevel ? 1 : -1;
        for (int d = -2; d < 5; ++d) {  // 2 plane samples and 5 square samples
          const int xi = x + inwards * d;
          if (xi < 1 || xi + 1 >= depth.width) continue;
          strip += depth.at(xi, y) == squareLevel;
          depth.at(xi, y) = 0;
        }
      }
    }
  ASSERT_GT(strip, 200u);
  Frame truth;
  Plane unused;
  rig.analytic.render(rig.scene.virtualCamera, truth, unused);
  Scene fillScene = rig.scene;
  fillScene.settings.missingDepthLevel = 0;
  fillScene.settings.missingDepthFill = true;
  Synthesizer plainFill(fillScene, test::planOnPath(fillScene));
  Frame fillOutput;
  StageTimes times;
  plainFill.synthesize(cut.frames(), fillOutput, times);
  const double fillPsnr = framePsnr(truth, fillOutput).y;

  const AutoResult result = synthesizeAuto(rig.analytic, rig.scene, cut);
  EXPECT_EQ(result.plan.missingDepthLevel, 0);
  EXPECT_TRUE(result.plan.missingDepthRunTest);
  EXPECT_GT(result.psnr, fillPsnr + 1.0) << "plain fill " << fillPsnr;
  std::cout << "[ figure   ] occluder strips: PSNR-Y auto " << result.psnr << ", plain fill " << fillPsnr << " dB; "
            << result.plan.missingDepthEvidence[0] << "\n";
}

// The per-run test under auto (testFilledRuns), against the analytic scene's exact depth: a run
// given the surface's true level is kept (a plane run: no nearer neighbour, step 1 does not apply);
// a run given a level far nearer than the surface (the other view then sees the plane behind where
// that sample would be) goes to the far level; a run of plane samples the other view cannot see
// because the square hides them (a half-occlusion, traced in the analytic scene) is kept.
struct RunTestRig : Rig {
  RunTestRig() : Rig(150.0) {}
  test::RenderedReferences exact = test::renderReferences(analytic, scene);
  // Runs the test on view 0's exact map with `run` (x0..x1 on row y) marked filled at `level`
  // (-1: the exact levels); returns the counts and the map after the test.
  RunTestCounts test(int y, int x0, int x1, int level, Plane& after) {
    after = exact.depths[0];
    std::vector<uint8_t> filled(after.samples.size(), 0);
    for (int x = x0; x <= x1; ++x) {
      if (level >= 0) after.at(x, y) = uint16_t(level);
      filled[size_t(y) * after.width + x] = 1;
    }
    return testFilledRuns(scene, 0, exact.frames(), 0, after, filled);
  }
};

TEST(MissingDepthRunTest, RunAtTheTrueLevelIsKept) {
  RunTestRig rig;
  Plane after;
  const RunTestCounts counts = rig.test(5, 30, 45, -1, after);  // row 5 lies on the plane
  EXPECT_EQ(counts.runs, 1u);
  EXPECT_EQ(counts.toFar, 0u);
  EXPECT_EQ(after.samples, rig.exact.depths[0].samples);
}

TEST(MissingDepthRunTest, RunMuchNearerThanTheSurfaceGoesFar) {
  RunTestRig rig;
  Plane after;
  const int nearLevel = maxDepthLevel(rig.analytic.range);
  ASSERT_GT(nearLevel, rig.exact.depths[0].at(38, 5) + 20);
  const RunTestCounts counts = rig.test(5, 30, 45, nearLevel, after);
  EXPECT_EQ(counts.runs, 1u);
  EXPECT_EQ(counts.toFar, 1u);
  EXPECT_EQ(counts.far, 16u);
  for (int x = 30; x <= 45; ++x) EXPECT_EQ(after.at(x, 5), 1) << x;
}

// An unmatched strip of the square (as Middlebury's maps leave at occluders' edges) filled with the
// plane's level: step 1 gives it back the square's level (the other view shows the square's colours
// there), and stops before the plane sample that ends the run.
TEST(MissingDepthRunTest, StripOfTheNearerSurfaceTakesItsLevel) {
  RunTestRig rig;
  const Plane& exact = rig.exact.depths[0];
  const int y = rig.analytic.height / 2;
  const int squareLevel = exact.at(rig.analytic.width / 2, y);
  int lastSquare = rig.analytic.width / 2;
  while (exact.at(lastSquare + 1, y) == squareLevel) ++lastSquare;
  const int planeLevel = exact.at(lastSquare + 2, y);
  ASSERT_LT(planeLevel + 20, squareLevel);
  // The run: the square's last 5 samples and the first plane sample, all at the plane's level.
  const int x0 = lastSquare - 4, x1 = lastSquare + 1;
  Plane after;
  const RunTestCounts counts = rig.test(y, x0, x1, planeLevel, after);
  EXPECT_EQ(counts.runs, 1u);
  EXPECT_EQ(counts.toNear, 1u);
  for (int x = x0; x <= lastSquare; ++x) EXPECT_EQ(after.at(x, y), squareLevel) << x;
  EXPECT_NE(after.at(x1, y), squareLevel) << "the plane sample is not drawn at the square's depth";
}

TEST(MissingDepthRunTest, HalfOccludedRunIsKept) {
  RunTestRig rig;
  const Camera& left = rig.scene.settings.references[0].camera;
  const Camera& right = rig.scene.settings.references[1].camera;
  const int y = rig.analytic.height / 2;
  // View 0's plane samples on row y that the square hides from view 1 (traced, not taken from the maps).
  int x0 = -1, x1 = -1;
  for (int x = 0; x < rig.analytic.width; ++x) {
    Vec3 hit, hitRight;
    bool onSquare = false, rightOnSquare = false;
    if (!rig.analytic.trace(left, x, y, hit, onSquare) || onSquare) continue;
    double u, v, z;
    if (!right.project(hit, u, v, z)) continue;
    if (rig.analytic.trace(right, u, v, hitRight, rightOnSquare) && rightOnSquare) {
      if (x0 < 0) x0 = x;
      x1 = x;
    }
  }
  ASSERT_GE(x0, 0);
  ASSERT_GE(x1 - x0, 3) << "a half-occluded band of a few samples";
  Plane after;
  const RunTestCounts counts = rig.test(y, x0 + 1, x1 - 1, -1, after);  // inside the band: away from rounding
  EXPECT_EQ(counts.runs, 1u);
  EXPECT_EQ(counts.toFar, 0u);
}

}  // namespace
}  // namespace vs
