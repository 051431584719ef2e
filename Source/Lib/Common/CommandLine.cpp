#include "Common/CommandLine.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>

#include "Common/BuildInfo.h"
#include "Common/CpuLevel.h"
#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/Memory.h"

namespace vs {

ValueCheck integerValues(int64_t minValue, int64_t maxValue) {
  return [=](const std::vector<std::string>& values) -> std::string {
    for (const std::string& value : values) {
      int64_t v = 0;
      if (!parseInt(value, v) || v < minValue || v > maxValue)
        return "expected an integer in [" + std::to_string(minValue) + ", " + std::to_string(maxValue) + "], got '" +
               value + "'";
    }
    return "";
  };
}

ValueCheck integerListValue(int64_t minValue, int64_t maxValue) {
  const ValueCheck each = integerValues(minValue, maxValue);
  return [=](const std::vector<std::string>& values) -> std::string {
    for (const std::string& value : values) {
      const std::string problem = each(splitList(value));
      if (!problem.empty()) return problem + " in the list '" + value + "'";
    }
    return "";
  };
}

ValueCheck realValues(bool lastMayBeInfinite) {
  return [=](const std::vector<std::string>& values) -> std::string {
    for (size_t k = 0; k < values.size(); ++k) {
      double v = 0;
      const bool infinityAllowed = lastMayBeInfinite && k + 1 == values.size();
      if (!parseDouble(values[k], v, infinityAllowed))
        return std::string("expected a number") + (infinityAllowed ? " or inf" : "") + ", got '" + values[k] + "'";
    }
    return "";
  };
}

ValueCheck md5Value() {
  return [](const std::vector<std::string>& values) -> std::string {
    for (const std::string& value : values) {
      bool hex = value.size() == 32;
      for (const char c : value) hex = hex && std::isxdigit(static_cast<unsigned char>(c));
      if (!hex) return "expected an MD5 digest (32 hexadecimal digits), got '" + value + "'";
    }
    return "";
  };
}

ValueCheck chromaFormatValue() {
  return [](const std::vector<std::string>& values) -> std::string {
    for (const std::string& value : values) {
      ChromaFormat chroma;
      if (!parseChromaFormat(value, chroma)) return "expected one of 420, 444, 400, got '" + value + "'";
    }
    return "";
  };
}

bool parseFrameSide(const std::string& text, int& side) {
  int64_t value = 0;
  if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) || !parseInt(text, value) || value < 1 ||
      value > kMaxFrameSide)
    return false;
  side = int(value);
  return true;
}

bool parseFrameSize(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  int w = 0, h = 0;
  if (x == std::string::npos || !parseFrameSide(text.substr(0, x), w) || !parseFrameSide(text.substr(x + 1), h))
    return false;
  width = w;
  height = h;
  return true;
}

std::string CommandLine::text(const std::string& option, const std::string& fallback) const {
  const auto found = options.find(option);
  return found == options.end() || found->second.empty() ? fallback : found->second[0];
}

int64_t CommandLine::integer(const std::string& option, int64_t fallback) const {
  int64_t value = fallback;
  if (has(option)) VS_CHECK_MSG(parseInt(text(option), value), "option values are checked when parsed");
  return value;
}

std::vector<int64_t> CommandLine::integerList(const std::string& option, const std::vector<int64_t>& fallback) const {
  if (!has(option)) return fallback;
  std::vector<int64_t> values;
  for (const std::string& item : splitList(text(option))) {
    int64_t value = 0;
    VS_CHECK_MSG(parseInt(item, value), "option values are checked when parsed");
    values.push_back(value);
  }
  return values;
}

namespace {

// Options every tool takes, after its own.
CommandLineTool withCommonOptions(const CommandLineTool& tool) {
  CommandLineTool front = tool;
  front.options.push_back({"--x86-64-level", {"N"},
                           "cap the x86-64 level of the vectorised code, 1 to 4 (as env VS_X86_64_LEVEL)",
                           integerValues(1, 4)});
  front.options.push_back({"--version", {}, "print version, commit, build type, x86-64 level, OpenCV; exit"});
  return front;
}

// The cap on the x86-64 level applies before anything runs; the option wins over the environment.
void capLevel(const std::vector<std::string>& args) {
  for (size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--x86-64-level") {
      int64_t level = 0;
      if (!parseInt(args[i + 1], level)) level = 0;  // capX86Level() names what was expected
      capX86Level(int(level), "--x86-64-level " + args[i + 1]);
      return;
    }
  capX86LevelFromEnvironment();
}

}  // namespace

