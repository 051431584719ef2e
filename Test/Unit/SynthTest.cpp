// Synthesis against analytic truth (Test/SynthTestScene.h) and the VSRS 4.2 defects that must not
// exist here, one test each.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <random>

#include <opencv2/photo.hpp>

#include "Common/Metrics.h"
#include "Synth/ExactDivision.h"
#include "Synth/HoleFill.h"
#include "Synth/Parallel.h"
#include "Synth/Interpolation.h"
#include "Synth/Layer.h"
#include "Synth/Warp.h"
#include "SynthTestScene.h"
#include "TestPlan.h"

namespace vs {
namespace {

using test::AnalyticScene;

Frame truthOf(const AnalyticScene& analytic, const Camera& camera) {
  Frame texture;
  Plane depth;
  analytic.render(camera, texture, depth);
  return texture;
}

double psnrY(const Frame& a, const Frame& b) { return framePsnr(a, b).y; }

TEST(Synth, PlaneBetweenTwoViewsMatchesTheAnalyticView) {
  AnalyticScene analytic;
  const Camera left = analytic.camera("left", -4), virtualCamera = analytic.camera("virtual", 0), right = analytic.camera("right", 4);
  const Scene scene = analytic.scene(left, virtualCamera, right);
  const Frame output = test::synthesizeOnce(analytic, scene);
  const Frame truth = truthOf(analytic, virtualCamera);
  EXPECT_GT(psnrY(truth, output), 40.0);
  EXPECT_GT(framePsnr(truth, output).u, 40.0);
  EXPECT_GT(framePsnr(truth, output).v, 40.0);
}

TEST(Synth, OccludingSquareIsPlacedAndItsDisocclusionFilledFromTheOtherView) {
  AnalyticScene analytic;
  analytic.square = true;
  const Camera left = analytic.camera("left", -6), virtualCamera = analytic.camera("virtual", 1), right = analytic.camera("right", 6);
  const Scene scene = analytic.scene(left, virtualCamera, right);
  const Frame output = test::synthesizeOnce(analytic, scene);
  const Frame truth = truthOf(analytic, virtualCamera);
  EXPECT_GT(psnrY(truth, output), 32.0);
  // The square's centre projects to u = cx + f * (0 - 1) / 60 in the virtual view.
  const int u = int(std::lround((analytic.width - 1) / 2.0 - analytic.focal / 60.0)), v = (analytic.height - 1) / 2;
  EXPECT_NEAR(output.planes[0].at(u, v), truth.planes[0].at(u, v), 2);
}

// MissingDepthLevel with MissingDepthFill: a patch of the background with unknown depth in both
// references (as Middlebury's occlusion areas are) is warped with its neighbours' background depth,
// which puts it where it belongs; without the fill it is a hole left to the hole filler, and as the
// far plane it lands in the wrong place.
TEST(Synth, MissingDepthFillWarpsUnknownBackgroundWithTheBackgroundsDepth) {
  AnalyticScene analytic;
  analytic.square = true;
  analytic.width = 96;
  analytic.range = DepthRange{50.0, 200.0, 8};
  const Camera left = analytic.camera("left", -6), virtualCamera = analytic.camera("virtual", 1), right = analytic.camera("right", 6);
  Scene scene = analytic.scene(left, virtualCamera, right);
  test::RenderedReferences rendered = test::renderReferences(analytic, scene);
  for (Plane& depth : rendered.depths)
    // Unknown depth on the background plane, right of the square in both views: 12 x 16 samples.
    for (int y = 16; y < 32; ++y)
      for (int x = 70; x < 82; ++x) {
        ASSERT_EQ(depth.at(x, y), depth.at(69, y));  // on the plane
        depth.at(x, y) = 0;
      }
  const std::vector<ReferenceFrame> references = rendered.frames();
  const Frame truth = truthOf(analytic, virtualCamera);
  auto synthesize = [&](const Scene& s) {
    Frame output;
    StageTimes times;
    Synthesizer(s, test::planOnPath(s)).synthesize(references, output, times);
    return psnrY(truth, output);
  };
  const double asFarPlane = synthesize(scene);
  scene.settings.missingDepthLevel = 0;
  const double holes = synthesize(scene);
  scene.settings.missingDepthFill = true;
  const double filled = synthesize(scene);
  EXPECT_GT(filled, asFarPlane + 3.0) << "far plane " << asFarPlane;
  EXPECT_GT(filled, holes + 1.0) << "holes " << holes;
  EXPECT_GT(filled, 35.0);
}

// A sample only one view shows is dropped when it lies far behind the surface the other view shows
// around that hole, on both sides along a row or a column (a sample of unknown depth coded as the
// far plane, typically). Not where the other view has no surroundings on both sides: here the square
// stands at the left border of the right camera's picture, so the strip of plane left of it in the
// virtual view is seen by the left camera only, and the right view's layer has nothing left of it.
// The left view's plane is far behind the square, and right: it stays.
TEST(Synth, SamplesInAStripTheOtherViewCannotSeeAreKept) {
  AnalyticScene analytic;
  analytic.square = true;
  analytic.range = DepthRange{50.0, 200.0, 8};
  const Camera left = analytic.camera("left", 6), virtualCamera = analytic.camera("virtual", 15),
               right = analytic.camera("right", 24);
  const Scene scene = analytic.scene(left, virtualCamera, right);
  const Frame output = test::synthesizeOnce(analytic, scene);
  const Frame truth = truthOf(analytic, virtualCamera);
  // The square's left edge is at virtual u = 8.5; the right camera sees no plane left of u = 5.4.
  double worst = 0;
  for (int y = 18; y <= 29; ++y)
    for (int x = 0; x <= 4; ++x)
      worst = std::max(worst, std::fabs(double(output.planes[0].at(x, y)) - truth.planes[0].at(x, y)));
  EXPECT_LE(worst, 6.0) << "76 when the right view's square alone judged the strip";
}

// The square seen from -6, 1 and 6 with level 0 read as unknown depth and filled, and references in
// which the plane left of the square has unknown depth in the left view only (the right view sees it).
struct SquareWithUnknownPatch {
  AnalyticScene analytic;
  Scene scene;
};

SquareWithUnknownPatch squareWithUnknownPatch() {
  SquareWithUnknownPatch s;
  s.analytic.square = true;
  s.analytic.width = 96;
  s.analytic.range = DepthRange{50.0, 200.0, 8};
  s.scene = s.analytic.scene(s.analytic.camera("left", -6), s.analytic.camera("virtual", 1), s.analytic.camera("right", 6));
  s.scene.settings.missingDepthLevel = 0;
  s.scene.settings.missingDepthFill = true;
  return s;
}

void clearLeftPlanePatch(test::RenderedReferences& rendered) {
  for (int y = 16; y < 32; ++y)
    for (int x = 8; x < 20; ++x) rendered.depths[0].at(x, y) = 0;
}

// Filled samples stay unreliable when depth edge alignment runs after the fill: where the other view
// sees the same surface with a real depth, that view's colour wins. On exact maps alignment moves
// nothing, so the output with it on must equal the output with it off, bit for bit.
TEST(Synth, FilledSamplesStayUnreliableWhenEdgesAreAligned) {
  const SquareWithUnknownPatch patch = squareWithUnknownPatch();
  const Scene& scene = patch.scene;
  test::RenderedReferences rendered = test::renderReferences(patch.analytic, scene);
  clearLeftPlanePatch(rendered);
  auto synthesize = [&](int reach, size_t& moved) {
    Scene s = scene;
    s.settings.depthEdgeAlignment = reach;
    Synthesizer synthesizer(s, test::planOnPath(s));
    Frame output;
    StageTimes times;
    synthesizer.synthesize(rendered.frames(), output, times);
    moved = synthesizer.lastStats().alignedDepthSamples;
    return output;
  };
  size_t movedOff = 0, movedOn = 0;
  const Frame off = synthesize(0, movedOff), on = synthesize(4, movedOn);
  EXPECT_EQ(movedOn, 0u);
  EXPECT_TRUE(on == off);
}

// A run of one frame frees each step's buffers once the step is over (Synthesizer::
// releaseBuffersAfterEachStep); a sequence keeps them for its next frame. Nothing later in the frame
// may read what was freed, and what grows again must not depend on what it held: a synthesizer that
// frees, given two different frames in a row, gives bit for bit what one that keeps gives, on both
// paths, with missing depth filled and tested, edges aligned and chroma.
TEST(Synth, FreeingSpentBuffersInAOneFrameRunChangesNoOutput) {
  SquareWithUnknownPatch patch = squareWithUnknownPatch();
  Scene& scene = patch.scene;
  scene.settings.depthEdgeAlignment = 4;
  test::RenderedReferences first = test::renderReferences(patch.analytic, scene), second = first;
  // The second frame: unknown depth on the plane in the left view, and the square's texture changed.
  clearLeftPlanePatch(second);
  for (Frame& texture : second.textures)
    for (uint16_t& sample : texture.planes[0].samples) sample = uint16_t(255 - sample);
  for (SynthesisMode path : {SynthesisMode::General, SynthesisMode::Parallel1D}) {
    auto run = [&](bool release) {
      Synthesizer synthesizer(scene, test::planOnPath(scene, path));
      if (release) synthesizer.releaseBuffersAfterEachStep();
      std::vector<Frame> outputs(2);
      StageTimes times;
      synthesizer.synthesize(first.frames(), outputs[0], times);
      synthesizer.synthesize(second.frames(), outputs[1], times);
      return outputs;
    };
    const std::vector<Frame> oneFrame = run(true), sequence = run(false);
    EXPECT_TRUE(oneFrame[0] == sequence[0]) << "path " << int(path);
    EXPECT_TRUE(oneFrame[1] == sequence[1]) << "path " << int(path);
    EXPECT_FALSE(oneFrame[0] == oneFrame[1]);  // the frames differ, so stale buffers would show
  }
}

// A one- or two-row line of unknown depth coded as the far plane across a nearer surface (as
// Middlebury's maps have between touching objects) warps into the crack it leaves in that surface, with
// far-plane depth and so the colour of the wrong spot. The warped depth closes such slivers like any
// crack: the line takes the surface's depth and colour.
TEST(Synth, FarSliversInsideASurfaceAreClosedLikeCracks) {
  AnalyticScene analytic;
  analytic.square = true;
  analytic.width = 96;
  analytic.squareHalf = 14.0;
  analytic.range = DepthRange{50.0, 200.0, 8};
  const Camera left = analytic.camera("left", -3), virtualCamera = analytic.camera("virtual", 0), right = analytic.camera("right", 3);
  const Scene scene = analytic.scene(left, virtualCamera, right);
  const Frame truth = truthOf(analytic, virtualCamera);
  const int squareLevel = int(zToLevelRounded(analytic.squareZ, analytic.range));
  for (int rows : {1, 2}) {
    test::RenderedReferences rendered = test::renderReferences(analytic, scene);
    for (Plane& depth : rendered.depths)
      for (int y = 24; y < 24 + rows; ++y)
        for (int x = 0; x < analytic.width; ++x)
          if (depth.at(x, y) == squareLevel) depth.at(x, y) = 0;  // the far plane's level
    Frame output;
    StageTimes times;
    Synthesizer(scene, test::planOnPath(scene)).synthesize(rendered.frames(), output, times);
    // The square covers |u - cx| < 14 at z = 60 in the virtual view: look well inside it.
    double worst = 0;
    int compared = 0;
    for (int y = 24; y < 24 + rows; ++y)
      for (int x = 36; x <= 59; ++x, ++compared)
        worst = std::max(worst, std::fabs(double(output.planes[0].at(x, y)) - truth.planes[0].at(x, y)));
    EXPECT_EQ(compared, 24 * rows);
    EXPECT_LE(worst, 4.0) << rows << " row(s) of far-plane depth inside the square";
  }
}

// VSRS 4.2: "the virtual camera equal to the left camera" must give back the left view exactly.
TEST(Synth, VirtualCameraOnAReferenceReproducesItBitExactlyForEveryPrecisionAndFilter) {
  AnalyticScene analytic;
  analytic.square = true;
  analytic.width = 34;  // not a multiple of 4 (VSRS 4.2 corrupts such frames)
  analytic.height = 26;
  const Camera left = analytic.camera("left", -5), right = analytic.camera("right", 5);
  for (int precision : {1, 2, 4})
    for (int filter : {0, 1, 2}) {
      for (const Camera* target : {&left, &right}) {
        Scene scene = analytic.scene(left, *target, right);
        scene.settings.precision = precision;
        scene.settings.filter = filter;
        const Frame output = test::synthesizeOnce(analytic, scene);
        EXPECT_TRUE(output == truthOf(analytic, *target))
            << "Precision " << precision << " Filter " << filter << " camera " << target->name;
      }
    }
}

// VSRS 4.2: general mode with Precision 1 writes a black picture.
TEST(Synth, IntegerPelGeneralModeIsAPicture) {
  AnalyticScene analytic;
  const Camera left = analytic.camera("left", -4), virtualCamera = analytic.camera("virtual", 1.3), right = analytic.camera("right", 4);
  Scene scene = analytic.scene(left, virtualCamera, right);
  scene.settings.precision = 1;
  EXPECT_GT(psnrY(truthOf(analytic, virtualCamera), test::synthesizeOnce(analytic, scene)), 30.0);
}

// VSRS 4.2 re-quantises the virtual depth to 8 bits, so depths outside the reference range wrap.
TEST(Synth, VirtualDepthOutsideTheReferenceRangeStaysRight) {
  AnalyticScene analytic;
  analytic.square = true;
  analytic.squareHalf = 6;
  // The virtual camera moves 25 units forward: the square is then 35 away, nearer than Znear = 50.
  // Wrapped depth would put the square elsewhere; checked well inside its 20-sample-wide image.
  const Camera left = analytic.camera("left", -3), virtualCamera = analytic.camera("virtual", 0, 0, 25), right = analytic.camera("right", 3);
  const Scene scene = analytic.scene(left, virtualCamera, right);
  const Frame output = test::synthesizeOnce(analytic, scene);
  const Frame truth = truthOf(analytic, virtualCamera);
  const int cx = (analytic.width - 1) / 2, cy = (analytic.height - 1) / 2;
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx) EXPECT_NEAR(output.planes[0].at(cx + dx, cy + dy), truth.planes[0].at(cx + dx, cy + dy), 4);
}

// VSRS 4.2 never checks for points behind the camera: they wrap around to the front as ghosts.
TEST(Synth, PointsBehindTheVirtualCameraNeverShowUp) {
  AnalyticScene analytic;
  const Camera left = analytic.camera("left", -4), right = analytic.camera("right", 4);
  Camera backwards = analytic.camera("virtual", 0, 0, 10);
  backwards.R = Mat3::identity();
  backwards.R[0][0] = -1;  // rotated 180 degrees about y: it looks down -z, away from the plane
  backwards.R[2][2] = -1;
  const Scene scene = analytic.scene(left, backwards, right);
  const Frame output = test::synthesizeOnce(analytic, scene);
  // Nothing is visible: every sample is the hole filler's empty value, none is scene texture.
  for (uint16_t sample : output.planes[0].samples) ASSERT_EQ(sample, 16);
  for (uint16_t sample : output.planes[1].samples) ASSERT_EQ(sample, 128);
}

// VSRS 4.2 divides by zero when both baselines are zero.
TEST(Synth, ZeroBaselinesShareTheWeight) {
  EXPECT_EQ(baselineWeights({0.0, 0.0}), (std::vector<double>{0.5, 0.5}));
  EXPECT_EQ(baselineWeights({0.0, 3.0}), (std::vector<double>{1.0, 0.0}));
  const std::vector<double> w = baselineWeights({1.0, 3.0});
  EXPECT_DOUBLE_EQ(w[0], 0.75);  // VSRS: d_right / (d_left + d_right)
  EXPECT_DOUBLE_EQ(w[1], 0.25);
  AnalyticScene analytic;
  const Camera here = analytic.camera("here", 2);
  const Scene scene = analytic.scene(here, here, here);
  EXPECT_TRUE(test::synthesizeOnce(analytic, scene) == truthOf(analytic, here));
}

TEST(Synth, DepthType1AndInfiniteZfar) {
  AnalyticScene analytic;
  analytic.depthType = 1;
  analytic.planeZ = 110;
  analytic.range = DepthRange{60.0, 130.0, 8};  // world z
  const Camera left = analytic.camera("left", -4, 0, 10), virtualCamera = analytic.camera("virtual", 1, 0, 10),
               right = analytic.camera("right", 4, 0, 10);
  EXPECT_GT(psnrY(truthOf(analytic, virtualCamera), test::synthesizeOnce(analytic, analytic.scene(left, virtualCamera, right))), 38.0);

  AnalyticScene infinite;
  infinite.range = DepthRange{50.0, HUGE_VAL, 16};
  const Camera l = infinite.camera("left", -4), v = infinite.camera("virtual", 1), r = infinite.camera("right", 4);
  EXPECT_GT(psnrY(truthOf(infinite, v), test::synthesizeOnce(infinite, infinite.scene(l, v, r))), 40.0);
}

// VSRS 4.2 compares depth levels as signed chars in blending: 200 counts as nearer than... nothing.
TEST(Synth, BlendingTakesTheNearerSurfaceForHighDepthLevels) {
  const DepthRange range{50.0, 120.0, 8};
  WarpedLayer near, far;
  near.reset(1, 1, 1);
  far.reset(1, 1, 1);
  near.inverseDepth[0] = levelToInverseZ(200, range);
  near.colour[0][0] = 200;
  far.inverseDepth[0] = levelToInverseZ(100, range);
  far.colour[0][0] = 100;
  BlendOptions options;
  options.weights = {0.5, 0.5};
  options.depthTolerance = 5 / 255.0 * (1 / 50.0 - 1 / 120.0);
  BlendedLayer out;
  blendLayers({&far, &near}, options, out);
  EXPECT_EQ(out.colour[0][0], 200.0f);
  // Within the tolerance the two are one surface and mixed by weight.
  far.inverseDepth[0] = levelToInverseZ(197, range);
  options.weights = {0.25, 0.75};
  blendLayers({&far, &near}, options, out);
  EXPECT_FLOAT_EQ(out.colour[0][0], 0.25f * 100 + 0.75f * 200);
}

TEST(Synth, ViewProjectionRoundTripsAndRejectsPointsBehind) {
  AnalyticScene analytic;
  Camera reference = analytic.camera("ref", 1e6 - 3, 1e6);  // far from the origin: must not cost precision
  Camera target = analytic.camera("tgt", 1e6 + 2, 1e6, 1);
  target.R[0][2] = 0.05;  // a slightly rotated target (re-orthonormalised below)
  target.R[2][0] = -0.05;
  target.R[0][0] = target.R[2][2] = std::sqrt(1 - 0.05 * 0.05);
  const ViewProjection forward(reference, target, 0), backward(reference, target, 0);
  for (double u : {0.0, 10.5, 63.0})
    for (double z : {50.0, 80.0, 120.0}) {
      double x, y, wv, bu, bv;
      ASSERT_TRUE(forward.forward(u, 20, 1 / z, x, y, wv));
      ASSERT_TRUE(backward.backward(x, y, wv, bu, bv));
      EXPECT_NEAR(bu, u, 1e-6);
      EXPECT_NEAR(bv, 20, 1e-6);
    }
  // A point 5 units in front of the reference is behind a target 10 units further forward.
  const Camera ahead = analytic.camera("ahead", 0, 0, 10);
  double x, y, wv;
  EXPECT_FALSE(ViewProjection(analytic.camera("ref", 0), ahead, 0).forward(30, 20, 1 / 5.0, x, y, wv));
  EXPECT_TRUE(ViewProjection(analytic.camera("ref", 0), ahead, 0).forward(30, 20, 1 / 15.0, x, y, wv));
  EXPECT_NEAR(1 / wv, 5.0, 1e-12);
}

// The 1D row maps: rowSource inverts rowTarget, and equals the division by rowScale it stands for,
// bit for bit, whether the target's focal length is the reference's times a power of two (where
// rowSource multiplies by the exact reciprocal) or not.
TEST(Synth, RowSourceInvertsRowTargetAndEqualsTheDivisionForAnyFocalRatio) {
  AnalyticScene analytic;
  const Camera reference = analytic.camera("ref", 0);
  for (double ratio : {1.0, 2.0, 0.5, 0.25, 3.0, 0.7, 1.0000001}) {
    Camera target = analytic.camera("tgt", 2.5);
    target.K[0][0] = target.K[1][1] = analytic.focal * ratio;
    const ViewProjection projection(reference, target, 0, true);
    const double rowScale = target.K[0][0] / reference.K[0][0];
    // x_tgt = x_ref - (2.5, 0, 0): the target sits 2.5 to the right.
    const double rowOffset = target.K[0][2] - rowScale * reference.K[0][2], rowShift = target.K[0][0] * -2.5;
    for (double wv : {0.0, 1 / 120.0, 1 / 61.3, 1 / 50.0})
      for (double x = -3.0; x < 70.0; x += 0.37) {
        const double expected = ViewProjection::snapPosition((x - rowOffset - rowShift * wv) / rowScale);
        ASSERT_EQ(projection.rowSource(x, wv), expected) << "ratio " << ratio << " x " << x << " wv " << wv;
        EXPECT_NEAR(projection.rowTarget(projection.rowSource(x, wv), wv), x, 1e-6) << "ratio " << ratio;
      }
  }
}

// exactReciprocal stands in for divisions that decide output bits (blend weights, the 1D row map):
// it must give x / d exactly, and refuse every d it cannot.
TEST(Synth, ExactReciprocalGivesTheQuotientBitForBitOrRefuses) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> value(-1e6, 1e6);
  for (int k = -1022; k <= 1022; k += 7)
    for (double sign : {1.0, -1.0}) {
      const double d = sign * std::ldexp(1.0, k), r = exactReciprocal(d);
      ASSERT_NE(r, 0.0) << "2^" << k;
      for (int t = 0; t < 20; ++t) {
        const double x = value(random) * std::ldexp(1.0, int(random() % 200) - 100);
        ASSERT_EQ(x * r, x / d) << x << " / 2^" << k;
      }
      const float f = float(value(random));
      ASSERT_EQ(float(double(f) * r), float(double(f) / d));
    }
  for (double d : {3.0, 0.75, 1.0000000000000002, 0.0, -0.0, std::ldexp(1.0, 1023), std::ldexp(1.0, -1030),
                   HUGE_VAL, std::nan("")})
    EXPECT_EQ(exactReciprocal(d), 0.0) << d;
}

