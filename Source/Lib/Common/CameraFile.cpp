#include "Common/CameraFile.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <utility>

#include "Common/CameraJson.h"
#include "Common/Error.h"
#include "Common/SafeOutput.h"

namespace vs {

namespace {

constexpr int kNumbersPerCamera = 23;

// What value number `index` (0-based) of a block is, for messages.
std::string valueName(int index) {
  if (index < 9) return "K[" + std::to_string(index / 3) + "][" + std::to_string(index % 3) + "]";
  if (index < 11) return "distortion[" + std::to_string(index - 9) + "]";
  const int row = (index - 11) / 4;
  const int col = (index - 11) % 4;
  if (col == 3) return "t[" + std::to_string(row) + "]";
  return "R[" + std::to_string(row) + "][" + std::to_string(col) + "]";
}

enum class NumberParse { Ok, NotANumber, NotFinite, OutOfRange };

// Locale-independent decimal parse of a whole token. A leading '+' is accepted (from_chars does not).
NumberParse parseNumber(const std::string& token, double& value) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') {
    ++first;
    if (first != last && (*first == '+' || *first == '-')) return NumberParse::NotANumber;
  }
  const auto result = std::from_chars(first, last, value, std::chars_format::general);
  if (result.ptr != last || first == last) return NumberParse::NotANumber;
  if (result.ec == std::errc::result_out_of_range) return NumberParse::OutOfRange;
  if (result.ec != std::errc()) return NumberParse::NotANumber;
  if (!std::isfinite(value)) return NumberParse::NotFinite;
  return NumberParse::Ok;
}

// Looks like a number to a reader: used to tell a numeric continuation line from a name line.
bool looksNumeric(const std::string& token) {
  double value;
  return parseNumber(token, value) != NumberParse::NotANumber;
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Whitespace-separated tokens of a line, up to a '#' comment.
std::vector<std::string> tokenize(const std::string& line) {
  std::vector<std::string> tokens;
  const std::size_t hash = line.find('#');
  const std::size_t n = hash == std::string::npos ? line.size() : hash;
  std::size_t i = 0;
  while (i < n) {
    while (i < n && isBlank(line[i])) ++i;
    std::size_t j = i;
    while (j < n && !isBlank(line[j])) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
  return tokens;
}

std::string joinTokens(const std::vector<std::string>& tokens) {
  std::string s;
  for (const auto& token : tokens) s += (s.empty() ? "" : " ") + token;
  return s;
}

void setValue(Camera& camera, int index, double value) {
  if (index < 9)
    camera.K[index / 3][index % 3] = value;
  else if (index < 11)
    camera.distortion[index - 9] = value;
  else if ((index - 11) % 4 == 3)
    camera.t[(index - 11) / 4] = value;
  else
    camera.R[(index - 11) / 4][(index - 11) % 4] = value;
}

struct PendingBlock {
  Camera camera;
  int nameLine = 0;
  int count = 0;  // numbers read so far
};

std::string shortestDecimal(double value) {
  char buffer[400];
  const double magnitude = std::fabs(value);
  const bool plain = value == 0.0 || (magnitude >= 1e-5 && magnitude < 1e15);
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value,
                                    plain ? std::chars_format::fixed : std::chars_format::general);
  VS_CHECK(result.ec == std::errc());
  return std::string(buffer, result.ptr);
}

}  // namespace

CameraFile::CameraFile(std::string path, std::vector<Camera> cameras, std::vector<std::string> warnings)
    : path_(std::move(path)), cameras_(std::move(cameras)), info_(cameras_.size()), warnings_(std::move(warnings)) {}

CameraFile::CameraFile(std::string path, std::vector<Camera> cameras, std::vector<CameraInfo> info,
                       std::vector<std::string> warnings)
    : path_(std::move(path)), cameras_(std::move(cameras)), info_(std::move(info)), warnings_(std::move(warnings)) {
  VS_CHECK(info_.size() == cameras_.size());
}

const CameraInfo& CameraFile::info(const std::string& name) const {
  for (size_t k = 0; k < cameras_.size(); ++k)
    if (cameras_[k].name == name) return info_[k];
  find(name);  // throws the message that lists the names
  VS_CHECK(false);
  return info_.front();
}

