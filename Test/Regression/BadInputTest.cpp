// The bad input catalogue (issue 8): every case starts from a valid tiny scene written in code
// (TinyScene.h), breaks one thing, runs Bin/ViewSyn on it and checks
//   - the exit code (1 bad input, 2 bad usage) and fragments of the message on stderr,
//   - that no file that was there before the run changed (byte for byte),
//   - that every file the run made holds whole frames only (or, where the case says so, exactly n),
//   - for the cases that ask for it, that the refusal is fast and allocates nothing big.
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/CameraFile.h"
#include "Process.h"
#include "ProcessStats.h"
#include "TestPaths.h"
#include "TinyScene.h"

namespace vs {
namespace {

namespace fs = std::filesystem;
using test::TinyScene;

constexpr int kWholeFramesOrNone = -1;  // outputFrames: no output file, or one of whole frames
constexpr int kNoOutput = -2;           // outputFrames: the output file must not exist

struct BadInputCase {
  std::string name;         // the test's name
  std::string description;  // what is broken, for the log
  // Breaks the scene (already written, valid). `arguments` starts as {the config path}; the harness
  // writes the scene's config again after build() and quotes every argument.
  std::function<void(TinyScene& scene, std::vector<std::string>& arguments)> build;
  int exitCode = 1;
  std::vector<std::string> messages;  // each must appear on stderr
  int outputFrames = kWholeFramesOrNone;  // >= 0: the output holds exactly this many whole frames
  bool needsNonRoot = false;              // permissions do not stop root
  double maxSeconds = 0;                  // > 0: the run must end within this many seconds
  long maxRssMiB = 0;                     // > 0: the run's peak resident memory must stay below this
  // Issue 24's cases set these after construction (see `issue24` below).
  std::string tool = "ViewSyn";           // the executable in Bin/
  std::string prefix = "timeout 60";      // shell words before it (a time limit: a hang is a failure)
  std::vector<std::string> outMessages = {};        // each must appear on stdout (warnings, the plan)
  std::vector<std::string> absentOutMessages = {};  // none may appear on stdout
};

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

void writeFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
}

// A Y4M file of `header` and the raw frames of `raw` (each `frameBytes` long), "FRAME\n" before each.
void writeY4m(const fs::path& path, const std::string& header, const std::string& raw, size_t frameBytes) {
  std::string content = header;
  for (size_t at = 0; at + frameBytes <= raw.size(); at += frameBytes) content += "FRAME\n" + raw.substr(at, frameBytes);
  writeFile(path, content);
}

// Size and FNV-1a hash of a file's bytes, read in chunks (inputs can be large and sparse).
struct Digest {
  uint64_t size = 0;
  uint64_t hash = 14695981039346656037ull;
  bool operator==(const Digest& o) const { return size == o.size && hash == o.hash; }
};

Digest digest(const fs::path& path) {
  Digest d;
  std::ifstream in(path, std::ios::binary);
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    const size_t got = size_t(in.gcount());
    for (size_t i = 0; i < got; ++i) d.hash = (d.hash ^ uint8_t(chunk[i])) * 1099511628211ull;
    d.size += got;
  }
  return d;
}

// Every regular file under `dir` (folders recursed, links not followed) -> its digest.
std::map<std::string, Digest> snapshot(const fs::path& dir) {
  std::map<std::string, Digest> files;
  for (auto it = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied);
       it != fs::recursive_directory_iterator(); ++it) {
    std::error_code ec;
    if (it->is_symlink(ec)) {
      it.disable_recursion_pending();
      continue;  // the target is (or is not) in the folder in its own right
    }
    if (it->is_regular_file(ec)) files[it->path().string()] = digest(it->path());
  }
  return files;
}

void truncateTo(const fs::path& path, uintmax_t bytes) { fs::resize_file(path, bytes); }

// The 23 numbers of a camera as text tokens, in file order (K, distortion, rows "r r r t").
std::vector<std::string> cameraTokens(const Camera& camera) {
  std::istringstream in(formatCamera(camera));
  std::string name;
  in >> name;
  std::vector<std::string> tokens;
  for (std::string token; in >> token;) tokens.push_back(token);
  return tokens;
}

std::string cameraBlock(const std::string& name, const std::vector<std::string>& tokens) {
  std::string text = name + "\n";
  for (size_t i = 0; i < tokens.size(); ++i) {
    text += tokens[i];
    // K rows of 3, two distortion lines, rows of 4.
    const bool endOfLine = i == 2 || i == 5 || i == 8 || i == 9 || i == 10 || (i > 10 && (i - 11) % 4 == 3);
    text += endOfLine || i + 1 == tokens.size() ? "\n" : " ";
  }
  return text + "\n";
}

// Rewrites the scene's camera file with `edit` applied to the tokens of camera `name`.
void editCamera(TinyScene& scene, const std::string& name, const std::function<void(std::vector<std::string>&)>& edit) {
  std::string text;
  for (const Camera& camera : scene.cameras()) {
    std::vector<std::string> tokens = cameraTokens(camera);
    if (camera.name == name) edit(tokens);
    text += cameraBlock(camera.name, tokens);
  }
  writeFile(scene.path("cameras.txt"), text);
}

// Builders for the common shapes of a case.
auto setKey(const std::string& key, const std::string& value) {
  return [key, value](TinyScene& scene, std::vector<std::string>&) { scene.set(key, value); };
}
auto eraseKey(const std::string& key) {
  return [key](TinyScene& scene, std::vector<std::string>&) { scene.erase(key); };
}
auto appendLine(const std::string& line) {
  return [line](TinyScene& scene, std::vector<std::string>&) { scene.extraConfigText += line; };
}
auto addArgument(const std::string& argument) {
  return [argument](TinyScene&, std::vector<std::string>& arguments) { arguments.push_back(argument); };
}

