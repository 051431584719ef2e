#include "Synth/HoleFill.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <vector>

#include "Common/Error.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

// An estimate's buffers for `layer`, sized but not cleared: the estimates write every hole sample
// (colour 0, background HUGE_VAL and found 0 where they find nothing), and nothing reads them
// elsewhere.
void sizeEstimate(const BlendedLayer& layer, std::vector<float> estimate[3], std::vector<double>& background,
                  std::vector<uint8_t>& found) {
  const size_t n = layer.hole.size();
  for (int k = 0; k < layer.channels; ++k) estimate[k].resize(n);
  background.resize(n);
  found.resize(n);
}

// Directional background estimate for every hole sample; `found` is 0 where no direction reached a
// valid sample. `background` receives the farthest inverse depth found.
void directionalFill(const BlendedLayer& layer, const HoleFillOptions& options, std::vector<float> estimate[3],
                     std::vector<double>& background, std::vector<uint8_t>& found) {
  static const int directions[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  const int w = layer.width, h = layer.height;
  sizeEstimate(layer, estimate, background, found);
  // Each hole sample writes only its own estimate: rows in parallel.
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
  for (int y = rowBegin; y < rowEnd; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!layer.hole[i]) continue;
      size_t hit[8];
      double distance[8];
      int count = 0;
      double farthest = HUGE_VAL;
      for (const auto& d : directions) {
        int px = x, py = y;
        for (int step = 1; step <= options.maxReach; ++step) {
          px += d[0];
          py += d[1];
          if (px < 0 || py < 0 || px >= w || py >= h) break;
          const size_t k = size_t(py) * w + px;
          if (layer.hole[k]) continue;
          hit[count] = k;
          distance[count] = step * ((d[0] && d[1]) ? std::sqrt(2.0) : 1.0);
          farthest = std::min(farthest, layer.inverseDepth[k]);
          ++count;
          break;
        }
      }
      if (count == 0) {
        for (int k = 0; k < layer.channels; ++k) estimate[k][i] = 0.0f;
        background[i] = HUGE_VAL;
        found[i] = 0;
        continue;
      }
      double weightSum = 0;
      double sum[3] = {0, 0, 0};
      for (int c = 0; c < count; ++c) {
        if (layer.inverseDepth[hit[c]] > farthest + options.depthTolerance) continue;
        const double weight = 1.0 / distance[c];
        weightSum += weight;
        for (int k = 0; k < layer.channels; ++k) sum[k] += weight * layer.colour[k][hit[c]];
      }
      for (int k = 0; k < layer.channels; ++k) estimate[k][i] = float(sum[k] / weightSum);
      background[i] = farthest;
      found[i] = 1;
    }
  });
}

// Row-run background estimate (after iVSRS's hole filling in VSRS 4.x): each run of hole samples
// along a row takes one colour, the mean of the candidates on the farthest surface among its two
// ends and the first valid samples met along seven rays up and seven down from its middle (slopes
// -2, -1, -1/2, 0, 1/2, 1, 2 samples across per row). One colour per run cannot streak, and the
// candidates above and below reach background that the row's ends, often foreground on both sides,
// do not. `background` receives that surface's inverse depth; `found` is 0 where no candidate exists.
void rowRunFill(const BlendedLayer& layer, const HoleFillOptions& options, std::vector<float> estimate[3],
                std::vector<double>& background, std::vector<uint8_t>& found) {
  const int w = layer.width, h = layer.height;
  sizeEstimate(layer, estimate, background, found);
  // Each run is one row's: rows in parallel.
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      const uint8_t* holes = layer.hole.data() + size_t(y) * w;
      for (int x = 0; x < w;) {
        if (!holes[x]) {
          ++x;
          continue;
        }
        const int left = x - 1;  // the run is (left, right), ends excluded
        int right = x;
        while (right < w && holes[right]) ++right;
        size_t candidate[16];
        int count = 0;
        double farthest = HUGE_VAL;
        auto consider = [&](int cx, int cy) {
          const size_t k = size_t(cy) * w + cx;
          if (layer.hole[k]) return false;
          candidate[count++] = k;
          farthest = std::min(farthest, layer.inverseDepth[k]);
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
        for (int c = 0; c < count; ++c) {
          if (layer.inverseDepth[candidate[c]] > farthest + options.depthTolerance) continue;
          for (int k = 0; k < layer.channels; ++k) sum[k] += layer.colour[k][candidate[c]];
          ++onFarthest;
        }
        for (int i = left + 1; i < right; ++i) {  // no candidate: colour 0, background HUGE_VAL, not found
          const size_t k = size_t(y) * w + i;
          for (int c = 0; c < layer.channels; ++c) estimate[c][k] = count > 0 ? float(sum[c] / onFarthest) : 0.0f;
          background[k] = farthest;
          found[k] = count > 0;
        }
        x = right;
      }
    }
  });
}

