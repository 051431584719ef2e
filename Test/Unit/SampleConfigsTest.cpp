// Every real VSRS config in ../shared/vsrs-samples parses, and passes `ViewSyn --check` with its camera
// file; every camera file lists all its cameras through --check too. The same for RVS 4.0's own
// synthesis configs and camera files in ../shared/vsrs-samples/rvs (run from that folder, as RVS's
// path rule needs).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "Common/CameraFile.h"
#include "Common/Config.h"
#include "Common/Json.h"
#include "Common/Options.h"
#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

// The camera file each sample config was made for (its own CameraParameterFile names a path on the
// author's machine).
const std::map<std::string, std::string>& cameraFileOf() {
  static const std::map<std::string, std::string> map = {
      {"vsrs42/ViewSynthesis_book.cfg", "cam_param_book_reg.txt"},
      {"vsrs42/ViewSynthesis_butterfly.cfg", "cam_param_bbb_butterfly2_arc+Znear-far.txt"},
      {"vsrs42/ViewSynthesis_champagne.cfg", "cam_param_champagne.txt"},
      {"vsrs42/ViewSynthesis_dog.cfg", "cam_param_dog.txt"},
      {"vsrs42/ViewSynthesis_doorflowers.cfg", "cam_param_doorflowers_reg.txt"},
      {"vsrs42/ViewSynthesis_laptop.cfg", "cam_param_laptop_reg.txt"},
      {"vsrs42/ViewSynthesis_lovebird1.cfg", "cam_param_lovebird1.txt"},
      {"vsrs42/ViewSynthesis_lovebird2.cfg", "cam_param_lovebird2.txt"},
      {"vsrs42/ViewSynthesis_moabit.cfg", "cam_param_outdoor_reg.txt"},
      {"vsrs42/ViewSynthesis_news.cfg", "cam_param_news.txt"},
      {"vsrs42/ViewSynthesis_pantomime.cfg", "cam_param_pantomime.txt"},
      {"vsrs35/ViewSynthesis_book.cfg", "vsrs35/cam_param_book_reg.txt"},
      {"vsrs35/ViewSynthesis_doorflowers.cfg", "vsrs35/cam_param_doorflowers_reg.txt"},
      {"vsrs35/ViewSynthesis_laptop.cfg", "vsrs35/cam_param_laptop_reg.txt"},
      {"vsrs35/ViewSynthesis_moabit.cfg", "vsrs35/cam_param_outdoor_reg.txt"},
      {"vsrs35/virtual_ori_newspaper_5.cfg", "vsrs35/cam_param_news.txt"},
  };
  return map;
}

// `--check` opens the sequences (issue 24), and the samples hold configs and camera files only: the
// config and cameras pass when the only problems reported are sequences that cannot be opened.
void expectOnlyMissingSequences(const std::string& err, const std::string& relative) {
  std::istringstream lines(err);
  std::string line;
  std::getline(lines, line);
  EXPECT_NE(line.find(": input files:"), std::string::npos) << relative << "\n" << err;
  while (std::getline(lines, line))
    EXPECT_NE(line.find(": cannot open: No such file or directory"), std::string::npos) << relative << ": " << line;
}

std::vector<fs::path> sampleConfigs() {
  std::vector<fs::path> configs;
  for (const auto& entry : fs::recursive_directory_iterator(test::samplesDir() / "configs"))
    if (entry.path().extension() == ".cfg") configs.push_back(entry.path());
  std::sort(configs.begin(), configs.end());
  return configs;
}

TEST(SampleConfigs, EveryConfigParses) {
  VS_REQUIRE_DIR(test::samplesDir());
  const std::vector<fs::path> configs = sampleConfigs();
  ASSERT_EQ(configs.size(), 17u);
  for (const fs::path& cfg : configs) {
    EXPECT_NO_THROW({
      const Config config = Config::load(viewSynOptionTable(), cfg.string(), {});
      EXPECT_TRUE(config.isSet("LeftCameraName"));
    }) << cfg;
  }
}

