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

// A plane with a replicated margin of `margin` samples on every side, as int32 for the search.
struct PaddedPlane {
  int width = 0, height = 0, margin = 0, stride = 0;
  std::vector<uint16_t> samples;
  void build(const Plane& plane, int m) {
    width = plane.width;
    height = plane.height;
    margin = m;
    stride = width + 2 * m;
    samples.resize(size_t(stride) * size_t(height + 2 * m));
    for (int y = -m; y < height + m; ++y) {
      const uint16_t* src = plane.row(std::clamp(y, 0, height - 1));
      uint16_t* dst = samples.data() + size_t(y + m) * size_t(stride);
      for (int x = 0; x < m; ++x) dst[x] = src[0];
      std::copy(src, src + width, dst + m);
      for (int x = 0; x < m; ++x) dst[m + width + x] = src[width - 1];
    }
  }
  // Sample (x, y) of the plane, -margin <= x < width + margin (and y likewise).
  const uint16_t* at(int x, int y) const {
    return samples.data() + size_t(y + margin) * size_t(stride) + size_t(x + margin);
  }
};

// One row of one direction: every sample of `from` (plus `offset`) matched with the candidate of `to`
// within the window whose weighted squared difference is smallest (the first in raster order on a
// tie); adds the squared differences of that candidate, per plane, to ssd[]. Err is the type of the
// weighted sum: int32_t where it cannot overflow (the reference software's), else int64_t.
template <class Err, int Planes>
void matchRow(const Frame& from, const PaddedPlane* to, int y, const int offset[3], int range, const int weights[3],
              uint64_t ssd[3]) {
  constexpr int kChunk = 256;
  const int width = from.format.width;
  Err value[Planes][kChunk];
  Err best[kChunk];
  Err bestSq[Planes][kChunk];
  const Err w0 = Err(weights[0]);
  const Err w1 = Planes == 3 ? Err(weights[1]) : 0;
  const Err w2 = Planes == 3 ? Err(weights[2]) : 0;
  for (int x0 = 0; x0 < width; x0 += kChunk) {
    const int n = std::min(kChunk, width - x0);
    for (int p = 0; p < Planes; ++p) {
      const uint16_t* src = from.planes[p].row(y) + x0;
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
            const Err error = w0 * s0 + w1 * s1 + w2 * s2;
            const bool better = error < best[i];
            best[i] = better ? error : best[i];
            bestSq[0][i] = better ? s0 : bestSq[0][i];
            bestSq[1][i] = better ? s1 : bestSq[1][i];
            bestSq[2][i] = better ? s2 : bestSq[2][i];
          }
        } else {
          for (int i = 0; i < n; ++i) {
            const Err d0 = value[0][i] - Err(c0[i]);
            const Err s0 = d0 * d0;
            const Err error = w0 * s0;
            const bool better = error < best[i];
            best[i] = better ? error : best[i];
            bestSq[0][i] = better ? s0 : bestSq[0][i];
          }
        }
      }
    }
    for (int p = 0; p < Planes; ++p) {
      uint64_t sum = 0;
      for (int i = 0; i < n; ++i) sum += uint64_t(bestSq[p][i]);
      ssd[p] += sum;
    }
  }
}

// Per-plane sums of squared differences of one direction, rows summed in order.
template <class Err, int Planes>
void matchPicture(const Frame& from, const PaddedPlane* to, const int offset[3], const IvPsnrOptions& options,
                  uint64_t total[3]) {
  const int height = from.format.height;
  std::vector<uint64_t> rowSsd(size_t(height) * 3, 0);
  parallelRows(height, metricThreads(options.threads), [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      matchRow<Err, Planes>(from, to, y, offset, options.searchRange, options.searchWeights, &rowSsd[size_t(y) * 3]);
  });
  for (int p = 0; p < 3; ++p) total[p] = 0;
  for (int y = 0; y < height; ++y)
    for (int p = 0; p < 3; ++p) total[p] += rowSsd[size_t(y) * 3 + size_t(p)];
}

}  // namespace

Frame toLumaResolution(const Frame& frame) {
  if (frame.format.chroma != ChromaFormat::Yuv420) return frame;
  FrameFormat format = frame.format;
  format.chroma = ChromaFormat::Yuv444;
  Frame full(format);
  full.planes[0] = frame.planes[0];
  for (int p = 1; p < 3; ++p) {
    const Plane& half = frame.planes[p];
    Plane& out = full.planes[p];
    for (int y = 0; y < format.height; ++y) {
      const uint16_t* src = half.row(y / 2);
      uint16_t* dst = out.row(y);
      for (int x = 0; x < format.width; ++x) dst[x] = src[x / 2];
    }
  }
  return full;
}

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

