// fillHoles with IvsrsInpaint 1 against a plain reference: the three estimates and the mix written
// as HoleFill.h describes them, one sample at a time over the whole picture, and the inpainting of
// the whole picture (of the holes, or of the holes and the nearer surface beside them): OpenCV's,
// or luma's (inpaintLikeOpenCv off) the plain one of TeleaReference.h. fillHoles skips samples without
// holes eight at a time, reads through local pointers, runs rows in parallel and inpaints group by
// group in crops; none of that may change a bit of its output (with luma's inpainting, up to the
// order of its float sums).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/photo.hpp>

#include "Synth/HoleFill.h"
#include "Synth/Parallel.h"
#include "Synth/Layer.h"
#include "TeleaReference.h"

namespace vs {
namespace {

BlendedLayer referenceFill(const BlendedLayer& in, const HoleFillOptions& o) {
  const int w = in.width, h = in.height, channels = in.channels;
  const size_t n = in.hole.size();
  const std::vector<uint8_t>& hole = in.hole;
  const std::vector<double>& depth = in.inverseDepth;
  std::vector<float> directional[3], runs[3], inpainted[3];
  std::vector<double> background(n, HUGE_VAL), runBackground(n, HUGE_VAL);
  std::vector<uint8_t> found(n, 0), runFound(n, 0);
  for (int k = 0; k < channels; ++k) {
    directional[k].assign(n, 0.0f);
    runs[k].assign(n, 0.0f);
  }
  // Directional: the nearest valid sample in each of eight directions, those on the farthest
  // surface mixed by inverse distance.
  static const int directions[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!hole[i]) continue;
      size_t hit[8];
      double distance[8];
      int count = 0;
      double farthest = HUGE_VAL;
      for (const auto& d : directions)
        for (int step = 1; step <= o.maxReach; ++step) {
          const int px = x + step * d[0], py = y + step * d[1];
          if (px < 0 || py < 0 || px >= w || py >= h) break;
          const size_t k = size_t(py) * w + px;
          if (hole[k]) continue;
          hit[count] = k;
          distance[count] = step * ((d[0] && d[1]) ? std::sqrt(2.0) : 1.0);
          farthest = std::min(farthest, depth[k]);
          ++count;
          break;
        }
      if (count == 0) continue;
      double weightSum = 0, sum[3] = {0, 0, 0};
      for (int c = 0; c < count; ++c) {
        if (depth[hit[c]] > farthest + o.depthTolerance) continue;
        const double weight = 1.0 / distance[c];
        weightSum += weight;
        for (int k = 0; k < channels; ++k) sum[k] += weight * in.colour[k][hit[c]];
      }
      for (int k = 0; k < channels; ++k) directional[k][i] = float(sum[k] / weightSum);
      background[i] = farthest;
      found[i] = 1;
    }
  // Row runs: one colour per run, from its ends and seven rays up and down from its middle.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w;) {
      if (!hole[size_t(y) * w + x]) {
        ++x;
        continue;
      }
      const int left = x - 1;
      int right = x;
      while (right < w && hole[size_t(y) * w + right]) ++right;
      std::vector<size_t> candidate;
      double farthest = HUGE_VAL;
      auto consider = [&](int cx, int cy) {
        const size_t k = size_t(cy) * w + cx;
        if (hole[k]) return false;
        candidate.push_back(k);
        farthest = std::min(farthest, depth[k]);
        return true;
      };
      if (left >= 0) consider(left, y);
      if (right < w) consider(right, y);
      const int middle = std::clamp((left + right) / 2, 0, w - 1);
      for (int step : {-1, 1}) {
        bool done[7] = {false, false, false, false, false, false, false};
        for (int v = 1, remaining = 7; remaining > 0; ++v) {
          const int cy = y + step * v;
          if (cy < 0 || cy >= h) break;
          const int across[7] = {-2 * v, -v, -(v / 2), 0, v / 2, v, 2 * v};
          for (int ray = 0; ray < 7; ++ray) {
            if (done[ray]) continue;
            const int cx = middle + across[ray];
            if (cx < 0 || cx >= w || consider(cx, cy)) {
              done[ray] = true;
              --remaining;
            }
          }
        }
      }
      double sum[3] = {0, 0, 0};
      int onFarthest = 0;
      for (const size_t c : candidate) {
        if (depth[c] > farthest + o.depthTolerance) continue;
        for (int k = 0; k < channels; ++k) sum[k] += in.colour[k][c];
        ++onFarthest;
      }
      for (int i = left + 1; i < right; ++i) {
        const size_t k = size_t(y) * w + i;
        for (int c = 0; c < channels; ++c) runs[c][k] = candidate.empty() ? 0.0f : float(sum[c] / onFarthest);
        runBackground[k] = farthest;
        runFound[k] = !candidate.empty();
      }
      x = right;
    }
  // The inpainting mask: the holes and, with inpaintNearerSurface, the nearer valid samples within
  // radius + 1 of a hole with a directional background.
  std::vector<uint8_t> mask = hole;
  const int band = o.inpaintNearerSurface ? o.inpaintRadius + 1 : 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!hole[i] || background[i] == HUGE_VAL) continue;
      for (int dy = -band; dy <= band; ++dy)
        for (int dx = -band; dx <= band; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const size_t k = size_t(ny) * w + nx;
          if (!hole[k] && depth[k] > background[i] + o.depthTolerance) mask[k] = 1;
        }
    }
  // OpenCV's, or luma's, a plain implementation of it (TeleaReference.h).
  cv::Mat maskMat(h, w, CV_8UC1, mask.data());
  for (int k = 0; k < channels; ++k) {
    if (!o.inpaintLikeOpenCv) {
      inpainted[k] = reference::plainTeleaMean(mask, w, h, in.colour[k], o.inpaintRadius);
      continue;
    }
    cv::Mat channel(h, w, CV_32FC1, const_cast<float*>(in.colour[k].data())), result;
    cv::inpaint(channel, maskMat, result, o.inpaintRadius, cv::INPAINT_TELEA);
    inpainted[k].assign(result.ptr<float>(), result.ptr<float>() + n);
  }
  // The mix, over the estimates that found something.
  BlendedLayer out = in;
  for (size_t i = 0; i < n; ++i) {
    if (!hole[i]) continue;
    const float d = found[i] ? o.directionalWeight : 0.0f, r = runFound[i] ? o.rowRunWeight : 0.0f;
    const float sum = d + r + o.inpaintWeight;
    for (int k = 0; k < channels; ++k)
      out.colour[k][i] = sum > 0 ? (d * directional[k][i] + r * runs[k][i] + o.inpaintWeight * inpainted[k][i]) / sum
                                 : inpainted[k][i];
    if (found[i]) out.inverseDepth[i] = background[i];
    else if (runFound[i]) out.inverseDepth[i] = runBackground[i];
  }
  std::fill(out.hole.begin(), out.hole.end(), uint8_t(0));
  return out;
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Random layers: widths that are not multiples of eight, surfaces at several depths, holes as the
// 1D path leaves them (strips), dots, blobs too large for a short reach, and holes on the border.
TEST(HoleFill, BackgroundFirstFillingEqualsAPlainReference) {
  std::mt19937 random(2027);
  auto at = [&](int n) { return int(random() % unsigned(n)); };
  std::uniform_real_distribution<float> colour(0.0f, 255.0f);
  const int threadsBefore = vs::workerThreads();
  HoleFillScratch kept;  // one caller's buffers over every trial, as a sequence keeps them
  for (int trial = 0; trial < 60; ++trial) {
    const int w = 9 + at(70), h = 5 + at(50), channels = 1 + trial % 3;
    BlendedLayer layer;
    layer.reset(w, h, channels);
    const int patch = 3 + at(8);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const int surface = (x / patch + y / (patch + 1)) % 3;  // three surfaces in patches
        layer.hole[i] = 0;
        layer.inverseDepth[i] = 0.01 + 0.005 * surface + (at(4) == 0 ? 0.0004 : 0.0);
        for (int k = 0; k < channels; ++k) layer.colour[k][i] = colour(random) * 0.3f + 60.0f * float(surface);
      }
    auto hole = [&](int x, int y) {
      if (x >= 0 && y >= 0 && x < w && y < h) layer.hole[size_t(y) * w + x] = 1;
    };
    for (int k = 0, shapes = 1 + at(8); k < shapes; ++k) {
      const int x = at(w + 4) - 2, y = at(h + 4) - 2;
      switch (at(4)) {
        case 0:  // a strip, the whole height
          for (int yy = 0; yy < h; ++yy)
            for (int t = 0, width = 1 + at(9); t < width; ++t) hole(x + t, yy);
          break;
        case 1:  // dots
          for (int t = 0; t < 20; ++t) hole(at(w), at(h));
          break;
        case 2:  // a blob
          for (int dy = 0, s = 2 + at(14); dy < s; ++dy)
            for (int dx = 0; dx < s; ++dx) hole(x + dx, y + dy);
          break;
        default:  // a run along a row
          for (int t = 0, length = 1 + at(w); t < length; ++t) hole(x + t, y);
          break;
      }
    }
    for (size_t i = 0; i < layer.hole.size(); ++i)
      if (layer.hole[i]) layer.inverseDepth[i] = kNoDepth;
    if (layer.holeCount() == 0 || layer.holeCount() == layer.hole.size()) continue;
    HoleFillOptions options;
    options.depthTolerance = trial % 4 == 0 ? 0.0 : 0.001;
    options.inpaintRadius = 1 + at(5);
    options.maxReach = trial % 3 == 0 ? 3 + at(6) : 256;
    options.inpaintNearerSurface = trial % 2 == 1;
    options.inpaintLikeOpenCv = trial % 4 >= 2;
    const BlendedLayer expected = referenceFill(layer, options);
    for (int threads : {1, 2}) {
      vs::setWorkerThreads(threads);
      BlendedLayer filled = layer;
      fillHoles(filled, options, threads == 2 ? &kept : nullptr);
      // With OpenCV's inpainting bit for bit; with the plain mean up to the order of its float sums.
      for (int k = 0; k < channels; ++k) {
        if (options.inpaintLikeOpenCv) {
          ASSERT_TRUE(sameBits(filled.colour[k], expected.colour[k]))
              << "trial " << trial << " channel " << k << " " << w << "x" << h << " " << threads << " threads";
        } else {
          for (size_t i = 0; i < filled.colour[k].size(); ++i)
            ASSERT_NEAR(filled.colour[k][i], expected.colour[k][i], 1e-4f * (1.0f + std::fabs(expected.colour[k][i])))
                << "trial " << trial << " channel " << k << " sample " << i << " " << threads << " threads";
        }
      }
      ASSERT_TRUE(sameBits(filled.inverseDepth, expected.inverseDepth)) << "trial " << trial;
      ASSERT_EQ(filled.holeCount(), 0u);
    }
  }
  vs::setWorkerThreads(threadsBefore);
}

