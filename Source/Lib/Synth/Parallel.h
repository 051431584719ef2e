#pragma once
// Work split over rows (or any index range) on OpenCV's thread pool; the thread count is set once per
// run from the Threads key (cv::setNumThreads). Every parallel loop in the synthesizer writes only
// its own rows, or combines by max (AtomicMaxBuffer), so the output is bit-identical whatever the
// number of threads.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "Synth/Raster.h"

namespace vs {

// Sets the pool's threads from the Threads key (0: every core), once per run before the first frame.
// The output does not depend on it.
inline void setWorkerThreads(int threads) { cv::setNumThreads(threads > 0 ? threads : cv::getNumberOfCPUs()); }

// Calls body(begin, end) on disjoint sub-ranges of [0, count); `stripes` as cv::parallel_for_'s
// nstripes (-1: as many as the pool likes).
template <class Body>
void parallelRanges(int count, const Body& body, double stripes = -1.0) {
  if (count <= 0) return;
  cv::parallel_for_(cv::Range(0, count), [&](const cv::Range& range) { body(range.start, range.end); }, stripes);
}

// parallelRanges() for loops over columns that scan every row: one sub-range per thread, so that each
// thread reads long runs of every row.
template <class Body>
void parallelColumns(int count, const Body& body) {
  parallelRanges(count, body, double(cv::getNumThreads()));
}

// Calls body(begin, end) on disjoint sub-ranges of [0, count) made of whole blocks of 64 Ki
// elements: for passes over a frame-sized array that has no rows.
template <class Body>
void parallelBlocks(size_t count, const Body& body) {
  constexpr size_t kBlock = size_t(1) << 16;
  parallelRanges(int((count + kBlock - 1) / kBlock), [&](int b0, int b1) {
    body(size_t(b0) * kBlock, std::min(count, size_t(b1) * kBlock));
  });
}

// Copies `from` into `to` (resized to match) on the threads: for frame-sized copies.
template <class T>
void copyOnThreads(const std::vector<T>& from, std::vector<T>& to) {
  to.resize(from.size());
  parallelBlocks(from.size(), [&](size_t begin, size_t end) {
    std::memcpy(to.data() + begin, from.data() + begin, (end - begin) * sizeof(T));
  });
}

// A z-buffer of inverse depths that many threads may raise at once (one writer needs none of this:
// Raster.h's raiseCell on plain doubles keeps the same values). Non-negative doubles order like
// their bit patterns read as signed integers, and kNoDepth (-1) reads as a negative one, so an
// integer atomic max is a max of the doubles; the result does not depend on the order of writes.
class AtomicMaxBuffer {
public:
  // A frame-sized buffer is set on the threads.
  void reset(size_t size, double value) {
    if (cells_.size() != size) cells_ = std::vector<std::atomic<int64_t>>(size);
    const int64_t bits = toBits(value);
    parallelBlocks(size, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) cells_[i].store(bits, std::memory_order_relaxed);
    });
  }
  void raise(size_t i, double value) { raiseAtomicCell(cells_[i], value); }
  // The cells, for the rasteriser's kernels (Synth/Kernels/QuadRow.h: AtomicRaise on them).
  std::atomic<int64_t>* cells() { return cells_.data(); }
  // Cells [begin, end) as doubles into out[0 .. end - begin).
  void copyTo(size_t begin, size_t end, double* out) const {
    for (size_t i = begin; i < end; ++i) out[i - begin] = fromBits(cells_[i].load(std::memory_order_relaxed));
  }

private:
  static int64_t toBits(double v) {
    int64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return bits;
  }
  static double fromBits(int64_t bits) {
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  std::vector<std::atomic<int64_t>> cells_;
};

}  // namespace vs
