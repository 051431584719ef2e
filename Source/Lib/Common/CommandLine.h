#pragma once
// The command line every config-driven executable shares (ViewSyn, MeshRender, SceneGen):
//   TOOL --help | -h          the usage and every key, on stdout; exit 0
//   TOOL --help-markdown      the keys as Markdown tables (the manuals' source); exit 0
//   TOOL --check FILE ...     where the tool has a check: run it instead of the tool
//   TOOL --print-config FILE ...  where offered: the effective config and scene as JSON, on stdout
//   TOOL ARGS ...             the tool
// No argument prints the usage on stderr and exits 2, as does an unknown --option. Bad input
// (InputError) is reported as "TOOL: error: ..." on stderr with exit 1, and so is running out of
// memory or any other failure a library reports with an exception: the run never ends in an
// uncaught exception.
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Scene.h"

namespace vs {

enum class ToolAction { Run, Check, PrintConfig };

struct CommandLineTool {
  std::string name;
  const OptionTable* table = nullptr;          // for --help-markdown
  std::function<void(std::FILE*)> printUsage;  // usage text and the keys
  // Runs the tool on the arguments after the options; `action` is Check for --check (only offered when
  // `hasCheck`), PrintConfig for --print-config (when `hasPrintConfig`). Returns the exit code.
  std::function<int(const std::vector<std::string>& args, ToolAction action)> run;
  bool hasCheck = false;
  bool hasPrintConfig = false;
};

int runCommandLine(int argc, char** argv, const CommandLineTool& tool);

// What --check prints for a config-driven synthesis tool: the tool, the config's effective text, the
// scene's warnings and its cameras (the caller adds what only it checks, then "configuration OK").
void printConfigCheck(const std::string& toolName, const std::string& configPath, const Config& config,
                      const Scene& scene);

}  // namespace vs
