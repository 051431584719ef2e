// MetricsBench: milliseconds per frame of each quality metric (PSNR, IV-PSNR, WS-PSNR, SSIM, MS-SSIM),
// on a generated 1920x1080 4:2:0 pair or on the first frame of two YUV files, and, given the IV-PSNR
// reference software's binary, its time and values on the same frames, side by side (doc/metrics.md).
// The bench is in MetricsBench.cpp. Exit codes: 0 done, 1 file error, 2 bad arguments.
#include <string>

#include "Common/CommandLine.h"
#include "MetricsBench.h"

int main(int argc, char** argv) {
  vs::CommandLineTool tool;
  tool.name = "MetricsBench";
  tool.description =
      "milliseconds per frame of each quality metric, ours and (optionally) the\n"
      "IV-PSNR reference software's, with both values. Without files: a generated 1920x1080 4:2:0 8-bit pair\n"
      "(a smooth texture and the same shifted by one sample, offset by 2 levels and noisy), written to /tmp\n"
      "for the reference software.";
  tool.synopsis = {"[REF.yuv TEST.yuv WxH] [options]"};
  tool.options = {
      {"--bitdepth", {"B"}, "8..16 (default 8)", vs::integerValues(8, 16)},
      {"--chroma", {"F"}, "420|444|400 (default 420)", vs::chromaFormatValue()},
      {"--repeat", {"N"}, "timed runs per metric; the fastest and the median are printed (default 5)",
       vs::integerValues(1, 1000)},
      {"--threads", {"T"}, "threads per metric, 0 = all hardware threads (default 0)", vs::integerValues(0, 256)},
      {"--reference", {"BIN"},
       "IV-PSNR reference software's IVPSNR binary: its times (1 thread, default) and values"},
  };
  tool.notes = "Exit codes: 0 done, 1 file error, 2 bad arguments.";
  tool.runsWithoutArguments = true;
  tool.checkPositional = [](const vs::CommandLine& line) -> std::string {
    int width = 0, height = 0;
    if (line.positional.empty()) return "";
    if (line.positional.size() != 3)
      return "expected REF.yuv TEST.yuv WxH or no arguments, got " + std::to_string(line.positional.size());
    return vs::parseFrameSize(line.positional[2], width, height) ? ""
                                                                 : "size '" + line.positional[2] + "' is not WIDTHxHEIGHT";
  };
  tool.run = [](const vs::CommandLine& line) {
    vs::MetricsBenchOptions options;
    options.format.width = 1920;
    options.format.height = 1080;
    if (line.positional.size() == 3) {
      options.refPath = line.positional[0];
      options.testPath = line.positional[1];
      vs::parseFrameSize(line.positional[2], options.format.width, options.format.height);
    }
    options.format.bitDepth = int(line.integer("--bitdepth", options.format.bitDepth));
    if (line.has("--chroma")) vs::parseChromaFormat(line.text("--chroma"), options.format.chroma);
    options.repeat = int(line.integer("--repeat", options.repeat));
    options.threads = int(line.integer("--threads", options.threads));
    options.referenceBinary = line.text("--reference");
    return vs::runMetricsBench(options);
  };
  return vs::runCommandLine(argc, argv, tool);
}
