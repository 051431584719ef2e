// DepthEdgeAlignment (Synth/EdgeAlign.h): depth edges moved onto texture edges, judged by a second
// view. Truth comes from the analytic scene (Test/SynthTestScene.h) and from rows built by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>


#include "Synth/Parallel.h"
#include "Common/Metrics.h"
#include "Synth/EdgeAlign.h"
#include "Synth/Warp.h"
#include "Common/Depth.h"
#include "SynthTestScene.h"
#include "TestPlan.h"

namespace vs {
namespace {

using test::AnalyticScene;

// A square in front of a plane, seen by two cameras displaced along x (horizontal) or y (vertical).
struct SquareRig {
  AnalyticScene analytic;
  Camera left, virtualCamera, right;
  Scene scene;
  explicit SquareRig(bool vertical) {
    analytic.square = true;
    analytic.width = 96;
    analytic.height = 72;
    analytic.squareHalf = 14.0;
    analytic.range = DepthRange{50.0, 200.0, 8};
    auto at = [&](const std::string& name, double offset) {
      return vertical ? analytic.camera(name, 0, offset) : analytic.camera(name, offset);
    };
    left = at("left", -3);
    virtualCamera = at("virtual", 0);
    right = at("right", 3);
    scene = analytic.scene(left, virtualCamera, right);
  }
};

// Gives the square's outermost `band` samples, at both ends of every run of square samples along
// rows (or columns), the level of the plane behind them: what Middlebury's maps do at foreground
// edges. Returns the number of samples changed; `clear` (when given) flags those whose run end is a
// clear texture edge: the luma of the square's last sample and the plane's first differ by 40 levels.
size_t codeSquareEdgesAsBackground(const AnalyticScene& analytic, const Camera& camera, const Plane& luma, int band,
                                   bool columns, Plane& depth, std::vector<uint8_t>* clear = nullptr) {
  AnalyticScene planeOnly = analytic;
  planeOnly.square = false;
  Frame unused;
  Plane plane;
  planeOnly.render(camera, unused, plane);
  const int squareLevel = int(zToLevelRounded(analytic.squareZ, analytic.range));
  const Plane truth = depth;
  if (clear) clear->assign(depth.samples.size(), 0);
  const int lines = columns ? depth.width : depth.height, length = columns ? depth.height : depth.width;
  auto index = [&](int line, int i) { return columns ? size_t(i) * depth.width + line : size_t(line) * depth.width + i; };
  auto onSquare = [&](int line, int i) { return i >= 0 && i < length && truth.samples[index(line, i)] == squareLevel; };
  size_t changed = 0;
  for (int line = 0; line < lines; ++line)
    for (int i = 0; i < length; ++i) {
      if (!onSquare(line, i)) continue;
      for (int direction : {-1, 1}) {
        int k = 1;
        while (k <= band && onSquare(line, i + direction * k)) ++k;
        if (k > band) continue;  // not within `band` of this end
        const size_t at = index(line, i);
        if (depth.samples[at] == squareLevel) ++changed;
        depth.samples[at] = plane.samples[at];
        const int end = i + direction * (k - 1), beyond = end + direction;
        if (clear && beyond >= 0 && beyond < length &&
            std::abs(int(luma.samples[index(line, end)]) - int(luma.samples[index(line, beyond)])) >= 40)
          (*clear)[at] = 1;
      }
    }
  return changed;
}

class EdgeAlignOnTheSquare : public ::testing::TestWithParam<bool> {};

// The square's last three samples coded as the plane behind it, in both references: alignment gives
// them back the square's depth, touches nothing else, and the synthesized view comes back to what the
// exact maps give.
TEST_P(EdgeAlignOnTheSquare, ForegroundEdgesCodedAsBackgroundGetTheirDepthBack) {
  const bool vertical = GetParam();
  SquareRig rig(vertical);
  test::RenderedReferences exact = test::renderReferences(rig.analytic, rig.scene);
  test::RenderedReferences coded = exact;
  size_t corrupted = 0;
  std::vector<uint8_t> clear[2];
  for (size_t k = 0; k < 2; ++k)
    corrupted += codeSquareEdgesAsBackground(rig.analytic, rig.scene.settings.references[k].camera,
                                             exact.textures[k].planes[0], 3, vertical, coded.depths[k], &clear[k]);
  ASSERT_GT(corrupted, 200u);

  DepthEdgeAligner aligner(rig.scene.settings);
  ASSERT_TRUE(aligner.enabled());
  EXPECT_EQ(aligner.witness(0), 1);
  EXPECT_EQ(aligner.witness(1), 0);
  const std::vector<const Plane*> lumas = {&coded.textures[0].planes[0], &coded.textures[1].planes[0]};
  size_t restored = 0, spoiled = 0, moved = 0, clearCount = 0, clearRestored = 0;
  for (size_t k = 0; k < 2; ++k) {
    const Plane& aligned = aligner.align(k, coded.depths[k], lumas, moved);
    for (size_t i = 0; i < aligned.samples.size(); ++i) {
      const bool wasWrong = coded.depths[k].samples[i] != exact.depths[k].samples[i];
      const bool isRight = aligned.samples[i] == exact.depths[k].samples[i];
      restored += wasWrong && isRight;
      clearCount += clear[k][i];
      clearRestored += clear[k][i] && isRight;
      spoiled += !wasWrong && !isRight;
    }
  }
  // Bands at a clear texture edge come back (88 % horizontally, 93 % vertically when this was
  // written). Where the plane happens to have the square's colour there is no texture edge to align
  // to; where the square is nearly flat along the line (around its centre) the witness sees the
  // band's colour at both depths alike, within the 4 levels a sample it needs, and cannot decide.
  EXPECT_GT(clearCount, corrupted / 2);
  EXPECT_GE(double(clearRestored), 0.8 * double(clearCount)) << clearRestored << " of " << clearCount;
  EXPECT_GE(double(restored), 0.7 * double(corrupted)) << restored << " of " << corrupted;
  EXPECT_EQ(spoiled, 0u);
  EXPECT_GE(moved, restored);

  // The same through the Synthesizer: PSNR-Y against the analytic truth.
  Frame truth;
  Plane unused;
  rig.analytic.render(rig.virtualCamera, truth, unused);
  auto synthesize = [&](test::RenderedReferences& references, int reach) {
    Scene scene = rig.scene;
    scene.settings.depthEdgeAlignment = reach;
    Synthesizer synthesizer(scene, test::planOnPath(scene));
    Frame output;
    StageTimes times;
    synthesizer.synthesize(references.frames(), output, times);
    return std::make_pair(framePsnr(truth, output).y, synthesizer.lastStats().alignedDepthSamples);
  };
  const auto [exactPsnr, exactMoved] = synthesize(exact, 4);
  const auto [codedPsnr, codedMoved] = synthesize(coded, 0);
  const auto [alignedPsnr, alignedMoved] = synthesize(coded, 4);
  EXPECT_EQ(exactMoved, 0u) << "exact depth maps have nothing to align";
  EXPECT_EQ(codedMoved, 0u);
  EXPECT_EQ(alignedMoved, moved);
  EXPECT_GT(alignedPsnr, codedPsnr + 15.0) << "coded " << codedPsnr << " aligned " << alignedPsnr;
  EXPECT_LT(alignedPsnr, exactPsnr + 0.1) << "exact " << exactPsnr << " aligned " << alignedPsnr;
  std::cout << "[ figure   ] PSNR-Y exact " << exactPsnr << ", coded " << codedPsnr << ", aligned " << alignedPsnr
            << " dB; restored " << restored << " of " << corrupted << " samples (" << clearRestored << " of "
            << clearCount << " at clear edges)\n";
}

// Rows and columns in parallel, each line's edges in order: the aligned maps do not depend on the
// number of threads (here with many moves, rows and columns).
// The alignment as it was first written (every depth edge visited, each test in turn, no flags found
// in kernels and no pre-test): rows of `depth` into `out`, then the columns of that result.
namespace plain {

int mismatch(const EdgeWitness& witness, const Plane& luma, int u, int v, int level) {
  if (size_t(level) >= witness.inverseDepth->size()) return -1;
  const double inverse = (*witness.inverseDepth)[size_t(level)];
  if (std::isnan(inverse)) return -1;
  double x, y, wv;
  if (!witness.projection->forward(u, v, inverse, x, y, wv)) return -1;
  const Plane& seen = *witness.luma;
  const double cx = std::floor(x + 0.5), cy = std::floor(y + 0.5);
  if (!(cx >= 0 && cy >= 0 && cx < seen.width && cy < seen.height)) return -1;
  const int px = int(cx), py = int(cy), colour = luma.at(u, v);
  int best = std::abs(seen.at(px, py) - colour);
  if (px > 0) best = std::min(best, std::abs(seen.at(px - 1, py) - colour));
  if (px + 1 < seen.width) best = std::min(best, std::abs(seen.at(px + 1, py) - colour));
  return best;
}

// The edge between samples i and i + 1 of line `line` (a row, or a column when `columns`).
void alignEdge(const Plane& depth, const Plane& luma, Plane& out, bool columns, int line, int i,
               const EdgeAlignOptions& o, const EdgeWitness& witness) {
  const int n = columns ? depth.height : depth.width;
  auto u = [&](int k) { return columns ? line : k; };
  auto v = [&](int k) { return columns ? k : line; };
  auto d = [&](int k) { return int(depth.at(u(k), v(k))); };
  auto y = [&](int k) { return int(luma.at(u(k), v(k))); };
  auto contrast = [&](int p) { return std::abs(y(p + 1) - y(p)); };
  const int a = d(i), b = d(i + 1);
  if (a == o.missingLevel || b == o.missingLevel || std::abs(a - b) < o.minStep) return;
  const bool nearLeft = a > b;
  const int nearLevel = std::max(a, b), toFar = nearLeft ? 1 : -1, nearSample = nearLeft ? i : i + 1;
  const int atEdge = contrast(i);
  int best = 0, bestContrast = atEdge;
  for (int k = 1; k <= o.reach; ++k) {
    const int p = i + k * toFar;
    if (p < 0 || p + 1 >= n) break;
    const int level = d(nearLeft ? p : p + 1);
    if (level == o.missingLevel || nearLevel - level < o.minStep) break;
    if (contrast(p) > bestContrast) {
      bestContrast = contrast(p);
      best = k;
    }
  }
  if (best == 0 || bestContrast < o.minContrast || bestContrast < 2 * atEdge) return;
  const int p = i + best * toFar;
  const int lo = std::min(i, p) + 1, hi = std::max(i, p), farSample = nearLeft ? hi + 1 : lo - 1;
  for (int q = std::min(i, p); q <= std::max(i, p); ++q)
    if (q != p && 2 * contrast(q) > bestContrast) return;
  for (int s = lo; s <= hi; ++s)
    if (!(std::abs(y(s) - y(nearSample)) < std::abs(y(s) - y(farSample)))) return;
  long nearError = 0, farError = 0;
  for (int s = lo; s <= hi; ++s) {
    const int en = mismatch(witness, luma, u(s), v(s), nearLevel), ef = mismatch(witness, luma, u(s), v(s), d(s));
    if (en < 0 || ef < 0) return;
    nearError += en;
    farError += ef;
  }
  if (nearError + long(hi - lo + 1) * o.minContrast / 4 >= farError) return;
  for (int s = lo; s <= hi; ++s) out.samples[size_t(v(s)) * out.width + size_t(u(s))] = uint16_t(nearLevel);
}

// `afterRows`, where given: the map after the row pass.
Plane align(const Plane& depth, const Plane& luma, const EdgeAlignOptions& o, const EdgeWitness& witness,
            Plane* afterRows = nullptr) {
  Plane rows = depth;
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x + 1 < depth.width; ++x) alignEdge(depth, luma, rows, false, y, x, o, witness);
  if (afterRows) *afterRows = rows;
  Plane out = rows;
  for (int x = 0; x < depth.width; ++x)
    for (int y = 0; y + 1 < depth.height; ++y) alignEdge(rows, luma, out, true, x, y, o, witness);
  return out;
}

}  // namespace plain

// Random maps against the plain alignment: rectangles of depth levels (near ones in front, some of the
// missing level, ramps of one level per sample) whose texture edges lie a few samples off their depth
// edges, with texture noise and flat texture, seen by a witness displaced sideways or up; every reach,
// missing level or none, luma of 8 and 10 bits. The same maps, bit for bit, and the same count
// (2000 maps: a sample moved by both passes turns up in about one in a thousand).
TEST(EdgeAlign, EqualsThePlainAlignmentOnRandomMaps) {
  const int defaultThreads = vs::workerThreads();
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto pick = [&](int n) { return int(unit(rng) * n) % n; };
  size_t moved = 0, movedTwice = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int w = 8 + pick(70), h = 8 + pick(50);
    const bool tenBits = trial % 4 == 3;
    Plane depth(w, h, uint16_t(20 + pick(20))), luma(w, h), seen(w, h);
    std::vector<int> shade(size_t(w) * h, pick(200));
    for (int r = 0; r < 12; ++r) {
      const int x0 = pick(w), y0 = pick(h), x1 = std::min(w, x0 + 2 + pick(w / 2)), y1 = std::min(h, y0 + 2 + pick(h / 2));
      const int level = pick(10) == 0 ? 0 : 30 + pick(200), ramp = pick(3) == 0 ? 1 : 0;
      const int dx = pick(9) - 4, dy = pick(9) - 4, colour = pick(256);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) depth.samples[size_t(y) * w + x] = uint16_t(std::min(255, level + ramp * (x - x0)));
      for (int y = std::max(0, y0 + dy); y < std::min(h, y1 + dy); ++y)
        for (int x = std::max(0, x0 + dx); x < std::min(w, x1 + dx); ++x) shade[size_t(y) * w + x] = colour;
    }
    const int scale = tenBits ? 4 : 1;
    for (size_t i = 0; i < shade.size(); ++i) {
      const int noise = pick(4) == 0 ? pick(12) - 6 : 0;
      luma.samples[i] = uint16_t(scale * std::clamp(shade[i] + noise, 0, 255));
    }
    // The witness: the same picture shifted by a few samples (what a nearby camera would see).
    const int shift = 1 + pick(4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) seen.samples[size_t(y) * w + x] = luma.at(std::clamp(x + shift, 0, w - 1), y);
    Camera reference, other;
    reference.K[0][0] = reference.K[1][1] = other.K[0][0] = other.K[1][1] = 100.0;
    reference.K[0][2] = other.K[0][2] = w / 2.0;
    reference.K[1][2] = other.K[1][2] = h / 2.0;
    (trial % 2 ? other.t.y : other.t.x) = unit(rng) < 0.5 ? 0.3 : -0.3;
    const ViewProjection projection(reference, other, 0);
    EdgeAlignOptions options;
    options.reach = 1 + trial % 6;
    options.minStep = 8;
    options.minContrast = 16 * scale;
    options.missingLevel = trial % 3 == 0 ? -1 : 0;
    std::vector<double> inverseDepth = inverseZTable(DepthRange{50.0, 200.0, 8});
    if (options.missingLevel == 0) inverseDepth[0] = std::nan("");
    EdgeWitness witness;
    witness.luma = &seen;
    witness.projection = &projection;
    witness.inverseDepth = &inverseDepth;
    // In place (each pass reading its lines from copies of a row or a ring of rows), on one thread or
    // on several (rows and columns split into ranges, each column range with its own ring).
    vs::setWorkerThreads(trial % 3 == 1 ? 1 : 2 + trial % 5);
    Plane out = depth;
    const size_t changed = alignDepthEdgesInPlace(out, luma, options, witness);
    Plane rows;
    const Plane expected = plain::align(depth, luma, options, witness, &rows);
    ASSERT_TRUE(out == expected) << "trial " << trial;
    size_t differ = 0;
    for (size_t i = 0; i < depth.samples.size(); ++i) {
      differ += depth.samples[i] != expected.samples[i];
      movedTwice += (depth.samples[i] != rows.samples[i]) & (rows.samples[i] != expected.samples[i]);
    }
    ASSERT_EQ(changed, differ) << "trial " << trial;
    moved += changed;
  }
  vs::setWorkerThreads(defaultThreads);
  std::cout << "[ moved ] " << moved << " samples, " << movedTwice << " by both passes\n";
  EXPECT_GT(moved, 300u);
  // A sample the row pass moved and the column pass moved again is counted once, against its level
  // before both (the in-place passes note what they change and count at the end).
  EXPECT_GT(movedTwice, 0u);
}