IvPsnrResult ivPsnr(const Frame& refIn, const Frame& testIn, const IvPsnrOptions& options) {
  VS_CHECK_MSG(refIn.format == testIn.format, "IV-PSNR of frames of different formats");
  VS_CHECK_MSG(validateIvPsnrOptions(options).empty(), "IV-PSNR options out of range");
  const Frame ref = toLumaResolution(refIn);
  const Frame test = toLumaResolution(testIn);
  const FrameFormat& format = ref.format;
  const int planes = planeCount(format.chroma);
  const int maxValue = format.maxValue();
  IvPsnrResult result;
  result.hasChroma = planes == 3;

  // Global colour offset: the mean test - reference difference per plane, rounded half to even (the
  // reference software's SSE conversion), clipped to the unnoticeable limit computed in float as there.
  const double area = double(format.width) * double(format.height);
  int maxOffsetSum = 0;
  for (int p = 0; p < planes; ++p) {
    int64_t sum = 0;
    const std::vector<uint16_t>& a = ref.planes[p].samples;
    const std::vector<uint16_t>& b = test.planes[p].samples;
    for (size_t i = 0; i < a.size(); ++i) sum += int64_t(b[i]) - int64_t(a[i]);
    const int limit = int(std::nearbyint(float(options.unnoticeable[p]) * float(maxValue)));
    const int mean = int(std::nearbyint(double(sum) / area));
    result.colourOffset[p] = std::clamp(mean, -limit, limit);
    maxOffsetSum = std::max(maxOffsetSum, limit);
  }

  const int range = options.searchRange;
  PaddedPlane paddedRef[3], paddedTest[3];
  for (int p = 0; p < planes; ++p) {
    paddedRef[p].build(ref.planes[p], range);
    paddedTest[p].build(test.planes[p], range);
  }
  const int offsetRefToTest[3] = {result.colourOffset[0], result.colourOffset[1], result.colourOffset[2]};
  const int offsetTestToRef[3] = {-result.colourOffset[0], -result.colourOffset[1], -result.colourOffset[2]};

  // The largest weighted error decides whether int32 sums are exact.
  const double largestDiff = double(maxValue) + double(maxOffsetSum);
  double largestError = 0;
  for (int p = 0; p < planes; ++p) largestError += double(options.searchWeights[p]) * largestDiff * largestDiff;
  const bool narrow = largestError < double(std::numeric_limits<int32_t>::max());

  uint64_t ssd[2][3];
  auto run = [&](const Frame& from, const PaddedPlane* to, const int* offset, uint64_t* out) {
    if (planes == 3) {
      if (narrow) matchPicture<int32_t, 3>(from, to, offset, options, out);
      else matchPicture<int64_t, 3>(from, to, offset, options, out);
    } else {
      if (narrow) matchPicture<int32_t, 1>(from, to, offset, options, out);
      else matchPicture<int64_t, 1>(from, to, offset, options, out);
    }
  };
  run(ref, paddedTest, offsetRefToTest, ssd[0]);
  run(test, paddedRef, offsetTestToRef, ssd[1]);

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

FrameQuality wsPsnr(const Frame& refIn, const Frame& testIn, double latitudeRangeDeg, const int averageWeights[3]) {
  VS_CHECK_MSG(refIn.format == testIn.format, "WS-PSNR of frames of different formats");
  VS_CHECK(latitudeRangeDeg > 0 && latitudeRangeDeg <= 180);
  const Frame ref = toLumaResolution(refIn);
  const Frame test = toLumaResolution(testIn);
  const int width = ref.format.width, height = ref.format.height;
  // Row h's centre lies at latitude (h + 0.5 - H/2) * pi / E, E = 180 H / latitudeRange rows for the
  // whole sphere; the weights are normalised to sum to H so that equal errors give plain PSNR.
  const double sphereRows = 180.0 * double(height) / latitudeRangeDeg;
  std::vector<double> weight(static_cast<size_t>(height));
  double weightSum = 0;
  for (int h = 0; h < height; ++h) {
    weight[size_t(h)] = std::cos((double(h) + 0.5 - double(height) / 2.0) * kPi / sphereRows);
    weightSum += weight[size_t(h)];
  }
  FrameQuality result;
  result.hasChroma = ref.format.chroma != ChromaFormat::Yuv400;
  const double area = double(width) * double(height);
  for (int p = 0; p < planeCount(ref.format.chroma); ++p) {
    double error = 0;
    for (int y = 0; y < height; ++y) {
      const uint16_t* a = ref.planes[p].row(y);
      const uint16_t* b = test.planes[p].row(y);
      uint64_t rowSsd = 0;
      for (int x = 0; x < width; ++x) {
        const int64_t d = int64_t(a[x]) - int64_t(b[x]);
        rowSsd += uint64_t(d * d);
      }
      error += double(rowSsd) * weight[size_t(y)];
    }
    error *= double(height) / weightSum;
    result.plane[p] = psnrFromSsd(error, area, ref.format.bitDepth);
  }
  result.yuv = weightedPlanes(result.plane, result.hasChroma, averageWeights);
  return result;
}

}  // namespace vs
