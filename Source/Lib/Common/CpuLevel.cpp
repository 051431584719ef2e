#include "Common/CpuLevel.h"

#include <atomic>
#include <cstdlib>

#include "Common/Config.h"
#include "Common/Error.h"

// The level all files are compiled for and the highest level with kernels in the binary; CMake defines
// both (Source/Lib/CMakeLists.txt).
#ifndef VS_COMPILED_X86_64_LEVEL
#define VS_COMPILED_X86_64_LEVEL 0
#endif
#ifndef VS_HIGHEST_X86_64_LEVEL
#define VS_HIGHEST_X86_64_LEVEL VS_COMPILED_X86_64_LEVEL
#endif

namespace vs {
namespace {

struct LevelState {
  int cap = 4;
  std::string origin;
};

LevelState& levelState() {
  static LevelState state;
  return state;
}

std::atomic<int> chosenLevel{-1};

}  // namespace

int cpuX86Level() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  // The level names need GCC 12 or clang 16; the features below are what the psABI lists per level.
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") &&
      __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2"))
    return 4;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
      __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("avx"))
    return 3;
  if (__builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("sse4.1") && __builtin_cpu_supports("ssse3") &&
      __builtin_cpu_supports("popcnt"))
    return 2;
  return 1;
#else
  return 0;
#endif
}

int compiledX86Level() { return VS_COMPILED_X86_64_LEVEL; }

int x86Level() {
  int level = chosenLevel.load(std::memory_order_acquire);
  if (level >= 0) return level;
  const LevelState& state = levelState();
  level = cpuX86Level();
  if (level > 0) {
    if (level > state.cap) level = state.cap;
    if (level > VS_HIGHEST_X86_64_LEVEL) level = VS_HIGHEST_X86_64_LEVEL;
    if (level < VS_COMPILED_X86_64_LEVEL) level = VS_COMPILED_X86_64_LEVEL;
  }
  chosenLevel.store(level, std::memory_order_release);
  return level;
}

std::string x86LevelOrigin() {
  const int level = x86Level();
  const LevelState& state = levelState();
  if (level == 0) return "no x86-64 kernels";
  if (VS_HIGHEST_X86_64_LEVEL == VS_COMPILED_X86_64_LEVEL)
    return "pinned build: every file compiled for this level";
  if (level == state.cap && !state.origin.empty()) return "capped by " + state.origin;
  if (level == VS_HIGHEST_X86_64_LEVEL && level < cpuX86Level()) return "the highest this binary has";
  return "the CPU's highest";
}

void capX86Level(int level, const std::string& origin) {
  VS_CHECK_MSG(chosenLevel.load() < 0, "the x86-64 level is capped before it is first used");
  if (level < 1 || level > 4) throw InputError(origin + ": expected an x86-64 level 1, 2, 3 or 4");
  if (cpuX86Level() > 0 && level < VS_COMPILED_X86_64_LEVEL)
    throw InputError(origin + ": this build is compiled for x86-64-v" + std::to_string(VS_COMPILED_X86_64_LEVEL) +
                     " throughout (CMake VS_X86_64_LEVEL) and cannot run a lower level");
  LevelState& state = levelState();
  state.cap = level;
  state.origin = origin;
}

void capX86LevelFromEnvironment() {
  const char* value = std::getenv("VS_X86_64_LEVEL");
  if (!value || !*value) return;
  int64_t level = 0;
  const std::string origin = std::string("VS_X86_64_LEVEL=") + value;
  if (!parseInt(value, level) || level < 1 || level > 4)
    throw InputError("environment variable " + origin + ": expected an x86-64 level 1, 2, 3 or 4");
  capX86Level(int(level), origin);
}

}  // namespace vs
