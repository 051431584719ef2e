// libFuzzer target: the VSRS camera file parser (parseCameraText), with a write-read round trip.
// Built with -DVS_FUZZ=ON and clang; run by scripts/fuzz.sh. The body is vs::fuzz::fuzzCameraFile (FuzzTargets.h),
// which the corpus replay test runs too.
#include <cstddef>
#include <cstdint>

#include "Fuzz/FuzzTargets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vs::fuzz::fuzzCameraFile(data, size);
  return 0;
}
