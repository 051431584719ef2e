// The plan: which path and which stages a scene gets, and why; the 1D path against analytic truth.
#include <cmath>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Metrics.h"
#include "Common/Options.h"
#include "Plan/Plan.h"
#include "Synth/ViewSynRenderer.h"
#include "SynthTestScene.h"
#include "TestPaths.h"
#include "TestPlan.h"

namespace vs {
namespace {

using test::AnalyticScene;

Scene rigScene(const AnalyticScene& analytic, SynthesisMode mode, double rotation = 0) {
  Camera left = analytic.camera("left", -4), virtualCamera = analytic.camera("virtual", 1), right = analytic.camera("right", 4);
  if (rotation != 0) {  // rotate the right camera about y
    right.R = Mat3::identity();
    right.R[0][0] = right.R[2][2] = std::cos(rotation);
    right.R[0][2] = -std::sin(rotation);
    right.R[2][0] = std::sin(rotation);
  }
  Scene scene = analytic.scene(left, virtualCamera, right);
  scene.settings.mode = mode;
  return scene;
}

TEST(Plan, AutoPicksTheOneDimensionalPathForARectifiedRigAndSaysWhy) {
  AnalyticScene analytic;
  const Plan plan = makePlan(rigScene(analytic, SynthesisMode::Auto));
  EXPECT_EQ(plan.mode, SynthesisMode::Parallel1D);
  EXPECT_NE(plan.lines()[0].find("auto: the rig is rectified"), std::string::npos) << plan.lines()[0];
  EXPECT_TRUE(plan.blend);
  EXPECT_TRUE(plan.chroma);
  EXPECT_EQ(plan.copyOf, -1);
}

TEST(Plan, AutoPicksTheGeneralPathForARotatedRigAndMode1IsRefusedWithTheDeviation) {
  AnalyticScene analytic;
  const Plan plan = makePlan(rigScene(analytic, SynthesisMode::Auto, 0.01));
  EXPECT_EQ(plan.mode, SynthesisMode::General);
  EXPECT_NE(plan.lines()[0].find("rotation differs by 0.573 deg"), std::string::npos) << plan.lines()[0];
  try {
    makePlan(rigScene(analytic, SynthesisMode::Parallel1D, 0.01));
    FAIL() << "SynthesisMode 1 on a rotated rig must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Right: rotation differs by 0.573 deg"), std::string::npos) << e.what();
  }
  // A camera off the x axis and a different cy are reported too.
  Camera raised = analytic.camera("raised", 4, 0.5), shifted = analytic.camera("shifted", 4);
  shifted.K[1][2] += 2;
  const Rectification offAxis = checkRectification(raised, analytic.camera("virtual", 0), 0);
  EXPECT_FALSE(offAxis.rectified());
  EXPECT_NEAR(offAxis.offAxis, 0.5 / std::hypot(4, 0.5), 1e-12);
  EXPECT_NEAR(checkRectification(shifted, analytic.camera("virtual", 0), 0).cyDifference, 2.0, 1e-12);
}

TEST(Plan, CopiesWhenTheVirtualCameraIsAReferenceAndSkipsWhatIsNotThere) {
  AnalyticScene analytic;
  const Camera left = analytic.camera("left", -4), right = analytic.camera("right", 4);
  EXPECT_EQ(makePlan(analytic.scene(left, right, right)).copyOf, 1);
  AnalyticScene grey = analytic;
  grey.chroma = ChromaFormat::Yuv400;
  Scene single = grey.scene(left, analytic.camera("virtual", 1), right);
  single.settings.references.pop_back();
  const Plan plan = makePlan(single);
  EXPECT_FALSE(plan.blend);
  EXPECT_FALSE(plan.chroma);
}

// DepthEdgeAlignment needs a second view to judge its moves: the plan says whether it runs and why.
TEST(Plan, SaysWhetherDepthEdgesAreAlignedAndWhy) {
  AnalyticScene analytic;
  auto depthEdgeLine = [](const Plan& plan) {
    for (const std::string& line : plan.lines())
      if (line.rfind("depth edges: ", 0) == 0) return line;
    return std::string("(no depth edges line)");
  };
  Scene scene = rigScene(analytic, SynthesisMode::General);
  EXPECT_NE(depthEdgeLine(makePlan(scene)).find("up to 4 samples away where the nearest other reference view agrees"),
            std::string::npos)
      << depthEdgeLine(makePlan(scene));
  scene.settings.depthEdgeAlignment = 0;
  EXPECT_NE(depthEdgeLine(makePlan(scene)).find("as given (DepthEdgeAlignment 0)"), std::string::npos);
  scene.settings.depthEdgeAlignment = 4;
  scene.settings.references.pop_back();
  EXPECT_NE(depthEdgeLine(makePlan(scene)).find("as given (one reference view"), std::string::npos);
}

