#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "TestPaths.h"

namespace vs {
namespace {

OptionTable smallTable() {
  OptionTable table("Test");
  OptionSpec width;
  width.key = "SourceWidth";
  width.type = OptionType::Int;
  width.defaultValue = "1280";
  width.minValue = 1;
  width.maxValue = 16384;
  table.add(width);
  OptionSpec zfar;
  zfar.key = "LeftFarthestDepthValue";
  zfar.type = OptionType::Double;
  zfar.defaultValue = "0";
  zfar.allowInfinity = true;
  table.add(zfar);
  OptionSpec znear = zfar;
  znear.key = "LeftNearestDepthValue";
  znear.allowInfinity = false;
  table.add(znear);
  OptionSpec file;
  file.key = "LeftViewImageName";
  file.type = OptionType::Path;
  file.required = true;
  table.add(file);
  OptionSpec precision;
  precision.key = "Precision";
  precision.type = OptionType::Choice;
  precision.choices = {"1", "2", "4"};
  precision.defaultValue = "2";
  table.add(precision);
  return table;
}

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ReadsVsrsSyntaxWithCommentsTabsAndCrlf) {
  const OptionTable table = smallTable();
  const std::string text =
      "# header comment\r\n"
      "SourceWidth\t\t  1024   # Input frame width\r\n"
      "\r\n"
      "   LeftFarthestDepthValue 141.044#no space before comment\r\n"
      "LeftViewImageName  view1.yuv\r\n"
      "Precision 4\r\n";
  const Config config = Config::fromText(table, text, "a.cfg", "/data/scene");
  EXPECT_EQ(config.getInt("SourceWidth"), 1024);
  EXPECT_DOUBLE_EQ(config.getDouble("LeftFarthestDepthValue"), 141.044);
  EXPECT_EQ(config.getString("Precision"), "4");
  // No '\r' may survive in a value.
  EXPECT_EQ(config.getString("LeftViewImageName"), "view1.yuv");
  EXPECT_EQ(config.getPath("LeftViewImageName"), "/data/scene/view1.yuv");
  EXPECT_EQ(config.origin("SourceWidth"), "a.cfg:2");
  EXPECT_EQ(config.origin("LeftNearestDepthValue"), "default");
}

TEST(Config, LastSettingWinsAndCommandLineOverrides) {
  const OptionTable table = smallTable();
  const std::string text = "SourceWidth 640\nSourceWidth 800\nLeftViewImageName a.yuv\n";
  const Config fileOnly = Config::fromText(table, text, "a.cfg", "/x");
  EXPECT_EQ(fileOnly.getInt("SourceWidth"), 800);
  EXPECT_EQ(fileOnly.origin("SourceWidth"), "a.cfg:2");
  const Config overridden = Config::fromText(table, text, "a.cfg", "/x", {"SourceWidth=320", "LeftViewImageName=b.yuv"});
  EXPECT_EQ(overridden.getInt("SourceWidth"), 320);
  EXPECT_EQ(overridden.origin("SourceWidth"), "command line");
  // Command-line paths resolve against the working directory, not the config's folder.
  EXPECT_EQ(overridden.getPath("LeftViewImageName"),
            (std::filesystem::current_path() / "b.yuv").lexically_normal().string());
}

TEST(Config, DefaultsApplyWhenUnset) {
  const Config config = Config::fromText(smallTable(), "LeftViewImageName v.yuv\n", "a.cfg", "/x");
  EXPECT_FALSE(config.isSet("SourceWidth"));
  EXPECT_EQ(config.getInt("SourceWidth"), 1280);
  EXPECT_EQ(config.getString("Precision"), "2");
}

// `auto` is a value only of the Int keys that allow it (MissingDepthLevel, MissingDepthFill); an
// explicit level keeps its meaning.
TEST(Config, AutoOnlyWhereAllowed) {
  const OptionTable table = viewSynOptionTable();
  const Config autoConfig = Config::fromText(table, "MissingDepthLevel auto\nMissingDepthFill auto\n", "a.cfg", "/x");
  EXPECT_TRUE(autoConfig.isAuto("MissingDepthLevel"));
  EXPECT_TRUE(autoConfig.isAuto("MissingDepthFill"));
  const Config explicitConfig = Config::fromText(table, "MissingDepthLevel 0\n", "a.cfg", "/x");
  EXPECT_FALSE(explicitConfig.isAuto("MissingDepthLevel"));
  EXPECT_EQ(explicitConfig.getInt("MissingDepthLevel"), 0);
  EXPECT_TRUE(explicitConfig.isAuto("MissingDepthFill")) << "the default; with an explicit level it means 0";
  const Config unset = Config::fromText(table, "", "a.cfg", "/x");
  EXPECT_TRUE(unset.isAuto("MissingDepthLevel")) << "auto is the default (issue 32)";
  EXPECT_TRUE(unset.isAuto("MissingDepthFill"));
  const Config vsrs = Config::fromText(table, "MissingDepthLevel -1\nMissingDepthFill 0\n", "a.cfg", "/x");
  EXPECT_FALSE(vsrs.isAuto("MissingDepthLevel"));
  EXPECT_EQ(vsrs.getInt("MissingDepthLevel"), -1);
  EXPECT_FALSE(vsrs.isAuto("MissingDepthFill"));
  const std::string error = errorOf([&] { Config::fromText(table, "DepthBlendDifference auto\n", "a.cfg", "/x"); });
  EXPECT_NE(error.find("a.cfg:1: DepthBlendDifference = 'auto'"), std::string::npos) << error;
  const std::string level = errorOf([&] { Config::fromText(table, "MissingDepthLevel automatic\n", "a.cfg", "/x"); });
  EXPECT_NE(level.find("or auto"), std::string::npos) << level;
}

TEST(Config, InfinityOnlyWhereAllowed) {
  const OptionTable table = smallTable();
  const Config config = Config::fromText(table, "LeftFarthestDepthValue inf\n", "a.cfg", "/x");
  EXPECT_TRUE(std::isinf(config.getDouble("LeftFarthestDepthValue")));
  const std::string error = errorOf([&] { Config::fromText(table, "LeftNearestDepthValue inf\n", "a.cfg", "/x"); });
  EXPECT_NE(error.find("a.cfg:1: LeftNearestDepthValue = 'inf'"), std::string::npos) << error;
  EXPECT_NE(errorOf([&] { Config::fromText(table, "LeftNearestDepthValue nan\n", "a.cfg", "/x"); }), "");
  EXPECT_NE(errorOf([&] { Config::fromText(table, "LeftNearestDepthValue 0x10\n", "a.cfg", "/x"); }), "");
}

TEST(Config, EveryFiniteDoubleIsInTheDefaultRange) {
  // A double option without a range of its own takes every finite value: 1e308 (near the largest double)
  // is a valid Zfar, not "not finite"; 1e309 overflows and is refused.
  const OptionTable table = smallTable();
  const Config config = Config::fromText(table, "LeftFarthestDepthValue 1e308\nLeftNearestDepthValue -1.7e308\n", "a.cfg", "/x");
  EXPECT_EQ(config.getDouble("LeftFarthestDepthValue"), 1e308);
  EXPECT_EQ(config.getDouble("LeftNearestDepthValue"), -1.7e308);
  const std::string error = errorOf([&] { Config::fromText(table, "LeftNearestDepthValue 1e309\n", "a.cfg", "/x"); });
  EXPECT_NE(error.find("a.cfg:1: LeftNearestDepthValue = '1e309': expected a finite number"), std::string::npos)
      << error;
}

TEST(Config, UnknownKeyNamesFileLineAndNearestKey) {
  const std::string error =
      errorOf([] { Config::fromText(smallTable(), "SourceWidth 10\nPrecison 4\n", "my.cfg", "/x"); });
  EXPECT_NE(error.find("my.cfg:2: unknown key 'Precison' (did you mean 'Precision'?)"), std::string::npos) << error;
  const std::string far = errorOf([] { Config::fromText(smallTable(), "CompletelyUnrelated 4\n", "my.cfg", "/x"); });
  EXPECT_NE(far.find("unknown key 'CompletelyUnrelated'"), std::string::npos);
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
}

TEST(Config, EveryProblemIsReportedInOneRun) {
  const std::string text =
      "SourceWidth\n"                 // missing value
      "SourceWidth 10 20\n"           // three tokens
      "Precision 3\n"                 // not a choice
      "SourceWidth -5\n"              // out of range (a later line: must still be reported)
      "Bogus 1\n";                    // unknown
  const std::string error = errorOf([&] { Config::fromText(smallTable(), text, "bad.cfg", "/x", {"Nonsense"}); });
  EXPECT_NE(error.find("bad.cfg:1: key 'SourceWidth' has no value"), std::string::npos) << error;
  EXPECT_NE(error.find("bad.cfg:2: key 'SourceWidth' takes one value but 2 were given"), std::string::npos) << error;
  EXPECT_NE(error.find("bad.cfg:3: Precision = '3': expected one of 1, 2, 4"), std::string::npos) << error;
  EXPECT_NE(error.find("bad.cfg:4: SourceWidth = '-5': expected an integer in [1, 16384]"), std::string::npos) << error;
  EXPECT_NE(error.find("bad.cfg:5: unknown key 'Bogus'"), std::string::npos) << error;
  EXPECT_NE(error.find("command line: argument 'Nonsense' is not of the form Key=Value"), std::string::npos) << error;
}

TEST(Config, BinaryJunkAndHugeLinesAreRefusedWithTheirLine) {
  std::string junk = "SourceWidth 10\n";
  junk += std::string("Precision \0\x01\x02", 13) + "\n";
  const std::string error = errorOf([&] { Config::fromText(smallTable(), junk, "junk.cfg", "/x"); });
  EXPECT_NE(error.find("junk.cfg:2: unexpected control byte 0x00"), std::string::npos) << error;

  const std::string huge = "SourceWidth " + std::string(10 * 1024 * 1024, '7') + "\n";
  const std::string hugeError = errorOf([&] { Config::fromText(smallTable(), huge, "huge.cfg", "/x"); });
  EXPECT_NE(hugeError.find("huge.cfg:1: line is 10485772 characters long"), std::string::npos) << hugeError;
}

TEST(Config, LoadRefusesMissingFileAndFolder) {
  const std::string missing = errorOf([] { Config::load(smallTable(), "/nonexistent/dir/x.cfg", {}); });
  EXPECT_NE(missing.find("/nonexistent/dir/x.cfg: config file not found"), std::string::npos) << missing;
  const auto dir = test::scratchDir("config_folder");
  EXPECT_NE(errorOf([&] { Config::load(smallTable(), dir.string(), {}); }).find("is a folder"), std::string::npos);
}

TEST(Config, LoadResolvesPathsAgainstTheConfigFolderWithWindowsSeparators) {
  const auto dir = test::scratchDir("config_paths");
  std::filesystem::create_directories(dir / "cfg");
  {
    std::ofstream out(dir / "cfg" / "a.cfg", std::ios::binary);
    out << "LeftViewImageName ..\\\\seq\\\\left.yuv\r\n";
  }
  const Config config = Config::load(smallTable(), (dir / "cfg" / "a.cfg").string(), {});
  EXPECT_EQ(config.getPath("LeftViewImageName"), (dir / "seq" / "left.yuv").string());
}

TEST(Config, RequiredKeysAreListed) {
  const Config config = Config::fromText(smallTable(), "SourceWidth 10\n", "r.cfg", "/x");
  ProblemList problems;
  config.requireKeys(problems, {"Precision"});
  ASSERT_EQ(problems.problems().size(), 2u);
  EXPECT_NE(problems.problems()[0].find("missing required key 'LeftViewImageName'"), std::string::npos);
  EXPECT_NE(problems.problems()[1].find("missing required key 'Precision'"), std::string::npos);
}

TEST(Config, ResolvePath) {
  EXPECT_EQ(resolvePath("a\\b\\\\c.yuv", "/base"), "/base/a/b/c.yuv");
  EXPECT_EQ(resolvePath("/abs/x.yuv", "/base"), "/abs/x.yuv");
  EXPECT_EQ(resolvePath("../x.yuv", "/base/sub"), "/base/x.yuv");
  EXPECT_EQ(resolvePath("I:\\seq\\x.yuv", "/base"), "I:/seq/x.yuv");  // a drive path is never made relative
}

TEST(Config, ParseNumbers) {
  double d = 0;
  EXPECT_TRUE(parseDouble("-2.424092", d, false));
  EXPECT_DOUBLE_EQ(d, -2.424092);
  EXPECT_TRUE(parseDouble("1e3", d, false));
  EXPECT_DOUBLE_EQ(d, 1000);
  EXPECT_FALSE(parseDouble("1.5x", d, false));
  EXPECT_FALSE(parseDouble("", d, false));
  EXPECT_FALSE(parseDouble("1e999", d, false));
  int64_t i = 0;
  EXPECT_TRUE(parseInt("-12", i));
  EXPECT_EQ(i, -12);
  EXPECT_FALSE(parseInt("12.0", i));
  EXPECT_FALSE(parseInt("99999999999999999999999", i));
}

TEST(Options, ViewSynTableHoldsEveryVsrs42Key) {
  const OptionTable table = viewSynOptionTable();
  for (const char* key :
       {"DepthType", "SourceWidth", "SourceHeight", "StartFrame", "TotalNumberOfFrames", "LeftNearestDepthValue",
        "LeftFarthestDepthValue", "RightNearestDepthValue", "RightFarthestDepthValue", "CameraParameterFile",
        "LeftCameraName", "VirtualCameraName", "RightCameraName", "LeftViewImageName", "RightViewImageName",
        "LeftDepthMapName", "RightDepthMapName", "OutputVirtualViewImageName", "ColorSpace", "Precision", "Filter",
        "SynthesisMode", "BoundaryNoiseRemoval", "ViewBlending", "DepthBlendDifference", "IvsrsInpaint",
        "SplattingOption", "BoundaryGrowth", "MergingOption", "DepthThreshold", "HoleCountThreshold",
        "TemporalImprovementOption", "WarpEnhancementOption", "CleanNoiseOption"}) {
    const OptionSpec* spec = table.find(key);
    ASSERT_NE(spec, nullptr) << key;
    EXPECT_FALSE(spec->help.empty()) << key;
    EXPECT_FALSE(spec->vsrsDefault.empty() || spec->vsrsDefault == "-") << key << " is a VSRS key";
  }
}

TEST(Options, DefaultsSatisfyTheirOwnRanges) {
  const std::vector<OptionTable> tables = {viewSynOptionTable(), meshRenderOptionTable()};
  for (const OptionTable& table : tables) {
    std::vector<std::string> overrides;
    for (const OptionSpec& spec : table.options())
      if (!spec.defaultValue.empty()) overrides.push_back(spec.key + "=" + spec.defaultValue);
    EXPECT_NO_THROW(Config::fromText(table, "", "defaults", "/x", overrides)) << table.toolName();
  }
}

TEST(Options, HelpListsEveryKey) {
  const OptionTable table = meshRenderOptionTable();
  const std::string help = table.helpText();
  for (const OptionSpec& spec : table.options()) EXPECT_NE(help.find("  " + spec.key + "  ("), std::string::npos) << spec.key;
}

}  // namespace
}  // namespace vs
