// The user manual's key tables equal the option tables (regenerate with scripts/update_manual.sh).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "Common/Options.h"
#include "TestPaths.h"

namespace vs {
namespace {

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The generated block of `doc` for `exe`, between its markers.
std::string keyBlock(const std::string& doc, const std::string& exe) {
  const std::string begin = "<!-- keys:" + exe + " -->", end = "<!-- /keys:" + exe + " -->";
  const size_t a = doc.find(begin), b = doc.find(end);
  if (a == std::string::npos || b == std::string::npos || b < a) return "(markers missing)";
  return doc.substr(a + begin.size(), b - a - begin.size());
}

std::set<std::string> keysIn(const std::string& block) {
  std::set<std::string> keys;
  std::istringstream lines(block);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("| `", 0) == 0) keys.insert(line.substr(3, line.find('`', 3) - 3));
  return keys;
}

void expectManualMatches(const OptionTable& table, const std::filesystem::path& doc) {
  const std::string block = keyBlock(readFile(doc), table.toolName());
  std::set<std::string> expected;
  for (const OptionSpec& spec : table.options()) expected.insert(spec.key);
  EXPECT_EQ(keysIn(block), expected) << doc << ": run scripts/update_manual.sh";
  std::string generated = table.markdownTable();
  generated.erase(0, generated.find_first_not_of('\n'));
  generated.erase(generated.find_last_not_of('\n') + 1);
  EXPECT_EQ(block, "\n" + generated + "\n") << doc << ": run scripts/update_manual.sh";
}

TEST(Manual, ViewSynKeysEqualTheOptionTable) {
  expectManualMatches(viewSynOptionTable(), std::filesystem::path(VS_SOURCE_DIR) / "doc" / "manual.md");
}

}  // namespace
}  // namespace vs
