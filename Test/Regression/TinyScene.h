#pragma once
// A small valid ViewSyn scene written into a scratch folder in code: three cameras of a parallel rig
// (cameras file written with writeCameraFile), left and right texture and depth sequences rendered
// from the analytic plane of SynthTestScene.h, and a VSRS-style config naming them with relative
// paths. Tests break one thing at a time, or run it as it is.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "Common/CameraFile.h"
#include "Common/Frame.h"
#include "Common/Yuv.h"
#include "SynthTestScene.h"

namespace vs::test {

struct TinyScene {
  std::filesystem::path dir;
  int width = 32;
  int height = 16;
  int frames = 3;
  int textureBitDepth = 8;
  int depthBitDepth = 8;
  // Config lines in file order; set() replaces a key in place or appends it.
  std::vector<std::pair<std::string, std::string>> keys;
  std::string extraConfigText;  // written after the keys, verbatim

  explicit TinyScene(std::filesystem::path folder) : dir(std::move(folder)) {}

  std::filesystem::path path(const std::string& name) const { return dir / name; }
  std::filesystem::path configPath() const { return path("scene.cfg"); }
  std::filesystem::path outputPath() const { return path("virtual.yuv"); }

  FrameFormat textureFormat() const { return FrameFormat{width, height, textureBitDepth, ChromaFormat::Yuv420}; }
  FrameFormat depthFormat() const { return FrameFormat{width, height, depthBitDepth, ChromaFormat::Yuv420}; }

  AnalyticScene analytic() const {
    AnalyticScene a;
    a.width = width;
    a.height = height;
    a.focal = 30.0;
    a.square = true;
    a.squareHalf = 6.0;
    a.range = DepthRange{50.0, 120.0, depthBitDepth};
    a.bitDepth = textureBitDepth;
    return a;
  }

  std::vector<Camera> cameras() const {
    const AnalyticScene a = analytic();
    return {a.camera("cam_left", -4.0), a.camera("cam_virtual", 0.0), a.camera("cam_right", 4.0)};
  }

  void set(const std::string& key, const std::string& value) {
    for (auto& entry : keys)
      if (entry.first == key) {
        entry.second = value;
        return;
      }
    keys.emplace_back(key, value);
  }
  void erase(const std::string& key) {
    for (auto it = keys.begin(); it != keys.end(); ++it)
      if (it->first == key) {
        keys.erase(it);
        return;
      }
  }

  // Writes everything: camera file, the four sequences, the config.
  void writeAll() {
    std::filesystem::create_directories(dir);
    writeCameraFile(path("cameras.txt").string(), cameras());
    writeSequences();
    keys = {{"DepthType", "0"},
            {"SourceWidth", std::to_string(width)},
            {"SourceHeight", std::to_string(height)},
            {"StartFrame", "0"},
            {"TotalNumberOfFrames", std::to_string(frames)},
            {"LeftNearestDepthValue", "50"},
            {"LeftFarthestDepthValue", "120"},
            {"RightNearestDepthValue", "50"},
            {"RightFarthestDepthValue", "120"},
            {"CameraParameterFile", "cameras.txt"},
            {"LeftCameraName", "cam_left"},
            {"VirtualCameraName", "cam_virtual"},
            {"RightCameraName", "cam_right"},
            {"LeftViewImageName", "left.yuv"},
            {"RightViewImageName", "right.yuv"},
            {"LeftDepthMapName", "left_depth.yuv"},
            {"RightDepthMapName", "right_depth.yuv"},
            {"OutputVirtualViewImageName", "virtual.yuv"},
            {"TextureBitDepth", std::to_string(textureBitDepth)},
            {"DepthBitDepth", std::to_string(depthBitDepth)},
            {"Threads", "1"}};
    writeConfig();
  }

  void writeConfig() const {
    std::ofstream out(configPath(), std::ios::binary | std::ios::trunc);
    out << "# tiny scene written by the tests\n";
    for (const auto& [key, value] : keys) out << key << "  " << value << "\n";
    out << extraConfigText;
  }

  // Texture and depth of both references, `frames` frames each; the texture drifts a little from
  // frame to frame so that frames differ.
  void writeSequences() const {
    const AnalyticScene a = analytic();
    const std::vector<Camera> c = cameras();
    const std::pair<const Camera*, std::string> views[] = {{&c[0], "left"}, {&c[2], "right"}};
    for (const auto& [camera, name] : views) {
      Frame texture;
      Plane depth;
      a.render(*camera, texture, depth);
      YuvWriter textureWriter(path(name + ".yuv").string(), textureFormat());
      YuvWriter depthWriter(path(name + "_depth.yuv").string(), depthFormat());
      Frame depthFrame(depthFormat());
      depthFrame.fill(0);
      depthFrame.planes[0] = depth;
      for (int f = 0; f < frames; ++f) {
        Frame shifted = texture;
        for (uint16_t& s : shifted.planes[0].samples) s = uint16_t(std::min<int>(s + f, textureFormat().maxValue()));
        textureWriter.append(shifted);
        depthWriter.append(depthFrame);
      }
      textureWriter.commit();
      depthWriter.commit();
    }
  }
};

}  // namespace vs::test
