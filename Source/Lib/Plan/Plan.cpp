#include "Plan/Plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "Common/Error.h"

namespace vs {

namespace {

bool sameCamera(const Camera& a, const Camera& b) {
  return a.projection == b.projection && a.K == b.K && a.R == b.R && a.t == b.t &&
         (!a.isEquirectangular() || a.erp == b.erp);
}

// Pixels per radian across the picture near its centre: the focal length of a pinhole camera, the
// columns per radian of longitude of an ERP one.
double pixelsPerRadian(const Camera& camera) {
  if (camera.isEquirectangular()) return camera.erp.width / ((camera.erp.lonMax - camera.erp.lonMin) * M_PI / 180.0);
  return camera.K[0][0];
}

// What no stage can do with an equirectangular camera, refused with the reason.
void refuseEquirectangular(const Scene& scene) {
  std::vector<const Camera*> erp;
  for (const ReferenceView& view : scene.settings.references)
    if (view.camera.isEquirectangular()) erp.push_back(&view.camera);
  if (scene.virtualCamera.isEquirectangular()) erp.push_back(&scene.virtualCamera);
  if (erp.empty()) return;
  // The reference pictures have the texture format's size, the virtual one the virtual format's
  // (VirtualWidth, VirtualHeight); an ERP camera's angles per pixel come from its Resolution, so the
  // picture's size and it must agree.
  for (const Camera* camera : erp) {
    const bool virtualCamera = camera == &scene.virtualCamera;
    const FrameFormat format = virtualCamera ? scene.settings.virtualFormat() : scene.settings.textureFormat;
    if (camera->erp.width != format.width || camera->erp.height != format.height)
      throw InputError("camera '" + camera->name + "' is equirectangular with Resolution " +
                       std::to_string(camera->erp.width) + "x" + std::to_string(camera->erp.height) + ", but the " +
                       (virtualCamera ? "virtual picture is " : "pictures are ") + std::to_string(format.width) + "x" +
                       std::to_string(format.height) + " (" + (virtualCamera ? "VirtualWidth x VirtualHeight" : "SourceWidth x SourceHeight") +
                       "); an ERP picture must have its camera's resolution");
  }
  if (scene.settings.depthType == 1)
    throw InputError("DepthType 1 (depth values are world z coordinates) with the equirectangular camera '" +
                     erp[0]->name + "': an ERP depth map holds distances along the rays (MPEG-I); use DepthType 0");
}

// Blend weights, tolerances and the discontinuity threshold from the cameras and depth ranges.
void decideDepthAndWeights(const Scene& scene, Plan& plan) {
  const SynthesisSettings& s = scene.settings;
  double inverseRange = 0;
  std::vector<double> distances, angles;
  for (const ReferenceView& reference : s.references) {
    const double farInverse = std::isinf(reference.depthRange.zfar) ? 0.0 : 1.0 / reference.depthRange.zfar;
    inverseRange += std::fabs(1.0 / reference.depthRange.znear - farInverse);
    distances.push_back(norm(reference.camera.centre() - scene.virtualCamera.centre()));
    // Angle between the optical axes (rows 2 of R are the viewing directions in world coordinates).
    // An equirectangular camera sees every direction (its rotation only says where its picture
    // starts): with one on either side the views are as alike as their positions.
    const double cosine = dot(reference.camera.R.row(2), scene.virtualCamera.R.row(2)) /
                          (norm(reference.camera.R.row(2)) * norm(scene.virtualCamera.R.row(2)));
    const bool spherical = reference.camera.isEquirectangular() || scene.virtualCamera.isEquirectangular();
    angles.push_back(spherical ? 0.0 : std::acos(std::clamp(cosine, -1.0, 1.0)));
  }
  inverseRange /= double(s.references.size());
  // Thresholds sit half a level past the whole number of 8-bit levels they name: inverse depths of
  // quantised maps differ by whole levels, so a difference never ties with a threshold and a change of
  // units or of world origin cannot flip a decision through rounding.
  auto levels = [&](double levels8) { return (levels8 + 0.5) / 255.0 * inverseRange; };
  plan.discontinuity = levels(kSurfaceStepLevels8);
  plan.edgeLevelStep = depthEdgeStep(s.depthFormat.maxValue());
  // A view's distance from the virtual camera counts its position and its viewing direction: the
  // angle between optical axes (radians) is scaled by the mean camera distance, so a parallel rig
  // keeps VSRS's baseline weights.
  double meanDistance = 0;
  for (double d : distances) meanDistance += d / double(distances.size());
  for (size_t k = 0; k < distances.size(); ++k) {
    // A view whose parallax against the virtual camera stays below 1e-3 px everywhere (baseline
    // times the nearest inverse depth, plus the turn between the optical axes, in pixels) is the
    // virtual camera for every purpose: it decides alone where it is valid.
    const ReferenceView& reference = s.references[k];
    const double nearest = std::max(std::fabs(1.0 / reference.depthRange.znear),
                                    std::isinf(reference.depthRange.zfar) ? 0.0 : std::fabs(1.0 / reference.depthRange.zfar));
    const double parallax = pixelsPerRadian(scene.virtualCamera) * (distances[k] * nearest + angles[k]);
    if (parallax < 1e-3) distances[k] = 0;
    else distances[k] += meanDistance * angles[k];
  }
  plan.blending.weights = baselineWeights(distances);
  plan.blending.depthTolerance = levels(s.depthBlendDifference);
  if (plan.mode == SynthesisMode::Parallel1D) {
    // VSRS's 1D MergingOption: 0 z-buffer only (one level of tolerance), 1 averaging only,
    // 2 adaptive: mixed within DepthThreshold levels (by default DepthBlendDifference's, so that the
    // 1D path blends as the general one does), hole counting decides between views.
    if (s.oneD.merging == 0) plan.blending.depthTolerance = levels(1);
    else if (s.oneD.merging == 1) plan.blending.depthTolerance = HUGE_VAL;
    else if (s.oneD.depthThreshold >= 0) plan.blending.depthTolerance = levels(s.oneD.depthThreshold);
  }
  plan.blending.nearestViewOnly = s.viewBlending == 1;
  plan.lumaFill.depthTolerance = levels(s.depthBlendDifference);
}

void decideHoleFilling(const Scene& scene, Plan& plan) {
  const SynthesisSettings& s = scene.settings;
  HoleFillOptions& fill = plan.lumaFill;
  fill.backgroundFirst = s.ivsrsInpaint;
  // Row runs follow the disocclusions of a rectified rig, which lie along rows. On any other rig they
  // do not (open3d: 33.29 dB with them), and hole filling stays the directional and inpainting
  // estimates mixed 1 : 1 (33.96 dB), the mix the weights of the three were chosen against.
  if (!plan.rectified) {
    fill.directionalWeight = fill.inpaintWeight = 1.0f;
    fill.rowRunWeight = 0.0f;
  }
  // An empty layer: black luma (mid-grey in RGB), mid-grey chroma.
  const int bitDepth = s.textureFormat.bitDepth;
  const float mid = float(1 << (bitDepth - 1));
  fill.emptyValue[0] = plan.rgb ? mid : float(16 << (bitDepth - 8));
  fill.emptyValue[1] = fill.emptyValue[2] = mid;
  plan.chromaFill = fill;
  plan.chromaFill.inpaintNearerSurface = true;
  plan.chromaFill.inpaintLikeOpenCv = true;
  plan.chromaFill.emptyValue[0] = plan.chromaFill.emptyValue[1] = mid;
}

}  // namespace

const char* toolName(Tool tool) { return tool == Tool::MeshRender ? "MeshRender" : "ViewSyn"; }

Plan makePlan(const Scene& scene, Tool tool) {
  const SynthesisSettings& s = scene.settings;
  Plan plan;
  plan.tool = tool;
  plan.requestedMode = s.mode;
  plan.virtualCameraName = scene.virtualCamera.name;
  for (const ReferenceView& view : s.references) plan.viewLabels.push_back(view.label);
  plan.blend = s.references.size() > 1;
  plan.chroma = s.textureFormat.chroma != ChromaFormat::Yuv400;
  plan.rgb = s.colorSpace == 1;
  plan.precision = s.precision;
  plan.filter = s.filter;
  plan.missingDepthLevel = s.missingDepthLevel;
  plan.missingDepthFill = s.missingDepthLevel >= 0 && s.missingDepthFill;
  plan.missingDepthAuto = s.missingDepthAuto;
  plan.missingDepthFillAuto = s.missingDepthFillAuto || s.missingDepthFill;
  plan.depthEdgeAlignment = std::max(0, s.depthEdgeAlignment);

  // What the tool cannot do is refused before anything else is looked at.
  if (tool == Tool::MeshRender && !s.virtualDepthPath.empty())
    throw InputError("OutputVirtualDepthMapName '" + s.virtualDepthPath +
                     "': MeshRender cannot write the virtual view's depth (ViewSyn can); remove the key or set it to -");
  if (tool == Tool::MeshRender && s.wantsMask())
    throw InputError(std::string(s.virtualMaskPath.empty() ? "OutputMaskedVirtualDepthMapName" : "OutputVirtualMaskName") +
                     ": MeshRender cannot write the virtual view's mask (ViewSyn can); remove the key or set it to -");
  if (tool == Tool::MeshRender && s.virtualResized())
    throw InputError("VirtualWidth x VirtualHeight " + std::to_string(s.virtualFormat().width) + "x" +
                     std::to_string(s.virtualFormat().height) + " differs from the inputs' " +
                     std::to_string(s.textureFormat.width) + "x" + std::to_string(s.textureFormat.height) +
                     ": MeshRender renders the virtual view at the inputs' size; use ViewSyn, or leave the keys at 0");
  plan.virtualDepthOutput = !s.virtualDepthPath.empty();
  plan.virtualMaskOutput = s.wantsMask();
  plan.virtualWidth = s.virtualFormat().width;
  plan.virtualHeight = s.virtualFormat().height;
  plan.resized = s.virtualResized();
  refuseEquirectangular(scene);

  // A reference view is copied only when the virtual picture also has its size.
  for (size_t k = 0; k < s.references.size() && tool == Tool::ViewSyn && !plan.resized; ++k)
    if (sameCamera(s.references[k].camera, scene.virtualCamera)) {
      plan.copyOf = int(k);
      break;
    }
  for (const ReferenceView& view : s.references) {
    const Rectification check = checkRectification(view.camera, scene.virtualCamera, s.depthType);
    if (!check.rectified()) {
      plan.rectified = false;
      plan.rigDeviations += "\n    " + view.label + ": " + check.describe();
    }
  }
  if (tool == Tool::ViewSyn) {
    if (s.mode == SynthesisMode::Parallel1D && !plan.rectified && plan.copyOf < 0)
      throw InputError("SynthesisMode 1 (1D parallel) needs a rectified rig, and this one is not:" + plan.rigDeviations +
                       "\n  use SynthesisMode 0 (general) or auto");
    // The 1D path warps each reference row into the same virtual row: one size for every picture.
    if (s.mode == SynthesisMode::Parallel1D && plan.resized)
      throw InputError("SynthesisMode 1 (1D parallel) warps rows into rows of the same length, but the virtual view is " +
                       std::to_string(s.virtualFormat().width) + "x" + std::to_string(s.virtualFormat().height) +
                       " (VirtualWidth x VirtualHeight) and the inputs " + std::to_string(s.textureFormat.width) + "x" +
                       std::to_string(s.textureFormat.height) + "; use SynthesisMode 0 (general) or auto");
    if (s.mode == SynthesisMode::Auto)
      plan.mode = plan.rectified && !plan.resized ? SynthesisMode::Parallel1D : SynthesisMode::General;
    else plan.mode = plan.copyOf >= 0 && !plan.rectified ? SynthesisMode::General : s.mode;
  }
  const bool oneD = plan.mode == SynthesisMode::Parallel1D;
  plan.referenceEdgeFlags = !oneD || s.oneD.warpEnhancement;
  plan.cleanNoise = oneD && s.oneD.cleanNoise;
  plan.crowdedHoles = oneD && s.oneD.merging == 2;
  plan.temporalFill = oneD && s.oneD.temporalImprovement;
  plan.boundaryNoiseRemoval = tool == Tool::ViewSyn && s.boundaryNoiseRemoval;
  if (tool == Tool::MeshRender) {
    if (s.boundaryNoiseRemoval) plan.notApplied.push_back("BoundaryNoiseRemoval 1: not applied by MeshRender");
    if (s.mode != SynthesisMode::General)
      plan.notApplied.push_back("SynthesisMode: MeshRender renders every rig the same way (the 1D mode does not apply)");
  }
  decideDepthAndWeights(scene, plan);
  decideHoleFilling(scene, plan);
  return plan;
}

}  // namespace vs
