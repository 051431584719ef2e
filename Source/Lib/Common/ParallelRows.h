#pragma once
// Rows split into one contiguous stripe per thread, on std::thread (vscommon does not link OpenCV).
// Callers keep results per row and combine them in row order, so no result depends on the thread count.
#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace vs {

// Threads a metric uses: `requested` when > 0, else the hardware's count (at least 1).
inline int metricThreads(int requested) {
  if (requested > 0) return requested;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware > 0 ? int(hardware) : 1;
}

// body(rowBegin, rowEnd) over [0, rows), on up to `threads` threads (the caller's thread is one of them).
template <class Body>
void parallelRows(int rows, int threads, const Body& body) {
  const int stripes = std::max(1, std::min(threads, rows));
  if (stripes == 1) {
    if (rows > 0) body(0, rows);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(size_t(stripes - 1));
  for (int s = 1; s < stripes; ++s) {
    const int begin = int(int64_t(rows) * s / stripes);
    const int end = int(int64_t(rows) * (s + 1) / stripes);
    workers.emplace_back([&body, begin, end] { body(begin, end); });
  }
  body(0, int(int64_t(rows) / stripes));
  for (std::thread& worker : workers) worker.join();
}

}  // namespace vs
