#include "Common/CommandLine.h"

#include <cerrno>
#include <cstring>
#include <exception>
#include <new>

#include "Common/Error.h"
#include "Common/Memory.h"

namespace vs {

int runCommandLine(int argc, char** argv, const CommandLineTool& tool) {
  keepFreedMemoryForReuse();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    tool.printUsage(stderr);
    return 2;
  }
  if (args[0] == "--help" || args[0] == "-h") {
    tool.printUsage(stdout);
    return 0;
  }
  if (args[0] == "--help-markdown" && tool.table) {
    std::fputs(tool.table->markdownTable().c_str(), stdout);
    return 0;
  }
  bool check = false;
  if (tool.hasCheck && args[0] == "--check") {
    check = true;
    args.erase(args.begin());
    if (args.empty()) {
      std::fprintf(stderr, "%s: --check needs a config file\n", tool.name.c_str());
      return 2;
    }
  }
  if (args[0].rfind("--", 0) == 0) {
    std::fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", tool.name.c_str(), args[0].c_str(),
                 tool.name.c_str());
    return 2;
  }
  try {
    const int code = tool.run(args, check);
    // What the tool printed must have reached stdout (a full disk, a closed pipe, /dev/full).
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int error = errno;
      std::fprintf(stderr, "%s: error: cannot write the standard output: %s\n", tool.name.c_str(),
                   error ? std::strerror(error) : "write error");
      return 1;
    }
    return code;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool.name.c_str(), e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", tool.name.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool.name.c_str(), e.what());
  }
  return 1;
}

void printConfigCheck(const std::string& toolName, const std::string& configPath, const Config& config,
                      const Scene& scene) {
  std::printf("%s %s --check %s\n\n%s\n", toolName.c_str(), VS_VERSION, configPath.c_str(), config.effectiveText().c_str());
  for (const std::string& warning : scene.warnings) std::printf("warning: %s\n", warning.c_str());
  std::printf("%s\n", describeCameras(scene).c_str());
}

}  // namespace vs
