// The run report (Pipeline/RunReport.h): the CSV and the JSON summary written from one list of
// columns, read back with Common/Json.h and compared with each other, with the stdout the tool
// prints and with means computed here; --print-config read back and compared with the config.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Json.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Pipeline/RunReport.h"
#include "Scene/SceneGen.h"
#include "Process.h"
#include "TestPaths.h"

namespace {

namespace fs = std::filesystem;
using vs::JsonValue;

std::string readText(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

std::vector<std::vector<std::string>> readCsv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream text(readText(path));
  for (std::string line; std::getline(text, line);) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream fields(line);
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

// A JSON cell as the CSV would hold it: null -> "", "inf" -> "inf", a number -> the number.
double jsonNumberOrInf(const JsonValue& value) {
  if (value.type == JsonValue::Type::String && value.text == "inf") return std::numeric_limits<double>::infinity();
  EXPECT_EQ(value.type, JsonValue::Type::Number) << "line " << value.line;
  return value.number;
}

const JsonValue& member(const JsonValue& object, const std::string& key) {
  const JsonValue* found = object.find(key);
  if (!found) {
    ADD_FAILURE() << "no key " << key;
    static const JsonValue none;
    return none;
  }
  return *found;
}

vs::FrameRecord record(int64_t frame, double y, double u, double v, double seconds) {
  vs::FrameRecord r;
  r.frame = frame;
  r.scored = true;
  r.psnr.y = y;
  r.psnr.u = u;
  r.psnr.v = v;
  r.psnr.yuv = vs::weightedYuvPsnr(y, u, v);
  r.times.read = seconds;
  r.times.depthWarp = 2 * seconds;
  r.times.write = 0.5 * seconds;
  return r;
}

TEST(RunReport, CsvAndJsonHoldTheSameFramesAndTheMeansAreFrameMeans) {
  const fs::path dir = vs::test::scratchDir("run_report_unit");
  const vs::Config config =
      vs::Config::fromText(vs::viewSynOptionTable(), "", "test.cfg", dir.string(),
                           {"ReportFile=" + (dir / "r.csv").string(), "SummaryFile=" + (dir / "s.json").string()});
  vs::Scene scene;
  scene.warnings = {"a warning \"quoted\""};
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<vs::FrameRecord> frames = {record(7, 30.0, 40.0, 50.0, 0.25), record(8, inf, 41.0, 51.0, 0.5),
                                               record(9, 32.0, 42.0, inf, 1.0)};
  vs::RunSummary summary;
  {
    vs::RunReport report("ViewSyn", config);
    report.recordDecisions({{"path", "1d"}, {"blend_weights", "0.375,0.625"}});
    report.begin(scene, {"plan line 1", "plan line 2"}, nullptr);
    report.startFrames(nullptr);
    for (const vs::FrameRecord& r : frames) report.addFrame(r, nullptr);
    report.commit();
    summary = report.finish("out.yuv", nullptr);
    report.writeSummary(0, "");
  }
  // Frame means over the finite PSNRs only (doc/formats-yuv.md): Y of frames 7 and 9, V of 7 and 8.
  const double meanY = (30.0 + 32.0) / 2, meanU = (40.0 + 41.0 + 42.0) / 3, meanV = (50.0 + 51.0) / 2;
  EXPECT_DOUBLE_EQ(summary.meanPsnrY, meanY);
  EXPECT_DOUBLE_EQ(summary.meanPsnrU, meanU);
  EXPECT_DOUBLE_EQ(summary.meanPsnrV, meanV);
  EXPECT_EQ(summary.framesWritten, 3);

  const std::vector<std::vector<std::string>> csv = readCsv(dir / "r.csv");
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[0], vs::reportColumns());
  const JsonValue json = vs::parseJson(readText(dir / "s.json"), "s.json");
  EXPECT_EQ(member(json, "tool").text, "ViewSyn");
  EXPECT_EQ(member(json, "version").text, VS_VERSION);
  EXPECT_EQ(member(json, "exit_status").number, 0);
  EXPECT_EQ(member(json, "error").type, JsonValue::Type::Null);
  EXPECT_EQ(member(json, "frames_written").number, 3);
  ASSERT_EQ(member(json, "plan").items.size(), 2u);
  EXPECT_EQ(member(json, "plan").items[1].text, "plan line 2");
  ASSERT_EQ(member(json, "decisions").members.size(), 2u);
  EXPECT_EQ(member(member(json, "decisions"), "path").text, "1d");
  EXPECT_EQ(member(member(json, "decisions"), "blend_weights").text, "0.375,0.625");
  ASSERT_EQ(member(json, "warnings").items.size(), 1u);
  EXPECT_EQ(member(json, "warnings").items[0].text, scene.warnings[0]);
  // Every key of the table, with the value the effective-config printout shows.
  const JsonValue& keys = member(json, "config");
  ASSERT_EQ(keys.members.size(), config.table().options().size());
  for (const vs::OptionSpec& option : config.table().options())
    EXPECT_EQ(member(keys, option.key).text, config.effectiveValue(option.key)) << option.key;
  EXPECT_EQ(member(keys, "LeftViewImageName").text, "(not set)");

  const JsonValue& rows = member(json, "frames");
  ASSERT_EQ(rows.items.size(), 3u);
  for (size_t f = 0; f < 3; ++f) {
    ASSERT_EQ(rows.items[f].members.size(), csv[0].size());
    for (size_t c = 0; c < csv[0].size(); ++c) {
      const JsonValue& cell = member(rows.items[f], csv[0][c]);
      const std::string& text = csv[f + 1][c];
      if (text == "inf") {
        EXPECT_EQ(cell.text, "inf") << csv[0][c];
      } else {
        // The CSV rounds PSNR to 4 decimals and seconds to 6.
        EXPECT_NEAR(jsonNumberOrInf(cell), std::stod(text), 0.6e-4) << csv[0][c] << " frame " << f;
      }
    }
  }
  EXPECT_EQ(member(rows.items[1], "psnr_y").text, "inf");
  EXPECT_EQ(member(rows.items[0], "frame").number, 7);
  EXPECT_DOUBLE_EQ(member(rows.items[2], "total_s").number, 3.5);
  const JsonValue& mean = member(json, "mean");
  EXPECT_DOUBLE_EQ(member(mean, "psnr_y").number, meanY);
  EXPECT_DOUBLE_EQ(member(mean, "psnr_u").number, meanU);
  EXPECT_DOUBLE_EQ(member(mean, "psnr_v").number, meanV);
  EXPECT_DOUBLE_EQ(member(mean, "read_s").number, (0.25 + 0.5 + 1.0) / 3);
  EXPECT_DOUBLE_EQ(member(mean, "total_s").number, 3.5 * (0.25 + 0.5 + 1.0) / 3);
  EXPECT_EQ(mean.find("frame"), nullptr);
}

TEST(RunReport, AFailedRunWritesItsErrorAndTheFramesItWrote) {
  const fs::path dir = vs::test::scratchDir("run_report_failure");
  const vs::Config config = vs::Config::fromText(vs::viewSynOptionTable(), "", "test.cfg", dir.string(),
                                                 {"SummaryFile=" + (dir / "s.json").string()});
  vs::Scene scene;
  scene.settings.textureFormat.chroma = vs::ChromaFormat::Yuv400;
  vs::RunReport report("MeshRender", config);
  EXPECT_THROW(vs::runReported(report,
                               [&]() -> vs::RunSummary {
                                 report.begin(scene, {}, nullptr);
                                 vs::FrameRecord first = record(0, 35.0, 0.0, 0.0, 0.1);
                                 first.psnr.hasChroma = false;
                                 first.psnr.yuv = 35.0;
                                 report.addFrame(first, nullptr);
                                 throw vs::InputError("texture.yuv: frame 1 is short");
                               }),
               vs::InputError);
  const JsonValue json = vs::parseJson(readText(dir / "s.json"), "s.json");
  EXPECT_EQ(member(json, "tool").text, "MeshRender");
  EXPECT_EQ(member(member(json, "build"), "version").text, VS_VERSION);  // the rest: VersionTest
  EXPECT_EQ(member(json, "exit_status").number, 1);
  EXPECT_EQ(member(json, "error").text, "texture.yuv: frame 1 is short");
  EXPECT_EQ(member(json, "frames_written").number, 1);
  ASSERT_EQ(member(json, "frames").items.size(), 1u);
  // 4:0:0 has no chroma: null, not a number.
  EXPECT_EQ(member(member(json, "frames").items[0], "psnr_u").type, JsonValue::Type::Null);
  EXPECT_EQ(member(member(json, "mean"), "psnr_v").type, JsonValue::Type::Null);
  EXPECT_DOUBLE_EQ(member(member(json, "mean"), "psnr_y").number, 35.0);
}

TEST(RunReport, ASummaryFileThatIsAnInputIsNeverWritten) {
  const fs::path dir = vs::test::scratchDir("run_report_input");
  { std::ofstream(dir / "cameras.txt") << "keep me\n"; }
  const vs::Config config = vs::Config::fromText(
      vs::viewSynOptionTable(), "", "test.cfg", dir.string(),
      {"CameraParameterFile=" + (dir / "cameras.txt").string(), "SummaryFile=" + (dir / "cameras.txt").string()});
  vs::RunReport report("ViewSyn", config);
  try {
    report.writeSummary(1, "failed");
    ADD_FAILURE() << "no error";
  } catch (const vs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CameraParameterFile"), std::string::npos) << e.what();
  }
  EXPECT_EQ(readText(dir / "cameras.txt"), "keep me\n");
}

// --- The executables ------------------------------------------------------------------------------

// A tiny generated scene with ground truth (SceneGen's demo), three frames.
fs::path tinyScene(const std::string& name) {
  const fs::path dir = vs::test::scratchDir(name);
  const vs::Config sceneConfig = vs::Config::fromText(
      vs::sceneGenOptionTable(), "", "test", ".",
      {"Scene=demo", "SourceWidth=48", "SourceHeight=32", "TotalNumberOfFrames=3", "OutputFolder=" + dir.string()});
  std::ostringstream quiet;
  vs::generateScene(vs::readSceneGenSettings(sceneConfig), quiet);
  return dir;
}

TEST(RunReportApp, ViewSynSummaryAgreesWithItsCsvAndItsStdout) {
  const fs::path dir = tinyScene("run_report_app");
  const vs::test::ToolResult run =
      vs::test::runTool("ViewSyn",
                        vs::test::quoted((dir / "viewsyn_cam1.cfg").string()) + " " +
                            vs::test::quoted("ReportFile=" + (dir / "r.csv").string()) + " " +
                            vs::test::quoted("SummaryFile=" + (dir / "s.json").string()),
                        dir);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const JsonValue json = vs::parseJson(readText(dir / "s.json"), "s.json");
  const std::vector<std::vector<std::string>> csv = readCsv(dir / "r.csv");
  const JsonValue& frames = member(json, "frames");
  ASSERT_EQ(frames.items.size(), 3u);
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(member(json, "frames_written").number, 3);
  EXPECT_EQ(member(json, "config_file").text, (dir / "viewsyn_cam1.cfg").string());
  // Each frame: the CSV's cells, and the stdout line "frame N: T s  PSNR Y a U b V c dB".
  std::istringstream out(run.out);
  std::map<int64_t, std::string> lines;
  std::string meanLine;
  for (std::string line; std::getline(out, line);) {
    if (line.rfind("frame ", 0) == 0) lines[std::stoll(line.substr(6))] = line;
    if (line.rfind("mean PSNR: ", 0) == 0) meanLine = line;
  }
  for (size_t f = 0; f < 3; ++f) {
    const JsonValue& row = frames.items[f];
    for (size_t c = 0; c < csv[0].size(); ++c)
      EXPECT_NEAR(jsonNumberOrInf(member(row, csv[0][c])), std::stod(csv[f + 1][c]), 0.6e-4) << csv[0][c];
    const int64_t frame = int64_t(member(row, "frame").number);
    ASSERT_TRUE(lines.count(frame)) << frame;
    char expected[256];
    std::snprintf(expected, sizeof expected, "frame %lld: %.4f s  PSNR Y %.4f U %.4f V %.4f dB", (long long)frame,
                  member(row, "total_s").number, member(row, "psnr_y").number, member(row, "psnr_u").number,
                  member(row, "psnr_v").number);
    EXPECT_EQ(lines[frame], expected);
  }
  const JsonValue& mean = member(json, "mean");
  char expected[256];
  std::snprintf(expected, sizeof expected, "mean PSNR: Y %.4f U %.4f V %.4f YUV %.4f dB", member(mean, "psnr_y").number,
                member(mean, "psnr_u").number, member(mean, "psnr_v").number, member(mean, "psnr_yuv").number);
  EXPECT_EQ(meanLine, expected);
  // The config printed at the start, key for key.
  for (const auto& [key, value] : member(json, "config").members) {
    const size_t at = run.out.find("\n" + key + " ");
    ASSERT_NE(at, std::string::npos) << key;
    const size_t end = run.out.find('\n', at + 1);
    std::string printed = run.out.substr(at + 1 + key.size(), end - at - 1 - key.size());
    printed.erase(0, printed.find_first_not_of(' '));
    EXPECT_EQ(printed, value.text) << key;
  }
}

TEST(RunReportApp, ViewSynWritesTheSummaryWhenTheRunFails) {
  const fs::path dir = tinyScene("run_report_app_failure");
  const vs::test::ToolResult run = vs::test::runTool(
      "ViewSyn",
      vs::test::quoted((dir / "viewsyn_cam1.cfg").string()) + " " +
          vs::test::quoted("LeftViewImageName=" + (dir / "missing.yuv").string()) + " " +
          vs::test::quoted("SummaryFile=" + (dir / "s.json").string()),
      dir);
  EXPECT_EQ(run.exitCode, 1);
  const JsonValue json = vs::parseJson(readText(dir / "s.json"), "s.json");
  EXPECT_EQ(member(json, "exit_status").number, 1);
  EXPECT_NE(member(json, "error").text.find("missing.yuv"), std::string::npos);
  EXPECT_NE(run.err.find(member(json, "error").text), std::string::npos) << run.err;
  EXPECT_EQ(member(json, "frames").items.size(), 0u);
  EXPECT_EQ(member(json, "frames_written").number, 0);
}

// The run's warnings (here a depth map a quarter at level 0, found when the inputs are checked) are
// printed and in the summary; a later run that fails keeps the previous output and CSV byte for byte
// and writes only its summary, the record of the failure (doc/report.md).
TEST(RunReportApp, SummaryHoldsTheRunsWarningsAndAFailedRunKeepsThePreviousFiles) {
  const fs::path dir = tinyScene("run_report_app_warnings");
  const std::string cfg = (dir / "viewsyn_cam1.cfg").string();
  const vs::Config config = vs::Config::load(vs::viewSynOptionTable(), cfg, {});
  const std::string depth = config.getPath("LeftDepthMapName"), output = config.getPath("OutputVirtualViewImageName");
  {
    std::fstream file(depth, std::ios::in | std::ios::out | std::ios::binary);
    file.write(std::string(48 * 32 / 4, '\0').data(), 48 * 32 / 4);  // a quarter of frame 0's samples
  }
  const std::string reports = vs::test::quoted("ReportFile=" + (dir / "r.csv").string()) + " " +
                              vs::test::quoted("SummaryFile=" + (dir / "s.json").string());
  // MissingDepthLevel -1: VSRS's reading, which warns about a large share at level 0 (auto tests it instead).
  const vs::test::ToolResult run =
      vs::test::runTool("ViewSyn", vs::test::quoted(cfg) + " MissingDepthLevel=-1 " + reports, dir);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const JsonValue json = vs::parseJson(readText(dir / "s.json"), "s.json");
  bool levelZero = false;
  for (const JsonValue& warning : member(json, "warnings").items) {
    EXPECT_NE(run.out.find("warning: " + warning.text + "\n"), std::string::npos) << warning.text;
    levelZero = levelZero || (warning.text.find(depth) != std::string::npos &&
                              warning.text.find("are at level 0") != std::string::npos);
  }
  EXPECT_TRUE(levelZero) << run.out;

  const std::string outputBefore = readText(output), csvBefore = readText(dir / "r.csv");
  ASSERT_FALSE(outputBefore.empty());
  const vs::test::ToolResult failed = vs::test::runTool(
      "ViewSyn",
      vs::test::quoted(cfg) + " " + vs::test::quoted("RightViewImageName=" + (dir / "missing.yuv").string()) + " " +
          reports,
      dir);
  EXPECT_EQ(failed.exitCode, 1);
  EXPECT_EQ(readText(output), outputBefore);
  EXPECT_EQ(readText(dir / "r.csv"), csvBefore);
  const JsonValue failure = vs::parseJson(readText(dir / "s.json"), "s.json");
  EXPECT_EQ(member(failure, "exit_status").number, 1);
  EXPECT_NE(member(failure, "error").text.find("missing.yuv"), std::string::npos);
  // No temporary file is left beside the outputs.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".vs-"), std::string::npos) << entry.path();
}

TEST(RunReportApp, PrintConfigDescribesTheSceneWithoutOpeningAnyYuvFile) {
  const fs::path dir = tinyScene("run_report_print_config");
  for (const char* tool : {"ViewSyn", "MeshRender"}) {
    const std::string cfg = (dir / (std::string(tool) == "ViewSyn" ? "viewsyn_cam1.cfg" : "meshrender_cam1.cfg")).string();
    // Inputs that do not exist: --print-config must not open them.
    const vs::test::ToolResult run = vs::test::runTool(
        tool, "--print-config " + vs::test::quoted(cfg) + " LeftViewImageName=nothing.yuv RightDepthMapName=none.yuv",
        dir, dir);
    ASSERT_EQ(run.exitCode, 0) << tool << ": " << run.err;
    const JsonValue json = vs::parseJson(run.out, std::string(tool) + " --print-config");
    EXPECT_EQ(member(json, "tool").text, tool);
    EXPECT_EQ(member(json, "version").text, VS_VERSION);
    EXPECT_EQ(member(json, "config_file").text, cfg);
    const vs::OptionTable table = std::string(tool) == "ViewSyn" ? vs::viewSynOptionTable() : vs::meshRenderOptionTable();
    const vs::Config config = vs::Config::load(table, cfg, {"LeftViewImageName=nothing.yuv", "RightDepthMapName=none.yuv"});
    const JsonValue& keys = member(json, "config");
    ASSERT_EQ(keys.members.size(), table.options().size());
    for (const vs::OptionSpec& option : table.options())
      EXPECT_EQ(member(keys, option.key).text, config.effectiveValue(option.key)) << option.key;
    const JsonValue& scene = member(json, "scene");
    EXPECT_EQ(member(scene, "width").number, 48);
    EXPECT_EQ(member(scene, "height").number, 32);
    EXPECT_EQ(member(scene, "chroma").text, "420");
    EXPECT_EQ(member(scene, "bit_depth").number, 8);
    EXPECT_EQ(member(scene, "frames").number, 3);
    EXPECT_EQ(member(scene, "start_frame").number, 0);
    EXPECT_EQ(member(scene, "output").text, config.getPath("OutputVirtualViewImageName"));
    EXPECT_EQ(member(scene, "reference").text, config.getPath("ReferenceVirtualViewImageName"));
    const JsonValue& references = member(scene, "references");
    ASSERT_EQ(references.items.size(), 2u);
    EXPECT_EQ(member(references.items[0], "label").text, "Left");
    EXPECT_EQ(member(references.items[0], "camera").text, config.getString("LeftCameraName"));
    EXPECT_EQ(member(references.items[0], "texture").text, (dir / "nothing.yuv").string());
    EXPECT_EQ(member(references.items[1], "depth").text, (dir / "none.yuv").string());
    EXPECT_EQ(member(references.items[1], "znear").number, config.getDouble("RightNearestDepthValue"));
    EXPECT_EQ(member(references.items[1], "zfar").number, config.getDouble("RightFarthestDepthValue"));
    const JsonValue& camera = member(scene, "virtual_camera");
    EXPECT_EQ(member(camera, "name").text, config.getString("VirtualCameraName"));
    ASSERT_EQ(member(camera, "K").items.size(), 3u);
    EXPECT_EQ(member(camera, "K").items[2].items[2].number, 1.0);
  }
}

}  // namespace
