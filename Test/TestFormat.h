#pragma once
// A frame format from its four fields, for tests that make their own frames.
#include "Common/Frame.h"

namespace test {

inline vs::FrameFormat makeFormat(int width, int height, int bitDepth, vs::ChromaFormat chroma) {
  vs::FrameFormat format;
  format.width = width;
  format.height = height;
  format.bitDepth = bitDepth;
  format.chroma = chroma;
  return format;
}

}  // namespace test
