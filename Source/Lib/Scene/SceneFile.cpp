#include "Scene/SceneFile.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "Common/Config.h"
#include "Common/Error.h"

namespace vs {

namespace {

constexpr size_t kMaxSceneFileBytes = 1 << 20;
constexpr size_t kMaxObjects = 10000;

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

// The period of the finest detail noise relative to the pattern's scale when DetailScale is not given:
// the same proportions the built-in scenes use (Scenes.cpp).
double detailScaleDivisor(Pattern pattern) {
  switch (pattern) {
    case Pattern::Checker:
      return 6.0;
    case Pattern::Stripes:
      return 3.0;
    case Pattern::Noise:
      return 40.0;
    case Pattern::Gradient:
      return 30.0;
    case Pattern::Rings:
      return 2.0;
    case Pattern::Flat:
      break;
  }
  return 0.0;  // Flat: keeps the Texture default
}

class Parser {
public:
  explicit Parser(std::string name) : name_(std::move(name)) {}

  void line(int number, const std::vector<std::string>& words) {
    where_ = name_ + ":" + std::to_string(number);
    const std::string& key = words[0];
    if (key == "Object") return startObject(words);
    if (!scene_.objects.empty()) return objectLine(words);
    if (key == "Description") {
      std::string text;
      for (size_t i = 1; i < words.size(); ++i) text += (i > 1 ? " " : "") + words[i];
      scene_.description = text;
      return;
    }
    SceneGenSettings& s = scene_.preset;
    if (key == "SourceWidth") return integer(words, s.width, 16, 16384);
    if (key == "SourceHeight") return integer(words, s.height, 16, 16384);
    if (key == "TotalNumberOfFrames") return integer(words, s.frames, 1, 100000);
    if (key == "CameraCount") return integer(words, s.cameraCount, 1, 256);
    if (key == "Baseline") return real(words, s.baseline);
    if (key == "FocalLength") return real(words, s.focalLength);
    if (key == "ArcRadius") return real(words, s.arcRadius);
    if (key == "ArcAngle") return real(words, s.arcStepDegrees);
    if (key == "Rig") {
      if (words.size() == 2 && words[1] == "parallel") s.rig = RigType::Parallel;
      else if (words.size() == 2 && words[1] == "arc") s.rig = RigType::Arc;
      else problem("Rig: parallel or arc expected");
      return;
    }
    problem("unknown scene setting '" + key +
            "' (expected Description, SourceWidth, SourceHeight, TotalNumberOfFrames, Rig, CameraCount, Baseline, "
            "FocalLength, ArcRadius, ArcAngle, or Object)");
  }

  SceneFile finish() {
    finishObject();
    if (scene_.objects.empty()) problems_.add(name_ + ": no Object in the scene file; at least one expected");
    problems_.throwIfAny(name_ + ": invalid scene file:");
    return scene_;
  }

  void problem(const std::string& text) { problems_.add(where_ + ": " + text); }

private:
  void startObject(const std::vector<std::string>& words) {
    finishObject();
    if (scene_.objects.size() >= kMaxObjects) return problem("more than 10000 objects");
    Primitive p;
    if (words.size() != 3) problem("Object NAME SHAPE expected (SHAPE: rectangle, box or sphere)");
    else if (words[2] == "rectangle") p.shape = Shape::Rectangle;
    else if (words[2] == "box") p.shape = Shape::Box;
    else if (words[2] == "sphere") p.shape = Shape::Sphere;
    else problem("shape '" + words[2] + "': rectangle, box or sphere expected");
    if (words.size() > 1) p.name = words[1];
    scene_.objects.push_back(p);
    orientationGiven_ = false;
    detailScaleGiven_ = false;
  }

  void finishObject() {
    if (scene_.objects.empty()) return;
    Texture& t = scene_.objects.back().texture;
    if (!detailScaleGiven_ && detailScaleDivisor(t.pattern) > 0.0) t.detailScale = t.scale / detailScaleDivisor(t.pattern);
  }

