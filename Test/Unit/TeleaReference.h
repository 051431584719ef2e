#pragma once
// A plain Telea inpainting of one float plane without OpenCV's outward march and colour-gradient term
// (luma's), written from Synth/Telea.h's description, one sample at a time and without any of
// Telea.cpp's shortcuts (no seed list, no heap keys, no known-side bytes, no lanes, no interior fast
// path): the reference that teleaInpaint(..., likeOpenCv = false) and the hole filling's luma are
// tested against.
//   - A grid one sample wider on every side; mask samples are "inside", the rest known. The band:
//     known samples of the picture beside (4-neighbours) a mask sample. Every known sample of the
//     picture is at time 0 (OpenCV's outward march, which gives those near the mask negative
//     times, is left out), the grid's border at 1e6.
//   - The inward march from the band: each sample reached gets its arrival time, its time gradient
//     and, from its known neighbours within `radius` (Euclidean), the weighted mean of their colours
//     plus 0.5; weight = |1 / |r|^3 x 1 / (1 + |T_neighbour - T|) x (r . grad T)|, the last factor
//     1e-6 where it is at most 0.01 in magnitude; r = sample - neighbour.
//   - Samples leave a march's queue by time, equal times in the order they entered.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace vs {
namespace reference {

inline std::vector<float> plainTeleaMean(const std::vector<uint8_t>& mask, int w, int h,
                                         const std::vector<float>& plane, int radius) {
  enum : uint8_t { kKnown, kInside };
  const int rows = h + 2, cols = w + 2;
  auto at = [&](int r, int c) { return size_t(r) * cols + c; };
  auto interior = [&](int r, int c) { return r >= 1 && c >= 1 && r <= rows - 2 && c <= cols - 2; };
  std::vector<uint8_t> flag(size_t(rows) * cols, kKnown);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (mask[size_t(y) * w + x]) flag[at(y + 1, x + 1)] = kInside;
  std::vector<float> time(flag.size(), 1.0e6f);
  std::vector<size_t> band;
  for (int r = 1; r < rows - 1; ++r)
    for (int c = 1; c < cols - 1; ++c) {
      const size_t s = at(r, c);
      if (flag[s] != kInside && (flag[s - 1] == kInside || flag[s + 1] == kInside || flag[s - cols] == kInside ||
                                 flag[s + cols] == kInside)) {
        band.push_back(s);
        time[s] = 0.0f;
      }
    }
  // Arrival time at s from the pairs (up or down, left or right) of `f`'s known neighbours.
  auto arrival = [&](const std::vector<uint8_t>& f, size_t s) {
    float best = 1.0e30f;
    for (const size_t a : {s - cols, s + cols})
      for (const size_t b : {s - 1, s + 1}) {
        const double ta = time[a], tb = time[b], lower = std::min(ta, tb);
        const bool aKnown = f[a] != kInside, bKnown = f[b] != kInside;
        double t;
        if (aKnown && bKnown)
          t = std::fabs(ta - tb) >= 1.0 ? 1 + lower : (ta + tb + std::sqrt(2 - (ta - tb) * (ta - tb))) * 0.5;
        else if (aKnown)
          t = 1 + ta;
        else if (bKnown)
          t = 1 + tb;
        else
          t = 1 + lower;
        best = std::min(best, float(t));
      }
    return best;
  };
  // A march: pops by (time, order of entry), calls reach(s) for each inside 4-neighbour, which sets
  // its time and flag; reached samples enter the queue.
  auto march = [&](std::vector<uint8_t>& f, auto reach) {
    std::map<std::pair<float, long>, size_t> queue;
    long order = 0;
    for (const size_t s : band) queue[{0.0f, order++}] = s;
    std::vector<size_t> reached;
    while (!queue.empty()) {
      const size_t s = queue.begin()->second;
      queue.erase(queue.begin());
      for (const size_t n : {s - cols, s - 1, s + cols, s + 1}) {
        if (f[n] != kInside) continue;
        reach(n);
        f[n] = kKnown;
        reached.push_back(n);
        queue[{time[n], order++}] = n;
      }
    }
    return reached;
  };
  // Every known sample of the picture at time 0 (no outward march).
  for (int r = 1; r < rows - 1; ++r)
    for (int c = 1; c < cols - 1; ++c)
      if (flag[at(r, c)] != kInside) time[at(r, c)] = 0.0f;
  // Inward.
  std::vector<float> out = plane;
  march(flag, [&](size_t n) {
    const float t = arrival(flag, n);
    time[n] = t;
    auto known = [&](size_t q) { return flag[q] != kInside; };
    float gx = 0, gy = 0;
    if (known(n + 1) && known(n - 1)) gx = (time[n + 1] - time[n - 1]) * 0.5f;
    else if (known(n + 1)) gx = time[n + 1] - t;
    else if (known(n - 1)) gx = t - time[n - 1];
    if (known(n + cols) && known(n - cols)) gy = (time[n + cols] - time[n - cols]) * 0.5f;
    else if (known(n + cols)) gy = time[n + cols] - t;
    else if (known(n - cols)) gy = t - time[n - cols];
    const int i = int(n / cols), j = int(n % cols);
    float sum = 1.0e-20f, weighted = 0;
    for (int dr = -radius; dr <= radius; ++dr)
      for (int dc = -radius; dc <= radius; ++dc) {
        if (dr * dr + dc * dc > radius * radius || (dr == 0 && dc == 0)) continue;
        const int k = i + dr, l = j + dc;
        if (!interior(k, l) || !known(at(k, l))) continue;
        const float rx = float(-dc), ry = float(-dr), length = rx * rx + ry * ry;
        const float distance = float(1. / (length * std::sqrt(length)));
        const float level = 1.0f / (1.0f + std::fabs(time[at(k, l)] - t));
        float dir = rx * gx + ry * gy;
        if (std::fabs(dir) <= 0.01f) dir = 0.000001f;
        const float weight = std::fabs(distance * level * dir);
        weighted += weight * out[size_t(k - 1) * w + (l - 1)];
        sum += weight;
      }
    out[size_t(i - 1) * w + (j - 1)] = weighted / sum + 0.5f;
  });
  return out;
}

}  // namespace reference
}  // namespace vs
