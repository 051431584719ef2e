#include "Synth/Plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "Common/Error.h"

namespace vs {

namespace {

// Tolerances of a rectified rig: calibration files print 6 to 17 digits.
constexpr double kMaxRotationDegrees = 1e-4;
constexpr double kMaxOffAxis = 1e-6;
constexpr double kMaxFyDifference = 1e-9;
constexpr double kMaxCyDifference = 1e-6;
constexpr double kMaxSkew = 1e-9;

bool sameCamera(const Camera& a, const Camera& b) { return a.K == b.K && a.R == b.R && a.t == b.t; }

std::string format(const char* pattern, double value) {
  char text[128];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace

bool Rectification::rectified() const {
  return rotationDegrees <= kMaxRotationDegrees && offAxis <= kMaxOffAxis && fyDifference <= kMaxFyDifference &&
         cyDifference <= kMaxCyDifference && skew <= kMaxSkew && depthTypeOk;
}

std::string Rectification::describe() const {
  std::string text = format("rotation differs by %.3g deg", rotationDegrees) +
                     format(", centre off the x axis by %.3g of the baseline", offAxis) +
                     format(", fy differs by %.3g (relative)", fyDifference) + format(", cy differs by %.3g px", cyDifference) +
                     format(", skew %.3g px", skew);
  if (!depthTypeOk) text += ", DepthType 1 with a camera z axis that is not the world z axis";
  return text;
}

Rectification checkRectification(const Camera& reference, const Camera& virtualCamera, int depthType) {
  Rectification r;
  const RelativePose pose = relativePose(reference, virtualCamera);
  const double trace = pose.R[0][0] + pose.R[1][1] + pose.R[2][2];
  r.rotationDegrees = std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
  const double baseline = norm(pose.t);
  r.offAxis = baseline > 0 ? std::hypot(pose.t.y, pose.t.z) / baseline : 0.0;
  r.fyDifference = std::fabs(reference.K[1][1] - virtualCamera.K[1][1]) / virtualCamera.K[1][1];
  r.cyDifference = std::fabs(reference.K[1][2] - virtualCamera.K[1][2]);
  r.skew = std::max(std::fabs(reference.K[0][1]), std::fabs(virtualCamera.K[0][1]));
  if (depthType == 1) {
    const Vec3 zAxis = reference.R.row(2);
    r.depthTypeOk = zAxis.x == 0 && zAxis.y == 0 && zAxis.z == 1;
  }
  return r;
}

bool rectifiedRig(const Scene& scene) {
  for (const ReferenceView& view : scene.settings.references)
    if (!checkRectification(view.camera, scene.virtualCamera, scene.settings.depthType).rectified()) return false;
  return true;
}

Plan makePlan(const Scene& scene) {
  const SynthesisSettings& s = scene.settings;
  Plan plan;
  plan.blend = s.references.size() > 1;
  plan.chroma = s.textureFormat.chroma != ChromaFormat::Yuv400;
  for (size_t k = 0; k < s.references.size(); ++k)
    if (sameCamera(s.references[k].camera, scene.virtualCamera)) {
      plan.copyOf = int(k);
      plan.lines.push_back("copy: the virtual camera '" + scene.virtualCamera.name + "' is the " + s.references[k].label +
                           " camera; its view is the output, nothing is warped");
      return plan;
    }

  std::vector<Rectification> checks;
  bool rectified = true;
  for (const ReferenceView& view : s.references) {
    checks.push_back(checkRectification(view.camera, scene.virtualCamera, s.depthType));
    rectified = rectified && checks.back().rectified();
  }
  std::string deviations;
  for (size_t k = 0; k < checks.size(); ++k)
    if (!checks[k].rectified()) deviations += "\n    " + s.references[k].label + ": " + checks[k].describe();
  if (s.mode == SynthesisMode::Parallel1D && !rectified)
    throw InputError("SynthesisMode 1 (1D parallel) needs a rectified rig, and this one is not:" + deviations +
                     "\n  use SynthesisMode 0 (general) or auto");
  if (s.mode == SynthesisMode::Auto) {
    plan.mode = rectified ? SynthesisMode::Parallel1D : SynthesisMode::General;
    plan.lines.push_back(rectified ? "mode: 1D parallel (auto: the rig is rectified: equal rotations, centres on the "
                                     "x axis, equal fy and cy, no skew)"
                                   : "mode: general 3D warping (auto: the rig is not rectified:" + deviations + ")");
  } else {
    plan.mode = s.mode;
    plan.lines.push_back(plan.mode == SynthesisMode::Parallel1D ? "mode: 1D parallel (SynthesisMode 1)"
                                                                : "mode: general 3D warping (SynthesisMode 0)");
  }
  std::string views;  // every reference view by its label, not only "left" and "right"
  for (const ReferenceView& view : s.references) views += (views.empty() ? "" : ", ") + view.label;
  plan.lines.push_back(plan.blend ? "blend: " + std::to_string(s.references.size()) + " reference views (" + views + ")"
                                  : "blend: off (one reference view: extrapolation)");
  plan.lines.push_back(plan.chroma ? "chroma: warped at its own sample positions" : "chroma: off (4:0:0)");
  plan.lines.push_back(std::string("holes: ") +
                       (!s.ivsrsInpaint ? "plain Telea inpainting, as VSRS (identical to OpenCV's)"
                        : rectified     ? "background-side fill (directional and along rows: the rig is rectified) and "
                                          "depth-aware inpainting"
                                        : "background-side fill (directional; not along rows: the rig is not rectified) "
                                          "and depth-aware inpainting") +
                       ", on frames that have holes");
  if (s.missingDepthLevel >= 0)
    plan.lines.push_back("depth level " + std::to_string(s.missingDepthLevel) + " is missing depth: " +
                         (s.missingDepthFill ? "runs between valid samples along a row take the farther level "
                                               "(unreliable), the rest are not warped"
                                             : "not warped"));
  plan.lines.push_back(std::string("depth edges: ") +
                       (s.depthEdgeAlignment == 0 ? "as given (DepthEdgeAlignment 0)"
                        : s.references.size() < 2
                            ? "as given (one reference view: no second view to judge a move)"
                            : "moved onto texture edges up to " + std::to_string(s.depthEdgeAlignment) +
                                  " samples away where the nearest other reference view agrees"));
  if (s.boundaryNoiseRemoval) plan.lines.push_back("boundary noise removal: on");
  return plan;
}

}  // namespace vs