// The decisions against values worked out here from the cameras and depth ranges: the left camera
// 5 units from the virtual one, the right 3 (weights 1/d, normalised), the depth tolerances (n + 0.5)
// 8-bit levels of the mean inverse-depth range.
TEST(Plan, WeightsAndTolerancesFollowFromTheCamerasAndTheDepthRanges) {
  AnalyticScene analytic;
  Scene scene = rigScene(analytic, SynthesisMode::General);
  scene.settings.depthBlendDifference = 5;
  const double inverseRange = 1.0 / analytic.range.znear - 1.0 / analytic.range.zfar;
  auto levels = [&](double n) { return (n + 0.5) / 255.0 * inverseRange; };
  const Plan plan = makePlan(scene);
  ASSERT_EQ(plan.blending.weights.size(), 2u);
  EXPECT_NEAR(plan.blending.weights[0], (1.0 / 5) / (1.0 / 5 + 1.0 / 3), 1e-15);
  EXPECT_NEAR(plan.blending.weights[1], (1.0 / 3) / (1.0 / 5 + 1.0 / 3), 1e-15);
  EXPECT_NEAR(plan.blending.depthTolerance, levels(5), 1e-18);
  EXPECT_NEAR(plan.lumaFill.depthTolerance, levels(5), 1e-18);
  EXPECT_NEAR(plan.discontinuity, levels(8), 1e-18);
  EXPECT_FALSE(plan.blending.nearestViewOnly);
  EXPECT_EQ(plan.edgeLevelStep, 8);  // 8-bit depth
  // The same step of 8 in 255 levels on deeper maps: 8 / 255 * 1023 = 32.1, 8 / 255 * 65535 = 2056.
  scene.settings.depthFormat.bitDepth = 10;
  EXPECT_EQ(makePlan(scene).edgeLevelStep, 32);
  scene.settings.depthFormat.bitDepth = 16;
  EXPECT_EQ(makePlan(scene).edgeLevelStep, 2056);
  // Hole filling on a rectified rig mixes the three estimates 2 : 3 : 1; an empty layer is black
  // (16) in luma and mid-grey (128) in chroma.
  EXPECT_TRUE(plan.lumaFill.backgroundFirst);
  EXPECT_EQ(plan.lumaFill.directionalWeight, 2.0f);
  EXPECT_EQ(plan.lumaFill.rowRunWeight, 3.0f);
  EXPECT_EQ(plan.lumaFill.inpaintWeight, 1.0f);
  EXPECT_EQ(plan.lumaFill.emptyValue[0], 16.0f);
  EXPECT_EQ(plan.lumaFill.emptyValue[1], 128.0f);
  EXPECT_EQ(plan.chromaFill.emptyValue[0], 128.0f);
  EXPECT_EQ(plan.chromaFill.emptyValue[1], 128.0f);

  // The right camera turned by 0.01 rad: its distance counts the turn, scaled by the mean distance
  // (4), and the rig is not rectified, so hole filling leaves the row runs out (1 : 0 : 1).
  const Plan turned = makePlan(rigScene(analytic, SynthesisMode::General, 0.01));
  const double right = 3 + 4 * 0.01;
  EXPECT_NEAR(turned.blending.weights[0], (1.0 / 5) / (1.0 / 5 + 1.0 / right), 1e-12);
  EXPECT_FALSE(turned.rectified);
  EXPECT_EQ(turned.lumaFill.directionalWeight, 1.0f);
  EXPECT_EQ(turned.lumaFill.rowRunWeight, 0.0f);
  EXPECT_EQ(turned.lumaFill.inpaintWeight, 1.0f);

  // 1D MergingOption: 0 one level of tolerance, 1 averaging everywhere, 2 DepthThreshold levels (by
  // default DepthBlendDifference's); the general path and hole filling do not look at it.
  Scene oneD = rigScene(analytic, SynthesisMode::Parallel1D);
  oneD.settings.depthBlendDifference = 5;
  oneD.settings.oneD.merging = 0;
  EXPECT_NEAR(makePlan(oneD).blending.depthTolerance, levels(1), 1e-18);
  EXPECT_NEAR(test::planOnPath(oneD, SynthesisMode::General).blending.depthTolerance, levels(5), 1e-18);
  EXPECT_NEAR(makePlan(oneD).lumaFill.depthTolerance, levels(5), 1e-18);
  oneD.settings.oneD.merging = 1;
  EXPECT_TRUE(std::isinf(makePlan(oneD).blending.depthTolerance));
  oneD.settings.oneD.merging = 2;
  EXPECT_NEAR(makePlan(oneD).blending.depthTolerance, levels(5), 1e-18);
  oneD.settings.oneD.depthThreshold = 3;
  EXPECT_NEAR(makePlan(oneD).blending.depthTolerance, levels(3), 1e-18);
  EXPECT_TRUE(makePlan(oneD).crowdedHoles);
  EXPECT_FALSE(test::planOnPath(oneD, SynthesisMode::General).crowdedHoles);
}

