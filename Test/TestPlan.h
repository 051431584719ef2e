#pragma once
// The plan a test's renderer gets: makePlan's, on the path the test names.
#include "Common/Scene.h"
#include "Plan/Plan.h"

namespace vs::test {

// makePlan(scene) for a configuration whose SynthesisMode is `path` (General or Parallel1D).
inline Plan planOnPath(const Scene& scene, SynthesisMode path = SynthesisMode::General) {
  Scene configured = scene;
  configured.settings.mode = path;
  return makePlan(configured);
}

}  // namespace vs::test