// The inpainting mask: the holes, plus valid samples of a nearer surface than the hole's background
// within `band` samples of it, so that inpainting continues the background and not the occluder.
void backgroundOnlyMask(const BlendedLayer& layer, const std::vector<double>& background, double tolerance, int band,
                        std::vector<uint8_t>& mask) {
  const int w = layer.width, h = layer.height;
  mask = layer.hole;
  // Holes of a block of rows mark samples up to `band` rows outside it. Blocks of at least 2 band + 1
  // rows, even ones first and then odd ones, in parallel: two blocks marked at once are then far
  // enough apart that they never write the same row.
  const int blockRows = std::max(32, 2 * band + 1), blocks = (h + blockRows - 1) / blockRows;
  for (int parity = 0; parity < 2; ++parity)
    parallelRanges((blocks + 1 - parity) / 2, [&](int first, int last) {
      for (int b = first; b < last; ++b) {
        const int block = 2 * b + parity;
        for (int y = block * blockRows; y < std::min(h, (block + 1) * blockRows); ++y)
          for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            if (!layer.hole[i] || background[i] == HUGE_VAL) continue;
            for (int dy = -band; dy <= band; ++dy)
              for (int dx = -band; dx <= band; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const size_t k = size_t(ny) * w + nx;
                if (!layer.hole[k] && layer.inverseDepth[k] > background[i] + tolerance) mask[k] = 1;
              }
          }
      }
    });
}

// Telea's inpainting of a mask sample reads colours within `radius` of it and arrival times one
// sample further, and its queue keeps equal arrival times in insertion (raster) order, which a crop
// keeps. So groups of mask samples farther apart than twice that reach can be inpainted apart, each
// in a crop around it with the other groups' samples left out of the mask: the result is exactly the
// whole-picture one, at a cost that follows each group's size instead of all the holes' (OpenCV's
// queue is a sorted list whose inserts walk it: over the whole picture the cost grows with the square
// of the number of hole samples).
void inpaint(BlendedLayer& layer, std::vector<uint8_t>& mask, int radius, std::vector<float> result[3],
             HoleFillScratch& scratch) {
  const cv::Mat maskMat(layer.height, layer.width, CV_8UC1, mask.data());
  const int reach = radius + 2;
  cv::Mat& grown = scratch.grown;
  cv::Mat& groups = scratch.groups;
  cv::Mat stats, centroids;
  cv::dilate(maskMat, grown, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * reach + 1, 2 * reach + 1)));
  const int groupCount = cv::connectedComponentsWithStats(grown, groups, stats, centroids, 8, CV_32S);
  // Every mask sample is in one group and is written below; nothing reads the others.
  for (int k = 0; k < layer.channels; ++k) result[k].resize(layer.colour[k].size());
  // Label 0 is what lies farther than `reach` from every mask sample. One task per group and
  // channel, the largest crops first, so that two threads share the work evenly (the channels of a
  // group write different planes; each group its own samples).
  using Task = HoleFillScratch::InpaintTask;
  std::vector<Task>& tasks = scratch.tasks;
  tasks.clear();
  for (int g = 1; g < groupCount; ++g) {
    const cv::Rect crop(stats.at<int>(g, cv::CC_STAT_LEFT), stats.at<int>(g, cv::CC_STAT_TOP),
                        stats.at<int>(g, cv::CC_STAT_WIDTH), stats.at<int>(g, cv::CC_STAT_HEIGHT));
    for (int k = 0; k < layer.channels; ++k) tasks.push_back({g, k, crop});
  }
  std::stable_sort(tasks.begin(), tasks.end(), [](const Task& a, const Task& b) { return a.crop.area() > b.crop.area(); });
  parallelRanges(int(tasks.size()), [&](int begin, int end) {
    cv::Mat groupMask, inpainted;
    for (int t = begin; t < end; ++t) {
      const Task& task = tasks[size_t(t)];
      // The group's mask samples: in the crop, those of other groups are more than 2 reach away.
      cv::compare(groups(task.crop), task.group, groupMask, cv::CMP_EQ);
      cv::bitwise_and(groupMask, maskMat(task.crop), groupMask);
      const cv::Mat channel(layer.height, layer.width, CV_32FC1, layer.colour[task.channel].data());
      cv::inpaint(channel(task.crop), groupMask, inpainted, radius, cv::INPAINT_TELEA);
      VS_CHECK(inpainted.type() == CV_32FC1 && inpainted.size() == task.crop.size());
      cv::Mat out(layer.height, layer.width, CV_32FC1, result[task.channel].data());
      inpainted.copyTo(out(task.crop), groupMask);  // every mask sample is in one group: one writer
    }
  });
}

}  // namespace

