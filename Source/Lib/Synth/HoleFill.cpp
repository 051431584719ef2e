#include "Synth/HoleFill.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "Synth/Flags.h"
#include "Synth/Parallel.h"
#include "Synth/Telea.h"

namespace vs {

void HoleFillScratch::HolePlaces::index(const std::vector<uint8_t>& hole, int w, int h) {
  width = w;
  blocksPerRow = std::max(1, (w + kBlock - 1) / kBlock);
  // Each block's holes into the entry after its own (rows in parallel), then summed in order.
  before.resize(size_t(h) * size_t(blocksPerRow) + 1);
  before[0] = 0;
  parallelRanges(h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int b = 0; b < blocksPerRow; ++b) {
        const uint8_t* p = hole.data() + size_t(y) * size_t(w) + size_t(b) * kBlock;
        const int n = std::max(0, std::min(kBlock, w - b * kBlock));
        size_t holes = 0;
        for (int x = 0; x < n; ++x) holes += p[x] != 0;
        before[size_t(y) * size_t(blocksPerRow) + size_t(b) + 1] = holes;
      }
  });
  for (size_t k = 1; k < before.size(); ++k) before[k] += before[k - 1];
  count = before.back();
}

size_t HoleFillScratch::HolePlaces::at(const uint8_t* hole, int x, int y) const {
  const int b = x / kBlock;
  size_t place = before[size_t(y) * size_t(blocksPerRow) + size_t(b)];
  const uint8_t* row = hole + size_t(y) * size_t(width);
  for (int i = b * kBlock; i < x; ++i) place += row[i] != 0;
  return place;
}

