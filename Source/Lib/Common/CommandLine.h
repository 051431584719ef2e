#pragma once
// The command-line front every executable shares (ViewSyn, MeshRender, SceneGen, CameraConvert,
// SynthBench, YuvPsnr, MetricsBench; tools with positional arguments of their own fit too):
//   - a table of options (name, value names, help, a check of the values) and, for config-driven tools,
//     the option table of keys: --help prints usage generated from both on stdout (exit 0);
//   - one parser that reads every argument and collects every problem (unknown option, missing or bad
//     value, wrong positional arguments), prints them all and exits 2; it never calls exit();
//   - one catch around the run: bad input (InputError), out of memory, file-system and any other
//     library exception become "TOOL: error: ..." on stderr and exit 1.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Scene.h"

namespace vs {

// What an option's values must look like: "" when `values` are fine, else what is wrong with them
// (the parser adds the option's name).
using ValueCheck = std::function<std::string(const std::vector<std::string>& values)>;
ValueCheck integerValues(int64_t minValue, int64_t maxValue);      // each value an integer in range
ValueCheck integerListValue(int64_t minValue, int64_t maxValue);   // one comma-separated list of them
ValueCheck realValues(bool lastMayBeInfinite);                     // each a finite number (the last: or inf)
ValueCheck md5Value();                                             // 32 hexadecimal digits
ValueCheck chromaFormatValue();                                    // 420, 444 or 400

// A frame's width or height: decimal digits only (no sign), 1..kMaxFrameSide; false when it is not.
constexpr int kMaxFrameSide = 65536;
bool parseFrameSide(const std::string& text, int& side);
// "WIDTHxHEIGHT" (a frame size as one argument), both as parseFrameSide: false when it is not.
bool parseFrameSize(const std::string& text, int& width, int& height);

struct CommandOption {
  std::string name;                    // "--runs"
  std::vector<std::string> valueNames;  // {"N"}; empty: a flag
  std::string help;                    // one line
  ValueCheck check = nullptr;          // null: any text
  // An action replaces the run (--check, --print-config): it must come first and is given to run()
  // as CommandLine::action.
  bool action = false;
};

// What the parser found, for the tool's run().
struct CommandLine {
  std::string action;                   // the action option given first, or empty
  std::vector<std::string> positional;  // in order (Key=Value arguments included)
  std::map<std::string, std::vector<std::string>> options;  // last use of each option -> its values

  bool has(const std::string& option) const { return options.count(option) != 0; }
  // The first value of `option`, or `fallback` when it was not given.
  std::string text(const std::string& option, const std::string& fallback = "") const;
  int64_t integer(const std::string& option, int64_t fallback) const;  // after integerValues()
  std::vector<int64_t> integerList(const std::string& option, const std::vector<int64_t>& fallback) const;
};

struct CommandLineTool {
  std::string name;
  std::string description;  // what the tool does, a paragraph (printf-free text; "%s" is not expanded)
  // Synopsis lines after the tool's name, e.g. "FILE.cfg [Key=Value ...]   synthesize every frame".
  std::vector<std::string> synopsis;
  std::vector<CommandOption> options;
  std::string notes;                    // printed after the options (exit codes, manual)
  const OptionTable* keys = nullptr;    // config-driven tools: --help lists every key, --help-markdown them as tables
  std::string keysHeading = "Keys (type and range; default; meaning):";
  bool runsWithoutArguments = false;    // else no argument prints the usage on stderr, exit 2
  // Checks the positional arguments (the action's too): "" when they are fine.
  std::function<std::string(const CommandLine&)> checkPositional;
  // The tool; returns the exit code. Exceptions are caught by runCommandLine().
  std::function<int(const CommandLine&)> run;
};

// Parses (every problem at once: exit 2), answers --help and --help-markdown, runs the tool inside the
// one catch. Returns the exit code for main().
int runCommandLine(int argc, char** argv, const CommandLineTool& tool);
// The same on arguments without the program name, for tests.
int runCommandLine(const std::vector<std::string>& args, const CommandLineTool& tool);
// Only the parse: the problems found (empty: none), for tests.
std::vector<std::string> parseCommandLine(const std::vector<std::string>& args, const CommandLineTool& tool,
                                          CommandLine& parsed);
// The usage text --help prints.
std::string usageText(const CommandLineTool& tool);

// What --check prints for a config-driven synthesis tool: the tool, the config's effective text, the
// scene's warnings and its cameras (the caller adds what only it checks, then "configuration OK").
void printConfigCheck(const std::string& toolName, const std::string& configPath, const Config& config,
                      const Scene& scene);

}  // namespace vs
