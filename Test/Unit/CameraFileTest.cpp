// Camera parameter files: every real VSRS sample, generated files with awkward formatting, every
// error, and exact write -> read round trips.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/CameraFile.h"
#include "Common/Error.h"
#include "TestPaths.h"

namespace fs = std::filesystem;

namespace {

using vs::Camera;
using vs::Mat3;
using vs::Vec3;

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeAll(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// An independent view of a camera file: all whitespace-separated tokens after comments are removed,
// starting at the first line that holds a single token (header lines come before it). A well-formed
// file is then a sequence of (name, 23 numbers) groups, so names sit at every 24th token.
std::vector<std::string> namesByTokenCount(const std::string& text, std::size_t& tokenCount) {
  std::vector<std::string> tokens;
  std::istringstream lines(text);
  std::string line;
  bool started = false;
  while (std::getline(lines, line)) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::vector<std::string> lineTokens;
    std::string word;
    while (words >> word) lineTokens.push_back(word);
    if (!started && lineTokens.size() == 1) started = true;
    if (started) tokens.insert(tokens.end(), lineTokens.begin(), lineTokens.end());
  }
  tokenCount = tokens.size();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < tokens.size(); i += 24) names.push_back(tokens[i]);
  return names;
}

std::string errorOf(const std::string& text) {
  try {
    vs::parseCameraText(text, "gen.txt");
  } catch (const vs::InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const char* const kBlock =
    "1000 0 500\n"
    "0 1000 400\n"
    "0 0 1\n"
    "0\n"
    "0\n"
    "1 0 0 10\n"
    "0 1 0 20\n"
    "0 0 1 30\n";

Mat3 rotation(Vec3 axis, double angle) {
  axis = axis / vs::norm(axis);
  const double c = std::cos(angle), s = std::sin(angle);
  const double x = axis.x, y = axis.y, z = axis.z;
  Mat3 R;
  R[0][0] = c + x * x * (1 - c);
  R[0][1] = x * y * (1 - c) - z * s;
  R[0][2] = x * z * (1 - c) + y * s;
  R[1][0] = y * x * (1 - c) + z * s;
  R[1][1] = c + y * y * (1 - c);
  R[1][2] = y * z * (1 - c) - x * s;
  R[2][0] = z * x * (1 - c) - y * s;
  R[2][1] = z * y * (1 - c) + x * s;
  R[2][2] = c + z * z * (1 - c);
  return R;
}

void expectSameCamera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.K, b.K) << a.name;
  EXPECT_EQ(a.R, b.R) << a.name;
  EXPECT_EQ(a.t, b.t) << a.name;
  EXPECT_EQ(a.distortion[0], b.distortion[0]) << a.name;
  EXPECT_EQ(a.distortion[1], b.distortion[1]) << a.name;
}

}  // namespace

TEST(CameraFileTest, EverySampleFileParsesWithTheRightCameraCount) {
  const fs::path dir = vs::test::samplesDir() / "cameras";
  VS_REQUIRE_DIR(dir);
  int files = 0;
  for (const fs::path& folder : {dir, dir / "vsrs35"}) {
    std::vector<fs::path> paths;
    for (const auto& entry : fs::directory_iterator(folder))
      if (entry.is_regular_file()) paths.push_back(entry.path());
    std::sort(paths.begin(), paths.end());
    for (const fs::path& path : paths) {
      SCOPED_TRACE(path.string());
      vs::CameraFile file;
      ASSERT_NO_THROW(file = vs::readCameraFile(path.string())) << path;
      std::size_t tokenCount = 0;
      const std::vector<std::string> names = namesByTokenCount(readAll(path), tokenCount);
      EXPECT_EQ(tokenCount % 24, 0u) << "token count " << tokenCount;
      ASSERT_GT(file.cameras().size(), 0u);
      EXPECT_EQ(file.cameras().size(), names.size());
      for (std::size_t i = 0; i < names.size() && i < file.cameras().size(); ++i)
        EXPECT_EQ(file.cameras()[i].name, names[i]);
      EXPECT_EQ(file.path(), path.string());
      ++files;
    }
  }
  EXPECT_GE(files, 29);
}

