#include "Common/CameraJson.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "Common/Error.h"
#include "Common/Json.h"
#include "Common/SafeOutput.h"

namespace vs {

namespace {

constexpr double kDegrees = 180.0 / M_PI;

// ours = P omaf: x = -y', y = -z', z = x'.
Mat3 axisPermutation() {
  Mat3 p;
  p[0][1] = -1;
  p[1][2] = -1;
  p[2][0] = 1;
  return p;
}

// R_omaf (camera to world, OMAF axes) = Rz(yaw) Ry(pitch) Rx(roll).
Mat3 omafRotation(double yaw, double pitch, double roll) {
  const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cr = std::cos(roll), sr = std::sin(roll);
  Mat3 r;
  r[0][0] = cy * cp;
  r[0][1] = cy * sp * sr - sy * cr;
  r[0][2] = cy * sp * cr + sy * sr;
  r[1][0] = sy * cp;
  r[1][1] = sy * sp * sr + cy * cr;
  r[1][2] = sy * sp * cr - cy * sr;
  r[2][0] = -sp;
  r[2][1] = cp * sr;
  r[2][2] = cp * cr;
  return r;
}

class CameraReader {
public:
  CameraReader(const JsonValue& object, const std::string& source) : object_(object), source_(source) {}

  [[noreturn]] void fail(const JsonValue& at, const std::string& what) const {
    throw InputError(source_ + ":" + std::to_string(at.line) + ": " + what);
  }

  const JsonValue& member(const std::string& key) const {
    const JsonValue* value = object_.find(key);
    if (!value) fail(object_, "camera " + name() + "has no \"" + key + "\"");
    return *value;
  }

  std::vector<double> numbers(const std::string& key, size_t count, bool allowInfinity = false) const {
    const JsonValue& value = member(key);
    if (value.type != JsonValue::Type::Array || value.items.size() != count)
      fail(value, "camera " + name() + "\"" + key + "\" must be an array of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const JsonValue& item : value.items) {
      double v = 0;
      if (item.type == JsonValue::Type::Number) v = item.number;
      else if (allowInfinity && item.type == JsonValue::Type::String && (item.text == "inf" || item.text == "Infinity"))
        v = HUGE_VAL;
      else fail(item, "camera " + name() + "\"" + key + "\" holds " + item.typeName() + " where a number is expected");
      if (!std::isfinite(v) && !(allowInfinity && v > 0))
        fail(item, "camera " + name() + "\"" + key + "\" holds a non-finite number");
      out.push_back(v);
    }
    return out;
  }

  int integer(const std::string& key, int fallback) const {
    const JsonValue* value = object_.find(key);
    if (!value) return fallback;
    if (value->type != JsonValue::Type::Number || value->number != std::floor(value->number) || value->number < 1 ||
        value->number > 65536)
      fail(*value, "camera " + name() + "\"" + key + "\" must be a positive integer");
    return int(value->number);
  }

  std::string text(const std::string& key) const {
    const JsonValue* value = object_.find(key);
    if (!value) return "";
    if (value->type != JsonValue::Type::String) fail(*value, "camera " + name() + "\"" + key + "\" must be a string");
    return value->text;
  }