TEST(Interpolation, IntegerPositionsReturnTheSampleForEveryFilter) {
  Plane plane(5, 4);
  for (size_t i = 0; i < plane.samples.size(); ++i) plane.samples[i] = uint16_t(i * 37 % 251);
  for (int precision : {1, 2, 4})
    for (int filter : {0, 1, 2}) {
      const SubPixelSampler sampler(precision, filter);
      for (int phase = 0; phase < precision; ++phase) {
        const float* k = sampler.kernel(phase);
        EXPECT_NEAR(std::accumulate(k, k + sampler.taps(), 0.0f), 1.0f, 1e-6f);
      }
      for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x) EXPECT_EQ(sampler.sample(plane, x, y), float(plane.at(x, y)));
    }
}

// VSRS 4.2's bicubic filter reads before the row start, and it truncates negative coordinates
// towards zero. Here edges read the nearest edge sample and positions round on the 1/P grid.
TEST(Interpolation, EdgesClampAndNegativePositionsRoundDownwards) {
  Plane ramp(4, 1);
  for (int x = 0; x < 4; ++x) ramp.at(x, 0) = uint16_t(100 + 10 * x);
  const SubPixelSampler bilinear(4, 0), bicubic(4, 1), avc(4, 2);
  // -0.25 lies between the (clamped) sample -1 and sample 0: both are 100.
  EXPECT_FLOAT_EQ(bilinear.sample(ramp, -0.25, 0), 100.0f);
  EXPECT_FLOAT_EQ(bilinear.sample(ramp, 0.25, 0), 102.5f);
  EXPECT_FLOAT_EQ(bilinear.sample(ramp, 3.75, 0), 130.0f);
  // Taps at -2, -1, 0, 1 read 100, 100, 100, 110 (the first two clamped): 100 - 0.0625 * 10.
  EXPECT_FLOAT_EQ(bicubic.sample(ramp, -0.5, 0), 99.375f);
  // A 1x1 plane: every filter reads only its one sample, wherever it is asked.
  const Plane single(1, 1, 77);
  for (const SubPixelSampler* s : {&bilinear, &bicubic, &avc})
    for (double x : {-0.75, -0.25, 0.0, 0.5, 0.75}) EXPECT_FLOAT_EQ(s->sample(single, x, x), 77.0f);
  // Precision 2 rounds 0.3 to the half-pel 0.5, Precision 1 to 0.
  EXPECT_FLOAT_EQ(SubPixelSampler(2, 0).sample(ramp, 1.3, 0), 115.0f);
  EXPECT_FLOAT_EQ(SubPixelSampler(1, 0).sample(ramp, 1.3, 0), 110.0f);
}

