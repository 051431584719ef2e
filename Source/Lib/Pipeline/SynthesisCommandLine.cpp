#include "Pipeline/SynthesisCommandLine.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "Common/Error.h"
#include "Common/Md5.h"
#include "Pipeline/RunReport.h"

namespace vs {

namespace {

// --print-config: one JSON document, or an array of them for an RVS config's virtual cameras.
void printConfigs(const SynthesisTool& tool, const std::vector<Config>& configs, const std::vector<Scene>& scenes) {
  if (configs.size() > 1) std::fputs("[\n", stdout);
  for (size_t k = 0; k < configs.size(); ++k) {
    if (k) std::fputs(",\n", stdout);
    std::fputs(configJson(tool.name, configs[k], scenes[k]).c_str(), stdout);
  }
  if (configs.size() > 1) std::fputs("]\n", stdout);
}

// --check or --print-config: read and check everything a run would, then print instead of running;
// every virtual camera of an RVS config (one configuration each) is loaded and planned first.
int runAction(const SynthesisTool& tool, const CommandLine& line, const std::vector<Config>& configs) {
  std::vector<Scene> scenes;
  for (const Config& config : configs) {
    scenes.push_back(loadScene(config));
    if (tool.validate) tool.validate(config, scenes.back());
  }
  if (line.action == "--print-config") {
    printConfigs(tool, configs, scenes);
    return 0;
  }
  for (size_t k = 0; k < configs.size(); ++k) {
    if (configs.size() > 1)
      std::printf("virtual camera %zu of %zu: %s\n", k + 1, configs.size(), scenes[k].settings.virtualCameraName.c_str());
    printConfigCheck(tool.name, line.positional[0], configs[k], scenes[k]);
  }
  // --check also opens every input (type, format, whole frames) and checks every output name, as
  // the run does before frame 0; after the printout (of every virtual camera), so that a refusal
  // follows what was read.
  for (size_t k = 0; k < configs.size(); ++k) {
    for (const std::string& warning : checkInputs(scenes[k])) std::printf("warning: %s\n", warning.c_str());
    checkOutputs(scenes[k], tool.extraOutputs ? tool.extraOutputs(configs[k], scenes[k]) : std::vector<NamedOutput>{});
  }
  std::printf("input files OK\n");
  if (tool.describe) tool.describe(stdout);
  std::printf("configuration OK\n");
  return 0;
}

// As dav1d's --verify: the digest of the whole output file, compared without regard to case.
int verifyOutput(const SynthesisTool& tool, const Config& config, std::string expected) {
  const std::string output = config.getPath("OutputVirtualViewImageName");
  const std::string actual = md5OfFile(output);
  std::transform(expected.begin(), expected.end(), expected.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (actual != expected) {
    std::fprintf(stderr, "%s: error: --verify: %s has MD5 %s, expected %s\n", tool.name.c_str(), output.c_str(),
                 actual.c_str(), expected.c_str());
    return 1;
  }
  std::printf("verified: %s has MD5 %s\n", output.c_str(), actual.c_str());
  return 0;
}

}  // namespace

CommandLineTool synthesisCommandLine(const SynthesisTool& tool) {
  CommandLineTool front;
  front.name = tool.name;
  front.description = tool.description;
  front.keys = tool.keys;
  front.synopsis = {
      "FILE.cfg [Key=Value ...] [--verify MD5]\n"
      "      synthesize every frame; Key=Value overrides the file",
      "--check FILE.cfg [Key=Value ...]\n      " + tool.checkHelp,
      "--print-config FILE.cfg [Key=Value ...]\n"
      "      print the effective configuration and the scene as JSON (doc/report.md); open no YUV file",
  };
  front.options = {
      {"--check", {}, "check the configuration instead of running (see above)", nullptr, true},
      {"--print-config", {}, "print configuration and scene as JSON instead of running", nullptr, true},
      {"--verify", {"MD5"}, "after the run, the output file's MD5 must be MD5 (else exit 1)", md5Value(), false},
  };
  front.notes = "Exit codes: 0 success, 1 bad input (the message says which file, line or key) or a --verify\n"
                "mismatch, 2 bad usage.\nThe manual: " + tool.manual + ".";
  front.checkPositional = [](const CommandLine& line) -> std::string {
    if (line.positional.empty())
      return line.action.empty() ? "expected a config file FILE.cfg" : line.action + " needs a config file";
    if (!line.action.empty() && line.has("--verify")) return "--verify checks a run's output, not " + line.action;
    return "";
  };
  front.run = [tool](const CommandLine& line) {
    const std::vector<std::string> overrides(line.positional.begin() + 1, line.positional.end());
    // A VSRS config gives one configuration; an RVS config one per virtual camera, run in turn, each
    // writing its own output (Common/RvsConfig.h).
    const std::vector<Config> configs = Config::loadAll(*tool.keys, line.positional[0], overrides);
    if (line.has("--verify") && configs.size() != 1)
      throw InputError(line.positional[0] + ": --verify checks one output, and this config has " +
                       std::to_string(configs.size()) + " virtual cameras");
    if (!line.action.empty()) return runAction(tool, line, configs);
    for (const Config& config : configs) tool.run(config);
    return line.has("--verify") ? verifyOutput(tool, configs[0], line.text("--verify")) : 0;
  };
  return front;
}

}  // namespace vs