// MeshRender blends and fills as ViewSyn's general path does (it no longer asks a Synthesizer), and
// what it cannot do is refused by its plan: no virtual depth output.
TEST(Plan, MeshRenderGetsTheGeneralPathsOptionsAndIsRefusedTheVirtualDepth) {
  AnalyticScene analytic;
  Scene scene = rigScene(analytic, SynthesisMode::Parallel1D);
  scene.settings.oneD.merging = 0;  // a 1D key: not MeshRender's
  const Plan mesh = makePlan(scene, Tool::MeshRender);
  const Plan general = test::planOnPath(scene, SynthesisMode::General);
  EXPECT_EQ(mesh.mode, SynthesisMode::General);
  EXPECT_EQ(mesh.blending.weights, general.blending.weights);
  EXPECT_EQ(mesh.blending.depthTolerance, general.blending.depthTolerance);
  EXPECT_EQ(mesh.lumaFill.depthTolerance, general.blending.depthTolerance);
  EXPECT_EQ(mesh.lumaFill.rowRunWeight, general.lumaFill.rowRunWeight);
  ASSERT_EQ(mesh.notApplied.size(), 1u);
  EXPECT_NE(mesh.notApplied[0].find("the 1D mode does not apply"), std::string::npos);

  scene.settings.virtualDepthPath = "/nonexistent/virtual_depth.yuv";
  EXPECT_TRUE(makePlan(scene).virtualDepthOutput);
  try {
    makePlan(scene, Tool::MeshRender);
    FAIL() << "MeshRender cannot write OutputVirtualDepthMapName";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("OutputVirtualDepthMapName '/nonexistent/virtual_depth.yuv'"), std::string::npos)
        << e.what();
  }
}

// The printed lines and the key/value fields are made from the plan's fields: change a field and
// both say so; numbers in the fields read back exactly.
TEST(Plan, LinesAndFieldsAreMadeFromThePlansFields) {
  AnalyticScene analytic;
  Plan plan = makePlan(rigScene(analytic, SynthesisMode::Auto));
  auto field = [](const Plan& p, const std::string& key) {
    std::string value = "(missing)";
    int count = 0;
    for (const auto& [k, v] : p.fields())
      if (k == key) {
        value = v;
        ++count;
      }
    EXPECT_EQ(count, 1) << key;
    return value;
  };
  EXPECT_EQ(field(plan, "path"), "1d");
  EXPECT_EQ(field(plan, "tool"), "ViewSyn");
  const std::string weights = field(plan, "blend_weights");
  const size_t comma = weights.find(',');
  ASSERT_NE(comma, std::string::npos) << weights;
  EXPECT_EQ(std::strtod(weights.substr(0, comma).c_str(), nullptr), plan.blending.weights[0]);
  EXPECT_EQ(std::strtod(weights.substr(comma + 1).c_str(), nullptr), plan.blending.weights[1]);
  EXPECT_EQ(std::strtod(field(plan, "blend_depth_tolerance").c_str(), nullptr), plan.blending.depthTolerance);
  EXPECT_EQ(std::strtod(field(plan, "discontinuity").c_str(), nullptr), plan.discontinuity);

  plan.blending.weights = {0.25, 0.75};
  plan.precision = 2;
  plan.rgb = true;
  bool weightsLine = false, textureLine = false;
  for (const std::string& line : plan.lines()) {
    weightsLine = weightsLine || line == "blend weights: Left 0.2500 Right 0.7500";
    textureLine = textureLine || line == "texture: Precision 2, Filter 1, processed in RGB";
  }
  EXPECT_TRUE(weightsLine);
  EXPECT_TRUE(textureLine);
  EXPECT_EQ(field(plan, "blend_weights"), "0.25,0.75");

  const Camera left = analytic.camera("left", -4), right = analytic.camera("right", 4);
  const Plan copy = makePlan(analytic.scene(left, right, right));
  EXPECT_EQ(field(copy, "path"), "copy");
  EXPECT_EQ(field(copy, "copy_of"), "Right");
  ASSERT_EQ(copy.lines().size(), 1u);
  EXPECT_EQ(copy.lines()[0].rfind("copy: the virtual camera 'right' is the Right camera", 0), 0u) << copy.lines()[0];
  EXPECT_EQ(field(makePlan(analytic.scene(left, right, right), Tool::MeshRender), "path"), "mesh");
}

