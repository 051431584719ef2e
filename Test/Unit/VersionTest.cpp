// --version on every tool of the shared front and the "build" object of the JSON summary
// (Common/BuildInfo.h, Common/CpuLevel.h): each fact against an independent source (CMakeLists.txt's
// project(), git, OpenCV's own version call, the CPU), the level cap by option and environment.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>


#include "Common/BuildInfo.h"
#include "Common/CpuLevel.h"
#include "Common/Json.h"
#include "Process.h"
#include "TestPaths.h"

namespace {

namespace fs = std::filesystem;

const char* const kTools[] = {"ViewSyn", "MeshRender", "SceneGen", "CameraConvert", "SynthBench", "YuvPsnr"};

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// project(ViewSynthesis VERSION x.y.z ...) in the top CMakeLists.txt: the one place of the version.
std::string projectVersion() {
  std::smatch match;
  const std::string text = readText(fs::path(VS_SOURCE_DIR) / "CMakeLists.txt");
  if (!std::regex_search(text, match, std::regex(R"(project\(ViewSynthesis VERSION ([0-9.]+))"))) return "?";
  return match[1];
}

// The value after "key: " in --version's output.
std::string field(const std::string& text, const std::string& key) {
  std::smatch match;
  if (!std::regex_search(text, match, std::regex("(^|\n)" + key + ": ([^\n]*)"))) return "(missing)";
  return match[2];
}

TEST(Version, EveryToolNamesVersionCommitBuildLevelAndOpenCV) {
  const fs::path dir = vs::test::scratchDir("version");
  const std::string version = projectVersion();
  for (const char* tool : kTools) {
    const vs::test::ToolResult result = vs::test::runTool(tool, "--version", dir);
    ASSERT_EQ(result.exitCode, 0) << tool << ": " << result.err;
    EXPECT_EQ(result.out.substr(0, result.out.find('\n')), std::string(tool) + " " + version);
    EXPECT_EQ(field(result.out, "OpenCV"), "none") << tool;  // no tool links OpenCV
    const std::string commit = field(result.out, "commit");
    EXPECT_TRUE(std::regex_match(commit, std::regex("unknown|[0-9a-f]{12}(-modified)?"))) << commit;
    if (commit != "unknown") {
      // The commit is one git knows (configure time: not necessarily HEAD any more).
      const std::string hash = commit.substr(0, 12);
      const std::string command =
          "git -C " + vs::test::quoted(VS_SOURCE_DIR) + " cat-file -e " + hash + "^{commit} 2>/dev/null";
      EXPECT_EQ(std::system(command.c_str()), 0) << tool << " names commit " << commit;
    }
    EXPECT_FALSE(field(result.out, "build type").empty()) << tool;
    const int cpu = vs::cpuX86Level();
    const std::string level = field(result.out, "x86-64 level");
    if (cpu == 0) EXPECT_EQ(level.substr(0, 10), "not x86-64");
    else EXPECT_TRUE(std::regex_search(level, std::regex("^x86-64[ -](baseline|v[234]) \\(.+\\)$"))) << level;
  }
}

TEST(Version, TheLevelInUseNeverExceedsTheCpuOrTheCap) {
  if (vs::cpuX86Level() == 0) GTEST_SKIP() << "not an x86-64 processor";
  const fs::path dir = vs::test::scratchDir("version_cap");
  const int cpu = vs::cpuX86Level();
  auto levelOf = [](const std::string& text) {
    const std::string level = field(text, "x86-64 level");
    return level.rfind("x86-64 baseline", 0) == 0 ? 1 : level[8] - '0';
  };
  const vs::test::ToolResult free = vs::test::runTool("ViewSyn", "--version", dir);
  ASSERT_EQ(free.exitCode, 0) << free.err;
  EXPECT_LE(levelOf(free.out), cpu);
  EXPECT_GE(levelOf(free.out), vs::compiledX86Level());
  for (int cap = vs::compiledX86Level(); cap <= cpu; ++cap) {
    if (cap < 1) continue;
    const std::string capText = std::to_string(cap);
    const vs::test::ToolResult byOption = vs::test::runTool("ViewSyn", "--version --x86-64-level " + capText, dir);
    ASSERT_EQ(byOption.exitCode, 0) << byOption.err;
    EXPECT_LE(levelOf(byOption.out), cap);
    const vs::test::ToolResult byEnv = vs::test::runTool("SceneGen", "--version", dir, {}, "VS_X86_64_LEVEL=" + capText);
    ASSERT_EQ(byEnv.exitCode, 0) << byEnv.err;
    EXPECT_EQ(levelOf(byEnv.out), levelOf(byOption.out));
  }
  // A bad cap is refused, naming where it came from.
  const vs::test::ToolResult badEnv = vs::test::runTool("ViewSyn", "--version", dir, {}, "VS_X86_64_LEVEL=5");
  EXPECT_EQ(badEnv.exitCode, 2);
  EXPECT_NE(badEnv.err.find("VS_X86_64_LEVEL=5: expected an x86-64 level 1, 2, 3 or 4"), std::string::npos) << badEnv.err;
  const vs::test::ToolResult badOption = vs::test::runTool("ViewSyn", "--check x.cfg --x86-64-level 0", dir);
  EXPECT_EQ(badOption.exitCode, 2);
  EXPECT_NE(badOption.err.find("--x86-64-level N: expected an integer in [1, 4], got '0'"), std::string::npos)
      << badOption.err;
}

TEST(Version, TheSummaryCarriesTheBuild) {
  const std::string json = "{\"build\": " + vs::buildJson("") + "}";
  const vs::JsonValue parsed = vs::parseJson(json, "build");
  const vs::JsonValue* build = parsed.find("build");
  ASSERT_NE(build, nullptr);
  EXPECT_EQ(build->find("version")->text, projectVersion());
  EXPECT_EQ(build->find("opencv")->text, "none");
  EXPECT_EQ(build->find("commit")->text, vs::buildInfo().commit);
  EXPECT_EQ(int(build->find("x86_64_level")->number), vs::x86Level());
  // --version prints the same facts.
  const fs::path dir = vs::test::scratchDir("version_summary");
  const vs::test::ToolResult result = vs::test::runTool("ViewSyn", "--version", dir);
  EXPECT_EQ(field(result.out, "commit"), build->find("commit")->text);
  EXPECT_EQ(field(result.out, "build type"), build->find("build_type")->text);
}

}  // namespace
