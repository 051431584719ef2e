// libFuzzer target: the MPEG-I camera JSON parser (parseCameraJson, with the JSON reader under it).
// Built with -DVS_FUZZ=ON and clang; run by scripts/fuzz.sh. The body is vs::fuzz::fuzzCameraJson
// (FuzzTargets.h), which the corpus replay test runs too.
#include <cstddef>
#include <cstdint>

#include "Fuzz/FuzzTargets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vs::fuzz::fuzzCameraJson(data, size);
  return 0;
}