TEST(CameraFileTest, BalletHasEightNumericallyNamedCameras) {
  const fs::path path = vs::test::samplesDir() / "cameras" / "calibParams-ballet.txt";
  VS_REQUIRE_DIR(path.parent_path());
  const vs::CameraFile file = vs::readCameraFile(path.string());
  ASSERT_EQ(file.cameras().size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(file.cameras()[i].name, std::to_string(i));
  // Camera "3" as written in the file: skew 0.571503, distortion "0.000000 0.000000" on one line.
  const Camera& c = file.find("3");
  EXPECT_EQ(c.K[0][0], 1909.91);
  EXPECT_EQ(c.K[0][1], 0.571503);
  EXPECT_EQ(c.K[1][2], 394.306);
  EXPECT_EQ(c.distortion[0], 0.0);
  EXPECT_EQ(c.distortion[1], 0.0);
  EXPECT_EQ(c.R[0][2], 0.080480);
  EXPECT_EQ(c.t, Vec3(-3.903715, -0.040429, 0.168691));
}

TEST(CameraFileTest, ButterflyArcSkipsItsDepthRangeHeader) {
  const fs::path path = vs::test::samplesDir() / "cameras" / "cam_param_bbb_butterfly2_arc+Znear-far.txt";
  VS_REQUIRE_DIR(path.parent_path());
  const vs::CameraFile file = vs::readCameraFile(path.string());
  EXPECT_EQ(file.cameras().size(), 80u);
  const auto header = std::count_if(file.warnings().begin(), file.warnings().end(),
                                    [](const std::string& w) { return contains(w, "skipped 13 header lines"); });
  EXPECT_EQ(header, 1);
  const Camera& c = file.find("param_ptm05");
  EXPECT_EQ(c.R[0][0], 0.939692620786);
  EXPECT_EQ(c.R[0][2], -0.342020143326);
  EXPECT_EQ(c.t, Vec3(-0.530131222155, 0.0, -1.45652356222));
  EXPECT_EQ(file.cameras().front().name, "param_ptm05");
  EXPECT_EQ(file.cameras().back().name, "param_ptm84");
}

TEST(CameraFileTest, ArtParamView3HasTheFileValues) {
  const fs::path path = vs::test::dataDir() / "middlebury2005" / "Art" / "cam_param.txt";
  VS_REQUIRE_DIR(path.parent_path());
  const vs::CameraFile file = vs::readCameraFile(path.string());
  EXPECT_EQ(file.cameras().size(), 5u);
  const Camera& c = file.find("param_view3");
  Mat3 K = Mat3::identity();
  K[0][0] = 1870.0;
  K[0][2] = 347.0;
  K[1][1] = 1870.0;
  K[1][2] = 277.0;
  EXPECT_EQ(c.K, K);
  EXPECT_EQ(c.R, Mat3::identity());
  EXPECT_EQ(c.t, Vec3(80.0, 0.0, 0.0));
  EXPECT_TRUE(file.warnings().empty());
}

TEST(CameraFileTest, FormattingVariantsAllReadTheSame) {
  const fs::path dir = vs::test::scratchDir("camera_file_formats");
  // The same two cameras, written six ways.
  const std::string plain = std::string("camA\n") + kBlock + "\ncamB\n" + kBlock;
  std::string crlf;
  for (char ch : plain) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  std::string cr;
  for (char ch : plain) cr += ch == '\n' ? '\r' : ch;
  const std::string messy =
      "\xEF\xBB\xBF# a comment line first\r\n"
      "  \t \r\n"
      "camA   # the name, then a comment\r\n"
      "+1000\t0 500 # trailing comment\r\n"
      "0\t\t1e3 400   \r\n"
      "\r\n"
      "0 0 1.0\r\n"
      "0.0 0\r\n"  // both distortion values on one line, as in calibParams-ballet.txt
      "1 0 0 10 0 1 0 20\r\n"
      "# a comment inside a block\r\n"
      "0 0 1\r\n"
      "30\r\n"
      "camB\r\n"  // no blank line between blocks, as in cam_param_lovebird1_original.txt
      "1000 0 500 0 1000 400 0 0 1 0 0 1 0 0 10 0 1 0 20 0 0 1 30";  // one line, no final newline
  std::string onePerLine = "camA\n";
  std::istringstream numbers(kBlock);
  std::string number;
  while (numbers >> number) onePerLine += number + "\n";
  onePerLine += "camB\n" + std::string(kBlock);
  const std::string header = "#ViewNum ZNear ZFar\n6 0.46 -2.42\n13 0.51 -2.49\n\n" + plain;

  int index = 0;
  for (const std::string& text : {plain, crlf, cr, messy, onePerLine, header}) {
    const fs::path path = dir / ("variant" + std::to_string(index++) + ".txt");
    writeAll(path, text);
    SCOPED_TRACE(path.string());
    vs::CameraFile file;
    ASSERT_NO_THROW(file = vs::readCameraFile(path.string()));
    ASSERT_EQ(file.cameras().size(), 2u);
    for (const Camera& c : file.cameras()) {
      EXPECT_EQ(c.K[0][0], 1000.0);
      EXPECT_EQ(c.K[1][1], 1000.0);
      EXPECT_EQ(c.K[0][2], 500.0);
      EXPECT_EQ(c.K[1][2], 400.0);
      EXPECT_EQ(c.R, Mat3::identity());
      EXPECT_EQ(c.t, Vec3(10, 20, 30));
    }
    EXPECT_EQ(file.cameras()[0].name, "camA");
    EXPECT_EQ(file.cameras()[1].name, "camB");
    EXPECT_EQ(file.warnings().size(), text == header ? 1u : 0u);
  }
}

TEST(CameraFileTest, NumericNamesAreNamesOnlyOutsideABlock) {
  // "7" between blocks is a name; the lone "0" lines inside a block are data.
  const std::string text = std::string("5\n") + kBlock + "7\n" + kBlock;
  const vs::CameraFile file = vs::parseCameraText(text, "numeric.txt");
  ASSERT_EQ(file.cameras().size(), 2u);
  EXPECT_EQ(file.cameras()[0].name, "5");
  EXPECT_EQ(file.cameras()[1].name, "7");
  EXPECT_EQ(file.find("7").t, Vec3(10, 20, 30));
}

TEST(CameraFileTest, TwentyTwoNumbersCutShortByTheNextName) {
  std::string block = kBlock;
  block = block.substr(0, block.rfind(' '));  // drop the last number (t[2] = 30)
  const std::string message = errorOf("first\n" + block + "\nsecond\n" + kBlock);
  // "first" is on line 1, its 22 numbers on lines 2-9, "second" on line 10.
  EXPECT_TRUE(contains(message, "gen.txt:10")) << message;
  EXPECT_TRUE(contains(message, "'first' (line 1) has only 22 of its 23 numbers")) << message;
  EXPECT_TRUE(contains(message, "'second'")) << message;
  EXPECT_TRUE(contains(message, "t[2]")) << message;
}

TEST(CameraFileTest, BlockCutShortByTheEndOfTheFile) {
  std::string block = kBlock;
  block = block.substr(0, block.rfind(' '));
  const std::string message = errorOf("only\n" + block);
  EXPECT_TRUE(contains(message, "gen.txt:9")) << message;
  EXPECT_TRUE(contains(message, "ends early")) << message;
  EXPECT_TRUE(contains(message, "22 of its 23")) << message;

  const std::string nameOnly = errorOf(std::string("camA\n") + kBlock + "\ndangling\n");
  EXPECT_TRUE(contains(nameOnly, "'dangling' (line 11) has only 0 of its 23")) << nameOnly;
}

TEST(CameraFileTest, NonFiniteNumbersAreErrors) {
  for (const std::string bad : {"nan", "NaN", "inf", "-inf", "Infinity"}) {
    std::string text = std::string("cam\n") + kBlock;
    text.replace(text.find("500"), 3, bad);
    const std::string message = errorOf(text);
    EXPECT_TRUE(contains(message, "gen.txt:2")) << message;
    EXPECT_TRUE(contains(message, "'" + bad + "'")) << message;
    EXPECT_TRUE(contains(message, "K[0][2]")) << message;
    EXPECT_TRUE(contains(message, "not a finite number")) << message;
  }
  std::string huge = std::string("cam\n") + kBlock;
  huge.replace(huge.find("500"), 3, "1e999");
  EXPECT_TRUE(contains(errorOf(huge), "out of the range")) << errorOf(huge);
}

TEST(CameraFileTest, LettersWhereANumberIsExpected) {
  std::string text = std::string("cam\n") + kBlock;
  text.replace(text.find("0 1000 400"), 10, "0 abc 400");
  std::string message = errorOf(text);
  EXPECT_TRUE(contains(message, "gen.txt:3")) << message;
  EXPECT_TRUE(contains(message, "expected a number for K[1][1]")) << message;
  EXPECT_TRUE(contains(message, "'abc'")) << message;

  text = std::string("cam\n") + kBlock;
  text.replace(text.find("1 0 0 10"), 8, "1 0 0 10,5");
  message = errorOf(text);
  EXPECT_TRUE(contains(message, "'10,5'")) << message;
  EXPECT_TRUE(contains(message, "t[0]")) << message;
}

TEST(CameraFileTest, ANameLineInsideABlockIsAnError) {
  const std::string message = errorOf("cam\n1000 0 500\n0 1000 400\nintruder\n0 0 1\n");
  EXPECT_TRUE(contains(message, "gen.txt:4")) << message;
  EXPECT_TRUE(contains(message, "'intruder'")) << message;
  EXPECT_TRUE(contains(message, "K[2][0]")) << message;
  EXPECT_TRUE(contains(message, "'cam' (line 1) has only 6 of its 23")) << message;
}

TEST(CameraFileTest, AStrayNumberLineAfterABlockIsPointedOut) {
  // A 24th number on its own line reads as a camera named "5", which the next name then cuts short.
  const std::string message = errorOf(std::string("a\n") + kBlock + "5\nb\n" + kBlock);
  EXPECT_TRUE(contains(message, "gen.txt:11")) << message;
  EXPECT_TRUE(contains(message, "camera '5' (line 10) has only 0 of its 23")) << message;
  EXPECT_TRUE(contains(message, "a number too many")) << message;
}

TEST(CameraFileTest, NumbersLeftOverAfterABlockAreAnError) {
  std::string text = std::string("cam\n") + kBlock;
  text.replace(text.find("0 0 1 30"), 8, "0 0 1 30 99");
  const std::string message = errorOf(text);
  EXPECT_TRUE(contains(message, "gen.txt:9")) << message;
  EXPECT_TRUE(contains(message, "unexpected '99'")) << message;
}

TEST(CameraFileTest, EmptyAndMissingFilesAreErrors) {
  EXPECT_TRUE(contains(errorOf("# nothing here\n\n"), "no camera found"));
  EXPECT_TRUE(contains(errorOf(""), "no camera found"));
  try {
    vs::readCameraFile("/nonexistent/folder/cams.txt");
    ADD_FAILURE() << "expected an InputError";
  } catch (const vs::InputError& e) {
    EXPECT_TRUE(contains(e.what(), "cannot open camera parameter file '/nonexistent/folder/cams.txt'")) << e.what();
  }
}

TEST(CameraFileTest, InvalidCameraIsReportedWithFileAndLine) {
  std::string text = std::string("good\n") + kBlock + "\nbad\n" + kBlock;
  text.replace(text.rfind("1000 0 500"), 4, "0000");  // fx = 0 in the second block
  const std::string message = errorOf(text);
  EXPECT_TRUE(contains(message, "gen.txt:11: camera 'bad'")) << message;
  EXPECT_TRUE(contains(message, "fx")) << message;
}

TEST(CameraFileTest, MissingNameListsEveryCameraOfTheFile) {
  const vs::CameraFile file =
      vs::parseCameraText(std::string("param_a\n") + kBlock + "param_b\n" + kBlock + "param_c\n" + kBlock, "three.txt");
  EXPECT_TRUE(file.contains("param_b"));
  EXPECT_FALSE(file.contains("param_d"));
  try {
    file.find("param_d");
    ADD_FAILURE() << "expected an InputError";
  } catch (const vs::InputError& e) {
    const std::string message = e.what();
    EXPECT_TRUE(contains(message, "three.txt")) << message;
    EXPECT_TRUE(contains(message, "'param_d'")) << message;
    EXPECT_TRUE(contains(message, "3 cameras: param_a, param_b, param_c")) << message;
  }
}

TEST(CameraFileTest, TheLastBlockWithAGivenNameWins) {
  std::string second = kBlock;
  second.replace(second.find("0 0 1 30"), 8, "0 0 1 99");
  const vs::CameraFile file =
      vs::parseCameraText(std::string("x\n") + kBlock + "y\n" + kBlock + "x\n" + second, "dup.txt");
  ASSERT_EQ(file.cameras().size(), 2u);
  EXPECT_EQ(file.cameras()[0].name, "x");
  EXPECT_EQ(file.find("x").t.z, 99.0);
  ASSERT_EQ(file.warnings().size(), 1u);
  EXPECT_TRUE(contains(file.warnings()[0], "dup.txt:19: camera 'x' is defined again (previous definition at line 1)"))
      << file.warnings()[0];
}

TEST(CameraFileTest, Vsrs35ConventionTransposesR) {
  const std::string text =
      "cam\n1000 0 500\n0 1000 400\n0 0 1\n0\n0\n"
      "0 -1 0 1\n"
      "1 0 0 2\n"
      "0 0 1 3\n";
  const Camera modern = vs::parseCameraText(text, "r.txt").find("cam");
  const Camera old = vs::parseCameraText(text, "r.txt", vs::RotationConvention::CameraToWorld).find("cam");
  EXPECT_EQ(modern.R[0][1], -1.0);
  EXPECT_EQ(modern.R[1][0], 1.0);
  EXPECT_EQ(old.R, vs::transpose(modern.R));
  EXPECT_EQ(old.t, modern.t);
}

TEST(CameraFileTest, WriteThenReadIsExact) {
  std::vector<Camera> cameras;
  for (int i = 0; i < 6; ++i) {
    Camera c;
    c.name = i == 0 ? "0" : "cam_" + std::to_string(i);  // a numeric name too
    c.K = Mat3::identity();
    c.K[0][0] = 1000.0 / 3.0 + i;
    c.K[1][1] = 2000.0 / 7.0 + i * 0.1;
    c.K[0][1] = i * 0.0123456789;
    c.K[0][2] = -832.101100 + std::sqrt(2.0) * i;
    c.K[1][2] = 457.7121 / (i + 1);
    c.distortion[0] = i * 1e-7;
    c.distortion[1] = -i * 3.3e-20;
    c.R = rotation({1.0, 0.1 * i, -0.3}, 0.1 + i);
    c.t = Vec3(1e6 + 1.0 / 3.0, -2e-9 * i, 7e15 / (i + 1));
    cameras.push_back(c);
  }
  const fs::path path = vs::test::scratchDir("camera_file_roundtrip") / "written.txt";
  vs::writeCameraFile(path.string(), cameras);
  const vs::CameraFile file = vs::readCameraFile(path.string());
  ASSERT_EQ(file.cameras().size(), cameras.size());
  for (std::size_t i = 0; i < cameras.size(); ++i) expectSameCamera(file.cameras()[i], cameras[i]);

  // formatCamera is the same block, parseable on its own.
  const vs::CameraFile single = vs::parseCameraText(vs::formatCamera(cameras[3]), "single");
  expectSameCamera(single.cameras().at(0), cameras[3]);
}

TEST(CameraFileTest, SampleFilesSurviveWriteAndRead) {
  const fs::path dir = vs::test::samplesDir() / "cameras";
  VS_REQUIRE_DIR(dir);
  const fs::path scratch = vs::test::scratchDir("camera_file_samples");
  for (const char* name : {"calibParams-ballet.txt", "cam_param_lovebird1_original.txt", "cam_param_rena.txt"}) {
    const vs::CameraFile original = vs::readCameraFile((dir / name).string());
    const fs::path copy = scratch / name;
    vs::writeCameraFile(copy.string(), original.cameras());
    const vs::CameraFile again = vs::readCameraFile(copy.string());
    ASSERT_EQ(again.cameras().size(), original.cameras().size()) << name;
    for (std::size_t i = 0; i < again.cameras().size(); ++i)
      expectSameCamera(again.cameras()[i], original.cameras()[i]);
  }
}

TEST(CameraFileTest, WriterRefusesWhatCannotBeReadBack) {
  const fs::path path = vs::test::scratchDir("camera_file_refuse") / "bad.txt";
  Camera c;
  c.name = "two words";
  EXPECT_THROW(vs::writeCameraFile(path.string(), {c}), vs::InputError);
  c.name = "has#hash";
  EXPECT_THROW(vs::writeCameraFile(path.string(), {c}), vs::InputError);
  c.name = "fine";
  c.t.x = NAN;
  EXPECT_THROW(vs::writeCameraFile(path.string(), {c}), vs::InputError);
  c.t.x = 0.0;
  EXPECT_THROW(vs::writeCameraFile("/nonexistent/folder/out.txt", {c}), vs::InputError);
}
