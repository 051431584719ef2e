#pragma once
// Planar YUV files (doc/formats-yuv.md): Y, then U, then V, frame after frame, no header. 8-bit files
// hold one byte a sample; 9- to 16-bit files hold one little-endian 16-bit word a sample, value in the
// low bits. Frame n starts at byte n * FrameFormat::frameBytes() (64-bit offsets). Y4M files (a
// "YUV4MPEG2" header, "FRAME" before each frame) are read and written too; other containers (PNG,
// JPEG, MP4...) are recognised by their first bytes and refused.
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "Common/FileKind.h"
#include "Common/Frame.h"

namespace vs {

// Reads frames from a planar YUV file, in any order. One byte buffer is reused for every read.
class YuvReader {
public:
  // Opens `path`. Throws InputError naming the file: when it is not a regular file (a FIFO or device
  // is refused by stat() before any open), cannot be opened (the OS reason), is an image or video
  // container other than Y4M (what it is and an ffmpeg command that converts it), is a Y4M file whose
  // header disagrees with `format`, and when `format` is unusable (size not positive, bit depth
  // outside 8..16).
  YuvReader(std::string path, const FrameFormat& format);

  const std::string& path() const { return path_; }
  const FrameFormat& format() const { return format_; }
  // File size when opened; frameCount() and trailingBytes() derive from it.
  uint64_t fileBytes() const { return fileBytes_; }
  // Whole frames in the file. A partial frame at the end is not counted; see trailingBytes().
  int64_t frameCount() const { return int64_t(dataBytes() / frameStride()); }
  // Bytes of a trailing partial frame (0 when the file holds whole frames only).
  uint64_t trailingBytes() const { return dataBytes() % frameStride(); }
  // The Y4M header when the file is a Y4M file; nullptr for raw YUV.
  const Y4mHeader* y4m() const { return y4m_ ? &*y4m_ : nullptr; }

  // Fills `frame` (reset to format()) with frame `frameIndex` (>= 0). Throws InputError when the frame is
  // not wholly in the file (naming file, frame and bytes missing), on a read error, and when a 16-bit
  // sample exceeds the bit depth's maximum (naming file, frame, plane and position).
  void read(int64_t frameIndex, Frame& frame);
  // Reads the Y plane only (depth maps): chroma bytes are skipped, not read. `luma` is resized to the
  // luma size. The frame must still be wholly in the file, as for read().
  void readLuma(int64_t frameIndex, Plane& luma);
  // The file bytes of frame `frameIndex` as they are (its Y plane's only with `lumaOnly`), into
  // `bytes`: a frame read ahead takes half the memory of its samples for 8-bit files. unpack() and
  // unpackLuma() then give what read() and readLuma() would have (the same checks and errors).
  void readBytes(int64_t frameIndex, bool lumaOnly, std::vector<uint8_t>& bytes);
  void unpack(int64_t frameIndex, const std::vector<uint8_t>& bytes, Frame& frame) const;
  void unpackLuma(int64_t frameIndex, const std::vector<uint8_t>& bytes, Plane& luma) const;

private:
  // File bytes into planes (sized already), as they come: plane p, its bytes already unpacked, and
  // each plane's largest 16-bit sample.
  struct Unpacker {
    Plane* const* planes;
    int bytesPerSample;
    int p = 0;
    uint64_t inPlane = 0;
    uint16_t largest[3] = {};
    void take(const uint8_t* bytes, uint64_t n);
  };
  // Throws when a 16-bit sample of the first `count` planes exceeds the bit depth's maximum.
  void checkRange(const Unpacker& unpacked, int64_t frameIndex, int count) const;
  uint64_t bytesOf(Plane* const* planes, int count) const;  // the file bytes of the first `count` planes
  // n bytes of the frame that starts at `start`, `done` bytes into it, of `total`.
  void readFileBytes(int64_t frameIndex, uint64_t start, uint64_t done, uint8_t* to, uint64_t n, uint64_t total);
  // Checks that frame `frameIndex` is wholly in the file and positions the file at its first sample;
  // returns the frame's offset in the file.
  uint64_t seekFrame(int64_t frameIndex);
  // Reads the first `count` planes of frame `frameIndex` (sized already) from the file, each into its
  // own memory.
  void readPlanes(int64_t frameIndex, Plane* const* planes, int count);
  [[noreturn]] void throwReadFailure(int64_t frameIndex, uint64_t start, uint64_t got, uint64_t count);
  [[noreturn]] void throwSampleOutOfRange(const Plane& plane, int64_t frameIndex, int planeIndex) const;
  [[noreturn]] void throwIncomplete(int64_t frameIndex, uint64_t bytesAvailable) const;
  // Bytes after the Y4M stream header (the whole file for raw YUV), and from one frame's start to
  // the next (its "FRAME" line included for Y4M).
  uint64_t dataBytes() const { return fileBytes_ > dataStart_ ? fileBytes_ - dataStart_ : 0; }
  uint64_t frameStride() const { return frameHeaderBytes_ + format_.frameBytes(); }

  std::string path_;
  FrameFormat format_;
  std::ifstream file_;
  uint64_t fileBytes_ = 0;
  std::shared_ptr<const Y4mHeader> y4m_;
  uint64_t dataStart_ = 0;         // Y4M: the stream header's bytes
  uint64_t frameHeaderBytes_ = 0;  // Y4M: "FRAME...\n" before each frame
};

class SafeOutputFile;

// Appends frames to a planar YUV file (a Y4M file when `path` ends in ".y4m"), through a temporary
// file that commit() renames onto `path` (SafeOutput.h): until then, and for ever when the writer is
// destroyed without commit(), a file that was at `path` keeps what it held.
class YuvWriter {
public:
  // Creates the temporary file. Throws InputError, before creating anything, when `path` is the same
  // file as one of `inputPaths` (also through another spelling or a link), when its folder does not
  // exist or is not a folder, when `path` is a folder, when `format` is unusable, and (with the OS
  // reason) when the file cannot be created. `role` (a key) starts the messages. A Y4M output takes
  // the frame rate of `rateFrom` (e.g. a Y4M input's header), else 25:1.
  YuvWriter(std::string path, const FrameFormat& format, const std::vector<std::string>& inputPaths = {},
            const std::string& role = "", const Y4mHeader* rateFrom = nullptr);
  ~YuvWriter();

  // The constructor's checks alone, without creating the file: a run with several outputs checks them
  // all before it truncates any.
  static void checkOutput(const std::string& path, const FrameFormat& format,
                          const std::vector<std::string>& inputPaths = {}, const std::string& role = "");

  const std::string& path() const { return path_; }
  const FrameFormat& format() const { return format_; }
  int64_t framesWritten() const { return framesWritten_; }

  // Writes `frame` at the end of the temporary file. `frame.format` must equal format() and every
  // sample must be <= maxValue() (both are programming errors: VS_CHECK). When the write fails,
  // InputError is thrown with the OS reason; the writer then refuses further frames and cannot be
  // committed.
  void append(const Frame& frame);
  // Renames the finished file onto path(). Throws InputError when that fails or a write had failed.
  void commit();

private:
  std::string path_;
  FrameFormat format_;
  std::unique_ptr<SafeOutputFile> file_;
  bool y4m_ = false;
  int64_t framesWritten_ = 0;
  bool failed_ = false;
  std::vector<uint8_t> buffer_;  // a chunk of file bytes (at most 256 KiB), allocated on first use
};

}  // namespace vs