std::vector<BadInputCase> catalogue() {
  std::vector<BadInputCase> cases;
  auto add = [&](BadInputCase c) { cases.push_back(std::move(c)); };

  // ---- Usage (exit code 2) ------------------------------------------------------------------------
  add({"NoArguments", "ViewSyn without any argument prints the usage",
       [](TinyScene&, std::vector<std::string>& a) { a.clear(); }, 2, {"Usage:"}, kNoOutput});
  add({"UnknownOption", "an option that does not exist",
       [](TinyScene&, std::vector<std::string>& a) { a.insert(a.begin(), "--frobnicate"); }, 2,
       {"unknown option '--frobnicate'"}, kNoOutput});
  add({"CheckWithoutConfig", "--check without a config file",
       [](TinyScene&, std::vector<std::string>& a) { a = {"--check"}; }, 2, {"--check needs a config file"}, kNoOutput});

  // ---- Config syntax ------------------------------------------------------------------------------
  add({"KeyWithoutValue", "a key with no value", appendLine("Precision\n"), 1,
       {"scene.cfg:23: key 'Precision' has no value; expected one of 1, 2, 4"}, kNoOutput});
  add({"ThreeTokens", "a key with two values (a comment without '#')", appendLine("Filter 1 bicubic\n"), 1,
       {"scene.cfg:23: key 'Filter' takes one value but 2 were given ('1' 'bicubic'); put comments after '#'"},
       kNoOutput});
  add({"BinaryJunk", "binary bytes in the config",
       appendLine(std::string("Filter 1\x01\x02\xff\xfe\x00junk\n", 17)), 1,
       {"scene.cfg:23: unexpected control byte 0x01 at column 9"}, kNoOutput});
  add({"YuvFileAsConfig", "a YUV sequence given where the config belongs",
       [](TinyScene& s, std::vector<std::string>& a) { a = {s.path("left.yuv").string()}; }, 1,
       {"left.yuv: invalid configuration:", "binary data in a text config?"}, kNoOutput});
  add({"ThousandsOfBadLines", "a config of 100000 unknown keys: the first 50 problems and a count",
       [](TinyScene& s, std::vector<std::string>& a) {
         std::string text;
         for (int i = 0; i < 100000; ++i) text += "k" + std::to_string(i) + " 1\n";
         writeFile(s.path("many.cfg"), text);
         a = {s.path("many.cfg").string()};
       },
       1, {"many.cfg:50: unknown key 'k49'", "... and 99950 more problems"}, kNoOutput, false, 5.0, 200});
  add({"TenMegabyteLine", "a config holding a 10 MB line",
       [](TinyScene& s, std::vector<std::string>& a) {
         writeFile(s.path("long.cfg"), "SourceWidth " + std::string(10u << 20, '9') + "\n");
         a = {s.path("long.cfg").string()};
       },
       1, {"long.cfg: config file is 10485773 bytes; at most 1048576 expected (is it a config file?)"}, kNoOutput,
       false, 5.0, 200});
  add({"LongLine", "a 5000-character line", appendLine("ReportFile " + std::string(4989, 'r') + "\n"), 1,
       {"scene.cfg:23: line is 5000 characters long; at most 4096 expected"}, kNoOutput});
  add({"UnknownKey", "a key VSRS and we do not know", appendLine("FrobnicationLevel 3\n"), 1,
       {"scene.cfg:23: unknown key 'FrobnicationLevel'"}, kNoOutput});
  add({"MisspelledKey", "a misspelled key gets the nearest key as a hint", appendLine("SourceWidht 32\n"), 1,
       {"unknown key 'SourceWidht' (did you mean 'SourceWidth'?)"}, kNoOutput});
  add({"MisspelledOverride", "a misspelled key on the command line", addArgument("Precison=4"), 1,
       {"command line: unknown key 'Precison' (did you mean 'Precision'?)"}, kNoOutput});
  add({"OverrideWithoutEquals", "a command-line argument that is not Key=Value", addArgument("Precision"), 1,
       {"argument 'Precision' is not of the form Key=Value"}, kNoOutput});
  add({"EmptyOverride", "an empty camera name on the command line", addArgument("LeftCameraName="), 1,
       {"LeftCameraName = '': expected a non-empty text"}, kNoOutput});
  add({"EveryProblemAtOnce", "three problems are reported in one run",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("Precision", "3");
         s.set("Filter", "7");
         s.extraConfigText = "Colourspace 1\n";
       },
       1,
       {"Precision = '3': expected one of 1, 2, 4", "Filter = '7': expected one of 0, 1, 2",
        "unknown key 'Colourspace' (did you mean 'ColorSpace'?)"},
       kNoOutput});
  add({"ConfigNotFound", "the config file does not exist",
       [](TinyScene& s, std::vector<std::string>& a) { a = {s.path("no_such.cfg").string()}; }, 1,
       {"no_such.cfg: config file not found"}, kNoOutput});
  add({"ConfigIsAFolder", "a folder given as the config",
       [](TinyScene& s, std::vector<std::string>& a) {
         fs::create_directory(s.path("folder.cfg"));
         a = {s.path("folder.cfg").string()};
       },
       1, {"folder.cfg: is a folder, not a config file"}, kNoOutput});

  // ---- Values out of range ------------------------------------------------------------------------
  add({"Precision3", "Precision 3", setKey("Precision", "3"), 1,
       {"scene.cfg:23: Precision = '3': expected one of 1, 2, 4"}, kNoOutput});
  add({"NegativeWidth", "a negative frame width", setKey("SourceWidth", "-32"), 1,
       {"SourceWidth = '-32': expected an integer in [1, 16384]"}, kNoOutput});
  add({"ZeroHeight", "a zero frame height", setKey("SourceHeight", "0"), 1,
       {"SourceHeight = '0': expected an integer in [1, 16384]"}, kNoOutput});
  add({"OddWidth420", "an odd width with 4:2:0", setKey("SourceWidth", "31"), 1,
       {"4:2:0 texture needs an even SourceWidth and SourceHeight, got 31 x 16"}, kNoOutput});
  add({"WidthNotANumber", "letters where a size belongs", setKey("SourceHeight", "16px"), 1,
       {"SourceHeight = '16px': expected an integer"}, kNoOutput});
  add({"BitDepth17", "texture bit depth 17", setKey("TextureBitDepth", "17"), 1,
       {"TextureBitDepth = '17': expected an integer in [8, 16]"}, kNoOutput});
  add({"DepthType2", "DepthType 2", setKey("DepthType", "2"), 1, {"DepthType = '2': expected an integer in [0, 1]"},
       kNoOutput});
  add({"NegativeStartFrame", "StartFrame -1", setKey("StartFrame", "-1"), 1,
       {"StartFrame = '-1': expected an integer in [0, 1000000000]"}, kNoOutput});
  add({"ZeroFrames", "TotalNumberOfFrames 0", setKey("TotalNumberOfFrames", "0"), 1,
       {"TotalNumberOfFrames = '0': expected an integer in [1, 1000000000]"}, kNoOutput});
  add({"MissingDepthLevelAboveMax", "MissingDepthLevel 300 with 8-bit depth", setKey("MissingDepthLevel", "300"), 1,
       {"MissingDepthLevel 300 is above the largest 8-bit depth level 255"}, kNoOutput});
  add({"RgbWithoutChroma", "ColorSpace 1 with 4:0:0 texture",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("ColorSpace", "1");
         s.set("ChromaFormat", "400");
       },
       1, {"ColorSpace 1 (RGB) needs colour input; ChromaFormat is 400"}, kNoOutput});
  add({"HugeFrameSize", "16384 x 16384 frames: refused before allocating, fast, small",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("SourceWidth", "16384");
         s.set("SourceHeight", "16384");
       },
       1, {"SourceWidth x SourceHeight = 16384 x 16384 is more than 67108864 pixels; refused before allocating memory"},
       kNoOutput, false, 3.0, 200});
  add({"LargestFrameSizeTinyFiles", "the largest allowed size with files far too small: refused before allocating",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("SourceWidth", "16384");
         s.set("SourceHeight", "4096");
       },
       1, {"left.yuv: 2304 bytes is not a whole number of 16384x4096 4:2:0 8-bit frames (100663296 bytes a frame)"}, kNoOutput,
       false, 3.0, 200});
  add({"BillionFrames", "TotalNumberOfFrames 1e9 on 3-frame files: the 3 frames are written, quickly",
       setKey("TotalNumberOfFrames", "1000000000"), 1,
       {"holds only 3 frames from StartFrame 0, but TotalNumberOfFrames is 1000000000; 3 whole frames were written to"},
       3, false, 30.0, 300});

  // ---- Missing keys -------------------------------------------------------------------------------
  add({"MissingLeftCameraName", "a required key left out", eraseKey("LeftCameraName"), 1,
       {"missing required key 'LeftCameraName'"}, kNoOutput});
  add({"MissingCameraFile", "no CameraParameterFile", eraseKey("CameraParameterFile"), 1,
       {"missing required key 'CameraParameterFile'"}, kNoOutput});
  add({"MissingDepthValues", "no depth range for the left view",
       [](TinyScene& s, std::vector<std::string>&) {
         s.erase("LeftNearestDepthValue");
         s.erase("LeftFarthestDepthValue");
       },
       1, {"no depth range for camera 'cam_left': give the LeftNearestDepthValue and LeftFarthestDepthValue keys"},
       kNoOutput});
  add({"PartialRightView", "some Right keys but not all", eraseKey("RightDepthMapName"), 1,
       {"missing key 'RightDepthMapName': give every Right key for two reference views, or none"}, kNoOutput});

  // ---- Missing or unreadable files ----------------------------------------------------------------
  add({"TextureMissing", "the left texture does not exist", setKey("LeftViewImageName", "no_such.yuv"), 1,
       {"no_such.yuv: cannot open: No such file or directory"}, kNoOutput});
  add({"DepthIsAFolder", "a folder where the right depth file belongs (unreadable)",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_directory(s.path("depth_folder.yuv"));
         s.set("RightDepthMapName", "depth_folder.yuv");
       },
       1, {"depth_folder.yuv: cannot open: is a folder, not a file"}, kNoOutput});
  add({"TextureUnreadable", "a texture without read permission (skipped as root)",
       [](TinyScene& s, std::vector<std::string>&) { fs::permissions(s.path("left.yuv"), fs::perms::none); }, 1,
       {"left.yuv: cannot open: Permission denied"}, kNoOutput, true});
  add({"CameraFileMissing", "the camera file does not exist", setKey("CameraParameterFile", "no_such_cameras.txt"), 1,
       {"cannot open camera parameter file", "no_such_cameras.txt"}, kNoOutput});
  add({"CameraFileIsAFolder", "a folder where the camera file belongs",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_directory(s.path("camera_folder"));
         s.set("CameraParameterFile", "camera_folder");
       },
       1, {"camera_folder", "is a folder, not a camera parameter file"}, kNoOutput});
  add({"CameraFileIsAVideo", "a 100 MB file given as the camera file: refused before reading it",
       [](TinyScene& s, std::vector<std::string>&) {
         std::ofstream(s.path("video.yuv")).close();
         fs::resize_file(s.path("video.yuv"), 100u << 20);  // sparse: no disk space used
         s.set("CameraParameterFile", "video.yuv");
       },
       1, {"video.yuv' is 104857600 bytes; at most 16777216 expected (is it a camera parameter file?)"}, kNoOutput,
       false, 3.0, 200});
  add({"ReferenceViewMissing", "the ground-truth view does not exist",
       setKey("ReferenceVirtualViewImageName", "no_truth.yuv"), 1, {"no_truth.yuv: cannot open"}, kNoOutput});

  // ---- Cameras ------------------------------------------------------------------------------------
  add({"CameraNameNotInFile", "a virtual camera name the file does not have", setKey("VirtualCameraName", "cam_middle"),
       1,
       {"camera 'cam_middle' named by VirtualCameraName is not in the file; it has: cam_left, cam_virtual, cam_right"},
       kNoOutput});
  add({"CameraBlock22Numbers", "the middle camera block has 22 numbers",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_virtual", [](std::vector<std::string>& t) { t.pop_back(); });
       },
       1,
       {"cameras.txt:21: found 'cam_right', which reads as the name of a new camera, but camera 'cam_virtual' (line 11) "
        "has only 22 of its 23 numbers"},
       kNoOutput});
  add({"CameraFileEndsEarly", "the last camera block has 22 numbers",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_right", [](std::vector<std::string>& t) { t.pop_back(); });
       },
       1, {"the file ends early: camera 'cam_right' (line 21) has only 22 of its 23 numbers"}, kNoOutput});
  add({"CameraNaN", "NaN in K",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[0] = "nan"; });
       },
       1, {"cameras.txt:2: 'nan' for K[0][0] of camera 'cam_left' is not a finite number"}, kNoOutput});
  add({"CameraLetters", "letters in R",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_right", [](std::vector<std::string>& t) { t[17] = "abc"; });
       },
       1, {"expected a number for R[1][2] of camera 'cam_right' (line 21), found 'abc'"}, kNoOutput});
  add({"CameraHugeNumber", "a number beyond double range",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[14] = "1e999"; });
       },
       1, {"'1e999' for t[0] of camera 'cam_left' is out of the range of a double-precision number"}, kNoOutput});
  add({"SingularK", "an intrinsic matrix without inverse",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_virtual", [](std::vector<std::string>& t) {
           t[1] = t[0];  // K = [f f cx; f f cy; 0 0 1]
           t[3] = t[0];
         });
       },
       1, {"camera 'cam_virtual': K is singular"}, kNoOutput});
  add({"NegativeFocal", "fx < 0",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[0] = "-30"; });
       },
       1, {"camera 'cam_left': focal length fx = K[0][0] = -30, expected a positive number"}, kNoOutput});
  add({"NotARotation", "R scaled by 2",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_right", [](std::vector<std::string>& t) {
           t[11] = "2";
           t[16] = "2";
           t[21] = "2";
         });
       },
       1, {"camera 'cam_right': R is not a rotation matrix: max |R R^T - I| = 3"}, kNoOutput});
  add({"ReflectionR", "R with determinant -1",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[21] = "-1"; });
       },
       1, {"camera 'cam_left': R is not a rotation matrix", "det(R) = -1 (expected +1)"}, kNoOutput});
  add({"EmptyCameraFile", "a camera file without cameras",
       [](TinyScene& s, std::vector<std::string>&) { writeFile(s.path("cameras.txt"), "# nothing here\n\n"); }, 1,
       {"cameras.txt: no camera found"}, kNoOutput});
  add({"YuvAsCameraFile", "a YUV sequence given as the camera file", setKey("CameraParameterFile", "left.yuv"), 1,
       {"left.yuv"}, kNoOutput});
  add({"Mode1NotRectified", "SynthesisMode 1 on a rig whose virtual camera is rotated",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("SynthesisMode", "1");
         editCamera(s, "cam_virtual", [](std::vector<std::string>& t) {
           t[11] = "0.9998476951563913";  // 1 degree about y
           t[13] = "0.01745240643728351";
           t[19] = "-0.01745240643728351";
           t[21] = "0.9998476951563913";
         });
       },
       1, {"SynthesisMode 1 (1D parallel) needs a rectified rig, and this one is not"}, kNoOutput});

  // ---- Depth ranges -------------------------------------------------------------------------------
  add({"ZnearEqualsZfar", "an empty depth range", setKey("LeftFarthestDepthValue", "50"), 1,
       {"LeftNearestDepthValue and LeftFarthestDepthValue are both 50: the depth range is empty"}, kNoOutput});
  add({"ZnearNegative", "Znear < 0 with DepthType 0", setKey("RightNearestDepthValue", "-5"), 1,
       {"RightNearestDepthValue = -5: with DepthType 0 (camera-frame z) it must be greater than 0"}, kNoOutput});
  add({"ZnearZero", "Znear = 0 with DepthType 0", setKey("LeftNearestDepthValue", "0"), 1,
       {"LeftNearestDepthValue = 0: with DepthType 0 (camera-frame z) it must be greater than 0"}, kNoOutput});
  add({"ZnearNaN", "Znear nan", setKey("LeftNearestDepthValue", "nan"), 1,
       {"LeftNearestDepthValue = 'nan': expected a finite number"}, kNoOutput});
  add({"ZnearSwapped", "Znear farther than Zfar", setKey("LeftNearestDepthValue", "500"), 1,
       {"LeftNearestDepthValue = 500 is farther than LeftFarthestDepthValue = 120", "swapped keys?"}, kNoOutput});
  add({"WorldZeroDepth", "DepthType 1 with Zfar 0",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("DepthType", "1");
         s.set("RightFarthestDepthValue", "0");
       },
       1, {"RightFarthestDepthValue = 0: 1/Z would be infinite"}, kNoOutput});

  // ---- Sequences ----------------------------------------------------------------------------------
  // A file that is not a whole number of frames is refused before frame 0 (issue 24): a wrong size
  // is the likely cause, and the message shows the sizes that would fit.
  add({"TruncatedTexture", "the left texture cut in the middle of frame 2: refused before frame 0",
       [](TinyScene& s, std::vector<std::string>&) {
         truncateTo(s.path("left.yuv"), 2 * s.textureFormat().frameBytes() + 100);
       },
       1, {"LeftViewImageName (texture of the Left view)", "left.yuv: 1636 bytes is not a whole number of 32x16 4:2:0 "
           "8-bit frames (768 bytes a frame): 2 whole frames and 100 bytes over", "head -c 1536 FILE > FIRST.yuv"},
       kNoOutput});
  add({"TextureShorterThanAFrame", "a texture shorter than one frame",
       [](TinyScene& s, std::vector<std::string>&) { truncateTo(s.path("right.yuv"), 100); }, 1,
       {"RightViewImageName (texture of the Right view)",
        "right.yuv: 100 bytes is not a whole number of 32x16 4:2:0 8-bit frames (768 bytes a frame)"}, kNoOutput});
  add({"StartFrameBeyondEnd", "StartFrame 5 of 3 frames", setKey("StartFrame", "5"), 1,
       {"StartFrame 5 is beyond the end of the file (3 whole frames of 768 bytes)"}, kNoOutput});
  add({"StartFrameAtEnd", "StartFrame 3 of 3 frames", setKey("StartFrame", "3"), 1,
       {"StartFrame 3 is beyond the end of the file (3 whole frames"}, kNoOutput});
  add({"TooManyFrames", "TotalNumberOfFrames 10 of 3: the 3 frames are written and the message says so",
       setKey("TotalNumberOfFrames", "10"), 1,
       {"holds only 3 frames from StartFrame 0, but TotalNumberOfFrames is 10; 3 whole frames were written to"}, 3});
  add({"TooManyFramesFromStart", "StartFrame 1 and TotalNumberOfFrames 5 of 3: 2 frames are written",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("StartFrame", "1");
         s.set("TotalNumberOfFrames", "5");
       },
       1, {"holds only 2 frames from StartFrame 1, but TotalNumberOfFrames is 5; 2 whole frames were written to"}, 2});
  add({"DepthShorterThanTexture", "the right depth holds 2 frames, the textures 3",
       [](TinyScene& s, std::vector<std::string>&) {
         truncateTo(s.path("right_depth.yuv"), 2 * s.depthFormat().frameBytes());
       },
       1, {"right_depth.yuv holds only 2 frames from StartFrame 0, but TotalNumberOfFrames is 3; 2 whole frames"}, 2});
  add({"ReferenceViewShort", "the ground-truth view holds 1 frame",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::copy_file(s.path("left.yuv"), s.path("truth.yuv"));
         truncateTo(s.path("truth.yuv"), s.textureFormat().frameBytes());
         s.set("ReferenceVirtualViewImageName", "truth.yuv");
       },
       1, {"truth.yuv holds only 1 frames from StartFrame 0, but TotalNumberOfFrames is 3; 1 whole frames"}, 1});
  add({"DepthSampleAboveMax", "a 10-bit depth file whose frame 1 holds the sample 4000: nothing is written",
       [](TinyScene& s, std::vector<std::string>&) {
         s.depthBitDepth = 10;
         s.writeAll();
         const uint64_t offset = s.depthFormat().frameBytes() + 2 * (2 * uint64_t(s.width) + 3);
         std::fstream file(s.path("left_depth.yuv"), std::ios::in | std::ios::out | std::ios::binary);
         file.seekp(std::streamoff(offset));
         const char sample[2] = {char(4000 & 0xff), char(4000 >> 8)};
         file.write(sample, 2);
       },
       1,
       {"left_depth.yuv: frame 1, plane Y: sample 4000 at (x 3, y 2) exceeds 1023, the maximum of 10-bit samples",
        "(frame 1; no output file was created or replaced)"},
       kNoOutput});
  // 8-bit files read as 10-bit are twice too short a frame: the size check names both textures.
  add({"WrongBitDepth", "8-bit files read as 10-bit: not a whole number of frames",
       setKey("TextureBitDepth", "10"), 1,
       {"left.yuv: 2304 bytes is not a whole number of 32x16 4:2:0 10-bit frames", "8-bit samples (3 frames)",
        "right.yuv: 2304 bytes"},
       kNoOutput});

  // ---- Output -------------------------------------------------------------------------------------
  add({"OutputIsInput", "the output is the left texture", setKey("OutputVirtualViewImageName", "left.yuv"), 1,
       {"OutputVirtualViewImageName", "is also an input", "refusing to overwrite it"}});
  add({"OutputIsInputOtherSpelling", "the output is the right depth, spelled with '.\\' and '..'",
       setKey("OutputVirtualViewImageName", ".\\sub\\..\\right_depth.yuv"), 1, {"is also an input"}});
  add({"OutputIsInputAbsolute", "the output is the left depth, absolute, on the command line",
       [](TinyScene& s, std::vector<std::string>& a) {
         a.push_back("OutputVirtualViewImageName=" + s.path("left_depth.yuv").string());
       },
       1, {"is also an input"}});
  add({"OutputIsCameraFile", "the output is the camera file", setKey("OutputVirtualViewImageName", "cameras.txt"), 1,
       {"is also an input"}});
  add({"OutputIsLinkToInput", "the output is a symbolic link to the right texture",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_symlink("right.yuv", s.path("alias.yuv"));
         s.set("OutputVirtualViewImageName", "alias.yuv");
       },
       1, {"is also an input"}});
  add({"OutputIsHardLinkToInput", "the output is a hard link to the left texture",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_hard_link(s.path("left.yuv"), s.path("hard.yuv"));
         s.set("OutputVirtualViewImageName", "hard.yuv");
       },
       1, {"is also an input"}});
  add({"OutputThroughLinkedFolder", "the output is the left texture through a linked folder",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_directory_symlink(".", s.path("here"));
         s.set("OutputVirtualViewImageName", "here/left.yuv");
       },
       1, {"is also an input"}});
  add({"OutputFolderMissing", "the output folder does not exist",
       setKey("OutputVirtualViewImageName", "no_such_folder/virtual.yuv"), 1,
       {"output folder", "no_such_folder' does not exist"}, kNoOutput});
  add({"OutputFolderIsAFile", "the output folder is a file", setKey("OutputVirtualViewImageName", "left.yuv/virtual.yuv"),
       1, {"left.yuv' is not a folder"}, kNoOutput});
  add({"OutputFolderNotWritable", "the output folder cannot hold new files (/proc)",
       setKey("OutputVirtualViewImageName", "/proc/vs_virtual.yuv"), 1,
       {"/proc/vs_virtual.yuv': cannot create the output file in folder '/proc'"}, kNoOutput});
  add({"OutputFolderReadOnly", "a read-only output folder (skipped as root)",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_directory(s.path("readonly"));
         fs::permissions(s.path("readonly"), fs::perms::owner_read | fs::perms::owner_exec);
         s.set("OutputVirtualViewImageName", "readonly/virtual.yuv");
       },
       1, {"cannot create the output file", "Permission denied"}, kNoOutput, true});
  add({"OutputIsAFolder", "the output path is a folder",
       [](TinyScene& s, std::vector<std::string>&) {
         fs::create_directory(s.path("out_folder"));
         s.set("OutputVirtualViewImageName", "out_folder");
       },
       1, {"output path is a folder, not a file"}, kNoOutput});
  add({"ReportIsInput", "the CSV report is the camera file", setKey("ReportFile", "cameras.txt"), 1,
       {"ReportFile", "is also an input"}, kNoOutput});
  add({"ReportIsOutput", "the CSV report is the output sequence", setKey("ReportFile", "virtual.yuv"), 1,
       {"ReportFile", "is the output"}, kNoOutput});
  add({"ReportIsVirtualDepth", "the CSV report is the virtual depth output",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("OutputVirtualDepthMapName", "virtual_depth.yuv");
         s.set("ReportFile", "virtual_depth.yuv");
       },
       1, {"ReportFile", "is the output depth sequence (OutputVirtualDepthMapName)"}, kNoOutput});
  add({"VirtualDepthIsOutput", "the virtual depth output is the virtual view output, spelled differently",
       setKey("OutputVirtualDepthMapName", "./sub/../virtual.yuv"), 1,
       {"OutputVirtualDepthMapName and OutputVirtualViewImageName are the same file"}, kNoOutput});
  add({"VirtualDepthIsInput", "the virtual depth output is the left depth input",
       setKey("OutputVirtualDepthMapName", "left_depth.yuv"), 1,
       {"OutputVirtualDepthMapName", "is also an input"}, kNoOutput});
  add({"VirtualDepthDiskFull", "the virtual depth output's disk is full (/dev/full)",
       setKey("OutputVirtualDepthMapName", "/dev/full"), 1,
       {"/dev/full: writing frame 0 failed: No space left on device", "(frame 0; no output file was created or replaced)"},
       kNoOutput});
  // Every output is checked before any is created: the view output is not even created here.
  add({"VirtualDepthFolderMissing", "the virtual depth output's folder does not exist",
       setKey("OutputVirtualDepthMapName", "no_such_folder/depth.yuv"), 1,
       {"output folder", "no_such_folder' does not exist"}, kNoOutput});
  // ---- Issue 24: wrong input is never silent, no run damages a file --------------------------------
  // Each case fails with the base executables (exit 0 with a wrong result, a damaged file, a crash or
  // a hang); the report of issue 24 lists the behaviour before and after.
  auto withTool = [](BadInputCase c, const std::string& tool) {
    c.tool = tool;
    return c;
  };
  auto onStdout = [](BadInputCase c, std::vector<std::string> present, std::vector<std::string> absent = {}) {
    c.outMessages = std::move(present);
    c.absentOutMessages = std::move(absent);
    return c;
  };
  auto check = [](std::function<void(TinyScene&, std::vector<std::string>&)> build) {
    return [build](TinyScene& s, std::vector<std::string>& a) {
      build(s, a);
      a.insert(a.begin(), "--check");
    };
  };
  auto previousOutput = [](TinyScene& s) { writeFile(s.outputPath(), std::string(768, 'p')); };
  // Silent wrong results.
  add({"WrongWidth", "SourceWidth 30 on 32-wide files: refused, the width that fits named",
       setKey("SourceWidth", "30"), 1,
       {"LeftViewImageName (texture of the Left view)",
        "left.yuv: 2304 bytes is not a whole number of 30x16 4:2:0 8-bit frames (720 bytes a frame)",
        "sizes that divide the file: width 32 (3 frames)", "LeftDepthMapName (depth of the Left view)"},
       kNoOutput});
  add({"PartialFrameAtTheEnd", "a texture of 3 frames and 100 bytes, 2 frames asked for: refused",
       [](TinyScene& s, std::vector<std::string>&) {
         std::ofstream(s.path("left.yuv"), std::ios::binary | std::ios::app) << std::string(100, 'x');
         s.set("TotalNumberOfFrames", "2");
       },
       1, {"left.yuv: 2404 bytes is not a whole number of 32x16 4:2:0 8-bit frames (768 bytes a frame): 3 whole frames "
           "and 100 bytes over", "head -c 2304 FILE > FIRST.yuv"},
       kNoOutput});
  add({"Y4mWrongSize", "a Y4M texture whose header says 34x16: refused, both sizes named",
       [](TinyScene& s, std::vector<std::string>&) {
         writeY4m(s.path("left.y4m"), "YUV4MPEG2 W34 H16 F25:1 Ip A1:1 C420jpeg\n", readFile(s.path("left.yuv")), 768);
         s.set("LeftViewImageName", "left.y4m");
       },
       1, {"LeftViewImageName (texture of the Left view)",
           "left.y4m: the Y4M header says 34x16 4:2:0 8-bit, the configuration 32x16 4:2:0 8-bit"},
       kNoOutput});
  add({"PngTexture", "a PNG image named as texture: refused with what it is and an ffmpeg command",
       [](TinyScene& s, std::vector<std::string>&) {
         writeFile(s.path("left.png"), std::string("\x89PNG\r\n\x1a\n", 8) + std::string(2296, 'i'));
         s.set("LeftViewImageName", "left.png");
       },
       1, {"left.png: the file is a PNG image, not a raw YUV or Y4M sequence; convert it: ffmpeg -i",
           "-f rawvideo -pix_fmt yuv420p", "left.yuv'"},
       kNoOutput});
  add({"JpegDepth", "a JPEG named as depth map: refused",
       [](TinyScene& s, std::vector<std::string>&) {
         writeFile(s.path("depth.jpg"), std::string("\xff\xd8\xff\xe0", 4) + std::string(2300, 'j'));
         s.set("RightDepthMapName", "depth.jpg");
       },
       1, {"RightDepthMapName (depth of the Right view)", "depth.jpg: the file is a JPEG image"}, kNoOutput});
  add({"Mp4Texture", "an MP4 video named as texture: refused",
       [](TinyScene& s, std::vector<std::string>&) {
         writeFile(s.path("view.mp4"), std::string("\0\0\0\x20" "ftypisom", 12) + std::string(2292, 'm'));
         s.set("RightViewImageName", "view.mp4");
       },
       1, {"view.mp4: the file is an MP4/MOV video", "ffmpeg -i"}, kNoOutput});
  add({"CheckMissingTexture", "--check with a missing texture: opens the inputs, fails",
       check(setKey("LeftViewImageName", "no_such.yuv")), 1, {"no_such.yuv: cannot open: No such file or directory"},
       kNoOutput});
  add({"CheckWrongWidth", "--check with SourceWidth 30 on 32-wide files", check(setKey("SourceWidth", "30")), 1,
       {"is not a whole number of 30x16 4:2:0 8-bit frames", "width 32 (3 frames)"}, kNoOutput});
  add({"CheckY4mWrongSize", "--check with a Y4M texture whose header disagrees",
       check([](TinyScene& s, std::vector<std::string>&) {
         writeY4m(s.path("left.y4m"), "YUV4MPEG2 W32 H18 C420jpeg\n", readFile(s.path("left.yuv")), 768);
         s.set("LeftViewImageName", "left.y4m");
       }),
       1, {"the Y4M header says 32x18 4:2:0 8-bit, the configuration 32x16 4:2:0 8-bit"}, kNoOutput});
  add(onStdout({"VirtualCameraTurnedAway", "a virtual camera looking away from the scene: a warning",
                [](TinyScene& s, std::vector<std::string>&) {
                  editCamera(s, "cam_virtual", [](std::vector<std::string>& t) {
                    t[11] = "-1";
                    t[21] = "-1";
                  });
                },
                0, {}, 3},
               {"warning: virtual view: only 0.00 % of the samples of frame 0 were warped from any reference view"}));
  add(onStdout({"VirtualCameraFarAway", "a virtual camera 1e90 above the rig: a warning",
                [](TinyScene& s, std::vector<std::string>&) {
                  editCamera(s, "cam_virtual", [](std::vector<std::string>& t) { t[18] = "1e90"; });
                },
                0, {}, 3},
               {"warning: virtual view: only 0.00 % of the samples"}));
  add(onStdout({"DepthLevelZeroShare", "12.5 % of a depth map at level 0, MissingDepthLevel -1 (VSRS's reading): a warning",
                [](TinyScene& s, std::vector<std::string>&) {
                  std::fstream file(s.path("left_depth.yuv"), std::ios::in | std::ios::out | std::ios::binary);
                  file.write(std::string(64, '\0').data(), 64);  // the first two rows of frame 0
                  s.set("MissingDepthLevel", "-1");
                },
                0, {}, 3},
               {"left_depth.yuv: 12.5 % of the depth samples of frame 0 are at level 0",
                "set MissingDepthLevel 0 (and MissingDepthFill 1)"}));
  add(onStdout({"DepthLevelZeroDeclared", "the same with MissingDepthLevel 0: no warning",
                [](TinyScene& s, std::vector<std::string>&) {
                  std::fstream file(s.path("left_depth.yuv"), std::ios::in | std::ios::out | std::ios::binary);
                  file.write(std::string(64, '\0').data(), 64);
                  s.set("MissingDepthLevel", "0");
                },
                0, {}, 3},
               {}, {"are at level 0"}));
  add(onStdout({"DepthLevelZeroAuto", "the same with MissingDepthLevel unset (auto): no warning, the plan's decision",
                [](TinyScene& s, std::vector<std::string>&) {
                  std::fstream file(s.path("left_depth.yuv"), std::ios::in | std::ios::out | std::ios::binary);
                  file.write(std::string(64, '\0').data(), 64);
                },
                0, {}, 3},
               {"depth level 0 (auto)"}, {"are at level 0"}));
  add(onStdout({"RotationRounding", "a rotation off by 1e-6 (6 decimals): no warning",
                [](TinyScene& s, std::vector<std::string>&) {
                  editCamera(s, "cam_virtual", [](std::vector<std::string>& t) { t[12] = "0.000001"; });
                },
                0, {}, 3},
               {}, {"R is a rotation only to within"}));
  add(onStdout({"ThreeReferenceViews", "three reference views: the printout and the plan name all three",
                [](TinyScene& s, std::vector<std::string>&) {
                  std::string cameras = readFile(s.path("cameras.txt"));
                  std::vector<Camera> list = s.cameras();
                  Camera far = list[2];
                  far.name = "cam_far";
                  far.t.x = 8;
                  writeCameraFile(s.path("cameras.txt").string(), {list[0], list[1], list[2], far});
                  fs::copy_file(s.path("right.yuv"), s.path("far.yuv"));
                  fs::copy_file(s.path("right_depth.yuv"), s.path("far_depth.yuv"));
                  for (const char* key : {"LeftCameraName", "RightCameraName", "LeftViewImageName", "RightViewImageName",
                                          "LeftDepthMapName", "RightDepthMapName", "LeftNearestDepthValue",
                                          "LeftFarthestDepthValue", "RightNearestDepthValue", "RightFarthestDepthValue"})
                    s.erase(key);
                  s.set("ReferenceCameraNames", "cam_left,cam_right,cam_far");
                  s.set("ReferenceViewImageNames", "left.yuv,right.yuv,far.yuv");
                  s.set("ReferenceDepthMapNames", "left_depth.yuv,right_depth.yuv,far_depth.yuv");
                  s.set("ReferenceNearestDepthValues", "50,50,50");
                  s.set("ReferenceFarthestDepthValues", "120,120,120");
                },
                0, {}, 3},
               {"reference 1 cam_left", "reference 3 cam_far", "blend: 3 reference views (Reference 1, Reference 2, "
                "Reference 3)"},
               {"two reference views"}));
  // Files damaged.
  add({"ReportIsConfig", "the report is the config file", setKey("ReportFile", "scene.cfg"), 1,
       {"ReportFile", "is also an input"}, kNoOutput});
  add({"OutputIsConfig", "the output is the config file", setKey("OutputVirtualViewImageName", "scene.cfg"), 1,
       {"OutputVirtualViewImageName", "is also an input"}});
  add({"VirtualDepthIsConfigByHardLink", "the depth output is a hard link to the config file",
       [](TinyScene& s, std::vector<std::string>&) {
         s.set("OutputVirtualDepthMapName", "config_link.yuv");
         s.writeConfig();
         fs::create_hard_link(s.configPath(), s.path("config_link.yuv"));
       },
       1, {"OutputVirtualDepthMapName", "is also an input"}, kNoOutput});
  add({"RefusedRunKeepsPreviousOutput", "a report in a missing folder: the previous output keeps its bytes",
       [previousOutput](TinyScene& s, std::vector<std::string>&) {
         previousOutput(s);
         s.set("ReportFile", "nodir/r.csv");
       },
       1, {"ReportFile '", "nodir' does not exist"}});
  add({"ReportNameTooLong", "a report name of 300 characters: refused up front, the previous output kept",
       [previousOutput](TinyScene& s, std::vector<std::string>&) {
         previousOutput(s);
         s.set("ReportFile", std::string(300, 'r') + ".csv");
       },
       1, {"the file name is 304 bytes long; at most 255 expected"}});
  add({"DepthOutputNameTooLong", "a depth output name of 300 characters: refused up front, the previous output kept",
       [previousOutput](TinyScene& s, std::vector<std::string>&) {
         previousOutput(s);
         s.set("OutputVirtualDepthMapName", std::string(300, 'd') + ".yuv");
       },
       1, {"OutputVirtualDepthMapName", "at most 255 expected"}});
  add({"FailedRunKeepsPreviousOutput", "a bad depth sample in frame 1: the previous output keeps its bytes",
       [previousOutput](TinyScene& s, std::vector<std::string>&) {
         s.depthBitDepth = 10;
         s.writeAll();
         const uint64_t offset = s.depthFormat().frameBytes() + 10;
         std::fstream file(s.path("right_depth.yuv"), std::ios::in | std::ios::out | std::ios::binary);
         file.seekp(std::streamoff(offset));
         file.write("\xff\xff", 2);
         previousOutput(s);
       },
       1, {"right_depth.yuv: frame 1, plane Y", "no output file was created or replaced"}});
  add({"ReportToFullDisk", "the report on a full disk (/dev/full): exit 1", setKey("ReportFile", "/dev/full"), 1,
       {"ReportFile '/dev/full': writing failed after 0 bytes: No space left on device"}, kNoOutput});
  {
    BadInputCase limit{"FileSizeLimit", "ulimit -f 1: the write fails (EFBIG), nothing replaced, no partial frame",
                       [previousOutput](TinyScene& s, std::vector<std::string>&) { previousOutput(s); }, 1,
                       {"writing frame", "File too large", "no output file was created or replaced"}};
    limit.prefix = "timeout 60 bash -c 'ulimit -f 1; exec \"$0\" \"$@\"'";
    add(limit);
  }
  {
    BadInputCase stdoutFull{"StdoutToFullDisk", "the log on a full disk (stdout to /dev/full): exit 1 after the run",
                            [](TinyScene&, std::vector<std::string>&) {}, 1,
                            {"cannot write the standard output: No space left on device"}, 3};
    stdoutFull.prefix = "timeout 60 bash -c 'exec \"$0\" \"$@\" >/dev/full'";
    add(stdoutFull);
  }
  add(withTool({"MeshPlyHardLinkToInput", "MeshRender: a PLY name that is a hard link to the left texture",
                [](TinyScene& s, std::vector<std::string>&) {
                  fs::create_hard_link(s.path("left.yuv"), s.path("mesh_left.ply"));
                  s.set("MeshPlyOutput", "mesh.ply");
                },
                1, {"MeshPlyOutput (Left view) '", "mesh_left.ply': output file is the same file as input"}, kNoOutput},
               "MeshRender"));
  add(withTool({"MeshPlyFolderMissing", "MeshRender: PLY in a missing folder: refused, the previous output kept",
                [previousOutput](TinyScene& s, std::vector<std::string>&) {
                  previousOutput(s);
                  s.set("MeshPlyOutput", "nodir/mesh.ply");
                },
                1, {"MeshPlyOutput (Left view)", "nodir' does not exist"}},
               "MeshRender"));
  add(withTool({"MeshCheckVirtualDepth", "MeshRender --check with OutputVirtualDepthMapName: refused",
                check(setKey("OutputVirtualDepthMapName", "virtual_depth.yuv")), 1,
                {"OutputVirtualDepthMapName", "MeshRender cannot write the virtual view's depth"}, kNoOutput},
               "MeshRender"));
  add(withTool({"MeshReportIsConfig", "MeshRender: the report is the config file", setKey("ReportFile", "scene.cfg"), 1,
                {"ReportFile", "is also an input"}, kNoOutput},
               "MeshRender"));
  // Crashes and hangs.
  add({"CameraCentreFar", "the left camera centre at x = 1e200: a clear error, no crash",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[14] = "1e200"; });
       },
       1, {"camera 'cam_left'", "t[0] (the camera centre) is 1e+200, expected a coordinate within +-1e100"}, kNoOutput});
  add({"CameraCentreFarNegative", "the right camera centre at x = -1e308: a clear error",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_right", [](std::vector<std::string>& t) { t[14] = "-1e308"; });
       },
       1, {"t[0] (the camera centre) is -1e+308"}, kNoOutput});
  add({"CameraCentreFarButAllowed", "the left camera centre at x = 1e90: a defined result",
       [](TinyScene& s, std::vector<std::string>&) {
         editCamera(s, "cam_left", [](std::vector<std::string>& t) { t[14] = "1e90"; });
       },
       0, {}, 3});
  {
    BadInputCase fifo{"FifoTexture", "a FIFO named as texture: refused without opening it (no hang)",
                      [](TinyScene& s, std::vector<std::string>&) {
                        ASSERT_EQ(mkfifo(s.path("pipe.yuv").c_str(), 0600), 0);
                        s.set("LeftViewImageName", "pipe.yuv");
                      },
                      1, {"pipe.yuv: cannot open: is a FIFO (named pipe), not a regular file"}, kNoOutput, false, 8.0};
    fifo.prefix = "timeout 10";
    add(fifo);
    BadInputCase checkFifo = fifo;
    checkFifo.name = "CheckFifoDepth";
    checkFifo.description = "--check with a FIFO named as depth";
    checkFifo.build = check([](TinyScene& s, std::vector<std::string>&) {
      ASSERT_EQ(mkfifo(s.path("pipe.yuv").c_str(), 0600), 0);
      s.set("RightDepthMapName", "pipe.yuv");
    });
    add(checkFifo);
  }
  add({"DeviceTexture", "a device named as texture (/dev/zero): refused", setKey("LeftViewImageName", "/dev/zero"), 1,
       {"/dev/zero: cannot open: is a device, not a regular file"}, kNoOutput});
  return cases;
}

