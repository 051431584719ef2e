#include "Plan/MissingDepth.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

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

std::vector<FarEvidence> testFarReading(const Scene& scene, const std::vector<ReferenceFrame>& references) {
  const SynthesisSettings& s = scene.settings;
  VS_CHECK(references.size() == s.references.size());
  std::vector<FarEvidence> evidence(references.size());
  const double colourTolerance = kFarColourTolerance * double(s.textureFormat.maxValue());
  for (size_t k = 0; k < references.size(); ++k) {
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
  return evidence;
}

void decideMissingDepth(const Scene& scene, const std::vector<ReferenceFrame>& references, Plan& plan) {
  if (!plan.missingDepthAuto || plan.missingDepthDecided) return;
  const std::vector<FarEvidence> evidence = testFarReading(scene, references);
  size_t tested = 0, contradicted = 0;
  for (const FarEvidence& e : evidence) {
    tested += e.tested;
    contradicted += e.contradicted;
  }
  // One reading for the scene: the renderers take one missing level for every view.
  const bool missing = tested > 0 && double(contradicted) > kFarContradictedShare * double(tested);
  plan.missingDepthLevel = missing ? 0 : -1;
  plan.missingDepthFill = missing && plan.missingDepthFillAuto;
  const std::string reading = !missing ? "kept as Zfar"
                              : plan.missingDepthFill ? "treated as missing, filled from the farther side"
                                                      : "treated as missing (MissingDepthFill 0: not filled)";
  plan.missingDepthEvidence.clear();
  for (size_t k = 0; k < evidence.size(); ++k) {
    const FarEvidence& e = evidence[k];
    std::string line = "depth level 0 (auto), " + scene.settings.references[k].label + ": " +
                       percent(e.level0Fraction()) + " at level 0";
    if (e.level0 > 0)
      line += e.tested ? ", far contradicted for " + percent(e.contradictedFraction()) + " of " + std::to_string(e.tested) +
                             " tested"
                       : ", none seen by another view";
    plan.missingDepthEvidence.push_back(line + ": " + reading);
  }
  plan.missingDepthDecided = true;
}

}  // namespace vs
