// The ready configs in cfg/: each reads with its tool's option table; the demo's synthesis configs say
// what SceneGen writes for cfg/demo/scenegen.cfg (same keys and values, files in its output folder);
// the Art config names the data set's files and keeps the data set's own settings.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Config.h"
#include "Common/Options.h"
#include "Scene/SceneGen.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

const fs::path kCfg = fs::path(VS_SOURCE_DIR) / "cfg";

OptionTable tableFor(const fs::path& cfg) {
  const std::string name = cfg.filename().string();
  if (name.rfind("scenegen", 0) == 0) return sceneGenOptionTable();
  if (name.rfind("meshrender", 0) == 0) return meshRenderOptionTable();
  return viewSynOptionTable();
}

std::string normal(const std::string& path) { return fs::weakly_canonical(fs::path(path)).string(); }

TEST(ReadyConfigs, EveryConfigInCfgReadsWithItsToolsTable) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kCfg)) {
    if (entry.path().extension() != ".cfg") continue;
    ++count;
    EXPECT_NO_THROW(Config::load(tableFor(entry.path()), entry.path().string(), {})) << entry.path();
  }
  EXPECT_GE(count, 4);  // demo: scenegen, viewsyn, meshrender; art_view3
}

// SceneGen run with cfg/demo/scenegen.cfg (small, so that it takes a fraction of a second) writes
// configs whose every key equals the ready config's, sizes aside; file keys name the same files in
// the folder that scenegen.cfg's OutputFolder names.
TEST(ReadyConfigs, DemoConfigsSayWhatSceneGenWritesForTheDemo) {
  const fs::path scratch = test::scratchDir("ready_configs_demo");
  const Config sceneGenConfig = Config::load(sceneGenOptionTable(), (kCfg / "demo" / "scenegen.cfg").string(),
                                             {"SourceWidth=64", "SourceHeight=48", "TotalNumberOfFrames=2",
                                              "Threads=1", "OutputFolder=" + scratch.string()});
  std::ostringstream log;
  generateScene(readSceneGenSettings(sceneGenConfig), log);
  const std::string demoFolder =
      normal(Config::load(sceneGenOptionTable(), (kCfg / "demo" / "scenegen.cfg").string(), {}).getPath("OutputFolder"));
  EXPECT_EQ(demoFolder, normal((fs::path(VS_SOURCE_DIR) / "out" / "demo").string()));

  for (const char* name : {"viewsyn_cam1.cfg", "meshrender_cam1.cfg"}) {
    SCOPED_TRACE(name);
    const OptionTable table = tableFor(name);
    const Config ready = Config::load(table, (kCfg / "demo" / name).string(), {});
    const Config written = Config::load(table, (scratch / name).string(), {});
    for (const OptionSpec& spec : table.options()) {
      SCOPED_TRACE(spec.key);
      if (spec.key == "SourceWidth" || spec.key == "SourceHeight" || spec.key == "TotalNumberOfFrames") {
        EXPECT_TRUE(ready.isSet(spec.key));
        continue;
      }
      EXPECT_EQ(ready.isSet(spec.key), written.isSet(spec.key));
      if (spec.type == OptionType::Path && written.isSet(spec.key)) {
        const fs::path readyPath = ready.getPath(spec.key), writtenPath = written.getPath(spec.key);
        EXPECT_EQ(readyPath.filename(), writtenPath.filename());
        EXPECT_EQ(normal(readyPath.parent_path().string()), demoFolder);
      } else {
        EXPECT_EQ(ready.raw(spec.key), written.raw(spec.key));
      }
    }
  }
  fs::remove_all(scratch);
}

TEST(ReadyConfigs, ArtConfigNamesTheDataSetsFilesWithItsSettings) {
  const fs::path art = test::dataDir() / "middlebury2005" / "Art";
  if (!fs::exists(art / "synth_view3_general.cfg")) GTEST_SKIP() << art << " is absent";
  if (normal(test::dataDir().string()) != normal((fs::path(VS_SOURCE_DIR) / ".." / "shared" / "data").string()))
    GTEST_SKIP() << "VS_DATA_DIR is not ../shared/data, which cfg/art_view3.cfg names";
  const OptionTable table = viewSynOptionTable();
  const Config ready = Config::load(table, (kCfg / "art_view3.cfg").string(), {});
  const Config original = Config::load(table, (art / "synth_view3_general.cfg").string(), {});
  for (const OptionSpec& spec : table.options()) {
    SCOPED_TRACE(spec.key);
    if (spec.key == "OutputVirtualViewImageName") {
      EXPECT_EQ(normal(ready.getPath(spec.key)), normal((fs::path(VS_SOURCE_DIR) / "out" / "art_view3.yuv").string()));
    } else if (spec.key == "ReferenceVirtualViewImageName") {
      EXPECT_EQ(normal(ready.getPath(spec.key)), normal((art / "view3.yuv").string()));
    } else if (spec.type == OptionType::Path) {
      EXPECT_EQ(ready.isSet(spec.key), original.isSet(spec.key));
      if (original.isSet(spec.key)) {
        EXPECT_EQ(normal(ready.getPath(spec.key)), normal(original.getPath(spec.key)));
        EXPECT_TRUE(fs::exists(ready.getPath(spec.key)));
      }
    } else {
      EXPECT_EQ(ready.isSet(spec.key), original.isSet(spec.key));
      EXPECT_EQ(ready.raw(spec.key), original.raw(spec.key));
    }
  }
}

}  // namespace
}  // namespace vs