  std::string name() const {
    const JsonValue* value = object_.find("Name");
    return value && value->type == JsonValue::Type::String ? "'" + value->text + "' " : std::string();
  }

private:
  const JsonValue& object_;
  const std::string& source_;
};

}  // namespace

Mat3 rotationFromYawPitchRoll(double yawDegrees, double pitchDegrees, double rollDegrees) {
  const Mat3 p = axisPermutation();
  return p * transpose(omafRotation(yawDegrees / kDegrees, pitchDegrees / kDegrees, rollDegrees / kDegrees)) * transpose(p);
}

void yawPitchRollFromRotation(const Mat3& R, double& yawDegrees, double& pitchDegrees, double& rollDegrees) {
  const Mat3 p = axisPermutation();
  const Mat3 omaf = transpose(transpose(p) * R * p);  // R_omaf = (P^T R P)^T
  pitchDegrees = std::asin(std::max(-1.0, std::min(1.0, -omaf[2][0]))) * kDegrees;
  yawDegrees = std::atan2(omaf[1][0], omaf[0][0]) * kDegrees;
  rollDegrees = std::atan2(omaf[2][1], omaf[2][2]) * kDegrees;
}

CameraFile parseCameraJson(const std::string& text, const std::string& source) {
  const JsonValue document = parseJson(text, source);
  const JsonValue* list = document.type == JsonValue::Type::Object ? document.find("cameras") : nullptr;
  if (!list || list->type != JsonValue::Type::Array)
    throw InputError(source + ":" + std::to_string(document.line) + ": an object with a \"cameras\" array was expected");
  std::vector<Camera> cameras;
  std::vector<CameraInfo> infos;
  std::vector<std::string> warnings;
  for (const JsonValue& entry : list->items) {
    if (entry.type != JsonValue::Type::Object)
      throw InputError(source + ":" + std::to_string(entry.line) + ": each camera must be an object");
    const CameraReader reader(entry, source);
    Camera camera;
    CameraInfo info;
    const JsonValue& nameValue = reader.member("Name");
    if (nameValue.type != JsonValue::Type::String || nameValue.text.empty())
      reader.fail(nameValue, "\"Name\" must be a non-empty string");
    camera.name = nameValue.text;
    for (const Camera& other : cameras)
      if (other.name == camera.name) reader.fail(nameValue, "camera name '" + camera.name + "' appears twice");
    const std::string projection = reader.text("Projection");
    if (!projection.empty() && projection != "Perspective" && projection != "Equirectangular")
      reader.fail(*entry.find("Projection"), "camera '" + camera.name + "' has Projection \"" + projection +
                                                 "\"; expected \"Perspective\" or \"Equirectangular\"");
    const std::vector<double> position = reader.numbers("Position", 3);
    const std::vector<double> rotation = reader.numbers("Rotation", 3);
    camera.t = axisPermutation() * Vec3(position[0], position[1], position[2]);
    camera.R = rotationFromYawPitchRoll(rotation[0], rotation[1], rotation[2]);
    camera.K = Mat3::identity();
    if (projection == "Equirectangular") {
      // Angles and picture size; no focal length or principal point (K stays the identity).
      camera.projection = Projection::Equirectangular;
      const std::vector<double> horizontal = reader.numbers("Hor_range", 2);
      const std::vector<double> vertical = reader.numbers("Ver_range", 2);
      camera.erp.lonMin = horizontal[0];
      camera.erp.lonMax = horizontal[1];
      camera.erp.latMin = vertical[0];
      camera.erp.latMax = vertical[1];
      reader.member("Resolution");  // required: the angles of a pixel depend on it
    } else {
      const std::vector<double> focal = reader.numbers("Focal", 2);
      const std::vector<double> principal = reader.numbers("Principle_point", 2);
      camera.K[0][0] = focal[0];
      camera.K[1][1] = focal[1];
      camera.K[0][2] = principal[0] - 0.5;
      camera.K[1][2] = principal[1] - 0.5;
    }
    if (entry.find("Resolution")) {
      const std::vector<double> resolution = reader.numbers("Resolution", 2);
      for (double r : resolution)
        if (r != std::floor(r) || r < 1 || r > 65536)
          reader.fail(*entry.find("Resolution"), "camera '" + camera.name + "' \"Resolution\" must hold two integers in 1..65536");
      info.width = int(resolution[0]);
      info.height = int(resolution[1]);
      camera.erp.width = camera.isEquirectangular() ? info.width : 0;
      camera.erp.height = camera.isEquirectangular() ? info.height : 0;
    }
    if (entry.find("Depth_range")) {
      const std::vector<double> range = reader.numbers("Depth_range", 2, true);
      info.hasDepthRange = true;
      info.znear = range[0];
      info.zfar = range[1];
    }
    info.bitDepthColor = reader.integer("BitDepthColor", 0);
    info.bitDepthDepth = reader.integer("BitDepthDepth", 0);
    info.colorSpace = reader.text("ColorSpace");
    info.depthColorSpace = reader.text("DepthColorSpace");
    validateCamera(camera, source + ":" + std::to_string(entry.line), warnings);
    cameras.push_back(camera);
    infos.push_back(info);
  }
  if (cameras.empty()) throw InputError(source + ": the \"cameras\" array is empty");
  return CameraFile(source, std::move(cameras), std::move(infos), std::move(warnings));
}

CameraFile readCameraJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open camera file '" + path + "': " + std::strerror(errno));
  std::ostringstream content;
  content << in.rdbuf();
  return parseCameraJson(content.str(), path);
}

