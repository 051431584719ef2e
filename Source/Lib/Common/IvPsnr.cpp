#include "Common/IvPsnr.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "Common/Metrics.h"
#include "Common/ParallelRows.h"

namespace vs {

namespace {

const int kDefaultWeights[3] = {4, 1, 1};
constexpr double kPi = 3.14159265358979323846;

// 10 log10(area peak^2 / ssd); +inf for ssd == 0.
double psnrFromSsd(double ssd, double area, int bitDepth) {
  if (ssd <= 0) return std::numeric_limits<double>::infinity();
  const double peak = double((1 << bitDepth) - 1);
  return 10.0 * std::log10(area * peak * peak / ssd);
}

// A plane at luma resolution with a replicated margin of `margin` samples on every side: 4:2:0
// chroma is repeated over 2x2 while it is copied (no upsampled frame is made).
struct PaddedPlane {
  int width = 0, height = 0, margin = 0, stride = 0;
  std::vector<uint16_t> samples;
  // Rows [y0, y1) of the padded plane (-margin <= y0 < y1 <= height + margin); `repeat`: the source
  // is a 4:2:0 chroma plane of a width x height picture.
  void buildRows(const Plane& plane, bool repeat, int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const int sourceY = std::clamp(y, 0, height - 1);
      const uint16_t* src = plane.row(repeat ? sourceY / 2 : sourceY);
      uint16_t* dst = samples.data() + size_t(y + margin) * size_t(stride) + size_t(margin);
      if (repeat) {
        for (int x = 0; x < width; ++x) dst[x] = src[x / 2];
      } else {
        std::copy(src, src + width, dst);
      }
      const uint16_t left = dst[0], right = dst[width - 1];
      for (int x = 1; x <= margin; ++x) {
        dst[-x] = left;
        dst[width - 1 + x] = right;
      }
    }
  }
  void resize(int w, int h, int m) {
    width = w;
    height = h;
    margin = m;
    stride = width + 2 * m;
    samples.resize(size_t(stride) * size_t(height + 2 * m));  // keeps its memory between frames
  }
  // Sample (x, y) at luma resolution, -margin <= x < width + margin (and y likewise).
  const uint16_t* at(int x, int y) const {
    return samples.data() + size_t(y + margin) * size_t(stride) + size_t(x + margin);
  }
};

// Weighted sum of the three squared differences; the default 4:1:1 as a shift (the reference
// software's compile-time default), any other weights by multiplication.
template <class Err, bool Default411>
inline Err weighted(Err s0, Err s1, Err s2, Err w0, Err w1, Err w2) {
  if constexpr (Default411) return (s0 << 2) + s1 + s2;
  else return w0 * s0 + w1 * s1 + w2 * s2;
}

// One row of one direction: every sample of `from` (plus `offset`) matched with the candidate of `to`
// within the window whose weighted squared difference is smallest (the first in raster order on a
// tie); adds the squared differences of that candidate, per plane, to ssd[]. Err is the type of the
// weighted sum: int32_t where it cannot overflow (the reference software's), else int64_t.
template <class Err, int Planes, bool Default411>
void matchRow(const PaddedPlane* from, const PaddedPlane* to, int y, const int offset[3], int range,
              const int weights[3], uint64_t ssd[3]) {
  constexpr int kChunk = 128;
  const int width = from[0].width;
  alignas(64) Err value[Planes][kChunk];
  alignas(64) Err best[kChunk];
  alignas(64) Err bestSq[Planes][kChunk];
  const Err w0 = Err(weights[0]);
  const Err w1 = Planes == 3 ? Err(weights[1]) : 0;
  const Err w2 = Planes == 3 ? Err(weights[2]) : 0;
  for (int x0 = 0; x0 < width; x0 += kChunk) {
    const int n = std::min(kChunk, width - x0);
    for (int p = 0; p < Planes; ++p) {
      const uint16_t* src = from[p].at(x0, y);
      for (int i = 0; i < n; ++i) value[p][i] = Err(src[i]) + Err(offset[p]);
    }
    for (int i = 0; i < n; ++i) best[i] = std::numeric_limits<Err>::max();
    for (int dy = -range; dy <= range; ++dy) {
      for (int dx = -range; dx <= range; ++dx) {
        const uint16_t* __restrict c0 = to[0].at(x0 + dx, y + dy);
        if constexpr (Planes == 3) {
          const uint16_t* __restrict c1 = to[1].at(x0 + dx, y + dy);
          const uint16_t* __restrict c2 = to[2].at(x0 + dx, y + dy);
          for (int i = 0; i < n; ++i) {
            const Err d0 = value[0][i] - Err(c0[i]);
            const Err d1 = value[1][i] - Err(c1[i]);
            const Err d2 = value[2][i] - Err(c2[i]);
            const Err s0 = d0 * d0, s1 = d1 * d1, s2 = d2 * d2;
            const Err error = weighted<Err, Default411>(s0, s1, s2, w0, w1, w2);
            const bool better = error < best[i];
            best[i] = better ? error : best[i];
            bestSq[0][i] = better ? s0 : bestSq[0][i];
            bestSq[1][i] = better ? s1 : bestSq[1][i];
            bestSq[2][i] = better ? s2 : bestSq[2][i];
          }
        } else {
          // Luma alone: the weight cannot change which candidate is smallest.
          for (int i = 0; i < n; ++i) {
            const Err d0 = value[0][i] - Err(c0[i]);
            const Err s0 = d0 * d0;
            best[i] = s0 < best[i] ? s0 : best[i];
          }
        }
      }
    }
    for (int p = 0; p < Planes; ++p) {
      const Err* sq = Planes == 3 ? bestSq[p] : best;
      uint64_t sum = 0;
      for (int i = 0; i < n; ++i) sum += uint64_t(sq[i]);
      ssd[p] += sum;
    }
  }
}

// Per-plane sums of squared differences of one direction, rows summed in order.
template <class Err, int Planes, bool Default411>
void matchPicture(const PaddedPlane* from, const PaddedPlane* to, const int offset[3], const IvPsnrOptions& options,
                  int threads, uint64_t total[3]) {
  const int height = from[0].height;
  std::vector<uint64_t> rowSsd(size_t(height) * 3, 0);
  parallelRows(height, threads, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      matchRow<Err, Planes, Default411>(from, to, y, offset, options.searchRange, options.searchWeights,
                                        &rowSsd[size_t(y) * 3]);
  });
  for (int p = 0; p < 3; ++p) total[p] = 0;
  for (int y = 0; y < height; ++y)
    for (int p = 0; p < 3; ++p) total[p] += rowSsd[size_t(y) * 3 + size_t(p)];
}

