#include "Plan/StageOptions.h"

#include <algorithm>
#include <cmath>

namespace vs {

std::vector<double> baselineWeights(const std::vector<double>& distances) {
  std::vector<double> weights(distances.size(), 0.0);
  if (distances.empty()) return weights;
  // Views the virtual camera sits on share all the weight: they alone decide where they are valid.
  // "On" means closer than 1e-6 of the farthest view's distance: a baseline of 1e-9 against one of 1
  // is the same camera for every purpose, and must not leave the other view a weight of 5e-9 with
  // which it still wins wherever it sees a nearer surface.
  double farthest = 0;
  for (double d : distances)
    if (std::isfinite(d)) farthest = std::max(farthest, d);
  std::vector<bool> on(distances.size());
  size_t onCamera = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    on[k] = distances[k] <= 1e-6 * farthest;
    onCamera += on[k] ? 1 : 0;
  }
  if (onCamera > 0) {
    for (size_t k = 0; k < distances.size(); ++k) weights[k] = on[k] ? 1.0 / double(onCamera) : 0.0;
    return weights;
  }
  double sum = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    weights[k] = std::isfinite(distances[k]) ? 1.0 / distances[k] : 0.0;
    sum += weights[k];
  }
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    std::fill(weights.begin(), weights.end(), 1.0 / double(distances.size()));
    return weights;
  }
  for (double& w : weights) w /= sum;
  return weights;
}

int depthEdgeStep(int maxLevel) { return std::max(1, int(std::lround(kSurfaceStepLevels8 / 255.0 * maxLevel))); }

}  // namespace vs
