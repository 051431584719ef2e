// YuvPsnr: PSNR of a test YUV file against a reference, frame by frame and averaged
// (doc/formats-yuv.md). Exit codes: 0 done, 1 file error, 2 bad arguments.
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/Metrics.h"
#include "Common/Yuv.h"

namespace {

constexpr int64_t kMaxInt64 = std::numeric_limits<int64_t>::max();
constexpr int kMaxSide = 65536;

struct PsnrOptions {
  std::string referencePath;  // first positional argument
  std::string testPath;       // second positional argument
  vs::FrameFormat format;     // WIDTH HEIGHT positional, --bitdepth, --chroma
  int64_t startFrame = 0;     // --start: first frame compared, in both files
  int64_t frameCount = -1;    // --frames; -1: every whole frame of the shorter file from startFrame on
};

// What the command line asks for. No exit() in the parser: main() decides.
struct ParsedArguments {
  enum class Action { Run, Help, Fail } action = Action::Run;
  PsnrOptions options;
  std::vector<std::string> errors;  // every problem found, for Action::Fail
};

struct OptionHelp {
  const char* name;
  const char* value;
  const char* defaultText;
  const char* range;
  const char* meaning;
};

const OptionHelp kOptions[] = {
    {"--frames", "N", "all whole frames of the shorter file from --start on", "1 and up", "frames to compare"},
    {"--start", "S", "0", "0 and up", "first frame compared (0-based), the same in both files"},
    {"--bitdepth", "B", "8", "8..16", "bits per sample; 9..16 are little-endian 16-bit words in the file"},
    {"--chroma", "F", "420", "420|444|400", "chroma format; 400 is luma only"},
    {"--help", "", "", "", "print this help and exit"},
};

void printUsage() {
  std::printf(
      "YuvPsnr %s: PSNR of a test YUV file against a reference, per frame and averaged.\n\n"
      "usage: YuvPsnr REF.yuv TEST.yuv WIDTH HEIGHT [options]\n\n"
      "  REF.yuv, TEST.yuv  planar YUV files of the same format, no header\n"
      "  WIDTH, HEIGHT      luma size in pixels, 1..%d\n\n"
      "options (also --name=value):\n",
      VS_VERSION, kMaxSide);
  for (const OptionHelp& option : kOptions) {
    const std::string head = std::string(option.name) + (*option.value ? " " : "") + option.value;
    std::printf("  %-14s %s\n", head.c_str(), option.meaning);
    if (*option.defaultText) std::printf("  %-14s default %s, range %s\n", "", option.defaultText, option.range);
  }
  std::printf(
      "\noutput: one line per frame (index, PSNR of Y, U, V and YUV in dB; identical planes print inf),\n"
      "then the means of each plane two ways:\n"
      "  frame-mean  mean of the per-frame PSNRs over frames with a finite PSNR; identical frames are\n"
      "              left out and counted, and it is inf only when every frame is identical\n"
      "  mean-MSE    PSNR of the mean of the per-frame MSEs\n"
      "PSNR = 10 log10((2^B - 1)^2 / MSE); YUV = (6 Y + U + V) / 8, inf when any plane is inf.\n"
      "With --chroma 400 only Y is printed.\n\n"
      "exit code: 0 done, 1 file error (missing, short, bad samples), 2 bad arguments\n");
}

bool parseInteger(const std::string& text, int64_t minValue, int64_t maxValue, int64_t& value) {
  int64_t parsed = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, parsed);
  if (ec != std::errc() || ptr != end || text.empty() || parsed < minValue || parsed > maxValue) return false;
  value = parsed;
  return true;
}

// Parses one integer argument into `value`, or records why not.
void takeInteger(const std::string& name, const std::string& text, int64_t minValue, int64_t maxValue,
                 const char* rangeText, int64_t& value, std::vector<std::string>& errors) {
  if (!parseInteger(text, minValue, maxValue, value))
    errors.push_back(name + " '" + text + "' is not an integer in " + rangeText);
}

