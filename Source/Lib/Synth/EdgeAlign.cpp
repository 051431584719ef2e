#include "Synth/EdgeAlign.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "Common/Depth.h"
#include "Common/Error.h"
#include "Common/Geometry.h"
#include "Synth/Flags.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/ScratchPool.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

// What an edge changes, where the passes align the map in place: the sample's index and the level it
// had before the pass.
struct Change {
  size_t index;
  uint16_t before;
};

// A row aligned in place: its depth before the pass read from `depth` (a copy of the row), its samples
// written into the map's row (`out`), each write noted in `changes` with the level before.
struct Line {
  const uint16_t* depth;
  const uint16_t* luma;
  uint16_t* out;
  ptrdiff_t stride;
  int n;
  int u0, v0, du, dv;  // reference pixel of sample i: (u0 + i du, v0 + i dv)
  size_t first;        // the map's index of sample 0
  std::vector<Change>* changes;
  int d(int i) const { return depth[i * stride]; }
  int y(int i) const { return luma[i * stride]; }
  void set(int i, int level) const {
    changes->push_back({first + size_t(i), uint16_t(d(i))});
    out[i * stride] = uint16_t(level);
  }
};

// A column aligned in place: its depth before the column pass read from `ring` (the thread's columns
// of the last ringMask + 1 rows, row r at r & ringMask, `ringWidth` samples a row), its samples written
// into the map (`out`, with the row stride), each write noted in `changes` with the level before.
struct RingColumn {
  const uint16_t* ring;
  const uint16_t* luma;
  uint16_t* out;
  ptrdiff_t stride;
  int n;
  int u0, v0, du, dv;  // as Line's: (x, 0, 0, 1)
  int ringMask;  // the ring's rows less one (a power of two)
  ptrdiff_t ringWidth;
  std::vector<Change>* changes;
  int d(int i) const { return ring[(i & ringMask) * ringWidth]; }
  int y(int i) const { return luma[i * stride]; }
  void set(int i, int level) const {
    changes->push_back({size_t(i) * size_t(stride) + size_t(u0), uint16_t(d(i))});
    out[i * stride] = uint16_t(level);
  }
};

// How unlike sample i of `line` the witness sees its point at depth `level`: the least luma
// difference over three witness samples along the row around where it lands; -1: no evidence.
template <class L>
int mismatch(const EdgeWitness& witness, const L& line, int i, int level) {
  if (size_t(level) >= witness.inverseDepth->size()) return -1;
  const double inverse = (*witness.inverseDepth)[size_t(level)];
  if (std::isnan(inverse)) return -1;
  double x, y, wv;
  if (!witness.projection->forward(line.u0 + i * line.du, line.v0 + i * line.dv, inverse, x, y, wv)) return -1;
  const Plane& luma = *witness.luma;
  const double cx = std::floor(x + 0.5), cy = std::floor(y + 0.5);
  if (!(cx >= 0 && cy >= 0 && cx < luma.width && cy < luma.height)) return -1;
  const int px = int(cx), py = int(cy), colour = line.y(i);
  int best = std::abs(luma.at(px, py) - colour);
  if (px > 0) best = std::min(best, std::abs(luma.at(px - 1, py) - colour));
  if (px + 1 < luma.width) best = std::min(best, std::abs(luma.at(px + 1, py) - colour));
  return best;
}

// Flags x in [0, n) where samples a[x] and b[x] form a depth edge (neither missing, levels minStep
// or more apart). Edges are few: the flags are found in a branch-free pass compiled for the CPU's
// x86-64 level (Kernels/Rows.h), and the callers then visit the set ones (Flags.h) instead of testing
// every pair with branches.
void markDepthEdges(const uint16_t* a, const uint16_t* b, int n, const EdgeAlignOptions& o, uint8_t* flags) {
  rowKernels().depthEdgePairs(a, b, n, o.missingLevel, o.minStep, flags);
}