TEST(Plan, OneReferenceViewIsAValidConfigWithoutAnyRightKey) {
  const std::string text =
      "SourceWidth 64\nSourceHeight 48\nLeftNearestDepthValue 50\nLeftFarthestDepthValue 120\n"
      "CameraParameterFile cams.txt\nLeftCameraName a\nVirtualCameraName b\nLeftViewImageName a.yuv\n"
      "LeftDepthMapName da.yuv\nOutputVirtualViewImageName out.yuv\n";
  const Config config = Config::fromText(viewSynOptionTable(), text, "one.cfg", "/tmp");
  EXPECT_EQ(readSynthesisSettings(config).references.size(), 1u);
  // Some Right keys but not all: each missing one is named.
  const Config partial = Config::fromText(viewSynOptionTable(), text + "RightCameraName c\n", "one.cfg", "/tmp");
  try {
    readSynthesisSettings(partial);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing key 'RightDepthMapName'"), std::string::npos) << e.what();
  }
}

TEST(OneD, ParallelPathMatchesTheAnalyticViewAndTheGeneralPath) {
  AnalyticScene analytic;
  analytic.square = true;
  Scene oneD = rigScene(analytic, SynthesisMode::Parallel1D);
  oneD.settings.oneD.splatting = 1;
  const Frame truth = [&] {
    Frame t;
    Plane d;
    analytic.render(oneD.virtualCamera, t, d);
    return t;
  }();
  test::RenderedReferences rendered = test::renderReferences(analytic, oneD);
  const std::vector<ReferenceFrame> refs = rendered.frames();
  Frame parallel, general;
  StageTimes times;
  Synthesizer(oneD, test::planOnPath(oneD, SynthesisMode::Parallel1D)).synthesize(refs, parallel, times);
  Synthesizer(oneD, test::planOnPath(oneD, SynthesisMode::General)).synthesize(refs, general, times);
  EXPECT_GT(framePsnr(truth, parallel).y, 32.0);
  // Same geometry: the two paths agree closely (not bitwise: the 1D path merges by its own keys).
  EXPECT_GT(framePsnr(general, parallel).y, 40.0);
  // The identity stays exact on the 1D path.
  Scene identity = oneD;
  identity.virtualCamera = identity.settings.references[0].camera;
  Frame copy;
  Synthesizer(identity, test::planOnPath(identity, SynthesisMode::Parallel1D)).synthesize(refs, copy, times);
  EXPECT_TRUE(copy == rendered.textures[0]);
}

