#include "Common/BuildInfo.h"

#include "Common/CpuLevel.h"
#include "Common/Json.h"

// CMake defines these for this file alone (Source/Lib/CMakeLists.txt), so that a new commit or
// OpenCV recompiles one file.
#ifndef VS_GIT_COMMIT
#define VS_GIT_COMMIT "unknown"
#endif
#ifndef VS_BUILD_TYPE
#define VS_BUILD_TYPE "unknown"
#endif
#ifndef VS_OPENCV_VERSION
#define VS_OPENCV_VERSION "none"
#endif

namespace vs {

const BuildInfo& buildInfo() {
  static const BuildInfo info{VS_VERSION, VS_GIT_COMMIT, VS_BUILD_TYPE, VS_OPENCV_VERSION};
  return info;
}

std::string x86LevelName() {
  const int level = x86Level();
  if (level == 0) return "not x86-64";
  return level == 1 ? "x86-64 baseline" : "x86-64-v" + std::to_string(level);
}

std::string versionText(const std::string& toolName) {
  const BuildInfo& info = buildInfo();
  return toolName + " " + info.version + "\ncommit: " + info.commit + "\nbuild type: " + info.buildType +
         "\nx86-64 level: " + x86LevelName() + " (" + x86LevelOrigin() + ")\nOpenCV: " + info.opencv + "\n";
}

std::string buildJson(const std::string& indent) {
  const BuildInfo& info = buildInfo();
  const std::string in = indent + "  ";
  return "{\n" + in + "\"version\": " + jsonString(info.version) + ",\n" + in + "\"commit\": " + jsonString(info.commit) +
         ",\n" + in + "\"build_type\": " + jsonString(info.buildType) + ",\n" + in + "\"x86_64_level\": " +
         std::to_string(x86Level()) + ",\n" + in + "\"x86_64_level_origin\": " + jsonString(x86LevelOrigin()) + ",\n" +
         in + "\"opencv\": " + jsonString(info.opencv) + "\n" + indent + "}";
}

}  // namespace vs
