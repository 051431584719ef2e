#include "Pipeline/FrameLoop.h"

#include <chrono>

#include "Common/Error.h"
#include "Common/Memory.h"
#include "Common/Metrics.h"
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
  SequenceInputs inputs(s);
  SequenceOutputs outputs(s);
  report.startFrames(log);
  Frame output;
  for (int64_t f = 0; f < inputs.available(); ++f) try {
      StageTimes times;
      const SequenceInputs::FrameInputs frame = inputs.next(times.read);
      if (f == 0) {
        const std::vector<std::string> decided = renderer.prepare(frame.references);
        if (!decided.empty()) report.recordDecisions(renderer.decisions());
        if (log)
          for (const std::string& line : decided) std::fprintf(log, "plan, first frame: %s\n", line.c_str());
      }
      renderer.render(frame.references, output, times);
      const auto start = std::chrono::steady_clock::now();
      outputs.append(
          output, [&](Plane& levels) { return renderer.virtualDepth(frame.references, s.virtualDepthRange, levels); },
          toolName);
      times.write = secondsSince(start);
      FrameRecord record{s.startFrame + f, frame.truth != nullptr, {}, times};
      if (frame.truth) record.psnr = framePsnr(*frame.truth, output);
      report.addFrame(record, log);
    } catch (const InputError& e) {
      // Say what is on disk: the writers keep whole frames only.
      throw InputError(std::string(e.what()) + " (frame " + std::to_string(s.startFrame + f) + "; " + outputs.written() + ")");
    }
  const RunSummary summary = report.finish(s.outputPath, log);
  if (inputs.available() < s.frameCount)
    throw InputError(inputs.shortfall() + "; " + std::to_string(summary.framesWritten) + " whole frames were written to " +
                     s.outputPath);
  return summary;
}

}  // namespace vs
