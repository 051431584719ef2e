#include "Common/Yuv.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <cerrno>
#include <filesystem>
#include <system_error>
#include <utility>

#include "Common/SafeOutput.h"

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

// Packs `count` samples into `out` (8-bit: bytes; else little-endian 16-bit words); returns the bytes
// written.
size_t packSamples(const uint16_t* samples, size_t count, int bitDepth, uint8_t* out) {
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
  requireRegularFile(path_);  // stat() first: open() on a FIFO would wait for a writer for ever
  errno = 0;
  file_.open(path_, std::ios::in | std::ios::binary);
  if (!file_.is_open()) throw InputError(path_ + ": cannot open: " + osReason(errno));
  std::error_code ec;
  fileBytes_ = fs::file_size(path_, ec);
  if (ec) throw InputError(path_ + ": cannot get the file size: " + ec.message());

  // What the file is, by its first bytes (a Y4M stream header can be long: up to 1 KiB is read).
  std::string head(size_t(std::min<uint64_t>(fileBytes_, 1024)), '\0');
  file_.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(std::max<std::streamsize>(file_.gcount(), 0)));
  file_.clear();
  const ContainerSniff sniff = sniffContainer(head, fileBytes_, path_, format_);
  if (sniff.kind == ContainerKind::Other)
    throw InputError(path_ + ": the file is " + sniff.description + ", not a raw YUV or Y4M sequence; convert it: " +
                     sniff.conversion);
  if (sniff.kind != ContainerKind::Y4m) return;
  const Y4mHeader header = parseY4mHeader(head, path_);
  if (header.format != format_)
    throw InputError(path_ + ": the Y4M header says " + describeFormat(header.format) + ", the configuration " +
                     describeFormat(format_) + " (set the size, chroma format and bit depth keys to the file's)");
  y4m_ = std::make_shared<const Y4mHeader>(header);
  dataStart_ = header.headerBytes;
  // Every frame starts with "FRAME", optional parameters and '\n'; the first one gives the length.
  frameHeaderBytes_ = 6;
  if (fileBytes_ > dataStart_) {
    std::string line(size_t(std::min<uint64_t>(fileBytes_ - dataStart_, 256)), '\0');
    file_.seekg(std::streamoff(dataStart_));
    file_.read(line.data(), std::streamsize(line.size()));
    file_.clear();
    const size_t end = line.find('\n');
    if (line.rfind("FRAME", 0) != 0 || end == std::string::npos)
      throw InputError(path_ + ": Y4M: no FRAME header after the stream header (a cut or damaged file?)");
    frameHeaderBytes_ = end + 1;
  }
}

void YuvReader::throwIncomplete(int64_t frameIndex, uint64_t bytesAvailable) const {
  const uint64_t frameBytes = frameStride();
  const std::string what = bytesAvailable > 0 ? " is incomplete: " : " is missing: ";
  throw InputError(path_ + ": frame " + std::to_string(frameIndex) + what +
                   std::to_string(frameBytes - bytesAvailable) + " of " + std::to_string(frameBytes) +
                   " bytes missing (file holds " + std::to_string(frameCount()) + " whole frames)");
}

uint64_t YuvReader::seekFrame(int64_t frameIndex) {
  VS_CHECK(frameIndex >= 0);
  const uint64_t stride = frameStride();
  // Comparing indices, not byte offsets, keeps absurd indices from overflowing the offset.
  if (uint64_t(frameIndex) >= dataBytes() / stride) {
    std::error_code ec;
    const uint64_t nowBytes = fs::file_size(path_, ec);  // the file may have grown since it was opened
    if (!ec) fileBytes_ = nowBytes;
    const uint64_t wholeFrames = dataBytes() / stride;
    if (uint64_t(frameIndex) >= wholeFrames)
      throwIncomplete(frameIndex, uint64_t(frameIndex) == wholeFrames ? dataBytes() % stride : 0);
  }

  const uint64_t start = dataStart_ + uint64_t(frameIndex) * stride;
  file_.clear();
  errno = 0;
  file_.seekg(std::streamoff(start), std::ios::beg);
  if (frameHeaderBytes_ > 0 && file_) {
    char frameHeader[5] = {};
    file_.read(frameHeader, 5);
    if (file_ && std::string(frameHeader, 5) != "FRAME")
      throw InputError(path_ + ": Y4M frame " + std::to_string(frameIndex) + " does not start with FRAME (frames with " +
                       "header parameters of different lengths are not read)");
    file_.seekg(std::streamoff(start + frameHeaderBytes_), std::ios::beg);
  }
  return start;
}

