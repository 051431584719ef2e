#include "Common/Yuv.h"

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <system_error>
#include <utility>

namespace vs {

namespace fs = std::filesystem;

namespace {

const char* const kPlaneNames[3] = {"Y", "U", "V"};

std::string osReason(int errorNumber) {
  return errorNumber ? std::generic_category().message(errorNumber) : std::string("unknown reason");
}

// A format from a config or the command line can be nonsense; say so before sizing any buffer.
void checkFormat(const FrameFormat& format, const std::string& path) {
  if (format.width <= 0 || format.height <= 0)
    throw InputError(path + ": frame size " + std::to_string(format.width) + "x" +
                     std::to_string(format.height) + " is not positive");
  if (format.bitDepth < 8 || format.bitDepth > 16)
    throw InputError(path + ": bit depth " + std::to_string(format.bitDepth) + " is outside 8..16");
}

size_t planeBytes(const Plane& plane, int bytesPerSample) {
  return size_t(plane.width) * size_t(plane.height) * size_t(bytesPerSample);
}

// Same file: std::filesystem::equivalent when both exist (catches links and other spellings), else
// the weakly canonical absolute paths (catches dir/./file and dir/../dir/file for files not yet made).
bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool equivalent = fs::equivalent(a, b, ec);
    if (!ec) return equivalent;
  }
  std::error_code ecA, ecB;
  const fs::path canonicalA = fs::weakly_canonical(fs::absolute(a, ecA), ecA);
  const fs::path canonicalB = fs::weakly_canonical(fs::absolute(b, ecB), ecB);
  if (ecA || ecB) return fs::absolute(a, ecA).lexically_normal() == fs::absolute(b, ecB).lexically_normal();
  return canonicalA == canonicalB;
}

