#pragma once
// Runs one of the project's executables from Bin/ and measures it: exit code, wall seconds and peak
// resident memory (what `/usr/bin/time -v` prints as "Maximum resident set size"). stdout and stderr
// of the tool go to /dev/null.
//
// The tool is started through the small helper tools/PeakRss.cpp: Linux carries a process's peak RSS
// across fork and exec, so a tool spawned straight from this test process would report the test's
// own peak when that is larger.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include "TestPaths.h"

extern char** environ;

namespace vs::test {

struct ProcessStats {
  bool measured = false;  // false: the helper could not run or write its report
  int exitCode = -1;      // 128 + signal when killed
  double seconds = 0;
  long maxRssKiB = 0;     // peak resident set size
};

// `environment` entries ("NAME=value") are set on top of the test's own environment; `reportFile` is a
// scratch file for the helper's report.
inline ProcessStats runMeasured(const std::string& tool, const std::vector<std::string>& arguments,
                                const std::filesystem::path& reportFile,
                                const std::vector<std::string>& environment = {}) {
  ProcessStats stats;
  std::vector<std::string> words{VS_PEAK_RSS_TOOL, reportFile.string(), (binDir() / tool).string()};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  // The test's environment, with the entries of `environment` replacing those of the same name.
  auto nameOf = [](const std::string& entry) { return entry.substr(0, entry.find('=')); };
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e) {
    bool replaced = false;
    for (const std::string& entry : environment) replaced = replaced || nameOf(entry) == nameOf(*e);
    if (!replaced) envp.push_back(*e);
  }
  for (const std::string& entry : environment) envp.push_back(const_cast<char*>(entry.c_str()));
  envp.push_back(nullptr);

  std::filesystem::remove(reportFile);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return stats;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return stats;
  std::ifstream report(reportFile);
  stats.measured = static_cast<bool>(report >> stats.seconds >> stats.maxRssKiB >> stats.exitCode);
  return stats;
}

}  // namespace vs::test