// Whether alignEdge's first test, on the luma contrasts, can pass for the depth edge between samples
// x and x + 1 of `line`: the texture edge it looks for is one of the contrasts within reach on the far
// side (it stops earlier where the far surface ends), so the largest of those must be at least
// minContrast, at least twice and more than the contrast at the depth edge. Most depth edges fail
// it; here without a branch on the samples (positions past the line's ends read the edge's own
// contrast instead, which adds nothing), so that they cost little.
template <class L>
inline bool mayMove(const L& line, int x, const EdgeAlignOptions& o) {
  const int n = line.n;
  auto contrast = [&](int p) { return std::abs(line.y(p + 1) - line.y(p)); };
  const int toFar = line.d(x) > line.d(x + 1) ? 1 : -1;
  const int atEdge = contrast(x);
  int most = 0;
  for (int k = 1; k <= o.reach; ++k) {
    const int p = x + k * toFar;
    const int c = contrast((p >= 0) & (p + 1 < n) ? p : x);
    most = most > c ? most : c;
  }
  return (most >= o.minContrast) & (most >= 2 * atEdge) & (most > atEdge);
}

// Asks for the cache lines of samples [begin, end) ahead of their use: the edges read the luma and
// depth of lines crossing a few rows ahead of the one visited, which would otherwise miss the cache
// at nearly every edge.
inline void prefetchSamples(const uint16_t* begin, const uint16_t* end) {
  for (const uint16_t* p = begin; p < end; p += 32) __builtin_prefetch(p);
  if (end > begin) __builtin_prefetch(end - 1);
}

// The depth edge between samples x and x + 1 of `line`: moves it onto the texture edge when the tests
// of EdgeAlign.h hold.
template <class L>
void alignEdge(const L& line, int x, const EdgeAlignOptions& o, const EdgeWitness& witness) {
  const int n = line.n;
  auto contrast = [&](int p) { return std::abs(line.y(p + 1) - line.y(p)); };
  const int a = line.d(x), b = line.d(x + 1);
  const bool nearLeft = a > b;
  const int nearLevel = std::max(a, b);
  const int toFar = nearLeft ? 1 : -1;
  const int nearSample = nearLeft ? x : x + 1;
  const int atEdge = contrast(x);
  // The luma edge between samples p and p + 1, k samples from the depth edge towards the far side,
  // with every sample passed on the far surface (farther by a step, and not missing).
  int best = 0, bestContrast = atEdge;
  for (int k = 1; k <= o.reach; ++k) {
    const int p = x + k * toFar;
    if (p < 0 || p + 1 >= n) break;
    const int passed = nearLeft ? p : p + 1;
    const int level = line.d(passed);
    if (level == o.missingLevel || nearLevel - level < o.minStep) break;
    if (contrast(p) > bestContrast) {
      bestContrast = contrast(p);
      best = k;
    }
  }
  if (best == 0 || bestContrast < o.minContrast || bestContrast < 2 * atEdge) return;
  const int p = x + best * toFar;
  const int lo = std::min(x, p) + 1, hi = std::max(x, p);  // the samples taken over
  const int farSample = nearLeft ? hi + 1 : lo - 1;        // first far sample beyond the luma edge
  bool takeOver = true;
  for (int q = std::min(x, p); q <= std::max(x, p) && takeOver; ++q)
    takeOver = q == p || 2 * contrast(q) <= bestContrast;
  for (int s = lo; s <= hi && takeOver; ++s)
    takeOver = std::abs(line.y(s) - line.y(nearSample)) < std::abs(line.y(s) - line.y(farSample));
  // The witness must see the band's colours where the near depth puts them better than where their
  // own depth does, summed over the band; a sample it cannot see either way vetoes the move.
  long nearError = 0, farError = 0;
  for (int s = lo; s <= hi && takeOver; ++s) {
    const int en = mismatch(witness, line, s, nearLevel), ef = mismatch(witness, line, s, line.d(s));
    takeOver = en >= 0 && ef >= 0;
    nearError += en;
    farError += ef;
  }
  // By a margin: a quarter of the texture-edge contrast per sample, above noise and interpolation.
  const long margin = long(hi - lo + 1) * o.minContrast / 4;
  if (!takeOver || nearError + margin >= farError) return;
  for (int s = lo; s <= hi; ++s) line.set(s, nearLevel);
}

}  // namespace