// Packs one plane into `out` (8-bit: bytes; else little-endian 16-bit words); returns the bytes written.
size_t packPlane(const Plane& plane, int bitDepth, uint8_t* out) {
  const size_t count = plane.samples.size();
  const uint16_t* samples = plane.samples.data();
  uint16_t maxSample = 0;
  if (bitDepth <= 8) {
    for (size_t i = 0; i < count; ++i) {
      maxSample = std::max(maxSample, samples[i]);
      out[i] = uint8_t(samples[i]);
    }
  } else {
    for (size_t i = 0; i < count; ++i) {
      maxSample = std::max(maxSample, samples[i]);
      out[2 * i] = uint8_t(samples[i] & 0xff);
      out[2 * i + 1] = uint8_t(samples[i] >> 8);
    }
  }
  VS_CHECK_MSG(int(maxSample) <= (1 << bitDepth) - 1, "a sample exceeds the bit depth's maximum");
  return bitDepth <= 8 ? count : 2 * count;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// YuvReader

YuvReader::YuvReader(std::string path, const FrameFormat& format) : path_(std::move(path)), format_(format) {
  checkFormat(format_, path_);
  std::error_code ec;
  if (fs::is_directory(path_, ec)) throw InputError(path_ + ": cannot open: is a folder, not a file");
  errno = 0;
  file_.open(path_, std::ios::in | std::ios::binary);
  if (!file_.is_open()) throw InputError(path_ + ": cannot open: " + osReason(errno));
  fileBytes_ = fs::file_size(path_, ec);
  if (ec) throw InputError(path_ + ": cannot get the file size: " + ec.message());
}

void YuvReader::throwIncomplete(int64_t frameIndex, uint64_t bytesAvailable) const {
  const uint64_t frameBytes = format_.frameBytes();
  const std::string what = bytesAvailable > 0 ? " is incomplete: " : " is missing: ";
  throw InputError(path_ + ": frame " + std::to_string(frameIndex) + what +
                   std::to_string(frameBytes - bytesAvailable) + " of " + std::to_string(frameBytes) +
                   " bytes missing (file holds " + std::to_string(frameCount()) + " whole frames)");
}

void YuvReader::readFrameBytes(int64_t frameIndex, uint64_t count) {
  VS_CHECK(frameIndex >= 0);
  const uint64_t frameBytes = format_.frameBytes();
  VS_CHECK(count <= frameBytes);
  if (buffer_.size() < frameBytes) buffer_.resize(frameBytes);  // once per reader

  // Comparing indices, not byte offsets, keeps absurd indices from overflowing the offset.
  if (uint64_t(frameIndex) >= fileBytes_ / frameBytes) {
    std::error_code ec;
    const uint64_t nowBytes = fs::file_size(path_, ec);  // the file may have grown since it was opened
    if (!ec) fileBytes_ = nowBytes;
    const uint64_t wholeFrames = fileBytes_ / frameBytes;
    if (uint64_t(frameIndex) >= wholeFrames)
      throwIncomplete(frameIndex, uint64_t(frameIndex) == wholeFrames ? fileBytes_ % frameBytes : 0);
  }

  file_.clear();
  errno = 0;
  file_.seekg(std::streamoff(uint64_t(frameIndex) * frameBytes), std::ios::beg);
  if (file_) file_.read(reinterpret_cast<char*>(buffer_.data()), std::streamsize(count));
  const uint64_t got = file_.gcount() > 0 ? uint64_t(file_.gcount()) : 0;
  if (got == count) return;

  const int readErrno = errno;
  std::error_code ec;
  const uint64_t nowBytes = fs::file_size(path_, ec);
  if (!ec && nowBytes < (uint64_t(frameIndex) + 1) * frameBytes) {  // the file shrank under us
    fileBytes_ = nowBytes;
    const uint64_t start = uint64_t(frameIndex) * frameBytes;
    throwIncomplete(frameIndex, nowBytes > start ? nowBytes - start : 0);
  }
  throw InputError(path_ + ": frame " + std::to_string(frameIndex) + ": read failed after " +
                   std::to_string(got) + " of " + std::to_string(count) + " bytes: " + osReason(readErrno));
}

void YuvReader::unpackPlane(size_t byteOffset, Plane& plane, int64_t frameIndex, int planeIndex) const {
  const size_t count = plane.samples.size();
  const uint8_t* bytes = buffer_.data() + byteOffset;
  uint16_t* samples = plane.samples.data();
  if (format_.bitDepth <= 8) {
    for (size_t i = 0; i < count; ++i) samples[i] = bytes[i];
    return;
  }
  uint16_t maxSample = 0;
  for (size_t i = 0; i < count; ++i) {
    samples[i] = uint16_t(bytes[2 * i] | (bytes[2 * i + 1] << 8));
    maxSample = std::max(maxSample, samples[i]);
  }
  const int maxValue = format_.maxValue();
  if (maxSample <= maxValue) return;
  // Rare path: find the first offending sample so the message can point at it.
  const auto first = std::find_if(plane.samples.begin(), plane.samples.end(),
                                  [maxValue](uint16_t s) { return s > maxValue; });
  const size_t index = size_t(first - plane.samples.begin());
  throw InputError(path_ + ": frame " + std::to_string(frameIndex) + ", plane " + kPlaneNames[planeIndex] +
                   ": sample " + std::to_string(*first) + " at (x " + std::to_string(index % size_t(plane.width)) +
                   ", y " + std::to_string(index / size_t(plane.width)) + ") exceeds " +
                   std::to_string(maxValue) + ", the maximum of " + std::to_string(format_.bitDepth) +
                   "-bit samples (wrong bit depth, or a big-endian file?)");
}

void YuvReader::read(int64_t frameIndex, Frame& frame) {
  readFrameBytes(frameIndex, format_.frameBytes());
  frame.reset(format_);
  size_t offset = 0;
  for (int p = 0; p < planeCount(format_.chroma); ++p) {
    unpackPlane(offset, frame.planes[p], frameIndex, p);
    offset += planeBytes(frame.planes[p], format_.bytesPerSample());
  }
}

void YuvReader::readLuma(int64_t frameIndex, Plane& luma) {
  luma.resize(format_.width, format_.height);
  readFrameBytes(frameIndex, planeBytes(luma, format_.bytesPerSample()));
  unpackPlane(0, luma, frameIndex, 0);
}

// ---------------------------------------------------------------------------------------------------
// YuvWriter

void YuvWriter::checkOutput(const std::string& path, const FrameFormat& format, const std::vector<std::string>& inputPaths) {
  if (path.empty()) throw InputError("output file name is empty");
  checkFormat(format, path);
  for (const std::string& input : inputPaths) {
    if (!input.empty() && sameFile(path, input))
      throw InputError(path + ": output file is the same file as input '" + input + "'; refusing to overwrite an input");
  }
  std::error_code ec;
  const fs::path absolutePath = fs::absolute(path, ec);
  const fs::path folder = absolutePath.parent_path();
  if (!fs::exists(folder, ec))
    throw InputError(path + ": output folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(folder, ec))
    throw InputError(path + ": output folder '" + folder.string() + "' is not a folder");
  if (fs::is_directory(absolutePath, ec)) throw InputError(path + ": output path is a folder, not a file");
}

YuvWriter::YuvWriter(std::string path, const FrameFormat& format, const std::vector<std::string>& inputPaths)
    : path_(std::move(path)), format_(format) {
  // Every check comes before the open: opening truncates, and an input must never be truncated.
  checkOutput(path_, format_, inputPaths);
  std::error_code ec;
  const fs::path folder = fs::absolute(path_, ec).parent_path();

  // Unbuffered: append() hands each frame to the OS in one write, and nothing is left in a buffer to
  // reach the file after a failed write has been cut back.
  file_.rdbuf()->pubsetbuf(nullptr, 0);
  errno = 0;
  file_.open(path_, std::ios::out | std::ios::binary | std::ios::trunc);
  if (!file_.is_open())
    throw InputError(path_ + ": cannot create the output file in folder '" + folder.string() +
                     "': " + osReason(errno));
}

void YuvWriter::append(const Frame& frame) {
  VS_CHECK_MSG(frame.format == format_, "the frame's format differs from the YuvWriter's");
  for (int p = 0; p < planeCount(format_.chroma); ++p) {
    const int w = p == 0 ? format_.width : chromaWidth(format_.width, format_.chroma);
    const int h = p == 0 ? format_.height : chromaHeight(format_.height, format_.chroma);
    VS_CHECK(frame.planes[p].width == w && frame.planes[p].height == h &&
             frame.planes[p].samples.size() == size_t(w) * size_t(h));
  }
  if (failed_) throw InputError(path_ + ": an earlier write failed; no further frames are written");

  const uint64_t frameBytes = format_.frameBytes();
  if (buffer_.size() != frameBytes) buffer_.resize(frameBytes);
  size_t offset = 0;
  for (int p = 0; p < planeCount(format_.chroma); ++p)
    offset += packPlane(frame.planes[p], format_.bitDepth, buffer_.data() + offset);
  VS_CHECK(offset == frameBytes);

  errno = 0;
  file_.write(reinterpret_cast<const char*>(buffer_.data()), std::streamsize(frameBytes));
  file_.flush();
  if (file_) {
    ++framesWritten_;
    return;
  }

  const int writeErrno = errno;
  failed_ = true;
  file_.close();
  const uint64_t wholeBytes = uint64_t(framesWritten_) * frameBytes;
  std::error_code ec;
  fs::resize_file(path_, wholeBytes, ec);
  std::string message = path_ + ": writing frame " + std::to_string(framesWritten_) +
                        " failed: " + osReason(writeErrno);
  if (ec)
    message += "; cutting the file back to its " + std::to_string(framesWritten_) +
               " whole frames also failed: " + ec.message();
  else
    message += "; the file keeps its " + std::to_string(framesWritten_) + " whole frames";
  throw InputError(message);
}

}  // namespace vs