void PrintTo(const BadInputCase& c, std::ostream* out) { *out << c.name << " (" << c.description << ")"; }

class BadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInput, RefusedWithMessageAndNoDamage) {
  const BadInputCase& c = GetParam();
  if (c.needsNonRoot && geteuid() == 0)
    GTEST_SKIP() << "running as root: file permissions do not stop root; the folder-as-file cases cover unreadable "
                    "input";
  const fs::path root = test::scratchDir("bad_input_" + c.name);
  const fs::path runDir = root / "run";
  fs::create_directories(runDir);
  TinyScene scene(root / "scene");
  scene.writeAll();
  std::vector<std::string> arguments{scene.configPath().string()};
  c.build(scene, arguments);
  scene.writeConfig();

  const std::map<std::string, Digest> before = snapshot(scene.dir);
  std::string command;
  for (const std::string& argument : arguments) command += (command.empty() ? "" : " ") + test::quoted(argument);
  const auto start = std::chrono::steady_clock::now();
  const test::ToolResult result = test::runTool(c.tool, command, runDir, scene.dir, c.prefix);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::map<std::string, Digest> after = snapshot(scene.dir);

  SCOPED_TRACE(c.description);
  EXPECT_EQ(result.exitCode, c.exitCode) << "stderr:\n" << result.err;
  if (c.exitCode == 1) {
    EXPECT_EQ(result.err.rfind(c.tool + ": error: ", 0), 0u) << result.err;
  }
  // Without an argument the usage is the error message: on stderr (--help prints it on stdout).
  const std::string& shown = result.err;
  for (const std::string& message : c.messages)
    EXPECT_NE(shown.find(message), std::string::npos) << "expected: " << message << "\nstderr:\n" << result.err;
  for (const std::string& message : c.outMessages)
    EXPECT_NE(result.out.find(message), std::string::npos) << "expected on stdout: " << message << "\nstdout:\n" << result.out;
  for (const std::string& message : c.absentOutMessages)
    EXPECT_EQ(result.out.find(message), std::string::npos) << "not expected on stdout: " << message;
  // Said in a few lines, however much is wrong.
  EXPECT_LT(result.err.size(), 16384u);

