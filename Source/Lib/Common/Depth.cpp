#include "Common/Depth.h"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>

#include "Common/Error.h"

namespace vs {

namespace {

std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

double reciprocal(double z) { return std::isinf(z) ? 0.0 : 1.0 / z; }

// The pixel's ray in world coordinates, scaled so that one unit along it is one unit of camera z.
Vec3 worldRay(const Camera& camera, double u, double v) { return inverse(camera.R) * camera.pixelToCamera(u, v, 1.0); }

}  // namespace

int maxDepthLevel(const DepthRange& range) {
  VS_CHECK_MSG(range.bitDepth >= 1 && range.bitDepth <= 16, "depth bit depth outside 1..16");
  return (1 << range.bitDepth) - 1;
}

void validateDepthRange(const DepthRange& range, int depthType, const std::string& keyPrefix) {
  const std::string nearKey = keyPrefix + "NearestDepthValue";
  const std::string farKey = keyPrefix + "FarthestDepthValue";
  std::vector<std::string> problems;
  if (range.bitDepth < 8 || range.bitDepth > 16)
    problems.push_back("depth bit depth " + std::to_string(range.bitDepth) + " is outside 8..16");
  if (depthType != kDepthTypeCamera && depthType != kDepthTypeWorld)
    problems.push_back("DepthType " + std::to_string(depthType) +
                       " is unknown; expected 0 (camera-frame z) or 1 (world z)");
  const bool nearFinite = std::isfinite(range.znear);
  const bool farValid = std::isfinite(range.zfar) || range.zfar == std::numeric_limits<double>::infinity();
  if (!nearFinite) problems.push_back(nearKey + " = " + number(range.znear) + ": expected a finite number");
  if (!farValid) problems.push_back(farKey + " = " + number(range.zfar) + ": expected a finite number or inf");
  if (nearFinite && farValid) {
    if (range.znear == range.zfar) {
      problems.push_back(nearKey + " and " + farKey + " are both " + number(range.znear) +
                         ": the depth range is empty, so depth levels cannot be converted");
    } else if (depthType == kDepthTypeCamera) {
      if (range.znear <= 0.0)
        problems.push_back(nearKey + " = " + number(range.znear) +
                           ": with DepthType 0 (camera-frame z) it must be greater than 0");
      if (range.zfar <= 0.0)
        problems.push_back(farKey + " = " + number(range.zfar) +
                           ": with DepthType 0 (camera-frame z) it must be greater than 0");
      if (range.znear > 0.0 && range.zfar > 0.0 && range.znear > range.zfar)
        problems.push_back(nearKey + " = " + number(range.znear) + " is farther than " + farKey + " = " +
                           number(range.zfar) + ": with DepthType 0 Znear must be smaller than Zfar (swapped keys?)");
    } else {
      if (range.znear == 0.0) problems.push_back(nearKey + " = 0: 1/Z would be infinite; expected a non-zero world z");
      if (range.zfar == 0.0)
        problems.push_back(farKey + " = 0: 1/Z would be infinite; expected a non-zero world z or inf");
    }
  }
  if (problems.empty()) return;
  std::string message = "invalid depth range";
  message += keyPrefix.empty() ? ": " : " (" + keyPrefix + "): ";
  for (std::size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  throw InputError(message);
}

double levelToInverseZ(double level, const DepthRange& range) {
  const double fraction = level / maxDepthLevel(range);
  // (1 - f) a + f b rather than a + f (b - a): exact at both ends of the range.
  return (1.0 - fraction) * reciprocal(range.zfar) + fraction * reciprocal(range.znear);
}

double levelToZ(double level, const DepthRange& range) {
  if (level == 0.0) return range.zfar;
  if (level == maxDepthLevel(range)) return range.znear;
  const double inverseZ = levelToInverseZ(level, range);
  if (inverseZ == 0.0) return std::numeric_limits<double>::infinity();
  return 1.0 / inverseZ;
}

double zToLevel(double z, const DepthRange& range) {
  const double inverseNear = reciprocal(range.znear);
  const double inverseFar = reciprocal(range.zfar);
  return maxDepthLevel(range) * ((reciprocal(z) - inverseFar) / (inverseNear - inverseFar));
}

int zToLevelRounded(double z, const DepthRange& range) {
  const double level = zToLevel(z, range);
  const int maxLevel = maxDepthLevel(range);
  if (std::isnan(level) || level <= 0.0) return 0;
  if (level >= maxLevel) return maxLevel;
  return static_cast<int>(std::floor(level + 0.5));
}

std::vector<double> inverseZTable(const DepthRange& range) {
  const int maxLevel = maxDepthLevel(range);
  std::vector<double> table(static_cast<std::size_t>(maxLevel) + 1);
  for (int level = 0; level <= maxLevel; ++level) table[level] = levelToInverseZ(level, range);
  return table;
}

double depthToCameraZ(const Camera& camera, double u, double v, double depthValue, int depthType, bool& ok) {
  ok = false;
  if (std::isnan(depthValue)) return depthValue;
  if (depthType == kDepthTypeCamera) {
    ok = depthValue > 0.0;
    return depthValue;
  }
  VS_CHECK_MSG(depthType == kDepthTypeWorld, "DepthType must be 0 or 1");
  const Vec3 ray = worldRay(camera, u, v);
  // A ray (nearly) parallel to the plane z = depthValue meets it nowhere useful.
  if (!(std::fabs(ray.z) > 1e-12 * norm(ray))) return 0.0;
  if (std::isinf(depthValue)) {
    ok = (depthValue > 0.0) == (ray.z > 0.0);
    return std::numeric_limits<double>::infinity();
  }
  const double zCam = (depthValue - camera.t.z) / ray.z;
  ok = zCam > 0.0 && std::isfinite(zCam);
  return zCam;
}

Vec3 backProjectDepth(const Camera& camera, double u, double v, double depthValue, int depthType, bool& ok) {
  const double zCam = depthToCameraZ(camera, u, v, depthValue, depthType, ok);
  if (!ok || std::isinf(zCam)) {
    ok = false;
    return {};
  }
  if (depthType == kDepthTypeCamera) return camera.backProject(u, v, zCam);
  Vec3 X = camera.t + worldRay(camera, u, v) * zCam;
  X.z = depthValue;  // on the plane by definition; no rounding off it
  return X;
}

namespace {

// Fills the runs of `missing` along one row of n samples that have a valid sample at both ends with
// the farther end's level.
size_t fillRow(uint16_t* line, uint8_t* mark, int n, uint16_t missing, const std::vector<double>& inverseZ) {
  auto inverse = [&](uint16_t level) { return level < inverseZ.size() ? inverseZ[level] : 0.0; };
  size_t count = 0;
  for (int k = 0; k < n;) {
    // Missing samples are few: sixteen at a time are passed while none is (a test that vectorises).
    if (k + 16 <= n) {
      bool any = false;
      for (int i = 0; i < 16; ++i) any |= line[k + i] == missing;
      if (!any) {
        k += 16;
        continue;
      }
    }
    if (line[k] != missing) {
      ++k;
      continue;
    }
    int end = k;
    while (end < n && line[end] == missing) ++end;
    if (k > 0 && end < n) {
      const uint16_t before = line[k - 1], after = line[end];
      const uint16_t farther = inverse(after) < inverse(before) ? after : before;
      for (int j = k; j < end; ++j) {
        line[j] = farther;
        mark[j] = 1;
      }
      count += size_t(end - k);
    }
    k = end;
  }
  return count;
}

}  // namespace

size_t fillMissingDepthRuns(const Plane& depth, int missingLevel, const std::vector<double>& inverseZ, Plane& out,
                            std::vector<uint8_t>& filled) {
  out = depth;
  filled.assign(depth.samples.size(), 0);
  if (missingLevel < 0 || depth.samples.empty()) return 0;
  const uint16_t missing = uint16_t(missingLevel);
  const int w = depth.width, h = depth.height;
  size_t count = 0;
  for (int y = 0; y < h; ++y) count += fillRow(out.row(y), filled.data() + size_t(y) * w, w, missing, inverseZ);
  // Then the columns, each the same way, visited row by row in memory order. What the rows left
  // missing is little: a column's run opens at a missing sample below a valid one and closes at the
  // next valid sample, which fills it with the farther of the two. Rows without a missing sample are
  // passed sixteen samples at a time, and only the open columns are looked at in every row.
  std::vector<int> runStart(size_t(w), -1);  // per column: the first row of its open run; -1: none
  std::vector<int> open;                      // the columns with an open run
  auto inverse = [&](uint16_t level) { return level < inverseZ.size() ? inverseZ[level] : 0.0; };
  for (int y = 0; y < h; ++y) {
    uint16_t* row = out.row(y);
    size_t kept = 0;
    for (const int x : open) {
      if (row[x] == missing) {
        open[kept++] = x;
        continue;
      }
      const int top = runStart[size_t(x)];
      const uint16_t before = out.at(x, top - 1), after = row[x];
      const uint16_t farther = inverse(after) < inverse(before) ? after : before;
      for (int r = top; r < y; ++r) {
        out.at(x, r) = farther;
        filled[size_t(r) * w + size_t(x)] = 1;
      }
      count += size_t(y - top);
      runStart[size_t(x)] = -1;
    }
    open.resize(kept);
    if (y == 0) continue;  // nothing valid above the first row
    const uint16_t* above = out.row(y - 1);
    for (int x = 0; x < w; ++x) {
      if (x + 16 <= w) {
        bool any = false;
        for (int i = 0; i < 16; ++i) any |= row[x + i] == missing;
        if (!any) {
          x += 15;
          continue;
        }
      }
      // A missing sample below a valid one opens a run (below a missing one, the run is open already
      // or there is nothing valid above).
      if (row[x] == missing && above[x] != missing && runStart[size_t(x)] < 0) {
        runStart[size_t(x)] = y;
        open.push_back(x);
      }
    }
  }
  return count;
}

}  // namespace vs