void YuvReader::Unpacker::take(const uint8_t* bytes, uint64_t n) {
  for (uint64_t used = 0; used < n;) {
    const uint64_t planeTotal = planeBytes(*planes[p], bytesPerSample);
    const uint64_t count = std::min(n - used, planeTotal - inPlane);
    const uint8_t* from = bytes + used;
    uint16_t* samples = planes[p]->samples.data() + inPlane / uint64_t(bytesPerSample);
    if (bytesPerSample == 1) {
      for (uint64_t i = 0; i < count; ++i) samples[i] = from[i];
    } else {
      uint16_t most = largest[p];
      for (uint64_t i = 0; i < count / 2; ++i) {
        samples[i] = uint16_t(from[2 * i] | (from[2 * i + 1] << 8));
        most = std::max(most, samples[i]);
      }
      largest[p] = most;
    }
    used += count;
    inPlane += count;
    if (inPlane == planeTotal) {
      ++p;
      inPlane = 0;
    }
  }
}

void YuvReader::checkRange(const Unpacker& unpacked, int64_t frameIndex, int count) const {
  if (unpacked.bytesPerSample > 1)
    for (int q = 0; q < count; ++q)
      if (unpacked.largest[q] > format_.maxValue()) throwSampleOutOfRange(*unpacked.planes[q], frameIndex, q);
}

uint64_t YuvReader::bytesOf(Plane* const* planes, int count) const {
  uint64_t total = 0;
  for (int p = 0; p < count; ++p) total += planeBytes(*planes[p], format_.bytesPerSample());
  VS_CHECK(total <= format_.frameBytes());
  return total;
}

void YuvReader::readFileBytes(int64_t frameIndex, uint64_t start, uint64_t done, uint8_t* to, uint64_t n,
                              uint64_t total) {
  uint64_t got = 0;  // not gcount() of an earlier read when this one is not attempted
  if (file_) {
    file_.read(reinterpret_cast<char*>(to), std::streamsize(n));
    got = file_.gcount() > 0 ? uint64_t(file_.gcount()) : 0;
  }
  if (got != n) throwReadFailure(frameIndex, start, done + got, total);
}

namespace {

// Widens n 8-bit samples that lie in the upper half of the samples' own memory (bytes n to 2n) into
// them, in place: a block is copied out before it is written, and writing samples [i, i + B) (bytes
// 2i to 2i + 2B) never reaches the bytes not yet read (from n + i + B on) while i + B <= n.
void widenInPlace(uint16_t* samples, uint64_t n) {
  const uint8_t* bytes = reinterpret_cast<const uint8_t*>(samples) + n;
  constexpr uint64_t kBlock = 256;
  uint8_t block[kBlock];
  for (uint64_t i = 0; i < n; i += kBlock) {
    const uint64_t count = std::min(kBlock, n - i);
    std::memcpy(block, bytes + i, size_t(count));
    for (uint64_t k = 0; k < count; ++k) samples[i + k] = block[k];
  }
}

}  // namespace

