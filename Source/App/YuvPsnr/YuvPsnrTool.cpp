// YuvPsnr: PSNR, and on request IV-PSNR, WS-PSNR, SSIM and MS-SSIM (doc/metrics.md), of a test YUV
// file against a reference, frame by frame and averaged (doc/formats-yuv.md). Exit codes: 0 done,
// 1 file error, 2 bad arguments. The command line goes through the shared front (Common/CommandLine.h):
// the option table below, every problem at once, --help from the table, --version, one catch.
#include "YuvPsnrTool.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/IvPsnr.h"
#include "Common/Json.h"
#include "Common/Metrics.h"
#include "Common/Ssim.h"
#include "Common/Yuv.h"

namespace {

constexpr int64_t kMaxInt64 = std::numeric_limits<int64_t>::max();

enum Metric { kPsnr, kIvPsnr, kWsPsnr, kSsim, kMsSsim, kMetricCount };
const char* const kMetricNames[kMetricCount] = {"psnr", "ivpsnr", "wspsnr", "ssim", "msssim"};

struct PsnrOptions {
  std::string referencePath;  // first positional argument
  std::string testPath;       // second positional argument
  vs::FrameFormat format;     // WIDTH HEIGHT (or WxH) positional, --bitdepth, --chroma
  int64_t startFrame = 0;     // --start: first frame compared, in both files
  int64_t frameCount = -1;    // --frames; -1: every whole frame of the shorter file from startFrame on
  bool metrics[kMetricCount] = {true, false, false, false, false};  // --metrics
  vs::IvPsnrOptions ivpsnr;   // --search-range, --unnoticeable, --search-weights, --average-weights, --threads
  vs::SsimOptions ssim;       // --ssim-convention, --average-weights, --threads
  double latitudeRange = 180; // --latitude-range: WS-PSNR's vertical field of view in degrees
  std::string csvPath;        // --csv: per-frame values and means as CSV
  std::string jsonPath;       // --json: the same as JSON
};

// "a:b:c" (or one value for all three) of numbers in [minValue, maxValue].
bool parseTriple(const std::string& text, double minValue, double maxValue, bool integers, double out[3]) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, ':')) parts.push_back(part);
  if (text.empty() || text.back() == ':' || (parts.size() != 1 && parts.size() != 3)) return false;
  for (size_t i = 0; i < parts.size(); ++i) {
    double value = 0;
    const char* end = parts[i].data() + parts[i].size();
    const auto [ptr, ec] = std::from_chars(parts[i].data(), end, value);
    if (ec != std::errc() || ptr != end || parts[i].empty() || !(value >= minValue && value <= maxValue) ||
        (integers && value != std::floor(value)))
      return false;
    out[i] = value;
  }
  if (parts.size() == 1) out[1] = out[2] = out[0];
  return true;
}

bool parseMetrics(const std::string& text, bool metrics[kMetricCount]) {
  bool chosen[kMetricCount] = {};
  std::stringstream stream(text);
  std::string name;
  bool any = false;
  while (std::getline(stream, name, ',')) {
    if (name == "all") {
      for (bool& c : chosen) c = true;
      any = true;
      continue;
    }
    int found = -1;
    for (int m = 0; m < kMetricCount; ++m)
      if (name == kMetricNames[m]) found = m;
    if (found < 0) return false;
    chosen[found] = true;
    any = true;
  }
  if (!any || text.back() == ',') return false;
  for (int m = 0; m < kMetricCount; ++m) metrics[m] = chosen[m];
  return true;
}

// Plane weights Y:U:V, integers in 0..1000, not all 0 (and, for the averages, Y > 0).
bool parseWeights(const std::string& text, bool lumaMustCount, double weights[3]) {
  return parseTriple(text, 0, 1000, true, weights) && weights[0] + weights[1] + weights[2] > 0 &&
         (!lumaMustCount || weights[0] > 0);
}

bool parseLatitudeRange(const std::string& text, double& degrees) {
  double triple[3] = {0, 0, 0};
  if (text.find(':') != std::string::npos || !parseTriple(text, 1e-9, 180, false, triple)) return false;
  degrees = triple[0];
  return true;
}

bool parseSsimConvention(const std::string& text, vs::SsimConvention& convention) {
  if (text == "qmiv") convention = vs::SsimConvention::Qmiv;
  else if (text == "wang") convention = vs::SsimConvention::Wang;
  else return false;
  return true;
}

