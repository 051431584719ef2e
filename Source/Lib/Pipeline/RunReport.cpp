#include "Pipeline/RunReport.h"

#include <cmath>
#include <sstream>

#include "Common/BuildInfo.h"
#include "Common/Error.h"
#include "Common/Json.h"
#include "Common/QualityReport.h"

namespace vs {

namespace {

// The report's columns: CSV header and row, JSON frame and mean, all from this one list.
struct Column {
  const char* name;
  enum Kind { Index, Psnr, Seconds } kind;
  double (*value)(const FrameRecord&);
  bool chroma;  // psnr_u, psnr_v: no value for 4:0:0 in the JSON
};

const Column kColumns[] = {
    {"frame", Column::Index, [](const FrameRecord& r) { return double(r.frame); }, false},
    {"psnr_y", Column::Psnr, [](const FrameRecord& r) { return r.psnr.y; }, false},
    {"psnr_u", Column::Psnr, [](const FrameRecord& r) { return r.psnr.u; }, true},
    {"psnr_v", Column::Psnr, [](const FrameRecord& r) { return r.psnr.v; }, true},
    {"psnr_yuv", Column::Psnr, [](const FrameRecord& r) { return r.psnr.yuv; }, false},
    {"read_s", Column::Seconds, [](const FrameRecord& r) { return r.times.read; }, false},
    {"depth_warp_s", Column::Seconds, [](const FrameRecord& r) { return r.times.depthWarp; }, false},
    {"texture_warp_s", Column::Seconds, [](const FrameRecord& r) { return r.times.textureWarp; }, false},
    {"blend_s", Column::Seconds, [](const FrameRecord& r) { return r.times.blend; }, false},
    {"hole_fill_s", Column::Seconds, [](const FrameRecord& r) { return r.times.holeFill; }, false},
    {"write_s", Column::Seconds, [](const FrameRecord& r) { return r.times.write; }, false},
    {"total_s", Column::Seconds, [](const FrameRecord& r) { return r.times.total(); }, false},
};

// A JSON value for a double: a number, the string "inf" for +infinity ("-inf" likewise), null for NaN.
std::string jsonValue(double value) {
  if (std::isnan(value)) return "null";
  if (std::isinf(value)) return value > 0 ? "\"inf\"" : "\"-inf\"";
  return jsonNumber(value);
}

std::string describeTimes(const StageTimes& t, double frames) {
  char line[512];
  std::snprintf(line, sizeof line,
                "read %.4f, depth warp %.4f, texture warp %.4f, blend %.4f, hole fill %.4f, write %.4f, total %.4f",
                t.read / frames, t.depthWarp / frames, t.textureWarp / frames, t.blend / frames, t.holeFill / frames,
                t.write / frames, t.total() / frames);
  return line;
}

// Frame means of the PSNRs (PsnrAccumulator: frames with an identical plane left out) and sums of the
// seconds, over the frames of a run.
struct Means {
  int64_t frames = 0, scored = 0;
  PsnrAccumulator::Mean psnr[4];  // Y, U, V, YUV
  StageTimes sums;
};

Means computeMeans(const std::vector<FrameRecord>& frames, bool hasChroma) {
  Means means;
  PsnrAccumulator accumulator(8, hasChroma);  // the frame means do not depend on the bit depth
  for (const FrameRecord& record : frames) {
    ++means.frames;
    means.sums += record.times;
    if (!record.scored) continue;
    ++means.scored;
    accumulator.add(record.psnr);
  }
  if (means.scored > 0) {
    means.psnr[0] = accumulator.y();
    if (hasChroma) {
      means.psnr[1] = accumulator.u();
      means.psnr[2] = accumulator.v();
    }
    means.psnr[3] = accumulator.yuv();
  }
  return means;
}

// {"Key": "effective value", ...} in the option table's order, one key a line.
std::string configMembers(const Config& config, const char* indent) {
  std::string out = "{";
  const std::vector<OptionSpec>& options = config.table().options();
  for (size_t k = 0; k < options.size(); ++k)
    out += std::string(k ? "," : "") + "\n" + indent + "  " + jsonString(options[k].key) + ": " +
           jsonString(config.effectiveValue(options[k].key));
  return out + "\n" + indent + "}";
}

std::string decisionMembers(const std::vector<std::pair<std::string, std::string>>& decisions) {
  std::string out = "{";
  for (size_t k = 0; k < decisions.size(); ++k)
    out += std::string(k ? ", " : "") + jsonString(decisions[k].first) + ": " + jsonString(decisions[k].second);
  return out + "}";
}

std::string jsonStrings(const std::vector<std::string>& lines) {
  std::string out = "[";
  for (size_t k = 0; k < lines.size(); ++k) out += std::string(k ? ", " : "") + jsonString(lines[k]);
  return out + "]";
}

}  // namespace

std::vector<std::string> reportColumns() {
  std::vector<std::string> names;
  for (const Column& column : kColumns) names.push_back(column.name);
  return names;
}

double RunReport::qualityMean(size_t column) const {
  const QualityReport quality(qualityMetrics_, hasChroma_);
  std::vector<double> values;
  for (const FrameRecord& record : frames_)
    if (column < record.quality.size()) values.push_back(record.quality[column]);
  return QualityReport::mean(values, quality.decibel(column));
}

RunReport::RunReport(std::string toolName, const Config& config)
    : toolName_(std::move(toolName)),
      config_(config),
      csvPath_(config.getPath("ReportFile")),
      summaryPath_(config.getPath("SummaryFile")) {}

RunReport::~RunReport() = default;

void RunReport::begin(const Scene& scene, const std::vector<std::string>& plan, std::FILE* log) {
  hasChroma_ = scene.settings.textureFormat.chroma != ChromaFormat::Yuv400;
  if (!scene.settings.referenceViewPath.empty()) qualityMetrics_ = scene.settings.qualityMetrics;
  plan_ = plan;
  warnings_ = scene.warnings;
  if (!log) return;
  std::fprintf(log, "%s %s\n\n%s\n%s", toolName_.c_str(), VS_VERSION, config_.effectiveText().c_str(),
               describeCameras(scene).c_str());
  for (const std::string& warning : warnings_) std::fprintf(log, "warning: %s\n", warning.c_str());
  std::fprintf(log, "\nplan:\n");
  for (const std::string& line : plan_) std::fprintf(log, "  %s\n", line.c_str());
}

void RunReport::warn(const std::string& line, std::FILE* log) {
  warnings_.push_back(line);
  if (log) std::fprintf(log, "warning: %s\n", line.c_str());
}

void RunReport::startFrames(std::FILE* log) {
  if (!csvPath_.empty()) {
    std::vector<std::string> inputs;
    if (!config_.configPath().empty()) inputs.push_back(config_.configPath());
    csv_ = std::make_unique<SafeOutputFile>(csvPath_, inputs, "ReportFile");
    std::string header;
    for (const Column& column : kColumns) header += std::string(header.empty() ? "" : ",") + column.name;
    header += QualityReport(qualityMetrics_, hasChroma_).csvHeader();  // QualityMetrics' columns last
    csv_->write(header + "\n");
  }
  if (log) std::fprintf(log, "\n");
}

void RunReport::commit() {
  if (csv_) csv_->commit();
}

void RunReport::addFrame(const FrameRecord& record, std::FILE* log) {
  frames_.push_back(record);
  if (log) {
    std::fprintf(log, "frame %lld: %.4f s", (long long)record.frame, record.times.total());
    if (record.scored)
      std::fprintf(log, "  PSNR Y %s U %s V %s dB", formatPsnr(record.psnr.y).c_str(),
                   formatPsnr(record.psnr.u).c_str(), formatPsnr(record.psnr.v).c_str());
    const QualityReport quality(qualityMetrics_, hasChroma_);
    for (size_t c = 0; c < record.quality.size(); ++c)
      std::fprintf(log, "  %s %s", quality.keys()[c].c_str(), quality.format(c, record.quality[c]).c_str());
    std::fprintf(log, "\n");
    std::fflush(log);
  }
  if (!csv_) return;
  std::string row;
  for (const Column& column : kColumns) {
    if (!row.empty()) row += ",";
    char cell[64];
    const double value = column.value(record);
    if (column.kind == Column::Index) std::snprintf(cell, sizeof cell, "%lld", (long long)record.frame);
    else if (column.kind == Column::Seconds) std::snprintf(cell, sizeof cell, "%.6f", value);
    else std::snprintf(cell, sizeof cell, "%s", record.scored ? formatPsnr(value).c_str() : "");
    row += cell;
  }
  const QualityReport quality(qualityMetrics_, hasChroma_);
  for (size_t c = 0; c < quality.keys().size(); ++c)
    row += "," + (c < record.quality.size() ? quality.format(c, record.quality[c]) : std::string());
  csv_->write(row + "\n");
}

RunSummary RunReport::finish(const std::string& outputPath, std::FILE* log) const {
  const Means means = computeMeans(frames_, hasChroma_);
  RunSummary summary;
  summary.framesWritten = means.frames;
  summary.times = means.sums;
  if (means.scored > 0) {
    summary.meanPsnrY = means.psnr[0].frameMean;
    summary.meanPsnrU = means.psnr[1].frameMean;
    summary.meanPsnrV = means.psnr[2].frameMean;
    summary.meanPsnrYuv = means.psnr[3].frameMean;
  }
  if (!log) return summary;
  std::fprintf(log, "\n%lld frames written to %s\n", (long long)means.frames, outputPath.c_str());
  std::fprintf(log, "seconds per frame: %s\n", describeTimes(means.sums, double(means.frames)).c_str());
  if (means.scored > 0)
    std::fprintf(log, "mean PSNR: Y %s U %s V %s YUV %s dB\n", formatPsnr(summary.meanPsnrY).c_str(),
                 hasChroma_ ? formatPsnr(summary.meanPsnrU).c_str() : "-",
                 hasChroma_ ? formatPsnr(summary.meanPsnrV).c_str() : "-", formatPsnr(summary.meanPsnrYuv).c_str());
  const QualityReport quality(qualityMetrics_, hasChroma_);
  if (means.scored > 0 && !quality.empty()) {
    std::fprintf(log, "mean");
    for (size_t c = 0; c < quality.keys().size(); ++c)
      std::fprintf(log, "  %s %s", quality.keys()[c].c_str(), quality.format(c, qualityMean(c)).c_str());
    std::fprintf(log, "\n");
  }
  return summary;
}

std::string RunReport::summaryJson(int exitStatus, const std::string& error) const {
  const Means means = computeMeans(frames_, hasChroma_);
  const QualityReport quality(qualityMetrics_, hasChroma_);
  // A column's value in a frame or in the means: null where it was not measured.
  auto cell = [&](const Column& column, const FrameRecord& record, bool scored) {
    if (column.kind == Column::Index) return std::to_string(record.frame);
    if (column.kind == Column::Psnr && (!scored || (column.chroma && !hasChroma_))) return std::string("null");
    return jsonValue(column.value(record));
  };
  std::ostringstream out;
  out << "{\n  \"tool\": " << jsonString(toolName_) << ",\n  \"version\": " << jsonString(VS_VERSION)
      << ",\n  \"build\": " << buildJson("  ") << ",\n  \"config_file\": " << (config_.configPath().empty() ? "null" : jsonString(config_.configPath()))
      << ",\n  \"config\": " << configMembers(config_, "  ") << ",\n  \"plan\": " << jsonStrings(plan_)
      << ",\n  \"decisions\": " << decisionMembers(decisions_)
      << ",\n  \"warnings\": " << jsonStrings(warnings_) << ",\n  \"frames\": [";
  for (size_t f = 0; f < frames_.size(); ++f) {
    out << (f ? ",\n    {" : "\n    {");
    for (size_t c = 0; c < std::size(kColumns); ++c)
      out << (c ? ", " : "") << '"' << kColumns[c].name << "\": " << cell(kColumns[c], frames_[f], frames_[f].scored);
    for (size_t c = 0; c < quality.keys().size(); ++c)
      out << ", \"" << quality.keys()[c] << "\": "
          << (c < frames_[f].quality.size() ? jsonValue(frames_[f].quality[c]) : std::string("null"));
    out << "}";
  }
  out << (frames_.empty() ? "]" : "\n  ]") << ",\n  \"frames_written\": " << means.frames << ",\n  \"mean\": {";
  // The means as a frame record: PSNR frame means, seconds per frame.
  FrameRecord mean;
  const double frames = double(means.frames);
  mean.psnr.y = means.psnr[0].frameMean;
  mean.psnr.u = means.psnr[1].frameMean;
  mean.psnr.v = means.psnr[2].frameMean;
  mean.psnr.yuv = means.psnr[3].frameMean;
  const StageTimes& t = means.sums;
  mean.times = StageTimes{t.read / frames, t.depthWarp / frames, t.textureWarp / frames, t.blend / frames,
                          t.holeFill / frames, t.write / frames};
  bool first = true;
  for (const Column& column : kColumns) {
    if (column.kind == Column::Index) continue;
    const bool measured = column.kind == Column::Psnr ? means.scored > 0 : means.frames > 0;
    out << (first ? "" : ", ") << '"' << column.name << "\": " << (measured ? cell(column, mean, true) : "null");
    first = false;
  }
  for (size_t c = 0; c < quality.keys().size(); ++c)
    out << ", \"" << quality.keys()[c] << "\": " << (means.scored > 0 ? jsonValue(qualityMean(c)) : std::string("null"));
  out << "},\n  \"exit_status\": " << exitStatus << ",\n  \"error\": " << (error.empty() ? "null" : jsonString(error))
      << "\n}\n";
  return out.str();
}

void RunReport::writeSummary(int exitStatus, const std::string& error) const {
  if (summaryPath_.empty()) return;
  // After a failure the scene's own check (SummaryFile is no input or output) may not have run.
  for (const OptionSpec& option : config_.table().options()) {
    if (option.key == "SummaryFile" || (option.type != OptionType::Path && option.type != OptionType::PathList))
      continue;
    const std::vector<std::string> paths =
        option.type == OptionType::Path ? std::vector<std::string>{config_.getPath(option.key)} : config_.getList(option.key);
    for (const std::string& path : paths)
      if (!path.empty() && samePath(path, summaryPath_))
        throw InputError(summaryPath_ + ": SummaryFile is also " + option.key + "; the summary was not written");
  }
  std::vector<std::string> inputs;
  if (!config_.configPath().empty()) inputs.push_back(config_.configPath());
  SafeOutputFile file(summaryPath_, inputs, "SummaryFile");
  file.write(summaryJson(exitStatus, error));
  file.commit();
}

RunSummary runReported(RunReport& report, const std::function<RunSummary()>& body) {
  RunSummary summary;
  try {
    summary = body();
  } catch (const std::exception& failure) {
    const std::string message = failure.what();
    try {
      report.writeSummary(1, message);
    } catch (const InputError& e) {
      throw InputError(message + " (and " + e.what() + ")");
    }
    throw;
  }
  report.writeSummary(0, "");
  return summary;
}

std::string configJson(const std::string& toolName, const Config& config, const Scene& scene) {
  const SynthesisSettings& s = scene.settings;
  auto matrix = [](const Mat3& m) {
    std::string out = "[";
    for (int r = 0; r < 3; ++r)
      out += std::string(r ? ", [" : "[") + jsonValue(m[r][0]) + ", " + jsonValue(m[r][1]) + ", " + jsonValue(m[r][2]) + "]";
    return out + "]";
  };
  auto path = [](const std::string& p) { return p.empty() ? std::string("null") : jsonString(p); };
  std::ostringstream out;
  out << "{\n  \"tool\": " << jsonString(toolName) << ",\n  \"version\": " << jsonString(VS_VERSION)
      << ",\n  \"config_file\": " << path(config.configPath()) << ",\n  \"config\": " << configMembers(config, "  ")
      << ",\n  \"scene\": {\n    \"width\": " << s.textureFormat.width << ",\n    \"height\": " << s.textureFormat.height
      << ",\n    \"virtual_width\": " << s.virtualFormat().width << ",\n    \"virtual_height\": " << s.virtualFormat().height
      << ",\n    \"chroma\": " << jsonString(chromaFormatName(s.textureFormat.chroma))
      << ",\n    \"bit_depth\": " << s.textureFormat.bitDepth << ",\n    \"frames\": " << s.frameCount
      << ",\n    \"start_frame\": " << s.startFrame << ",\n    \"output\": " << path(s.outputPath)
      << ",\n    \"reference\": " << path(s.referenceViewPath) << ",\n    \"references\": [";
  for (size_t k = 0; k < s.references.size(); ++k) {
    const ReferenceView& view = s.references[k];
    out << (k ? ",\n" : "\n") << "      {\"label\": " << jsonString(view.label) << ", \"camera\": " << jsonString(view.cameraName)
        << ", \"texture\": " << path(view.texturePath) << ", \"depth\": " << path(view.depthPath)
        << ", \"znear\": " << jsonValue(view.depthRange.znear) << ", \"zfar\": " << jsonValue(view.depthRange.zfar) << "}";
  }
  const Camera& c = scene.virtualCamera;
  out << "\n    ],\n    \"virtual_camera\": {\"name\": " << jsonString(c.name) << ", \"K\": " << matrix(c.K)
      << ", \"R\": " << matrix(c.R) << ", \"centre\": [" << jsonValue(c.t.x) << ", " << jsonValue(c.t.y) << ", "
      << jsonValue(c.t.z) << "]}\n  }\n}\n";
  return out.str();
}

}  // namespace vs