TEST(SampleConfigs, EveryConfigPassesViewSynCheckWithItsCameraFile) {
  VS_REQUIRE_DIR(test::samplesDir());
  const fs::path scratch = test::scratchDir("sample_check");
  for (const fs::path& cfg : sampleConfigs()) {
    const std::string relative = fs::relative(cfg, test::samplesDir() / "configs").generic_string();
    std::string arguments = "--check " + test::quoted(cfg.string());
    std::string cameraFile;
    if (relative == "vsrs42/ViewSynthesis.cfg") {
      // Breakdancers: its camera file is not among the samples, so a stand-in with its three names.
      cameraFile = (scratch / "cam_param_bd.txt").string();
      std::ofstream out(cameraFile);
      for (int k = 0; k < 3; ++k)
        out << "param_bd" << k << "\n1000 0 512\n0 1000 384\n0 0 1\n0\n0\n1 0 0 " << 10 * k << "\n0 1 0 0\n0 0 1 0\n\n";
    } else {
      ASSERT_TRUE(cameraFileOf().count(relative)) << "no camera file known for " << relative;
      cameraFile = (test::samplesDir() / "cameras" / cameraFileOf().at(relative)).string();
    }
    arguments += " " + test::quoted("CameraParameterFile=" + cameraFile);
    if (relative == "vsrs35/virtual_ori_newspaper_5.cfg") {
      // VSRS 3.5 data: negative depth values are world z coordinates of cameras looking down -z.
      const test::ToolResult refused = test::runTool("ViewSyn", arguments, scratch);
      EXPECT_EQ(refused.exitCode, 1);
      EXPECT_NE(refused.err.find("set DepthType 1"), std::string::npos) << refused.err;
      arguments += " DepthType=1";
    }
    const Config config = Config::load(viewSynOptionTable(), cfg.string(), {});
    if (config.getString("SynthesisMode") == "1") {
      // The plan refuses the 1D path on a rig that is not rectified, in --check as in a run (before
      // any input is opened); the rest of the configuration is checked with SynthesisMode auto. A
      // rectified rig passes the plan and meets the absent sequences, checked below.
      const test::ToolResult refused = test::runTool("ViewSyn", arguments, scratch);
      if (refused.exitCode != 0 && refused.err.find(": input files:") == std::string::npos) {
        EXPECT_NE(refused.err.find("SynthesisMode 1 (1D parallel) needs a rectified rig"), std::string::npos)
            << relative << "\n" << refused.err;
        arguments += " SynthesisMode=auto";
      }
    }
    const test::ToolResult result = test::runTool("ViewSyn", arguments, scratch);
    // --check opens the sequences (issue 24), and the samples hold configs and camera files only: the
    // config and cameras pass when the only problems left are sequences that cannot be opened.
    if (result.exitCode == 0) {
      EXPECT_NE(result.out.find("configuration OK"), std::string::npos) << relative;
    } else {
      EXPECT_EQ(result.exitCode, 1) << relative << "\n" << result.err;
      expectOnlyMissingSequences(result.err, relative);
    }
    // The effective configuration lists every key, and the three cameras are printed.
    const OptionTable table = viewSynOptionTable();
    for (const OptionSpec& spec : table.options())
      EXPECT_NE(result.out.find("\n" + spec.key + " "), std::string::npos) << relative << " " << spec.key;
    for (const char* key : {"LeftCameraName", "VirtualCameraName", "RightCameraName"})
      EXPECT_NE(result.out.find(" " + config.getString(key) + "\n"), std::string::npos) << relative << " " << key;
  }
}

TEST(SampleConfigs, CheckNamesTheCamerasAMissingNameCouldBe) {
  VS_REQUIRE_DIR(test::samplesDir());
  const fs::path scratch = test::scratchDir("sample_missing_camera");
  // Every camera of every sample camera file is offered in the error message of a wrong name.
  for (const auto& entry : fs::recursive_directory_iterator(test::samplesDir() / "cameras")) {
    if (entry.path().extension() != ".txt") continue;
    const CameraFile file = readCameraFile(entry.path().string());
    const test::ToolResult result = test::runTool(
        "ViewSyn",
        "--check " + test::quoted((test::samplesDir() / "configs/vsrs42/ViewSynthesis_book.cfg").string()) + " " +
            test::quoted("CameraParameterFile=" + entry.path().string()) + " LeftCameraName=no_such_camera",
        scratch);
    EXPECT_EQ(result.exitCode, 1) << entry.path();
    EXPECT_NE(result.err.find("camera 'no_such_camera' named by LeftCameraName is not in the file"), std::string::npos)
        << result.err;
    for (const Camera& camera : file.cameras()) EXPECT_NE(result.err.find(camera.name), std::string::npos) << camera.name;
  }
}

