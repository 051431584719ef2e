// Chooses the rasteriser's kernels by x86Level() among the levels compiled in (VS_KERNEL_LEVEL_1 .. 4,
// defined by Source/Lib/Synth/area.cmake for this file).
#include "Common/CpuLevel.h"
#include "Common/Error.h"
#include "Synth/Kernels/QuadRow.h"

namespace vs {

#define VS_DECLARE_LEVEL(ns) \
  namespace ns {             \
  extern const QuadRowKernels quadRowKernelsOfLevel; \
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

const QuadRowKernels* quadRowKernelsFor(int level) {
  switch (level) {
#if defined(VS_KERNEL_LEVEL_1)
    case 1: return &v1::quadRowKernelsOfLevel;
#endif
#if defined(VS_KERNEL_LEVEL_2)
    case 2: return &v2::quadRowKernelsOfLevel;
#endif
#if defined(VS_KERNEL_LEVEL_3)
    case 3: return &v3::quadRowKernelsOfLevel;
#endif
#if defined(VS_KERNEL_LEVEL_4)
    case 4: return &v4::quadRowKernelsOfLevel;
#endif
#if defined(VS_KERNEL_LEVEL_0)
    case 0: return &v0::quadRowKernelsOfLevel;
#endif
    default: return nullptr;
  }
}

const QuadRowKernels& quadRowKernels() {
  // The level in use, or the highest below it compiled in (a compiler without -march=x86-64-vN).
  static const QuadRowKernels* const chosen = [] {
    const QuadRowKernels* kernels = nullptr;
    for (int level = x86Level(); level >= 0 && !kernels; --level) kernels = quadRowKernelsFor(level);
    return kernels;
  }();
  VS_CHECK_MSG(chosen != nullptr, "kernels compiled for the x86-64 level in use");
  return *chosen;
}

}  // namespace vs