size_t fillHoles(BlendedLayer& layer, const HoleFillOptions& options, HoleFillScratch* scratch) {
  const size_t holes = layer.holeCount();
  if (holes == 0) return 0;
  const size_t n = layer.hole.size();
  if (holes == n) {  // nothing to fill from
    for (int k = 0; k < layer.channels; ++k) std::fill(layer.colour[k].begin(), layer.colour[k].end(), options.emptyValue[k]);
    std::fill(layer.hole.begin(), layer.hole.end(), uint8_t(0));
    return holes;
  }
  HoleFillScratch local;
  HoleFillScratch& s = scratch ? *scratch : local;
  if (!options.backgroundFirst) {
    s.mask = layer.hole;
    inpaint(layer, s.mask, options.inpaintRadius, s.inpainted, s);
    for (int k = 0; k < layer.channels; ++k)
      for (size_t i = 0; i < n; ++i)
        if (layer.hole[i]) layer.colour[k][i] = s.inpainted[k][i];
  } else {
    directionalFill(layer, options, s.directional, s.background, s.found);
    rowRunFill(layer, options, s.runs, s.runBackground, s.runFound);
    backgroundOnlyMask(layer, s.background, options.depthTolerance, options.inpaintRadius + 1, s.mask);
    inpaint(layer, s.mask, options.inpaintRadius, s.inpainted, s);
    // Three estimates of the background, mixed by weight (2 : 3 : 1 by default) over those that found
    // one; their errors differ, and the mix has a lower error than any of them.
    // Every sample on its own: rows in parallel.
    parallelRanges(layer.height, [&](int y0, int y1) {
      for (size_t i = size_t(y0) * layer.width; i < size_t(y1) * layer.width; ++i) {
        if (!layer.hole[i]) continue;
        const float directional = s.found[i] ? options.directionalWeight : 0.0f;
        const float run = s.runFound[i] ? options.rowRunWeight : 0.0f, inpainted = options.inpaintWeight;
        const float sum = directional + run + inpainted;
        for (int k = 0; k < layer.channels; ++k)
          layer.colour[k][i] = sum > 0 ? (directional * s.directional[k][i] + run * s.runs[k][i] + inpainted * s.inpainted[k][i]) / sum
                                       : s.inpainted[k][i];
        if (s.found[i]) layer.inverseDepth[i] = s.background[i];
        else if (s.runFound[i]) layer.inverseDepth[i] = s.runBackground[i];
      }
    });
  }
  std::fill(layer.hole.begin(), layer.hole.end(), uint8_t(0));
  return holes;
}

}  // namespace vs
