#include "Synth/Cracks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "Synth/Flags.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

// Closes the gap [gap1, gap2] of `zbuffer` between samples a and b when it is one (gap2 == gap1 for one
// sample).
inline bool closeGap(double* zbuffer, double tolerance, size_t a, size_t gap1, size_t gap2, size_t b, bool two) {
  const double wa = zbuffer[a], wb = zbuffer[b];
  if (wa < 0 || wb < 0 || std::fabs(wa - wb) > tolerance) return false;
  const double behind = std::min(wa, wb) - tolerance;  // kNoDepth is behind everything
  if (!(zbuffer[gap1] < behind) || (two && !(zbuffer[gap2] < behind))) return false;
  if (two) {
    zbuffer[gap1] = (2 * wa + wb) / 3;
    zbuffer[gap2] = (wa + 2 * wb) / 3;
  } else {
    zbuffer[gap1] = 0.5 * (wa + wb);
  }
  return true;
}

}  // namespace

void closeRowCracks(double* z, int width, double tolerance, uint8_t* flags) {
  // A gap starts only where a sample lies more than the tolerance behind the one before it (closeGap
  // asks at least that), which few do: those are flagged for the whole row in a branch-free pass, and
  // only they are visited. A gap closed at x changes samples x and x + 1, which the tests at x + 1 and
  // x + 2 read: from a flagged sample on, the samples are tested one by one on the current values until
  // two in a row have passed without a close; the flags beyond are still those of the current values.
  const double limit = tolerance;
  if (width > 2) rowKernels().behindFlags(z, z + 1, width - 2, limit, flags + 1);  // flags[x]: z[x] < z[x - 1] - limit
  int done = 0;  // samples up to here have been tested
  forEachFlag(flags + 1, std::max(width - 2, 0), [&](int offset) {
    int x = offset + 1;
    if (x <= done) return;
    for (int last = x; x <= last && x + 1 < width; ++x) {
      const size_t i = size_t(x);
      if (!(z[i] < z[i - 1] - limit)) continue;
      if (closeGap(z, limit, i - 1, i, i, i + 1, false) || (x + 2 < width && closeGap(z, limit, i - 1, i, i + 1, i + 2, true)))
        last = x + 2;
    }
    done = x - 1;
  });
}

void closeColumnCracks(std::vector<double>& inverseDepth, int width, int height, double tolerance,
                       ScratchPool<std::vector<uint8_t>>& flagRows) {
  double* const zbuffer = inverseDepth.data();
  // Each thread its range of columns, row by row in memory order. A gap closed in row y changes that
  // column's rows y and y + 1 only: a row's flags, found before it is visited, stay those of the
  // current values for the whole row.
  parallelColumns(width, [&](int x0, int x1) {
    const auto flagsBuffer = flagRows.take();
    flagsBuffer->resize(size_t(width));
    uint8_t* flags = flagsBuffer->data();
    const double limit = tolerance;
    const size_t stride = size_t(width);
    const RowKernels& kernels = rowKernels();
    for (int y = 1; y + 1 < height; ++y) {
      const double* z = zbuffer + size_t(y) * stride;
      const double* above = z - stride;
      kernels.behindFlags(above + x0, z + x0, x1 - x0, limit, flags);  // flags[x - x0]: z[x] < above[x] - limit
      forEachFlag(flags, x1 - x0, [&](int offset) {
        const size_t i = size_t(y) * stride + size_t(x0 + offset), up = i - stride, down = i + stride;
        if (!closeGap(zbuffer, limit, up, i, i, down, false) && y + 2 < height)
          closeGap(zbuffer, limit, up, i, down, down + stride, true);
      });
    }
  });
}

void closeCracks(std::vector<double>& inverseDepth, int width, int height, double tolerance,
                 ScratchPool<std::vector<uint8_t>>& flagRows) {
  // Rows (each row by one thread), then columns.
  parallelRanges(height, [&](int y0, int y1) {
    const auto flagsBuffer = flagRows.take();
    flagsBuffer->resize(size_t(width));
    for (int y = y0; y < y1; ++y) closeRowCracks(inverseDepth.data() + size_t(y) * width, width, tolerance, flagsBuffer->data());
  });
  closeColumnCracks(inverseDepth, width, height, tolerance, flagRows);
}

}  // namespace vs