void YuvReader::readPlanes(int64_t frameIndex, Plane* const* planes, int count) {
  const uint64_t total = bytesOf(planes, count);
  const uint64_t start = seekFrame(frameIndex);
  // Each plane's file bytes are read straight into the plane's own memory and widened there: no
  // buffer beside the samples (a chunk of 256 KiB per reader until 2026-11-26, sixth round: 64 pages
  // first touched per reader in a run of one frame). 8-bit samples land in the plane's upper half and
  // are widened in place; 16-bit ones are the file's little-endian words already.
  const int bytesPerSample = format_.bytesPerSample();
  Unpacker unpacker{planes, bytesPerSample};
  uint64_t done = 0;
  for (int p = 0; p < count; ++p) {
    uint16_t* samples = planes[p]->samples.data();
    const uint64_t n = planes[p]->samples.size(), bytes = planeBytes(*planes[p], bytesPerSample);
    uint8_t* memory = reinterpret_cast<uint8_t*>(samples);
    if (bytesPerSample == 1) {
      readFileBytes(frameIndex, start, done, memory + n, bytes, total);
      widenInPlace(samples, n);
    } else {
      readFileBytes(frameIndex, start, done, memory, bytes, total);
      uint16_t most = 0;
      for (uint64_t i = 0; i < n; ++i) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
        samples[i] = uint16_t(memory[2 * i] | (memory[2 * i + 1] << 8));
#endif
        most = std::max(most, samples[i]);
      }
      unpacker.largest[p] = most;
    }
    done += bytes;
  }
  checkRange(unpacker, frameIndex, count);
}

void YuvReader::readBytes(int64_t frameIndex, bool lumaOnly, std::vector<uint8_t>& bytes) {
  const uint64_t luma = uint64_t(format_.width) * uint64_t(format_.height) * uint64_t(format_.bytesPerSample());
  const uint64_t total = lumaOnly ? luma : format_.frameBytes();
  const uint64_t start = seekFrame(frameIndex);
  bytes.resize(size_t(total));
  readFileBytes(frameIndex, start, 0, bytes.data(), total, total);
}

void YuvReader::unpack(int64_t frameIndex, const std::vector<uint8_t>& bytes, Frame& frame) const {
  frame.reset(format_);
  Plane* planes[3] = {&frame.planes[0], &frame.planes[1], &frame.planes[2]};
  const int count = planeCount(format_.chroma);
  VS_CHECK(bytes.size() == bytesOf(planes, count));
  Unpacker unpacker{planes, format_.bytesPerSample()};
  unpacker.take(bytes.data(), bytes.size());
  checkRange(unpacker, frameIndex, count);
}

void YuvReader::unpackLuma(int64_t frameIndex, const std::vector<uint8_t>& bytes, Plane& luma) const {
  luma.resize(format_.width, format_.height);
  Plane* planes[1] = {&luma};
  VS_CHECK(bytes.size() == bytesOf(planes, 1));
  Unpacker unpacker{planes, format_.bytesPerSample()};
  unpacker.take(bytes.data(), bytes.size());
  checkRange(unpacker, frameIndex, 1);
}

void YuvReader::throwReadFailure(int64_t frameIndex, uint64_t start, uint64_t got, uint64_t count) {
  const int readErrno = errno;
  std::error_code ec;
  const uint64_t nowBytes = fs::file_size(path_, ec);
  if (!ec && nowBytes < start + frameStride()) {  // the file shrank under us
    fileBytes_ = nowBytes;
    throwIncomplete(frameIndex, nowBytes > start ? nowBytes - start : 0);
  }
  throw InputError(path_ + ": frame " + std::to_string(frameIndex) + ": read failed after " +
                   std::to_string(got) + " of " + std::to_string(count) + " bytes: " + osReason(readErrno));
}

void YuvReader::throwSampleOutOfRange(const Plane& plane, int64_t frameIndex, int planeIndex) const {
  const int maxValue = format_.maxValue();
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
  frame.reset(format_);
  Plane* planes[3] = {&frame.planes[0], &frame.planes[1], &frame.planes[2]};
  readPlanes(frameIndex, planes, planeCount(format_.chroma));
}

