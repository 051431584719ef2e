// The shared command-line front (Common/CommandLine.h): every problem collected in one parse, one
// catch for every exception a run throws, usage generated from the option table; and what it fixed in
// the executables: SynthBench's faults, --verify on ViewSyn and MeshRender.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Scene/SceneGen.h"
#include "Process.h"
#include "TestPaths.h"

namespace {

namespace fs = std::filesystem;
using vs::test::quoted;
using vs::test::ToolResult;

vs::CommandLineTool exampleTool() {
  vs::CommandLineTool tool;
  tool.name = "Example";
  tool.description = "an example.";
  tool.synopsis = {"[options] IN OUT"};
  tool.options = {
      {"--runs", {"N"}, "runs per case", vs::integerValues(1, 100)},
      {"--size", {"W", "H"}, "a size", vs::integerValues(1, 65536)},
      {"--range", {"NEAR", "FAR"}, "a depth range", vs::realValues(true)},
      {"--threads", {"LIST"}, "thread counts", vs::integerListValue(1, 8)},
      {"--verify", {"MD5"}, "a digest", vs::md5Value()},
      {"--quiet", {}, "a flag"},
      {"--check", {}, "an action", nullptr, true},
  };
  tool.checkPositional = [](const vs::CommandLine& line) {
    return line.positional.size() == 2 ? std::string() : "expected IN and OUT, got " + std::to_string(line.positional.size());
  };
  return tool;
}

TEST(CommandLine, EveryProblemIsCollectedInOneParse) {
  vs::CommandLine parsed;
  const std::vector<std::string> problems = vs::parseCommandLine(
      {"--runs", "abc", "--frob", "--size", "640", "x", "--range", "1", "inf", "--threads", "1,9", "--verify",
       "0123", "--check", "in"},
      exampleTool(), parsed);
  const std::vector<std::string> expected = {
      "--runs N: expected an integer in [1, 100], got 'abc'",
      "unknown option '--frob'",
      "--size W H: expected an integer in [1, 65536], got 'x'",
      "--threads LIST: expected an integer in [1, 8], got '9' in the list '1,9'",
      "--verify MD5: expected an MD5 digest (32 hexadecimal digits), got '0123'",
      "--check must come first",
      "expected IN and OUT, got 1",
  };
  EXPECT_EQ(problems, expected);
  // The range was fine and is kept; the bad values are not.
  EXPECT_EQ(parsed.options.at("--range"), (std::vector<std::string>{"1", "inf"}));
  EXPECT_FALSE(parsed.has("--runs"));
}

TEST(CommandLine, ValuesAreReadBackAsGiven) {
  vs::CommandLine parsed;
  EXPECT_TRUE(vs::parseCommandLine({"--check", "a", "--runs", "7", "--threads", "1,2,8", "--quiet", "b",
                                    "--verify", "D41D8CD98F00B204E9800998ECF8427E"},
                                   exampleTool(), parsed)
                  .empty());
  EXPECT_EQ(parsed.action, "--check");
  EXPECT_EQ(parsed.positional, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(parsed.integer("--runs", 5), 7);
  EXPECT_EQ(parsed.integer("--size", 3), 3);
  EXPECT_EQ(parsed.integerList("--threads", {}), (std::vector<int64_t>{1, 2, 8}));
  EXPECT_TRUE(parsed.has("--quiet"));
  EXPECT_EQ(parsed.text("--verify"), "D41D8CD98F00B204E9800998ECF8427E");
}

TEST(CommandLine, AMissingValueIsNamedAndAnOptionIsNeverTakenAsAValue) {
  vs::CommandLine parsed;
  EXPECT_EQ(vs::parseCommandLine({"in", "out", "--size", "3", "--quiet"}, exampleTool(), parsed),
            (std::vector<std::string>{"--size needs W H"}));
  EXPECT_TRUE(parsed.has("--quiet"));
}

TEST(CommandLine, AnEqualsSignJoinsAnOptionToItsFirstValue) {
  // "--opt=value" must parse exactly as "--opt value", for one value and for the first of several.
  vs::CommandLine joined, separate;
  EXPECT_TRUE(vs::parseCommandLine({"in", "--runs=7", "--size=640", "480", "--range=1", "inf", "out"}, exampleTool(),
                                   joined)
                  .empty());
  EXPECT_TRUE(vs::parseCommandLine({"in", "--runs", "7", "--size", "640", "480", "--range", "1", "inf", "out"},
                                   exampleTool(), separate)
                  .empty());
  EXPECT_EQ(joined.options, separate.options);
  EXPECT_EQ(joined.positional, separate.positional);
  EXPECT_EQ(joined.text("--runs"), "7");
  // Only the first '=' splits; the rest belongs to the value (checked like any value).
  vs::CommandLine parsed;
  EXPECT_EQ(vs::parseCommandLine({"in", "out", "--runs=1=2", "--quiet=yes", "--frob=1", "--size=3"}, exampleTool(),
                                 parsed),
            (std::vector<std::string>{"--runs N: expected an integer in [1, 100], got '1=2'",
                                      "--quiet takes no value, got '--quiet=yes'", "unknown option '--frob=1'",
                                      "--size needs W H"}));
}

TEST(CommandLine, ChromaFormatsAndFrameSizes) {
  const vs::ValueCheck chroma = vs::chromaFormatValue();
  for (const char* good : {"420", "444", "400"}) EXPECT_EQ(chroma({good}), "") << good;
  EXPECT_EQ(chroma({"422"}), "expected one of 420, 444, 400, got '422'");
  int width = 0, height = 0;
  EXPECT_TRUE(vs::parseFrameSize("1920x1080", width, height));
  EXPECT_EQ(width, 1920);
  EXPECT_EQ(height, 1080);
  EXPECT_TRUE(vs::parseFrameSize("65536x1", width, height));
  EXPECT_EQ(width, vs::kMaxFrameSide);
  int side = 0;
  EXPECT_TRUE(vs::parseFrameSide("640", side));
  EXPECT_EQ(side, 640);
  for (const char* bad : {"", "0", "+640", "-640", "65537", "6 4", "640x"}) EXPECT_FALSE(vs::parseFrameSide(bad, side)) << bad;
  for (const char* bad : {"", "x", "16", "16x", "x16", "0x16", "16x0", "65537x16", "16x16x16", "16 x16", "-16x16", "+16x16", "16x+16", "ax16"}) {
    width = height = 7;
    EXPECT_FALSE(vs::parseFrameSize(bad, width, height)) << bad;
    EXPECT_EQ(width, 7) << bad;  // left as it was
  }
}

TEST(CommandLine, UsageListsEveryOption) {
  const vs::CommandLineTool tool = exampleTool();
  const std::string usage = vs::usageText(tool);
  for (const vs::CommandOption& option : tool.options) EXPECT_NE(usage.find(option.name), std::string::npos) << option.name;
  EXPECT_NE(usage.find("--size W H"), std::string::npos);
  EXPECT_NE(usage.find("Example [options] IN OUT"), std::string::npos);
}

TEST(CommandLine, EveryExceptionOfARunBecomesExitCodeOne) {
  vs::CommandLineTool tool = exampleTool();
  const std::vector<std::string> args = {"in", "out"};
  tool.run = [](const vs::CommandLine&) -> int { throw vs::InputError("bad input"); };
  EXPECT_EQ(vs::runCommandLine(args, tool), 1);
  tool.run = [](const vs::CommandLine&) -> int { throw std::bad_alloc(); };
  EXPECT_EQ(vs::runCommandLine(args, tool), 1);
  tool.run = [](const vs::CommandLine&) -> int {
    fs::create_directories("/dev/null/x");  // throws filesystem_error
    return 0;
  };
  EXPECT_EQ(vs::runCommandLine(args, tool), 1);
  tool.run = [](const vs::CommandLine& line) { return int(line.positional.size()) + 40; };
  EXPECT_EQ(vs::runCommandLine(args, tool), 42);
  EXPECT_EQ(vs::runCommandLine({"in"}, tool), 2);
  EXPECT_EQ(vs::runCommandLine({}, tool), 2);
  EXPECT_EQ(vs::runCommandLine({"in", "--help"}, tool), 0);
}

// --- The executables ------------------------------------------------------------------------------

bool haveTool(const char* name) { return fs::exists(vs::test::binDir() / name); }

TEST(SynthBenchApp, AWorkFolderThatCannotBeMadeIsAClearError) {
  if (!haveTool("SynthBench")) GTEST_SKIP() << "Bin/SynthBench is not built";
  const fs::path scratch = vs::test::scratchDir("synthbench_work");
  const ToolResult run = vs::test::runTool("SynthBench", "--work /dev/null/x --no-demo --no-data --no-process", scratch);
  EXPECT_EQ(run.exitCode, 1) << run.err;
  EXPECT_NE(run.err.find("SynthBench: error: --work /dev/null/x: cannot create the folder"), std::string::npos)
      << run.err;
}

TEST(SynthBenchApp, BadValuesAreRefusedAllAtOnce) {
  if (!haveTool("SynthBench")) GTEST_SKIP() << "Bin/SynthBench is not built";
  const fs::path scratch = vs::test::scratchDir("synthbench_values");
  const ToolResult run = vs::test::runTool("SynthBench", "--runs abc --threads 0 --work", scratch, scratch);
  EXPECT_EQ(run.exitCode, 2);
  EXPECT_NE(run.err.find("--runs N: expected an integer in [1, 1000], got 'abc'"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--threads LIST: expected an integer in [1, 256], got '0'"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--work needs DIR"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(scratch / "out"));
}

// Without --work, SynthBench writes under $TMPDIR only, and removes what it wrote.
TEST(SynthBenchApp, WritesNothingIntoTheWorkingDirectory) {
  if (!haveTool("SynthBench") || !haveTool("ViewSyn")) GTEST_SKIP() << "Bin/SynthBench is not built";
  const fs::path scratch = vs::test::scratchDir("synthbench_cwd");
  fs::create_directories(scratch / "cwd");
  fs::create_directories(scratch / "tmp");
  const fs::path config = scratch / "demo" / "viewsyn_cam1.cfg";
  const vs::Config sceneConfig = vs::Config::fromText(
      vs::sceneGenOptionTable(), "", "test", ".",
      {"Scene=demo", "SourceWidth=32", "SourceHeight=16", "TotalNumberOfFrames=1", "OutputFolder=" + (scratch / "demo").string()});
  std::ostringstream quiet;
  vs::generateScene(vs::readSceneGenSettings(sceneConfig), quiet);
  const ToolResult run = vs::test::runTool("SynthBench", "--no-demo --no-data --runs 1 --threads 1 " + quoted(config.string()),
                                           scratch, scratch / "cwd", "TMPDIR=" + quoted((scratch / "tmp").string()));
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("viewsyn_cam1"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::is_empty(scratch / "cwd"));
  EXPECT_TRUE(fs::is_empty(scratch / "tmp"));
}

// --verify: the digest md5sum (coreutils) gives for the output passes, any other fails with both.
TEST(VerifyOption, ViewSynAndMeshRenderCheckTheirOutputsDigest) {
  const fs::path dir = vs::test::scratchDir("verify_option");
  const vs::Config sceneConfig = vs::Config::fromText(
      vs::sceneGenOptionTable(), "", "test", ".",
      {"Scene=demo", "SourceWidth=32", "SourceHeight=16", "TotalNumberOfFrames=2", "OutputFolder=" + dir.string()});
  std::ostringstream quiet;
  vs::generateScene(vs::readSceneGenSettings(sceneConfig), quiet);
  for (const char* tool : {"ViewSyn", "MeshRender"}) {
    if (!haveTool(tool)) continue;
    const std::string cfg = quoted((dir / (std::string(tool) == "ViewSyn" ? "viewsyn_cam1.cfg" : "meshrender_cam1.cfg")).string());
    const fs::path output = dir / (std::string(tool) + ".yuv");
    const std::string out = quoted("OutputVirtualViewImageName=" + output.string());
    const ToolResult first = vs::test::runTool(tool, cfg + " " + out, dir);
    if (first.exitCode != 0 && std::string(tool) == "MeshRender") continue;  // no OpenGL here
    ASSERT_EQ(first.exitCode, 0) << first.err;
    FILE* pipe = popen(("md5sum " + quoted(output.string())).c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    char digest[33] = {};
    ASSERT_EQ(std::fread(digest, 1, 32, pipe), 32u);
    pclose(pipe);
    std::string upper = digest;
    for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
    const ToolResult good = vs::test::runTool(tool, cfg + " " + out + " --verify " + upper, dir);
    EXPECT_EQ(good.exitCode, 0) << tool << ": " << good.err;
    EXPECT_NE(good.out.find(std::string("has MD5 ") + digest), std::string::npos) << good.out;
    std::string wrong = digest;
    wrong[0] = wrong[0] == '0' ? '1' : '0';
    const ToolResult bad = vs::test::runTool(tool, cfg + " " + out + " --verify " + wrong, dir);
    EXPECT_EQ(bad.exitCode, 1) << tool;
    EXPECT_NE(bad.err.find(std::string("has MD5 ") + digest + ", expected " + wrong), std::string::npos) << bad.err;
    EXPECT_EQ(vs::test::runTool(tool, cfg + " --verify 12345", dir).exitCode, 2) << tool;
    EXPECT_EQ(vs::test::runTool(tool, "--check " + cfg + " --verify " + wrong, dir).exitCode, 2) << tool;
  }
}

}  // namespace
