#include "Synth/Colour.h"

#include <algorithm>
#include <cmath>

#include "Common/Error.h"

namespace vs {

namespace {

uint16_t clampRound(double v, int maxValue) {
  if (!(v > 0)) return 0;
  return uint16_t(std::min<double>(maxValue, std::floor(v + 0.5)));
}

// Bilinear value of a chroma plane at luma position (x, y); chroma sample centres sit at luma
// (2i + 0.5, 2j + 0.5) for 4:2:0.
double chromaAt(const Plane& plane, int x, int y, ChromaFormat format) {
  if (format == ChromaFormat::Yuv444) return plane.at(x, y);
  const double cx = (x - 0.5) / 2.0, cy = (y - 0.5) / 2.0;
  const int x0 = int(std::floor(cx)), y0 = int(std::floor(cy));
  const double fx = cx - x0, fy = cy - y0;
  auto at = [&](int px, int py) {
    return double(plane.at(std::clamp(px, 0, plane.width - 1), std::clamp(py, 0, plane.height - 1)));
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

}  // namespace

void yuvToRgb(const Frame& yuv, Frame& rgb) {
  VS_CHECK(yuv.format.chroma != ChromaFormat::Yuv400);
  FrameFormat format = yuv.format;
  format.chroma = ChromaFormat::Yuv444;
  rgb.reset(format);
  const int maxValue = format.maxValue();
  const double mid = double(1 << (format.bitDepth - 1));
  for (int y = 0; y < format.height; ++y)
    for (int x = 0; x < format.width; ++x) {
      const double Y = yuv.planes[0].at(x, y);
      const double cb = chromaAt(yuv.planes[1], x, y, yuv.format.chroma) - mid;
      const double cr = chromaAt(yuv.planes[2], x, y, yuv.format.chroma) - mid;
      rgb.planes[0].at(x, y) = clampRound(Y + 1.402 * cr, maxValue);
      rgb.planes[1].at(x, y) = clampRound(Y - 0.344136 * cb - 0.714136 * cr, maxValue);
      rgb.planes[2].at(x, y) = clampRound(Y + 1.772 * cb, maxValue);
    }
}

void rgbToYuv(const Frame& rgb, Frame& yuv) {
  VS_CHECK(rgb.format.chroma == ChromaFormat::Yuv444 && yuv.format.chroma != ChromaFormat::Yuv400);
  const int w = rgb.format.width, h = rgb.format.height, maxValue = yuv.format.maxValue();
  const double mid = double(1 << (yuv.format.bitDepth - 1));
  std::vector<double> cb(size_t(w) * h), cr(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double r = rgb.planes[0].at(x, y), g = rgb.planes[1].at(x, y), b = rgb.planes[2].at(x, y);
      const double Y = 0.299 * r + 0.587 * g + 0.114 * b;
      yuv.planes[0].at(x, y) = clampRound(Y, maxValue);
      cb[size_t(y) * w + x] = (b - Y) * 0.564 + mid;
      cr[size_t(y) * w + x] = (r - Y) * 0.713 + mid;
    }
  const int scale = yuv.format.chroma == ChromaFormat::Yuv420 ? 2 : 1;
  for (int j = 0; j < yuv.planes[1].height; ++j)
    for (int i = 0; i < yuv.planes[1].width; ++i) {
      double sb = 0, sr = 0;
      int count = 0;
      for (int dy = 0; dy < scale; ++dy)
        for (int dx = 0; dx < scale; ++dx) {
          const int x = i * scale + dx, y = j * scale + dy;
          if (x >= w || y >= h) continue;
          sb += cb[size_t(y) * w + x];
          sr += cr[size_t(y) * w + x];
          ++count;
        }
      yuv.planes[1].at(i, j) = clampRound(sb / count, maxValue);
      yuv.planes[2].at(i, j) = clampRound(sr / count, maxValue);
    }
}

namespace {

// Each value rounded half up and clamped to [0, maxValue], 0 for NaN. Written without branches so
// that the loop vectorises: for v > 0, min(v + 0.5, maxValue) truncated is floor(v + 0.5) capped at
// maxValue, as maxValue is a whole number and truncation is floor for positive values. (The addition
// runs for every value, selected after: the compiler will not start a floating-point operation that
// might trap where the source has none, and would keep a branch.)
void roundInto(const std::vector<float>& colour, int maxValue, Plane& plane) {
  const float top = float(maxValue);
  const float* const in = colour.data();
  uint16_t* const out = plane.samples.data();
  const size_t n = plane.samples.size();
  for (size_t i = 0; i < n; ++i) {
    const float value = in[i];
    const float capped = std::min(value + 0.5f, top);
    out[i] = uint16_t(int(value > 0.0f ? capped : 0.0f));  // !(value > 0): also NaN
  }
}

}  // namespace

void roundLayersToFrame(const BlendedLayer& luma, const BlendedLayer& chroma, bool rgb, Frame& rgbScratch, Frame& output) {
  const FrameFormat& format = output.format;
  const int maxValue = format.maxValue();
  if (rgb) {
    rgbScratch.reset(FrameFormat{format.width, format.height, format.bitDepth, ChromaFormat::Yuv444});
    for (int c = 0; c < 3; ++c) roundInto(luma.colour[c], maxValue, rgbScratch.planes[c]);
    rgbToYuv(rgbScratch, output);
    return;
  }
  roundInto(luma.colour[0], maxValue, output.planes[0]);
  if (format.chroma != ChromaFormat::Yuv400)
    for (int c = 0; c < 2; ++c) roundInto(chroma.colour[c], maxValue, output.planes[c + 1]);
}

}  // namespace vs