template <class Err, int Planes>
void matchPictureWeights(const PaddedPlane* from, const PaddedPlane* to, const int offset[3],
                         const IvPsnrOptions& options, int threads, uint64_t total[3]) {
  const int* w = options.searchWeights;
  if (Planes == 3 && w[0] == 4 && w[1] == 1 && w[2] == 1)
    matchPicture<Err, Planes, true>(from, to, offset, options, threads, total);
  else
    matchPicture<Err, Planes, false>(from, to, offset, options, threads, total);
}

}  // namespace

double weightedPlanes(const double value[3], bool hasChroma, const int weights[3]) {
  if (!hasChroma) return value[0];
  const int* w = weights ? weights : kDefaultWeights;
  double sum = 0;
  int weightSum = 0;
  for (int p = 0; p < 3; ++p) {
    if (w[p] == 0) continue;  // an unweighted +inf plane must not turn the sum into NaN
    sum += double(w[p]) * value[p];
    weightSum += w[p];
  }
  return sum / double(weightSum);
}

std::string validateIvPsnrOptions(const IvPsnrOptions& options) {
  if (options.searchRange < 0 || options.searchRange > 16) return "search range must be in 0..16";
  for (int p = 0; p < 3; ++p) {
    if (!(options.unnoticeable[p] >= 0 && options.unnoticeable[p] <= 1))
      return "unnoticeable colour difference must be in 0..1";
    if (options.searchWeights[p] < 0 || options.searchWeights[p] > 1000 || options.averageWeights[p] < 0 ||
        options.averageWeights[p] > 1000)
      return "component weights must be in 0..1000";
  }
  if (options.searchWeights[0] + options.searchWeights[1] + options.searchWeights[2] == 0 ||
      options.averageWeights[0] + options.averageWeights[1] + options.averageWeights[2] == 0)
    return "component weights must not all be 0";
  if (options.averageWeights[0] == 0) return "the luma average weight must not be 0 (4:0:0 has luma only)";
  return "";
}

