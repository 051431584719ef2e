// CameraConvert: VSRS camera parameter file <-> MPEG-I camera JSON (doc/formats-camera.md).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/SafeOutput.h"

namespace {

const char* kUsage =
    "CameraConvert %s: converts camera files between the VSRS text format and the MPEG-I JSON format\n"
    "(RVS, TMIV). The direction follows the file names: *.json is JSON, anything else VSRS text.\n\n"
    "Usage:\n"
    "  CameraConvert IN OUT [options]\n"
    "  CameraConvert --help\n\n"
    "Options (text -> JSON; a JSON input keeps its own values unless given):\n"
    "  --resolution W H          Resolution of every camera (default: none written)\n"
    "  --depth-range NEAR FAR    Depth_range of every camera; FAR may be inf (default: none written)\n"
    "  --bitdepth-color B        BitDepthColor, 8..16 (default: none written)\n"
    "  --bitdepth-depth B        BitDepthDepth, 8..16 (default: none written)\n\n"
    "Exit codes: 0 done, 1 bad input (file, line and what), 2 bad usage.\n"
    "Skew cannot be written to JSON and is refused; JSON -> text is exact (shortest round-trip digits).\n";

struct Arguments {
  std::string input, output;
  int width = 0, height = 0, bitDepthColor = 0, bitDepthDepth = 0;
  bool hasDepthRange = false;
  double znear = 0, zfar = 0;
};

bool parseArguments(const std::vector<std::string>& args, Arguments& a, std::string& error) {
  std::vector<std::string> positional;
  auto integer = [&](size_t& i, int lo, int hi, int& out) {
    int64_t v = 0;
    if (i + 1 >= args.size() || !vs::parseInt(args[i + 1], v) || v < lo || v > hi) {
      error = args[i] + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
      return false;
    }
    out = int(v);
    ++i;
    return true;
  };
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--resolution") {
      if (!integer(i, 1, 65536, a.width) || !integer(i, 1, 65536, a.height)) return false;
    } else if (arg == "--depth-range") {
      if (i + 2 >= args.size() || !vs::parseDouble(args[i + 1], a.znear, false) || !vs::parseDouble(args[i + 2], a.zfar, true)) {
        error = "--depth-range needs two numbers (FAR may be inf)";
        return false;
      }
      a.hasDepthRange = true;
      i += 2;
    } else if (arg == "--bitdepth-color") {
      if (!integer(i, 8, 16, a.bitDepthColor)) return false;
    } else if (arg == "--bitdepth-depth") {
      if (!integer(i, 8, 16, a.bitDepthDepth)) return false;
    } else if (arg.rfind("--", 0) == 0) {
      error = "unknown option '" + arg + "'";
      return false;
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) {
    error = "expected IN and OUT file names";
    return false;
  }
  a.input = positional[0];
  a.output = positional[1];
  return true;
}

bool isJson(const std::string& path) { return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0; }

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::printf(kUsage, VS_VERSION);
    return 0;
  }
  Arguments a;
  std::string error;
  if (!parseArguments(args, a, error)) {
    std::fprintf(stderr, "CameraConvert: %s (see CameraConvert --help)\n", error.c_str());
    return 2;
  }
  try {
    if (vs::sameFile(a.input, a.output))
      throw vs::InputError(a.output + ": the output is the input file '" + a.input + "'; refusing to overwrite an input");
    const vs::CameraFile file = vs::readCameraFile(a.input);
    std::vector<vs::CameraInfo> info;
    for (const vs::Camera& camera : file.cameras()) {
      vs::CameraInfo i = file.info(camera.name);
      if (a.width > 0) {
        i.width = a.width;
        i.height = a.height;
      }
      if (a.hasDepthRange) {
        i.hasDepthRange = true;
        i.znear = a.znear;
        i.zfar = a.zfar;
      }
      if (a.bitDepthColor > 0) i.bitDepthColor = a.bitDepthColor;
      if (a.bitDepthDepth > 0) i.bitDepthDepth = a.bitDepthDepth;
      info.push_back(i);
    }
    if (isJson(a.output)) vs::writeCameraJson(a.output, file.cameras(), info);
    else vs::writeCameraFile(a.output, file.cameras());
    for (const std::string& warning : file.warnings()) std::fprintf(stderr, "warning: %s\n", warning.c_str());
    std::printf("%zu cameras written to %s\n", file.cameras().size(), a.output.c_str());
    return 0;
  } catch (const vs::InputError& e) {
    std::fprintf(stderr, "CameraConvert: error: %s\n", e.what());
    return 1;
  }
}
