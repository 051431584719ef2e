#include "Plan/MissingDepth.h"

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "Common/Depth.h"
#include "Common/Error.h"

namespace vs {

namespace {

// The world point a level-0 sample at (u, v) describes when level 0 is Zfar; false when there is none
// in front of the camera (an infinite Zfar is replaced by a distance far beyond Znear).
bool farPoint(const ReferenceView& view, int depthType, double u, double v, Vec3& point) {
  double z = view.depthRange.zfar;
  if (!std::isfinite(z)) z = 1e6 * std::abs(view.depthRange.znear);
  double zCam = z;
  if (depthType == kDepthTypeWorld) {
    const Vec3 centre = view.camera.centre(), ray = view.camera.rayDirectionWorld(u, v);
    if (std::abs(ray.z) < 1e-12) return false;
    const double s = (z - centre.z) / ray.z;
    if (!(s > 0)) return false;
    point = centre + ray * s;
    return true;
  }
  if (!(zCam > 0)) return false;
  point = view.camera.backProject(u, v, zCam);
  return true;
}

std::string percent(double fraction) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f %%", 100.0 * fraction);
  return buffer;
}

}  // namespace

namespace {

// runner(count, body), or body(0, count) without one.
void runViews(const ViewRangeRunner& runner, size_t count, const std::function<void(int, int)>& body) {
  if (runner) runner(int(count), body);
  else body(0, int(count));
}

}  // namespace

std::vector<FarEvidence> testFarReading(const Scene& scene, const std::vector<ReferenceFrame>& references,
                                        const ViewRangeRunner& runner) {
  const SynthesisSettings& s = scene.settings;
  VS_CHECK(references.size() == s.references.size());
  std::vector<FarEvidence> evidence(references.size());
  const double colourTolerance = kFarColourTolerance * double(s.textureFormat.maxValue());
  // Each view's evidence on its own (the views' tests only read the frame).
  runViews(runner, references.size(), [&](int first, int last) {
  for (size_t k = size_t(first); k < size_t(last); ++k) {
    const Plane& depth = *references[k].depth;
    const Plane& luma = references[k].texture->planes[0];
    FarEvidence& e = evidence[k];
    e.samples = depth.samples.size();
    for (uint16_t level : depth.samples) e.level0 += level == 0;
    for (int y = 0; y < depth.height; y += 2)
      for (int x = 0; x < depth.width; x += 2) {
        if (depth.at(x, y) != 0) continue;
        Vec3 point;
        if (!farPoint(s.references[k], s.depthType, x, y, point)) continue;
        // Seen by another view: hidden there (a valid nearer surface) or seen (level 0 there too, the
        // colours must agree). Outside every other view: no evidence either way.
        bool seen = false, contradicted = false;
        for (size_t j = 0; j < references.size(); ++j) {
          if (j == k) continue;
          double u, v, zCam;
          if (!s.references[j].camera.project(point, u, v, zCam)) continue;
          const int ju = int(std::lround(u)), jv = int(std::lround(v));
          const Plane& otherDepth = *references[j].depth;
          if (ju < 0 || jv < 0 || ju >= otherDepth.width || jv >= otherDepth.height) continue;
          seen = true;
          const Plane& otherLuma = references[j].texture->planes[0];
          const bool nearer = otherDepth.at(ju, jv) != 0;
          const bool otherColour = std::abs(double(luma.at(x, y)) - double(otherLuma.at(ju, jv))) > colourTolerance;
          if (nearer || otherColour) {
            contradicted = true;
          } else {
            contradicted = false;  // one view that agrees is enough
            break;
          }
        }
        e.tested += seen;
        e.contradicted += seen && contradicted;
      }
  }
  });
  return evidence;
}

