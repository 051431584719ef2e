#include "Common/Config.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Common/Error.h"
#include "Common/RvsConfig.h"

namespace vs {

namespace {

constexpr size_t kMaxLineLength = 4096;
constexpr uintmax_t kMaxConfigBytes = 1u << 20;

std::string toLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> previous(b.size() + 1), current(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::vector<std::string> splitWhitespace(const std::string& line) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

// First control character (other than tab) in `text`, or npos. Bytes >= 0x80 are allowed: real
// configs carry file names in legacy 8-bit encodings.
size_t findControlCharacter(const std::string& text) {
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) return i;
  }
  return std::string::npos;
}

std::string describeByte(unsigned char c) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "0x%02x", c);
  return buffer;
}

std::string formatNumber(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

std::string typeDescription(const OptionSpec& spec) {
  switch (spec.type) {
    case OptionType::Int:
      return "integer in [" + formatNumber(spec.minValue) + ", " + formatNumber(spec.maxValue) + "]" +
             (spec.allowAuto ? " or auto" : "");
    case OptionType::Double: {
      std::string text = spec.minValue <= -std::numeric_limits<double>::max() && spec.maxValue >= std::numeric_limits<double>::max()
                             ? std::string("finite number")
                             : "number in [" + formatNumber(spec.minValue) + ", " + formatNumber(spec.maxValue) + "]";
      if (spec.allowInfinity) text += " or inf";
      return text;
    }
    case OptionType::String: return "text";
    case OptionType::Path: return "file name";
    case OptionType::TextList: return "comma-separated names";
    case OptionType::PathList: return "comma-separated file names";
    case OptionType::Choice: {
      std::string text = "one of";
      for (size_t i = 0; i < spec.choices.size(); ++i) text += (i ? ", " : " ") + spec.choices[i];
      return text;
    }
  }
  return "?";
}

}  // namespace

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

void ProblemList::throwIfAny(const std::string& header) const {
  if (problems_.empty()) return;
  // A binary file read as a config has a problem on every line: show the first ones, count the rest.
  constexpr size_t kMaxProblemsShown = 50;
  std::string message = header;
  for (size_t i = 0; i < problems_.size() && i < kMaxProblemsShown; ++i) message += "\n  " + problems_[i];
  if (problems_.size() > kMaxProblemsShown)
    message += "\n  ... and " + std::to_string(problems_.size() - kMaxProblemsShown) + " more problems";
  throw InputError(message);
}

bool parseDouble(const std::string& text, double& value, bool allowInfinity) {
  if (text.empty()) return false;
  const std::string lower = toLower(text);
  if (lower == "inf" || lower == "+inf" || lower == "infinity" || lower == "+infinity") {
    if (!allowInfinity) return false;
    value = HUGE_VAL;
    return true;
  }
  // Only plain decimal notation: strtod would also take hex floats, "nan" and "infinity".
  for (char c : lower)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == '+' || c == '-'))
      return false;
  errno = 0;
  char* end = nullptr;
  const double parsed = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(parsed)) return false;
  value = parsed;
  return true;
}

bool parseInt(const std::string& text, int64_t& value) {
  if (text.empty()) return false;
  size_t i = (text[0] == '+' || text[0] == '-') ? 1 : 0;
  if (i == text.size()) return false;
  for (size_t k = i; k < text.size(); ++k)
    if (!std::isdigit(static_cast<unsigned char>(text[k]))) return false;
  errno = 0;
  char* end = nullptr;
  const long long parsed = std::strtoll(text.c_str(), &end, 10);
  if (errno == ERANGE || end != text.c_str() + text.size()) return false;
  value = parsed;
  return true;
}

std::string resolvePath(const std::string& name, const std::string& baseDir) {
  if (name.empty()) return name;
  std::string normalised;
  normalised.reserve(name.size());
  for (char c : name) {
    const char s = c == '\\' ? '/' : c;
    // Collapse repeated separators ("..\\dir\\file" as written in VSRS samples), except a leading
    // "//" which may be a network path.
    if (s == '/' && !normalised.empty() && normalised.back() == '/' && normalised.size() > 1) continue;
    normalised += s;
  }
  const bool windowsDrive = normalised.size() >= 2 && std::isalpha(static_cast<unsigned char>(normalised[0])) &&
                            normalised[1] == ':';
  std::filesystem::path path(normalised);
  if (path.is_absolute() || windowsDrive || baseDir.empty()) return path.lexically_normal().string();
  return (std::filesystem::path(baseDir) / path).lexically_normal().string();
}

