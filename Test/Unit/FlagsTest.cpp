// Synth/Flags.h against plain loops over every sample.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

#include "Synth/Flags.h"

namespace vs {
namespace {

// Rows of every length from 0 to 40 and some longer, flags from none to all set, in runs and alone.
std::vector<std::vector<uint8_t>> flagRows() {
  std::mt19937 rng(7);
  std::vector<std::vector<uint8_t>> rows;
  for (int n : {0, 1, 2, 7, 8, 9, 15, 16, 17, 40, 63, 64, 65, 200, 688})
    for (double density : {0.0, 0.01, 0.05, 0.2, 0.5, 1.0})
      for (int repeat = 0; repeat < 3; ++repeat) {
        std::vector<uint8_t> row(static_cast<size_t>(n));
        std::bernoulli_distribution set(density);
        for (uint8_t& flag : row) flag = set(rng) ? 1 : 0;
        rows.push_back(row);
      }
  return rows;
}

TEST(Flags, ForEachFlagVisitsTheSetFlagsInOrder) {
  for (const std::vector<uint8_t>& row : flagRows()) {
    std::vector<int> expected, visited;
    for (int x = 0; x < int(row.size()); ++x)
      if (row[size_t(x)]) expected.push_back(x);
    forEachFlag(row.data(), int(row.size()), [&](int x) { visited.push_back(x); });
    EXPECT_EQ(visited, expected);
  }
}

TEST(Flags, ForEachRunVisitsTheRunsOfSetFlagsInOrder) {
  for (const std::vector<uint8_t>& row : flagRows()) {
    std::vector<std::pair<int, int>> expected, visited;
    for (int x = 0; x < int(row.size()); ++x)
      if (row[size_t(x)] && (x == 0 || !row[size_t(x) - 1])) {
        int end = x;
        while (end < int(row.size()) && row[size_t(end)]) ++end;
        expected.emplace_back(x, end);
      }
    forEachRun(row.data(), int(row.size()), [&](int begin, int end) { visited.emplace_back(begin, end); });
    EXPECT_EQ(visited, expected);
  }
}

TEST(Flags, MarkWithinReachMarksEverySampleNearASetFlagAndNoOther) {
  for (const std::vector<uint8_t>& row : flagRows())
    for (int reach : {0, 1, 3, 8, 40, 1000}) {
      const int n = int(row.size());
      std::vector<uint8_t> near(size_t(n), 7);  // stale values must go
      markWithinReach(row.data(), n, reach, near.data());
      for (int x = 0; x < n; ++x) {
        bool expected = false;
        for (int s = 0; s < n; ++s) expected = expected || (row[size_t(s)] && std::abs(x - s) <= reach);
        ASSERT_EQ(near[size_t(x)], expected ? 1 : 0) << "sample " << x << " of " << n << ", reach " << reach;
      }
    }
}

}  // namespace
}  // namespace vs