TEST(EdgeAlign, AnyThreadCountGivesTheSameMaps) {
  const int defaultThreads = vs::workerThreads();
  std::vector<Plane> maps[2];
  size_t moves[2] = {0, 0};
  const int counts[2] = {std::max(2, vs::availableCores()), 1};  // many first, then one
  for (int run = 0; run < 2; ++run) {
    vs::setWorkerThreads(counts[run]);
    for (bool vertical : {false, true}) {
      SquareRig rig(vertical);
      test::RenderedReferences coded = test::renderReferences(rig.analytic, rig.scene);
      for (size_t k = 0; k < 2; ++k)
        codeSquareEdgesAsBackground(rig.analytic, rig.scene.settings.references[k].camera, coded.textures[k].planes[0],
                                    3, vertical, coded.depths[k]);
      DepthEdgeAligner aligner(rig.scene.settings);
      const std::vector<const Plane*> lumas = {&coded.textures[0].planes[0], &coded.textures[1].planes[0]};
      for (size_t k = 0; k < 2; ++k) maps[run].push_back(aligner.align(k, coded.depths[k], lumas, moves[run]));
    }
  }
  vs::setWorkerThreads(defaultThreads);
  EXPECT_GT(moves[0], 400u);
  EXPECT_EQ(moves[0], moves[1]);
  ASSERT_EQ(maps[0].size(), maps[1].size());
  for (size_t i = 0; i < maps[0].size(); ++i) EXPECT_TRUE(maps[0][i] == maps[1][i]) << "map " << i;
}