TEST(HoleFill, HolesTakeTheBackgroundNeverTheForeground) {
  // A row: background (far, 50) | hole x 6 | foreground (near, 200).
  BlendedLayer layer;
  layer.reset(12, 5, 1);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 12; ++x) {
      const size_t i = size_t(y) * 12 + x;
      if (x < 3) {
        layer.colour[0][i] = 50;
        layer.inverseDepth[i] = 0.01;
        layer.hole[i] = 0;
      } else if (x >= 9) {
        layer.colour[0][i] = 200;
        layer.inverseDepth[i] = 0.05;
        layer.hole[i] = 0;
      }
    }
  // Background is 50, foreground 200. The background-side estimates (directional, row runs) take
  // the background alone, and so does the whole mix where the inpainting fills the nearer surface
  // too (chroma's setting). Luma's inpainting fills only the holes and sees both sides: its share
  // of the mix (1 of 2 + 3 + 1) is all the foreground that reaches a hole.
  for (int setting = 0; setting < 3; ++setting) {
    BlendedLayer filled = layer;
    HoleFillOptions options;
    options.backgroundFirst = true;
    options.depthTolerance = 0.001;
    if (setting == 0) options.inpaintWeight = 0.0f;
    options.inpaintNearerSurface = setting == 1;
    EXPECT_EQ(fillHoles(filled, options), size_t(6 * 5));
    EXPECT_EQ(filled.holeCount(), 0u);
    const float foregroundShare = setting == 2 ? 1.0f / 6.0f : 0.0f;
    for (int y = 0; y < 5; ++y)
      for (int x = 3; x < 9; ++x)
        EXPECT_NEAR(filled.colour[0][size_t(y) * 12 + x], 50.0f, 5.0f + 150.0f * foregroundShare)
            << x << "," << y << " setting " << setting;
  }
  // IvsrsInpaint 0 is VSRS's plain inpainting: it does not know depth and mixes both sides in.
  {
    BlendedLayer filled = layer;
    HoleFillOptions options;
    options.backgroundFirst = false;
    fillHoles(filled, options);
    EXPECT_EQ(filled.holeCount(), 0u);
    EXPECT_GT(filled.colour[0][size_t(2) * 12 + 8], 100.0f);  // next to the foreground: mostly foreground
    EXPECT_LT(filled.colour[0][size_t(2) * 12 + 3], 100.0f);  // next to the background: mostly background
  }
  // Nothing valid at all: the empty value.
  BlendedLayer empty;
  empty.reset(4, 4, 1);
  HoleFillOptions options;
  options.emptyValue[0] = 16;
  fillHoles(empty, options);
  for (float v : empty.colour[0]) EXPECT_EQ(v, 16.0f);
}

