#pragma once
// The Plan step between parsing and the frame loop (../shared/DESIGN.md, "Data flow"): from the
// cameras and the settings it makes every decision the renderers act on, says why, and refuses up
// front what the tool cannot do.
//   - the path: SynthesisMode auto takes the 1D parallel path for a rectified rig, the general path
//     otherwise; SynthesisMode 1 on a rig that is not rectified is refused with the measured
//     deviations; the virtual camera equal to a reference camera is a copy of that view (ViewSyn)
//   - blend weights from the camera distances, the depth tolerances and the discontinuity threshold
//     from the depth ranges, the reference depth-edge step from the depth bit depth, 1D merging
//   - hole filling: which estimates and how they are mixed on this rig, what an empty layer holds
//   - one reference view: extrapolation, no blending; 4:0:0: no chroma work
//   - what the tool can honour: MeshRender cannot write OutputVirtualDepthMapName (refused here,
//     so `--check` refuses it too, before any YUV file is opened)
// The renderers receive the plan (Synthesizer, MeshSynthesizer) and decide nothing themselves.
#include <string>
#include <utility>
#include <vector>

#include "Common/Scene.h"
#include "Plan/Rectification.h"
#include "Plan/StageOptions.h"

namespace vs {

enum class Tool { ViewSyn, MeshRender };

const char* toolName(Tool tool);

struct Plan {
  Tool tool = Tool::ViewSyn;
  // The path. MeshRender renders every rig the same way: General here, whatever SynthesisMode says.
  SynthesisMode mode = SynthesisMode::General;  // General or Parallel1D, never Auto
  SynthesisMode requestedMode = SynthesisMode::Auto;  // SynthesisMode as configured
  int copyOf = -1;            // ViewSyn: index of the reference view copied, -1: synthesize
  bool rectified = true;      // every reference camera forms a rectified pair with the virtual camera
  std::string rigDeviations;  // how it is not rectified, one "\n    <label>: ..." per camera that is not

  std::string virtualCameraName;
  std::vector<std::string> viewLabels;  // the reference views' labels, in order
  bool blend = true;          // more than one reference view
  bool chroma = true;         // colour planes present (not 4:0:0)
  bool rgb = false;           // ColorSpace 1: warped, blended and filled as R, G, B
  int precision = 4;          // Precision: texture look-ups at 1 / precision sample
  int filter = 1;             // Filter: the interpolation kernel of those look-ups

  // Depth.
  double discontinuity = 0;   // inverse-depth step that separates two surfaces in a warped depth map
  int edgeLevelStep = 1;      // depth-level step that marks a reference depth edge
  int missingDepthLevel = -1; // MissingDepthLevel: such samples carry no depth; -1: none
  bool missingDepthFill = false;  // runs of it between valid samples along a row take the farther level
  // MissingDepthLevel auto: level 0's reading is decided on the first frame (Plan/MissingDepth.h),
  // which sets the two fields above and says why, one line per reference view.
  bool missingDepthAuto = false;
  bool missingDepthFillAuto = true;      // MissingDepthFill auto or 1: filled when auto finds level 0 missing
  bool missingDepthRunTest = false;      // auto chose the fill: each filled run is tested (testFilledRuns)
  bool missingDepthDecided = false;      // decideMissingDepth has run
  std::vector<std::string> missingDepthEvidence;  // "depth1: 6.5 % at level 0, far contradicted for 93 %: ..."
  int depthEdgeAlignment = 0; // DepthEdgeAlignment: reach in samples, 0: off; runs with two views or more

  // Stages switched on or off by the path and the keys.
  bool referenceEdgeFlags = true;     // reference samples at depth edges are flagged (1D WarpEnhancementOption 0: off)
  bool cleanNoise = false;            // 1D CleanNoiseOption: isolated warped samples removed
  bool crowdedHoles = false;          // 1D MergingOption 2: samples among many holes are unreliable
  bool temporalFill = false;          // 1D TemporalImprovementOption: static holes keep the previous fill
  bool boundaryNoiseRemoval = false;  // BoundaryNoiseRemoval (ViewSyn only)
  bool virtualDepthOutput = false;    // OutputVirtualDepthMapName is written
  bool virtualMaskOutput = false;     // OutputVirtualMaskName or OutputMaskedVirtualDepthMapName is written
  // The virtual picture's size (VirtualWidth, VirtualHeight); resized: not the inputs' (general path only).
  int virtualWidth = 0, virtualHeight = 0;
  bool resized = false;
  std::vector<std::string> notApplied;  // keys set that this tool leaves aside, each with why

  BlendOptions blending;              // weights, depth tolerance (1D: by MergingOption), ViewBlending
  HoleFillOptions lumaFill;           // luma (or R, G, B)
  HoleFillOptions chromaFill;         // U, V: the same, with mid-grey for an empty layer

  // What the plan prints, made from the fields above, with reasons.
  std::vector<std::string> lines() const;
  // The same as key/value pairs for a machine-readable report (numbers as text, full precision).
  std::vector<std::pair<std::string, std::string>> fields() const;
};

// Throws InputError when SynthesisMode 1 is asked for on a rig that is not rectified (ViewSyn), or
// when the configuration asks for what `tool` cannot do (MeshRender: OutputVirtualDepthMapName).
Plan makePlan(const Scene& scene, Tool tool = Tool::ViewSyn);

}  // namespace vs