namespace {

using HolePlaces = HoleFillScratch::HolePlaces;

// An estimate's buffers for the holes (`places`), sized but not cleared: the estimates write every
// hole's (colour 0, background HUGE_VAL and found 0 where they find nothing).
void sizeEstimate(const BlendedLayer& layer, const HolePlaces& places, UntouchedBuffer<float> estimate[3],
                  UntouchedBuffer<double>& background, UntouchedBuffer<uint8_t>& found) {
  const size_t n = places.count;
  for (int k = 0; k < layer.channels; ++k) estimate[k].resize(n);
  background.resize(n);
  found.resize(n);
}

// Directional background estimate for every hole sample; `found` is 0 where no direction reached a
// valid sample. `background` receives the farthest inverse depth found.
// Along a row or a column, the samples of one run of holes share their nearest valid samples: the
// run's ends. A row's run is found once; a column's ends are kept per column while its samples come
// row after row, and only found anew where the sample above was not a hole of this range of rows.
// The diagonals, which leave a run of holes soon, are walked.
void directionalFill(const BlendedLayer& layer, const HoleFillOptions& options, const HolePlaces& places,
                     UntouchedBuffer<float> estimate[3], UntouchedBuffer<double>& background,
                     UntouchedBuffer<uint8_t>& found, ScratchPool<std::vector<int>>& columnRows) {
  static const int diagonals[4][2] = {{1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  const int w = layer.width, h = layer.height;
  sizeEstimate(layer, places, estimate, background, found);
  // Each hole sample writes only its own estimate: rows in parallel.
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
  // Per column: the last row of this range whose hole was estimated, and the nearest valid rows
  // above (-1: none) and below (h: none) it.
  const auto scratch = columnRows.take();
  std::vector<int>& columns = *scratch;
  columns.assign(size_t(w) * 3, -2);
  int* lastRow = columns.data();
  int* above = lastRow + w;
  int* below = above + w;
  // Locals: the byte stores to `found` could alias the vectors' own pointers (and anything the
  // lambda captures by reference).
  const uint8_t* hole = layer.hole.data();
  const double* depth = layer.inverseDepth.data();
  const int channels = layer.channels, maxReach = options.maxReach;
  const double tolerance = options.depthTolerance;
  const float* colour[3] = {layer.colour[0].data(), layer.colour[1].data(), layer.colour[2].data()};
  float* out[3] = {estimate[0].data(), estimate[1].data(), estimate[2].data()};
  double* far = background.data();
  uint8_t* any = found.data();
  for (int y = rowBegin; y < rowEnd; ++y) {
    // Each run of holes [runStart, runEnd) of the row, and each of its samples x, at its place p.
    size_t place = places.rowStart(y);
    forEachRun(hole + size_t(y) * w, w, [&](int runStart, int runEnd) {
    for (int x = runStart; x < runEnd; ++x) {
      const size_t i = size_t(y) * w + x, p = place++;
      if (lastRow[x] != y - 1) {
        int r = y - 1;
        while (r >= 0 && hole[size_t(r) * w + x]) --r;
        above[x] = r;
        for (r = y + 1; r < h && hole[size_t(r) * w + x];) ++r;
        below[x] = r;
      }
      lastRow[x] = y;
      size_t hit[8];
      double distance[8];
      int count = 0;
      double farthest = HUGE_VAL;
      // The first valid sample `step` samples away, if within reach; in the order (1, 0), (-1, 0),
      // (0, 1), (0, -1), then the diagonals.
      auto take = [&](int px, int py, int step, bool diagonal) {
        if (step > maxReach) return;
        const size_t k = size_t(py) * w + px;
        hit[count] = k;
        distance[count] = step * (diagonal ? std::sqrt(2.0) : 1.0);
        farthest = std::min(farthest, depth[k]);
        ++count;
      };
      if (runEnd < w) take(runEnd, y, runEnd - x, false);
      if (runStart > 0) take(runStart - 1, y, x - runStart + 1, false);
      if (below[x] < h) take(x, below[x], below[x] - y, false);
      if (above[x] >= 0) take(x, above[x], y - above[x], false);
      for (const auto& d : diagonals) {
        // The steps that stay within the picture and the reach, then no bound to test per step.
        const int steps = std::min({maxReach, d[0] > 0 ? w - 1 - x : x, d[1] > 0 ? h - 1 - y : y});
        const ptrdiff_t stride = ptrdiff_t(d[1]) * w + d[0];
        const uint8_t* p = hole + i;
        for (int step = 1; step <= steps; ++step) {
          p += stride;
          if (*p) continue;
          take(x + step * d[0], y + step * d[1], step, true);
          break;
        }
      }
      if (count == 0) {
        for (int k = 0; k < channels; ++k) out[k][p] = 0.0f;
        far[p] = HUGE_VAL;
        any[p] = 0;
        continue;
      }
      double weightSum = 0;
      double sum[3] = {0, 0, 0};
      for (int c = 0; c < count; ++c) {
        if (depth[hit[c]] > farthest + tolerance) continue;
        const double weight = 1.0 / distance[c];
        weightSum += weight;
        for (int k = 0; k < channels; ++k) sum[k] += weight * colour[k][hit[c]];
      }
      for (int k = 0; k < channels; ++k) out[k][p] = float(sum[k] / weightSum);
      far[p] = farthest;
      any[p] = 1;
    }
    });
  }
  });
}

// Row-run background estimate (after iVSRS's hole filling in VSRS 4.x): each run of hole samples
// along a row takes one colour, the mean of the candidates on the farthest surface among its two
// ends and the first valid samples met along seven rays up and seven down from its middle (slopes
// -2, -1, -1/2, 0, 1/2, 1, 2 samples across per row). One colour per run cannot streak, and the
// candidates above and below reach background that the row's ends, often foreground on both sides,
// do not. `background` receives that surface's inverse depth; `found` is 0 where no candidate exists.
void rowRunFill(const BlendedLayer& layer, const HoleFillOptions& options, const HolePlaces& places,
                UntouchedBuffer<float> estimate[3], UntouchedBuffer<double>& background,
                UntouchedBuffer<uint8_t>& found) {
  const int w = layer.width, h = layer.height;
  sizeEstimate(layer, places, estimate, background, found);
  // Each run is one row's: rows in parallel.
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      size_t place = places.rowStart(y);  // the next hole's
      forEachRun(layer.hole.data() + size_t(y) * w, w, [&](int begin, int right) {
        const int left = begin - 1;  // the run is (left, right), ends excluded
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
          const size_t k = place++;
          for (int c = 0; c < layer.channels; ++c) estimate[c][k] = count > 0 ? float(sum[c] / onFarthest) : 0.0f;
          background[k] = farthest;
          found[k] = count > 0;
        }
      });
    }
  });
}

