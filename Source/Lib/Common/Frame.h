#pragma once
// A picture that knows its size, bit depth and chroma format. Samples are stored as uint16_t for every
// bit depth (8 to 16), one contiguous row-major vector per plane with stride == plane width.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "Common/Error.h"

namespace vs {

enum class ChromaFormat { Yuv400, Yuv420, Yuv444 };

// "400", "420", "444" <-> enum. parseChromaFormat returns false on anything else.
const char* chromaFormatName(ChromaFormat format);
bool parseChromaFormat(const std::string& text, ChromaFormat& format);

// Width and height of chroma planes for a luma size; 0x0 for 4:0:0. 4:2:0 rounds up for odd sizes.
int chromaWidth(int lumaWidth, ChromaFormat format);
int chromaHeight(int lumaHeight, ChromaFormat format);
inline int planeCount(ChromaFormat format) { return format == ChromaFormat::Yuv400 ? 1 : 3; }

struct Plane {
  int width = 0;
  int height = 0;
  std::vector<uint16_t> samples;  // row-major, stride == width

  Plane() = default;
  Plane(int w, int h, uint16_t fill = 0) : width(w), height(h), samples(size_t(w) * size_t(h), fill) {}
  void resize(int w, int h) {
    width = w;
    height = h;
    samples.resize(size_t(w) * size_t(h));
  }
  uint16_t* row(int y) { return samples.data() + size_t(y) * size_t(width); }
  const uint16_t* row(int y) const { return samples.data() + size_t(y) * size_t(width); }
  uint16_t& at(int x, int y) { return samples[size_t(y) * size_t(width) + size_t(x)]; }
  uint16_t at(int x, int y) const { return samples[size_t(y) * size_t(width) + size_t(x)]; }
  bool operator==(const Plane& other) const {
    return width == other.width && height == other.height && samples == other.samples;
  }
};

struct FrameFormat {
  int width = 0;
  int height = 0;
  int bitDepth = 8;  // 8..16; > 8 is stored as little-endian 16-bit words in files
  ChromaFormat chroma = ChromaFormat::Yuv420;

  int maxValue() const { return (1 << bitDepth) - 1; }
  int bytesPerSample() const { return bitDepth > 8 ? 2 : 1; }
  // Bytes of one frame in a planar YUV file. 64-bit: frame offsets can pass 4 GiB.
  uint64_t frameBytes() const;
  bool operator==(const FrameFormat& o) const {
    return width == o.width && height == o.height && bitDepth == o.bitDepth && chroma == o.chroma;
  }
  bool operator!=(const FrameFormat& o) const { return !(*this == o); }
};

struct Frame {
  FrameFormat format;
  Plane planes[3];  // Y, U (Cb), V (Cr); U and V are empty for 4:0:0

  Frame() = default;
  explicit Frame(const FrameFormat& f) { reset(f); }
  // Resizes every plane for the format (no reallocation when the size is unchanged). Samples keep
  // whatever they held; call fill() for a defined content.
  void reset(const FrameFormat& f);
  // Luma to `luma`, chroma to mid-grey (1 << (bitDepth - 1)).
  void fill(uint16_t luma);
  int width() const { return format.width; }
  int height() const { return format.height; }
  bool operator==(const Frame& other) const;
};

// One reference view's frame: texture and depth levels (the luma of the depth file).
struct ReferenceFrame {
  const Frame* texture = nullptr;
  const Plane* depth = nullptr;
};

}  // namespace vs
