#pragma once
// The Plan step between parsing and the frame loop (../shared/DESIGN.md, "Data flow"): from the
// cameras and the settings it decides which stages this scene needs, and says why.
//   - SynthesisMode auto: the 1D parallel path for a rectified rig, the general path otherwise;
//     SynthesisMode 1 on a rig that is not rectified is refused with the measured deviations
//   - one reference view: extrapolation, no blending
//   - the virtual camera equal to a reference camera: a copy of that view, nothing else runs
//   - 4:0:0: no chroma work; hole filling runs only on frames that have holes (decided per frame)
#include <string>
#include <vector>

#include "Common/Scene.h"

namespace vs {

// How far a reference camera is from forming a rectified pair with the virtual camera.
struct Rectification {
  double rotationDegrees = 0;  // angle of R_ref R_virtual^-1
  double offAxis = 0;          // |(y, z)| of the centre offset in the virtual camera frame, relative to |offset|
  double fyDifference = 0;     // |fy_ref - fy_virtual| / fy_virtual
  double cyDifference = 0;     // |cy_ref - cy_virtual| in pixels
  double skew = 0;             // largest |K[0][1]| of the two cameras, pixels
  bool depthTypeOk = true;     // DepthType 1 maps to camera depth only when the camera z axis is world z
  bool rectified() const;
  std::string describe() const;  // "rotation 0.3 deg, centre off the x axis by 2%, ..."
};

Rectification checkRectification(const Camera& reference, const Camera& virtualCamera, int depthType);

// Every reference camera forms a rectified pair with the virtual camera.
bool rectifiedRig(const Scene& scene);

struct Plan {
  SynthesisMode mode = SynthesisMode::General;  // General or Parallel1D, never Auto
  int copyOf = -1;                              // index of the reference view copied, -1: synthesize
  bool blend = true;                            // more than one reference view
  bool chroma = true;                           // colour planes present
  std::vector<std::string> lines;               // what the plan prints, with reasons
};

// Throws InputError when SynthesisMode 1 is asked for on a rig that is not rectified.
Plan makePlan(const Scene& scene);

}  // namespace vs