void writeCameraJson(const std::string& path, const std::vector<Camera>& cameras, const std::vector<CameraInfo>& info) {
  VS_CHECK(info.size() == cameras.size());
  std::ostringstream out;
  out << "{\n  \"Version\": \"2.0\",\n  \"cameras\": [";
  const Mat3 p = axisPermutation();
  for (size_t k = 0; k < cameras.size(); ++k) {
    const Camera& c = cameras[k];
    const CameraInfo& i = info[k];
    if (!c.isEquirectangular() && (c.K[0][1] != 0 || c.K[1][0] != 0 || c.K[2][0] != 0 || c.K[2][1] != 0 || c.K[2][2] != 1))
      throw InputError(path + ": camera '" + c.name + "' has skew or a K the JSON format cannot hold");
    const Vec3 position = transpose(p) * c.t;
    double yaw, pitch, roll;
    yawPitchRollFromRotation(c.R, yaw, pitch, roll);
    auto pair = [](double a, double b) { return "[" + jsonNumber(a) + ", " + jsonNumber(b) + "]"; };
    out << (k ? ",\n" : "\n") << "    {\n      \"Name\": " << jsonString(c.name) << ",\n"
        << "      \"Projection\": \"" << (c.isEquirectangular() ? "Equirectangular" : "Perspective") << "\",\n"
        << "      \"Position\": [" << jsonNumber(position.x) << ", " << jsonNumber(position.y) << ", "
        << jsonNumber(position.z) << "],\n"
        << "      \"Rotation\": [" << jsonNumber(yaw) << ", " << jsonNumber(pitch) << ", " << jsonNumber(roll) << "],\n";
    if (c.isEquirectangular())
      out << "      \"Hor_range\": " << pair(c.erp.lonMin, c.erp.lonMax) << ",\n"
          << "      \"Ver_range\": " << pair(c.erp.latMin, c.erp.latMax) << ",\n"
          << "      \"Resolution\": [" << c.erp.width << ", " << c.erp.height << "]";
    else
      out << "      \"Focal\": " << pair(c.K[0][0], c.K[1][1]) << ",\n"
          << "      \"Principle_point\": " << pair(c.K[0][2] + 0.5, c.K[1][2] + 0.5);
    if (i.width > 0 && !c.isEquirectangular()) out << ",\n      \"Resolution\": [" << i.width << ", " << i.height << "]";
    if (i.hasDepthRange) out << ",\n      \"Depth_range\": " << pair(i.znear, i.zfar);
    if (i.bitDepthColor > 0) out << ",\n      \"BitDepthColor\": " << i.bitDepthColor;
    if (i.bitDepthDepth > 0) out << ",\n      \"BitDepthDepth\": " << i.bitDepthDepth;
    if (!i.colorSpace.empty()) out << ",\n      \"ColorSpace\": " << jsonString(i.colorSpace);
    if (!i.depthColorSpace.empty()) out << ",\n      \"DepthColorSpace\": " << jsonString(i.depthColorSpace);
    out << "\n    }";
  }
  out << "\n  ]\n}\n";
  SafeOutputFile file(path, {}, "camera file");  // a failed write leaves a previous file as it was
  file.write(out.str());
  file.commit();
}

}  // namespace vs
