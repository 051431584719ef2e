// SafeOutputFile and the input checks of FileKind.h: what a run may write and what it may read.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "Common/Error.h"
#include "Common/FileKind.h"
#include "Common/SafeOutput.h"
#include "TestPaths.h"

namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

template <typename Action>
std::string inputErrorOf(Action action) {
  try {
    action();
  } catch (const vs::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

size_t regularFiles(const fs::path& dir) {
  size_t count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) count += entry.is_regular_file();
  return count;
}

// Until commit() the bytes go to a temporary file next to the destination; commit() renames it onto
// the name, with the permissions of the file it replaces.
TEST(SafeOutputTest, TemporaryFileUntilCommitThenRenamed) {
  const fs::path dir = vs::test::scratchDir("safe_output_commit");
  const fs::path path = dir / "report.csv";
  writeText(path, "old");
  ASSERT_EQ(chmod(path.c_str(), 0640), 0);
  vs::SafeOutputFile file(path.string());
  EXPECT_NE(file.writingPath(), path.string());
  EXPECT_EQ(fs::path(file.writingPath()).parent_path(), dir);
  file.write("new text\n");
  EXPECT_EQ(readText(path), "old");
  EXPECT_EQ(readText(file.writingPath()), "new text\n");
  file.commit();
  EXPECT_EQ(readText(path), "new text\n");
  EXPECT_EQ(fs::status(path).permissions() & fs::perms::all, fs::perms(0640));
  EXPECT_EQ(regularFiles(dir), 1u);
  EXPECT_NO_THROW(file.commit());  // idempotent
}

// discard() and the destructor remove the temporary file; the destination is never touched.
TEST(SafeOutputTest, DiscardRemovesTheTemporaryFile) {
  const fs::path dir = vs::test::scratchDir("safe_output_discard");
  {
    vs::SafeOutputFile file((dir / "a.yuv").string());
    file.write("abc");
  }
  vs::SafeOutputFile file((dir / "b.yuv").string());
  file.write("abc");
  file.discard();
  EXPECT_EQ(regularFiles(dir), 0u);
  EXPECT_NE(inputErrorOf([&] { file.commit(); }).find("discarded"), std::string::npos);
}

// Devices are written in place, and their write errors are InputErrors naming the role and path.
TEST(SafeOutputTest, DevicesAreWrittenInPlace) {
  vs::SafeOutputFile null("/dev/null", {}, "ReportFile");
  EXPECT_EQ(null.writingPath(), "/dev/null");
  null.write("ignored");
  null.commit();
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  vs::SafeOutputFile full("/dev/full", {}, "ReportFile");
  const std::string message = inputErrorOf([&] { full.write("x"); });
  EXPECT_NE(message.find("ReportFile '/dev/full': writing failed after 0 bytes: No space left on device"),
            std::string::npos)
      << message;
  EXPECT_NE(full.lastError(), 0);
}

// An input is never an output: other spellings, symbolic and hard links; names the file system would
// refuse at the end are refused at the start.
TEST(SafeOutputTest, CheckPathRefusesInputsAndImpossibleNames) {
  const fs::path dir = vs::test::scratchDir("safe_output_check");
  writeText(dir / "scene.cfg", "SourceWidth 32\n");
  fs::create_hard_link(dir / "scene.cfg", dir / "hard.yuv");
  fs::create_symlink(dir / "scene.cfg", dir / "soft.yuv");
  const std::vector<std::string> inputs = {(dir / "scene.cfg").string()};
  for (const fs::path& output : {dir / "hard.yuv", dir / "soft.yuv", dir / "." / "scene.cfg"}) {
    const std::string message = inputErrorOf([&] { vs::SafeOutputFile::checkPath(output.string(), inputs, "ReportFile"); });
    EXPECT_NE(message.find("same file as input"), std::string::npos) << output << ": " << message;
  }
  EXPECT_TRUE(vs::sameFile((dir / "hard.yuv").string(), (dir / "scene.cfg").string()));
  EXPECT_FALSE(vs::sameFile((dir / "new.yuv").string(), (dir / "scene.cfg").string()));
  const std::string longName = inputErrorOf([&] {
    vs::SafeOutputFile::checkPath((dir / (std::string(256, 'n'))).string(), {}, "ReportFile");
  });
  EXPECT_NE(longName.find("the file name is 256 bytes long; at most 255 expected"), std::string::npos) << longName;
  EXPECT_EQ(readText(dir / "scene.cfg"), "SourceWidth 32\n");
}

// requireRegularFile decides by stat() alone: a FIFO is refused without being opened (an open would
// block until a writer comes).
TEST(SafeOutputTest, RequireRegularFileRefusesWhatIsNotAFile) {
  const fs::path dir = vs::test::scratchDir("safe_output_regular");
  ASSERT_EQ(mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_NE(inputErrorOf([&] { vs::requireRegularFile((dir / "pipe").string(), "LeftViewImageName"); })
                .find("LeftViewImageName: " + (dir / "pipe").string() + ": cannot open: is a FIFO"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] { vs::requireRegularFile("/dev/null"); }).find("is a device"), std::string::npos);
  EXPECT_NE(inputErrorOf([&] { vs::requireRegularFile(dir.string()); }).find("is a folder"), std::string::npos);
  EXPECT_NE(inputErrorOf([&] { vs::requireRegularFile((dir / "none").string()); }).find("No such file"),
            std::string::npos);
  writeText(dir / "file.yuv", "x");
  EXPECT_NO_THROW(vs::requireRegularFile((dir / "file.yuv").string()));
}

}  // namespace