// The inpainting mask: the holes, plus valid samples of a nearer surface than the hole's background
// within `band` samples of it, so that inpainting continues the background and not the occluder.
// A valid sample is nearer than some hole's background + tolerance exactly when it is nearer than
// the least of them (a NaN marks nothing either way): each run of holes along a row marks, in each
// row within `band`, the samples nearer than the least threshold of its holes within `band` columns,
// one pass over its span per row instead of one window per hole.
void backgroundOnlyMask(const BlendedLayer& layer, const HolePlaces& places, const UntouchedBuffer<double>& background,
                        double tolerance, int band, std::vector<uint8_t>& mask,
                        ScratchPool<HoleFillScratch::Thresholds>& thresholdRows) {
  const int w = layer.width, h = layer.height;
  mask = layer.hole;
  // Holes of a block of rows mark samples up to `band` rows outside it. Blocks of at least 2 band + 1
  // rows, even ones first and then odd ones, in parallel: two blocks marked at once are then far
  // enough apart that they never write the same row.
  const int blockRows = std::max(32, 2 * band + 1), blocks = (h + blockRows - 1) / blockRows;
  for (int parity = 0; parity < 2; ++parity)
    parallelRanges((blocks + 1 - parity) / 2, [&](int first, int last) {
      const auto scratch = thresholdRows.take();
      std::vector<double>& runThreshold = scratch->run;
      std::vector<double>& spanThreshold = scratch->span;
      runThreshold.resize(size_t(w));
      spanThreshold.resize(size_t(w) + 2 * size_t(band));
      // Local pointers: the mask's byte stores could alias the vectors' own pointers (and anything
      // the lambda captures by reference).
      const uint8_t* hole = layer.hole.data();
      const double* depth = layer.inverseDepth.data();
      const double* far = background.data();
      uint8_t* out = mask.data();
      double* run = runThreshold.data();
      double* span = spanThreshold.data();
      for (int b = first; b < last; ++b) {
        const int block = 2 * b + parity;
        for (int y = block * blockRows; y < std::min(h, (block + 1) * blockRows); ++y) {
          size_t place = places.rowStart(y);  // the next run's first hole's
          forEachRun(hole + size_t(y) * w, w, [&](int x, int end) {
            // The run [x, end) and its holes' thresholds; HUGE_VAL (no background) marks nothing.
            const double* farRun = far + place;
            place += size_t(end - x);
            bool any = false;
            for (int i = x; i < end; ++i) {
              const bool known = farRun[i - x] != HUGE_VAL;
              run[i - x] = known ? farRun[i - x] + tolerance : HUGE_VAL;
              any |= known;
            }
            if (any) {
              // Columns x0..x1 are within `band` of the run: each takes its holes' least threshold.
              const int x0 = std::max(0, x - band), x1 = std::min(w - 1, end - 1 + band);
              for (int c = x0; c <= x1; ++c) {
                double least = HUGE_VAL;
                for (int i = std::max(x, c - band); i <= std::min(end - 1, c + band); ++i)
                  least = run[i - x] < least ? run[i - x] : least;
                span[c - x0] = least;
              }
              for (int ny = std::max(0, y - band); ny <= std::min(h - 1, y + band); ++ny) {
                const size_t row = size_t(ny) * w;
                // Without a branch: which neighbours are nearer follows the picture.
                for (int c = x0; c <= x1; ++c)
                  out[row + c] |= uint8_t(!hole[row + c] & (depth[row + c] > span[c - x0]));
              }
            }
          });
        }
      }
    });
}