// ---------------------------------------------------------------------------------------------------
// OptionTable

void OptionTable::add(OptionSpec spec) {
  VS_CHECK_MSG(index_.count(spec.key) == 0, spec.key.c_str());
  index_[spec.key] = options_.size();
  options_.push_back(std::move(spec));
}

const OptionSpec* OptionTable::find(const std::string& key) const {
  auto it = index_.find(key);
  return it == index_.end() ? nullptr : &options_[it->second];
}

std::string OptionTable::nearestKey(const std::string& key) const {
  const std::string lower = toLower(key);
  std::string best;
  size_t bestDistance = std::string::npos;
  const size_t allowed = std::max<size_t>(2, key.size() / 3);
  for (const OptionSpec& spec : options_) {
    // The distance is at least the difference in length: skip the quadratic work for a long junk key.
    const size_t lengthDifference =
        lower.size() > spec.key.size() ? lower.size() - spec.key.size() : spec.key.size() - lower.size();
    if (lengthDifference > allowed) continue;
    const size_t d = editDistance(lower, toLower(spec.key));
    if (d < bestDistance) {
      bestDistance = d;
      best = spec.key;
    }
  }
  return bestDistance <= allowed ? best : std::string();
}

std::string OptionTable::helpText() const {
  std::ostringstream out;
  std::string section;
  for (const OptionSpec& spec : options_) {
    if (spec.section != section) {
      section = spec.section;
      out << "\n" << section << ":\n";
    }
    out << "  " << spec.key << "  (" << typeDescription(spec) << "; default: ";
    if (spec.required && spec.defaultValue.empty()) out << "required";
    else out << (spec.defaultValue.empty() ? "empty" : spec.defaultValue);
    if (!spec.vsrsDefault.empty() && spec.vsrsDefault != "-") out << "; VSRS 4.2: " << spec.vsrsDefault;
    out << ")\n      " << spec.help << "\n";
  }
  return out.str();
}

std::string OptionTable::markdownTable() const {
  std::ostringstream out;
  std::string section;
  for (const OptionSpec& spec : options_) {
    if (spec.section != section) {
      section = spec.section;
      out << "\n### " << section << "\n\n| key | values | default | VSRS 4.2 | meaning |\n|---|---|---|---|---|\n";
    }
    std::string defaultText = spec.required && spec.defaultValue.empty() ? "required" : spec.defaultValue;
    if (defaultText.empty()) defaultText = "(none)";
    out << "| `" << spec.key << "` | " << typeDescription(spec) << " | " << defaultText << " | "
        << (spec.vsrsDefault.empty() ? "-" : spec.vsrsDefault) << " | " << spec.help << " |\n";
  }
  return out.str();
}

namespace {

// `text` as comment lines of at most 100 columns, broken between words.
void writeWrappedComment(std::ostream& out, const std::string& text) {
  std::istringstream words(text);
  std::string word, line = "#";
  while (words >> word) {
    if (line.size() > 1 && line.size() + 1 + word.size() > 100) {
      out << line << "\n";
      line = "#";
    }
    line += " " + word;
  }
  out << line << "\n";
}

}  // namespace

std::string OptionTable::configTemplate() const {
  std::ostringstream out;
  const std::string rule(99, '-');
  out << "# " << toolName_ << ": every key, with its meaning, values and default.\n";
  writeWrappedComment(out, "Generated from " + toolName_ +
                               "'s option table; do not edit (scripts/update_manual.sh writes it, "
                               "Test/Unit/ConfigTemplateTest.cpp keeps it equal to the table). Copy it to start a "
                               "config: the keys set below hold their defaults; lines starting with #Key are keys "
                               "without a default (remove the # and give a value). Syntax: `Key value # comment`; "
                               "the last setting of a key wins; `Key=Value` arguments after the file override it; "
                               "file names are relative to the folder of the file that names them.");
  std::string section;
  for (const OptionSpec& spec : options_) {
    if (spec.section != section) {
      section = spec.section;
      out << "\n#" << rule << "\n# " << section << "\n#" << rule << "\n";
    }
    out << "\n";
    writeWrappedComment(out, spec.help + ".");
    std::string facts = "Values: " + typeDescription(spec) + ".";
    if (spec.required && spec.defaultValue.empty()) facts += " Required.";
    if (!spec.vsrsDefault.empty() && spec.vsrsDefault != "-") facts += " VSRS 4.2 default: " + spec.vsrsDefault + ".";
    writeWrappedComment(out, facts);
    std::string line = spec.defaultValue.empty() ? "#" + spec.key : spec.key;
    line.resize(std::max<size_t>(line.size() + 1, 33), ' ');
    line += spec.defaultValue;
    while (line.back() == ' ') line.pop_back();  // no invisible trailing blanks
    out << line << "\n";
  }
  return out.str();
}

