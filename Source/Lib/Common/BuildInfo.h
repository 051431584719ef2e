#pragma once
// What a binary is: the project version (one place, CMakeLists.txt's project()), the git commit it was
// configured from, the build type, the x86-64 level of the code in use and the OpenCV version it was
// built against. `--version` prints it and the JSON run summary carries it as "build".
#include <string>

namespace vs {

struct BuildInfo {
  std::string version;    // CMakeLists.txt's project version
  std::string commit;     // `git rev-parse` at configure time; "unknown" when built outside git
  std::string buildType;  // CMAKE_BUILD_TYPE (Release, RelWithDebInfo, ...)
  std::string opencv;     // the OpenCV version the libraries were built against; "none" without it
};

const BuildInfo& buildInfo();

// The x86-64 level of the code in use, for reports: "x86-64-v3", "x86-64 baseline"; "not x86-64" on
// other processors.
std::string x86LevelName();

// What `TOOL --version` prints: name and version, then one "key: value" line each.
std::string versionText(const std::string& toolName);

// The "build" object of the JSON run summary, members at `indent` + 2 spaces.
std::string buildJson(const std::string& indent);

}  // namespace vs
