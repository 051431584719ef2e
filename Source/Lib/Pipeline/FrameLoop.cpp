#include "Pipeline/FrameLoop.h"

#include <chrono>
#include <cstdint>

#include "Common/Error.h"
#include "Common/InputCheck.h"
#include "Common/Memory.h"
#include "Common/Metrics.h"
#include "Common/QualityReport.h"
#include "Pipeline/SequenceInputs.h"
#include "Pipeline/SequenceOutputs.h"

namespace vs {
namespace {

// Before any file is opened or created: room on huge pages, the plan on the log, then every input by
// content and size and every output by name (Common/InputCheck.h).
void checkBeforeOpening(const Scene& scene, FrameRenderer& renderer, RunReport& report, std::FILE* log) {
  const SynthesisSettings& s = scene.settings;
  // Room on huge pages for what the frames will allocate: about 200 bytes per output sample with two
  // views (measured on Middlebury), about 60 more per further view; half as much again to spare.
  const size_t samples = size_t(s.virtualFormat().width) * size_t(s.virtualFormat().height);
  // Huge pages for a sequence, 4 KiB pages for a single frame, whose first run after some idle time
  // would pay the host's faults on fresh huge pages (Common/Memory.h; VS_HUGE_PAGES decides instead).
  const bool hugePages = reserveHugePageHeap(samples * (144 + 96 * s.references.size()), s.frameCount > 1);
  // Sparse buffers on 4 KiB pages from 1 MiB for pictures of a megapixel or more (1920x1080: 23 MiB
  // less resident than from 4 MiB), from 4 MiB below (Art, 688x554: 5 ms more CPU of 60 in page faults
  // with its 1.5 to 3 MB estimates on 4 KiB pages); doc/speed.md. Where the heap is not on huge
  // pages (a single frame, by default) they stay on the heap whatever their size: its 4 KiB pages
  // already fault in only where written, and a mapping of their own is fresh pages, where the heap
  // has the memory the earlier steps freed (the occlusion rule's surroundings of a 1920x1080 frame:
  // about 3 600 page faults).
  setSmallPageBuffersFrom(!hugePages ? SIZE_MAX : samples >= 1000000 ? size_t(1) << 20 : size_t(4) << 20);
  report.recordDecisions(renderer.decisions());
  report.begin(scene, renderer.plan(), log);
  const std::vector<std::string> inputWarnings = checkInputs(scene);
  checkOutputs(scene, renderer.extraOutputs());
  for (const std::string& warning : inputWarnings) report.warn(warning, log);
}

// The decisions a renderer can only make on the first frame's pictures (MissingDepthLevel auto) join
// the report's and are logged.
void decideOnFirstFrame(FrameRenderer& renderer, const std::vector<ReferenceFrame>& references, RunReport& report,
                        std::FILE* log) {
  const std::vector<std::string> decided = renderer.prepare(references);
  if (!decided.empty()) report.recordDecisions(renderer.decisions());
  if (log)
    for (const std::string& line : decided) std::fprintf(log, "plan, first frame: %s\n", line.c_str());
}

// The frame with the fewest samples warped from any view, for the warning at the end.
struct LeastCovered {
  int64_t samples = -1;  // -1: the renderer does not say
  int64_t frame = 0;

  void add(int64_t frameIndex, const Frame& output, int64_t uncovered) {
    if (uncovered < 0) return;
    const int64_t covered = int64_t(output.planes[0].samples.size()) - uncovered;
    if (samples < 0 || covered < samples) {
      samples = covered;
      frame = frameIndex;
    }
  }

  // A virtual camera that sees (almost) nothing gives plain hole-filled frames: say so.
  void warnIfAlmostNothing(const SynthesisSettings& s, RunReport& report, std::FILE* log) const {
    const size_t frameSamples = size_t(s.virtualFormat().width) * size_t(s.virtualFormat().height);
    if (samples < 0 || frameSamples == 0) return;
    const double share = double(samples) / double(frameSamples);
    if (share >= 0.01) return;
    char line[512];
    std::snprintf(line, sizeof line,
                  "virtual view: only %.2f %% of the samples of frame %lld were warped from any reference view; the "
                  "rest is hole filling (is the virtual camera '%s' turned away from the scene, or far from it?)",
                  100.0 * share, (long long)frame, s.virtualCameraName.c_str());
    report.warn(line, log);
  }
};

// What one run's frames share: the opened inputs and outputs, the scores, the report.
struct FrameSteps {
  const std::string& toolName;
  const SynthesisSettings& s;
  const std::vector<Camera>& virtualCameraPerFrame;  // VirtualPoseTraceName; empty: a fixed camera
  FrameRenderer& renderer;
  RunReport& report;
  std::FILE* log;
  SequenceInputs& inputs;
  SequenceOutputs& outputs;
  QualityReport& quality;
  Frame output;
  LeastCovered leastCovered;

