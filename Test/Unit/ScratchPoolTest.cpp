// ScratchPool: the working buffers of parallel loop bodies (Synth/ScratchPool.h), which replaced the
// thread_local buffers (BUG-5 in doc/stability.md).
#include <atomic>
#include <cstdint>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Memory.h"
#include "Synth/Parallel.h"
#include "Synth/ScratchPool.h"

namespace vs {
namespace {

struct Counted {
  static std::atomic<int> made;
  Counted() { ++made; }
  std::vector<int> buffer;
};
std::atomic<int> Counted::made{0};

TEST(ScratchPool, LeasesHeldAtOnceAreDistinctAndReturnedOnesAreReused) {
  ScratchPool<Counted> pool;
  Counted::made = 0;
  const Counted* first;
  const Counted* second;
  {
    const auto a = pool.take();
    const auto b = pool.take();
    first = &*a;
    second = &*b;
    EXPECT_NE(first, second);
  }
  EXPECT_EQ(Counted::made.load(), 2);
  {
    const auto c = pool.take();
    EXPECT_TRUE(&*c == first || &*c == second);
  }
  EXPECT_EQ(Counted::made.load(), 2);
  // A copy of the pool does not share its sets.
  ScratchPool<Counted> copy(pool);
  const auto d = copy.take();
  EXPECT_TRUE(&*d != first && &*d != second);
  EXPECT_EQ(Counted::made.load(), 3);
}

// prepare() makes the sets a pool lacks and passes every set it holds to the sizing function; the
// bodies that take them later find them so, and no further set is made for as many bodies at once.
TEST(ScratchPool, PreparedSetsAreMadeAheadAndSizedOnce) {
  ScratchPool<Counted> pool;
  Counted::made = 0;
  int calls = 0;
  pool.prepare(3, [&](Counted& set) {
    ++calls;
    set.buffer.resize(17);
  });
  EXPECT_EQ(Counted::made.load(), 3);
  EXPECT_EQ(calls, 3);
  {
    const auto a = pool.take();
    const auto b = pool.take();
    const auto c = pool.take();
    EXPECT_TRUE(&*a != &*b && &*b != &*c && &*a != &*c);
    for (const Counted* set : {&*a, &*b, &*c}) EXPECT_EQ(set->buffer.size(), 17u);
  }
  EXPECT_EQ(Counted::made.load(), 3);
  // Fewer asked for than held: every held set is passed again, none made.
  pool.prepare(1, [&](Counted& set) {
    ++calls;
    set.buffer.resize(5);
  });
  EXPECT_EQ(Counted::made.load(), 3);
  EXPECT_EQ(calls, 6);
  const auto d = pool.take();
  EXPECT_EQ(d->buffer.size(), 5u);
}

// In parallel loops a set is held by one body at a time, and no more sets are made than bodies run
// at once (at most the thread count), however many bodies and loops there are.
TEST(ScratchPool, ParallelLoopsMakeNoMoreSetsThanThreadsAndNeverShareOne) {
  const int defaultThreads = vs::workerThreads();
  for (int threads : {1, 2, 4}) {
    vs::setWorkerThreads(threads);
    ScratchPool<Counted> pool;
    Counted::made = 0;
    std::atomic<int> shared{0};
    for (int loop = 0; loop < 20; ++loop)
      parallelRanges(1000, [&](int begin, int end) {
        const auto lease = pool.take();
        // Every body marks its set with its own range and finds the mark unchanged at its end.
        lease->buffer.assign(16, begin);
        for (int i = begin; i < end; ++i) lease->buffer[size_t(i % 16)] = begin;
        for (int value : lease->buffer) shared += value != begin;
      });
    EXPECT_EQ(shared.load(), 0) << threads << " threads";
    EXPECT_GE(Counted::made.load(), 1);
    EXPECT_LE(Counted::made.load(), std::max(threads, vs::workerThreads())) << threads << " threads";
  }
  vs::setWorkerThreads(defaultThreads);
}

}  // namespace
}  // namespace vs

// Small buffers come from the heap, large ones (Common/Memory.h: smallPageBuffersFrom()) from a
// mapping of their own: in both, what is written stays, growing gives room for every new element,
// and a smaller size keeps the memory (and the values). Every size goes each way once.
TEST(UntouchedBuffer, HoldsWhatIsWrittenAtEverySizeAndKeepsItsMemoryWhenNotGrowing) {
  const size_t usual = vs::smallPageBuffersFrom();
  for (const size_t from : {size_t(1), usual, SIZE_MAX}) {
    vs::setSmallPageBuffersFrom(from);
    for (const size_t size : {size_t(1), size_t(1000), size_t(3) << 20}) {
      vs::UntouchedBuffer<double> buffer;
      EXPECT_EQ(buffer.size(), 0u);
      buffer.resize(size);
      ASSERT_EQ(buffer.size(), size);
      for (size_t i = 0; i < size; i += 4093) buffer[i] = double(i) + 0.5;
      buffer[size - 1] = -1.0;
      for (size_t i = 0; i + 1 < size; i += 4093) EXPECT_EQ(buffer[i], double(i) + 0.5) << i;
      const double* before = buffer.data();
      buffer.resize(size / 2 + 1);
      EXPECT_EQ(buffer.data(), before);
      EXPECT_EQ(buffer.size(), size / 2 + 1);
      EXPECT_EQ(buffer[0], size > 1 ? 0.5 : -1.0);
      buffer.resize(2 * size + 7);  // grows: contents unspecified, every element writable
      for (size_t i = 0; i < buffer.size(); ++i) buffer[i] = 1.0;
      double sum = 0;
      for (size_t i = 0; i < buffer.size(); ++i) sum += buffer[i];
      EXPECT_EQ(sum, double(2 * size + 7));
    }
  }
  vs::setSmallPageBuffersFrom(usual);
}