INSTANTIATE_TEST_SUITE_P(Directions, EdgeAlignOnTheSquare, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) { return info.param ? "Vertical" : "Horizontal"; });

// One row by hand. Reference: a near surface (level 200) up to x = 19, a far one (level 0) from x = 20;
// the luma is 200 up to x = 22 and 60 after, so the colour edge lies three samples past the depth edge.
// Whether those three samples belong to the near surface (its depth map lost them) or are a bright
// stripe painted on the far one (the map is right), only a second view can tell: it is drawn here both
// ways, and alignment must follow it.
TEST(EdgeAlign, TheWitnessDecidesWhetherTheBandBelongsToTheNearSurface) {
  const int width = 64;
  AnalyticScene geometry;
  geometry.width = width;
  geometry.height = 1;
  geometry.range = DepthRange{50.0, 200.0, 8};
  const Camera reference = geometry.camera("reference", 0), witnessCamera = geometry.camera("witness", 5);
  const ViewProjection projection(reference, witnessCamera, 0);
  const std::vector<double> inverseDepth = inverseZTable(geometry.range);
  const int nearLevel = 200, farLevel = 0;

  Plane depth(width, 1), luma(width, 1);
  for (int x = 0; x < width; ++x) {
    depth.at(x, 0) = uint16_t(x < 20 ? nearLevel : farLevel);
    luma.at(x, 0) = uint16_t(x <= 22 ? 200 : 60);
  }
  // The witness row: every reference sample forward-warped with the level it truly has, far first.
  auto witnessRow = [&](bool bandIsNear) {
    Plane row(width, 1, 60);
    for (int pass = 0; pass < 2; ++pass)
      for (int x = 0; x < width; ++x) {
        const bool isNear = x < 20 || (bandIsNear && x <= 22);
        if (isNear != (pass == 1)) continue;
        double wx, wy, wv;
        if (!projection.forward(x, 0, inverseDepth[size_t(isNear ? nearLevel : farLevel)], wx, wy, wv)) continue;
        const long target = std::lround(wx);
        if (target >= 0 && target < width) row.at(int(target), 0) = luma.at(x, 0);
      }
    return row;
  };
  EdgeAlignOptions options;
  options.minStep = depthEdgeStep(255);
  for (bool bandIsNear : {true, false}) {
    const Plane witnessLuma = witnessRow(bandIsNear);
    EdgeWitness witness;
    witness.luma = &witnessLuma;
    witness.projection = &projection;
    witness.inverseDepth = &inverseDepth;
    Plane aligned;
    const size_t moved = alignDepthEdges(depth, luma, options, witness, aligned);
    for (int x = 0; x < width; ++x) {
      const int expected = x < 20 || (bandIsNear && x <= 22) ? nearLevel : farLevel;
      EXPECT_EQ(aligned.at(x, 0), expected) << "x " << x << (bandIsNear ? ", band on the near surface" : ", stripe");
    }
    EXPECT_EQ(moved, bandIsNear ? 3u : 0u);
  }
}