size_t alignDepthEdgesInPlace(Plane& depth, const Plane& luma, const EdgeAlignOptions& options,
                              const EdgeWitness& witness) {
  if (options.reach <= 0 || luma.width != depth.width || luma.height != depth.height || !witness.luma ||
      !witness.projection || !witness.inverseDepth)
    return 0;
  const int w = depth.width, h = depth.height;
  // The samples the passes wrote, with their levels before (few): counted at the end.
  std::mutex changesMutex;
  std::vector<Change> rowChanges, columnChanges;
  auto keep = [&](std::vector<Change>& into, std::vector<Change>& from) {
    if (from.empty()) return;
    std::lock_guard<std::mutex> lock(changesMutex);
    into.insert(into.end(), from.begin(), from.end());
    from.clear();
  };
  // Each line's edges read the line as it was before its pass and write the map: a row is copied
  // before its edges are aligned, and the column pass keeps the last rows it read before writing
  // them (a ring). Per loop body: the line's edge flags, the copy, and the changes found.
  struct Scratch {
    std::vector<uint8_t> flags;
    std::vector<uint16_t> copy;
    std::vector<Change> changes;
  };
  ScratchPool<Scratch> scratchPool;
  parallelRanges(h, [&](int y0, int y1) {
    const auto scratch = scratchPool.take();
    std::vector<uint8_t>& edgeFlags = scratch->flags;
    std::vector<uint16_t>& before = scratch->copy;
    std::vector<Change>& changes = scratch->changes;
    edgeFlags.resize(size_t(w));
    before.resize(size_t(w));
    for (int y = y0; y < y1; ++y) {
      if (y + 1 < y1) prefetchSamples(luma.row(y + 1), luma.row(y + 1) + w);  // read at the next row's edges
      uint16_t* row = depth.row(y);
      std::copy(row, row + w, before.data());
      const Line line{before.data(), luma.row(y), row, 1, w, 0, y, 1, 0, size_t(y) * size_t(w), &changes};
      markDepthEdges(before.data(), before.data() + 1, w - 1, options, edgeFlags.data());
      forEachFlag(edgeFlags.data(), w - 1, [&](int x) {
        if (mayMove(line, x, options)) alignEdge(line, x, options, witness);
      });
    }
    keep(rowChanges, changes);
  });
  // Then the columns of the aligned rows, each from top to bottom; a thread takes a range of columns
  // and finds their edges row by row, in memory order. The edges at rows y, y + 1 read rows y - reach
  // + 1 to y + reach and write rows up to y + reach, so a ring of 2 reach + 2 rows holds every row
  // they read as it was before the pass: row y + reach + 1 is copied in before the edges at y, when
  // no edge has written it yet. Its rows rounded up to a power of two, so that a row's place is a mask.
  int ringRows = 1;
  while (ringRows < 2 * options.reach + 2) ringRows *= 2;
  parallelColumns(w, [&](int x0, int x1) {
    const auto scratch = scratchPool.take();
    std::vector<uint8_t>& edgeFlags = scratch->flags;
    std::vector<uint16_t>& ringRow = scratch->copy;
    std::vector<Change>& changes = scratch->changes;
    const int width = x1 - x0;
    edgeFlags.resize(size_t(width));
    ringRow.resize(size_t(ringRows) * size_t(width));
    uint16_t* ring = ringRow.data();
    auto ringAt = [&](int r) { return ring + size_t(r & (ringRows - 1)) * size_t(width); };
    int copied = 0;  // rows [0, copied) are in the ring (the last ringRows of them)
    for (int y = 0; y + 1 < h; ++y) {
      for (const int last = std::min(h - 1, y + options.reach + 1); copied <= last; ++copied)
        std::copy(depth.row(copied) + x0, depth.row(copied) + x1, ringAt(copied));
      // The luma rows the edges of the rows ahead will read, up to reach + 1 below the pair's first.
      const int ahead = std::min(h - 1, y + options.reach + 1);
      prefetchSamples(luma.row(ahead) + x0, luma.row(ahead) + x1);
      markDepthEdges(ringAt(y), ringAt(y + 1), width, options, edgeFlags.data());
      forEachFlag(edgeFlags.data(), width, [&](int offset) {
        const int x = x0 + offset;
        const RingColumn column{ring + offset, luma.samples.data() + x, depth.samples.data() + x, w, h, x, 0, 0, 1,
                                ringRows - 1, width, &changes};
        if (mayMove(column, y, options)) alignEdge(column, y, options, witness);
      });
    }
    keep(columnChanges, changes);
  });
  // Samples moved: those whose level differs from the one they had before both passes. A sample
  // written twice in its row pass was noted twice with the same level (the row's copy's); a column's
  // note holds the level after the row pass, so a sample the row pass wrote takes the row's note.
  auto byIndex = [](const Change& a, const Change& b) { return a.index < b.index; };
  std::sort(rowChanges.begin(), rowChanges.end(), byIndex);
  rowChanges.erase(std::unique(rowChanges.begin(), rowChanges.end(),
                               [](const Change& a, const Change& b) { return a.index == b.index; }),
                   rowChanges.end());
  std::stable_sort(columnChanges.begin(), columnChanges.end(), byIndex);
  size_t changed = 0;
  const uint16_t* after = depth.samples.data();
  for (const Change& c : rowChanges) changed += after[c.index] != c.before;
  for (size_t k = 0; k < columnChanges.size(); ++k) {
    const Change& c = columnChanges[k];
    if (k > 0 && columnChanges[k - 1].index == c.index) continue;  // the first write saw the level before
    if (std::binary_search(rowChanges.begin(), rowChanges.end(), c, byIndex)) continue;
    changed += after[c.index] != c.before;
  }
  return changed;
}