// RVS 4.0's configs (rvs/config_files): every one passes --check up to its absent sequences,
// equirectangular cameras included; what each asks for is read from the config itself, by the test, and
// must show in the configuration printed: a mask or masked depth output (OutputMasks,
// MaskedDepthOutputFiles) its key of ours, a virtual camera of another size than the inputs its size.
std::vector<fs::path> rvsConfigs() {
  std::vector<fs::path> configs;
  const fs::path folder = test::samplesDir() / "rvs" / "config_files";
  if (!fs::is_directory(folder)) return configs;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.path().extension() == ".json" && entry.path().parent_path() != folder) configs.push_back(entry.path());
  configs.push_back(folder / "example_config_file.json");
  std::sort(configs.begin(), configs.end());
  return configs;
}

JsonValue readJson(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return parseJson(text.str(), path.string());
}

TEST(SampleConfigs, EveryRvsConfigPassesViewSynCheckFromTheRvsFolder) {
  VS_REQUIRE_DIR(test::samplesDir() / "rvs" / "config_files");
  const fs::path rvs = test::samplesDir() / "rvs";
  const fs::path scratch = test::scratchDir("sample_rvs_check");
  const std::vector<fs::path> configs = rvsConfigs();
  EXPECT_EQ(configs.size(), 345u);
  std::map<std::string, int> outcomes;
  for (const fs::path& path : configs) {
    const std::string relative = fs::relative(path, rvs).generic_string();
    const JsonValue config = readJson(path);
    // What RVS's own camera files say of the cameras this config names, after its overrides.
    const JsonValue cameras = readJson(rvs / config.find("InputCameraParameterFile")->text);
    auto camera = [&](const std::string& name) -> const JsonValue& {
      for (const JsonValue& c : cameras.find("cameras")->items)
        if (c.find("Name")->text == name) return c;
      ADD_FAILURE() << relative << ": no camera " << name;
      return cameras;
    };
    auto field = [&](const JsonValue& c, const char* overridesKey, const char* key) {
      const JsonValue* overrides = config.find(overridesKey);
      const JsonValue* value = overrides ? overrides->find(key) : nullptr;
      return value ? value : c.find(key);
    };
    bool equirectangular = false, otherSize = false;
    const JsonValue& first = camera(config.find("InputCameraNames")->items[0].text);
    for (const JsonValue& name : config.find("InputCameraNames")->items)
      equirectangular = equirectangular || field(camera(name.text), "InputOverrides", "Projection")->text == "Equirectangular";
    for (const JsonValue& name : config.find("VirtualCameraNames")->items) {
      const JsonValue& c = camera(name.text);
      equirectangular = equirectangular || field(c, "VirtualOverrides", "Projection")->text == "Equirectangular";
      otherSize = otherSize || field(c, "VirtualOverrides", "Resolution")->items[0].number !=
                                   field(first, "InputOverrides", "Resolution")->items[0].number ||
                  field(c, "VirtualOverrides", "Resolution")->items[1].number !=
                      field(first, "InputOverrides", "Resolution")->items[1].number;
    }
    // A key as --print-config and --check print it: padded to 33 characters, then its value.
    auto printed = [](const std::string& key, const std::string& value) {
      return key + std::string(key.size() < 33 ? 33 - key.size() : 1, ' ') + value + "\n";
    };
    const test::ToolResult result = test::runTool("ViewSyn", "--check " + test::quoted(relative), scratch, rvs);
    ASSERT_TRUE(result.exitCode == 0 || result.exitCode == 1) << relative << "\n" << result.err;  // no crash
    // Passes up to the absent sequences (the samples hold configs and camera files only).
    const std::string outcome = equirectangular ? "passes (equirectangular cameras)" : "passes (perspective cameras)";
    if (result.exitCode != 0) expectOnlyMissingSequences(result.err, relative);
    // Every virtual camera's configuration is printed: its camera and its outputs, masks included.
    const auto& names = config.find("VirtualCameraNames")->items;
    for (size_t v = 0; v < names.size(); ++v) {
      EXPECT_NE(result.out.find(printed("VirtualCameraName", names[v].text)), std::string::npos) << relative;
      using KeyPair = std::pair<const char*, const char*>;
      for (const auto& [rvsKey, ours] : {KeyPair{"OutputMasks", "OutputVirtualMaskName"},
                                         KeyPair{"MaskedDepthOutputFiles", "OutputMaskedVirtualDepthMapName"}})
        if (const JsonValue* files = config.find(rvsKey)) {
          if (v == 0) ++outcomes[std::string("with ") + rvsKey];
          EXPECT_NE(result.out.find(printed(ours, files->items[v].text)), std::string::npos) << relative << ": " << ours;
        }
    }
    if (otherSize) {
      // The virtual view at the virtual camera's Resolution (RVS's rule), not the inputs' size.
      const JsonValue& c = camera(names[0].text);
      const auto& resolution = field(c, "VirtualOverrides", "Resolution")->items;
      EXPECT_NE(result.out.find(printed("VirtualWidth", std::to_string(int(resolution[0].number)))), std::string::npos)
          << relative << "\n" << result.out;
      EXPECT_NE(result.out.find(printed("VirtualHeight", std::to_string(int(resolution[1].number)))), std::string::npos)
          << relative;
      ++outcomes["with a virtual camera of another size"];
    }
    ++outcomes[outcome];
  }
  for (const auto& [outcome, count] : outcomes) std::printf("RVS configs, %s: %d\n", outcome.c_str(), count);
  // Counted from the configs themselves above; written out here so that a change shows.
  // Every one passes: none is refused any more (the four refused before asked for masks and a virtual
  // view of another size, which ViewSyn now writes).
  EXPECT_EQ(outcomes["passes (perspective cameras)"], 5);
  EXPECT_EQ(outcomes["passes (equirectangular cameras)"], 340);
  EXPECT_EQ(outcomes["with OutputMasks"], 2);
  EXPECT_EQ(outcomes["with MaskedDepthOutputFiles"], 1);
  EXPECT_EQ(outcomes["with a virtual camera of another size"], 1);
}