// The row-run estimate alone (IvsrsInpaint 1 with only its weight): one colour per run, the mean of
// the candidates on the farthest surface among the run's ends and the first samples up and down from
// its middle. Where both ends are foreground, the rays reach the background above the run.
TEST(HoleFill, RowRunsTakeTheMeanOfTheirFarthestCandidates) {
  const int w = 11, h = 9;
  auto layerWith = [&](float aboveColour, double aboveDepth) {
    BlendedLayer layer;
    layer.reset(w, h, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        if (y == 4 && x >= 2 && x <= 8) continue;  // the run: x 2 to 8 of row 4
        layer.hole[i] = 0;
        layer.inverseDepth[i] = y < 4 ? aboveDepth : 0.05;
        layer.colour[0][i] = y < 4 ? aboveColour : 200.0f;
      }
    return layer;
  };
  HoleFillOptions options;
  options.depthTolerance = 0.001;
  options.directionalWeight = options.inpaintWeight = 0.0f;
  // Ends on the far surface (10 and 30), everything around nearer: the ends' mean on every sample.
  BlendedLayer ends = layerWith(200.0f, 0.05);
  ends.colour[0][4 * w + 1] = 10.0f;
  ends.colour[0][4 * w + 9] = 30.0f;
  ends.inverseDepth[4 * w + 1] = ends.inverseDepth[4 * w + 9] = 0.01;
  fillHoles(ends, options);
  for (int x = 2; x <= 8; ++x) EXPECT_FLOAT_EQ(ends.colour[0][4 * w + x], 20.0f) << x;
  EXPECT_DOUBLE_EQ(ends.inverseDepth[4 * w + 5], 0.01);
  // Both ends foreground (200, near); background (60, far) fills the rows above: the run is 60.
  BlendedLayer above = layerWith(60.0f, 0.01);
  fillHoles(above, options);
  for (int x = 2; x <= 8; ++x) EXPECT_FLOAT_EQ(above.colour[0][4 * w + x], 60.0f) << x;
  // The directional estimate alone, in the first case, leans to the nearer end: not one colour.
  BlendedLayer directional = layerWith(200.0f, 0.05);
  directional.colour[0][4 * w + 1] = 10.0f;
  directional.colour[0][4 * w + 9] = 30.0f;
  directional.inverseDepth[4 * w + 1] = directional.inverseDepth[4 * w + 9] = 0.01;
  options.directionalWeight = 1.0f;
  options.rowRunWeight = 0.0f;
  fillHoles(directional, options);
  EXPECT_LT(directional.colour[0][4 * w + 2], 15.0f);
  EXPECT_GT(directional.colour[0][4 * w + 8], 25.0f);
}

