#include "Synth/Occlusion.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "Common/Error.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

constexpr uint8_t kNone = 255;  // no candidate: no view, or more than one, covers the sample

static_assert(kKernelNoDepth == kNoDepth, "the row kernels' hole is the layers' hole");

// rejectMisplacedSamples for two views, whose candidates each have one other view: the candidates of
// view 0 are decided on view 1's surroundings and those of view 1 on view 0's, so both are found in
// one pass down the columns (which also finds the candidates, and keeps each column's last valid
// sample above in each view), one row pass over the candidates and one pass up the columns, and a
// candidate is dropped where it is decided (the scans read a sample's depth before deciding it, and
// each thread owns its columns).
void rejectBetweenTwoViews(WarpedLayer& view0, WarpedLayer& view1, const std::vector<double>& weights, double behind,
                           OcclusionScratch& scratch) {
  const int w = view0.width, h = view0.height;
  const size_t n = size_t(w) * size_t(h);
  double* const depth[2] = {view0.inverseDepth.data(), view1.inverseDepth.data()};
  scratch.soleView.resize(n);
  scratch.candidateRows.assign(size_t(h), 0);
  // `above`: the samples above the candidates that the pass down finds, packed (a range of columns
  // [x0, x1) from x0 h on), which the pass up takes back in reverse order of rows. Only the
  // candidates' entries are written: not zeroed, its untouched pages are never faulted in.
  scratch.around.resize(n);
  scratch.above.resize(n);
  scratch.columnLast.resize(3 * size_t(w));  // the lasts of view 0, of view 1, and a row of samples above
  std::vector<int> packedEnd(static_cast<size_t>(w));  // per range of columns, at its first: the packed samples' count
  const uint8_t first = weights[0] < 1.0 ? 0 : kNone, second = weights[1] < 1.0 ? 1 : kNone;
  // Down the columns, row by row in memory order (each thread its range of columns), in a loop
  // compiled for the CPU's x86-64 level (Synth/Kernels/Rows.h, where the rule is written out).
  parallelColumns(w, [&](int x0, int x1) {
    uint8_t* sole = scratch.soleView.data();
    uint8_t* candidateRow = scratch.candidateRows.data();
    double* last0 = scratch.columnLast.data();
    double* last1 = last0 + w;
    double* packed = scratch.above.data() + size_t(x0) * size_t(h);
    const double* d0 = depth[0];
    const double* d1 = depth[1];
    const int width = w, height = h, count = x1 - x0;
    std::fill(last0 + x0, last0 + x1, kNoDepth);
    std::fill(last1 + x0, last1 + x1, kNoDepth);
    const RowKernels& kernels = rowKernels();
    int used = 0;
    for (int y = 0; y < height; ++y) {
      const size_t at = size_t(y) * width + size_t(x0);
      const int found =
          kernels.occlusionDown(d0 + at, d1 + at, first, second, kNone, sole + at, last0 + x0, last1 + x0, packed + used, count);
      used += found;
      // Another thread may mark the same row: the same value, stored atomically.
      if (found) __atomic_store_n(candidateRow + y, uint8_t(1), __ATOMIC_RELAXED);
    }
    packedEnd[size_t(x0)] = used;
  });
  const uint8_t* candidateRows = scratch.candidateRows.data();
  int firstRow = 0, lastRow = h - 1;  // the rows holding candidates
  while (firstRow < h && !candidateRows[size_t(firstRow)]) ++firstRow;
  while (lastRow >= firstRow && !candidateRows[size_t(lastRow)]) --lastRow;
  if (firstRow > lastRow) return;
  // Along rows: each candidate takes the farther of the valid samples that close the other view's run
  // of holes around it (HUGE_VAL where the run reaches the border). Only candidates are visited; each
  // view's run is found once and kept while the candidates lie in it.
  parallelRanges(lastRow - firstRow + 1, [&](int r0, int r1) {
    const uint8_t* soleView = scratch.soleView.data();
    const uint8_t* candidateRow = scratch.candidateRows.data();
    double* rowFarthest = scratch.around.data();
    const int width = w;
    for (int y = firstRow + r0; y < firstRow + r1; ++y) {
      if (!candidateRow[size_t(y)]) continue;
      const size_t rowStart = size_t(y) * width;
      const uint8_t* sole = soleView + rowStart;
      int runEnd[2] = {0, 0};  // view o's hole run holding the last candidate: [.., runEnd[o])
      double runAround[2] = {HUGE_VAL, HUGE_VAL};
      for (int x = 0; x < width;) {
        uint64_t eight;
        if (x + 8 <= width && (std::memcpy(&eight, sole + x, sizeof eight), eight == ~uint64_t(0))) {
          x += 8;
          continue;
        }
        const uint8_t k = sole[x];
        if (k != kNone) {
          const int o = 1 - k;  // a candidate of view k lies in a hole of view o
          if (x >= runEnd[o]) {
            const double* row = depth[o] + rowStart;
            int a = x, e = x + 1;
            while (a > 0 && !(row[a - 1] >= 0.0)) --a;
            while (e < width && !(row[e] >= 0.0)) ++e;
            runEnd[o] = e;
            runAround[o] = a > 0 && e < width ? std::min(row[e], row[a - 1]) : HUGE_VAL;
          }
          rowFarthest[rowStart + size_t(x)] = runAround[o];
        }
        ++x;
      }
    }
  });
  // Up the columns, row by row in memory order (each thread the range of columns it had on the way
  // down), both views at once, with the samples below: the candidates are decided on the other view's.
  parallelColumns(w, [&](int x0, int x1) {
    const uint8_t* soleView = scratch.soleView.data();
    const double* rowFarthest = scratch.around.data();
    const double* packed = scratch.above.data() + size_t(x0) * size_t(h) + packedEnd[size_t(x0)];
    double* aboveRow = scratch.columnLast.data() + 2 * size_t(w) + x0;
    double* last0 = scratch.columnLast.data();
    double* last1 = last0 + w;
    double* d0 = depth[0];
    double* d1 = depth[1];
    const int width = w, top = firstRow, height = h;
    const double steps = behind;
    std::fill(last0 + x0, last0 + x1, kNoDepth);
    std::fill(last1 + x0, last1 + x1, kNoDepth);
    const RowKernels& kernels = rowKernels();
    const int count = x1 - x0;
    for (int y = height - 1; y >= top; --y) {
      const size_t at = size_t(y) * width + size_t(x0);
      packed -= kernels.occlusionUp(soleView + at, d0 + at, d1 + at, last0 + x0, last1 + x0, packed, rowFarthest + at,
                                    steps, count, aboveRow);
    }
  });
}

}  // namespace

