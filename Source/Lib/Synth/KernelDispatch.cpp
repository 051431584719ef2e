// Chooses the kernels (the rasteriser's, Kernels/QuadRow.h, and the row loops', Kernels/Rows.h) by
// x86Level() among the levels compiled in (VS_KERNEL_LEVEL_1 .. 4, defined by
// Source/Lib/Synth/area.cmake for this file).
#include "Common/CpuLevel.h"
#include "Common/Error.h"
#include "Synth/Kernels/QuadRow.h"
#include "Synth/Kernels/Rows.h"

namespace vs {

#define VS_DECLARE_LEVEL(ns) \
  namespace ns {             \
  extern const QuadRowKernels quadRowKernelsOfLevel; \
  extern const RowKernels rowKernelsOfLevel;         \
  }
#if defined(VS_KERNEL_LEVEL_0)
VS_DECLARE_LEVEL(v0)
#endif
#if defined(VS_KERNEL_LEVEL_1)
VS_DECLARE_LEVEL(v1)
#endif
#if defined(VS_KERNEL_LEVEL_2)
VS_DECLARE_LEVEL(v2)
#endif
#if defined(VS_KERNEL_LEVEL_3)
VS_DECLARE_LEVEL(v3)
#endif
#if defined(VS_KERNEL_LEVEL_4)
VS_DECLARE_LEVEL(v4)
#endif
#undef VS_DECLARE_LEVEL

// The table of `level` (member `table` of namespace vN), nullptr when none is compiled in.
#define VS_TABLE_OF_LEVEL(Type, table)                          \
  const Type* table##For(int level) {                           \
    switch (level) {                                            \
      VS_CASE_LEVEL_1(table)                                    \
      VS_CASE_LEVEL_2(table)                                    \
      VS_CASE_LEVEL_3(table)                                    \
      VS_CASE_LEVEL_4(table)                                    \
      VS_CASE_LEVEL_0(table)                                    \
      default: return nullptr;                                  \
    }                                                           \
  }
#if defined(VS_KERNEL_LEVEL_0)
#define VS_CASE_LEVEL_0(table) case 0: return &v0::table##OfLevel;
#else
#define VS_CASE_LEVEL_0(table)
#endif
#if defined(VS_KERNEL_LEVEL_1)
#define VS_CASE_LEVEL_1(table) case 1: return &v1::table##OfLevel;
#else
#define VS_CASE_LEVEL_1(table)
#endif
#if defined(VS_KERNEL_LEVEL_2)
#define VS_CASE_LEVEL_2(table) case 2: return &v2::table##OfLevel;
#else
#define VS_CASE_LEVEL_2(table)
#endif
#if defined(VS_KERNEL_LEVEL_3)
#define VS_CASE_LEVEL_3(table) case 3: return &v3::table##OfLevel;
#else
#define VS_CASE_LEVEL_3(table)
#endif
#if defined(VS_KERNEL_LEVEL_4)
#define VS_CASE_LEVEL_4(table) case 4: return &v4::table##OfLevel;
#else
#define VS_CASE_LEVEL_4(table)
#endif

VS_TABLE_OF_LEVEL(QuadRowKernels, quadRowKernels)
VS_TABLE_OF_LEVEL(RowKernels, rowKernels)

namespace {

// The table of the level in use, or of the highest below it compiled in (a compiler without
// -march=x86-64-vN).
template <class Table>
const Table& chooseTable(const Table* (*tableFor)(int)) {
  const Table* table = nullptr;
  for (int level = x86Level(); level >= 0 && !table; --level) table = tableFor(level);
  VS_CHECK_MSG(table != nullptr, "kernels compiled for the x86-64 level in use");
  return *table;
}

}  // namespace

const QuadRowKernels& quadRowKernels() {
  static const QuadRowKernels& chosen = chooseTable(quadRowKernelsFor);
  return chosen;
}

const RowKernels& rowKernels() {
  static const RowKernels& chosen = chooseTable(rowKernelsFor);
  return chosen;
}

}  // namespace vs