// ---------------------------------------------------------------------------------------------------
// Config

namespace {

// The text of config file `cfgPath`, after the checks every config passes (exists, a file, not huge).
std::string readConfigText(const std::string& cfgPath) {
  std::error_code ec;
  if (!std::filesystem::exists(cfgPath, ec)) throw InputError(cfgPath + ": config file not found");
  if (std::filesystem::is_directory(cfgPath, ec)) throw InputError(cfgPath + ": is a folder, not a config file");
  const uintmax_t size = std::filesystem::file_size(cfgPath, ec);
  if (ec) throw InputError(cfgPath + ": cannot read the config file: " + ec.message());
  if (size > kMaxConfigBytes)
    throw InputError(cfgPath + ": config file is " + std::to_string(size) + " bytes; at most " +
                     std::to_string(kMaxConfigBytes) + " expected (is it a config file?)");
  std::ifstream in(cfgPath, std::ios::binary);
  if (!in) throw InputError(cfgPath + ": cannot open the config file for reading");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(cfgPath + ": error while reading the config file");
  return text;
}

// One Config per virtual camera of an RVS config (Common/RvsConfig.h).
std::vector<Config> rvsConfigs(const OptionTable& table, const std::string& text, const std::string& cfgPath,
                               const std::vector<std::string>& overrides) {
  std::vector<Config> configs;
  for (const std::vector<TranslatedSetting>& translated : translateRvsConfig(text, cfgPath, table)) {
    std::vector<std::tuple<std::string, std::string, SettingOrigin>> settings;
    for (const TranslatedSetting& s : translated) settings.emplace_back(s.key, s.value, SettingOrigin{s.where, s.baseDir});
    configs.push_back(Config::fromSettings(table, cfgPath, settings, overrides));
  }
  return configs;
}

}  // namespace

Config Config::load(const OptionTable& table, const std::string& cfgPath, const std::vector<std::string>& overrides) {
  Config config(table);
  ProblemList problems;
  if (!cfgPath.empty()) {
    config.configPath_ = cfgPath;
    const std::string text = readConfigText(cfgPath);
    if (looksLikeJsonConfig(text)) {
      std::vector<Config> configs = rvsConfigs(table, text, cfgPath, overrides);
      if (configs.size() != 1)
        throw InputError(cfgPath + ": this RVS config names " + std::to_string(configs.size()) +
                         " virtual cameras; read it with Config::loadAll (one configuration per virtual camera)");
      return configs[0];
    }
    std::string baseDir = std::filesystem::path(cfgPath).parent_path().string();
    if (baseDir.empty()) baseDir = ".";
    config.parseText(text, cfgPath, baseDir, problems);
  }
  for (const std::string& argument : overrides) config.applyOverride(argument, problems);
  config.validateValues(problems);
  problems.throwIfAny((cfgPath.empty() ? std::string("configuration") : cfgPath) + ": invalid configuration:");
  return config;
}

std::vector<Config> Config::loadAll(const OptionTable& table, const std::string& cfgPath,
                                    const std::vector<std::string>& overrides) {
  if (!cfgPath.empty()) {
    const std::string text = readConfigText(cfgPath);
    if (looksLikeJsonConfig(text)) return rvsConfigs(table, text, cfgPath, overrides);
  }
  return {load(table, cfgPath, overrides)};
}

Config Config::fromSettings(const OptionTable& table, const std::string& name,
                            const std::vector<std::tuple<std::string, std::string, SettingOrigin>>& settings,
                            const std::vector<std::string>& overrides) {
  Config config(table);
  config.configPath_ = name;
  ProblemList problems;
  for (const auto& [key, value, origin] : settings) {
    if (!table.find(key)) {
      problems.add(origin.where + ": unknown key '" + key + "'");
      continue;
    }
    if (findControlCharacter(value) != std::string::npos) {
      problems.add(origin.where + ": value of '" + key + "' holds a control character");
      continue;
    }
    config.setValue(key, value, origin);
  }
  for (const std::string& argument : overrides) config.applyOverride(argument, problems);
  config.validateValues(problems);
  problems.throwIfAny(name + ": invalid configuration:");
  return config;
}

