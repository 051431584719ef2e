#include "Synth/Occlusion.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "Common/Error.h"
#include "Synth/Parallel.h"

namespace vs {

void rejectMisplacedSamples(const std::vector<WarpedLayer*>& views, const std::vector<double>& weights, double behind,
                            OcclusionScratch& scratch) {
  // The surroundings are needed at the candidates only (samples exactly one view covers): rows
  // without a candidate are skipped, a row's holes are handled a run at a time, and the column scans
  // keep each column's last valid sample without a branch, deciding the candidates on the way up.
  if (views.size() < 2) return;
  const int w = views[0]->width, h = views[0]->height;
  const size_t n = size_t(w) * size_t(h);
  constexpr uint8_t kNone = 255;  // no candidate: no view, or more than one, covers the sample
  VS_CHECK(views.size() < kNone && weights.size() == views.size());
  for (const WarpedLayer* view : views) VS_CHECK(view->width == w && view->height == h);
  std::vector<uint8_t>& sole = scratch.soleView;
  sole.resize(n);
  std::vector<uint8_t>& candidateRow = scratch.candidateRows;
  candidateRow.assign(size_t(h), 0);
  // 1 while a candidate is still behind the surroundings in every other view looked at so far.
  std::vector<uint8_t>& reject = scratch.stillBehind;
  reject.resize(n);
  std::vector<const double*> depths;
  for (const WarpedLayer* view : views) depths.push_back(view->inverseDepth.data());
  parallelRanges(h, [&](int y0, int y1) {
    const double* const* depth = depths.data();
    const size_t viewCount = depths.size(), width = size_t(w);
    uint8_t* out = sole.data();
    uint8_t* stillBehind = reject.data();
    // Two views (nearly every run): which one covers the sample alone, without branches.
    const bool two = viewCount == 2;
    const uint8_t first = weights[0] < 1.0 ? 0 : kNone, second = weights[1] < 1.0 ? 1 : kNone;
    for (int y = y0; y < y1; ++y) {
      uint8_t any = 0;
      const size_t begin = size_t(y) * width, end = size_t(y + 1) * width;
      if (two) {
        const double *d0 = depth[0], *d1 = depth[1];
        for (size_t i = begin; i < end; ++i) {
          const bool v0 = d0[i] >= 0.0, v1 = d1[i] >= 0.0;
          const uint8_t view = v0 == v1 ? kNone : v0 ? first : second;
          out[i] = view;
          stillBehind[i] = uint8_t(view != kNone);
          any |= uint8_t(view != kNone);
        }
      } else {
        for (size_t i = begin; i < end; ++i) {
          size_t count = 0, only = 0;
          for (size_t k = 0; k < viewCount; ++k)
            if (depth[k][i] >= 0.0) {
              ++count;
              only = k;
            }
          const bool candidate = count == 1 && weights[only] < 1.0;
          out[i] = candidate ? uint8_t(only) : kNone;
          stillBehind[i] = candidate;
          any |= uint8_t(candidate);
        }
      }
      candidateRow[size_t(y)] = any;
    }
  });
  int firstRow = 0, lastRow = h - 1;  // the rows holding candidates
  while (firstRow < h && !candidateRow[size_t(firstRow)]) ++firstRow;
  while (lastRow >= firstRow && !candidateRow[size_t(lastRow)]) --lastRow;
  if (firstRow > lastRow) return;
  std::vector<double>& farthest = scratch.around;  // per candidate: the row's, then with the column's
  std::vector<double>& above = scratch.above;      // per sample: the column's last valid sample above
  std::vector<double>& columnLast = scratch.columnLast;
  farthest.resize(n);
  above.resize(n);
  columnLast.resize(size_t(w));
  for (size_t o = 0; o < views.size(); ++o) {
    const double* other = depths[o];
    // Along rows: each run of o's holes takes the farther of the valid samples that close it.
    parallelRanges(lastRow - firstRow + 1, [&](int r0, int r1) {
      const uint8_t* soleView = sole.data();
      double* rowFarthest = farthest.data();
      const int width = w;
      for (int y = firstRow + r0; y < firstRow + r1; ++y) {
        if (!candidateRow[size_t(y)]) continue;
        const size_t rowStart = size_t(y) * width;
        const double* row = other + rowStart;
        for (int x = 0; x < width;) {
          if (row[x] >= 0.0) {
            ++x;
            continue;
          }
          const int a = x;
          while (x < width && !(row[x] >= 0.0)) ++x;
          const double around = a > 0 && x < width ? std::min(row[x], row[a - 1]) : HUGE_VAL;
          for (int i = a; i < x; ++i) {
            const size_t s = rowStart + size_t(i);
            if (soleView[s] != kNone && soleView[s] != o) rowFarthest[s] = around;
          }
        }
      }
    });
    // Along columns, row by row in memory order (each thread its range of columns): down to keep
    // each column's last valid sample above, then up with the one below, where the candidates are
    // decided.
    parallelRanges(w, [&](int x0, int x1) {
      const uint8_t* soleView = sole.data();
      const double* const* depth = depths.data();
      double* last = columnLast.data();
      double* up = above.data();
      double* rowFarthest = farthest.data();
      uint8_t* stillBehind = reject.data();
      const int width = w, top = firstRow, bottom = lastRow, height = h;
      const double steps = behind;
      std::fill(last + x0, last + x1, kNoDepth);
      for (int y = 0; y <= bottom; ++y) {
        const double* row = other + size_t(y) * width;
        double* upRow = up + size_t(y) * width;
        for (int x = x0; x < x1; ++x) {
          const double value = row[x], previous = last[x];
          upRow[x] = previous;
          last[x] = value >= 0.0 ? value : previous;
        }
      }
      std::fill(last + x0, last + x1, kNoDepth);
      for (int y = height - 1; y >= top; --y) {
        const size_t rowStart = size_t(y) * width;
        const double* row = other + rowStart;
        for (int x = x0; x < x1; ++x) {
          const size_t s = rowStart + size_t(x);
          const double value = row[x], below = last[x];
          last[x] = value >= 0.0 ? value : below;
          const uint8_t k = soleView[s];
          if (k == kNone || k == o || !stillBehind[s]) continue;
          double around = rowFarthest[s];
          if (below >= 0.0 && up[s] >= 0.0) around = std::min(around, std::min(below, up[s]));
          stillBehind[s] = around != HUGE_VAL && depth[k][s] < around - steps;
        }
      }
    });
  }
  parallelRanges(lastRow - firstRow + 1, [&](int r0, int r1) {
    for (size_t i = size_t(firstRow + r0) * w; i < size_t(firstRow + r1) * w; ++i)
      if (sole[i] != kNone && reject[i]) views[sole[i]]->inverseDepth[i] = kNoDepth;
  });
}

}  // namespace vs