// The 1D path's row sampler is sample() with an integer y, bit for bit: every Precision and Filter,
// positions inside, at and beyond the borders (also negative), rows at the top and bottom edge and
// outside the plane.
TEST(SubPixelSampler, RowSamplingEqualsTwoDimensionalSamplingOnWholeRows) {
  Plane plane(23, 7);
  std::mt19937 random(11);
  for (uint16_t& v : plane.samples) v = uint16_t(random() % 1024);
  std::uniform_real_distribution<double> position(-4.0, 27.0);
  for (int precision : {1, 2, 4})
    for (int filter : {0, 1, 2}) {
      const SubPixelSampler sampler(precision, filter);
      for (int k = 0; k < 2000; ++k) {
        const double x = k < 64 ? -4.0 + k * 0.125 : position(random);  // the first: every phase, and ties
        for (long long y : {-2LL, 0LL, 1LL, 3LL, 6LL, 9LL}) {
          const float a = sampler.sample(plane, x, double(y)), b = sampler.sampleRow(plane, x, y);
          ASSERT_EQ(a, b) << "Precision " << precision << " Filter " << filter << " x " << x << " y " << y;
        }
      }
    }
}

// A reference and a target camera for the row projections' tests: random focal lengths and
// principal points, the same y focal length and principal point; rectified (a shift along x only) or
// turned about y (up to 0.3 rad, or 3 rad in one trial of seven) and moved anywhere.
std::pair<Camera, Camera> randomPair(std::mt19937& random, int trial, bool rectified) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Camera reference, target;
  reference.K[0][0] = reference.K[1][1] = 500 + 1500 * unit(random);
  target.K[0][0] = target.K[1][1] = 500 + 1500 * unit(random);
  reference.K[0][2] = target.K[0][2] = 320 * unit(random);
  reference.K[1][2] = target.K[1][2] = 240 * unit(random);
  if (!rectified) {
    const double a = (unit(random) - 0.5) * (trial % 7 == 1 ? 6.0 : 0.6), c = std::cos(a), sn = std::sin(a);
    target.R = Mat3{{{c, 0, sn}, {0, 1, 0}, {-sn, 0, c}}};
  }
  target.t = Vec3((unit(random) - 0.5) * 200, rectified ? 0.0 : (unit(random) - 0.5) * 50,
                  rectified ? 0.0 : (unit(random) - 0.5) * 300);
  return {reference, target};
}

