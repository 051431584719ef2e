#pragma once
// Configuration: one option table (key, type, default, range, help) shared by every executable, and
// the parsed values of a VSRS-style config file plus Key=Value overrides.
//
// Syntax (as VSRS writes it): `Key value # comment`, spaces or tabs, CRLF or LF, the last setting of a
// key wins; `Key=Value` (or `Key value`) arguments after the file override it.
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace vs {

// Collects every problem found, then fails once (VVenC's confirm step).
class ProblemList {
public:
  void add(const std::string& problem) { problems_.push_back(problem); }
  bool empty() const { return problems_.empty(); }
  const std::vector<std::string>& problems() const { return problems_; }
  // Throws InputError whose message is `header` followed by one problem a line; no-op when empty.
  void throwIfAny(const std::string& header) const;

private:
  std::vector<std::string> problems_;
};

enum class OptionType {
  Int,     // decimal integer in [minValue, maxValue]
  Double,  // finite real in [minValue, maxValue]; `inf` too when allowInfinity
  String,  // any text without control characters
  Path,    // a file name, resolved against the folder of the config file that names it
  TextList,  // comma-separated items, e.g. camera names "v1,v2,v4"
  PathList,  // comma-separated file names, each resolved like a Path
  Choice,  // one of `choices`
};

struct OptionSpec {
  std::string key;
  OptionType type = OptionType::Int;
  std::string defaultValue;        // used when the key is not set; empty with required: must be given
  bool required = false;           // the tool cannot run without it (checked by the tool's settings)
  double minValue = -std::numeric_limits<double>::max();  // Int and Double range, inclusive
  double maxValue = std::numeric_limits<double>::max();
  bool allowInfinity = false;      // Double: `inf` accepted (Zfar)
  bool allowAuto = false;          // Int: `auto` accepted (the plan decides; Config::isAuto)
  std::vector<std::string> choices;  // Choice
  std::string help;                // one line: what it means
  std::string vsrsDefault;         // VSRS 4.2's default, for the manual; "-" when VSRS has no such key
  std::string section;             // heading it is listed under in --help and in the manual
};

class OptionTable {
public:
  explicit OptionTable(std::string toolName) : toolName_(std::move(toolName)) {}
  void add(OptionSpec spec);
  const OptionSpec* find(const std::string& key) const;
  const std::vector<OptionSpec>& options() const { return options_; }
  const std::string& toolName() const { return toolName_; }
  // The known key closest to `key` (case-insensitive edit distance); empty when nothing is close.
  std::string nearestKey(const std::string& key) const;
  // One block per key: name, type and range, default, meaning; for --help.
  std::string helpText() const;
  // The same as a Markdown table per section (| key | values | default | VSRS 4.2 | meaning |), for
  // the user manual; a test keeps doc/ equal to it.
  std::string markdownTable() const;
  // A config file of every key, each under comment lines with its meaning, values and default: keys
  // with a default are set to it, the others are commented out (`#Key`). The files in cfg/ are this
  // text; a test keeps them equal (regenerate with scripts/update_manual.sh).
  std::string configTemplate() const;

private:
  std::string toolName_;
  std::vector<OptionSpec> options_;
  std::map<std::string, size_t> index_;
};

// Where a value came from, for messages: "file.cfg:12" or "command line".
struct SettingOrigin {
  std::string where;
  std::string baseDir;  // folder that relative paths resolve against
};

class Config {
public:
  // Reads `cfgPath` (may be empty: defaults and overrides only), then the overrides ("Key=Value"),
  // checks syntax, keys and values against the table, and throws InputError listing every problem.
  // An RVS synthesis config (a JSON object, Common/RvsConfig.h) is read too when it names exactly one
  // virtual camera; loadAll() reads one with several.
  static Config load(const OptionTable& table, const std::string& cfgPath,
                     const std::vector<std::string>& overrides);
  // One Config per virtual camera: a VSRS config gives one; an RVS config one per entry of its
  // VirtualCameraNames, each with the overrides applied.
  static std::vector<Config> loadAll(const OptionTable& table, const std::string& cfgPath,
                                     const std::vector<std::string>& overrides);
  // Settings given as (key, value, where, baseDir), e.g. translated from an RVS config, then the
  // overrides; same checks as load(). `name` is the config's path for messages.
  static Config fromSettings(const OptionTable& table, const std::string& name,
                             const std::vector<std::tuple<std::string, std::string, SettingOrigin>>& settings,
                             const std::vector<std::string>& overrides = {});
  // Parses config text as if read from `name` (tests, fuzzing); same checks as load().
  static Config fromText(const OptionTable& table, const std::string& text, const std::string& name,
                         const std::string& baseDir, const std::vector<std::string>& overrides = {});

  const OptionTable& table() const { return table_; }
  const std::string& configPath() const { return configPath_; }

  bool isSet(const std::string& key) const;  // given in the file or on the command line
  std::string raw(const std::string& key) const;  // effective text value (default when unset)
  int64_t getInt(const std::string& key) const;  // not for a value `auto` (isAuto first)
  // The value is `auto` (an Int option with allowAuto).
  bool isAuto(const std::string& key) const;
  double getDouble(const std::string& key) const;
  std::string getString(const std::string& key) const;
  // File name with `\` turned into `/`, resolved against the folder of the config that set it
  // (command line: the working directory). Empty when the value is empty.
  std::string getPath(const std::string& key) const;
  // The items of a TextList, or of a PathList resolved like getPath; empty when unset.
  std::vector<std::string> getList(const std::string& key) const;
  // "file.cfg:12", "command line" or "default".
  std::string origin(const std::string& key) const;

  // Adds "missing required key" problems for every `required` key that is not set, and for each of
  // `extraKeys` (keys required in the chosen mode).
  void requireKeys(ProblemList& problems, const std::vector<std::string>& extraKeys = {}) const;

  // The value effectiveText() shows for `key`: raw(key), or "(not set)" for an unset key without a
  // default. The JSON summary and --print-config write the same text.
  std::string effectiveValue(const std::string& key) const;
  // Every key with its effective value, VSRS style ("Key   value"), one a line.
  std::string effectiveText() const;

private:
  struct Setting {
    std::string value;
    SettingOrigin origin;
  };
  explicit Config(const OptionTable& table) : table_(table) {}
  void parseText(const std::string& text, const std::string& name, const std::string& baseDir,
                 ProblemList& problems);
  void applyOverride(const std::string& argument, ProblemList& problems);
  void setValue(const std::string& key, const std::string& value, const SettingOrigin& origin);
  void validateValues(ProblemList& problems) const;
  const OptionSpec& spec(const std::string& key) const;  // aborts on a key not in the table (a bug)

  OptionTable table_;  // a copy: a config outlives the table it was read with
  std::string configPath_;
  std::map<std::string, Setting> settings_;
};

// Parses a double the way every key does: the whole text must be a number; `inf` only when allowed.
bool parseDouble(const std::string& text, double& value, bool allowInfinity);
bool parseInt(const std::string& text, int64_t& value);
// "a,b,c" -> {"a", "b", "c"}; empty items are kept (and refused by the value checks).
std::vector<std::string> splitList(const std::string& text);
// `\` -> `/`, repeated separators collapsed; relative names resolved against baseDir.
std::string resolvePath(const std::string& name, const std::string& baseDir);

}  // namespace vs
