#include "Common/Frame.h"

#include <algorithm>

namespace vs {

const char* chromaFormatName(ChromaFormat format) {
  switch (format) {
    case ChromaFormat::Yuv400: return "400";
    case ChromaFormat::Yuv420: return "420";
    case ChromaFormat::Yuv444: return "444";
  }
  return "?";
}

bool parseChromaFormat(const std::string& text, ChromaFormat& format) {
  if (text == "400") format = ChromaFormat::Yuv400;
  else if (text == "420") format = ChromaFormat::Yuv420;
  else if (text == "444") format = ChromaFormat::Yuv444;
  else return false;
  return true;
}

int chromaWidth(int lumaWidth, ChromaFormat format) {
  switch (format) {
    case ChromaFormat::Yuv400: return 0;
    case ChromaFormat::Yuv420: return (lumaWidth + 1) / 2;
    case ChromaFormat::Yuv444: return lumaWidth;
  }
  return 0;
}

int chromaHeight(int lumaHeight, ChromaFormat format) {
  switch (format) {
    case ChromaFormat::Yuv400: return 0;
    case ChromaFormat::Yuv420: return (lumaHeight + 1) / 2;
    case ChromaFormat::Yuv444: return lumaHeight;
  }
  return 0;
}

uint64_t FrameFormat::frameBytes() const {
  const uint64_t luma = uint64_t(width) * uint64_t(height);
  const uint64_t chroma = uint64_t(chromaWidth(width, this->chroma)) * uint64_t(chromaHeight(height, this->chroma));
  return (luma + 2 * chroma) * uint64_t(bytesPerSample());
}

void Frame::reset(const FrameFormat& f) {
  format = f;
  planes[0].resize(f.width, f.height);
  const int cw = chromaWidth(f.width, f.chroma), ch = chromaHeight(f.height, f.chroma);
  planes[1].resize(cw, ch);
  planes[2].resize(cw, ch);
}

void Frame::fill(uint16_t luma) {
  std::fill(planes[0].samples.begin(), planes[0].samples.end(), luma);
  const uint16_t mid = uint16_t(1u << (format.bitDepth - 1));
  for (int c = 1; c < 3; ++c) std::fill(planes[c].samples.begin(), planes[c].samples.end(), mid);
}

bool Frame::operator==(const Frame& other) const {
  return format == other.format && planes[0] == other.planes[0] && planes[1] == other.planes[1] &&
         planes[2] == other.planes[2];
}

}  // namespace vs