// A value check from a parse function: `expected` says what the value must be.
vs::ValueCheck valueCheck(const std::function<bool(const std::string&)>& parses, const std::string& expected) {
  return [=](const std::vector<std::string>& values) -> std::string {
    for (const std::string& value : values)
      if (!parses(value)) return "expected " + expected + ", got '" + value + "'";
    return "";
  };
}

// An option's meaning, then its default and range on a line of their own under it.
std::string help(const std::string& meaning, const std::string& defaultText, const std::string& range) {
  return meaning + "\n" + std::string(28, ' ') + "default " + defaultText + ", range " + range;
}

std::vector<vs::CommandOption> psnrOptionTable() {
  return {
      {"--frames", {"N"}, help("frames to compare", "all whole frames of the shorter file from --start on", "1 and up"),
       vs::integerValues(1, kMaxInt64)},
      {"--start", {"S"}, help("first frame compared (0-based), the same in both files", "0", "0 and up"),
       vs::integerValues(0, kMaxInt64)},
      {"--bitdepth", {"B"}, help("bits per sample; 9..16 are little-endian 16-bit words in the file", "8", "8..16"),
       vs::integerValues(8, 16)},
      {"--chroma", {"F"}, help("chroma format; 400 is luma only", "420", "420|444|400"), vs::chromaFormatValue()},
      {"--metrics", {"LIST"},
       help("metrics to compute, comma separated, in this order in the table", "psnr",
            "psnr,ivpsnr,wspsnr,ssim,msssim or all"),
       valueCheck([](const std::string& v) {
                    bool metrics[kMetricCount];
                    return parseMetrics(v, metrics);
                  },
                  "a comma-separated list of psnr, ivpsnr, wspsnr, ssim, msssim (or all)")},
      {"--search-range", {"R"}, help("IV-PSNR: candidates within +-R samples (a (2R+1)^2 window)", "2", "0..16"),
       vs::integerValues(0, 16)},
      {"--unnoticeable", {"F[:F:F]"},
       help("IV-PSNR: largest global colour offset corrected, as a fraction of 2^B-1, per plane; 0 = off", "0.01",
            "0..1"),
       valueCheck([](const std::string& v) {
                    double fractions[3];
                    return parseTriple(v, 0, 1, false, fractions);
                  },
                  "F or F:F:F with each F in 0..1")},
      {"--search-weights", {"Y:U:V"}, help("IV-PSNR: plane weights in the search", "4:1:1", "0..1000 each"),
       valueCheck([](const std::string& v) {
                    double weights[3];
                    return parseWeights(v, false, weights);
                  },
                  "Y:U:V of integers in 0..1000, not all 0")},
      {"--average-weights", {"Y:U:V"},
       help("IV-PSNR, WS-PSNR, SSIM, MS-SSIM: plane weights of the YUV value (PSNR keeps 6:1:1)", "4:1:1",
            "0..1000 each"),
       valueCheck([](const std::string& v) {
                    double weights[3];
                    return parseWeights(v, true, weights);
                  },
                  "Y:U:V of integers in 0..1000, not all 0, Y > 0")},
      {"--ssim-convention", {"C"},
       help("SSIM, MS-SSIM: qmiv = IV-PSNR software 7.1's window and averaging, wang = the papers' (doc/metrics.md)",
            "qmiv", "qmiv|wang"),
       valueCheck([](const std::string& v) {
                    vs::SsimConvention convention;
                    return parseSsimConvention(v, convention);
                  },
                  "one of qmiv, wang")},
      {"--latitude-range", {"DEG"}, help("WS-PSNR: degrees of latitude the picture covers", "180", "(0, 180]"),
       valueCheck([](const std::string& v) {
                    double degrees = 0;
                    return parseLatitudeRange(v, degrees);
                  },
                  "a number of degrees in (0, 180]")},
      {"--threads", {"T"}, help("threads for IV-PSNR, SSIM, MS-SSIM", "0 (all hardware threads)", "0..256"),
       vs::integerValues(0, 256)},
      {"--csv", {"FILE"}, help("also write the per-frame values and the means as CSV", "none", "a path")},
      {"--json", {"FILE"}, help("also write the per-frame values and the means as JSON", "none", "a path")},
  };
}

