#include "Synth/Telea.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif

namespace vs {
namespace {

// Sample states, as OpenCV names them: known, on the marching front, not reached yet; `kChanged`
// marks what the outward march has passed.
constexpr uint8_t kKnown = 0, kBand = 1, kInside = 2, kChanged = 3;

// Arrival time at a sample from two of its neighbours (one vertical, one horizontal): the
// first-order upwind solution of |grad T| = 1, in double, rounded to float at the end.
inline float solve(const uint8_t* flags, const float* time, size_t a, size_t b) {
  const double ta = time[a], tb = time[b], lower = ta > tb ? tb : ta;
  double t;
  if (flags[a] != kInside) {
    if (flags[b] != kInside)
      t = std::fabs(ta - tb) >= 1.0 ? 1 + lower : (ta + tb + std::sqrt(2 - (ta - tb) * (ta - tb))) * 0.5;
    else
      t = 1 + ta;
  } else {
    t = flags[b] != kInside ? 1 + tb : 1 + lower;
  }
  return float(t);
}

inline float smaller(float a, float b) { return a > b ? b : a; }

#if defined(__SSE2__)
// Two doubles, each lane computed exactly as the scalar double is.
typedef double Doubles __attribute__((vector_size(16)));
typedef int64_t DoubleMask __attribute__((vector_size(16)));

// solve() for the pairs (a[0], b) and (a[1], b) side by side and without a branch: which neighbours
// are known follows the mask's shape, which no branch predictor guesses. Every case is computed
// and one picked per lane; the square root's argument is kept non-negative in the lanes whose
// root is not picked (|ta - tb| >= 1), where it would otherwise be a NaN at best and a call into
// libm to set errno at worst.
inline Doubles solvePairs(Doubles ta, DoubleMask aKnown, double tbValue, bool bKnown) {
  const Doubles tb = {tbValue, tbValue}, one = {1.0, 1.0};
  const Doubles lower = ta > tb ? tb : ta;
  const Doubles d = ta - tb;
  const DoubleMask far = (d >= one) | (d <= -one);  // fabs(d) >= 1
  const Doubles root = _mm_sqrt_pd(_mm_max_pd(2 - d * d, Doubles{}));
  const Doubles both = far ? one + lower : (ta + tb + root) * 0.5;
  const DoubleMask bMask = DoubleMask{} - int64_t(bKnown);
  const Doubles aOnly = one + ta, bOnly = one + tb, neither = one + lower;
  return aKnown ? (bMask ? both : aOnly) : (bMask ? bOnly : neither);
}
#endif

// The arrival time at sample `s` of a grid `cols` wide: the least over its four pairs of neighbours.
inline float arrival(const uint8_t* flags, const float* time, size_t s, size_t cols) {
  const size_t up = s - cols, down = s + cols, left = s - 1, right = s + 1;
#if defined(__SSE2__)
  // Lane 0 pairs with `up`, lane 1 with `down`.
  const Doubles ta = {double(time[up]), double(time[down])};
  const DoubleMask aKnown = {-int64_t(flags[up] != kInside), -int64_t(flags[down] != kInside)};
  const Doubles withLeft = solvePairs(ta, aKnown, time[left], flags[left] != kInside);
  const Doubles withRight = solvePairs(ta, aKnown, time[right], flags[right] != kInside);
  return smaller(smaller(float(withLeft[0]), float(withLeft[1])), smaller(float(withRight[0]), float(withRight[1])));
#else
  return smaller(smaller(solve(flags, time, up, left), solve(flags, time, down, left)),
                 smaller(solve(flags, time, up, right), solve(flags, time, down, right)));
#endif
}

// A queue that gives what OpenCV's sorted list gives: the least time first, equal times in the
// order they were pushed. The times pushed are never negative (the marches push 0 and arrival
// times computed from non-negative neighbours), so a time's float bits, followed by the push count,
// order as one 64-bit key (a -0 would not: it is made +0, which OpenCV's comparisons do not tell
// apart from it). A march starts from its seeds (the band), all at time 0 and pushed before anything
// else: they are read from their list in order, and only the times computed later go into a heap.
// Each pop compares the next seed's key with the heap's least, so the order is the one queue's
// whatever the times. The heap is 4-ary: half the levels of a binary one, each level's four children
// side by side in memory. It holds keys; the grid position of each push is kept by its count.
class Queue {
 public:
  Queue(std::vector<uint64_t>& heap, std::vector<uint32_t>& positions) : heap_(heap), positions_(positions) {}
  // Starts a march from `count` seeds (time 0, in this order); the queue must be empty.
  void seed(const uint32_t* seeds, size_t count) {
    heap_.clear();
    positions_.clear();
    seeds_ = seeds;
    seedCount_ = count;
    nextSeed_ = 0;
  }
  bool empty() const { return nextSeed_ == seedCount_ && heap_.empty(); }
  void push(size_t position, float time) {
    const float t = time + 0.0f;  // -0 -> +0
    uint32_t bits;
    std::memcpy(&bits, &t, sizeof bits);
    const uint64_t key = uint64_t(bits) << 32 | uint32_t(seedCount_ + positions_.size());
    positions_.push_back(uint32_t(position));
    heap_.push_back(key);
    uint64_t* h = heap_.data();
    size_t i = heap_.size() - 1;
    while (i > 0) {
      const size_t parent = (i - 1) / 4;
      if (h[parent] <= key) break;
      h[i] = h[parent];
      i = parent;
    }
    h[i] = key;
  }
  size_t pop() {
    // A seed's key is its index: time 0.
    if (nextSeed_ < seedCount_ && (heap_.empty() || uint64_t(nextSeed_) < heap_.front())) return seeds_[nextSeed_++];
    uint64_t* h = heap_.data();
    const uint64_t top = h[0], last = heap_.back();
    const size_t size = heap_.size() - 1;
    heap_.pop_back();
    // Sift `last` down from the root: the hole moves to the least child while that is less.
    // Keys are distinct (their counts are): the least child is picked without a branch, which the
    // keys' order would leave to chance.
    size_t i = 0;
    for (;;) {
      const size_t first = 4 * i + 1;
      if (first >= size) break;
      size_t least = first;
      uint64_t leastKey = h[first];
      const size_t end = std::min(first + 4, size);
      for (size_t c = first + 1; c < end; ++c) {
        const uint64_t k = h[c];
        const bool less = k < leastKey;
        leastKey = less ? k : leastKey;
        least = less ? c : least;
      }
      if (leastKey >= last) break;
      h[i] = leastKey;
      i = least;
    }
    if (size > 0) h[i] = last;
    return positions_[uint32_t(top) - seedCount_];
  }

