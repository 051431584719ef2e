#include "Synth/Run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <functional>
#include <future>
#include <memory>

#include <opencv2/core/utility.hpp>

#include "Common/Error.h"
#include "Common/InputCheck.h"
#include "Common/SafeOutput.h"
#include "Common/Memory.h"
#include "Common/Metrics.h"
#include "Common/Depth.h"
#include "Common/Yuv.h"
#include "Synth/Parallel.h"
#include "Synth/Plan.h"

namespace vs {

namespace {

// ViewSyn's middle box: what the plan decided, a copy or the synthesizer on the chosen path.
class ViewSynRenderer : public FrameRenderer {
public:
  explicit ViewSynRenderer(const Scene& scene) : scene_(scene), plan_(makePlan(scene)) {
    if (plan_.copyOf < 0) synthesizer_ = std::make_unique<Synthesizer>(scene, plan_.mode);
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
  int64_t uncoveredSamples() const override {
    return synthesizer_ ? int64_t(synthesizer_->lastStats().holesAfterBlend) : -1;
  }
  std::vector<std::string> plan() const override {
    std::vector<std::string> lines = plan_.lines;
    if (!synthesizer_) return lines;
    const SynthesisSettings& s = scene_.settings;
    std::string weights = "blend weights:";
    for (size_t k = 0; k < s.references.size(); ++k) {
      char item[64];
      std::snprintf(item, sizeof item, " %s %.4f", s.references[k].label.c_str(), synthesizer_->blendWeights()[k]);
      weights += item;
    }
    lines.push_back(weights + (s.viewBlending ? " (ViewBlending 1: the heavier view where views agree)" : ""));
    lines.push_back("texture: Precision " + std::to_string(s.precision) + ", Filter " + std::to_string(s.filter) +
                    (s.colorSpace ? ", processed in RGB" : ", processed in YUV"));
    return lines;
  }

private:
  const Scene& scene_;
  Plan plan_;
  std::unique_ptr<Synthesizer> synthesizer_;
};

std::string describeTimes(const StageTimes& t, double frames) {
  char line[512];
  std::snprintf(line, sizeof line,
                "read %.4f, depth warp %.4f, texture warp %.4f, blend %.4f, hole fill %.4f, write %.4f, total %.4f",
                t.read / frames, t.depthWarp / frames, t.textureWarp / frames, t.blend / frames, t.holeFill / frames,
                t.write / frames, t.total() / frames);
  return line;
}

}  // namespace

RunSummary runSequence(const std::string& toolName, const Config& config, const Scene& scene, FrameRenderer& renderer,
                       std::FILE* log) {
  // Everything people read goes to `log`; nullptr: silent (benchmarks).
  auto say = [log](const char* format, auto... args) {
    if (log) std::fprintf(log, format, args...);
  };
  const SynthesisSettings& s = scene.settings;
  // Room on huge pages for what the frames will allocate: about 200 bytes per output sample with two
  // views (measured on Middlebury), about 60 more per further view; half as much again to spare.
  const size_t samples = size_t(s.textureFormat.width) * size_t(s.textureFormat.height);
  reserveHugePageHeap(samples * (144 + 96 * s.references.size()));
  // Threads 0: every core. The output does not depend on it (Synth/Parallel.h).
  cv::setNumThreads(s.threads > 0 ? s.threads : cv::getNumberOfCPUs());
  say("%s %s\n\n%s\n%s", toolName.c_str(), VS_VERSION, config.effectiveText().c_str(), describeCameras(scene).c_str());
  // Every input by content and size, every output by name, before anything is created.
  RunSummary summary;
  summary.warnings = scene.warnings;
  for (const std::string& warning : checkInputs(scene)) summary.warnings.push_back(warning);
  checkOutputs(scene, renderer.extraOutputs());
  for (const std::string& warning : summary.warnings) say("warning: %s\n", warning.c_str());
  say("\nplan:\n");
  for (const std::string& line : renderer.plan()) say("  %s\n", line.c_str());

  // Open every input and find how many frames all of them hold from StartFrame on.
  std::vector<std::unique_ptr<YuvReader>> textures, depths;
  for (const ReferenceView& view : s.references) {
    textures.push_back(std::make_unique<YuvReader>(view.texturePath, s.textureFormat));
    depths.push_back(std::make_unique<YuvReader>(view.depthPath, view.depthFormat));
  }
  std::unique_ptr<YuvReader> truth;
  if (!s.referenceViewPath.empty()) truth = std::make_unique<YuvReader>(s.referenceViewPath, s.textureFormat);
  int64_t available = s.frameCount;
  std::string shortest;
  auto limit = [&](const YuvReader& reader) {
    const int64_t count = reader.frameCount();
    if (s.startFrame >= count)
      throw InputError(reader.path() + ": StartFrame " + std::to_string(s.startFrame) + " is beyond the end of the file (" +
                       std::to_string(count) + " whole frames of " + std::to_string(reader.format().frameBytes()) + " bytes)");
    if (count - s.startFrame < available) {
      available = count - s.startFrame;
      shortest = reader.path();
    }
  };
  for (size_t k = 0; k < textures.size(); ++k) {
    limit(*textures[k]);
    limit(*depths[k]);
  }
  if (truth) limit(*truth);

  // Every output is checked before any is created: a refused run truncates nothing.
  const std::vector<std::string> inputs = s.inputPaths();
  FrameFormat virtualDepthFormat = s.depthFormat;
  virtualDepthFormat.bitDepth = s.virtualDepthRange.bitDepth;
  std::vector<std::string> notDepth = inputs;
  notDepth.push_back(s.outputPath);
  YuvWriter::checkOutput(s.outputPath, s.textureFormat, inputs, "OutputVirtualViewImageName");
  if (!s.virtualDepthPath.empty())
    YuvWriter::checkOutput(s.virtualDepthPath, virtualDepthFormat, notDepth, "OutputVirtualDepthMapName");
  // Each output is a temporary file until the run ends well (SafeOutput.h).
  const Y4mHeader* rate = nullptr;  // a Y4M output keeps the frame rate of a Y4M texture
  for (const auto& texture : textures) rate = rate ? rate : texture->y4m();
  YuvWriter writer(s.outputPath, s.textureFormat, inputs, "OutputVirtualViewImageName", rate);
  std::unique_ptr<YuvWriter> depthWriter;
  Frame virtualDepthFrame(virtualDepthFormat);
  if (!s.virtualDepthPath.empty()) {
    depthWriter = std::make_unique<YuvWriter>(s.virtualDepthPath, virtualDepthFormat, notDepth, "OutputVirtualDepthMapName");
    virtualDepthFrame.fill(0);
  }
  std::unique_ptr<SafeOutputFile> report;
  if (!s.reportPath.empty()) {
    report = std::make_unique<SafeOutputFile>(s.reportPath, inputs, "ReportFile");
    report->write("frame,psnr_y,psnr_u,psnr_v,psnr_yuv,read_s,depth_warp_s,texture_warp_s,blend_s,hole_fill_s,write_s,total_s\n");
  }

  // Two sets of input buffers: while one frame is synthesized, the next one is read on another
  // thread (reading is file I/O and unpacking; the synthesis keeps the cores busy).
  struct Inputs {
    std::vector<Frame> textures;
    std::vector<Plane> depths;
    Frame truth;
    double seconds = 0;
  };
  Inputs slots[2];
  for (Inputs& slot : slots) {
    slot.textures.resize(textures.size());
    slot.depths.resize(depths.size());
  }
  // The files of one frame: each view's texture and depth (every view its own readers and buffers),
  // then the ground truth. onThreads: the views (and the truth) read side by side on the pool, for
  // the first frame, which nothing else overlaps; a failure is reported as the first file in that
  // order would be read alone.
  auto readInputs = [&](int64_t frameIndex, Inputs& slot, bool onThreads) {
    const auto start = std::chrono::steady_clock::now();
    const int jobs = int(textures.size()) + (truth ? 1 : 0);
    auto readJob = [&](int j) {
      if (size_t(j) == textures.size()) {
        truth->read(frameIndex, slot.truth);
        return;
      }
      textures[size_t(j)]->read(frameIndex, slot.textures[size_t(j)]);
      depths[size_t(j)]->readLuma(frameIndex, slot.depths[size_t(j)]);
    };
    if (onThreads && jobs > 1) {
      std::vector<std::exception_ptr> failed(static_cast<size_t>(jobs));
      parallelRanges(jobs, [&](int j0, int j1) {
        for (int j = j0; j < j1; ++j) try {
            readJob(j);
          } catch (...) {
            failed[size_t(j)] = std::current_exception();
          }
      });
      for (const std::exception_ptr& failure : failed)
        if (failure) std::rethrow_exception(failure);
    } else {
      for (int j = 0; j < jobs; ++j) readJob(j);
    }
    slot.seconds = secondsSince(start);
  };
  // The first frame is read when the loop asks for it, on the calling thread and the pool; each next
  // one on a thread of its own while the frame before is synthesized.
  std::future<void> nextRead;
  if (available > 0) nextRead = std::async(std::launch::deferred, readInputs, s.startFrame, std::ref(slots[0]), true);
  // A frame's read that is still running when the loop leaves early (an error) is waited for here,
  // before the buffers it fills go away.
  struct ReadWaiter {
    std::future<void>& read;
    ~ReadWaiter() {
      if (read.valid()) read.wait();
    }
  } waiter{nextRead};
  Frame output;
  PsnrAccumulator accumulator(s.textureFormat.bitDepth, s.textureFormat.chroma != ChromaFormat::Yuv400);
  int64_t leastCovered = -1, leastCoveredFrame = 0;  // samples warped from any view, in the worst frame
  say("\n");
  for (int64_t f = 0; f < available; ++f) try {
    const int64_t frameIndex = s.startFrame + f;
    StageTimes times;
    auto start = std::chrono::steady_clock::now();
    nextRead.get();  // rethrows a read error
    Inputs& current = slots[f % 2];
    // Read time: what the read took on its own thread, or the wait for it when that is longer.
    times.read = std::max(secondsSince(start), f == 0 ? current.seconds : 0.0);
    if (f + 1 < available)
      nextRead = std::async(std::launch::async, readInputs, frameIndex + 1, std::ref(slots[(f + 1) % 2]), false);
    std::vector<ReferenceFrame> references(textures.size());
    for (size_t k = 0; k < textures.size(); ++k) references[k] = ReferenceFrame{&current.textures[k], &current.depths[k]};
    const Frame& truthFrame = current.truth;
    renderer.render(references, output, times);
    const int64_t uncovered = renderer.uncoveredSamples();
    if (uncovered >= 0) {
      const int64_t covered = int64_t(output.planes[0].samples.size()) - uncovered;
      if (leastCovered < 0 || covered < leastCovered) {
        leastCovered = covered;
        leastCoveredFrame = frameIndex;
      }
    }
    start = std::chrono::steady_clock::now();
    writer.append(output);
    if (depthWriter) {
      if (!renderer.virtualDepth(references, s.virtualDepthRange, virtualDepthFrame.planes[0]))
        throw InputError(toolName + " cannot write OutputVirtualDepthMapName");
      depthWriter->append(virtualDepthFrame);
    }
    times.write = secondsSince(start);
    summary.times += times;
    ++summary.framesWritten;
    say("frame %lld: %.4f s", (long long)frameIndex, times.total());
    FramePsnr psnr;
    if (truth) {
      psnr = framePsnr(truthFrame, output);
      accumulator.add(psnr);
      say("  PSNR Y %s U %s V %s dB", formatPsnr(psnr.y).c_str(), formatPsnr(psnr.u).c_str(), formatPsnr(psnr.v).c_str());
    }
    say("\n");
    if (log) std::fflush(log);
    if (report) {
      char line[512];
      std::snprintf(line, sizeof line, "%lld,%s,%s,%s,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", (long long)frameIndex,
                    truth ? formatPsnr(psnr.y).c_str() : "", truth ? formatPsnr(psnr.u).c_str() : "",
                    truth ? formatPsnr(psnr.v).c_str() : "", truth ? formatPsnr(psnr.yuv).c_str() : "", times.read,
                    times.depthWarp, times.textureWarp, times.blend, times.holeFill, times.write, times.total());
      report->write(line);
    }
  } catch (const InputError& e) {
    // Nothing is on disk yet: every output is a temporary file, removed as the writers go away.
    throw InputError(std::string(e.what()) + " (frame " + std::to_string(s.startFrame + f) +
                     "; no output file was created or replaced)");
  }

  // A virtual camera that sees (almost) nothing gives plain hole-filled frames: say so.
  if (leastCovered >= 0) {
    const double share = double(leastCovered) / double(size_t(s.textureFormat.width) * size_t(s.textureFormat.height));
    if (share < 0.01) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "virtual view: only %.2f %% of the samples of frame %lld were warped from any reference view; the "
                    "rest is hole filling (is the virtual camera '%s' turned away from the scene, or far from it?)",
                    100.0 * share, (long long)leastCoveredFrame, s.virtualCameraName.c_str());
      summary.warnings.push_back(line);
      say("warning: %s\n", line);
    }
  }
  // The run ended well (or the inputs ran out, which the message below says): every output is
  // renamed into place, whole.
  writer.commit();
  if (depthWriter) depthWriter->commit();
  if (report) report->commit();
  renderer.commitOutputs();

