#pragma once
// The bodies of the fuzz targets, shared by the libFuzzer executables (Test/Fuzz/Fuzz*.cpp, built with
// -DVS_FUZZ=ON and clang) and by the corpus replay test of the regular build.
//
// Each function takes one input and returns true when it was accepted, false when it was refused with
// vs::InputError (expected for bad input). Anything else is a bug: another exception type escapes, a
// VS_CHECK aborts, a sanitizer reports, or an oracle (a round trip that must give back what went in)
// throws OracleFailure.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/Config.h"
#include "Common/Depth.h"
#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"

namespace vs::fuzz {

// A round trip that did not give back what went in: a bug, not bad input.
class OracleFailure : public std::logic_error {
public:
  explicit OracleFailure(const std::string& what) : std::logic_error(what) {}
};

inline void oracle(bool ok, const std::string& what) {
  if (!ok) throw OracleFailure(what);
}

// Config text. Lines after a line "%%" (not the first line) are command-line overrides (Key=Value), one a line. An accepted
// config is read through every getter and into SynthesisSettings (which checks combinations and
// depth ranges); the depth ranges it accepts are then converted both ways.
inline bool fuzzConfig(const uint8_t* data, size_t size) {
  static const OptionTable table = viewSynOptionTable();
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  const size_t split = text.find("\n%%\n");
  if (split != std::string::npos) {
    std::string rest = text.substr(split + 4);
    text.resize(split + 1);
    size_t start = 0;
    while (start < rest.size()) {
      size_t end = rest.find('\n', start);
      if (end == std::string::npos) end = rest.size();
      overrides.push_back(rest.substr(start, end - start));
      start = end + 1;
    }
  }
  try {
    const Config config = Config::fromText(table, text, "fuzz.cfg", "/vs-fuzz-nonexistent", overrides);
    for (const OptionSpec& spec : table.options()) {
      config.isSet(spec.key);
      config.raw(spec.key);
      config.origin(spec.key);
      if (!config.isSet(spec.key) && spec.defaultValue.empty()) continue;  // no value: the tools check isSet first
      if (config.isAuto(spec.key)) continue;  // `auto` (set or the default): the tools check isAuto first
      switch (spec.type) {
        case OptionType::Int: config.getInt(spec.key); break;
        case OptionType::Double: config.getDouble(spec.key); break;
        case OptionType::Path: config.getPath(spec.key); break;
        case OptionType::TextList:
        case OptionType::PathList: config.getList(spec.key); break;
        default: config.getString(spec.key); break;
      }
    }
    config.effectiveText();
    ProblemList problems;
    config.requireKeys(problems);
    const SynthesisSettings settings = readSynthesisSettings(config);
    oracle(settings.textureFormat.frameBytes() > 0 && settings.depthFormat.frameBytes() > 0, "empty frame format");
    for (const ReferenceView& view : settings.references) {
      if (std::isnan(view.depthRange.znear)) continue;  // not given (a camera file may give it)
      const int maxLevel = maxDepthLevel(view.depthRange);
      for (int level : {0, 1, maxLevel / 2, maxLevel}) {
        const double z = levelToZ(level, view.depthRange);
        const int back = zToLevelRounded(z, view.depthRange);
        oracle(back >= 0 && back <= maxLevel, "zToLevelRounded out of range");
      }
    }
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// Camera file text, read with both rotation conventions. Every camera accepted is written with
// formatCamera and read again: the same numbers must come back, bit for bit. A pixel is projected
// through each accepted camera and back.
inline bool fuzzCameraFile(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  bool accepted = false;
  for (RotationConvention convention : {RotationConvention::WorldToCamera, RotationConvention::CameraToWorld}) {
    try {
      const CameraFile file = parseCameraText(text, "fuzz.txt", convention);
      accepted = true;
      oracle(!file.cameras().empty(), "a camera file without cameras was accepted");
      const Camera* previous = nullptr;
      for (const Camera& camera : file.cameras()) {
        oracle(file.contains(camera.name) && &file.find(camera.name) == &camera, "find() does not find " + camera.name);
        const CameraFile again = parseCameraText(formatCamera(camera), "formatted.txt");
        oracle(again.cameras().size() == 1, "formatCamera wrote a file of " + std::to_string(again.cameras().size()) +
                                                " cameras for " + camera.name);
        const Camera& copy = again.cameras().front();
        oracle(copy.name == camera.name && copy.K == camera.K && copy.R == camera.R && copy.t == camera.t &&
                   copy.distortion[0] == camera.distortion[0] && copy.distortion[1] == camera.distortion[1],
               "formatCamera -> parseCameraText changed camera " + camera.name);
        const Vec3 point = camera.backProject(0.5 * camera.K[0][2], 0.5 * camera.K[1][2], 10.0);
        double u = 0, v = 0, z = 0;
        camera.project(point, u, v, z);
        bool ok = false;
        depthToCameraZ(camera, u, v, 10.0, kDepthTypeWorld, ok);
        if (previous) relativePose(*previous, camera);
        previous = &camera;
      }
    } catch (const InputError&) {
    }
  }
  return accepted;
}

// MPEG-I camera JSON text (CameraJson.h). Every camera accepted passed validateCamera, so its VSRS text
// form must read back to the same numbers.
inline bool fuzzCameraJson(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const CameraFile file = parseCameraJson(text, "fuzz.json");
    for (const Camera& camera : file.cameras()) {
      const CameraInfo& info = file.info(camera.name);
      oracle(info.width >= 0 && info.height >= 0, "negative resolution accepted for " + camera.name);
      const CameraFile again = parseCameraText(formatCamera(camera), "formatted.txt");
      oracle(again.cameras().size() == 1 && again.cameras().front().K == camera.K &&
                 again.cameras().front().R == camera.R && again.cameras().front().t == camera.t,
             "formatCamera -> parseCameraText changed camera " + camera.name);
    }
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// A temporary file of this process, removed at exit. In memory (/dev/shm) where there is one: on a
// disk file system every truncation of a written file costs a flush to the disk.
class TemporaryFile {
public:
  explicit TemporaryFile(const std::string& tag) {
    const char* tmp = std::getenv("TMPDIR");
    std::error_code ec;
    const std::string dir = std::filesystem::is_directory("/dev/shm", ec) ? "/dev/shm" : tmp && *tmp ? tmp : "/tmp";
    path_ = dir + "/vs_fuzz_" + std::to_string(getpid()) + "_" + tag + ".yuv";
  }
  ~TemporaryFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

private:
  std::string path_;
};

// A YUV file: byte 0 picks the size (width 1..8, height 1..4), byte 1 the chroma format and the bit
// depth (8..16); the rest is the file. Every frame is read whole and luma only, and the frame after
// the last must be refused. Every frame read is written back with YuvWriter: the bytes must be those
// of the file.
inline bool fuzzYuv(const uint8_t* data, size_t size) {
  if (size < 2) return false;
  static const TemporaryFile input("in"), output("out");
  FrameFormat format;
  format.width = 1 + (data[0] & 7);
  format.height = 1 + ((data[0] >> 3) & 3);
  format.chroma = (data[1] & 3) == 0 ? ChromaFormat::Yuv400 : (data[1] & 3) == 1 ? ChromaFormat::Yuv444 : ChromaFormat::Yuv420;
  format.bitDepth = 8 + (data[1] >> 2) % 9;
  const std::string content(reinterpret_cast<const char*>(data + 2), size - 2);
  {
    std::ofstream file(input.path(), std::ios::binary | std::ios::trunc);
    file << content;
  }
  const uint64_t frameBytes = format.frameBytes();
  try {
    YuvReader reader(input.path(), format);
    if (reader.y4m()) return false;  // a Y4M header that matches the format: frames are not at n * frameBytes
    oracle(reader.fileBytes() == content.size(), "fileBytes differs from the file size");
    oracle(uint64_t(reader.frameCount()) * frameBytes + reader.trailingBytes() == content.size(),
           "frameCount and trailingBytes do not add up to the file size");
    YuvWriter writer(output.path(), format, {input.path()});
    Frame frame;
    Plane luma;
    int64_t readFrames = 0;
    bool refused = false;
    for (int64_t f = 0; f <= reader.frameCount() && f < 64; ++f) {
      try {
        reader.read(f, frame);
        reader.readLuma(f, luma);
      } catch (const InputError&) {
        refused = true;
        break;
      }
      oracle(f < reader.frameCount(), "frame " + std::to_string(f) + " past the end was read");
      oracle(luma == frame.planes[0], "readLuma differs from the luma of read");
      writer.append(frame);
      ++readFrames;
    }
    oracle(refused || reader.frameCount() >= 64, "the frame after the last was not refused");
    writer.commit();
    std::ifstream written(output.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(written)), std::istreambuf_iterator<char>());
    oracle(bytes.size() == uint64_t(readFrames) * frameBytes, "the writer wrote a partial frame");
    oracle(content.compare(0, bytes.size(), bytes) == 0, "read -> write changed the bytes");
    try {
      reader.read(reader.frameCount(), frame);
      oracle(false, "the frame after the last was read");
    } catch (const InputError&) {
    }
    return !refused || readFrames == reader.frameCount();
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace vs::fuzz