  // Every file that was there is unchanged.
  for (const auto& [path, content] : before) {
    const auto now = after.find(path);
    if (now == after.end()) {
      ADD_FAILURE() << path << " was removed";
      continue;
    }
    EXPECT_TRUE(now->second == content) << path << " changed: " << content.size << " -> " << now->second.size
                                        << " bytes";
  }
  // Every file the run made is a sequence of whole frames (a report, if any, is text).
  const uint64_t frameBytes = scene.textureFormat().frameBytes();
  for (const auto& [path, content] : after) {
    // No temporary output file is left behind (SafeOutput.h names them ".NAME.vs-PID-N").
    EXPECT_EQ(fs::path(path).filename().string().find(".vs-"), std::string::npos) << path << " was left behind";
    if (before.count(path) || fs::path(path).extension() != ".yuv") continue;
    EXPECT_EQ(content.size % frameBytes, 0u) << path << " holds a partial frame: " << content.size << " bytes";
  }
  const fs::path output = scene.outputPath();
  const bool outputIsNew = !before.count(output.string());
  if (c.outputFrames == kNoOutput) {
    EXPECT_FALSE(outputIsNew && fs::exists(output)) << output << " was created";
  }
  if (c.outputFrames >= 0) {
    ASSERT_TRUE(fs::exists(output)) << output;
    EXPECT_EQ(fs::file_size(output), uint64_t(c.outputFrames) * frameBytes) << output;
  }

