#include "Synth/Cracks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "Synth/Flags.h"
#include "Synth/Kernels/Rows.h"
#include "Synth/Parallel.h"

namespace vs {

void closeCracks(std::vector<double>& inverseDepth, int width, int height, double tolerance,
                 ScratchPool<std::vector<uint8_t>>& flagRows) {
  double* const zbuffer = inverseDepth.data();
  // Closes the gap [gap1, gap2] between samples a and b when it is one (gap2 == gap1 for one sample).
  auto close = [zbuffer, tolerance](size_t a, size_t gap1, size_t gap2, size_t b, bool two) {
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
  };
  // A gap starts only where a sample lies more than the tolerance behind the one before it (close()
  // asks at least that), which few do: those are flagged for a whole line at a time in a branch-free
  // pass, and only they are visited.
  // Rows (each row by one thread). A gap closed at x changes samples x and x + 1, which the tests at
  // x + 1 and x + 2 read: from a flagged sample on, the samples are tested one by one on the current
  // values until two in a row have passed without a close; the flags beyond are still those of the
  // current values.
  parallelRanges(height, [&](int y0, int y1) {
    const auto flagsBuffer = flagRows.take();
    flagsBuffer->resize(size_t(width));
    uint8_t* flags = flagsBuffer->data();
    const double limit = tolerance;
    const RowKernels& kernels = rowKernels();  // the loops compiled for the CPU's x86-64 level
    for (int y = y0; y < y1; ++y) {
      const double* z = zbuffer + size_t(y) * width;
      const size_t rowStart = size_t(y) * width;
      if (width > 2) kernels.behindFlags(z, z + 1, width - 2, limit, flags + 1);  // flags[x]: z[x] < z[x - 1] - limit
      int done = 0;  // samples up to here have been tested
      forEachFlag(flags + 1, std::max(width - 2, 0), [&](int offset) {
        int x = offset + 1;
        if (x <= done) return;
        for (int last = x; x <= last && x + 1 < width; ++x) {
          const size_t i = rowStart + size_t(x);
          if (!(zbuffer[i] < zbuffer[i - 1] - limit)) continue;
          if (close(i - 1, i, i, i + 1, false) || (x + 2 < width && close(i - 1, i, i + 1, i + 2, true))) last = x + 2;
        }
        done = x - 1;
      });
    }
  });
  // Then columns (each thread its range of columns, row by row in memory order). A gap closed in row
  // y changes that column's rows y and y + 1 only: a row's flags, found before it is visited, stay
  // those of the current values for the whole row.
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
        if (!close(up, i, i, down, false) && y + 2 < height) close(up, i, down, down + stride, true);
      });
    }
  });
}

}  // namespace vs