  const double frames = double(summary.framesWritten);
  say("\n%lld frames written to %s\n", (long long)summary.framesWritten, s.outputPath.c_str());
  say("seconds per frame: %s\n", describeTimes(summary.times, frames).c_str());
  if (truth && accumulator.frames() > 0) {
    summary.meanPsnrY = accumulator.y().frameMean;
    if (accumulator.hasChroma()) {
      summary.meanPsnrU = accumulator.u().frameMean;
      summary.meanPsnrV = accumulator.v().frameMean;
    }
    say("mean PSNR: Y %s U %s V %s YUV %s dB\n", formatPsnr(accumulator.y().frameMean).c_str(),
                accumulator.hasChroma() ? formatPsnr(accumulator.u().frameMean).c_str() : "-",
                accumulator.hasChroma() ? formatPsnr(accumulator.v().frameMean).c_str() : "-",
                formatPsnr(accumulator.yuv().frameMean).c_str());
  }
  if (available < s.frameCount)
    throw InputError(shortest + " holds only " + std::to_string(available) + " frames from StartFrame " +
                     std::to_string(s.startFrame) + ", but TotalNumberOfFrames is " + std::to_string(s.frameCount) + "; " +
                     std::to_string(summary.framesWritten) + " whole frames were written to " + s.outputPath);
  return summary;
}

RunSummary runViewSyn(const Config& config, std::FILE* log) {
  const Scene scene = loadScene(config);
  ViewSynRenderer renderer(scene);
  return runSequence("ViewSyn", config, scene, renderer, log);
}

}  // namespace vs
