#pragma once
// Planar YUV files (doc/formats-yuv.md): Y, then U, then V, frame after frame, no header. 8-bit files
// hold one byte a sample; 9- to 16-bit files hold one little-endian 16-bit word a sample, value in the
// low bits. Frame n starts at byte n * FrameFormat::frameBytes() (64-bit offsets).
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "Common/Frame.h"

namespace vs {

// Reads frames from a planar YUV file, in any order. One byte buffer is reused for every read.
class YuvReader {
public:
  // Opens `path`. Throws InputError naming the file and the OS reason when it cannot be opened, and
  // when `format` is unusable (size not positive, bit depth outside 8..16).
  YuvReader(std::string path, const FrameFormat& format);

  const std::string& path() const { return path_; }
  const FrameFormat& format() const { return format_; }
  // File size when opened; frameCount() and trailingBytes() derive from it.
  uint64_t fileBytes() const { return fileBytes_; }
  // Whole frames in the file. A partial frame at the end is not counted; see trailingBytes().
  int64_t frameCount() const { return int64_t(fileBytes_ / format_.frameBytes()); }
  // Bytes of a trailing partial frame (0 when the file holds whole frames only).
  uint64_t trailingBytes() const { return fileBytes_ % format_.frameBytes(); }

  // Fills `frame` (reset to format()) with frame `frameIndex` (>= 0). Throws InputError when the frame is
  // not wholly in the file (naming file, frame and bytes missing), on a read error, and when a 16-bit
  // sample exceeds the bit depth's maximum (naming file, frame, plane and position).
  void read(int64_t frameIndex, Frame& frame);
  // Reads the Y plane only (depth maps): chroma bytes are skipped, not read. `luma` is resized to the
  // luma size. The frame must still be wholly in the file, as for read().
  void readLuma(int64_t frameIndex, Plane& luma);

private:
  // Reads `count` bytes of frame `frameIndex`, from its start, into buffer_.
  void readFrameBytes(int64_t frameIndex, uint64_t count);
  // Converts `plane.width * plane.height` samples at buffer_[byteOffset] into `plane`.
  void unpackPlane(size_t byteOffset, Plane& plane, int64_t frameIndex, int planeIndex) const;
  [[noreturn]] void throwIncomplete(int64_t frameIndex, uint64_t bytesAvailable) const;

  std::string path_;
  FrameFormat format_;
  std::ifstream file_;
  uint64_t fileBytes_ = 0;
  std::vector<uint8_t> buffer_;  // one frame of file bytes, allocated on first use
};

// Appends frames to a planar YUV file. A frame is written whole or not at all.
class YuvWriter {
public:
  // Creates or truncates `path`. Throws InputError, before touching any file, when `path` is the same
  // file as one of `inputPaths` (also through another spelling or a link), when its folder does not
  // exist or is not a folder, when `path` is a folder, when `format` is unusable, and (with the OS
  // reason) when the file cannot be created.
  YuvWriter(std::string path, const FrameFormat& format, const std::vector<std::string>& inputPaths = {});

  // The constructor's checks alone, without creating the file: a run with several outputs checks them
  // all before it truncates any.
  static void checkOutput(const std::string& path, const FrameFormat& format,
                          const std::vector<std::string>& inputPaths = {});

  const std::string& path() const { return path_; }
  const FrameFormat& format() const { return format_; }
  int64_t framesWritten() const { return framesWritten_; }

  // Writes `frame` at the end of the file with one write and a flush. `frame.format` must equal
  // format() and every sample must be <= maxValue() (both are programming errors: VS_CHECK). When the
  // write fails, the file is cut back to framesWritten() whole frames and InputError is thrown with the
  // OS reason; the writer then refuses further frames.
  void append(const Frame& frame);

private:
  std::string path_;
  FrameFormat format_;
  std::ofstream file_;
  int64_t framesWritten_ = 0;
  bool failed_ = false;
  std::vector<uint8_t> buffer_;  // one frame of file bytes, allocated on first use
};

}  // namespace vs
