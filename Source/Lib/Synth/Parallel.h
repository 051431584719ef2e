#pragma once
// Work split over rows (or any index range) on the synthesizer's own thread pool (Parallel.cpp); the
// thread count is set once per run from the Threads key (setWorkerThreads). Every parallel loop in
// the synthesizer writes only its own rows, or combines by max (AtomicMaxBuffer), so the output is
// bit-identical whatever the number of threads.
//
// The pool is plain std::thread: its workers start on the first loop that can use them, or earlier on
// startWorkerThreads() (a few tens of microseconds each, nothing searched or loaded), wait on a
// condition variable between loops, and are left to the process's exit. A loop started inside another
// loop's body, or while another thread's loop holds the pool, runs on its caller's thread alone (as
// OpenCV's pool, which this replaces, ran nested loops).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "Synth/Raster.h"

namespace vs {

// Sets the pool's threads from the Threads key (0: every core this process may run on), once per run
// before the first frame. The output does not depend on it.
void setWorkerThreads(int threads);

// Starts the pool's workers now rather than at the first loop that can use them: for a caller about
// to load a library on another thread (a dlopen holds a lock of glibc's that creating a thread takes,
// so a worker started during the load would wait for its end, and the loop with it).
void startWorkerThreads();

// The threads a parallel loop uses now, the caller's included (at least 1).
int workerThreads();

// The cores this process may run on (its CPU affinity; at least 1).
int availableCores();

// Calls body(begin, end) on disjoint sub-ranges of [0, count), in `stripes` ranges of about equal
// size (<= 0: a few per thread), on the pool's threads and the caller's; returns when all are done.
// An exception from a body is rethrown here (the first one; the other ranges still run).
void parallelStripes(int count, int stripes, const std::function<void(int, int)>& body);

// Calls body(begin, end) on disjoint sub-ranges of [0, count); `stripes` as above (-1: a few per
// thread).
template <class Body>
void parallelRanges(int count, const Body& body, double stripes = -1.0) {
  if (count <= 0) return;
  parallelStripes(count, int(stripes), [&](int begin, int end) { body(begin, end); });
}

// parallelRanges() for loops over columns that scan every row: one sub-range per thread, so that each
// thread reads long runs of every row.
template <class Body>
void parallelColumns(int count, const Body& body) {
  parallelRanges(count, body, double(workerThreads()));
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