// Off with one reference view (no witness) and with DepthEdgeAlignment 0: the map comes back as it is.
TEST(EdgeAlign, OffWithoutAWitnessOrWithReachZero) {
  SquareRig rig(false);
  test::RenderedReferences coded = test::renderReferences(rig.analytic, rig.scene);
  codeSquareEdgesAsBackground(rig.analytic, rig.left, coded.textures[0].planes[0], 3, false, coded.depths[0]);
  const std::vector<const Plane*> lumas = {&coded.textures[0].planes[0], &coded.textures[1].planes[0]};

  Scene single = rig.scene;
  single.settings.references.resize(1);
  DepthEdgeAligner alone(single.settings);
  EXPECT_FALSE(alone.enabled());
  size_t moved = 0;
  EXPECT_EQ(&alone.align(0, coded.depths[0], lumas, moved), &coded.depths[0]);

  Scene off = rig.scene;
  off.settings.depthEdgeAlignment = 0;
  DepthEdgeAligner disabled(off.settings);
  EXPECT_FALSE(disabled.enabled());
  EXPECT_TRUE(disabled.align(0, coded.depths[0], lumas, moved) == coded.depths[0]);
  EXPECT_EQ(moved, 0u);

  DepthEdgeAligner on(rig.scene.settings);
  EXPECT_FALSE(on.align(0, coded.depths[0], lumas, moved) == coded.depths[0]);
  EXPECT_GT(moved, 0u);
}

// A reference centre so far away that every distance to it overflows to inf (x = 1e200, issue 24):
// each view still gets a witness (the other one), and aligning leaves a map of the right size.
// The search kept no witness and read references[size_t(-1)].
TEST(EdgeAlign, FarCentreStillHasAWitness) {
  SquareRig rig(false);
  test::RenderedReferences coded = test::renderReferences(rig.analytic, rig.scene);
  for (double x : {1e200, -1e308}) {
    Scene far = rig.scene;
    far.settings.references[0].camera.t.x = x;
    DepthEdgeAligner aligner(far.settings);
    ASSERT_TRUE(aligner.enabled());
    EXPECT_EQ(aligner.witness(0), 1) << x;
    EXPECT_EQ(aligner.witness(1), 0) << x;
    const std::vector<const Plane*> lumas = {&coded.textures[0].planes[0], &coded.textures[1].planes[0]};
    size_t moved = 0;
    const Plane& aligned = aligner.align(0, coded.depths[0], lumas, moved);
    EXPECT_EQ(aligned.samples.size(), coded.depths[0].samples.size());
  }
}

}  // namespace
}  // namespace vs
