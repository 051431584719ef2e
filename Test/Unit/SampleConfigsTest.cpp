// Every real VSRS config in ../shared/vsrs-samples parses, and passes `ViewSyn --check` with its camera
// file; every camera file lists all its cameras through --check too.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "Common/CameraFile.h"
#include "Common/Config.h"
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
      // The plan refuses the 1D path on a rig that is not rectified, in --check as in a run; the rest
      // of the configuration is checked with SynthesisMode auto.
      const test::ToolResult refused = test::runTool("ViewSyn", arguments, scratch);
      if (refused.exitCode != 0) {
        EXPECT_NE(refused.err.find("SynthesisMode 1 (1D parallel) needs a rectified rig"), std::string::npos)
            << relative << "\n" << refused.err;
        arguments += " SynthesisMode=auto";
      }
    }
    const test::ToolResult result = test::runTool("ViewSyn", arguments, scratch);
    EXPECT_EQ(result.exitCode, 0) << relative << "\n" << result.err;
    EXPECT_NE(result.out.find("configuration OK"), std::string::npos) << relative;
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

}  // namespace
}  // namespace vs