bool CameraFile::contains(const std::string& name) const {
  for (const auto& camera : cameras_)
    if (camera.name == name) return true;
  return false;
}

const Camera& CameraFile::find(const std::string& name) const {
  for (const auto& camera : cameras_)
    if (camera.name == name) return camera;
  std::string names;
  for (const auto& camera : cameras_) names += (names.empty() ? "" : ", ") + camera.name;
  throw InputError(path_ + ": no camera named '" + name + "'; the file has " + std::to_string(cameras_.size()) +
                   " camera" + (cameras_.size() == 1 ? "" : "s") + ": " + names);
}

CameraFile parseCameraText(const std::string& text, const std::string& sourceName, RotationConvention convention) {
  std::vector<Camera> cameras;
  std::vector<std::string> warnings;
  std::map<std::string, std::pair<std::size_t, int>> byName;  // name -> (index in cameras, line)
  std::vector<std::pair<int, std::string>> headerLines;

  bool pending = false;
  PendingBlock block;
  const auto where = [&](int line) { return sourceName + ":" + std::to_string(line); };
  const auto finishBlock = [&]() {
    Camera& camera = block.camera;
    applyRotationConvention(camera, convention);
    validateCamera(camera, where(block.nameLine), warnings);
    const auto found = byName.find(camera.name);
    if (found == byName.end()) {
      byName[camera.name] = {cameras.size(), block.nameLine};
      cameras.push_back(camera);
    } else {
      warnings.push_back(where(block.nameLine) + ": camera '" + camera.name +
                         "' is defined again (previous definition at line " + std::to_string(found->second.second) +
                         "); the last definition wins");
      cameras[found->second.first] = camera;
      found->second.second = block.nameLine;
    }
    pending = false;
  };
  const auto cutShort = [&]() {
    std::string message = "camera '" + block.camera.name + "' (line " + std::to_string(block.nameLine) + ") has only " +
                          std::to_string(block.count) + " of its " + std::to_string(kNumbersPerCamera) +
                          " numbers (9 of K, 2 distortion, 3 rows 'r r r t'); the next expected is " +
                          valueName(block.count);
    if (block.count == 0 && looksNumeric(block.camera.name) && !cameras.empty())
      message +=
          " (if '" + block.camera.name + "' is not meant as a camera name, the camera before it has a number too many)";
    return message;
  };

  std::size_t position = 0;
  int lineNumber = 0;
  while (position < text.size()) {
    // Lines end with LF, CRLF or a lone CR.
    std::size_t end = text.find_first_of("\r\n", position);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(position, end - position);
    position = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    ++lineNumber;
    // UTF-8 BOM: at the start of the file, or of any line (files joined with cat); never part of a name.
    if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);

    const std::vector<std::string> tokens = tokenize(line);
    if (tokens.empty()) continue;

    if (!pending) {
      if (tokens.size() == 1) {
        block = PendingBlock();
        block.camera.name = tokens[0];
        block.nameLine = lineNumber;
        pending = true;
      } else {
        headerLines.emplace_back(lineNumber, joinTokens(tokens));
      }
      continue;
    }

    if (tokens.size() == 1 && !looksNumeric(tokens[0]))
      throw InputError(where(lineNumber) + ": found '" + tokens[0] +
                       "', which reads as the name of a new camera, but " + cutShort());

    for (const std::string& token : tokens) {
      if (!pending)
        throw InputError(where(lineNumber) + ": unexpected '" + token + "' after the " +
                         std::to_string(kNumbersPerCamera) + " numbers of camera '" + block.camera.name + "' (line " +
                         std::to_string(block.nameLine) + "); expected the end of the line");
      double value = 0.0;
      switch (parseNumber(token, value)) {
        case NumberParse::Ok:
          break;
        case NumberParse::OutOfRange:
          throw InputError(where(lineNumber) + ": '" + token + "' for " + valueName(block.count) + " of camera '" +
                           block.camera.name + "' is out of the range of a double-precision number");
        case NumberParse::NotFinite:
          throw InputError(where(lineNumber) + ": '" + token + "' for " + valueName(block.count) + " of camera '" +
                           block.camera.name + "' is not a finite number; expected a finite decimal number");
        case NumberParse::NotANumber:
          throw InputError(where(lineNumber) + ": expected a number for " + valueName(block.count) + " of camera '" +
                           block.camera.name + "' (line " + std::to_string(block.nameLine) + "), found '" + token +
                           "'");
      }
      setValue(block.camera, block.count, value);
      if (++block.count == kNumbersPerCamera) finishBlock();
    }
  }
  if (pending) throw InputError(where(lineNumber) + ": the file ends early: " + cutShort());

  if (!headerLines.empty()) {
    std::string list;
    const std::size_t shown = std::min<std::size_t>(headerLines.size(), 3);
    for (std::size_t i = 0; i < shown; ++i)
      list += (i ? ", " : "") + std::string("line ") + std::to_string(headerLines[i].first) + " '" +
              headerLines[i].second + "'";
    if (headerLines.size() > shown) list += ", ...";
    warnings.push_back(sourceName + ": skipped " + std::to_string(headerLines.size()) + " header line" +
                       (headerLines.size() == 1 ? "" : "s") +
                       " outside camera blocks (more than one token where a camera name was expected): " + list);
  }
  if (cameras.empty())
    throw InputError(sourceName + ": no camera found; expected blocks of a name line followed by " +
                     std::to_string(kNumbersPerCamera) + " numbers (K 3x3, 2 distortion values, 3 rows 'r r r t')");
  return CameraFile(sourceName, std::move(cameras), std::move(warnings));
}