  void objectLine(const std::vector<std::string>& words) {
    Primitive& p = scene_.objects.back();
    Texture& t = p.texture;
    const std::string& key = words[0];
    if (key == "HalfSize") return vector(words, p.halfSize);
    if (key == "Position") return vector(words, p.position);
    if (key == "Velocity") return vector(words, p.motion.velocity);
    if (key == "SpinAxis") return vector(words, p.motion.spinAxis);
    if (key == "SpinDegrees") return real(words, p.motion.spinDegrees);
    if (key == "Orientation") {
      std::vector<double> values;
      if (!numbers(words, 9, values)) return;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p.orientation[r][c] = values[size_t(3 * r + c)];
      orientationGiven_ = true;
      return;
    }
    if (key == "Rotate") {
      std::vector<double> values;
      if (!numbers(words, 4, values)) return;
      const Vec3 axis{values[0], values[1], values[2]};
      if (axis == Vec3()) return problem("Rotate: the axis must not be 0 0 0");
      const Mat3 rotation = axisAngleRotation(axis, values[3]);
      p.orientation = orientationGiven_ ? p.orientation * rotation : rotation;
      orientationGiven_ = true;
      return;
    }
    if (key == "Texture") {
      static const std::map<std::string, Pattern> patterns{{"flat", Pattern::Flat},       {"checker", Pattern::Checker},
                                                           {"stripes", Pattern::Stripes}, {"noise", Pattern::Noise},
                                                           {"gradient", Pattern::Gradient}, {"rings", Pattern::Rings}};
      const auto found = words.size() == 2 ? patterns.find(words[1]) : patterns.end();
      if (found == patterns.end()) return problem("Texture: flat, checker, stripes, noise, gradient or rings expected");
      t.pattern = found->second;
      return;
    }
    if (key == "ColourA") return colour(words, t.colourA);
    if (key == "ColourB") return colour(words, t.colourB);
    if (key == "Scale") return real(words, t.scale);
    if (key == "Direction") return vector(words, t.direction);
    if (key == "BandDirection") return vector(words, t.bandDirection);
    if (key == "BandWidth") return real(words, t.bandWidth);
    if (key == "Octaves") return integer(words, t.octaves, 1, 16);
    if (key == "Detail") return real(words, t.detail);
    if (key == "DetailScale") {
      detailScaleGiven_ = true;
      return real(words, t.detailScale);
    }
    if (key == "Seed") {
      int seed = 0;
      integer(words, seed, 0, 2147483647);
      t.seed = uint32_t(seed);
      return;
    }
    problem("unknown object setting '" + key +
            "' (expected HalfSize, Position, Orientation, Rotate, Velocity, SpinAxis, SpinDegrees, Texture, ColourA, "
            "ColourB, Scale, Direction, BandDirection, BandWidth, Octaves, Detail, DetailScale, Seed)");
  }

  bool numbers(const std::vector<std::string>& words, size_t count, std::vector<double>& values) {
    if (words.size() != count + 1) {
      problem(words[0] + ": " + std::to_string(count) + " number(s) expected, " + std::to_string(words.size() - 1) +
              " given");
      return false;
    }
    values.assign(count, 0.0);
    for (size_t i = 0; i < count; ++i)
      if (!parseDouble(words[i + 1], values[i], false)) {
        problem(words[0] + ": '" + words[i + 1] + "' is not a finite number");
        return false;
      }
    return true;
  }

  void real(const std::vector<std::string>& words, double& target) {
    std::vector<double> values;
    if (numbers(words, 1, values)) target = values[0];
  }

  void vector(const std::vector<std::string>& words, Vec3& target) {
    std::vector<double> values;
    if (numbers(words, 3, values)) target = {values[0], values[1], values[2]};
  }

  void integer(const std::vector<std::string>& words, int& target, int lo, int hi) {
    int64_t value = 0;
    if (words.size() != 2 || !parseInt(words[1], value) || value < lo || value > hi)
      return problem(words[0] + ": an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] expected");
    target = int(value);
  }

  // Colours are floats: read as the compiler reads a float literal, so that a file's 0.2 is the
  // built-in scenes' 0.2f.
  void colour(const std::vector<std::string>& words, Rgb& target) {
    std::vector<double> values;
    if (!numbers(words, 3, values)) return;
    float channel[3];
    for (int i = 0; i < 3; ++i) {
      if (values[size_t(i)] < 0.0 || values[size_t(i)] > 1.0)
        return problem(words[0] + ": channels in [0, 1] expected");
      channel[i] = std::strtof(words[size_t(i) + 1].c_str(), nullptr);
    }
    target = {channel[0], channel[1], channel[2]};
  }

  std::string name_, where_;
  SceneFile scene_;
  ProblemList problems_;
  bool orientationGiven_ = false;
  bool detailScaleGiven_ = false;
};

}  // namespace

SceneFile parseSceneFile(const std::string& text, const std::string& name) {
  Parser parser(name);
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const std::vector<std::string> words = tokens(line);
    if (!words.empty()) parser.line(number, words);
  }
  SceneFile scene = parser.finish();
  scene.preset.scene = std::filesystem::path(name).stem().string();
  return scene;
}

SceneFile readSceneFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": scene file not found");
  if (std::filesystem::file_size(path, ec) > kMaxSceneFileBytes)
    throw InputError(path + ": scene file is larger than 1 MiB (is it a scene file?)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the scene file for reading");
  std::stringstream text;
  text << in.rdbuf();
  return parseSceneFile(text.str(), path);
}

}  // namespace vs
