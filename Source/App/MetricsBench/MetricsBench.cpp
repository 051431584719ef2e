// MetricsBench's work: the generated pair, the timing, the reference software's run and the table
// (doc/metrics.md). The command line is in main.cpp.
#include "MetricsBench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "Common/Error.h"
#include "Common/IvPsnr.h"
#include "Common/Metrics.h"
#include "Common/ParallelRows.h"
#include "Common/Ssim.h"
#include "Common/Yuv.h"

namespace vs {
namespace {

// A smooth random texture (sum of a few sinusoids) plus the same shifted, offset and noisy.
void generatePair(Frame& ref, Frame& test, const FrameFormat& format) {
  ref.reset(format);
  test.reset(format);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> phase(0, 6.283);
  std::normal_distribution<double> noise(0, 2.0);
  const double maxValue = format.maxValue();
  const double p[6] = {phase(random), phase(random), phase(random), phase(random), phase(random), phase(random)};
  for (int c = 0; c < planeCount(format.chroma); ++c) {
    Plane& a = ref.planes[c];
    Plane& b = test.planes[c];
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const double v = 0.5 + 0.2 * std::sin(x * 0.031 + p[0] + c) * std::cos(y * 0.017 + p[1]) +
                         0.15 * std::sin((x + y) * 0.11 + p[2]) + 0.1 * std::sin(x * 0.7 + y * 0.3 + p[3]);
        a.at(x, y) = uint16_t(std::clamp(std::lround(v * maxValue), 0L, long(maxValue)));
      }
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const double v = a.at(std::min(x + 1, a.width - 1), y) + 2.0 * (maxValue / 255.0) + noise(random);
        b.at(x, y) = uint16_t(std::clamp(std::lround(v), 0L, long(maxValue)));
      }
  }
}

// The fastest of `repeat` runs: on a shared machine other work only ever adds time, so the minimum
// is the steadiest figure (the median is printed beside it).
// cpuMs: the process's CPU time (every thread) of the fastest run by that measure; it does not grow
// when other processes share the cores, so it tells the work apart from the waiting.
struct Timing {
  double minMs = 0, medianMs = 0, cpuMs = 0;
};

double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

Timing timeMs(int repeat, const std::function<void()>& body) {
  std::vector<double> ms;
  double cpu = 1e300;
  for (int i = 0; i < repeat; ++i) {
    const double c0 = processCpuMs();
    const auto t0 = std::chrono::steady_clock::now();
    body();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    cpu = std::min(cpu, processCpuMs() - c0);
  }
  std::sort(ms.begin(), ms.end());
  return {ms.front(), ms[ms.size() / 2], cpu};
}

// The reference software's "AvgTime <metric> X ms" and "Average <metric> ..." lines.
struct ReferenceRun {
  std::map<std::string, double> ms;
  std::map<std::string, std::vector<double>> values;
  bool ok = false;
};

ReferenceRun runReference(const MetricsBenchOptions& options, const std::string& ref, const std::string& test,
                          int threads, const std::string& metrics, bool erp) {
  ReferenceRun run;
  const FrameFormat& f = options.format;
  const char* cf = f.chroma == ChromaFormat::Yuv444 ? "444" : "420";
  const std::string out = "/tmp/MetricsBench_reference.txt";
  const std::string command = "'" + options.referenceBinary + "' -i0 '" + ref + "' -i1 '" + test + "' -ps " +
                              std::to_string(f.width) + "x" + std::to_string(f.height) + " -bd " +
                              std::to_string(f.bitDepth) + " -cf " + cf +
                              " -ml \"" + metrics + "\"" + (erp ? " -erp" : "") + " -nf 1 -v 3 -nth " +
                              std::to_string(threads) + " > " + out + " 2>&1";
  if (std::system(command.c_str()) != 0) return run;
  FILE* file = std::fopen(out.c_str(), "r");
  if (!file) return run;
  char line[1024];
  while (std::fgets(line, sizeof line, file)) {
    char name[64];
    double value = 0;
    if (std::sscanf(line, "AvgTime %63s %lf ms", name, &value) == 2) run.ms[name] = value;
    double v[3];
    const int got = std::sscanf(line, "Average %63s Y:Cb:Cr %lf dB %lf dB %lf", name, &v[0], &v[1], &v[2]);
    if (got == 4) run.values[name] = {v[0], v[1], v[2]};
    else if (std::sscanf(line, "Average %63s Y:Cb:Cr %lf %lf %lf", name, &v[0], &v[1], &v[2]) == 4)
      run.values[name] = {v[0], v[1], v[2]};
    else if (std::sscanf(line, "Average IVPSNR %lf", &v[0]) == 1)
      run.values["IVPSNR"] = {v[0]};
  }
  std::fclose(file);
  run.ok = true;
  return run;
}