// Groups the mask samples by blocks of kBlock x kBlock samples: blocks holding mask samples within
// `link` blocks of each other (Chebyshev) are in one group, so that mask samples of two groups are
// more than link * kBlock samples apart. Labels each block with its group (-1: no mask sample)
// and gives each group's extent in blocks.
constexpr int kBlock = 4;
using BlockGroups = HoleFillScratch::InpaintGroups;  // extents in blocks
void groupBlocks(const std::vector<uint8_t>& mask, int width, int height, int link, BlockGroups& groups) {
  const int bw = (width + kBlock - 1) / kBlock, bh = (height + kBlock - 1) / kBlock;
  groups.columns = bw;
  groups.rows = bh;
  std::vector<int>& label = groups.label;
  label.assign(size_t(bw) * bh, -1);
  const int kUnvisited = -2;
  parallelRanges(bh, [&](int by0, int by1) {  // each block row on its own
    for (int y = by0 * kBlock; y < std::min(height, by1 * kBlock); ++y) {
      const uint8_t* m = mask.data() + size_t(y) * width;
      int* row = label.data() + size_t(y / kBlock) * bw;
      for (int bx = 0; bx < bw; ++bx) {
        const int x0 = bx * kBlock, x1 = std::min(width, x0 + kBlock);
        if (x0 + 4 * kBlock <= width) {  // four blocks' row without a mask sample, at once
          uint64_t first, second;
          std::memcpy(&first, m + x0, sizeof first);
          std::memcpy(&second, m + x0 + 8, sizeof second);
          if ((first | second) == 0) {
            bx += 3;
            continue;
          }
        }
        bool any = false;
        if (x1 - x0 == kBlock) {  // a whole block's row: its bytes at once
          uint32_t bytes;
          static_assert(sizeof bytes == kBlock, "a block's row is four bytes");
          std::memcpy(&bytes, m + x0, sizeof bytes);
          any = bytes != 0;
        } else {
          for (int x = x0; x < x1; ++x) any |= m[x] != 0;
        }
        if (any) row[bx] = kUnvisited;
      }
    }
  });
  groups.extent.clear();
  std::vector<int>& stack = groups.stack;
  for (size_t start = 0; start < label.size(); ++start) {
    if (label[start] != kUnvisited) continue;
    const int g = int(groups.extent.size());
    int x0 = bw, y0 = bh, x1 = -1, y1 = -1;
    label[start] = g;
    stack.assign(1, int(start));
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      const int bx = b % bw, by = b / bw;
      x0 = std::min(x0, bx), x1 = std::max(x1, bx), y0 = std::min(y0, by), y1 = std::max(y1, by);
      for (int ny = std::max(0, by - link); ny <= std::min(bh - 1, by + link); ++ny)
        for (int nx = std::max(0, bx - link); nx <= std::min(bw - 1, bx + link); ++nx) {
          int& l = label[size_t(ny) * bw + nx];
          if (l != kUnvisited) continue;
          l = g;
          stack.push_back(ny * bw + nx);
        }
    }
    groups.extent.push_back({x0, y0, x1 - x0 + 1, y1 - y0 + 1});
  }
}