RunTestCounts testFilledRuns(const Scene& scene, size_t k, const std::vector<ReferenceFrame>& references,
                             int missingLevel, Plane& filledDepth, const std::vector<uint8_t>& filled) {
  const SynthesisSettings& s = scene.settings;
  VS_CHECK(references.size() == s.references.size() && k < references.size());
  VS_CHECK(filled.size() == filledDepth.samples.size());
  RunTestCounts counts;
  const int w = filledDepth.width, h = filledDepth.height;
  if (missingLevel < 0 || w == 0 || h == 0) return counts;
  const ReferenceView& view = s.references[k];
  const std::vector<double> inverseZ = inverseZTable(view.depthRange);
  const uint16_t farLevel = missingLevel == 0 ? 1 : 0;
  const Plane& luma = references[k].texture->planes[0];
  const double colourTolerance = kFarColourTolerance * double(s.textureFormat.maxValue());
  // +1: agrees, -1: contradicts, 0: tells nothing. One view that agrees is enough.
  auto verdict = [&](int x, int y, uint16_t level) {
    bool ok = false;
    const Vec3 point = backProjectDepth(view.camera, x, y, 1.0 / inverseZ[level], s.depthType, ok);
    if (!ok) return 0;
    int result = 0;
    for (size_t j = 0; j < references.size(); ++j) {
      if (j == k) continue;
      const ReferenceView& other = s.references[j];
      double u, v, zCam;
      if (!other.camera.project(point, u, v, zCam)) continue;
      const int ju = int(std::lround(u)), jv = int(std::lround(v));
      const Plane& otherDepth = *references[j].depth;
      if (ju < 0 || jv < 0 || ju >= otherDepth.width || jv >= otherDepth.height) continue;
      const int otherLevel = otherDepth.at(ju, jv);
      if (otherLevel == missingLevel) continue;
      // The sample's depth on the other view's level scale (DepthType 1: its world z).
      const double level = zToLevel(s.depthType == kDepthTypeWorld ? point.z : zCam, other.depthRange);
      const double tolerance = kRunLevelTolerance8Bit * double(maxDepthLevel(other.depthRange)) / 255.0;
      if (otherLevel > level + tolerance) {
        if (result == 0) result = 1;  // hidden behind a nearer surface
      } else if (otherLevel < level - tolerance) {
        result = -1;  // the other view sees farther, through where the sample would be
      } else if (std::abs(double(luma.at(x, y)) - double(references[j].texture->planes[0].at(ju, jv))) >
                 colourTolerance) {
        result = -1;  // that depth, another colour
      } else {
        return 1;  // that depth, that colour: the same surface
      }
    }
    return result;
  };
  // The luma difference between sample (x, y) taken at `level` and what the first other view that
  // sees it shows there, whatever that view's depth; -1 when no other view sees it.
  auto sampleDifference = [&](int x, int y, uint16_t level) {
    bool ok = false;
    const Vec3 point = backProjectDepth(view.camera, x, y, 1.0 / inverseZ[level], s.depthType, ok);
    if (!ok) return -1.0;
    for (size_t j = 0; j < references.size(); ++j) {
      if (j == k) continue;
      double u, v, zCam;
      if (!s.references[j].camera.project(point, u, v, zCam)) continue;
      const int ju = int(std::lround(u)), jv = int(std::lround(v));
      const Plane& otherLuma = references[j].texture->planes[0];
      if (ju < 0 || jv < 0 || ju >= otherLuma.width || jv >= otherLuma.height) continue;
      return std::abs(double(luma.at(x, y)) - double(otherLuma.at(ju, jv)));
    }
    return -1.0;
  };
  // Their mean over samples x0..x1-1 of row y; -1 when none is seen.
  auto runDifference = [&](int x0, int x1, int y, uint16_t level) {
    double sum = 0;
    size_t n = 0;
    for (int x = x0; x < x1; ++x) {
      const double d = sampleDifference(x, y, level);
      if (d < 0) continue;
      sum += d;
      ++n;
    }
    return n ? sum / double(n) : -1.0;
  };
  // Step 2 on samples x0..x1-1 of row y (one filled level): to the far level when contradicted.
  auto testFarther = [&](int x0, int x1, int y, uint16_t* row) {
    size_t agree = 0, contradict = 0;
    for (int i = x0; i < x1; ++i) {
      const int r = verdict(i, y, row[i]);
      agree += r > 0;
      contradict += r < 0;
    }
    if (double(contradict) > kRunContradictedShare * double(agree + contradict)) {
      for (int i = x0; i < x1; ++i) row[i] = farLevel;
      ++counts.toFar;
      counts.far += size_t(x1 - x0);
    }
  };
  // Mean luma of up to kRunSideSamples valid samples beyond x (stepping by `step`); -1 when none.
  auto sideMean = [&](const uint16_t* row, const uint8_t* mark, int x, int step, int y) {
    double sum = 0;
    int n = 0;
    for (int i = x; n < kRunSideSamples && i >= 0 && i < w && !mark[i] && row[i] != missingLevel; i += step, ++n)
      sum += luma.at(i, y);
    return n ? sum / n : -1.0;
  };
  for (int y = 0; y < h; ++y) {
    uint16_t* row = filledDepth.samples.data() + size_t(y) * w;
    const uint8_t* mark = filled.data() + size_t(y) * w;
    for (int x = 0; x < w;) {
      // Filled samples are few: eight marks at a time are passed while none is set.
      uint64_t eight;
      if (x + 8 <= w && (std::memcpy(&eight, mark + x, sizeof eight), eight == 0)) {
        x += 8;
        continue;
      }
      if (!mark[x]) {
        ++x;
        continue;
      }
      int end = x;
      while (end < w && mark[end] && row[end] == row[x]) ++end;
      ++counts.runs;
      counts.samples += size_t(end - x);
      // Step 1: the nearer neighbour (a valid sample, not a filled one).
      const bool leftNear = x > 0 && !mark[x - 1] && row[x - 1] != missingLevel && row[x - 1] > row[x];
      const bool rightNear = end < w && !mark[end] && row[end] != missingLevel && row[end] > row[x];
      const bool fromLeft = leftNear && (!rightNear || row[x - 1] >= row[end]);
      if ((leftNear || rightNear) && end - x >= kRunNearMinSamples) {
        const uint16_t nearLevel = fromLeft ? row[x - 1] : row[end], farther = row[x];
        const double nearDifference = runDifference(x, end, y, nearLevel);
        const double fartherDifference = runDifference(x, end, y, farther);
        const bool otherViewsSayNear = nearDifference >= 0 && fartherDifference >= 0 &&
                                       nearDifference < kRunNearDifferenceRatio * fartherDifference &&
                                       nearDifference < colourTolerance;
        const double nearSide = fromLeft ? sideMean(row, mark, x - 1, -1, y) : sideMean(row, mark, end, 1, y);
        const double farSide = fromLeft ? sideMean(row, mark, end, 1, y) : sideMean(row, mark, x - 1, -1, y);
        double runMean = 0;
        for (int i = x; i < end; ++i) runMean += luma.at(i, y);
        runMean /= double(end - x);
        const double toNearSide = std::abs(runMean - nearSide), toFarSide = std::abs(runMean - farSide);
        const bool ownTextureSaysNear = nearSide >= 0 && farSide >= 0 && toNearSide < colourTolerance &&
                                        toNearSide < kRunNearDifferenceRatio * toFarSide;
        if (otherViewsSayNear || ownTextureSaysNear) {
          // From the nearer end inwards, while each sample matches the other views at the near level
          // within the tolerance and at least as well as at the farther one: a sample wrongly taken
          // near is drawn over what lies in front of the far level, one wrongly taken far is mostly
          // hidden, so the strip stops at the first doubt and the rest goes to step 2.
          int a = x, b = end;
          while (a < b) {
            const int i = fromLeft ? a : b - 1;
            const double dn = sampleDifference(i, y, nearLevel), df = sampleDifference(i, y, farther);
            if (!(dn >= 0 && dn <= colourTolerance && (df < 0 || dn <= df))) break;
            row[i] = nearLevel;
            ++counts.near;
            if (fromLeft) ++a;
            else --b;
          }
          counts.toNear += (b - a) < (end - x);
          if (a < b) testFarther(a, b, y, row);
          x = end;
          continue;
        }
      }
      testFarther(x, end, y, row);
      x = end;
    }
  }
  return counts;
}