// WIDTH HEIGHT (or WIDTHxHEIGHT) from the positional arguments; the problems found, "; " between them.
std::string readSize(const std::vector<std::string>& positional, vs::FrameFormat& format) {
  const std::string range = "1.." + std::to_string(vs::kMaxFrameSide);
  if (positional.size() == 3 && positional[2].find('x') != std::string::npos)
    return vs::parseFrameSize(positional[2], format.width, format.height)
               ? ""
               : "size '" + positional[2] + "' is not WIDTHxHEIGHT with both in " + range;
  if (positional.size() != 4)
    return "expected 4 arguments REF.yuv TEST.yuv WIDTH HEIGHT (or 3: REF.yuv TEST.yuv WxH), got " +
           std::to_string(positional.size());
  std::string problems;
  const char* names[2] = {"WIDTH", "HEIGHT"};
  int* sides[2] = {&format.width, &format.height};
  for (int k = 0; k < 2; ++k)
    if (!vs::parseFrameSide(positional[2 + k], *sides[k]))
      problems += std::string(problems.empty() ? "" : "; ") + names[k] + " '" + positional[2 + k] +
                  "' is not an integer in " + range;
  return problems;
}

// The run's options from the parsed command line (every value was checked by the table).
PsnrOptions psnrOptions(const vs::CommandLine& line) {
  PsnrOptions options;
  options.referencePath = line.positional[0];
  options.testPath = line.positional[1];
  readSize(line.positional, options.format);
  options.frameCount = line.integer("--frames", options.frameCount);
  options.startFrame = line.integer("--start", options.startFrame);
  options.format.bitDepth = int(line.integer("--bitdepth", options.format.bitDepth));
  if (line.has("--chroma")) vs::parseChromaFormat(line.text("--chroma"), options.format.chroma);
  if (line.has("--metrics")) parseMetrics(line.text("--metrics"), options.metrics);
  options.ivpsnr.searchRange = int(line.integer("--search-range", options.ivpsnr.searchRange));
  double triple[3] = {0, 0, 0};
  if (line.has("--unnoticeable") && parseTriple(line.text("--unnoticeable"), 0, 1, false, triple))
    for (int p = 0; p < 3; ++p) options.ivpsnr.unnoticeable[p] = triple[p];
  if (line.has("--search-weights") && parseWeights(line.text("--search-weights"), false, triple))
    for (int p = 0; p < 3; ++p) options.ivpsnr.searchWeights[p] = int(triple[p]);
  if (line.has("--average-weights") && parseWeights(line.text("--average-weights"), true, triple))
    for (int p = 0; p < 3; ++p) options.ivpsnr.averageWeights[p] = options.ssim.averageWeights[p] = int(triple[p]);
  if (line.has("--ssim-convention")) parseSsimConvention(line.text("--ssim-convention"), options.ssim.convention);
  if (line.has("--latitude-range")) parseLatitudeRange(line.text("--latitude-range"), options.latitudeRange);
  if (line.has("--threads")) options.ivpsnr.threads = options.ssim.threads = int(line.integer("--threads", 0));
  options.csvPath = line.text("--csv");
  options.jsonPath = line.text("--json");
  return options;
}

void noteTrailingBytes(const vs::YuvReader& reader) {
  if (reader.trailingBytes() > 0)
    std::fprintf(stderr, "note: %s ends with a partial frame of %llu bytes (ignored)\n", reader.path().c_str(),
                 static_cast<unsigned long long>(reader.trailingBytes()));
}

// The frames to compare, checked against what both files hold.
int64_t framesToCompare(const PsnrOptions& options, const vs::YuvReader& ref, const vs::YuvReader& test) {
  const vs::YuvReader& shorter = ref.frameCount() <= test.frameCount() ? ref : test;
  const int64_t available = shorter.frameCount();
  if (ref.frameCount() != test.frameCount())
    std::fprintf(stderr, "note: %s holds %lld whole frames, %s holds %lld\n", ref.path().c_str(),
                 static_cast<long long>(ref.frameCount()), test.path().c_str(),
                 static_cast<long long>(test.frameCount()));
  if (options.startFrame >= available)
    throw vs::InputError(shorter.path() + ": --start " + std::to_string(options.startFrame) +
                         " but the file holds " + std::to_string(available) + " whole frames of " +
                         std::to_string(options.format.frameBytes()) + " bytes");
  const int64_t count = options.frameCount < 0 ? available - options.startFrame : options.frameCount;
  if (count > available - options.startFrame)
    throw vs::InputError(shorter.path() + ": frames " + std::to_string(options.startFrame) + ".." +
                         std::to_string(options.startFrame + count - 1) + " requested but the file holds " +
                         std::to_string(available) + " whole frames");
  return count;
}