  if (c.maxSeconds > 0) {
    EXPECT_LT(seconds, c.maxSeconds) << "the refusal took " << seconds << " s";
  }
  if (c.maxRssMiB > 0) {
    // Once more, measured on its own: the peak resident memory of the refusal.
    const test::ProcessStats stats = test::runMeasured("ViewSyn", arguments, runDir / "peak_rss.txt");
    ASSERT_TRUE(stats.measured);
    EXPECT_EQ(stats.exitCode, c.exitCode);
    EXPECT_LT(stats.maxRssKiB, c.maxRssMiB * 1024) << "peak RSS " << stats.maxRssKiB / 1024 << " MiB";
    if (c.maxSeconds > 0) {
      EXPECT_LT(stats.seconds, c.maxSeconds);
    }
  }
  // Leave nothing unreadable behind for the next run's clean-up.
  std::error_code ec;
  for (const char* name : {"left.yuv", "readonly"}) fs::permissions(scene.path(name), fs::perms::owner_all, ec);
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInput, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<BadInputCase>& info) { return info.param.name; });

TEST(BadInputCatalogue, HasAtLeastFortyCasesWithUniqueNames) {
  const std::vector<BadInputCase> cases = catalogue();
  EXPECT_GE(cases.size(), 40u);
  std::map<std::string, int> names;
  for (const BadInputCase& c : cases) EXPECT_EQ(++names[c.name], 1) << c.name;
}