ParsedArguments parseArguments(int argc, char** argv) {
  ParsedArguments parsed;
  PsnrOptions& options = parsed.options;
  std::vector<std::string>& errors = parsed.errors;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--help" || argument == "-h") {
      parsed.action = ParsedArguments::Action::Help;
      return parsed;
    }
    // "-5" is a (bad) number for WIDTH or HEIGHT, not an option.
    if (argument.size() < 2 || argument[0] != '-' || (argument[1] >= '0' && argument[1] <= '9')) {
      positional.push_back(argument);
      continue;
    }
    const size_t equals = argument.find('=');
    const std::string name = argument.substr(0, equals);
    if (name != "--frames" && name != "--start" && name != "--bitdepth" && name != "--chroma") {
      errors.push_back("unknown option '" + argument + "'");
      continue;
    }
    std::string value;
    if (equals != std::string::npos) {
      value = argument.substr(equals + 1);
    } else if (i + 1 < argc) {
      value = argv[++i];
    } else {
      errors.push_back(name + " needs a value");
      continue;
    }
    int64_t number = 0;
    if (name == "--frames") {
      takeInteger(name, value, 1, kMaxInt64, "1 and up", options.frameCount, errors);
    } else if (name == "--start") {
      takeInteger(name, value, 0, kMaxInt64, "0 and up", options.startFrame, errors);
    } else if (name == "--bitdepth") {
      number = options.format.bitDepth;
      takeInteger(name, value, 8, 16, "8..16", number, errors);
      options.format.bitDepth = int(number);
    } else if (!vs::parseChromaFormat(value, options.format.chroma)) {
      errors.push_back("--chroma '" + value + "' is not one of 420, 444, 400");
    }
  }
  if (positional.size() != 4) {
    errors.push_back("expected 4 arguments REF.yuv TEST.yuv WIDTH HEIGHT, got " +
                     std::to_string(positional.size()));
  } else {
    options.referencePath = positional[0];
    options.testPath = positional[1];
    int64_t side = 0;
    const std::string range = "1.." + std::to_string(kMaxSide);
    if (parseInteger(positional[2], 1, kMaxSide, side)) options.format.width = int(side);
    else errors.push_back("WIDTH '" + positional[2] + "' is not an integer in " + range);
    if (parseInteger(positional[3], 1, kMaxSide, side)) options.format.height = int(side);
    else errors.push_back("HEIGHT '" + positional[3] + "' is not an integer in " + range);
  }
  if (!errors.empty()) parsed.action = ParsedArguments::Action::Fail;
  return parsed;
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

int run(const PsnrOptions& options) {
  vs::YuvReader ref(options.referencePath, options.format);
  vs::YuvReader test(options.testPath, options.format);
  noteTrailingBytes(ref);
  noteTrailingBytes(test);
  const int64_t count = framesToCompare(options, ref, test);
  const vs::FrameFormat& format = options.format;
  const bool hasChroma = format.chroma != vs::ChromaFormat::Yuv400;

  std::printf("YuvPsnr %s\nreference  %s\ntest       %s\n", VS_VERSION, ref.path().c_str(), test.path().c_str());
  std::printf("format     %dx%d %s %d-bit, frames %lld..%lld (%lld frames)\n", format.width, format.height,
              vs::chromaFormatName(format.chroma), format.bitDepth, static_cast<long long>(options.startFrame),
              static_cast<long long>(options.startFrame + count - 1), static_cast<long long>(count));
  if (hasChroma) std::printf("%7s %10s %10s %10s %10s\n", "frame", "Y-PSNR", "U-PSNR", "V-PSNR", "YUV-PSNR");
  else std::printf("%7s %10s\n", "frame", "Y-PSNR");

  vs::Frame refFrame, testFrame;
  vs::PsnrAccumulator accumulator(format.bitDepth, hasChroma);
  for (int64_t frameIndex = options.startFrame; frameIndex < options.startFrame + count; ++frameIndex) {
    ref.read(frameIndex, refFrame);
    test.read(frameIndex, testFrame);
    const vs::FramePsnr psnr = vs::framePsnr(refFrame, testFrame);
    accumulator.add(psnr);
    if (hasChroma)
      std::printf("%7lld %10s %10s %10s %10s\n", static_cast<long long>(frameIndex), vs::formatPsnr(psnr.y).c_str(),
                  vs::formatPsnr(psnr.u).c_str(), vs::formatPsnr(psnr.v).c_str(), vs::formatPsnr(psnr.yuv).c_str());
    else
      std::printf("%7lld %10s\n", static_cast<long long>(frameIndex), vs::formatPsnr(psnr.y).c_str());
  }

  std::printf("mean over %lld frames [dB]\n  %-5s %12s %12s\n", static_cast<long long>(count), "plane",
              "frame-mean", "mean-MSE");
  printMean("Y", accumulator.y(), count);
  if (hasChroma) {
    printMean("U", accumulator.u(), count);
    printMean("V", accumulator.v(), count);
    printMean("YUV", accumulator.yuv(), count);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const ParsedArguments parsed = parseArguments(argc, argv);
  if (parsed.action == ParsedArguments::Action::Help) {
    printUsage();
    return 0;
  }
  if (parsed.action == ParsedArguments::Action::Fail) {
    for (const std::string& error : parsed.errors) std::fprintf(stderr, "YuvPsnr: error: %s\n", error.c_str());
    std::fprintf(stderr, "run 'YuvPsnr --help' for usage\n");
    return 2;
  }
  try {
    const int code = run(parsed.options);
    // The numbers must have reached stdout (a full disk, /dev/full, a closed pipe): else exit 1.
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      std::fprintf(stderr, "YuvPsnr: error: cannot write the standard output: %s\n", std::strerror(errno));
      return 1;
    }
    return code;
  } catch (const vs::InputError& error) {
    std::fflush(stdout);
    std::fprintf(stderr, "YuvPsnr: error: %s\n", error.what());
    return 1;
  }
}