Config Config::fromText(const OptionTable& table, const std::string& text, const std::string& name,
                        const std::string& baseDir, const std::vector<std::string>& overrides) {
  Config config(table);
  config.configPath_ = name;
  ProblemList problems;
  config.parseText(text, name, baseDir, problems);
  for (const std::string& argument : overrides) config.applyOverride(argument, problems);
  config.validateValues(problems);
  problems.throwIfAny(name + ": invalid configuration:");
  return config;
}

void Config::parseText(const std::string& text, const std::string& name, const std::string& baseDir,
                       ProblemList& problems) {
  size_t lineStart = 0;
  int lineNumber = 0;
  while (lineStart < text.size()) {
    size_t lineEnd = text.find('\n', lineStart);
    if (lineEnd == std::string::npos) lineEnd = text.size();
    ++lineNumber;
    const std::string where = name + ":" + std::to_string(lineNumber);
    std::string line = text.substr(lineStart, std::min(lineEnd - lineStart, kMaxLineLength + 1));
    const size_t fullLength = lineEnd - lineStart;
    lineStart = lineEnd + 1;
    if (fullLength > kMaxLineLength) {
      problems.add(where + ": line is " + std::to_string(fullLength) + " characters long; at most " +
                   std::to_string(kMaxLineLength) + " expected");
      continue;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF
    // UTF-8 BOM (Notepad): at the start of the file, or of any line (files joined with cat).
    if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const size_t control = findControlCharacter(line);
    if (control != std::string::npos) {
      problems.add(where + ": unexpected control byte " + describeByte(static_cast<unsigned char>(line[control])) +
                   " at column " + std::to_string(control + 1) + " (binary data in a text config?)");
      continue;
    }
    const std::vector<std::string> tokens = splitWhitespace(line);
    if (tokens.empty()) continue;
    const std::string& key = tokens[0];
    if (!table_.find(key)) {
      const std::string hint = table_.nearestKey(key);
      problems.add(where + ": unknown key '" + key + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
      continue;
    }
    if (tokens.size() == 1) {
      problems.add(where + ": key '" + key + "' has no value; expected " + typeDescription(spec(key)));
      continue;
    }
    if (tokens.size() > 2) {
      problems.add(where + ": key '" + key + "' takes one value but " + std::to_string(tokens.size() - 1) +
                   " were given ('" + tokens[1] + "' '" + tokens[2] + "'" + (tokens.size() > 3 ? " ..." : "") +
                   "); put comments after '#'");
      continue;
    }
    setValue(key, tokens[1], SettingOrigin{where, baseDir});
  }
}

void Config::applyOverride(const std::string& argument, ProblemList& problems) {
  const std::string where = "command line";
  const size_t eq = argument.find('=');
  if (eq == std::string::npos || eq == 0) {
    problems.add(where + ": argument '" + argument + "' is not of the form Key=Value");
    return;
  }
  const std::string key = argument.substr(0, eq);
  const std::string value = argument.substr(eq + 1);
  if (!table_.find(key)) {
    const std::string hint = table_.nearestKey(key);
    problems.add(where + ": unknown key '" + key + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
    return;
  }
  if (findControlCharacter(value) != std::string::npos) {
    problems.add(where + ": value of '" + key + "' holds a control character");
    return;
  }
  // The throwing overload would abort the tool when the working folder has been removed; "." then
  // leaves relative names relative, and opening them fails with the file's name.
  std::error_code ec;
  const std::filesystem::path workingFolder = std::filesystem::current_path(ec);
  setValue(key, value, SettingOrigin{where, ec ? std::string(".") : workingFolder.string()});
}

void Config::setValue(const std::string& key, const std::string& value, const SettingOrigin& origin) {
  // The last setting wins; values are checked once all are known (validateValues).
  settings_[key] = Setting{value, origin};
}

void Config::validateValues(ProblemList& problems) const {
  for (const auto& [key, setting] : settings_) {
    const OptionSpec& s = spec(key);
    const std::string& value = setting.value;
    const std::string prefix = setting.origin.where + ": " + key + " = '" + value + "': ";
    switch (s.type) {
      case OptionType::Int: {
        int64_t v = 0;
        if (s.allowAuto && value == "auto") break;
        if (!parseInt(value, v) || double(v) < s.minValue || double(v) > s.maxValue)
          problems.add(prefix + "expected an " + typeDescription(s));
        break;
      }
      case OptionType::Double: {
        double v = 0;
        if (!parseDouble(value, v, s.allowInfinity) || (std::isfinite(v) && (v < s.minValue || v > s.maxValue)))
          problems.add(prefix + "expected a " + typeDescription(s));
        break;
      }
      case OptionType::Choice:
        if (std::find(s.choices.begin(), s.choices.end(), value) == s.choices.end())
          problems.add(prefix + "expected " + typeDescription(s));
        break;
      case OptionType::String:
      case OptionType::Path:
        if (value.empty()) problems.add(prefix + "expected a non-empty " + typeDescription(s));
        break;
      case OptionType::TextList:
      case OptionType::PathList:
        for (const std::string& item : splitList(value))
          if (item.empty()) {
            problems.add(prefix + "expected " + typeDescription(s) + " without empty items");
            break;
          }
        break;
    }
  }
}

const OptionSpec& Config::spec(const std::string& key) const {
  const OptionSpec* s = table_.find(key);
  VS_CHECK_MSG(s != nullptr, key.c_str());
  return *s;
}

bool Config::isSet(const std::string& key) const {
  spec(key);
  return settings_.count(key) != 0;
}

std::string Config::raw(const std::string& key) const {
  const OptionSpec& s = spec(key);
  auto it = settings_.find(key);
  return it == settings_.end() ? s.defaultValue : it->second.value;
}

int64_t Config::getInt(const std::string& key) const {
  VS_CHECK(spec(key).type == OptionType::Int);
  int64_t v = 0;
  VS_CHECK_MSG(parseInt(raw(key), v), key.c_str());  // values were validated in load()
  return v;
}

bool Config::isAuto(const std::string& key) const { return spec(key).allowAuto && raw(key) == "auto"; }

double Config::getDouble(const std::string& key) const {
  const OptionSpec& s = spec(key);
  VS_CHECK(s.type == OptionType::Double);
  double v = 0;
  VS_CHECK_MSG(parseDouble(raw(key), v, s.allowInfinity), key.c_str());
  return v;
}

std::string Config::getString(const std::string& key) const { return raw(key); }

std::string Config::getPath(const std::string& key) const {
  VS_CHECK(spec(key).type == OptionType::Path);
  auto it = settings_.find(key);
  if (it == settings_.end()) return resolvePath(spec(key).defaultValue, "");
  return resolvePath(it->second.value, it->second.origin.baseDir);
}

std::vector<std::string> Config::getList(const std::string& key) const {
  const OptionSpec& s = spec(key);
  VS_CHECK(s.type == OptionType::TextList || s.type == OptionType::PathList);
  auto it = settings_.find(key);
  if (it == settings_.end()) return {};
  std::vector<std::string> items = splitList(it->second.value);
  if (s.type == OptionType::PathList)
    for (std::string& item : items) item = resolvePath(item, it->second.origin.baseDir);
  return items;
}

std::string Config::origin(const std::string& key) const {
  spec(key);
  auto it = settings_.find(key);
  return it == settings_.end() ? "default" : it->second.origin.where;
}

void Config::requireKeys(ProblemList& problems, const std::vector<std::string>& extraKeys) const {
  std::vector<std::string> keys;
  for (const OptionSpec& s : table_.options())
    if (s.required) keys.push_back(s.key);
  for (const std::string& key : extraKeys)
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  for (const std::string& key : keys)
    if (!isSet(key))
      problems.add((configPath_.empty() ? std::string("configuration") : configPath_) + ": missing required key '" +
                   key + "' (" + spec(key).help + ")");
}

std::string Config::effectiveValue(const std::string& key) const {
  return !isSet(key) && spec(key).defaultValue.empty() ? "(not set)" : raw(key);
}

std::string Config::effectiveText() const {
  std::ostringstream out;
  for (const OptionSpec& s : table_.options()) {
    char line[64];
    std::snprintf(line, sizeof line, "%-32s ", s.key.c_str());
    out << line << effectiveValue(s.key) << "\n";
  }
  return out.str();
}

}  // namespace vs
