#include "Pipeline/FrameLoop.h"

#include <chrono>

#include "Common/Error.h"
#include "Common/InputCheck.h"
#include "Common/Memory.h"
#include "Common/Metrics.h"
#include "Common/QualityReport.h"
#include "Pipeline/SequenceInputs.h"
#include "Pipeline/SequenceOutputs.h"

namespace vs {

RunSummary runSequence(const std::string& toolName, const Scene& scene, FrameRenderer& renderer, RunReport& report,
                       std::FILE* log) {
  const SynthesisSettings& s = scene.settings;
  // Room on huge pages for what the frames will allocate: about 200 bytes per output sample with two
  // views (measured on Middlebury), about 60 more per further view; half as much again to spare.
  const size_t samples = size_t(s.textureFormat.width) * size_t(s.textureFormat.height);
  reserveHugePageHeap(samples * (144 + 96 * s.references.size()));
  report.recordDecisions(renderer.decisions());
  report.begin(scene, renderer.plan(), log);
  // Every input by content and size, every output by name, before anything is
  // created (Common/InputCheck.h).
  const std::vector<std::string> inputWarnings = checkInputs(scene);
  checkOutputs(scene, renderer.extraOutputs());
  for (const std::string& warning : inputWarnings) report.warn(warning, log);
  SequenceInputs inputs(s);
  // Each output is a temporary file until the run ends well (Common/SafeOutput.h).
  SequenceOutputs outputs(s, inputs.y4mTexture());
  report.startFrames(log);
  // Metrics besides PSNR against the reference view (QualityMetrics, doc/metrics.md).
  QualityReport quality(s.referenceViewPath.empty() ? std::vector<std::string>{} : s.qualityMetrics,
                        s.textureFormat.chroma != ChromaFormat::Yuv400);
  if (scene.virtualCamera.isEquirectangular())
    quality.setLatitudeRange(scene.virtualCamera.erp.latMax - scene.virtualCamera.erp.latMin);
  Frame output;
  int64_t leastCovered = -1, leastCoveredFrame = 0;  // samples warped from any view, in the worst frame
  for (int64_t f = 0; f < inputs.available(); ++f) try {
      StageTimes times;
      const SequenceInputs::FrameInputs frame = inputs.next(times.read);
      if (f == 0) {
        const std::vector<std::string> decided = renderer.prepare(frame.references);
        if (!decided.empty()) report.recordDecisions(renderer.decisions());
        if (log)
          for (const std::string& line : decided) std::fprintf(log, "plan, first frame: %s\n", line.c_str());
      }
      // A pose trace moves the virtual camera frame by frame (Common/RvsConfig.h).
      if (!scene.virtualCameraPerFrame.empty() && !renderer.moveVirtualCamera(scene.virtualCameraPerFrame[size_t(f)]))
        throw InputError(toolName + " cannot move its virtual camera: VirtualPoseTraceName is not supported by it");
      renderer.render(frame.references, output, times);
      const int64_t uncovered = renderer.uncoveredSamples();
      if (uncovered >= 0) {
        const int64_t covered = int64_t(output.planes[0].samples.size()) - uncovered;
        if (leastCovered < 0 || covered < leastCovered) {
          leastCovered = covered;
          leastCoveredFrame = s.startFrame + f;
        }
      }
      const auto start = std::chrono::steady_clock::now();
      outputs.append(
          output, [&](Plane& levels) { return renderer.virtualDepth(frame.references, s.virtualDepthRange, levels); },
          toolName);
      times.write = secondsSince(start);
      FrameRecord record{s.startFrame + f, frame.truth != nullptr, {}, times, {}};
      if (frame.truth) record.psnr = framePsnr(*frame.truth, output);
      if (frame.truth && !quality.empty()) {
        quality.score(*frame.truth, output);
        record.quality = quality.lastValues();
      }
      report.addFrame(record, log);
    } catch (const InputError& e) {
      // Nothing is on disk yet: every output is a temporary file, removed as the writers go away.
      throw InputError(std::string(e.what()) + " (frame " + std::to_string(s.startFrame + f) +
                       "; no output file was created or replaced)");
    }

  // A virtual camera that sees (almost) nothing gives plain hole-filled frames: say so.
  if (leastCovered >= 0 && samples > 0) {
    const double share = double(leastCovered) / double(samples);
    if (share < 0.01) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "virtual view: only %.2f %% of the samples of frame %lld were warped from any reference view; the "
                    "rest is hole filling (is the virtual camera '%s' turned away from the scene, or far from it?)",
                    100.0 * share, (long long)leastCoveredFrame, s.virtualCameraName.c_str());
      report.warn(line, log);
    }
  }
  // The run ended well (or the inputs ran out, which the message below says): every output is
  // renamed into place, whole.
  outputs.commit();
  report.commit();
  renderer.commitOutputs();
  const RunSummary summary = report.finish(s.outputPath, log);
  if (inputs.available() < s.frameCount)
    throw InputError(inputs.shortfall() + "; " + std::to_string(summary.framesWritten) + " whole frames were written to " +
                     s.outputPath);
  return summary;
}

}  // namespace vs