// The scene the catalogue breaks is valid: ViewSyn synthesizes it with exit code 0.
TEST(BadInputCatalogue, TheUnbrokenSceneRuns) {
  const fs::path root = test::scratchDir("bad_input_valid");
  TinyScene scene(root / "scene");
  scene.writeAll();
  const std::map<std::string, Digest> before = snapshot(scene.dir);
  const test::ToolResult result = test::runTool("ViewSyn", test::quoted(scene.configPath().string()), root, scene.dir);
  EXPECT_EQ(result.exitCode, 0) << result.err;
  ASSERT_TRUE(fs::exists(scene.outputPath()));
  EXPECT_EQ(fs::file_size(scene.outputPath()), 3 * scene.textureFormat().frameBytes());
  for (const auto& [path, content] : before) EXPECT_TRUE(digest(path) == content) << path;
}

// The frame loop reads the next frame while it synthesizes the current one: frame k of a whole-
// sequence run is exactly what a run of that frame alone (StartFrame=k) gives.
TEST(BadInputCatalogue, ReadingAheadKeepsEveryFrameInPlace) {
  const fs::path root = test::scratchDir("read_ahead");
  TinyScene scene(root / "scene");
  scene.writeAll();
  const test::ToolResult whole = test::runTool("ViewSyn", test::quoted(scene.configPath().string()), root, scene.dir);
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  const std::string sequence = readFile(scene.outputPath());
  const size_t frameBytes = size_t(scene.textureFormat().frameBytes());
  ASSERT_EQ(sequence.size(), 3 * frameBytes);
  for (int k = 0; k < 3; ++k) {
    const fs::path single = root / ("frame" + std::to_string(k) + ".yuv");
    const test::ToolResult one = test::runTool(
        "ViewSyn",
        test::quoted(scene.configPath().string()) + " StartFrame=" + std::to_string(k) +
            " TotalNumberOfFrames=1 OutputVirtualViewImageName=" + test::quoted(single.string()),
        root, scene.dir);
    ASSERT_EQ(one.exitCode, 0) << one.err;
    EXPECT_TRUE(readFile(single) == sequence.substr(size_t(k) * frameBytes, frameBytes)) << "frame " << k;
  }
  // The frames differ (the texture drifts), so a frame read into the wrong buffer would show.
  EXPECT_FALSE(sequence.substr(0, frameBytes) == sequence.substr(frameBytes, frameBytes));
}