// The general depth warp projects a row in one vectorised pass (ViewProjection::forwardRow): where
// forward() succeeds, its results bit for bit; elsewhere -1. Rotated and rectified rigs, DepthType 0
// and 1 (which take forward() sample by sample), points behind either camera, on the camera plane
// and far off the picture, NaN, negative, signed-zero and huge inverse depths.
TEST(ViewProjection, ForwardRowEqualsForwardAtEachSample) {
  std::mt19937 random(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const bool rectified = trial % 4 == 0;
    const auto [reference, target] = randomPair(random, trial, rectified);
    const int depthType = rectified ? 0 : trial % 3 == 2 ? 1 : 0;
    const ViewProjection projection(reference, target, depthType, rectified && trial % 8 == 0);
    const int n = 1 + int(300 * unit(random));
    const double v = trial % 5 == 0 ? 1e7 * (unit(random) - 0.5) : std::floor(480 * unit(random));
    std::vector<double> inverse(static_cast<size_t>(n)), xs(static_cast<size_t>(n)), ys(static_cast<size_t>(n)),
        ws(static_cast<size_t>(n));
    for (double& w : inverse) {
      const double u = unit(random);
      w = u < 0.05 ? std::nan("") : u < 0.1 ? -unit(random) / 100 : u < 0.13 ? 0.0 : u < 0.16 ? -0.0
          : u < 0.18 ? 1e300 : unit(random) / 50;
    }
    projection.forwardRow(inverse.data(), n, v, xs.data(), ys.data(), ws.data());
    for (int u = 0; u < n; ++u) {
      const size_t k = size_t(u);
      double x = 0, y = 0, w = 0;
      const bool ok = !std::isnan(inverse[k]) && projection.forward(u, v, inverse[k], x, y, w);
      if (!ok) {
        ASSERT_EQ(ws[k], -1.0) << "trial " << trial << " u " << u << ": forward() refuses this sample";
        continue;
      }
      ASSERT_EQ(std::memcmp(&x, &xs[k], sizeof x), 0) << "trial " << trial << " u " << u << " x";
      ASSERT_EQ(std::memcmp(&y, &ys[k], sizeof y), 0) << "trial " << trial << " u " << u << " y";
      ASSERT_EQ(std::memcmp(&w, &ws[k], sizeof w), 0) << "trial " << trial << " u " << u << " w";
    }
  }
}