struct IvPsnrScratch::Pictures {
  PaddedPlane padded[2][3];  // [reference, test][plane]
};

IvPsnrScratch::IvPsnrScratch() : pictures_(std::make_unique<Pictures>()) {}
IvPsnrScratch::~IvPsnrScratch() = default;
IvPsnrScratch::IvPsnrScratch(IvPsnrScratch&&) noexcept = default;
IvPsnrScratch& IvPsnrScratch::operator=(IvPsnrScratch&&) noexcept = default;

IvPsnrResult ivPsnr(const Frame& ref, const Frame& test, const IvPsnrOptions& options) {
  IvPsnrScratch scratch;
  return ivPsnr(ref, test, options, scratch);
}

IvPsnrResult ivPsnr(const Frame& ref, const Frame& test, const IvPsnrOptions& options, IvPsnrScratch& scratch) {
  VS_CHECK_MSG(ref.format == test.format, "IV-PSNR of frames of different formats");
  VS_CHECK_MSG(validateIvPsnrOptions(options).empty(), "IV-PSNR options out of range");
  const FrameFormat& format = ref.format;
  const int planes = planeCount(format.chroma);
  const bool repeat = format.chroma == ChromaFormat::Yuv420;
  const int maxValue = format.maxValue();
  const int threads = metricThreads(options.threads);
  const int range = options.searchRange;
  IvPsnrResult result;
  result.hasChroma = planes == 3;

  // Both pictures at luma resolution with margins, in the caller's scratch (kept between frames).
  PaddedPlane (&padded)[2][3] = scratch.pictures().padded;
  for (int p = 0; p < planes; ++p)
    for (int i = 0; i < 2; ++i) padded[i][p].resize(format.width, format.height, range);
  parallelRows(format.height + 2 * range, threads, [&](int r0, int r1) {
    for (int p = 0; p < planes; ++p) {
      padded[0][p].buildRows(ref.planes[p], p > 0 && repeat, r0 - range, r1 - range);
      padded[1][p].buildRows(test.planes[p], p > 0 && repeat, r0 - range, r1 - range);
    }
  });

  // Global colour offset: the mean test - reference difference per plane at luma resolution,
  // rounded half to even (the reference software's SSE conversion), clipped to the unnoticeable
  // limit computed in float as there.
  const double area = double(format.width) * double(format.height);
  int largestLimit = 0;
  for (int p = 0; p < planes; ++p) {
    int64_t sum = 0;
    for (int y = 0; y < format.height; ++y) {
      const uint16_t* a = padded[0][p].at(0, y);
      const uint16_t* b = padded[1][p].at(0, y);
      int64_t row = 0;
      for (int x = 0; x < format.width; ++x) row += int64_t(b[x]) - int64_t(a[x]);
      sum += row;
    }
    const int limit = int(std::nearbyint(float(options.unnoticeable[p]) * float(maxValue)));
    const int mean = int(std::nearbyint(double(sum) / area));
    result.colourOffset[p] = std::clamp(mean, -limit, limit);
    largestLimit = std::max(largestLimit, limit);
  }
  const int offsetRefToTest[3] = {result.colourOffset[0], result.colourOffset[1], result.colourOffset[2]};
  const int offsetTestToRef[3] = {-result.colourOffset[0], -result.colourOffset[1], -result.colourOffset[2]};

  // The largest weighted error decides whether int32 sums are exact.
  const double largestDiff = double(maxValue) + double(largestLimit);
  double largestError = 0;
  for (int p = 0; p < planes; ++p) largestError += double(options.searchWeights[p]) * largestDiff * largestDiff;
  const bool narrow = largestError < double(std::numeric_limits<int32_t>::max());

  uint64_t ssd[2][3];
  auto run = [&](const PaddedPlane* from, const PaddedPlane* to, const int* offset, uint64_t* out) {
    if (planes == 3) {
      if (narrow) matchPictureWeights<int32_t, 3>(from, to, offset, options, threads, out);
      else matchPictureWeights<int64_t, 3>(from, to, offset, options, threads, out);
    } else {
      if (narrow) matchPictureWeights<int32_t, 1>(from, to, offset, options, threads, out);
      else matchPictureWeights<int64_t, 1>(from, to, offset, options, threads, out);
    }
  };
  run(padded[0], padded[1], offsetRefToTest, ssd[0]);
  run(padded[1], padded[0], offsetTestToRef, ssd[1]);

  // A direction matched exactly in every plane scores +inf. Otherwise an exactly matched plane counts
  // as an SSD of 1, as in the reference software, so that an exact chroma plane does not turn a luma
  // error into +inf.
  const double ceiling = psnrFromSsd(1.0, area, format.bitDepth);
  for (int d = 0; d < 2; ++d) {
    bool exact = true;
    double capped[3] = {0, 0, 0};
    for (int p = 0; p < planes; ++p) {
      result.planePsnr[d][p] = psnrFromSsd(double(ssd[d][p]), area, format.bitDepth);
      exact = exact && (ssd[d][p] == 0 || options.averageWeights[p] == 0);
      capped[p] = ssd[d][p] == 0 ? ceiling : result.planePsnr[d][p];
    }
    result.direction[d] = exact ? std::numeric_limits<double>::infinity()
                                : weightedPlanes(capped, result.hasChroma, options.averageWeights);
  }
  result.ivpsnr = std::min(result.direction[0], result.direction[1]);
  return result;
}