// Telea's inpainting of a mask sample reads colours within `radius` of it and arrival times one
// sample further, and its queue keeps equal arrival times in insertion (raster) order, which a crop
// keeps. So groups of mask samples farther apart than twice that reach can be inpainted apart, each
// in a crop reaching at least that far around it (or to the picture's edge) with the other groups'
// samples left out of the mask: the result is exactly the whole-picture one, at a cost that follows
// each group's size instead of all the holes'. Each group's channels are filled in one march
// (Synth/Telea.h: OpenCV's result channel by channel, or the cheaper weighted mean for luma).
void planInpaint(const BlendedLayer& layer, const std::vector<uint8_t>& mask, int radius, UntouchedBuffer<float> result[3],
                 HoleFillScratch& scratch) {
  const int reach = radius + 2;
  // Blocks more than `link` apart hold samples at least link * kBlock + 1 > 2 reach + 1 apart.
  const int link = (2 * reach + 1 + kBlock - 1) / kBlock;
  BlockGroups& groups = scratch.inpaintGroups;
  groupBlocks(mask, layer.width, layer.height, link, groups);
  // Every hole is a mask sample in one group and is written by its task, at its place; nothing reads
  // the mask's other samples.
  for (int k = 0; k < layer.channels; ++k) result[k].resize(scratch.places.count);
  // One task per group, its crop its blocks and `reach` samples around them.
  std::vector<HoleFillScratch::InpaintTask>& tasks = scratch.tasks;
  tasks.clear();
  for (size_t g = 0; g < groups.extent.size(); ++g) {
    const SampleBox& e = groups.extent[g];
    // The blocks and `reach` around them, within the picture.
    const int x0 = std::max(0, e.x * kBlock - reach), y0 = std::max(0, e.y * kBlock - reach);
    const int x1 = std::min(layer.width, (e.x + e.width) * kBlock + reach);
    const int y1 = std::min(layer.height, (e.y + e.height) * kBlock + reach);
    tasks.push_back({int(g), {x0, y0, x1 - x0, y1 - y0}});
  }
}

// Inpaints one group of `layer`'s mask samples in its crop, all channels in one march, into `result`.
void inpaintGroup(const BlendedLayer& layer, const std::vector<uint8_t>& mask, int radius, bool likeOpenCv,
                  const BlockGroups& groups, const HolePlaces& places,
                  const HoleFillScratch::InpaintTask& task, UntouchedBuffer<float> result[3],
                  ScratchPool<HoleFillScratch::InpaintBuffers>& buffers) {
  const auto scratch = buffers.take();
  TeleaScratch& telea = scratch->telea;
  std::vector<uint8_t>& groupMask = scratch->groupMask;
  std::vector<float>& samples = scratch->samples;
  const int channels = layer.channels;
  const size_t w = size_t(layer.width);
  const SampleBox& c = task.crop;
  const size_t cw = size_t(c.width), area = cw * size_t(c.height);
  // The group's mask samples: in the crop, those of other groups are more than 2 reach away.
  groupMask.resize(area);
  samples.resize(area * 4);
  const int group = task.group;
  // The crop's blocks: whole ones inside, parts of the first and last (the crop's edges need not
  // fall on a block's). The mask's bytes are copied as they are (non-zero: a mask sample), a whole
  // block's row at once and without a branch on its label.
  const int firstBlock = c.x / kBlock, lastBlock = (c.x + c.width - 1) / kBlock;
  for (int y = 0; y < c.height; ++y) {
    const int* label = groups.label.data() + size_t((c.y + y) / kBlock) * groups.columns;
    const size_t row = size_t(c.y + y) * w + c.x;
    const uint8_t* m = mask.data() + row;
    uint8_t* g = groupMask.data() + size_t(y) * cw;
    for (int b = firstBlock; b <= lastBlock; ++b) {
      const int x0 = std::max(b * kBlock, c.x) - c.x, x1 = std::min((b + 1) * kBlock, c.x + c.width) - c.x;
      const bool ours = label[b] == group;
      if (x1 - x0 == kBlock) {
        uint32_t bytes;
        std::memcpy(&bytes, m + x0, sizeof bytes);
        bytes &= 0u - uint32_t(ours);
        std::memcpy(g + x0, &bytes, sizeof bytes);
      } else {
        for (int x = x0; x < x1; ++x) g[x] = ours ? m[x] : 0;
      }
    }
    // The planes the layer lacks hold zeros. By channel count, through restrict pointers and with
    // the width in a local, so that the loops vectorise (the stores could otherwise alias the crop).
    float* __restrict to = samples.data() + size_t(y) * cw * 4;
    const float* __restrict from0 = layer.colour[0].data() + row;
    const float* __restrict from1 = channels > 1 ? layer.colour[1].data() + row : from0;
    const float* __restrict from2 = channels > 2 ? layer.colour[2].data() + row : from0;
    const int width = c.width;
    if (channels == 1) {
      for (int x = 0; x < width; ++x) {
        to[4 * x] = from0[x];
        to[4 * x + 1] = to[4 * x + 2] = to[4 * x + 3] = 0.0f;
      }
    } else if (channels == 2) {
      for (int x = 0; x < width; ++x) {
        to[4 * x] = from0[x];
        to[4 * x + 1] = from1[x];
        to[4 * x + 2] = to[4 * x + 3] = 0.0f;
      }
    } else {
      for (int x = 0; x < width; ++x) {
        to[4 * x] = from0[x];
        to[4 * x + 1] = from1[x];
        to[4 * x + 2] = from2[x];
        to[4 * x + 3] = 0.0f;
      }
    }
  }
  teleaInpaint(groupMask.data(), cw, c.width, c.height, samples.data(), cw, radius, telea, likeOpenCv);
  // Every hole is in one group: one writer. The crop row's holes in order from the place of its first.
  float* out[3] = {result[0].data(), result[1].data(), result[2].data()};
  const uint8_t* hole = layer.hole.data();
  for (int y = 0; y < c.height; ++y) {
    const size_t local = size_t(y) * cw, i = size_t(c.y + y) * w + c.x;
    const float* from = samples.data() + local * 4;
    const uint8_t* ours = groupMask.data() + local;
    size_t place = places.at(hole, c.x, c.y + y);
    forEachFlag(hole + i, c.width, [&](int x) {
      const size_t p = place++;
      if (!ours[x]) return;
      for (int k = 0; k < channels; ++k) out[k][p] = from[size_t(x) * 4 + k];
    });
  }
}

