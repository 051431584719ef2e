// libFuzzer target: the config parser (Config::fromText with ViewSyn's option table, then SynthesisSettings).
// Built with -DVS_FUZZ=ON and clang; run by scripts/fuzz.sh. The body is vs::fuzz::fuzzConfig (FuzzTargets.h),
// which the corpus replay test runs too.
#include <cstddef>
#include <cstdint>

#include "Fuzz/FuzzTargets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vs::fuzz::fuzzConfig(data, size);
  return 0;
}