FrameQuality wsPsnr(const Frame& ref, const Frame& test, double latitudeRangeDeg, const int averageWeights[3]) {
  VS_CHECK_MSG(ref.format == test.format, "WS-PSNR of frames of different formats");
  VS_CHECK(latitudeRangeDeg > 0 && latitudeRangeDeg <= 180);
  const int width = ref.format.width, height = ref.format.height;
  // Row h's centre lies at latitude (h + 0.5 - H/2) * pi / E, E = 180 H / latitudeRange rows for the
  // whole sphere; the error is normalised by H / (sum of the weights) so that equal row errors give
  // plain PSNR.
  const double sphereRows = 180.0 * double(height) / latitudeRangeDeg;
  std::vector<double> weight(static_cast<size_t>(height));
  double weightSum = 0;
  for (int h = 0; h < height; ++h) {
    weight[size_t(h)] = std::cos((double(h) + 0.5 - double(height) / 2.0) * kPi / sphereRows);
    weightSum += weight[size_t(h)];
  }
  FrameQuality result;
  result.hasChroma = ref.format.chroma != ChromaFormat::Yuv400;
  const bool repeat = ref.format.chroma == ChromaFormat::Yuv420;
  const double area = double(width) * double(height);
  for (int p = 0; p < planeCount(ref.format.chroma); ++p) {
    // The planes as stored; a 4:2:0 chroma row stands for luma rows 2k and 2k+1 (those inside the
    // picture), each of its samples for two luma columns (one for the last at an odd width).
    const Plane& a = ref.planes[p];
    const Plane& b = test.planes[p];
    const bool halfSize = p > 0 && repeat;
    double error = 0;
    for (int y = 0; y < a.height; ++y) {
      const uint16_t* pa = a.row(y);
      const uint16_t* pb = b.row(y);
      uint64_t rowSsd = 0;
      for (int x = 0; x < a.width; ++x) {
        const int64_t d = int64_t(pa[x]) - int64_t(pb[x]);
        rowSsd += uint64_t(d * d);
      }
      if (!halfSize) {
        error += double(rowSsd) * weight[size_t(y)];
        continue;
      }
      if (width % 2 == 1) {
        const int64_t d = int64_t(pa[a.width - 1]) - int64_t(pb[a.width - 1]);
        rowSsd = 2 * rowSsd - uint64_t(d * d);
      } else {
        rowSsd *= 2;
      }
      double rowWeight = weight[size_t(2 * y)];
      if (2 * y + 1 < height) rowWeight += weight[size_t(2 * y + 1)];
      error += double(rowSsd) * rowWeight;
    }
    error *= double(height) / weightSum;
    result.plane[p] = psnrFromSsd(error, area, ref.format.bitDepth);
  }
  result.yuv = weightedPlanes(result.plane, result.hasChroma, averageWeights);
  return result;
}

}  // namespace vs
