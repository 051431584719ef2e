#pragma once
// What a file named as a sequence input really is, decided by its type (stat) and its first bytes,
// never by its name (doc/formats-yuv.md, "What is accepted"). Also the Y4M (YUV4MPEG2) header,
// which ViewSyn reads and writes natively.
#include <cstdint>
#include <string>

#include "Common/Frame.h"

namespace vs {

// Throws InputError, without opening the file, unless `path` names an existing regular file (links
// followed): a folder, a FIFO, a socket or a device is refused by stat() alone, so a FIFO cannot make
// the run wait forever in open(). `role` starts the message, e.g. "LeftViewImageName".
void requireRegularFile(const std::string& path, const std::string& role = "");

enum class ContainerKind { RawYuv, Y4m, Other };

// The container, from the first bytes of a file. For Other, `description` says what the file is
// ("a PNG image") and `conversion` is an ffmpeg command line that turns it into raw YUV.
struct ContainerSniff {
  ContainerKind kind = ContainerKind::RawYuv;
  std::string description;
  std::string conversion;
};
// `head`: the file's first bytes (up to 64 are used); `fileBytes`: its size; `path` and `format`
// fill the ffmpeg command line.
ContainerSniff sniffContainer(const std::string& head, uint64_t fileBytes, const std::string& path,
                              const FrameFormat& format);

// A Y4M stream header: "YUV4MPEG2 W.. H.. F..:.. I.. A..:.. C.. X..\n". Every frame is "FRAME",
// optional parameters, '\n', then the planar frame exactly as in a raw file.
struct Y4mHeader {
  FrameFormat format;
  int rateNumerator = 25, rateDenominator = 1;  // F; 25:1 when absent
  char interlacing = 'p';                       // I: p, t, b, m or ? (any is accepted: frames are read as they are)
  uint64_t headerBytes = 0;                     // the stream header, its '\n' included
};

// Parses the stream header at the start of `head`; throws InputError naming `path` and what is
// wrong (no end of line within 1024 bytes, no W or H, a chroma tag we do not read such as 422).
Y4mHeader parseY4mHeader(const std::string& head, const std::string& path);

// The stream header written for `format` (C420jpeg, C444, Cmono; C420p10, C444p12, Cmono16... above
// 8 bits), with its '\n'.
std::string formatY4mHeader(const FrameFormat& format, int rateNumerator = 25, int rateDenominator = 1);

// "32x16 4:2:0 8-bit": a format as people say it.
std::string describeFormat(const FrameFormat& format);

// Sizes for which a raw file of `fileBytes` bytes holds a whole number of frames: widths with the
// format's height, heights with its width (nearest the format's first, at most `count` of each), and
// common video sizes; e.g. "width 688 (7 frames), height 556 (3 frames), 1920x1080 (1 frame)".
// Empty when none is found.
std::string wholeFrameSizes(uint64_t fileBytes, const FrameFormat& format, int count = 3);

}  // namespace vs