// The general texture and chroma warps project a row back in one vectorised pass
// (ViewProjection::backwardRow): ok where backward() succeeds, and then its results bit for bit, at
// luma positions and at chroma block centres. Rotated and rectified rigs, the rectified form (which
// calls backward()), points behind the reference camera, far rows, and holes, zero, huge and NaN
// inverse depths.
TEST(ViewProjection, BackwardRowEqualsBackwardAtEachSample) {
  std::mt19937 random(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const bool rectified = trial % 4 == 0;
    const auto [reference, target] = randomPair(random, trial, rectified);
    const ViewProjection projection(reference, target, 0, rectified && trial % 8 == 0);
    const int n = 1 + int(300 * unit(random)), step = 1 + trial % 2;
    const double start = step == 2 ? 0.5 : 0.0;
    const double y = trial % 5 == 0 ? 1e7 * (unit(random) - 0.5) : std::floor(480 * unit(random)) + start;
    std::vector<double> wv(static_cast<size_t>(n)), us(static_cast<size_t>(n)), vs(static_cast<size_t>(n));
    std::vector<uint8_t> ok(static_cast<size_t>(n));
    for (double& w : wv) {
      const double u = unit(random);
      w = u < 0.05 ? std::nan("") : u < 0.1 ? -1.0 : u < 0.13 ? 0.0 : u < 0.16 ? 1e300 : unit(random) / 50;
    }
    projection.backwardRow(wv.data(), n, y, us.data(), vs.data(), ok.data(), step, start);
    for (int i = 0; i < n; ++i) {
      const size_t k = size_t(i);
      double u = 0, v = 0;
      const bool expected = projection.backward(i * step + start, y, wv[k], u, v);
      ASSERT_EQ(bool(ok[k]), expected) << "trial " << trial << " i " << i;
      if (!expected) continue;
      ASSERT_EQ(std::memcmp(&u, &us[k], sizeof u), 0) << "trial " << trial << " i " << i << " u";
      ASSERT_EQ(std::memcmp(&v, &vs[k], sizeof v), 0) << "trial " << trial << " i " << i << " v";
    }
  }
}

// The 1D warps compute a row's source positions in one vectorised pass (ViewProjection::rowSources):
// bit for bit rowSource at each position, for focal-length ratios that are powers of two (the
// multiplication by the reciprocal) and not (the division), luma steps and chroma block centres,
// and depths that are holes (-1), zero, signed zero, huge or NaN.
TEST(ViewProjection, RowSourcesEqualRowSourceAtEachPosition) {
  std::mt19937 random(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double ratios[] = {1.0, 2.0, 0.5, 1.37, 0.8};
  for (int trial = 0; trial < 200; ++trial) {
    Camera reference, target;
    reference.K[0][0] = reference.K[1][1] = std::round(500 + 1500 * unit(random));
    target.K[0][0] = target.K[1][1] = reference.K[0][0] * ratios[trial % 5];
    reference.K[0][2] = 300 * unit(random);
    target.K[0][2] = trial % 3 == 0 ? reference.K[0][2] : 300 * unit(random);
    target.t.x = (trial % 2 ? -1 : 1) * (1 + 100 * unit(random));
    const ViewProjection projection(reference, target, 0, true);
    const int n = 1 + int(200 * unit(random)), step = 1 + trial % 2;
    const double start = step == 2 ? 0.5 : 0.0;
    std::vector<double> depth(static_cast<size_t>(n)), sources(static_cast<size_t>(n));
    for (double& wv : depth) {
      const double u = unit(random);
      wv = u < 0.1 ? -1.0 : u < 0.15 ? 0.0 : u < 0.2 ? -0.0 : u < 0.22 ? 1e300 : u < 0.25 ? std::nan("") : unit(random) / 1000;
    }
    projection.rowSources(depth.data(), n, sources.data(), step, start);
    for (int i = 0; i < n; ++i) {
      const double expected = projection.rowSource(i * step + start, depth[size_t(i)]);
      ASSERT_EQ(std::memcmp(&expected, &sources[size_t(i)], sizeof expected), 0)
          << "trial " << trial << " i " << i << ": " << expected << " vs " << sources[size_t(i)];
    }
  }
}

// A row sampled once at every grid position (SampledRow, the 1D warps' look-up table) gives
// sampleRowTaps bit for bit: every Precision and Filter, rows narrower than the kernel, tables that
// cover the row, part of it or more than it, positions inside, on and beyond the borders and far
// outside (the general rounding), rows outside the plane.
TEST(SubPixelSampler, SampledRowEqualsRowSamplingAtEveryPosition) {
  std::mt19937 random(5);
  for (int width : {1, 2, 3, 5, 23, 64}) {
    Plane plane(width, 3);
    for (uint16_t& v : plane.samples) v = uint16_t(random() % 1024);
    std::uniform_real_distribution<double> position(-4.0, width + 4.0);
    for (int precision : {1, 2, 4})
      for (int filter : {0, 1, 2}) {
        const SubPixelSampler sampler(precision, filter);
        sampler.withTaps([&](auto taps) {
          constexpr int kTaps = decltype(taps)::value;
          const long long ranges[][2] = {{-1, width}, {0, width - 1}, {2, width / 2}, {-6, width + 6}, {3, 1}};
          for (const auto& range : ranges)
            for (long long y : {-1LL, 0LL, 2LL, 5LL}) {
              SampledRow row;
              row.build<kTaps>(sampler, plane, y, range[0], range[1]);
              for (int k = 0; k < 600; ++k) {
                const double x = k < 160 ? -5.0 + k * 0.0625 : k < 164 ? (k % 2 ? 1e17 : -3e16) : position(random);
                const float a = sampler.sampleRowTaps<kTaps>(plane, x, y), b = row.at<kTaps>(x);
                ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0)
                    << "width " << width << " Precision " << precision << " Filter " << filter << " range ["
                    << range[0] << ", " << range[1] << "] y " << y << " x " << x << ": " << a << " vs " << b;
                // The general warps read the table for any v that rounds to row y (wholeRow): the 2D
                // sampler's value there.
                const double v = double(y) + (k % 5 - 2) * 0.2 / precision;
                long long whole;
                ASSERT_TRUE(sampler.wholeRow(v, whole) && whole == y) << "v " << v;
                const float c = sampler.sampleTaps<kTaps>(plane, x, v);
                ASSERT_EQ(std::memcmp(&c, &b, sizeof c), 0)
                    << "2D, width " << width << " Precision " << precision << " Filter " << filter << " y " << y
                    << " v " << v << " x " << x << ": " << c << " vs " << b;
                if (precision > 1) {
                  const double between = double(y) + 0.5;  // half a row: phase precision / 2
                  ASSERT_FALSE(sampler.wholeRow(between, whole)) << "v " << between;
                }
              }
            }
        });
      }
  }
}