// The pair: generated (and written to /tmp, where the reference software reads it) or the first
// frame of each file. Returns the paths the reference software is to read.
std::pair<std::string, std::string> loadPair(const MetricsBenchOptions& options, Frame& ref, Frame& test) {
  if (!options.refPath.empty()) {
    YuvReader(options.refPath, options.format).read(0, ref);
    YuvReader(options.testPath, options.format).read(0, test);
    return {options.refPath, options.testPath};
  }
  generatePair(ref, test, options.format);
  const std::string refPath = "/tmp/MetricsBench_ref.yuv", testPath = "/tmp/MetricsBench_test.yuv";
  for (const auto& [path, frame] : {std::pair(refPath, &ref), std::pair(testPath, &test)}) {
    YuvWriter writer(path, options.format);  // the reference software reads the pair from files
    writer.append(*frame);
    writer.commit();
  }
  return {refPath, testPath};
}

// One metric's row: our times and values, and its name in the reference software's output.
struct Row {
  const char* name;
  const char* referenceName;
  Timing ms;
  std::vector<double> ours;
};

std::vector<Row> timeOurs(const MetricsBenchOptions& options, const Frame& ref, const Frame& test) {
  IvPsnrOptions iv;
  iv.threads = options.threads;
  IvPsnrScratch ivScratch;  // kept over the runs, as a caller scoring frame after frame keeps it
  SsimOptions so;
  so.threads = options.threads;
  FramePsnr psnr;
  IvPsnrResult ivr;
  FrameQuality ws, ss, ms;
  std::vector<Row> rows;
  rows.push_back({"PSNR", "PSNR", timeMs(options.repeat, [&] { psnr = framePsnr(ref, test); }), {}});
  rows.back().ours = {psnr.y, psnr.u, psnr.v};
  rows.push_back({"WS-PSNR", "WSPSNR", timeMs(options.repeat, [&] { ws = wsPsnr(ref, test); }), {}});
  rows.back().ours = {ws.plane[0], ws.plane[1], ws.plane[2]};
  rows.push_back({"IV-PSNR", "IVPSNR", timeMs(options.repeat, [&] { ivr = ivPsnr(ref, test, iv, ivScratch); }), {}});
  rows.back().ours = {ivr.ivpsnr};
  rows.push_back({"SSIM", "SSIM", timeMs(options.repeat, [&] { ss = ssim(ref, test, so); }), {}});
  rows.back().ours = {ss.plane[0], ss.plane[1], ss.plane[2]};
  rows.push_back({"MS-SSIM", "MSSSIM", timeMs(options.repeat, [&] { ms = msSsim(ref, test, so); }), {}});
  rows.back().ours = {ms.plane[0], ms.plane[1], ms.plane[2]};
  return rows;
}

