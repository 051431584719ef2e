#pragma once
// The x86-64 micro-architecture level of the code in use: 1 the baseline (SSE2), 2 (SSE4.2, POPCNT),
// 3 (AVX2, FMA, BMI2), 4 (AVX-512 F, BW, CD, DQ, VL); 0 on a processor that is not x86-64. The level is
// the lowest of: what the CPU runs, a cap (environment variable VS_X86_64_LEVEL or the option
// --x86-64-level), and the highest level this binary has code for; it is never below the level the
// whole binary is compiled for (CMake's VS_X86_64_LEVEL). Every level gives the same output bits.
#include <string>

namespace vs {

int cpuX86Level();       // the highest level this CPU runs (0: not x86-64)
int compiledX86Level();  // the level every file of this binary is compiled for (0: not x86-64)
int x86Level();          // the level in use (fixed at the first call)
std::string x86LevelOrigin();  // why that level: "the CPU's highest", "capped by VS_X86_64_LEVEL=2", ...

// Caps the level (the option --x86-64-level; `origin` names it in reports). Throws InputError when
// `level` is not 1 to 4 or is below compiledX86Level(). Call before the first x86Level().
void capX86Level(int level, const std::string& origin);
// Reads the environment variable VS_X86_64_LEVEL (unset or empty: no cap); throws InputError on a bad
// value.
void capX86LevelFromEnvironment();

}  // namespace vs