void decideMissingDepth(const Scene& scene, const std::vector<ReferenceFrame>& references, Plan& plan,
                        std::vector<FilledDepth>* firstFrameFill, const ViewRangeRunner& runner) {
  if (firstFrameFill) firstFrameFill->clear();
  if (!plan.missingDepthAuto || plan.missingDepthDecided) return;
  const std::vector<FarEvidence> evidence = testFarReading(scene, references, runner);
  size_t tested = 0, contradicted = 0;
  for (const FarEvidence& e : evidence) {
    tested += e.tested;
    contradicted += e.contradicted;
  }
  // One reading for the scene: the renderers take one missing level for every view.
  const bool missing = tested > 0 && double(contradicted) > kFarContradictedShare * double(tested);
  plan.missingDepthLevel = missing ? 0 : -1;
  plan.missingDepthFill = missing && plan.missingDepthFillAuto;
  plan.missingDepthRunTest = plan.missingDepthFill;
  const std::string reading = !missing ? "kept as Zfar"
                              : plan.missingDepthFill ? "treated as missing, runs filled from the farther side "
                                                        "(the nearer where its colours match, Zfar where the "
                                                        "other views contradict)"
                                                      : "treated as missing (MissingDepthFill 0: not filled)";
  // What the per-run test does on this frame (the renderers repeat it on every frame), each view on
  // its own.
  std::vector<FilledDepth> fills(plan.missingDepthRunTest ? evidence.size() : 0);
  std::vector<RunTestCounts> runCounts(fills.size());
  runViews(runner, fills.size(), [&](int first, int last) {
    for (size_t k = size_t(first); k < size_t(last); ++k) {
      fillMissingDepthRuns(*references[k].depth, plan.missingDepthLevel,
                           inverseZTable(scene.settings.references[k].depthRange), fills[k].depth, fills[k].filled);
      runCounts[k] = testFilledRuns(scene, k, references, plan.missingDepthLevel, fills[k].depth, fills[k].filled);
    }
  });
  plan.missingDepthEvidence.clear();
  for (size_t k = 0; k < evidence.size(); ++k) {
    const FarEvidence& e = evidence[k];
    std::string line = "depth level 0 (auto), " + scene.settings.references[k].label + ": " +
                       percent(e.level0Fraction()) + " at level 0";
    if (e.level0 > 0)
      line += e.tested ? ", far contradicted for " + percent(e.contradictedFraction()) + " of " + std::to_string(e.tested) +
                             " tested"
                       : ", none seen by another view";
    line += ": " + reading;
    if (plan.missingDepthRunTest) {
      const RunTestCounts& runs = runCounts[k];
      line += "; frame 0: " + std::to_string(runs.runs) + " runs, " + std::to_string(runs.toNear) +
              " to the nearer side, " + std::to_string(runs.toFar) + " to Zfar";
    }
    plan.missingDepthEvidence.push_back(line);
  }
  if (firstFrameFill) *firstFrameFill = std::move(fills);
  plan.missingDepthDecided = true;
}

}  // namespace vs