CameraFile readCameraFile(const std::string& path, RotationConvention convention) {
  // A folder opens as an empty stream, and a video given by mistake would be read whole: say so first.
  constexpr std::uintmax_t kMaxCameraFileBytes = std::uintmax_t(16) << 20;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError("camera parameter file '" + path + "' is a folder, not a camera parameter file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > kMaxCameraFileBytes)
    throw InputError("camera parameter file '" + path + "' is " + std::to_string(bytes) + " bytes; at most " +
                     std::to_string(kMaxCameraFileBytes) + " expected (is it a camera parameter file?)");
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0) return readCameraJson(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open camera parameter file '" + path + "': " + std::strerror(errno));
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError("cannot read camera parameter file '" + path + "': " + std::strerror(errno));
  return parseCameraText(content.str(), path, convention);
}

std::string formatCamera(const Camera& camera) {
  std::string s = camera.name + "\n";
  for (int r = 0; r < 3; ++r)
    s += shortestDecimal(camera.K[r][0]) + " " + shortestDecimal(camera.K[r][1]) + " " +
         shortestDecimal(camera.K[r][2]) + "\n";
  s += shortestDecimal(camera.distortion[0]) + "\n";
  s += shortestDecimal(camera.distortion[1]) + "\n";
  for (int r = 0; r < 3; ++r)
    s += shortestDecimal(camera.R[r][0]) + " " + shortestDecimal(camera.R[r][1]) + " " +
         shortestDecimal(camera.R[r][2]) + " " + shortestDecimal(camera.t[r]) + "\n";
  return s;
}

void writeCameraFile(const std::string& path, const std::vector<Camera>& cameras) {
  std::string text;
  for (const auto& camera : cameras) {
    const std::vector<std::string> tokens = tokenize(camera.name);
    if (tokens.size() != 1 || tokens[0] != camera.name)
      throw InputError("cannot write camera file '" + path + "': camera name '" + camera.name +
                       "' is not one token without spaces or '#'");
    if (camera.isEquirectangular())
      throw InputError("cannot write camera file '" + path + "': camera '" + camera.name +
                       "' is equirectangular, and the VSRS text format holds pinhole cameras only (write MPEG-I JSON)");
    bool finite = isFinite(camera.K) && isFinite(camera.R) && isFinite(camera.t) &&
                  std::isfinite(camera.distortion[0]) && std::isfinite(camera.distortion[1]);
    if (!finite)
      throw InputError("cannot write camera file '" + path + "': camera '" + camera.name +
                       "' holds a number that is not finite");
    text += formatCamera(camera) + "\n";
  }
  // Through a temporary file: a failed write leaves a previous file as it was (SafeOutput.h).
  SafeOutputFile out(path, {}, "camera file");
  out.write(text);
  out.commit();
}

}  // namespace vs
