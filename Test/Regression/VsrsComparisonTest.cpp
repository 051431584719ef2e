// ViewSyn against VSRS 4.2 on the real data sets, with VSRS's own figures from
// ../shared/data/vsrs_baseline.csv: the shipped general configs, unchanged, must keep the mean
// PSNR-Y over the Middlebury 2005/2006 scenes at least 1 dB above VSRS's (view 3 from views 1 and
// 5) with no scene more than 0.3 dB below VSRS's, and beat VSRS on the rotated open3d set.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Options.h"
#include "Synth/ViewSynRenderer.h"
#include "TestPaths.h"

namespace vs {
namespace {

// PSNR-Y of VSRS 4.2 per "set/scene/target/mode" from the baseline table.
std::map<std::string, double> vsrsPsnrY(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::map<std::string, double> psnr;
  std::string line;
  std::getline(in, line);  // header: set,scene,target,mode,precision,filter,width,height,psnr_y,...
  while (std::getline(in, line)) {
    std::vector<std::string> field;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) field.push_back(cell);
    if (field.size() >= 9) psnr[field[0] + "/" + field[1] + "/" + field[2] + "/" + field[3]] = std::stod(field[8]);
  }
  return psnr;
}

double ourPsnrY(const std::filesystem::path& folder, const std::string& config, const std::string& target,
                const std::filesystem::path& scratch) {
  const Config c = Config::load(viewSynOptionTable(), (folder / config).string(),
                                {"OutputVirtualViewImageName=" + (scratch / "out.yuv").string(),
                                 "ReferenceVirtualViewImageName=" + (folder / (target + ".yuv")).string()});
  return runViewSyn(c, nullptr).meanPsnrY;
}

TEST(VsrsComparison, MiddleburyMeanIsAtLeastOneDecibelAboveVsrsAndNoSceneFarBelowWithTheShippedConfigs) {
  const std::filesystem::path data = test::dataDir();
  VS_REQUIRE_DIR(data / "middlebury2005");
  VS_REQUIRE_DIR(data / "middlebury2006");
  const std::map<std::string, double> vsrs = vsrsPsnrY(data / "vsrs_baseline.csv");
  const std::filesystem::path scratch = test::scratchDir("vsrs_middlebury");
  double ours = 0, theirs = 0;
  int scenes = 0;
  for (const char* set : {"middlebury2005", "middlebury2006"})
    for (const auto& entry : std::filesystem::directory_iterator(data / set)) {
      if (!std::filesystem::exists(entry.path() / "synth_view3_general.cfg")) continue;
      const std::string key = std::string(set) + "/" + entry.path().filename().string() + "/view3/general";
      const auto baseline = vsrs.find(key);
      ASSERT_NE(baseline, vsrs.end()) << key << " is missing from vsrs_baseline.csv";
      const double psnr = ourPsnrY(entry.path(), "synth_view3_general.cfg", "view3", scratch);
      EXPECT_GE(psnr, baseline->second - 0.3) << key << ": ours " << psnr << " dB, VSRS " << baseline->second << " dB";
      ours += psnr;
      theirs += baseline->second;
      ++scenes;
    }
  ASSERT_GT(scenes, 0);
  ours /= scenes;
  theirs /= scenes;
  EXPECT_GE(ours, theirs + 1.0) << scenes << " scenes: ours " << ours << " dB, VSRS " << theirs << " dB";
}

TEST(VsrsComparison, Open3dBeatsVsrs) {
  const std::filesystem::path folder = test::dataDir() / "open3d" / "RGBD5";
  VS_REQUIRE_DIR(folder);
  const std::map<std::string, double> vsrs = vsrsPsnrY(test::dataDir() / "vsrs_baseline.csv");
  const auto baseline = vsrs.find("open3d/RGBD5/view2/general");
  ASSERT_NE(baseline, vsrs.end());
  const double ours = ourPsnrY(folder, "synth_view2_general.cfg", "view2", test::scratchDir("vsrs_open3d"));
  EXPECT_GT(ours, baseline->second);
}

}  // namespace
}  // namespace vs