void rejectMisplacedSamples(const std::vector<WarpedLayer*>& views, const std::vector<double>& weights, double behind,
                            OcclusionScratch& scratch) {
  // The surroundings are needed at the candidates only (samples exactly one view covers): rows
  // without a candidate are skipped, a row's holes are handled a run at a time, and the column scans
  // keep each column's last valid sample without a branch, deciding the candidates on the way up.
  if (views.size() < 2) return;
  const int w = views[0]->width, h = views[0]->height;
  const size_t n = size_t(w) * size_t(h);
  VS_CHECK(views.size() < kNone && weights.size() == views.size());
  for (const WarpedLayer* view : views) VS_CHECK(view->width == w && view->height == h);
  if (views.size() == 2) {
    rejectBetweenTwoViews(*views[0], *views[1], weights, behind, scratch);
    return;
  }
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
    for (int y = y0; y < y1; ++y) {
      uint8_t any = 0;
      const size_t begin = size_t(y) * width, end = size_t(y + 1) * width;
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
      candidateRow[size_t(y)] = any;
    }
  });
  int firstRow = 0, lastRow = h - 1;  // the rows holding candidates
  while (firstRow < h && !candidateRow[size_t(firstRow)]) ++firstRow;
  while (lastRow >= firstRow && !candidateRow[size_t(lastRow)]) --lastRow;
  if (firstRow > lastRow) return;
  UntouchedBuffer<double>& farthest = scratch.around;  // per candidate: the row's, then with the column's
  auto& above = scratch.above;                        // per sample: the column's last valid sample above
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
    parallelColumns(w, [&](int x0, int x1) {
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