// One layer's share of a fill.
struct LayerFill {
  BlendedLayer* layer;
  const HoleFillOptions* options;
  HoleFillScratch* scratch;
};

// Runs the planned inpainting tasks of every layer together, the largest crops first, so that two
// threads share the work evenly whichever layer holds it.
void inpaintAll(const std::vector<LayerFill>& fills) {
  struct Job {
    size_t fill, task;
    int area;
  };
  std::vector<Job> jobs;
  for (size_t f = 0; f < fills.size(); ++f)
    for (size_t t = 0; t < fills[f].scratch->tasks.size(); ++t) jobs.push_back({f, t, fills[f].scratch->tasks[t].crop.area()});
  std::stable_sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.area > b.area; });
  parallelRanges(int(jobs.size()), [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      const LayerFill& f = fills[jobs[size_t(j)].fill];
      HoleFillScratch& s = *f.scratch;
      inpaintGroup(*f.layer, *s.inpaintMask, f.options->inpaintRadius, f.options->inpaintLikeOpenCv, s.inpaintGroups,
                   s.places, s.tasks[jobs[size_t(j)].task], s.inpainted, s.inpaintBuffers);
    }
  });
}

}  // namespace

void fillHoles(const std::vector<HoleFillJob>& jobs) {
  std::vector<LayerFill> fills;
  for (const HoleFillJob& job : jobs) {
    BlendedLayer& layer = *job.layer;
    const HoleFillOptions& options = *job.options;
    HoleFillScratch& s = *job.scratch;
    const size_t holes = layer.holeCount();
    if (holes == 0) continue;
    if (holes == layer.hole.size()) {  // nothing to fill from
      for (int k = 0; k < layer.channels; ++k) std::fill(layer.colour[k].begin(), layer.colour[k].end(), options.emptyValue[k]);
      std::fill(layer.hole.begin(), layer.hole.end(), uint8_t(0));
      continue;
    }
    s.places.index(layer.hole, layer.width, layer.height);
    // The inpainting's mask: the holes themselves (not copied) or the background-only mask.
    s.inpaintMask = &layer.hole;
    if (options.backgroundFirst) {
      directionalFill(layer, options, s.places, s.directional, s.background, s.found, s.columnRows);
      rowRunFill(layer, options, s.places, s.runs, s.runBackground, s.runFound);
      if (options.inpaintNearerSurface) {
        backgroundOnlyMask(layer, s.places, s.background, options.depthTolerance, options.inpaintRadius + 1, s.mask, s.thresholdRows);
        s.inpaintMask = &s.mask;
      }
    }
    planInpaint(layer, *s.inpaintMask, options.inpaintRadius, s.inpainted, s);
    fills.push_back({&layer, &options, &s});
  }
  inpaintAll(fills);
  for (const LayerFill& f : fills) {
    BlendedLayer& layer = *f.layer;
    const HoleFillOptions& options = *f.options;
    HoleFillScratch& s = *f.scratch;
    const size_t n = layer.hole.size();
    if (!options.backgroundFirst) {
      for (int k = 0; k < layer.channels; ++k)
        for (size_t i = 0, p = 0; i < n; ++i)
          if (layer.hole[i]) layer.colour[k][i] = s.inpainted[k][p++];
    } else {
      // Three estimates of the background, mixed by weight (2 : 3 : 1 by default) over those that
      // found one; their errors differ, and the mix has a lower error than any of them.
      // Every sample on its own: rows in parallel.
      parallelRanges(layer.height, [&](int y0, int y1) {
        // Locals: stores to the layer could otherwise alias every vector's pointer and size.
        const uint8_t* hole = layer.hole.data();
        const uint8_t* found = s.found.data();
        const uint8_t* runFound = s.runFound.data();
        const double* background = s.background.data();
        const double* runBackground = s.runBackground.data();
        double* depth = layer.inverseDepth.data();
        const int channels = layer.channels;
        const float directionalWeight = options.directionalWeight, rowRunWeight = options.rowRunWeight;
        const float inpaintWeight = options.inpaintWeight;
        float* colour[3];
        const float *directionalColour[3], *runColour[3], *inpaintedColour[3];
        for (int k = 0; k < 3; ++k) {
          colour[k] = layer.colour[k].data();
          directionalColour[k] = s.directional[k].data();
          runColour[k] = s.runs[k].data();
          inpaintedColour[k] = s.inpainted[k].data();
        }
        const size_t begin = size_t(y0) * layer.width;
        size_t place = s.places.rowStart(y0);  // the next hole's
        forEachFlag(hole + begin, int(size_t(y1 - y0) * layer.width), [&](int offset) {
          const size_t i = begin + size_t(offset), p = place++;
          const float directional = found[p] ? directionalWeight : 0.0f;
          const float run = runFound[p] ? rowRunWeight : 0.0f, inpainted = inpaintWeight;
          const float sum = directional + run + inpainted;
          for (int k = 0; k < channels; ++k)
            colour[k][i] = sum > 0 ? (directional * directionalColour[k][p] + run * runColour[k][p] +
                                      inpainted * inpaintedColour[k][p]) / sum
                                   : inpaintedColour[k][p];
          if (found[p]) depth[i] = background[p];
          else if (runFound[p]) depth[i] = runBackground[p];
        });
      });
    }
    std::fill(layer.hole.begin(), layer.hole.end(), uint8_t(0));
  }
}

size_t fillHoles(BlendedLayer& layer, const HoleFillOptions& options, HoleFillScratch* scratch) {
  const size_t holes = layer.holeCount();
  HoleFillScratch local;
  fillHoles({{&layer, &options, scratch ? scratch : &local}});
  return holes;
}

}  // namespace vs