  // Frame f of the run: read (ahead), decide on frame 0, render, append to the outputs, score, report.
  void renderFrame(int64_t f) {
    StageTimes times;
    const SequenceInputs::FrameInputs frame = inputs.next(times.read);
    if (f == 0) {
      renderer.firstInputsRead();
      decideOnFirstFrame(renderer, frame.references, report, log);
    }
    // A pose trace moves the virtual camera frame by frame (Common/RvsConfig.h).
    if (!virtualCameraPerFrame.empty() && !renderer.moveVirtualCamera(virtualCameraPerFrame[size_t(f)]))
      throw InputError(toolName + " cannot move its virtual camera: VirtualPoseTraceName is not supported by it");
    renderer.render(frame.references, output, times);
    leastCovered.add(s.startFrame + f, output, renderer.uncoveredSamples());
    const auto start = std::chrono::steady_clock::now();
    outputs.append(
        output, [&](Plane& levels) { return renderer.virtualDepth(frame.references, s.virtualDepthRange, levels); },
        [&](Plane& mask) { return renderer.virtualMask(frame.references, mask); }, toolName);
    times.write = secondsSince(start);
    FrameRecord record{s.startFrame + f, frame.hasTruth, {}, times, {}};
    if (frame.hasTruth) record.psnr = framePsnr(inputs.truth(), output);
    if (frame.hasTruth && !quality.empty()) {
      quality.score(inputs.truth(), output);
      record.quality = quality.lastValues();
    }
    report.addFrame(record, log);
  }

  // The run ended well (or the inputs ran out, which the error then says): every output is renamed
  // into place, whole.
  RunSummary commit() {
    leastCovered.warnIfAlmostNothing(s, report, log);
    outputs.commit();
    report.commit();
    renderer.commitOutputs();
    const RunSummary summary = report.finish(s.outputPath, log);
    if (inputs.available() < s.frameCount)
      throw InputError(inputs.shortfall() + "; " + std::to_string(summary.framesWritten) +
                       " whole frames were written to " + s.outputPath);
    return summary;
  }
};

}  // namespace

RunSummary runSequence(const std::string& toolName, const Scene& scene, FrameRenderer& renderer, RunReport& report,
                       std::FILE* log) {
  const SynthesisSettings& s = scene.settings;
  checkBeforeOpening(scene, renderer, report, log);
  SequenceInputs inputs(s);
  // Each output is a temporary file until the run ends well (Common/SafeOutput.h).
  SequenceOutputs outputs(s, inputs.y4mTexture());
  report.startFrames(log);
  // Metrics besides PSNR against the reference view (QualityMetrics, doc/metrics.md).
  QualityReport quality(s.referenceViewPath.empty() ? std::vector<std::string>{} : s.qualityMetrics,
                        s.textureFormat.chroma != ChromaFormat::Yuv400);
  if (scene.virtualCamera.isEquirectangular())
    quality.setLatitudeRange(scene.virtualCamera.erp.latMax - scene.virtualCamera.erp.latMin);
  FrameSteps steps{toolName, s, scene.virtualCameraPerFrame, renderer, report, log, inputs, outputs, quality, Frame(),
                   LeastCovered()};
  for (int64_t f = 0; f < inputs.available(); ++f) try {
      steps.renderFrame(f);
    } catch (const InputError& e) {
      // Nothing is on disk yet: every output is a temporary file, removed as the writers go away.
      throw InputError(std::string(e.what()) + " (frame " + std::to_string(s.startFrame + f) +
                       "; no output file was created or replaced)");
    }
  return steps.commit();
}

}  // namespace vs