// The ground truth is read into one buffer while its frame is rendered (Pipeline/SequenceInputs.h):
// each frame of a whole-sequence run is scored against its own truth, as a run of that frame alone.
TEST(BadInputCatalogue, EachFrameIsScoredAgainstItsOwnTruth) {
  const fs::path root = test::scratchDir("read_truth");
  TinyScene scene(root / "scene");
  scene.writeAll();
  // A truth whose frames are flat grey of levels far apart: every frame scores differently.
  std::string truth;
  for (int k = 0; k < 3; ++k) truth += std::string(size_t(scene.textureFormat().frameBytes()), char(30 + 80 * k));
  writeFile(scene.path("truth.yuv"), truth);
  scene.set("ReferenceVirtualViewImageName", "truth.yuv");
  scene.writeConfig();
  // "PSNR Y .. U .. V .. dB" of the log's line for frame k.
  auto scoreOf = [](const std::string& log, int k) {
    const size_t line = log.find("frame " + std::to_string(k) + ":");
    if (line == std::string::npos) return std::string();
    const size_t psnr = log.find("PSNR", line), end = log.find('\n', line);
    return psnr < end ? log.substr(psnr, end - psnr) : std::string();
  };
  const test::ToolResult whole = test::runTool("ViewSyn", test::quoted(scene.configPath().string()), root, scene.dir);
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  std::vector<std::string> scores;
  for (int k = 0; k < 3; ++k) {
    const test::ToolResult one = test::runTool(
        "ViewSyn",
        test::quoted(scene.configPath().string()) + " StartFrame=" + std::to_string(k) +
            " TotalNumberOfFrames=1 OutputVirtualViewImageName=" + test::quoted((root / "one.yuv").string()),
        root, scene.dir);
    ASSERT_EQ(one.exitCode, 0) << one.err;
    ASSERT_FALSE(scoreOf(one.out, k).empty()) << one.out;
    EXPECT_EQ(scoreOf(whole.out, k), scoreOf(one.out, k)) << "frame " << k;
    scores.push_back(scoreOf(one.out, k));
  }
  // The scores differ from frame to frame, so a truth of the wrong frame would show.
  EXPECT_NE(scores[0], scores[1]);
  EXPECT_NE(scores[1], scores[2]);
}

// Key=Value arguments resolve paths against the working folder; a removed working folder is bad
// input like any other, not an uncaught std::filesystem::filesystem_error (which aborted ViewSyn).
TEST(BadInputCatalogue, RemovedWorkingFolderIsNoCrash) {
  const fs::path root = test::scratchDir("bad_input_removed_cwd");
  TinyScene scene(root / "scene");
  scene.writeAll();
  const fs::path gone = root / "gone";
  fs::create_directories(gone);
  const test::ToolResult result =
      test::runTool("ViewSyn",
                    "\"$(rmdir " + test::quoted(gone.string()) + ")\"" + test::quoted(scene.configPath().string()) +
                        " LeftViewImageName=left.yuv",
                    root, gone);
  EXPECT_EQ(result.exitCode, 1) << result.err;
  EXPECT_NE(result.err.find("left.yuv: cannot open"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(scene.outputPath()));
}

// A config saved by Notepad starts with a UTF-8 byte order mark; it is read like any other.
TEST(BadInputCatalogue, ConfigWithByteOrderMarkIsRead) {
  const fs::path root = test::scratchDir("bad_input_bom");
  TinyScene scene(root / "scene");
  scene.writeAll();
  writeFile(scene.configPath(), "\xEF\xBB\xBF" + readFile(scene.configPath()));
  const test::ToolResult result =
      test::runTool("ViewSyn", "--check " + test::quoted(scene.configPath().string()), root, scene.dir);
  EXPECT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("configuration OK"), std::string::npos) << result.out;
}

// ---- Issue 24: outputs, formats and tools beyond one refused run -----------------------------------

// No file in `dir` is a temporary output (".NAME.vs-PID-N").
void expectNoTemporaryFile(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".vs-"), std::string::npos) << entry.path() << " was left behind";
}