TEST(SampleConfigs, EveryRvsCameraFileListsItsCamerasThroughCheck) {
  VS_REQUIRE_DIR(test::samplesDir() / "rvs" / "config_files");
  const fs::path rvs = test::samplesDir() / "rvs";
  const fs::path scratch = test::scratchDir("sample_rvs_cameras");
  for (const char* file : {"ClassroomVideo.json", "TechnicolorHijack.json", "TechnicolorMuseum.json", "ULB_Unicorn.json"}) {
    const std::string cameras = "config_files/" + std::string(file);
    const test::ToolResult result = test::runTool(
        "ViewSyn",
        "--check config_files/example_config_file.json CameraParameterFile=" + cameras +
            " VirtualCameraParameterFile=" + cameras + " VirtualCameraName=no_such_camera",
        scratch, rvs);
    EXPECT_EQ(result.exitCode, 1) << file;
    // Handed to ViewSyn as a config, a camera file is named for what it is.
    const test::ToolResult asConfig = test::runTool("ViewSyn", "--check " + cameras, scratch, rvs);
    EXPECT_NE(asConfig.err.find("this is a camera parameter file"), std::string::npos) << asConfig.err;
    EXPECT_NE(result.err.find("camera 'no_such_camera' named by VirtualCameraName is not in the file"), std::string::npos)
        << result.err;
    const JsonValue document = readJson(rvs / cameras);
    for (const JsonValue& camera : document.find("cameras")->items)
      EXPECT_NE(result.err.find(camera.find("Name")->text), std::string::npos) << file << " " << camera.find("Name")->text;
  }
}

}  // namespace
}  // namespace vs