void printMean(const char* plane, const vs::PsnrAccumulator::Mean& mean, int64_t frames) {
  std::string note;
  if (mean.identicalFrames == frames)
    note = "  (all frames identical)";
  else if (mean.identicalFrames > 0)
    note = "  (" + std::to_string(mean.identicalFrames) + " identical frame" +
           (mean.identicalFrames > 1 ? "s" : "") + " excluded from frame-mean)";
  std::printf("  %-5s %12s %12s%s\n", plane, vs::formatPsnr(mean.frameMean).c_str(),
              vs::formatPsnr(mean.psnrOfMeanMse).c_str(), note.c_str());
}

// One printed value per frame: a metric's plane (or its one value), in dB or as an index.
struct Column {
  std::string name;   // "Y-PSNR", "IV-PSNR", "YUV-SSIM", ...
  std::string key;    // CSV and JSON name: "psnr_y", "ivpsnr", "ssim_yuv", ...
  bool decibel;       // dB: the mean leaves +inf (identical) frames out; else a plain mean
  double sum = 0;     // of the finite values (dB) or of all values (index)
  int64_t finite = 0;
  int64_t identical = 0;
  double mean(int64_t frames) const {
    if (!decibel) return sum / double(frames);
    return finite > 0 ? sum / double(finite) : std::numeric_limits<double>::infinity();
  }
};

std::string formatValue(const Column& column, double value) {
  return column.decibel ? vs::formatPsnr(value) : vs::formatPsnr(value, 6);
}

