#pragma once
// The run report (../shared/DESIGN.md, "Output that people read"; doc/report.md): what a run prints
// (version, effective configuration, cameras, plan, a line per frame, totals and means), the CSV of
// ReportFile (one row per frame, columns from one list) and the JSON summary of SummaryFile (the whole
// run, written also when it fails). Experiment scripts read the JSON instead of parsing stdout.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "Common/Config.h"
#include "Common/Metrics.h"
#include "Common/Scene.h"
#include "Common/Timing.h"

namespace vs {

// One frame of a run as the report keeps it.
struct FrameRecord {
  int64_t frame = 0;    // index in the input files (StartFrame + n)
  bool scored = false;  // PSNR against the reference view was measured
  FramePsnr psnr;
  StageTimes times;
  std::vector<double> quality;  // QualityMetrics' values, in the order of QualityReport::keys()
};

// The CSV header's names in order: frame, psnr_y, psnr_u, psnr_v, psnr_yuv, then seconds per stage
// (read_s ... write_s) and total_s. The JSON summary's frames and means use the same names.
std::vector<std::string> reportColumns();

struct RunSummary {
  int64_t framesWritten = 0;
  double meanPsnrY = 0, meanPsnrU = 0, meanPsnrV = 0, meanPsnrYuv = 0;  // frame means; 0 without a reference view
  StageTimes times;                                                      // sums over all frames
};

class RunReport {
public:
  // Keeps the tool's name and the effective configuration; reads ReportFile and SummaryFile from it.
  RunReport(std::string toolName, const Config& config);
  ~RunReport();
  RunReport(const RunReport&) = delete;
  RunReport& operator=(const RunReport&) = delete;

  // Prints the start of the run to `log` (nullptr: silent): tool and version, the effective
  // configuration, the cameras, the scene's warnings and the plan; keeps warnings and plan.
  void begin(const Scene& scene, const std::vector<std::string>& plan, std::FILE* log);
  // The plan's decisions as key/value pairs, written as the summary's "decisions" object.
  void recordDecisions(std::vector<std::pair<std::string, std::string>> decisions) { decisions_ = std::move(decisions); }
  // Creates ReportFile (when set) with its header, after the outputs are open. Throws InputError.
  void startFrames(std::FILE* log);
  // One frame: a line on `log`, a CSV row, a JSON entry.
  void addFrame(const FrameRecord& record, std::FILE* log);
  // Prints frames written, seconds per frame and stage, mean PSNR; returns the same figures.
  RunSummary finish(const std::string& outputPath, std::FILE* log) const;

  const std::vector<FrameRecord>& frames() const { return frames_; }
  // The summary as JSON text (doc/report.md has the schema); `error` empty when the run succeeded.
  std::string summaryJson(int exitStatus, const std::string& error) const;
  // Writes summaryJson() to SummaryFile when one is configured; throws InputError when it cannot.
  // A SummaryFile that names a file the configuration reads or writes is never written.
  void writeSummary(int exitStatus, const std::string& error) const;

private:
  double qualityMean(size_t column) const;  // mean of a QualityMetrics column over the frames

  std::string toolName_;
  const Config& config_;
  std::string csvPath_, summaryPath_;
  std::FILE* csv_ = nullptr;
  bool hasChroma_ = true;
  std::vector<std::string> qualityMetrics_;  // QualityMetrics when a reference view is set (doc/metrics.md)
  std::vector<std::string> plan_, warnings_;
  std::vector<std::pair<std::string, std::string>> decisions_;
  std::vector<FrameRecord> frames_;
};

// Runs `body` (load the scene, render, runSequence into `report`) and writes the JSON summary
// afterwards: exit status 0, or 1 with the error's message when `body` throws (then rethrown).
RunSummary runReported(RunReport& report, const std::function<RunSummary()>& body);

// The JSON that --print-config prints: tool, version, config file, every key's effective value and
// the scene as the tool reads it (sizes, formats, frames, files, cameras). Opens no YUV file.
std::string configJson(const std::string& toolName, const Config& config, const Scene& scene);

}  // namespace vs
