#pragma once
// Runs one of the project's executables from Bin/ in a shell and collects its exit code, stdout and
// stderr, for tests that check what a user sees.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include "TestPaths.h"

namespace vs::test {

struct ToolResult {
  int exitCode = -1;
  std::string out;
  std::string err;
};

inline std::string quoted(const std::string& text) { return "'" + text + "'"; }

// Runs `Bin/<tool> <arguments>` (arguments are passed to the shell as written: quote them) with the
// working directory `workDir` and `environment` (shell assignments such as "VAR=value ", or empty)
// before the command; stderr goes through a file in `scratch`.
inline ToolResult runTool(const std::string& tool, const std::string& arguments, const std::filesystem::path& scratch,
                          const std::filesystem::path& workDir = {}, const std::string& environment = "") {
  ToolResult result;
  const std::filesystem::path errPath = scratch / (tool + "_stderr.txt");
  std::string command = environment + " " + quoted((binDir() / tool).string()) + " " + arguments + " 2>" +
                        quoted(errPath.string()) + " </dev/null";
  if (!workDir.empty()) command = "cd " + quoted(workDir.string()) + " && " + command;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char chunk[4096];
  size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof chunk, pipe)) > 0) result.out.append(chunk, got);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream errFile(errPath);
  std::stringstream err;
  err << errFile.rdbuf();
  result.err = err.str();
  return result;
}

}  // namespace vs::test