std::vector<std::string> parseCommandLine(const std::vector<std::string>& args, const CommandLineTool& toolOnly,
                                          CommandLine& parsed) {
  const CommandLineTool tool = withCommonOptions(toolOnly);
  std::vector<std::string> problems;
  auto find = [&](const std::string& name) -> const CommandOption* {
    for (const CommandOption& option : tool.options)
      if (option.name == name) return &option;
    return nullptr;
  };
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i].size() <= 2 || args[i].compare(0, 2, "--") != 0) {
      parsed.positional.push_back(args[i]);
      continue;
    }
    // "--opt=value" is "--opt value": the text after the first '=' is the option's first value.
    const size_t equals = args[i].find('=');
    const std::string arg = args[i].substr(0, equals);
    const CommandOption* option = find(arg);
    if (!option) {
      problems.push_back("unknown option '" + args[i] + "'");
      continue;
    }
    if (option->action) {
      if (i != 0) problems.push_back(arg + " must come first");
      parsed.action = arg;
    }
    std::vector<std::string> values;
    if (equals != std::string::npos) {
      if (option->valueNames.empty()) {
        problems.push_back(arg + " takes no value, got '" + args[i] + "'");
        continue;
      }
      values.push_back(args[i].substr(equals + 1));
    }
    while (values.size() < option->valueNames.size() && i + 1 < args.size() && !find(args[i + 1]))
      values.push_back(args[++i]);
    std::string valueNames;
    for (const std::string& name : option->valueNames) valueNames += " " + name;
    if (values.size() < option->valueNames.size()) {
      problems.push_back(arg + " needs" + valueNames);
      continue;
    }
    const std::string problem = option->check ? option->check(values) : "";
    if (!problem.empty()) problems.push_back(arg + valueNames + ": " + problem);
    else parsed.options[arg] = values;
  }
  if (tool.checkPositional) {
    const std::string problem = tool.checkPositional(parsed);
    if (!problem.empty()) problems.push_back(problem);
  }
  return problems;
}

std::string usageText(const CommandLineTool& toolOnly) {
  const CommandLineTool tool = withCommonOptions(toolOnly);
  std::string text = tool.name + " " + VS_VERSION + ": " + tool.description + "\n\nUsage:\n";
  for (const std::string& line : tool.synopsis) text += "  " + tool.name + " " + line + "\n";
  text += "  " + tool.name + " --help" + (tool.keys ? " | --help-markdown" : "") + "\n";
  if (!tool.options.empty()) {
    text += "\nOptions:\n";
    for (const CommandOption& option : tool.options) {
      std::string left = "  " + option.name;
      for (const std::string& name : option.valueNames) left += " " + name;
      left.resize(std::max<size_t>(left.size() + 2, 28), ' ');
      text += left + option.help + "\n";
    }
  }
  if (!tool.notes.empty()) text += "\n" + tool.notes + (tool.notes.back() == '\n' ? "" : "\n");
  if (tool.keys) text += tool.keysHeading + "\n" + tool.keys->helpText();
  return text;
}

int runCommandLine(const std::vector<std::string>& args, const CommandLineTool& tool) {
  const char* name = tool.name.c_str();
  if (args.empty() && !tool.runsWithoutArguments) {
    std::fputs(usageText(tool).c_str(), stderr);
    return 2;
  }
  for (const std::string& arg : args)
    if (arg == "--help" || arg == "-h") {
      std::fputs(usageText(tool).c_str(), stdout);
      return 0;
    }
  // --version needs no other argument (a config-driven tool would ask for its config).
  for (const std::string& arg : args)
    if (arg == "--version") {
      try {
        capLevel(args);
      } catch (const InputError& e) {
        std::fprintf(stderr, "%s: error: %s\n", name, e.what());
        return 2;
      }
      std::fputs(versionText(tool.name).c_str(), stdout);
      return 0;
    }
  if (tool.keys && args.size() == 1 && args[0] == "--help-markdown") {
    std::fputs(tool.keys->markdownTable().c_str(), stdout);
    return 0;
  }
  CommandLine parsed;
  const std::vector<std::string> problems = parseCommandLine(args, tool, parsed);
  if (!problems.empty()) {
    for (const std::string& problem : problems) std::fprintf(stderr, "%s: %s\n", name, problem.c_str());
    std::fprintf(stderr, "%s: %zu problem%s on the command line (see %s --help)\n", name, problems.size(),
                 problems.size() == 1 ? "" : "s", name);
    return 2;
  }
  // The one catch: whatever a library throws ends as a message and exit code 1, never as an abort.
  try {
    capLevel(args);
    const int code = tool.run(parsed);
    // What the tool printed must have reached stdout (a full disk, a closed pipe, /dev/full).
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int error = errno;
      std::fprintf(stderr, "%s: error: cannot write the standard output: %s\n", name,
                   error ? std::strerror(error) : "write error");
      return 1;
    }
    return code;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", name);
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
  }
  return 1;
}

int runCommandLine(int argc, char** argv, const CommandLineTool& tool) {
  keepFreedMemoryForReuse();
  return runCommandLine(std::vector<std::string>(argv + 1, argv + argc), tool);
}

void printConfigCheck(const std::string& toolName, const std::string& configPath, const Config& config,
                      const Scene& scene) {
  std::printf("%s %s --check %s\n\n%s\n", toolName.c_str(), VS_VERSION, configPath.c_str(), config.effectiveText().c_str());
  for (const std::string& warning : scene.warnings) std::printf("warning: %s\n", warning.c_str());
  std::printf("%s\n", describeCameras(scene).c_str());
}

}  // namespace vs