size_t alignDepthEdges(const Plane& depth, const Plane& luma, const EdgeAlignOptions& options,
                       const EdgeWitness& witness, Plane& out) {
  out = depth;
  return alignDepthEdgesInPlace(out, luma, options, witness);
}

DepthEdgeAligner::DepthEdgeAligner(const SynthesisSettings& s, int missingLevel) {
  if (s.depthEdgeAlignment <= 0 || s.references.size() < 2) return;
  views_.resize(s.references.size());
  for (size_t k = 0; k < views_.size(); ++k) {
    const ReferenceView& reference = s.references[k];
    View& view = views_[k];
    // The nearest other view. Distances can overflow to inf (a centre at 1e200) or be NaN: the first
    // other view is the witness until a strictly nearer one is found, so there always is one.
    double best = HUGE_VAL;
    view.witness = k == 0 ? 1 : 0;
    for (size_t j = 0; j < views_.size(); ++j) {
      const double d = norm(s.references[j].camera.centre() - reference.camera.centre());
      if (j != k && d < best) {
        best = d;
        view.witness = int(j);
      }
    }
    VS_CHECK(view.witness >= 0 && size_t(view.witness) < views_.size() && size_t(view.witness) != k);
    view.projection.emplace(reference.camera, s.references[size_t(view.witness)].camera, s.depthType);
    view.inverseDepth = inverseZTable(reference.depthRange);
    if (missingLevel >= 0 && size_t(missingLevel) < view.inverseDepth.size())
      view.inverseDepth[size_t(missingLevel)] = std::nan("");
    view.options.reach = s.depthEdgeAlignment;
    view.options.minStep = depthEdgeStep(s.depthFormat.maxValue());
    view.options.minContrast = 16 << std::max(0, s.textureFormat.bitDepth - 8);
    view.options.missingLevel = missingLevel;
  }
}

const Plane& DepthEdgeAligner::align(size_t k, const Plane& depth, const std::vector<const Plane*>& lumas,
                                     size_t& moved) {
  if (!enabled()) return depth;
  View& view = views_[k];
  EdgeWitness witness;
  witness.luma = lumas[size_t(view.witness)];
  witness.projection = &*view.projection;
  witness.inverseDepth = &view.inverseDepth;
  moved += alignDepthEdges(depth, *lumas[k], view.options, witness, view.aligned);
  return view.aligned;
}

void DepthEdgeAligner::alignInPlace(size_t k, Plane& depth, const std::vector<const Plane*>& lumas, size_t& moved) {
  if (!enabled()) return;
  const View& view = views_[k];
  EdgeWitness witness;
  witness.luma = lumas[size_t(view.witness)];
  witness.projection = &*view.projection;
  witness.inverseDepth = &view.inverseDepth;
  moved += alignDepthEdgesInPlace(depth, *lumas[k], view.options, witness);
}

}  // namespace vs