// The estimates' places (HoleFillScratch::HolePlaces): the holes before a sample, counted here one by
// one, at every column of every row (and one past the last), for widths around the 64-sample blocks
// and holes from none to all; and a layer of another size indexed with the same places after.
TEST(HoleFill, HolePlacesCountTheHolesBefore) {
  std::mt19937 random(31);
  HoleFillScratch::HolePlaces places;
  for (const int w : {1, 5, 63, 64, 65, 128, 130, 200})
    for (const int percent : {0, 3, 40, 100}) {
      const int h = 1 + int(random() % 9u);
      std::vector<uint8_t> hole(size_t(w) * size_t(h));
      for (uint8_t& flag : hole) flag = int(random() % 100u) < percent ? 1 : 0;
      places.index(hole, w, h);
      size_t before = 0;
      for (int y = 0; y < h; ++y) {
        EXPECT_EQ(places.rowStart(y), before) << w << " " << percent << " % row " << y;
        for (int x = 0; x <= w; ++x) {
          ASSERT_EQ(places.at(hole.data(), x, y), before) << w << " " << percent << " % at " << x << ", " << y;
          if (x < w) before += hole[size_t(y) * size_t(w) + size_t(x)];
        }
      }
      EXPECT_EQ(places.count, before);
    }
}

}  // namespace
}  // namespace vs