// CSV: shortest text that reads back to the same double, inf and nan as words. JSON: the project's
// numbers (Infinity for identical planes, as Python's json reads it), null for an undefined value.
std::string exactNumber(double value, bool json) {
  if (std::isnan(value)) return json ? "null" : "nan";
  if (json) return vs::jsonNumber(value);
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::vector<Column> makeColumns(const PsnrOptions& options, bool hasChroma) {
  std::vector<Column> columns;
  const char* planes[4] = {"Y", "U", "V", "YUV"};
  const char* keys[4] = {"y", "u", "v", "yuv"};
  struct Kind {
    Metric metric;
    const char* title;
    const char* key;
    bool decibel;
  };
  const Kind kinds[] = {{kPsnr, "PSNR", "psnr", true},
                        {kIvPsnr, "IV-PSNR", "ivpsnr", true},
                        {kWsPsnr, "WSPSNR", "wspsnr", true},
                        {kSsim, "SSIM", "ssim", false},
                        {kMsSsim, "MSSSIM", "msssim", false}};
  for (const Kind& kind : kinds) {
    if (!options.metrics[kind.metric]) continue;
    if (kind.metric == kIvPsnr) {
      columns.push_back({kind.title, kind.key, true});
      continue;
    }
    for (int p = 0; p < (hasChroma ? 4 : 1); ++p)
      columns.push_back({std::string(planes[p]) + "-" + kind.title, std::string(kind.key) + "_" + keys[p], kind.decibel});
  }
  return columns;
}

// The values of one frame, in the order of makeColumns().
std::vector<double> frameValues(const PsnrOptions& options, bool hasChroma, const vs::Frame& refFrame,
                                const vs::Frame& testFrame, vs::IvPsnrScratch& ivpsnrScratch, vs::FramePsnr& psnr) {
  std::vector<double> values;
  auto addPlanes = [&](const vs::FrameQuality& quality) {
    for (int p = 0; p < (hasChroma ? 3 : 1); ++p) values.push_back(quality.plane[p]);
    if (hasChroma) values.push_back(quality.yuv);
  };
  psnr = vs::framePsnr(refFrame, testFrame);
  if (options.metrics[kPsnr]) {
    values.push_back(psnr.y);
    if (hasChroma) values.insert(values.end(), {psnr.u, psnr.v, psnr.yuv});
  }
  if (options.metrics[kIvPsnr]) values.push_back(vs::ivPsnr(refFrame, testFrame, options.ivpsnr, ivpsnrScratch).ivpsnr);
  if (options.metrics[kWsPsnr])
    addPlanes(vs::wsPsnr(refFrame, testFrame, options.latitudeRange, options.ivpsnr.averageWeights));
  if (options.metrics[kSsim]) addPlanes(vs::ssim(refFrame, testFrame, options.ssim));
  if (options.metrics[kMsSsim]) addPlanes(vs::msSsim(refFrame, testFrame, options.ssim));
  return values;
}

void writeReports(const PsnrOptions& options, const std::vector<Column>& columns,
                  const std::vector<int64_t>& frameIndices, const std::vector<std::vector<double>>& rows) {
  const int64_t frames = int64_t(rows.size());
  if (!options.csvPath.empty()) {
    std::ofstream csv(options.csvPath, std::ios::trunc);
    if (!csv) throw vs::InputError(options.csvPath + ": cannot create the CSV file");
    csv << "frame";
    for (const Column& column : columns) csv << "," << column.key;
    csv << "\n";
    for (size_t f = 0; f < rows.size(); ++f) {
      csv << frameIndices[f];
      for (double value : rows[f]) csv << "," << exactNumber(value, false);
      csv << "\n";
    }
    csv << "mean";
    for (const Column& column : columns) csv << "," << exactNumber(column.mean(frames), false);
    csv << "\n";
    if (!csv.flush()) throw vs::InputError(options.csvPath + ": write failed");
  }
  if (!options.jsonPath.empty()) {
    std::ofstream json(options.jsonPath, std::ios::trunc);
    if (!json) throw vs::InputError(options.jsonPath + ": cannot create the JSON file");
    const vs::FrameFormat& f = options.format;
    json << "{\n  \"reference\": " << vs::jsonString(options.referencePath) << ",\n  \"test\": "
         << vs::jsonString(options.testPath) << ",\n  \"width\": " << f.width << ", \"height\": " << f.height
         << ", \"bitDepth\": " << f.bitDepth << ", \"chroma\": \"" << vs::chromaFormatName(f.chroma) << "\",\n"
         << "  \"frames\": [\n";
    for (size_t r = 0; r < rows.size(); ++r) {
      json << "    {\"frame\": " << frameIndices[r];
      for (size_t c = 0; c < columns.size(); ++c)
        json << ", " << vs::jsonString(columns[c].key) << ": " << exactNumber(rows[r][c], true);
      json << "}" << (r + 1 < rows.size() ? "," : "") << "\n";
    }
    json << "  ],\n  \"mean\": {";
    for (size_t c = 0; c < columns.size(); ++c)
      json << (c ? ", " : "") << vs::jsonString(columns[c].key) << ": " << exactNumber(columns[c].mean(frames), true);
    json << "}\n}\n";
    if (!json.flush()) throw vs::InputError(options.jsonPath + ": write failed");
  }
}

// The means after the table: PSNR's two ways (frame-mean, mean-MSE), then every other column's.
void printMeans(const PsnrOptions& options, bool hasChroma, const vs::PsnrAccumulator& accumulator,
                const std::vector<Column>& columns, int64_t count) {
  if (options.metrics[kPsnr]) {
    std::printf("mean over %lld frames [dB]\n  %-5s %12s %12s\n", static_cast<long long>(count), "plane",
                "frame-mean", "mean-MSE");
    printMean("Y", accumulator.y(), count);
    if (hasChroma) {
      printMean("U", accumulator.u(), count);
      printMean("V", accumulator.v(), count);
      printMean("YUV", accumulator.yuv(), count);
    }
  }
  bool others = false;
  for (const Column& column : columns) {
    if (column.key.rfind("psnr", 0) == 0) continue;
    if (!others) std::printf("mean of the per-frame values over %lld frames\n", static_cast<long long>(count));
    others = true;
    std::string note;
    if (column.decibel && column.identical > 0)
      note = "  (" + std::to_string(column.identical) + " identical frame" + (column.identical > 1 ? "s" : "") +
             (column.identical == count ? ", all)" : " left out)");
    std::printf("  %-11s %12s%s\n", column.name.c_str(), formatValue(column, column.mean(count)).c_str(),
                note.c_str());
  }
}

// Prints one frame's row and adds its values to the columns' sums.
void printFrame(int64_t frameIndex, const std::vector<double>& values, std::vector<Column>& columns) {
  std::printf("%7lld", static_cast<long long>(frameIndex));
  for (size_t c = 0; c < columns.size(); ++c) {
    Column& column = columns[c];
    std::printf(" %10s", formatValue(column, values[c]).c_str());
    if (column.decibel && std::isinf(values[c])) {
      ++column.identical;
    } else {
      column.sum += values[c];
      ++column.finite;
    }
  }
  std::printf("\n");
}

int run(const PsnrOptions& options) {
  vs::YuvReader ref(options.referencePath, options.format);
  vs::YuvReader test(options.testPath, options.format);
  noteTrailingBytes(ref);
  noteTrailingBytes(test);
  const int64_t count = framesToCompare(options, ref, test);
  const vs::FrameFormat& format = options.format;
  const bool hasChroma = format.chroma != vs::ChromaFormat::Yuv400;
  std::vector<Column> columns = makeColumns(options, hasChroma);
  // A report that cannot be written is found before the work, not after it.
  for (const std::string& path : {options.csvPath, options.jsonPath})
    if (!path.empty() && !std::ofstream(path, std::ios::trunc))
      throw vs::InputError(path + ": cannot create the report file");

  std::printf("YuvPsnr %s\nreference  %s\ntest       %s\n", VS_VERSION, ref.path().c_str(), test.path().c_str());
  std::printf("format     %dx%d %s %d-bit, frames %lld..%lld (%lld frames)\n", format.width, format.height,
              vs::chromaFormatName(format.chroma), format.bitDepth, static_cast<long long>(options.startFrame),
              static_cast<long long>(options.startFrame + count - 1), static_cast<long long>(count));
  std::printf("%7s", "frame");
  for (const Column& column : columns) std::printf(" %10s", column.name.c_str());
  std::printf("\n");

  vs::Frame refFrame, testFrame;
  vs::IvPsnrScratch ivpsnrScratch;  // kept over the frames
  vs::PsnrAccumulator accumulator(format.bitDepth, hasChroma);
  std::vector<std::vector<double>> rows;
  std::vector<int64_t> frameIndices;
  for (int64_t frameIndex = options.startFrame; frameIndex < options.startFrame + count; ++frameIndex) {
    ref.read(frameIndex, refFrame);
    test.read(frameIndex, testFrame);
    vs::FramePsnr psnr;
    const std::vector<double> values = frameValues(options, hasChroma, refFrame, testFrame, ivpsnrScratch, psnr);
    accumulator.add(psnr);
    printFrame(frameIndex, values, columns);
    if (!options.csvPath.empty() || !options.jsonPath.empty()) {
      rows.push_back(values);
      frameIndices.push_back(frameIndex);
    }
  }
  printMeans(options, hasChroma, accumulator, columns, count);
  writeReports(options, columns, frameIndices, rows);
  return 0;
}

}  // namespace