// The reference software with 1 thread (`single`) and with its automatic count (`multi`).
void timeReference(const MetricsBenchOptions& options, const std::string& refPath, const std::string& testPath,
                   ReferenceRun& single, ReferenceRun& multi) {
  // WS-PSNR needs -erp, which also weights the reference's IV-PSNR rows: two runs.
  const std::string metrics = "PSNR, IVPSNR, SSIM, MSSSIM";
  single = runReference(options, refPath, testPath, 0, metrics, false);
  multi = runReference(options, refPath, testPath, -2, metrics, false);
  ReferenceRun single2 = runReference(options, refPath, testPath, 0, "WSPSNR", true);
  ReferenceRun multi2 = runReference(options, refPath, testPath, -2, "WSPSNR", true);
  single.ok = single.ok && single2.ok;
  multi.ok = multi.ok && multi2.ok;
  single.ms["WSPSNR"] = single2.ms["WSPSNR"];
  multi.ms["WSPSNR"] = multi2.ms["WSPSNR"];
  single.values["WSPSNR"] = single2.values["WSPSNR"];
  if (!single.ok || !multi.ok)
    throw InputError(options.referenceBinary + ": the reference software did not run (see "
                     "/tmp/MetricsBench_reference.txt)");
}

void printTable(const std::vector<Row>& rows, bool withReference, ReferenceRun& single, ReferenceRun& multi) {
  std::printf("%-8s %9s %9s %9s", "metric", "ours min", "ours med", "ours cpu");
  if (withReference) std::printf(" %12s %12s", "ref 1thr ms", "ref auto ms");
  std::printf("  %-40s%s\n", "ours (Y U V or one value)", withReference ? "  reference" : "");
  for (const Row& row : rows) {
    std::printf("%-8s %9.2f %9.2f %9.2f", row.name, row.ms.minMs, row.ms.medianMs, row.ms.cpuMs);
    if (withReference) {
      // The reference times IV-PSNR without its colour offset step (GCD), which it reports apart.
      double t1 = single.ms.count(row.referenceName) ? single.ms[row.referenceName] : NAN;
      double tm = multi.ms.count(row.referenceName) ? multi.ms[row.referenceName] : NAN;
      if (std::string(row.referenceName) == "IVPSNR") {
        t1 += single.ms.count("GCD") ? single.ms["GCD"] : 0;
        tm += multi.ms.count("GCD") ? multi.ms["GCD"] : 0;
      }
      std::printf(" %12.2f %12.2f", t1, tm);
    }
    std::string ours;
    for (double v : row.ours) ours += formatPsnr(v, 6) + " ";
    std::printf("  %-40s", ours.c_str());
    if (withReference && single.values.count(row.referenceName)) {
      std::string theirs;
      for (double v : single.values[row.referenceName]) theirs += formatPsnr(v, 6) + " ";
      std::printf("  %s", theirs.c_str());
    }
    std::printf("\n");
  }
  if (withReference)
    std::printf("(reference WS-PSNR with -erp; its PSNR/WS-PSNR/IV-PSNR write 10 log10(W H peak^2) where ours "
                "is inf)\n");
}

}  // namespace

int runMetricsBench(const MetricsBenchOptions& options) {
  Frame ref, test;
  const auto [refPath, testPath] = loadPair(options, ref, test);
  const FrameFormat& f = options.format;
  std::printf("MetricsBench %s: %dx%d %s %d-bit, %s, threads %d, %d runs (ms: fastest, median, least CPU time of all threads)\n", VS_VERSION, f.width,
              f.height, chromaFormatName(f.chroma), f.bitDepth,
              options.refPath.empty() ? "generated pair" : (refPath + " vs " + testPath).c_str(),
              metricThreads(options.threads), options.repeat);
  const std::vector<Row> rows = timeOurs(options, ref, test);
  ReferenceRun single, multi;
  const bool withReference = !options.referenceBinary.empty();
  if (withReference) timeReference(options, refPath, testPath, single, multi);
  printTable(rows, withReference, single, multi);
  return 0;
}

}  // namespace vs
