#include "Common/RvsConfig.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "Common/CameraJson.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Json.h"

namespace vs {

namespace {

constexpr uintmax_t kMaxJsonBytes = 64u << 20;  // the largest camera file we know (280 cameras) is 120 kB

std::string readWholeFile(const std::string& path, const std::string& role) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(role + " '" + path + "': no such file");
  if (std::filesystem::file_size(path, ec) > kMaxJsonBytes)
    throw InputError(role + " '" + path + "': larger than " + std::to_string(kMaxJsonBytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(role + " '" + path + "': cannot open: " + std::strerror(errno));
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

// Compact JSON text of a parsed value (the inverse of parseJson up to blanks and line numbers).
void writeJson(const JsonValue& value, std::string& out) {
  switch (value.type) {
    case JsonValue::Type::Null: out += "null"; break;
    case JsonValue::Type::Bool: out += value.boolean ? "true" : "false"; break;
    case JsonValue::Type::Number: out += jsonNumber(value.number); break;
    case JsonValue::Type::String: out += jsonString(value.text); break;
    case JsonValue::Type::Array:
      out += '[';
      for (size_t k = 0; k < value.items.size(); ++k) {
        if (k) out += ',';
        writeJson(value.items[k], out);
      }
      out += ']';
      break;
    case JsonValue::Type::Object:
      out += '{';
      for (size_t k = 0; k < value.members.size(); ++k) {
        if (k) out += ',';
        out += jsonString(value.members[k].first) + ':';
        writeJson(value.members[k].second, out);
      }
      out += '}';
      break;
  }
}

std::string compactJson(const JsonValue& value) {
  std::string out;
  writeJson(value, out);
  return out;
}

void setMember(JsonValue& object, const std::string& key, const JsonValue& value) {
  for (auto& member : object.members)
    if (member.first == key) {
      member.second = value;
      return;
    }
  object.members.emplace_back(key, value);
}

// The camera JSON document at `path` with `overrides` applied to every camera.
JsonValue cameraDocument(const std::string& path, const JsonValue* overrides) {
  JsonValue document = parseJson(readWholeFile(path, "camera file"), path);
  JsonValue* cameras = nullptr;
  if (document.type == JsonValue::Type::Object)
    for (auto& member : document.members)
      if (member.first == "cameras") cameras = &member.second;
  if (!cameras || cameras->type != JsonValue::Type::Array)
    throw InputError(path + ":" + std::to_string(document.line) + ": an object with a \"cameras\" array was expected");
  if (overrides)
    for (JsonValue& camera : cameras->items)
      if (camera.type == JsonValue::Type::Object)
        for (const auto& [key, value] : overrides->members) setMember(camera, key, value);
  return document;
}

bool isJsonPath(const std::string& path) {
  return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (size_t k = 0; k < items.size(); ++k) out += (k ? "," : "") + items[k];
  return out;
}

std::string number(double value) { return std::isinf(value) ? "inf" : jsonNumber(value); }

// Reads the RVS keys, collecting every problem; `where(value)` is "file:line".
class RvsReader {
public:
  RvsReader(const JsonValue& root, const std::string& path, ProblemList& problems)
      : root_(root), path_(path), problems_(problems) {}

  std::string where(const JsonValue& value) const { return path_ + ":" + std::to_string(value.line); }
  void problem(const JsonValue& at, const std::string& what) { problems_.add(where(at) + ": " + what); }

  const JsonValue* find(const std::string& key) const { return root_.find(key); }

  const JsonValue* require(const std::string& key, const std::string& why) {
    const JsonValue* value = root_.find(key);
    if (!value) problems_.add(path_ + ": missing RVS key \"" + key + "\" (" + why + ")");
    return value;
  }

  bool text(const JsonValue& value, const std::string& key, std::string& out) {
    if (value.type != JsonValue::Type::String || value.text.empty()) {
      problem(value, "\"" + key + "\" must be a non-empty string, not " + value.typeName());
      return false;
    }
    out = value.text;
    return true;
  }

  // A list of non-empty strings; `commaFree`: the items become one of our comma-separated values.
  bool textList(const JsonValue& value, const std::string& key, std::vector<std::string>& out) {
    if (value.type != JsonValue::Type::Array) {
      problem(value, "\"" + key + "\" must be an array of strings, not " + value.typeName());
      return false;
    }
    bool ok = true;
    for (const JsonValue& item : value.items) {
      std::string s;
      if (!text(item, key, s)) {
        ok = false;
        continue;
      }
      if (s.find(',') != std::string::npos) {
        problem(item, "\"" + key + "\" item '" + s + "' holds a comma, which our lists cannot carry; rename it");
        ok = false;
      }
      out.push_back(s);
    }
    return ok;
  }

  bool numberValue(const JsonValue& value, const std::string& key, double& out) {
    if (value.type != JsonValue::Type::Number) {
      problem(value, "\"" + key + "\" must be a number, not " + value.typeName());
      return false;
    }
    out = value.number;
    return true;
  }

  bool integer(const JsonValue& value, const std::string& key, int64_t minimum, int64_t& out) {
    double v = 0;
    if (!numberValue(value, key, v)) return false;
    if (v != std::floor(v) || v < double(minimum) || v > 1e9) {
      problem(value,
              "\"" + key + "\" must be an integer from " + std::to_string(minimum) + " on, not " + jsonNumber(v));
      return false;
    }
    out = int64_t(v);
    return true;
  }

private:
  const JsonValue& root_;
  std::string path_;
  ProblemList& problems_;
};

// Every key RVS 4.0 documents for a synthesis config (and "Version"); keys starting with '_' are
// comments (RVS's own integration tests carry "_NOTE").
const std::vector<std::string>& rvsKeys() {
  static const std::vector<std::string> keys = {
      "Version", "InputCameraParameterFile", "VirtualCameraParameterFile", "InputCameraNames", "VirtualCameraNames",
      "ViewImageNames", "DepthMapNames", "OutputFiles", "DepthOutputFiles", "OutputMasks", "MaskedOutputFiles",
      "MaskedDepthOutputFiles", "StartFrame", "NumberOfFrames", "Precision", "ColorSpace", "ViewSynthesisMethod",
      "BlendingMethod", "BlendingFactor", "BlendingLowFreqFactor", "BlendingHighFreqFactor", "InputOverrides",
      "VirtualOverrides", "VirtualPoseTraceName"};
  return keys;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// What a camera of a camera JSON file says about formats and depth (after its overrides).
struct CameraFacts {
  int width = 0, height = 0;
  int bitDepthColor = 0, bitDepthDepth = 0;
  std::string colorSpace, depthColorSpace;
  bool hasDepthRange = false;
  double znear = 0, zfar = 0;
  bool hasInvalidDepth = true;  // RVS's default: level 0 is "no depth"
};

class CameraFactsFile {
public:
  CameraFactsFile(const std::string& path, const JsonValue* overrides) : path_(path) {
    if (!isJsonPath(path)) return;  // a VSRS text file: no facts, loadScene reports its own problems
    document_ = cameraDocument(path, overrides);
    const JsonValue* cameras = document_.find("cameras");
    for (const JsonValue& camera : cameras->items) {
      const JsonValue* name = camera.type == JsonValue::Type::Object ? camera.find("Name") : nullptr;
      if (name && name->type == JsonValue::Type::String) index_[name->text] = &camera;
    }
  }
  bool isJson() const { return document_.type == JsonValue::Type::Object; }
  bool contains(const std::string& name) const { return index_.count(name) != 0; }

  // Facts of camera `name`; problems (missing or malformed fields) are added, naming the camera.
  CameraFacts facts(const std::string& name, ProblemList& problems) const {
    CameraFacts f;
    const JsonValue& camera = *index_.at(name);
    const std::string at = path_ + ":" + std::to_string(camera.line) + ": camera '" + name + "': ";
    auto pair = [&](const char* key, double& a, double& b, bool allowInfinity) {
      const JsonValue* value = camera.find(key);
      if (!value) return false;
      if (value->type != JsonValue::Type::Array || value->items.size() != 2) {
        problems.add(at + "\"" + key + "\" must be an array of two numbers");
        return false;
      }
      double* out[2] = {&a, &b};
      for (int k = 0; k < 2; ++k) {
        const JsonValue& item = value->items[size_t(k)];
        if (item.type == JsonValue::Type::Number) *out[k] = item.number;
        else if (allowInfinity && item.type == JsonValue::Type::String &&
                 (item.text == "inf" || item.text == "Infinity"))
          *out[k] = HUGE_VAL;
        else {
          problems.add(at + "\"" + key + "\" must be an array of two numbers");
          return false;
        }
      }
      return true;
    };
    auto integer = [&](const char* key, int& out) {
      const JsonValue* value = camera.find(key);
      if (!value) return;
      if (value->type != JsonValue::Type::Number || value->number != std::floor(value->number) || value->number < 1 ||
          value->number > 65536)
        problems.add(at + "\"" + key + "\" must be a positive integer");
      else out = int(value->number);
    };
    auto text = [&](const char* key, std::string& out) {
      const JsonValue* value = camera.find(key);
      if (!value) return;
      if (value->type != JsonValue::Type::String) problems.add(at + "\"" + key + "\" must be a string");
      else out = value->text;
    };
    double w = 0, h = 0;
    if (pair("Resolution", w, h, false)) {
      if (w != std::floor(w) || h != std::floor(h) || w < 1 || h < 1 || w > 65536 || h > 65536)
        problems.add(at + "\"Resolution\" must hold two integers in 1..65536");
      else {
        f.width = int(w);
        f.height = int(h);
      }
    } else if (!camera.find("Resolution")) {
      problems.add(at + "no \"Resolution\" (RVS needs it for every camera)");
    }
    f.hasDepthRange = pair("Depth_range", f.znear, f.zfar, true);
    integer("BitDepthColor", f.bitDepthColor);
    integer("BitDepthDepth", f.bitDepthDepth);
    text("ColorSpace", f.colorSpace);
    text("DepthColorSpace", f.depthColorSpace);
    if (const JsonValue* invalid = camera.find("HasInvalidDepth")) {
      if (invalid->type != JsonValue::Type::Bool) problems.add(at + "\"HasInvalidDepth\" must be true or false");
      else f.hasInvalidDepth = invalid->boolean;
    }
    return f;
  }

private:
  std::string path_;
  JsonValue document_;
  std::map<std::string, const JsonValue*> index_;
};

// "YUV420" -> "420" (our ChromaFormat values); empty when RVS's name has no counterpart.
std::string chromaOf(const std::string& colorSpace) {
  if (colorSpace == "YUV420") return "420";
  if (colorSpace == "YUV400") return "400";
  if (colorSpace == "YUV444") return "444";
  return "";
}

}  // namespace

bool looksLikeJsonConfig(const std::string& text) {
  size_t k = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (k < text.size() && (text[k] == ' ' || text[k] == '\t' || text[k] == '\r' || text[k] == '\n')) ++k;
  return k < text.size() && (text[k] == '{' || text[k] == '[');
}

namespace {

// The translation of one RVS config, in named steps; every problem is collected, then reported once.
class RvsTranslation {
public:
  RvsTranslation(const JsonValue& root, const std::string& path, const OptionTable& table)
      : root_(root), path_(path), table_(table), rvs_(root, path, problems_) {
    // RVS's path rule: names are used as written, relative to the working folder.
    std::error_code ec;
    const std::filesystem::path workingFolder = std::filesystem::current_path(ec);
    baseDir_ = ec ? std::string(".") : workingFolder.string();
  }

  std::vector<std::vector<TranslatedSetting>> run() {
    checkKeys();
    readCameraFiles();
    readLists();
    readOutputs();
    readScalars();
    problems_.throwIfAny(path_ + ": invalid RVS config:");
    readInputCameras();
    std::vector<std::vector<TranslatedSetting>> perCamera;
    for (size_t v = 0; v < virtualNames_.size(); ++v) perCamera.push_back(virtualCameraSettings(v));
    problems_.throwIfAny(path_ + ": invalid RVS config:");
    return perCamera;
  }

private:
  void set(const std::string& key, const std::string& value, const JsonValue& at) {
    if (table_.find(key)) shared_.push_back({key, value, rvs_.where(at), baseDir_});
  }
  void setDefault(const std::string& key, const std::string& value, const std::string& why) {
    shared_.push_back({key, value, path_ + " (" + why + ")", baseDir_});
  }

  // Unknown keys (with the nearest RVS key), comments, Version.
  void checkKeys() {
    for (const auto& [key, value] : root_.members) {
      if (!key.empty() && key[0] == '_') continue;  // a comment
      if (std::find(rvsKeys().begin(), rvsKeys().end(), key) != rvsKeys().end()) continue;
      std::string hint;
      size_t best = key.size() / 3 + 1;
      for (const std::string& known : rvsKeys())
        if (editDistance(key, known) < best) {
          best = editDistance(key, known);
          hint = known;
        }
      rvs_.problem(value,
                   "unknown RVS key \"" + key + "\"" + (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
    }
    if (const JsonValue* version = rvs_.find("Version")) {
      std::string v;
      if (rvs_.text(*version, "Version", v) && v.compare(0, 2, "2.") != 0 && v.compare(0, 2, "3.") != 0 &&
          v.compare(0, 2, "4.") != 0)
        rvs_.problem(*version, "\"Version\" '" + v + "': RVS configs of versions 2.x, 3.x and 4.x are read");
    }
  }

  // The camera files and their overrides.
  void readCameraFiles() {
    inputFileValue_ = rvs_.require("InputCameraParameterFile", "the camera file of the input cameras");
    virtualFileValue_ = rvs_.require("VirtualCameraParameterFile", "the camera file of the virtual cameras");
    if (inputFileValue_ && rvs_.text(*inputFileValue_, "InputCameraParameterFile", inputCameraFile_))
      set("CameraParameterFile", inputCameraFile_, *inputFileValue_);
    if (virtualFileValue_ && rvs_.text(*virtualFileValue_, "VirtualCameraParameterFile", virtualCameraFile_))
      set("VirtualCameraParameterFile", virtualCameraFile_, *virtualFileValue_);
    inputOverrides_ = rvs_.find("InputOverrides");
    virtualOverrides_ = rvs_.find("VirtualOverrides");
    for (const auto& [key, value, ours] :
         {std::tuple<const char*, const JsonValue*, const char*>{"InputOverrides", inputOverrides_,
                                                                 "InputCameraOverrides"},
          std::tuple<const char*, const JsonValue*, const char*>{"VirtualOverrides", virtualOverrides_,
                                                                 "VirtualCameraOverrides"}}) {
      if (!value) continue;
      if (value->type != JsonValue::Type::Object)
        rvs_.problem(*value, std::string("\"") + key + "\" must be an object of camera keys");
      else set(ours, compactJson(*value), *value);
    }
  }

  // The camera names and the input sequences, lists of matching lengths.
  void readLists() {
    std::vector<std::string> textures, depths;
    const JsonValue* inputNames = rvs_.require("InputCameraNames", "the input cameras");
    virtualNamesValue_ = rvs_.require("VirtualCameraNames", "the virtual cameras");
    const JsonValue* texturesValue = rvs_.require("ViewImageNames", "the texture sequences of the input cameras");
    const JsonValue* depthsValue = rvs_.require("DepthMapNames", "the depth sequences of the input cameras");
    if (inputNames) rvs_.textList(*inputNames, "InputCameraNames", inputNames_);
    if (virtualNamesValue_) rvs_.textList(*virtualNamesValue_, "VirtualCameraNames", virtualNames_);
    if (texturesValue) rvs_.textList(*texturesValue, "ViewImageNames", textures);
    if (depthsValue) rvs_.textList(*depthsValue, "DepthMapNames", depths);
    if (inputNames && inputNames_.empty() && inputNames->type == JsonValue::Type::Array)
      rvs_.problem(*inputNames, "\"InputCameraNames\" is empty");
    if (virtualNamesValue_ && virtualNames_.empty() && virtualNamesValue_->type == JsonValue::Type::Array)
      rvs_.problem(*virtualNamesValue_, "\"VirtualCameraNames\" is empty");
    for (const auto& [key, value] : {std::pair<const char*, const JsonValue*>{"ViewImageNames", texturesValue},
                                     std::pair<const char*, const JsonValue*>{"DepthMapNames", depthsValue}})
      if (value && value->type == JsonValue::Type::Array && value->items.size() != inputNames_.size())
        rvs_.problem(*value, std::string("\"") + key + "\" lists " + std::to_string(value->items.size()) +
                                 " files for " + std::to_string(inputNames_.size()) + " InputCameraNames");
    if (!inputNames) return;
    set("ReferenceCameraNames", join(inputNames_), *inputNames);
    if (texturesValue) set("ReferenceViewImageNames", join(textures), *texturesValue);
    if (depthsValue) set("ReferenceDepthMapNames", join(depths), *depthsValue);
  }

  // One output (and depth output, mask, masked depth) per virtual camera; masked textures are refused.
  void readOutputs() {
    for (const char* key : {"OutputFiles", "DepthOutputFiles", "OutputMasks", "MaskedDepthOutputFiles"}) {
      const JsonValue* value = rvs_.find(key);
      if (!value) continue;
      std::vector<std::string> files;
      if (!rvs_.textList(*value, key, files)) continue;
      if (files.size() != virtualNames_.size())
        rvs_.problem(*value, std::string("\"") + key + "\" lists " + std::to_string(files.size()) + " files for " +
                                 std::to_string(virtualNames_.size()) + " VirtualCameraNames");
      else outputs_[key] = files;
    }
    if (!rvs_.find("OutputFiles"))
      problems_.add(path_ + ": missing RVS key \"OutputFiles\" (one output sequence per virtual camera; RVS would "
                            "write nothing)");
    if (const JsonValue* value = rvs_.find("MaskedOutputFiles"))
      rvs_.problem(*value, std::string("\"MaskedOutputFiles\": masked textures are not written by ") + table_.toolName() +
                               " (doc/manual.md, \"RVS synthesis configs\"); write OutputMasks and mask the texture "
                               "with it, or remove the key");
  }

  // Frames, precision, colour space, method, blending, pose trace.
  void readScalars() {
    if (const JsonValue* value = rvs_.find("StartFrame")) {
      int64_t v = 0;
      if (rvs_.integer(*value, "StartFrame", 0, v)) set("StartFrame", std::to_string(v), *value);
    }
    if (const JsonValue* value = rvs_.find("NumberOfFrames")) {
      int64_t v = 1;
      if (rvs_.integer(*value, "NumberOfFrames", 1, v)) set("TotalNumberOfFrames", std::to_string(v), *value);
    } else {
      setDefault("TotalNumberOfFrames", "1", "RVS's default NumberOfFrames");  // ours (VSRS's) is 300
    }
    if (const JsonValue* value = rvs_.find("Precision")) {
      double v = 0;
      if (rvs_.numberValue(*value, "Precision", v)) {
        if (v == 1 || v == 2 || v == 4) set("Precision", std::to_string(int(v)), *value);
        else
          rvs_.problem(*value, "\"Precision\" " + jsonNumber(v) +
                                   ": 1, 2 or 4 expected (RVS's other values have no counterpart here)");
      }
    }
    if (const JsonValue* value = rvs_.find("ColorSpace")) {
      std::string v;
      if (rvs_.text(*value, "ColorSpace", v)) {
        if (v == "YUV" || v == "RGB") set("ColorSpace", v == "YUV" ? "0" : "1", *value);
        else rvs_.problem(*value, "\"ColorSpace\" '" + v + "': \"YUV\" or \"RGB\" expected");
      }
    }
    // RVS warps triangles between neighbouring samples ("Triangles", its default and only method); our
    // general path warps every sample and closes the cracks (doc/manual.md): the same task, another method.
    if (const JsonValue* value = rvs_.find("ViewSynthesisMethod")) {
      std::string v;
      if (rvs_.text(*value, "ViewSynthesisMethod", v)) {
        if (v == "Triangles") set("SynthesisMode", "0", *value);
        else
          rvs_.problem(*value, "\"ViewSynthesisMethod\" '" + v +
                                   "': only \"Triangles\" (RVS's default) is read; it maps to SynthesisMode 0");
      }
    } else {
      setDefault("SynthesisMode", "0", "RVS's default ViewSynthesisMethod \"Triangles\"");
    }
    if (const JsonValue* value = rvs_.find("BlendingMethod")) {
      std::string v;
      if (rvs_.text(*value, "BlendingMethod", v) && v != "Simple" && v != "Multispectral")
        rvs_.problem(*value, "\"BlendingMethod\" '" + v + "': \"Simple\" or \"Multispectral\" expected");
    }
    for (const char* key : {"BlendingFactor", "BlendingLowFreqFactor", "BlendingHighFreqFactor"})
      if (const JsonValue* value = rvs_.find(key)) {
        double v = 0;
        rvs_.numberValue(*value, key, v);  // read and checked; our blending has no such factor (doc/manual.md)
      }
    if (const JsonValue* value = rvs_.find("VirtualPoseTraceName")) {
      std::string v;
      if (rvs_.text(*value, "VirtualPoseTraceName", v)) set("VirtualPoseTraceName", v, *value);
    }
  }

  // Formats, depth bit depth, depth ranges and "no depth" from the input cameras (after the overrides),
  // as RVS takes them. A VSRS text camera file gives none: loadScene then reports what is missing.
  void readInputCameras() {
    const CameraFactsFile file(resolvePath(inputCameraFile_, baseDir_), inputOverrides_);
    if (!file.isJson()) return;
    for (const std::string& name : inputNames_)
      if (file.contains(name)) inputs_.push_back(file.facts(name, problems_));
    // A missing name is reported by loadScene, which lists the names the file has.
    if (inputs_.empty() || inputs_.size() != inputNames_.size()) return;
    const CameraFacts& first = inputs_[0];
    const std::string where = rvs_.where(*inputFileValue_);
    bool same = true, sameDepthBits = first.bitDepthDepth > 0;
    for (const CameraFacts& f : inputs_) {
      same = same && f.width == first.width && f.height == first.height && f.bitDepthColor == first.bitDepthColor &&
             f.colorSpace == first.colorSpace && f.depthColorSpace == first.depthColorSpace;
      sameDepthBits = sameDepthBits && f.bitDepthDepth == first.bitDepthDepth;
    }
    if (!same)
      problems_.add(where + ": the input cameras differ in Resolution, BitDepthColor, ColorSpace or DepthColorSpace; "
                            "every reference view must share one texture format here");
    set("SourceWidth", std::to_string(first.width), *inputFileValue_);
    set("SourceHeight", std::to_string(first.height), *inputFileValue_);
    if (first.bitDepthColor > 0) set("TextureBitDepth", std::to_string(first.bitDepthColor), *inputFileValue_);
    for (const auto& [space, key, jsonKey] :
         {std::tuple<const std::string*, const char*, const char*>{&first.colorSpace, "ChromaFormat", "ColorSpace"},
          std::tuple<const std::string*, const char*, const char*>{&first.depthColorSpace, "DepthChromaFormat",
                                                                   "DepthColorSpace"}}) {
      if (space->empty()) continue;
      if (chromaOf(*space).empty())
        problems_.add(where + ": " + jsonKey + " '" + *space +
                      "' of the input cameras: YUV420, YUV400 or YUV444 expected");
      else set(key, chromaOf(*space), *inputFileValue_);
    }
    // One depth bit depth when the input cameras agree (RVS's configs always do); else each view keeps
    // its camera's (Scene.cpp).
    if (sameDepthBits) set("DepthBitDepth", std::to_string(first.bitDepthDepth), *inputFileValue_);
    // Depth ranges: RVS (and TMIV) read a far plane of 1000 or more as infinitely far.
    std::vector<std::string> nears, fars;
    bool allRanges = true, anyInvalid = false;
    for (const CameraFacts& f : inputs_) {
      allRanges = allRanges && f.hasDepthRange;
      anyInvalid = anyInvalid || f.hasInvalidDepth;
      nears.push_back(number(f.znear));
      fars.push_back(f.zfar >= 1000 ? "inf" : number(f.zfar));
    }
    if (allRanges) {
      set("ReferenceNearestDepthValues", join(nears), *inputFileValue_);
      set("ReferenceFarthestDepthValues", join(fars), *inputFileValue_);
    }
    // RVS: level 0 is "no depth" unless every camera says HasInvalidDepth false.
    if (anyInvalid) set("MissingDepthLevel", "0", *inputFileValue_);
  }

  // The settings of virtual camera v: the shared ones, its name, outputs and depth output range, and
  // its size when its Resolution is not the inputs'; its texture bit depth must be the inputs'.
  std::vector<TranslatedSetting> virtualCameraSettings(size_t v) {
    std::vector<TranslatedSetting> settings = shared_;
    const std::string& name = virtualNames_[v];
    settings.push_back({"VirtualCameraName", name, rvs_.where(*virtualNamesValue_), baseDir_});
    using KeyPair = std::pair<const char*, const char*>;
    for (const auto& [key, ours] : {KeyPair{"OutputFiles", "OutputVirtualViewImageName"},
                                    KeyPair{"DepthOutputFiles", "OutputVirtualDepthMapName"},
                                    KeyPair{"OutputMasks", "OutputVirtualMaskName"},
                                    KeyPair{"MaskedDepthOutputFiles", "OutputMaskedVirtualDepthMapName"}})
      if (outputs_.count(key)) settings.push_back({ours, outputs_[key][v], rvs_.where(*rvs_.find(key)), baseDir_});
    if (!virtualFacts_)
      virtualFacts_ = std::make_unique<CameraFactsFile>(resolvePath(virtualCameraFile_, baseDir_), virtualOverrides_);
    if (!virtualFacts_->isJson() || !virtualFacts_->contains(name) || inputs_.empty()) return settings;
    const CameraFacts f = virtualFacts_->facts(name, problems_);
    const CameraFacts& in = inputs_[0];
    const std::string where = rvs_.where(*virtualFileValue_);
    // RVS writes each virtual view at its camera's Resolution.
    if (f.width != in.width || f.height != in.height) {
      settings.push_back({"VirtualWidth", std::to_string(f.width), where, baseDir_});
      settings.push_back({"VirtualHeight", std::to_string(f.height), where, baseDir_});
    }
    if (f.bitDepthColor > 0 && in.bitDepthColor > 0 && f.bitDepthColor != in.bitDepthColor)
      problems_.add(where + ": virtual camera '" + name + "' has BitDepthColor " + std::to_string(f.bitDepthColor) +
                    " but the input cameras " + std::to_string(in.bitDepthColor) +
                    "; the output has the inputs' texture bit depth");
    if (f.hasDepthRange && (outputs_.count("DepthOutputFiles") || outputs_.count("MaskedDepthOutputFiles"))) {
      settings.push_back({"VirtualNearestDepthValue", number(f.znear), where, baseDir_});
      settings.push_back({"VirtualFarthestDepthValue", f.zfar >= 1000 ? "inf" : number(f.zfar), where, baseDir_});
    }
    return settings;
  }

  const JsonValue& root_;
  std::string path_;
  const OptionTable& table_;
  ProblemList problems_;
  RvsReader rvs_;
  std::string baseDir_;
  std::vector<TranslatedSetting> shared_;  // the settings every virtual camera has
  const JsonValue* inputFileValue_ = nullptr;
  const JsonValue* virtualFileValue_ = nullptr;
  const JsonValue* inputOverrides_ = nullptr;
  const JsonValue* virtualOverrides_ = nullptr;
  const JsonValue* virtualNamesValue_ = nullptr;
  std::string inputCameraFile_, virtualCameraFile_;
  std::vector<std::string> inputNames_, virtualNames_;
  std::map<std::string, std::vector<std::string>> outputs_;
  std::vector<CameraFacts> inputs_;
  std::unique_ptr<CameraFactsFile> virtualFacts_;
};

}  // namespace

std::vector<std::vector<TranslatedSetting>> translateRvsConfig(const std::string& text, const std::string& path,
                                                               const OptionTable& table) {
  const JsonValue root = parseJson(text, path);
  if (root.type != JsonValue::Type::Object)
    throw InputError(path + ":" + std::to_string(root.line) + ": an RVS config is a JSON object, not " +
                     root.typeName());
  if (root.find("cameras"))
    throw InputError(path + ": this is a camera parameter file (it has \"cameras\"), not a synthesis config; name it "
                            "in CameraParameterFile, or in an RVS config's InputCameraParameterFile");
  return RvsTranslation(root, path, table).run();
}

CameraFile readCameraFileWithOverrides(const std::string& path, RotationConvention convention,
                                       const std::string& overrides, const std::string& key) {
  if (overrides.empty()) return readCameraFile(path, convention);
  const JsonValue object = parseJson(overrides, key);
  if (object.type != JsonValue::Type::Object)
    throw InputError(key + ": a JSON object of camera keys was expected, e.g. {\"BitDepthDepth\":16}");
  if (!isJsonPath(path))
    throw InputError(key + " is set, but the camera file '" + path + "' is a VSRS text file: only MPEG-I camera JSON "
                           "files take overrides");
  return parseCameraJson(compactJson(cameraDocument(path, &object)), path + " (with " + key + ")");
}

std::vector<Pose> parsePoseTrace(const std::string& text, const std::string& source) {
  std::vector<Pose> poses;
  std::istringstream lines(text);
  std::string line;
  int lineNumber = 0;
  bool blankSeen = false;
  auto fields = [](const std::string& row) {
    std::vector<std::string> out(1);
    for (char c : row) {
      if (c == ',') out.emplace_back();
      else if (c != ' ' && c != '\t' && c != '\r') out.back() += c;
    }
    return out;
  };
  while (std::getline(lines, line)) {
    ++lineNumber;
    const std::string where = source + ":" + std::to_string(lineNumber) + ": ";
    if (lineNumber == 1) {
      if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
      const std::vector<std::string> header = fields(line);
      const std::vector<std::string> expected = {"X", "Y", "Z", "Yaw", "Pitch", "Roll"};
      if (header != expected)
        throw InputError(where + "a pose trace starts with the header 'X, Y, Z, Yaw, Pitch, Roll'");
      continue;
    }
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      blankSeen = true;
      continue;
    }
    if (blankSeen) throw InputError(where + "a pose after a blank line; blank lines may only end the file");
    const std::vector<std::string> row = fields(line);
    double v[6];
    bool ok = row.size() == 6;
    for (size_t k = 0; ok && k < 6; ++k) ok = parseDouble(row[k], v[k], false);
    if (!ok) throw InputError(where + "six numbers expected (X, Y, Z, Yaw, Pitch, Roll), got '" + line + "'");
    poses.push_back(Pose{v[0], v[1], v[2], v[3], v[4], v[5]});
  }
  if (lineNumber == 0)
    throw InputError(source + ": empty pose trace (the header 'X, Y, Z, Yaw, Pitch, Roll' is expected)");
  return poses;
}

std::vector<Pose> readPoseTrace(const std::string& path) {
  return parsePoseTrace(readWholeFile(path, "pose trace"), path);
}

Camera posedCamera(const Camera& base, const Pose& pose) {
  Camera camera = base;
  // MPEG-I axes (x forward, y left, z up) to ours (x right, y down, z forward): CameraJson.h.
  camera.t = base.t + Vec3(-pose.y, -pose.z, pose.x);
  camera.R = rotationFromYawPitchRoll(pose.yaw, pose.pitch, pose.roll);
  return camera;
}

}  // namespace vs