// Two runs writing one output at the same time: each writes its own temporary file and the later
// rename wins, so the output is always one run's whole output (doc/formats-yuv.md, "Safe outputs").
TEST(CatalogueSafeOutput, TwoRunsOnOneOutputNeverMix) {
  const fs::path root = test::scratchDir("safe_two_runs");
  TinyScene scene(root / "scene");
  scene.width = 320;
  scene.height = 240;
  scene.frames = 12;
  scene.writeAll();
  const std::string config = test::quoted(scene.configPath().string());
  // Two different results: all frames, and the same run at Precision 1.
  const fs::path a = root / "a.yuv", b = root / "b.yuv";
  ASSERT_EQ(test::runTool("ViewSyn", config + " OutputVirtualViewImageName=" + test::quoted(a.string()), root).exitCode, 0);
  ASSERT_EQ(test::runTool("ViewSyn", config + " Precision=1 Filter=0 OutputVirtualViewImageName=" + test::quoted(b.string()), root).exitCode, 0);
  const std::string resultA = readFile(a), resultB = readFile(b);
  ASSERT_NE(resultA, resultB);
  const fs::path shared = root / "shared.yuv";
  const std::string bin = test::quoted((test::binDir() / "ViewSyn").string());
  for (int round = 0; round < 4; ++round) {
    const std::string both = bin + " " + config + " OutputVirtualViewImageName=" + test::quoted(shared.string()) +
                             " >/dev/null & " + bin + " " + config + " Precision=1 Filter=0 OutputVirtualViewImageName=" +
                             test::quoted(shared.string()) + " >/dev/null & wait";
    ASSERT_EQ(std::system(("bash -c " + test::quoted(both)).c_str()), 0);
    const std::string result = readFile(shared);
    EXPECT_TRUE(result == resultA || result == resultB) << "round " << round << ": a mixed file of " << result.size()
                                                        << " bytes";
  }
  expectNoTemporaryFile(root);
}

// SIGTERM at any moment of a run: the output is the previous file or the whole new one, never a cut
// frame, and the temporary file is removed (only SIGKILL can leave one).
TEST(CatalogueSafeOutput, TerminatedRunLeavesTheOutputWholeOrAsItWas) {
  const fs::path root = test::scratchDir("safe_sigterm");
  TinyScene scene(root / "scene");
  scene.width = 640;
  scene.height = 480;
  scene.frames = 30;
  scene.writeAll();
  const std::string config = test::quoted(scene.configPath().string());
  const fs::path whole = root / "whole.yuv";
  ASSERT_EQ(test::runTool("ViewSyn", config + " OutputVirtualViewImageName=" + test::quoted(whole.string()), root).exitCode, 0);
  const std::string complete = readFile(whole);
  const std::string previous(1000, 'p');
  int killed = 0;
  for (const char* delay : {"0.05", "0.15", "0.3", "0.5", "0.8"}) {
    writeFile(scene.outputPath(), previous);
    const test::ToolResult result = test::runTool("ViewSyn", config, root, {}, std::string("timeout -s TERM ") + delay);
    killed += result.exitCode == 124;
    const std::string now = readFile(scene.outputPath());
    EXPECT_TRUE(now == previous || now == complete) << "after " << delay << " s: " << now.size() << " bytes";
    expectNoTemporaryFile(scene.dir);
  }
  EXPECT_GT(killed, 0) << "no run was long enough to be terminated";
}

// A Y4M texture is read natively: the result is the raw run's, byte for byte. An output named .y4m
// is written as Y4M: its header, then the same frames each after "FRAME\n".
TEST(CatalogueY4m, ReadNativelyAndWrittenByName) {
  const fs::path root = test::scratchDir("y4m_native");
  TinyScene scene(root / "scene");
  scene.writeAll();
  const std::string config = test::quoted(scene.configPath().string());
  ASSERT_EQ(test::runTool("ViewSyn", config, root).exitCode, 0);
  const std::string raw = readFile(scene.outputPath());
  const size_t frameBytes = size_t(scene.textureFormat().frameBytes());
  writeY4m(scene.path("left.y4m"), "YUV4MPEG2 W32 H16 F30000:1001 It A1:1 C420mpeg2 XYSCSS=420MPEG2\n",
           readFile(scene.path("left.yuv")), frameBytes);
  writeY4m(scene.path("right_depth.y4m"), "YUV4MPEG2 W32 H16 C420jpeg\n", readFile(scene.path("right_depth.yuv")),
           frameBytes);
  const fs::path fromY4m = root / "from_y4m.yuv";
  const test::ToolResult y4mRun = test::runTool(
      "ViewSyn", config + " LeftViewImageName=left.y4m RightDepthMapName=right_depth.y4m OutputVirtualViewImageName=" +
                     test::quoted(fromY4m.string()),
      root, scene.dir);
  ASSERT_EQ(y4mRun.exitCode, 0) << y4mRun.err;
  EXPECT_TRUE(readFile(fromY4m) == raw);

  const fs::path y4mOut = root / "virtual.y4m";
  ASSERT_EQ(test::runTool("ViewSyn", config + " OutputVirtualViewImageName=" + test::quoted(y4mOut.string()), root).exitCode, 0);
  const std::string header = "YUV4MPEG2 W32 H16 F25:1 Ip A1:1 C420jpeg\n";
  std::string expected = header;
  for (size_t at = 0; at < raw.size(); at += frameBytes) expected += "FRAME\n" + raw.substr(at, frameBytes);
  EXPECT_TRUE(readFile(y4mOut) == expected);
  // With a Y4M texture, its frame rate is kept.
  ASSERT_EQ(test::runTool("ViewSyn", config + " LeftViewImageName=left.y4m OutputVirtualViewImageName=" +
                                         test::quoted(y4mOut.string()), root, scene.dir).exitCode, 0);
  EXPECT_EQ(readFile(y4mOut).rfind("YUV4MPEG2 W32 H16 F30000:1001 Ip A1:1 C420jpeg\n", 0), 0u);
}

// YuvPsnr: a FIFO is refused without waiting for a writer; numbers that cannot reach stdout are exit 1.
TEST(CatalogueYuvPsnr, FifoRefusedAndStdoutErrorsAreExit1) {
  const fs::path root = test::scratchDir("yuvpsnr_trust");
  TinyScene scene(root / "scene");
  scene.writeAll();
  const std::string left = test::quoted(scene.path("left.yuv").string());
  ASSERT_EQ(mkfifo(scene.path("pipe.yuv").c_str(), 0600), 0);
  const test::ToolResult fifo =
      test::runTool("YuvPsnr", left + " " + test::quoted(scene.path("pipe.yuv").string()) + " 32 16", root, {}, "timeout 10");
  EXPECT_EQ(fifo.exitCode, 1) << fifo.err;
  EXPECT_NE(fifo.err.find("pipe.yuv: cannot open: is a FIFO"), std::string::npos) << fifo.err;
  if (fs::exists("/dev/full")) {
    const test::ToolResult full = test::runTool("YuvPsnr", left + " " + left + " 32 16 >/dev/full", root);
    EXPECT_EQ(full.exitCode, 1);
    EXPECT_NE(full.err.find("cannot write the standard output: No space left on device"), std::string::npos) << full.err;
  }
  const test::ToolResult ok = test::runTool("YuvPsnr", left + " " + left + " 32 16", root);
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

// CameraConvert: the output may not be its input, by any name (here a hard link); a camera file is
// written through a temporary file like every other output.
TEST(CatalogueTools, CameraConvertRefusesItsInputAsOutput) {
  const fs::path root = test::scratchDir("cameraconvert_trust");
  TinyScene scene(root / "scene");
  scene.writeAll();
  fs::create_hard_link(scene.path("cameras.txt"), scene.path("alias.txt"));
  const std::string before = readFile(scene.path("cameras.txt"));
  const test::ToolResult result =
      test::runTool("CameraConvert", test::quoted(scene.path("cameras.txt").string()) + " " +
                                         test::quoted(scene.path("alias.txt").string()), root);
  EXPECT_EQ(result.exitCode, 1) << result.err;
  EXPECT_NE(result.err.find("refusing to overwrite an input"), std::string::npos) << result.err;
  EXPECT_EQ(readFile(scene.path("cameras.txt")), before);
  const test::ToolResult json = test::runTool(
      "CameraConvert",
      test::quoted(scene.path("cameras.txt").string()) + " " + test::quoted(scene.path("cameras.json").string()), root);
  EXPECT_EQ(json.exitCode, 0) << json.err;
  expectNoTemporaryFile(scene.dir);
}

}  // namespace
}  // namespace vs
