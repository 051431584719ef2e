// The plan in words (Plan::lines, printed before the first frame) and as key/value data
// (Plan::fields, for a machine-readable report); both made from the plan's fields only.
#include <cstdio>
#include <string>

#include "Common/Error.h"
#include "Plan/Plan.h"

namespace vs {

namespace {

std::string exact(double value) { return formatNumber("%.17g", value); }
std::string exact(float value) { return formatNumber("%.9g", double(value)); }
std::string flag(bool value) { return value ? "true" : "false"; }

const char* modeName(SynthesisMode mode) {
  return mode == SynthesisMode::Parallel1D ? "1d" : mode == SynthesisMode::General ? "general" : "auto";
}

std::string weightList(const Plan& plan, const char* pattern, const char* separator) {
  std::string text;
  for (size_t k = 0; k < plan.viewLabels.size(); ++k) {
    char item[160];
    std::snprintf(item, sizeof item, pattern, k ? separator : "", plan.viewLabels[k].c_str(), plan.blending.weights[k]);
    text += item;
  }
  return text;
}

// MissingDepthLevel auto: before the first frame, that it will be decided; after, the decision with
// its evidence, one line per reference view.
void addMissingDepthAutoLines(const Plan& plan, std::vector<std::string>& lines) {
  if (!plan.missingDepthAuto) return;
  if (!plan.missingDepthDecided) {
    lines.push_back("depth level 0: far or missing, decided on the first frame (MissingDepthLevel auto)");
    return;
  }
  for (const std::string& line : plan.missingDepthEvidence) lines.push_back(line);
}

std::vector<std::string> viewSynLines(const Plan& plan) {
  std::vector<std::string> lines;
  if (plan.copyOf >= 0) {
    lines.push_back("copy: the virtual camera '" + plan.virtualCameraName + "' is the " + plan.viewLabels[size_t(plan.copyOf)] +
                    " camera; its view is the output, nothing is warped");
    if (plan.virtualMaskOutput)
      lines.push_back("mask: the copied view's samples without depth (MissingDepthLevel) are written as 255");
    return lines;
  }
  const bool oneD = plan.mode == SynthesisMode::Parallel1D;
  if (plan.resized)
    lines.push_back("size: the virtual view is " + std::to_string(plan.virtualWidth) + "x" +
                    std::to_string(plan.virtualHeight) +
                    " (VirtualWidth, VirtualHeight), not the inputs' size: general path, no copy of a reference view");
  if (plan.requestedMode == SynthesisMode::Auto && plan.resized && plan.rectified)
    lines.push_back("mode: general 3D warping (auto: the rig is rectified, but the 1D path needs one size for every picture)");
  else if (plan.requestedMode == SynthesisMode::Auto)
    lines.push_back(oneD ? "mode: 1D parallel (auto: the rig is rectified: equal rotations, centres on the x axis, "
                           "equal fy and cy, no skew)"
                         : "mode: general 3D warping (auto: the rig is not rectified:" + plan.rigDeviations + ")");
  else
    lines.push_back(oneD ? "mode: 1D parallel (SynthesisMode 1)" : "mode: general 3D warping (SynthesisMode 0)");
  std::string views;  // every reference view by its label, not only "left" and "right"
  for (const std::string& label : plan.viewLabels) views += (views.empty() ? "" : ", ") + label;
  lines.push_back(plan.blend ? "blend: " + std::to_string(plan.viewLabels.size()) + " reference views (" + views + ")"
                             : "blend: off (one reference view: extrapolation)");
  lines.push_back(plan.chroma ? "chroma: warped at its own sample positions" : "chroma: off (4:0:0)");
  lines.push_back(std::string("holes: ") +
                  (!plan.lumaFill.backgroundFirst ? "plain Telea inpainting, as VSRS (identical to OpenCV's)"
                   : plan.rectified ? "background-side fill (directional and along rows: the rig is rectified) and "
                                      "inpainting (chroma's depth-aware)"
                                    : "background-side fill (directional; not along rows: the rig is not rectified) "
                                      "and inpainting (chroma's depth-aware)") +
                  ", on frames that have holes");
  addMissingDepthAutoLines(plan, lines);
  if (plan.missingDepthLevel >= 0)
    lines.push_back("depth level " + std::to_string(plan.missingDepthLevel) + " is missing depth: " +
                    (plan.missingDepthFill ? "runs between valid samples along a row take the farther level "
                                             "(unreliable), the rest are not warped"
                                           : "not warped"));
  lines.push_back(std::string("depth edges: ") +
                  (plan.depthEdgeAlignment == 0 ? "as given (DepthEdgeAlignment 0)"
                   : plan.viewLabels.size() < 2 ? "as given (one reference view: no second view to judge a move)"
                                                : "moved onto texture edges up to " + std::to_string(plan.depthEdgeAlignment) +
                                                    " samples away where the nearest other reference view agrees"));
  if (plan.boundaryNoiseRemoval) lines.push_back("boundary noise removal: on");
  if (plan.virtualMaskOutput)
    lines.push_back("mask: the samples no reference view gave (hole filling made them up) are written as 255");
  lines.push_back("blend weights:" + weightList(plan, "%s %s %.4f", "") +
                  (plan.blending.nearestViewOnly ? " (ViewBlending 1: the heavier view where views agree)" : ""));
  lines.push_back("texture: Precision " + std::to_string(plan.precision) + ", Filter " + std::to_string(plan.filter) +
                  (plan.rgb ? ", processed in RGB" : ", processed in YUV"));
  return lines;
}

std::vector<std::string> meshRenderLines(const Plan& plan) {
  std::vector<std::string> lines;
  addMissingDepthAutoLines(plan, lines);
  if (plan.missingDepthLevel >= 0)
    lines.push_back("depth level " + std::to_string(plan.missingDepthLevel) + " is missing depth: " +
                    (plan.missingDepthFill ? "runs between valid samples take the farther level, the rest are dropped"
                                           : "its vertices are dropped"));
  lines.push_back(std::string("texture: Precision ") + std::to_string(plan.precision) + ", Filter " +
                  std::to_string(plan.filter) + " as ViewSyn samples, evaluated in the fragment shader" +
                  (plan.rgb ? ", processed in RGB" : (plan.chroma ? "; chroma rendered at chroma resolution" : "")));
  lines.push_back("blend weights: " + weightList(plan, "%s%s %.4f", ", ") + " (" +
                  (plan.blending.nearestViewOnly ? "nearer view only" : "weighted blending") + "), depth tolerance " +
                  formatNumber("%.4g", plan.blending.depthTolerance) + " (1/depth)");
  lines.push_back(std::string("holes: ") + (plan.lumaFill.backgroundFirst
                                                ? "background-side fill, then Telea inpainting"
                                                : "plain Telea inpainting, as VSRS (identical to OpenCV's)"));
  for (const std::string& note : plan.notApplied) lines.push_back(note);
  return lines;
}

}  // namespace

std::vector<std::string> Plan::lines() const {
  return tool == Tool::MeshRender ? meshRenderLines(*this) : viewSynLines(*this);
}

std::vector<std::pair<std::string, std::string>> Plan::fields() const {
  std::vector<std::pair<std::string, std::string>> f;
  const char* path = tool == Tool::MeshRender ? "mesh" : copyOf >= 0 ? "copy" : modeName(mode);
  f.emplace_back("tool", toolName(tool));
  f.emplace_back("path", path);
  f.emplace_back("requested_mode", modeName(requestedMode));
  f.emplace_back("copy_of", copyOf >= 0 ? viewLabels[size_t(copyOf)] : "");
  f.emplace_back("rectified", flag(rectified));
  f.emplace_back("views", std::to_string(viewLabels.size()));
  std::string weights;
  for (size_t k = 0; k < blending.weights.size(); ++k) weights += (k ? "," : "") + exact(blending.weights[k]);
  f.emplace_back("blend_weights", weights);
  f.emplace_back("blend_depth_tolerance", exact(blending.depthTolerance));
  f.emplace_back("nearest_view_only", flag(blending.nearestViewOnly));
  f.emplace_back("chroma", flag(chroma));
  f.emplace_back("rgb", flag(rgb));
  f.emplace_back("precision", std::to_string(precision));
  f.emplace_back("filter", std::to_string(filter));
  f.emplace_back("discontinuity", exact(discontinuity));
  f.emplace_back("edge_level_step", std::to_string(edgeLevelStep));
  f.emplace_back("missing_depth_level", std::to_string(missingDepthLevel));
  f.emplace_back("missing_depth_fill", flag(missingDepthFill));
  f.emplace_back("missing_depth_auto", flag(missingDepthAuto));
  std::string evidence;
  for (const std::string& line : missingDepthEvidence) evidence += (evidence.empty() ? "" : "; ") + line;
  f.emplace_back("missing_depth_evidence", evidence);
  f.emplace_back("depth_edge_alignment", std::to_string(viewLabels.size() < 2 ? 0 : depthEdgeAlignment));
  f.emplace_back("reference_edge_flags", flag(referenceEdgeFlags));
  f.emplace_back("clean_noise", flag(cleanNoise));
  f.emplace_back("crowded_holes", flag(crowdedHoles));
  f.emplace_back("temporal_fill", flag(temporalFill));
  f.emplace_back("boundary_noise_removal", flag(boundaryNoiseRemoval));
  f.emplace_back("virtual_depth_output", flag(virtualDepthOutput));
  f.emplace_back("virtual_mask_output", flag(virtualMaskOutput));
  f.emplace_back("virtual_size", std::to_string(virtualWidth) + "x" + std::to_string(virtualHeight));
  std::string notes;
  for (const std::string& note : notApplied) notes += (notes.empty() ? "" : "; ") + note;
  f.emplace_back("not_applied", notes);
  f.emplace_back("hole_fill", lumaFill.backgroundFirst ? "background-first" : "telea");
  f.emplace_back("hole_fill_weights", exact(lumaFill.directionalWeight) + "," + exact(lumaFill.rowRunWeight) + "," +
                                          exact(lumaFill.inpaintWeight));
  f.emplace_back("hole_fill_depth_tolerance", exact(lumaFill.depthTolerance));
  return f;
}

}  // namespace vs
