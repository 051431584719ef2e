#include "Synth/ViewSynRenderer.h"

#include <cstdio>
#include <functional>
#include <memory>
#include <utility>

#include "Common/Depth.h"
#include "Pipeline/FrameLoop.h"
#include "Plan/MissingDepth.h"
#include "Plan/Plan.h"
#include "Synth/Parallel.h"
#include "Synth/Synthesizer.h"

namespace vs {

namespace {

// ViewSyn's middle box: what the plan decided, a copy or the synthesizer on the chosen path.
class ViewSynRenderer : public FrameRenderer {
public:
  explicit ViewSynRenderer(const Scene& scene) : scene_(scene), plan_(makePlan(scene_)) {
    if (plan_.copyOf < 0 && !plan_.missingDepthAuto) makeSynthesizer();
  }
  // MissingDepthLevel auto: the plan decides on the first frame, then the synthesizer is built.
  std::vector<std::string> prepare(const std::vector<ReferenceFrame>& firstFrame) override {
    if (plan_.copyOf >= 0 || !plan_.missingDepthAuto || synthesizer_) return {};
    std::vector<FilledDepth> firstFrameFill;  // the maps the decision filled: frame 0 need not again
    // The views' tests side by side on the pool's threads, a view per stripe.
    const ViewRangeRunner onThreads = [](int count, const std::function<void(int, int)>& body) {
      parallelStripes(count, count, body);
    };
    decideMissingDepth(scene_, firstFrame, plan_, &firstFrameFill, onThreads);
    makeSynthesizer();
    synthesizer_->takeFirstFrameFill(std::move(firstFrameFill));
    return plan_.missingDepthEvidence;
  }
  void render(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) override {
    if (plan_.copyOf >= 0) {
      output = *references[size_t(plan_.copyOf)].texture;
      return;
    }
    synthesizer_->synthesize(references, output, times);
  }
  bool virtualDepth(const std::vector<ReferenceFrame>& references, const DepthRange& range, Plane& levels) override {
    if (synthesizer_) {
      synthesizer_->virtualDepth(range, levels);
      return true;
    }
    // A copy: the reference's depth, re-expressed in the virtual range (same camera, same depth).
    const ReferenceView& view = scene_.settings.references[size_t(plan_.copyOf)];
    const Plane& depth = *references[size_t(plan_.copyOf)].depth;
    levels.resize(depth.width, depth.height);
    for (size_t i = 0; i < depth.samples.size(); ++i)
      levels.samples[i] = uint16_t(zToLevelRounded(levelToZ(depth.samples[i], view.depthRange), range));
    return true;
  }
  bool virtualMask(const std::vector<ReferenceFrame>& references, Plane& mask) override {
    if (synthesizer_) {
      synthesizer_->virtualMask(mask);
      return true;
    }
    // A copy: every sample is the reference's own, except those without depth (MissingDepthLevel).
    const Plane& depth = *references[size_t(plan_.copyOf)].depth;
    mask.resize(depth.width, depth.height);
    for (size_t i = 0; i < depth.samples.size(); ++i)
      mask.samples[i] = plan_.missingDepthLevel >= 0 && depth.samples[i] == plan_.missingDepthLevel ? 255 : 0;
    return true;
  }
  int64_t uncoveredSamples() const override {
    return synthesizer_ ? int64_t(synthesizer_->lastStats().holesAfterBlend) : -1;
  }
  // A pose trace: the plan is made again for the moved camera (its weights and paths depend on it);
  // a MissingDepthLevel auto decision taken on the first frame is kept.
  bool moveVirtualCamera(const Camera& camera) override {
    scene_.virtualCamera = camera;
    Plan moved = makePlan(scene_);
    if (moved.missingDepthAuto && plan_.missingDepthDecided) {
      moved.missingDepthLevel = plan_.missingDepthLevel;
      moved.missingDepthFill = plan_.missingDepthFill;
      moved.missingDepthEvidence = plan_.missingDepthEvidence;
      moved.missingDepthDecided = true;
    }
    plan_ = std::move(moved);
    synthesizer_.reset();
    if (plan_.copyOf < 0 && (!plan_.missingDepthAuto || plan_.missingDepthDecided)) makeSynthesizer();
    return true;
  }
  std::vector<std::string> plan() const override { return plan_.lines(); }
  std::vector<std::pair<std::string, std::string>> decisions() const override { return plan_.fields(); }

private:
  // A run of one frame frees the synthesizer's buffers step by step and keeps nothing for a next
  // frame (Synthesizer.h).
  void makeSynthesizer() {
    synthesizer_ = std::make_unique<Synthesizer>(scene_, plan_);
    if (scene_.settings.frameCount <= 1) {
      synthesizer_->releaseBuffersAfterEachStep();
      synthesizer_->noNextFrame();
    }
  }
  Scene scene_;  // a copy: a pose trace moves its virtual camera
  Plan plan_;
  std::unique_ptr<Synthesizer> synthesizer_;
};

}  // namespace

RunSummary runViewSyn(const Config& config, std::FILE* log) {
  RunReport report("ViewSyn", config);
  return runReported(report, [&] {
    const Scene scene = loadScene(config);
    ViewSynRenderer renderer(scene);
    setWorkerThreads(scene.settings.threads);
    return runSequence("ViewSyn", scene, renderer, report, log);
  });
}

}  // namespace vs