// fillHoles inpaints groups of holes apart, each in a crop (HoleFill.cpp), all channels in one march
// (Synth/Telea.h): the result must be exactly OpenCV's inpainting of the whole picture, channel by
// channel, also with groups just far enough apart to be split, groups next to the picture's border
// and one large hole, for several radii.
TEST(HoleFill, InpaintingGroupByGroupEqualsInpaintingTheWholePicture) {
  const int w = 160, h = 96;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> colour(0.0f, 255.0f);
  const int radii[] = {3, 1, 2, 5, 3, 8};
  for (int trial = 0; trial < 6; ++trial) {
    const int radius = radii[trial], channels = 1 + trial % 3;
    BlendedLayer layer;
    layer.reset(w, h, channels);
    for (size_t i = 0; i < layer.hole.size(); ++i) {
      layer.hole[i] = 0;
      layer.inverseDepth[i] = 0.01;
      for (int c = 0; c < channels; ++c) layer.colour[c][i] = colour(random);
    }
    auto hole = [&](int x, int y) {
      if (x >= 0 && y >= 0 && x < w && y < h) layer.hole[size_t(y) * w + x] = 1;
    };
    std::uniform_int_distribution<int> px(-3, w + 2), py(-3, h + 2), length(1, 14 + 10 * (trial % 4));
    for (int k = 0; k < 40; ++k) {  // slivers, dots and blobs, some across the border
      const int x = px(random), y = py(random), l = length(random);
      for (int t = 0; t < l; ++t) hole(x + (k % 3 == 0 ? t : 0), y + (k % 3 == 1 ? t : 0));
      if (k % 3 == 2)
        for (int dy = 0; dy < l / 2; ++dy)
          for (int dx = 0; dx < l / 2; ++dx) hole(x + dx, y + dy);
    }
    for (int y = 40; y < 60; ++y)  // two holes about the splitting distance apart
      for (int x : {20, 20 + 2 * (radius + 2) + 1 + trial % 2}) hole(x, y);
    std::vector<uint8_t> mask = layer.hole;
    cv::Mat maskMat(h, w, CV_8UC1, mask.data());
    std::vector<float> expected[3];
    for (int c = 0; c < channels; ++c) {
      cv::Mat channel(h, w, CV_32FC1, layer.colour[c].data()), inpainted;
      cv::inpaint(channel, maskMat, inpainted, radius, cv::INPAINT_TELEA);
      expected[c].assign(inpainted.ptr<float>(), inpainted.ptr<float>() + size_t(w) * h);
    }
    HoleFillOptions options;
    options.backgroundFirst = false;
    options.inpaintRadius = radius;
    options.inpaintLikeOpenCv = true;  // OpenCV's (without it: Test/Unit/HoleFillTest.cpp)
    ASSERT_GT(fillHoles(layer, options), 0u);
    for (int c = 0; c < channels; ++c)
      for (size_t i = 0; i < expected[c].size(); ++i)
        ASSERT_EQ(layer.colour[c][i], expected[c][i]) << "trial " << trial << " channel " << c << " sample " << i;
  }
}

// Luma and chroma are filled in one call that shares the inpainting among the threads: each layer
// must come out exactly as when filled alone, with one thread or two.
TEST(HoleFill, FillingLayersTogetherEqualsFillingEachAlone) {
  std::mt19937 random(3);
  auto makeLayer = [&](int w, int h, int channels) {
    BlendedLayer layer;
    layer.reset(w, h, channels);
    std::uniform_real_distribution<float> colour(0.0f, 255.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const bool near = (x / 9 + y / 7) % 3 == 0;  // a nearer surface in patches
        layer.inverseDepth[i] = near ? 0.02 : 0.01;
        for (int c = 0; c < channels; ++c) layer.colour[c][i] = colour(random) * 0.2f + (near ? 180.0f : 40.0f);
        layer.hole[i] = (x % 23 < 2 + (y % 5)) || random() % 40 == 0;  // strips and scattered samples
        if (layer.hole[i]) layer.inverseDepth[i] = kNoDepth;
      }
    return layer;
  };
  const BlendedLayer luma = makeLayer(120, 80, 1), chroma = makeLayer(60, 40, 2);
  HoleFillOptions lumaOptions, chromaOptions;
  lumaOptions.depthTolerance = chromaOptions.depthTolerance = 0.001;
  chromaOptions.emptyValue[0] = chromaOptions.emptyValue[1] = 128;
  chromaOptions.inpaintNearerSurface = true;  // as the plan sets it for chroma
  const int threadsBefore = vs::workerThreads();
  for (int threads : {1, 2}) {
    vs::setWorkerThreads(threads);
    BlendedLayer lumaAlone = luma, chromaAlone = chroma, lumaTogether = luma, chromaTogether = chroma;
    fillHoles(lumaAlone, lumaOptions);
    fillHoles(chromaAlone, chromaOptions);
    HoleFillScratch lumaScratch, chromaScratch;
    fillHoles({{&lumaTogether, &lumaOptions, &lumaScratch}, {&chromaTogether, &chromaOptions, &chromaScratch}});
    EXPECT_EQ(lumaTogether.colour[0], lumaAlone.colour[0]) << threads << " threads";
    EXPECT_EQ(lumaTogether.inverseDepth, lumaAlone.inverseDepth) << threads << " threads";
    for (int c = 0; c < 2; ++c) EXPECT_EQ(chromaTogether.colour[c], chromaAlone.colour[c]) << threads << " threads";
    EXPECT_EQ(lumaTogether.holeCount(), 0u);
    EXPECT_EQ(chromaTogether.holeCount(), 0u);
    EXPECT_NE(lumaTogether.colour[0], luma.colour[0]);  // something was filled
  }
  vs::setWorkerThreads(threadsBefore);
}

}  // namespace
}  // namespace vs