// TemporalImprovementOption: where every reference row is unchanged since the previous frame, hole
// samples keep the previous frame's fill; elsewhere the frame is what a fresh synthesis gives. The
// second frame brightens the references' lower half (depth unchanged), which changes the fill of
// holes in the upper half too (it reaches across rows): those must keep the first frame's values.
TEST(OneD, TemporalImprovementKeepsThePreviousFillWhereTheReferenceRowsAreUnchanged) {
  AnalyticScene analytic;
  analytic.square = true;
  Scene scene = rigScene(analytic, SynthesisMode::Parallel1D);
  scene.virtualCamera = analytic.camera("virtual", 9);  // beyond the right camera: holes to fill
  test::RenderedReferences first = test::renderReferences(analytic, scene), second = first;
  const int h = analytic.height, changedFrom = h / 2;
  for (Frame& texture : second.textures)
    for (int p = 0; p < 3; ++p) {
      Plane& plane = texture.planes[size_t(p)];
      const int from = p == 0 ? changedFrom : changedFrom / 2;  // 4:2:0: chroma row j covers rows 2j, 2j + 1
      for (int y = from; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x) plane.at(x, y) = uint16_t(std::min(255, plane.at(x, y) + 40));
    }
  for (bool temporal : {true, false}) {
    scene.settings.oneD.temporalImprovement = temporal;
    Synthesizer sequence(scene, test::planOnPath(scene, SynthesisMode::Parallel1D));
    Frame output1, output2, fresh2;
    StageTimes times;
    sequence.synthesize(first.frames(), output1, times);
    sequence.synthesize(second.frames(), output2, times);
    Synthesizer(scene, test::planOnPath(scene, SynthesisMode::Parallel1D)).synthesize(second.frames(), fresh2, times);
    if (!temporal) {
      EXPECT_TRUE(output2 == fresh2);
      continue;
    }
    bool fillChangedAbove = false;
    for (int p = 0; p < 3; ++p) {
      const int split = p == 0 ? changedFrom : changedFrom / 2;
      const Plane &a = output1.planes[size_t(p)], &b = output2.planes[size_t(p)], &f = fresh2.planes[size_t(p)];
      for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x) {
          if (y < split) {
            ASSERT_EQ(b.at(x, y), a.at(x, y)) << "plane " << p << " unchanged row " << y << " x " << x;
            fillChangedAbove |= f.at(x, y) != a.at(x, y);
          } else {
            ASSERT_EQ(b.at(x, y), f.at(x, y)) << "plane " << p << " changed row " << y << " x " << x;
          }
        }
    }
    EXPECT_TRUE(fillChangedAbove);  // else the test would not tell keeping from recomputing
  }
}

// TemporalImprovementOption changes nothing on a first frame; a synthesizer told there is no next frame
// (Synthesizer::noNextFrame, a run of one frame) keeps nothing for one and gives that frame bit for bit.
TEST(OneD, TemporalImprovementWithoutANextFrameGivesTheSameFrame) {
  AnalyticScene analytic;
  analytic.square = true;
  Scene scene = rigScene(analytic, SynthesisMode::Parallel1D);
  scene.virtualCamera = analytic.camera("virtual", 9);  // beyond the right camera: holes to fill
  scene.settings.oneD.temporalImprovement = true;
  test::RenderedReferences rendered = test::renderReferences(analytic, scene);
  Synthesizer keeping(scene, test::planOnPath(scene, SynthesisMode::Parallel1D));
  Synthesizer last(scene, test::planOnPath(scene, SynthesisMode::Parallel1D));
  last.noNextFrame();
  Frame kept, alone;
  StageTimes times;
  keeping.synthesize(rendered.frames(), kept, times);
  last.synthesize(rendered.frames(), alone, times);
  EXPECT_GT(last.lastStats().holesAfterBlend, 0u);  // there was fill to keep or not
  EXPECT_TRUE(alone == kept);
}

// Real data: the shipped general configs run on the 1D path (`SynthesisMode=1`, the 1D keys at their
// defaults) give the general path's PSNR-Y within 0.1 dB. The scenes are those where VSRS's own 1D
// defaults (DepthThreshold 75, CleanNoiseOption 1) cost the most (0.5 to 1.1 dB).
TEST(OneD, OnMiddleburyThe1DPathIsWithinATenthOfADecibelOfTheGeneralPath) {
  const std::filesystem::path data = test::dataDir();
  VS_REQUIRE_DIR(data / "middlebury2006");
  const std::filesystem::path scratch = test::scratchDir("oned_middlebury");
  for (const char* scene : {"middlebury2005/Art", "middlebury2005/Laundry", "middlebury2006/Cloth2", "middlebury2006/Midd1"}) {
    const std::filesystem::path config = data / scene / "synth_view3_general.cfg";
    if (!std::filesystem::exists(config)) GTEST_SKIP() << config << " is absent";
    double psnr[2] = {0, 0};
    for (int mode : {0, 1}) {
      const Config c = Config::load(viewSynOptionTable(), config.string(),
                                    {"SynthesisMode=" + std::to_string(mode),
                                     "OutputVirtualViewImageName=" + (scratch / "out.yuv").string(),
                                     "ReferenceVirtualViewImageName=" + (data / scene / "view3.yuv").string()});
      psnr[mode] = runViewSyn(c, nullptr).meanPsnrY;
    }
    EXPECT_GT(psnr[0], 30.0) << scene;
    EXPECT_NEAR(psnr[1], psnr[0], 0.1) << scene;
  }
}

}  // namespace
}  // namespace vs
