// CameraConvert: VSRS camera parameter file <-> MPEG-I camera JSON (doc/formats-camera.md).
#include <cstdio>
#include <string>
#include <vector>

#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/SafeOutput.h"

namespace {

bool isJson(const std::string& path) { return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0; }

// Reads IN, applies the options to every camera's information, writes OUT in the format its name says.
int convert(const vs::CommandLine& line) {
  const std::string& input = line.positional[0];
  const std::string& output = line.positional[1];
  if (vs::sameFile(input, output))
    throw vs::InputError(output + ": the output is the input file '" + input + "'; refusing to overwrite an input");
  const vs::CameraFile file = vs::readCameraFile(input);
  std::vector<vs::CameraInfo> info;
  for (const vs::Camera& camera : file.cameras()) {
    vs::CameraInfo i = file.info(camera.name);
    if (line.has("--resolution") && camera.isEquirectangular())
      throw vs::InputError("--resolution: camera '" + camera.name +
                           "' is equirectangular; its Resolution is part of the camera (the angle of a pixel "
                           "depends on it) and is not replaced");
    if (line.has("--resolution")) {
      i.width = int(std::stoll(line.options.at("--resolution")[0]));
      i.height = int(std::stoll(line.options.at("--resolution")[1]));
    }
    if (line.has("--depth-range")) {
      i.hasDepthRange = true;
      vs::parseDouble(line.options.at("--depth-range")[0], i.znear, false);
      vs::parseDouble(line.options.at("--depth-range")[1], i.zfar, true);
    }
    i.bitDepthColor = int(line.integer("--bitdepth-color", i.bitDepthColor));
    i.bitDepthDepth = int(line.integer("--bitdepth-depth", i.bitDepthDepth));
    info.push_back(i);
  }
  if (isJson(output)) vs::writeCameraJson(output, file.cameras(), info);
  else vs::writeCameraFile(output, file.cameras());
  for (const std::string& warning : file.warnings()) std::fprintf(stderr, "warning: %s\n", warning.c_str());
  std::printf("%zu cameras written to %s\n", file.cameras().size(), output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  vs::CommandLineTool tool;
  tool.name = "CameraConvert";
  tool.description =
      "converts camera files between the VSRS text format and the MPEG-I JSON format\n"
      "(RVS, TMIV). The direction follows the file names: *.json is JSON, anything else VSRS text.";
  tool.synopsis = {"IN OUT [options]"};
  tool.options = {
      {"--resolution", {"W", "H"}, "Resolution of every camera (default: none written)", vs::integerValues(1, 65536)},
      {"--depth-range", {"NEAR", "FAR"}, "Depth_range of every camera; FAR may be inf (default: none written)",
       vs::realValues(true)},
      {"--bitdepth-color", {"B"}, "BitDepthColor, 8..16 (default: none written)", vs::integerValues(8, 16)},
      {"--bitdepth-depth", {"B"}, "BitDepthDepth, 8..16 (default: none written)", vs::integerValues(8, 16)},
  };
  tool.notes = "Options apply text -> JSON; a JSON input keeps its own values unless given.\n"
               "Exit codes: 0 done, 1 bad input (file, line and what), 2 bad usage.\n"
               "Skew cannot be written to JSON and is refused; JSON -> text is exact (shortest round-trip digits).";
  tool.checkPositional = [](const vs::CommandLine& line) {
    return line.positional.size() == 2 ? std::string() : std::string("expected IN and OUT file names");
  };
  tool.run = convert;
  return vs::runCommandLine(argc, argv, tool);
}
