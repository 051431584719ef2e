// The synthesizer's thread pool (Synth/Parallel.h): every index of a loop is visited exactly once
// whatever the thread and stripe counts, nested loops and loops started by two threads at once run
// to the end, and an exception in a body reaches the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "Synth/Parallel.h"

namespace vs {
namespace {

// Restores the pool's thread count at the end of a test.
struct ThreadsRestored {
  int before = workerThreads();
  ~ThreadsRestored() { setWorkerThreads(before); }
};

// Counts, per index, how many body calls covered it; checks the ranges lie inside [0, count).
std::vector<int> visits(int count, int stripes) {
  std::vector<std::atomic<int>> seen(size_t(std::max(count, 0)));
  std::atomic<bool> outside{false};
  parallelStripes(count, stripes, [&](int begin, int end) {
    if (begin < 0 || end > count || begin >= end) outside = true;
    for (int i = std::max(begin, 0); i < std::min(end, count); ++i) seen[size_t(i)]++;
  });
  EXPECT_FALSE(outside) << count << " " << stripes;
  std::vector<int> result;
  for (const auto& s : seen) result.push_back(s.load());
  return result;
}

TEST(Parallel, EveryIndexOnceForAnyThreadAndStripeCount) {
  ThreadsRestored restore;
  for (int threads : {1, 2, 3, 8})
    for (int count : {0, 1, 2, 3, 7, 64, 1000})
      for (int stripes : {-1, 1, 2, 5, 64, 5000}) {
        setWorkerThreads(threads);
        EXPECT_EQ(workerThreads(), threads);
        const std::vector<int> seen = visits(count, stripes);
        for (int i = 0; i < count; ++i)
          ASSERT_EQ(seen[size_t(i)], 1) << "index " << i << " of " << count << ", " << threads << " threads, "
                                        << stripes << " stripes";
      }
}

TEST(Parallel, UsesSeveralThreadsAndRunsNestedLoopsOnTheCaller) {
  ThreadsRestored restore;
  setWorkerThreads(2);
  std::mutex mutex;
  std::set<std::thread::id> outer;
  std::atomic<int> inner{0};
  std::atomic<bool> innerElsewhere{false};
  parallelRanges(64, [&](int begin, int end) {
    const std::thread::id self = std::this_thread::get_id();
    {
      std::lock_guard<std::mutex> lock(mutex);
      outer.insert(self);
    }
    for (int i = begin; i < end; ++i) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      parallelRanges(10, [&](int b, int e) {
        if (std::this_thread::get_id() != self) innerElsewhere = true;
        inner += e - b;
      });
    }
  });
  EXPECT_EQ(outer.size(), 2u);  // the caller and one worker
  EXPECT_EQ(inner.load(), 640);
  EXPECT_FALSE(innerElsewhere);
}

TEST(Parallel, LoopsFromTwoThreadsAtOnceBothFinish) {
  ThreadsRestored restore;
  setWorkerThreads(2);
  std::atomic<long> sum[2] = {{0}, {0}};
  auto loops = [&](int k) {
    for (int r = 0; r < 200; ++r)
      parallelRanges(100, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) sum[k] += i;
      });
  };
  std::thread other(loops, 1);
  loops(0);
  other.join();
  EXPECT_EQ(sum[0].load(), 200L * 4950);
  EXPECT_EQ(sum[1].load(), 200L * 4950);
}

TEST(Parallel, AnExceptionInABodyReachesTheCallerAndThePoolGoesOn) {
  ThreadsRestored restore;
  for (int threads : {1, 2}) {
    setWorkerThreads(threads);
    EXPECT_THROW(parallelRanges(50, [&](int begin, int end) {
                   if (begin <= 17 && 17 < end) throw std::runtime_error("body");
                 }),
                 std::runtime_error);
    const std::vector<int> seen = visits(100, -1);
    for (int i = 0; i < 100; ++i) ASSERT_EQ(seen[size_t(i)], 1) << threads;
  }
}

}  // namespace
}  // namespace vs