vs::CommandLineTool yuvPsnrTool() {
  vs::CommandLineTool tool;
  tool.name = "YuvPsnr";
  tool.description =
      "PSNR (and on request IV-PSNR, WS-PSNR, SSIM, MS-SSIM) of a test YUV file against a\n"
      "reference, per frame and averaged.\n\n"
      "  REF.yuv, TEST.yuv  planar YUV files of the same format, no header\n"
      "  WIDTH, HEIGHT      luma size in pixels, 1..65536 (or WIDTHxHEIGHT as one argument)";
  tool.synopsis = {"REF.yuv TEST.yuv WIDTH HEIGHT [options]", "REF.yuv TEST.yuv WIDTHxHEIGHT [options]"};
  tool.options = psnrOptionTable();
  tool.notes =
      "Options also as --name=value.\n\n"
      "output: one line per frame (index, PSNR of Y, U, V and YUV in dB; identical planes print inf),\n"
      "then the means of each plane two ways:\n"
      "  frame-mean  mean of the per-frame PSNRs over frames with a finite PSNR; identical frames are\n"
      "              left out and counted, and it is inf only when every frame is identical\n"
      "  mean-MSE    PSNR of the mean of the per-frame MSEs\n"
      "PSNR = 10 log10((2^B - 1)^2 / MSE); YUV = (6 Y + U + V) / 8, inf when any plane is inf.\n"
      "With --chroma 400 only Y is printed.\n"
      "Other metrics (--metrics) add their columns: IV-PSNR one value in dB; WS-PSNR, SSIM, MS-SSIM Y, U,\n"
      "V and YUV (weighted by --average-weights); their means are the means of the per-frame values\n"
      "(IV-PSNR and WS-PSNR leave identical frames, inf, out and count them). Definitions, defaults and\n"
      "the agreement with the IV-PSNR reference software: doc/metrics.md.\n\n"
      "Exit codes: 0 done, 1 file error (missing, short, bad samples), 2 bad arguments.";
  // No argument at all is a problem with the positional arguments (exit 2), named as such.
  tool.runsWithoutArguments = true;
  tool.checkPositional = [](const vs::CommandLine& line) {
    vs::FrameFormat format;
    return readSize(line.positional, format);
  };
  tool.run = [](const vs::CommandLine& line) { return run(psnrOptions(line)); };
  return tool;
}