 private:
  std::vector<uint64_t>& heap_;
  std::vector<uint32_t>& positions_;
  const uint32_t* seeds_ = nullptr;
  size_t seedCount_ = 0, nextSeed_ = 0;
};

// Takes samples off the queue in order, marks each `poppedState` and calls visit(s) for each of its
// 4-neighbours (up, left, down, right, OpenCV's order) that is still kInside. OpenCV's marches visit
// rows and columns from 1 (and its two marches differ in their last ones), but every sample popped
// is inside the grid's border and no border sample is ever kInside: no bound needs testing.
template <class Visit>
void march(Queue& queue, uint8_t* flags, uint8_t poppedState, size_t cols, const Visit& visit) {
  while (!queue.empty()) {
    const size_t popped = queue.pop();
    flags[popped] = poppedState;
    const size_t neighbour[4] = {popped - cols, popped - 1, popped + cols, popped + 1};
    for (const size_t s : neighbour)
      if (flags[s] == kInside) visit(s);
  }
}

// Four float lanes (the planes of one sample), computed lane by lane exactly as scalar floats are.
typedef float Lanes __attribute__((vector_size(16)));
typedef int32_t LaneMask __attribute__((vector_size(16)));

inline Lanes load(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// `yes ? a : b` lane by lane without a branch: the conditions follow the mask's shape, which no
// branch predictor guesses.
inline Lanes pick(LaneMask yes, Lanes a, Lanes b) { return Lanes((LaneMask(a) & yes) | (LaneMask(b) & ~yes)); }

using Offset = TeleaOffset;

// OpenCV's weight of a known neighbour at `o` with arrival time `neighbourTime`, for a sample with
// arrival time `time` and time gradient (gradTx, gradTy): distance x level-set x direction. OpenCV
// writes the level term as (float)(1. / (1 + fabs(dT))) and tests fabs(dir) <= 0.01 in double; for
// a float 1 + |dT|, 1.0f / x is the same float (a double has more than twice float's bits, so
// rounding twice equals rounding once), and 0.01f is the largest float not above 0.01.
inline float neighbourWeight(float rx, float ry, float distance, float neighbourTime, float time, float gradTx,
                             float gradTy) {
  const float level = 1.0f / (1.0f + std::fabs(neighbourTime - time));
  float dir = rx * gradTx + ry * gradTy;
  if (std::fabs(dir) <= 0.01f) dir = 0.000001f;
  return std::fabs(distance * level * dir);
}
inline float neighbourWeight(const Offset& o, float neighbourTime, float time, float gradTx, float gradTy) {
  return neighbourWeight(o.rx, o.ry, o.distance, neighbourTime, time, gradTx, gradTy);
}

// For each combination of a neighbour's four neighbours being known (bit 0 right, 1 left, 2 below,
// 3 above): where a colour gradient reads each side, in floats from the neighbour (the neighbour
// itself where that side is not known: a difference with its own colour is what OpenCV's one-sided
// and zero gradients come to), and whether it is a doubled central difference.
struct GradientRule {
  ptrdiff_t right, left, below, above;
  float scaleX, scaleY;
};
void gradientRules(ptrdiff_t rowStep, GradientRule rule[16]) {
  for (int bits = 0; bits < 16; ++bits) {
    const bool r = bits & 1, l = bits & 2, b = bits & 4, a = bits & 8;
    rule[bits] = {r ? 4 : 0, l ? -4 : 0, b ? rowStep : 0, a ? -rowStep : 0, 1.0f + float(r && l),
                  1.0f + float(b && a)};
  }
}

// The same bits read for a filled sample's time gradient: lanes 0 (x) and 1 (y) take the right
// and lower neighbours' times (`after`), the left and upper ones' (`before`), halved where both
// sides are known.
struct TimeGradientRule {
  LaneMask after, before;
  Lanes scale;
};
struct TimeGradientRules {
  TimeGradientRule rule[16];
  TimeGradientRules() {
    for (int bits = 0; bits < 16; ++bits) {
      const bool r = bits & 1, l = bits & 2, b = bits & 4, a = bits & 8;
      rule[bits] = {LaneMask{-int32_t(r), -int32_t(b), 0, 0}, LaneMask{-int32_t(l), -int32_t(a), 0, 0},
                    Lanes{r && l ? 0.5f : 1.0f, b && a ? 0.5f : 1.0f, 1.0f, 1.0f}};
    }
  }
};
const TimeGradientRules kTimeGradientRules;

// The sums of one sample's neighbours, four planes at once, when the whole neighbourhood, and a
// sample around each neighbour, lies inside the picture (none of OpenCV's edge rules applies).
// `centre` points at the sample's first plane; `known` lists the neighbours that are not still to be
// filled (OpenCV skips those), in OpenCV's order; `weight` holds every neighbour's weight;
// `knownSides` points at the sample's entry of the grid of which 4-neighbours are known
// (GradientRules' bits).
void interiorSums(const float* centre, const GradientRule* rules, const uint8_t* knownSides,
                  const Offset* offsets, const ptrdiff_t* gridOffset, const ptrdiff_t* sampleOffset,
                  const float* weight, const uint16_t* known, size_t count, Lanes& ia, Lanes& jx, Lanes& jy,
                  float& sum) {
  Lanes a = {}, x = {}, y = {};
  float s = sum;
  for (size_t e = 0; e < count; ++e) {
    const size_t m = known[e];
    const ptrdiff_t g = gridOffset[m];
    const Offset& o = offsets[m];
    const float w = weight[m];
    const GradientRule& rule = rules[knownSides[g]];
    const float* q = centre + sampleOffset[m];
    const Lanes c = load(q);
    const Lanes gx = (load(q + rule.right) - load(q + rule.left)) * rule.scaleX;
    const Lanes gy = (load(q + rule.below) - load(q + rule.above)) * rule.scaleY;
    a += w * c;
    x -= w * (gx * o.rx);
    y -= w * (gy * o.ry);
    s += w;
  }
  ia = a;
  jx = x;
  jy = y;
  sum = s;
}

}  // namespace

void teleaInpaint(const uint8_t* mask, size_t maskStride, int width, int height, float* samples,
                  size_t rowStride, double radius, TeleaScratch& scratch, bool likeOpenCv) {
  const bool outwardMarch = likeOpenCv;
  if (width <= 0 || height <= 0) return;
  const int range = std::min(std::max(int(std::lrint(radius)), 1), 100);
  // Grids one sample wider on every side (row and column 0 and the last ones are a border).
  const int rows = height + 2, cols = width + 2;
  const size_t n = size_t(rows) * cols;
  std::vector<uint8_t>& flags = scratch.flags;
  std::vector<uint8_t>& outer = scratch.outer;
  std::vector<float>& time = scratch.time;
  // The passes over the grids below go through local pointers: a byte store may alias anything, and
  // a vector's data pointer reloaded after each one keeps a loop from being vectorised.
  flags.resize(n);
  uint8_t* fl = flags.data();
  std::memset(fl, kKnown, cols);
  std::memset(fl + (n - cols), kKnown, cols);
  uint8_t any = 0;
  for (int y = 0; y < height; ++y) {
    const uint8_t* m = mask + size_t(y) * maskStride;
    uint8_t* to = fl + size_t(y + 1) * cols;
    to[0] = to[cols - 1] = kKnown;
    for (int x = 0; x < width; ++x) {
      to[x + 1] = m[x] ? kInside : kKnown;
      any |= m[x];
    }
  }
  if (!any) return;
  auto at = [cols](int r, int c) { return size_t(r) * cols + c; };
  auto interior = [rows, cols](int r, int c) { return r > 0 && c > 0 && r < rows - 1 && c < cols - 1; };

  // The band: known interior samples beside (4-neighbours) a mask sample. Time 0.
  time.assign(n, 1.0e6f);
  // In raster order: both marches start from it. Written without a branch (the band follows the
  // mask's shape): every sample is stored and the count moves past the band's. The flags are only
  // kKnown (0) and kInside so far: eight samples whose own and neighbours' bytes are all 0 are
  // passed at once.
  static_assert(kKnown == 0, "a word of known flags is 0");
  std::vector<uint32_t>& band = scratch.band;
  if (band.size() < n) band.resize(n);
  size_t bandCount = 0;
  // The same pass records which 4-neighbours of each interior sample are known (bit 0 right, 1
  // left, 2 below, 3 above), kept as the inward march fills: a neighbour's gradient rule is then one
  // byte, not four flags.
  std::vector<uint8_t>& knownSides = scratch.knownSides;
  knownSides.resize(n);
  uint8_t* sides = knownSides.data();
  {
    uint32_t* to = band.data();
    auto word = [](const uint8_t* p) {
      uint64_t w;
      std::memcpy(&w, p, sizeof w);
      return w;
    };
    for (int r = 1; r < rows - 1; ++r) {
      const uint8_t* f = fl + at(r, 0);
      const uint32_t base = uint32_t(at(r, 0));
      uint8_t* rowSides = sides + at(r, 0);
      for (int c = 1; c < cols - 1; ++c) {
        // Samples c..c+7 read columns c-1..c+8 of this row and c..c+7 of the rows beside it.
        if (c + 9 <= cols && (word(f + c - 1) | word(f + c + 1) | word(f + c - cols) | word(f + c + cols)) == 0) {
          const uint64_t allKnown = 0x0f0f0f0f0f0f0f0full;
          std::memcpy(rowSides + c, &allKnown, sizeof allKnown);
          c += 7;
          continue;
        }
        const bool right = f[c + 1] != kInside, left = f[c - 1] != kInside;
        const bool below = f[c + cols] != kInside, above = f[c - cols] != kInside;
        rowSides[c] = uint8_t(right | left << 1 | below << 2 | above << 3);
        to[bandCount] = base + uint32_t(c);
        bandCount += (f[c] != kInside) & !(right & left & below & above);
      }
    }
  }
  Queue queue(scratch.queue, scratch.positions);
  if (!outwardMarch) {
    // Every known sample at time 0.
    float* tm = time.data();
    for (int r = 1; r < rows - 1; ++r)
      for (int c = 1; c < cols - 1; ++c) tm[at(r, c)] = fl[at(r, c)] == kInside ? 1.0e6f : 0.0f;
  } else {
    // The outer ring: known interior samples within `range` (Chebyshev) of a mask sample, band left
    // out. Row-wise counts of mask samples in the window, then, row by row, the count of rows of the
    // window that hold one, per column. Counts of at most 2 range + 1 <= 201 rows are bytes: a quarter
    // of the memory traffic of ints, sixteen columns to a vector.
    outer.resize(n);
    {
      std::vector<uint8_t>& rowCount = scratch.rowCount;  // rows 0..rows-1: whether the row's window
      rowCount.resize(n + cols);                          // holds mask samples; then the column counts
      uint8_t* near = rowCount.data();
      // A row's window of `span` samples is the union of two of `covered` samples, the largest power of
      // two not above it, and those come from doubling: log(span) passes of byte ORs that vectorise,
      // where a running count along the row waits on itself sample by sample. spanBytes[range + c] is
      // column c's flag, zero around the row.
      const int span = 2 * range + 1;
      std::vector<uint8_t>& spanBytes = scratch.rowSpan;
      const size_t length = size_t(cols) + 2 * size_t(span);
      spanBytes.assign(length, 0);
      uint8_t* e = spanBytes.data();
      for (int r = 0; r < rows; ++r) {
        const uint8_t* f = fl + at(r, 0);
        uint8_t* to = near + at(r, 0);
        for (int c = 0; c < cols; ++c) e[range + c] = f[c] == kInside;
        std::fill(e + range + cols, e + length, uint8_t(0));  // the doubling's last row left its ORs
        int covered = 1;  // e[k]: some flag in k..k+covered-1
        for (; 2 * covered <= span; covered *= 2)
          for (size_t k = 0; k + covered < length; ++k) e[k] |= e[k + covered];
        // Window of column c: e's flags c..c+span-1.
        for (int c = 0; c < cols; ++c) to[c] = e[c] | e[c + span - covered];
        std::fill(e, e + range, uint8_t(0));
      }
      uint8_t* columnCount = near + n;
      std::fill(columnCount, columnCount + cols, uint8_t(0));
      for (int r = 0; r < std::min(range, rows); ++r) {
        const uint8_t* from = near + at(r, 0);
        for (int c = 0; c < cols; ++c) columnCount[c] += from[c];
      }
      for (int r = 0; r < rows; ++r) {
        if (r + range < rows) {
          const uint8_t* from = near + at(r + range, 0);
          for (int c = 0; c < cols; ++c) columnCount[c] += from[c];
        }
        const uint8_t* f = fl + at(r, 0);
        uint8_t* to = outer.data() + at(r, 0);
        if (r == 0 || r == rows - 1) {
          std::memset(to, kKnown, cols);
        } else {
          to[0] = to[cols - 1] = kKnown;
          // Without a branch, so that it vectorises.
          static_assert(kKnown == 0, "known is 0");
          for (int c = 1; c < cols - 1; ++c) to[c] = uint8_t(kInside * ((columnCount[c] != 0) & (f[c] != kInside)));
        }
        if (r - range >= 0) {
          const uint8_t* from = near + at(r - range, 0);
          for (int c = 0; c < cols; ++c) columnCount[c] -= from[c];
        }
      }
    }
    for (size_t b = 0; b < bandCount; ++b) {
      time[band[b]] = 0;
      outer[band[b]] = kKnown;
    }
    queue.seed(band.data(), bandCount);

    // Outward march over the outer ring from the band; what it passes gets the negated time.
    march(queue, outer.data(), kChanged, size_t(cols), [&](size_t s) {
      const float t = arrival(outer.data(), time.data(), s, size_t(cols));
      time[s] = t;
      outer[s] = kBand;
      queue.push(s, t);
    });
    // It passed the band and every sample it pushed (the queue ends empty), and nothing else.
    {
      float* tm = time.data();
      for (size_t b = 0; b < bandCount; ++b) tm[band[b]] = -tm[band[b]];
      for (const uint32_t s : scratch.positions) tm[s] = -tm[s];
    }

  }

  // The neighbours within the radius, in OpenCV's order (row by row).
  std::vector<Offset>& offsets = scratch.offsets;
  std::vector<ptrdiff_t>& gridOffset = scratch.gridOffset;
  std::vector<ptrdiff_t>& sampleOffset = scratch.sampleOffset;
  offsets.clear();
  gridOffset.clear();
  sampleOffset.clear();
  const ptrdiff_t rowStep = ptrdiff_t(rowStride) * 4;  // floats per picture row
  for (int dr = -range; dr <= range; ++dr)
    for (int dc = -range; dc <= range; ++dc) {
      if (dr * dr + dc * dc > range * range || (dr == 0 && dc == 0)) continue;
      const float ry = float(-dr), rx = float(-dc);
      const float length = rx * rx + ry * ry;
      offsets.push_back({dr, dc, rx, ry, float(1. / (length * std::sqrt(length)))});
      gridOffset.push_back(ptrdiff_t(dr) * cols + dc);
      sampleOffset.push_back(ptrdiff_t(dr) * rowStep + ptrdiff_t(dc) * 4);
    }
  const size_t offsetCount = offsets.size();
  GradientRule gradientRule[16];
  gradientRules(rowStep, gradientRule);
  std::vector<uint16_t>& known = scratch.known;
  known.resize(offsetCount);
  // The offsets' fields side by side, and room for each sample's neighbour times and weights.
  std::vector<float>& lanes = scratch.offsetLanes;
  lanes.resize(offsetCount * 5);
  float* __restrict rx = lanes.data();
  float* __restrict ry = rx + offsetCount;
  float* __restrict distance = ry + offsetCount;
  float* __restrict neighbourTime = distance + offsetCount;
  float* __restrict weight = neighbourTime + offsetCount;
  for (size_t m = 0; m < offsetCount; ++m) {
    rx[m] = offsets[m].rx;
    ry[m] = offsets[m].ry;
    distance[m] = offsets[m].distance;
  }

  // Inward march from the band, filling each sample as it is reached. The picture is OpenCV's `out`,
  // which has no border: sample (r, c) of a grid is (r - 1, c - 1) there.
  queue.seed(band.data(), bandCount);
  const uint8_t* f = flags.data();
  const float* tm = time.data();
  // Within the picture, OpenCV's edge rules read only picture samples; clamping keeps a picture one
  // sample high or wide (where OpenCV reads outside its image) inside ours.
  auto value = [&](int row, int col, int lane) {
    row = std::min(std::max(row, 0), height - 1);
    col = std::min(std::max(col, 0), width - 1);
    return samples[(size_t(row) * rowStride + col) * 4 + lane];
  };
  march(queue, flags.data(), kKnown, size_t(cols), [&](size_t s) {
    const int i = int(uint32_t(s) / uint32_t(cols)), j = int(uint32_t(s) % uint32_t(cols));
    const float t = arrival(f, tm, s, size_t(cols));
    time[s] = t;
    // OpenCV's time gradient: a central difference halved where both sides are known, a one-sided
    // one where one is, 0 where neither is. Without a branch: each side reads the sample's own time
    // where it is not known (t - t is 0; a one-sided difference times 1 is itself).
    const TimeGradientRule& own = kTimeGradientRules.rule[sides[s]];
    const Lanes here = {t, t, 0.0f, 0.0f};
    const Lanes after = {tm[s + 1], tm[s + cols], 0.0f, 0.0f}, before = {tm[s - 1], tm[s - cols], 0.0f, 0.0f};
    const Lanes gradT = (pick(own.after, after, here) - pick(own.before, before, here)) * own.scale;
    const float gradTx = gradT[0], gradTy = gradT[1];
    float* centre = samples + (size_t(i - 1) * rowStride + (j - 1)) * 4;
    float ia[4], jx[4] = {}, jy[4] = {}, sum = 1.0e-20f;
    if (i - range >= 2 && i + range <= rows - 3 && j - range >= 2 && j + range <= cols - 3) {
      // Away from the grid's edges: the neighbours that are known, then their sums.
      // Every neighbour's weight, known or not, lane by lane four at a time (the same float
      // operations, so the same bits): fewer divisions than one per known neighbour.
      const uint8_t* fc = f + s;
      const float* tc = tm + s;
      size_t knownCount = 0;
      for (size_t m = 0; m < offsetCount; ++m) {
        known[knownCount] = uint16_t(m);
        knownCount += fc[gridOffset[m]] != kInside;
        neighbourTime[m] = tc[gridOffset[m]];
      }
      for (size_t m = 0; m < offsetCount; ++m)
        weight[m] = neighbourWeight(rx[m], ry[m], distance[m], neighbourTime[m], t, gradTx, gradTy);
      if (likeOpenCv) {
        Lanes a, x, y;
        interiorSums(centre, gradientRule, sides + s, offsets.data(), gridOffset.data(), sampleOffset.data(), weight,
                     known.data(), knownCount, a, x, y, sum);
        std::memcpy(ia, &a, sizeof a);
        std::memcpy(jx, &x, sizeof x);
        std::memcpy(jy, &y, sizeof y);
      } else {
        // The weighted mean alone: one multiply-add of the neighbour's four planes.
        Lanes a = {};
        float total = sum;
        for (size_t e = 0; e < knownCount; ++e) {
          const size_t m = known[e];
          a += weight[m] * load(centre + sampleOffset[m]);
          total += weight[m];
        }
        std::memcpy(ia, &a, sizeof a);
        sum = total;
      }
    } else if (!likeOpenCv) {
      for (int p = 0; p < 4; ++p) ia[p] = 0;
      for (const Offset& o : offsets) {
        const int k = i + o.dRow, l = j + o.dCol;
        if (!interior(k, l)) continue;
        const size_t sn = at(k, l);
        if (f[sn] == kInside) continue;
        const float w = neighbourWeight(o, tm[sn], t, gradTx, gradTy);
        for (int p = 0; p < 4; ++p) ia[p] += w * value(k - 1, l - 1, p);
        sum += w;
      }
    } else {
      for (int p = 0; p < 4; ++p) ia[p] = jx[p] = jy[p] = 0;
      for (const Offset& o : offsets) {
        const int k = i + o.dRow, l = j + o.dCol;
        if (!interior(k, l)) continue;
        const size_t sn = at(k, l);
        if (f[sn] == kInside) continue;
        const float w = neighbourWeight(o, tm[sn], t, gradTx, gradTy);
        // OpenCV's picture rows and columns for the neighbour: the first row or column reads
        // the second; the last ones stay in the picture.
        const int km = k - 1 + (k == 1), kp = k - 1 - (k == rows - 2);
        const int lm = l - 1 + (l == 1), lp = l - 1 - (l == cols - 2);
        const bool right = f[sn + 1] != kInside, left = f[sn - 1] != kInside;
        const bool below = f[sn + cols] != kInside, above = f[sn - cols] != kInside;
        for (int p = 0; p < 4; ++p) {
          auto px = [&](int row, int col) { return value(row, col, p); };
          float gradIx, gradIy;
          if (right)
            gradIx = left ? float(px(km, lp + 1) - px(km, lm - 1)) * 2.0f : float(px(km, lp + 1) - px(km, lm));
          else
            gradIx = left ? float(px(km, lp) - px(km, lm - 1)) : 0.0f;
          if (below)
            gradIy = above ? float(px(kp + 1, lm) - px(km - 1, lm)) * 2.0f : float(px(kp + 1, lm) - px(km, lm));
          else
            gradIy = above ? float(px(kp, lm) - px(km - 1, lm)) : 0.0f;
          ia[p] += w * px(km, lm);
          jx[p] -= w * (gradIx * o.rx);
          jy[p] -= w * (gradIy * o.ry);
        }
        sum += w;
      }
    }
    if (!likeOpenCv) {
      const Lanes filled = load(ia) / sum + 0.5f;
      std::memcpy(centre, &filled, sizeof filled);
    } else {
#if defined(__SSE2__)
    // Lane by lane the float expression below (a square root and divisions are correctly rounded
    // in either form): one square root and two divisions for all planes instead of four each.
    const Lanes a = load(ia), x = load(jx), y = load(jy);
    const Lanes filled = a / sum + (x + y) / (Lanes(_mm_sqrt_ps(x * x + y * y)) + 1.0e-20f) + 0.5f;
    std::memcpy(centre, &filled, sizeof filled);
#else
    for (int p = 0; p < 4; ++p)
      centre[p] = float(ia[p] / sum + (jx[p] + jy[p]) / (std::sqrt(jx[p] * jx[p] + jy[p] * jy[p]) + 1.0e-20f) + 0.5f);
#endif
    }
    flags[s] = kBand;
    // s is known now: its neighbours' bits (s is the right one of s - 1, and so on).
    sides[s - 1] |= 1;
    sides[s + 1] |= 2;
    sides[s - cols] |= 4;
    sides[s + cols] |= 8;
    queue.push(s, t);
  });
}

}  // namespace vs
