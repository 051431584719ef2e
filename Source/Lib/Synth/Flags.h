#pragma once
// Lines of byte flags (1 set, 0 clear) in which few are set: depth edges along a row. Found eight
// flags at a time, so that the clear stretches cost one load and one test per eight samples.
#include <algorithm>
#include <cstdint>
#include <cstring>

namespace vs {

// Calls f(x) for every x in [0, n) with flags[x] set, in increasing order.
template <class F>
void forEachFlag(const uint8_t* flags, int n, F&& f) {
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    uint64_t eight;
    std::memcpy(&eight, flags + x, sizeof eight);
    if (eight == 0) continue;
    for (int k = 0; k < 8; ++k)
      if (flags[x + k]) f(x + k);
  }
  for (; x < n; ++x)
    if (flags[x]) f(x);
}

// Calls f(begin, end) for every run [begin, end) of set flags in [0, n), from left to right.
template <class F>
void forEachRun(const uint8_t* flags, int n, F&& f) {
  for (int x = 0; x < n;) {
    uint64_t eight;
    if (x + 8 <= n && (std::memcpy(&eight, flags + x, sizeof eight), eight == 0)) {
      x += 8;
      continue;
    }
    if (!flags[x]) {
      ++x;
      continue;
    }
    int end = x + 1;
    while (end < n && flags[end]) ++end;
    f(x, end);
    x = end;
  }
}

// near[x] = 1 where some flags[s] is set with |x - s| <= reach, else 0, for x in [0, n). Each set
// flag marks its reach, starting where the previous one's ended when they overlap.
inline void markWithinReach(const uint8_t* flags, int n, int reach, uint8_t* near) {
  std::fill(near, near + std::max(n, 0), uint8_t(0));
  int marked = 0;  // samples [0, marked) are done
  forEachFlag(flags, n, [&](int s) {
    const int from = std::max(std::max(s - reach, 0), marked), to = std::min(s + reach + 1, n);
    if (to > from) std::fill(near + from, near + to, uint8_t(1));
    marked = std::max(marked, to);
  });
}

}  // namespace vs