void YuvReader::readLuma(int64_t frameIndex, Plane& luma) {
  luma.resize(format_.width, format_.height);
  Plane* planes[1] = {&luma};
  readPlanes(frameIndex, planes, 1);
}

// ---------------------------------------------------------------------------------------------------
// YuvWriter

void YuvWriter::checkOutput(const std::string& path, const FrameFormat& format, const std::vector<std::string>& inputPaths,
                            const std::string& role) {
  if (path.empty()) throw InputError((role.empty() ? std::string("output") : role) + ": file name is empty");
  checkFormat(format, path);
  SafeOutputFile::checkPath(path, inputPaths, role);
}

YuvWriter::YuvWriter(std::string path, const FrameFormat& format, const std::vector<std::string>& inputPaths,
                     const std::string& role, const Y4mHeader* rateFrom)
    : path_(std::move(path)), format_(format) {
  checkFormat(format_, path_);
  file_ = std::make_unique<SafeOutputFile>(path_, inputPaths, role);
  std::string extension = fs::path(path_).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  y4m_ = extension == ".y4m";
  if (y4m_)
    file_->write(rateFrom ? formatY4mHeader(format_, rateFrom->rateNumerator, rateFrom->rateDenominator)
                          : formatY4mHeader(format_));
}

YuvWriter::~YuvWriter() = default;

void YuvWriter::append(const Frame& frame) {
  VS_CHECK_MSG(frame.format == format_, "the frame's format differs from the YuvWriter's");
  for (int p = 0; p < planeCount(format_.chroma); ++p) {
    const int w = p == 0 ? format_.width : chromaWidth(format_.width, format_.chroma);
    const int h = p == 0 ? format_.height : chromaHeight(format_.height, format_.chroma);
    VS_CHECK(frame.planes[p].width == w && frame.planes[p].height == h &&
             frame.planes[p].samples.size() == size_t(w) * size_t(h));
  }
  if (failed_) throw InputError(path_ + ": an earlier write failed; no further frames are written");

  // Packed and written through a chunk of at most 256 KiB, as the readers read (a whole frame of file
  // bytes per writer was first-touched memory beside the frame itself).
  constexpr uint64_t kChunk = uint64_t(1) << 18;
  const uint64_t frameBytes = (y4m_ ? 6 : 0) + format_.frameBytes();
  if (buffer_.size() < std::min(frameBytes, kChunk)) buffer_.resize(size_t(std::min(frameBytes, kChunk)));
  const size_t sampleBytes = format_.bitDepth <= 8 ? 1 : 2;
  try {
    size_t used = 0;
    if (y4m_) {
      std::memcpy(buffer_.data(), "FRAME\n", 6);
      used = 6;
    }
    uint64_t written = 0;
    for (int p = 0; p < planeCount(format_.chroma); ++p) {
      const uint16_t* samples = frame.planes[p].samples.data();
      const size_t count = frame.planes[p].samples.size();
      for (size_t i = 0; i < count;) {
        if (buffer_.size() - used < sampleBytes) {
          file_->write(buffer_.data(), used);
          written += used;
          used = 0;
        }
        const size_t n = std::min(count - i, (buffer_.size() - used) / sampleBytes);
        used += packSamples(samples + i, n, format_.bitDepth, buffer_.data() + used);
        i += n;
      }
    }
    if (used > 0) file_->write(buffer_.data(), used);
    VS_CHECK(written + used == frameBytes);
  } catch (const InputError& e) {
    failed_ = true;
    if (!file_->lastError()) throw;
    // The caller says what became of the outputs (the temporary file goes when the writer does).
    throw InputError(path_ + ": writing frame " + std::to_string(framesWritten_) + " failed: " +
                     osReason(file_->lastError()));
  }
  ++framesWritten_;
}

void YuvWriter::commit() {
  if (failed_) throw InputError(path_ + ": a write failed; the file is not replaced");
  file_->commit();
}

}  // namespace vs
