// The key templates in cfg/ equal the option tables (regenerate with scripts/update_manual.sh, which
// runs this test with VS_UPDATE_TEMPLATES=1), and a template read as a config gives every default.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "TestPaths.h"

namespace vs {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path templatePath(const OptionTable& table) {
  return fs::path(VS_SOURCE_DIR) / "cfg" / (table.toolName() + ".cfg.template");
}

void expectTemplateMatches(const OptionTable& table) {
  const fs::path path = templatePath(table);
  const std::string generated = table.configTemplate();
  const char* update = std::getenv("VS_UPDATE_TEMPLATES");
  if (update && std::string(update) == "1" && readFile(path) != generated) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << generated;
    std::printf("updated %s\n", path.string().c_str());
  }
  EXPECT_TRUE(readFile(path) == generated) << path << " differs from " << table.toolName()
                                          << "'s option table: run scripts/update_manual.sh";
}

// Read back as a config, the template sets exactly the keys that have a default, each to it, and
// names every other key on a `#Key` line.
void expectTemplateReadsAsDefaults(const OptionTable& table) {
  const std::string text = table.configTemplate();
  const Config config = Config::fromText(table, text, table.toolName() + ".cfg.template", ".");
  for (const OptionSpec& spec : table.options()) {
    SCOPED_TRACE(spec.key);
    if (spec.defaultValue.empty()) {
      EXPECT_FALSE(config.isSet(spec.key));
      EXPECT_NE(text.find("\n#" + spec.key + "\n"), std::string::npos);
    } else {
      EXPECT_TRUE(config.isSet(spec.key));
      EXPECT_EQ(config.raw(spec.key), spec.defaultValue);
    }
    EXPECT_NE(text.find(spec.help.substr(0, 20)), std::string::npos) << "help missing";
  }
  size_t longest = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) longest = std::max(longest, line.size());
  EXPECT_LE(longest, 100u);
}

TEST(ConfigTemplate, ViewSynTemplateEqualsTheOptionTable) { expectTemplateMatches(viewSynOptionTable()); }
TEST(ConfigTemplate, MeshRenderTemplateEqualsTheOptionTable) { expectTemplateMatches(meshRenderOptionTable()); }
TEST(ConfigTemplate, ViewSynTemplateReadsAsTheDefaults) { expectTemplateReadsAsDefaults(viewSynOptionTable()); }
TEST(ConfigTemplate, MeshRenderTemplateReadsAsTheDefaults) { expectTemplateReadsAsDefaults(meshRenderOptionTable()); }

}  // namespace
}  // namespace vs
