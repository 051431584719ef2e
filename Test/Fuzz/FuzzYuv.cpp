// libFuzzer target: the YUV reader (YuvReader::read and readLuma on a temporary file), with a read-write round trip.
// Built with -DVS_FUZZ=ON and clang; run by scripts/fuzz.sh. The body is vs::fuzz::fuzzYuv (FuzzTargets.h),
// which the corpus replay test runs too.
#include <cstddef>
#include <cstdint>

#include "Fuzz/FuzzTargets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vs::fuzz::fuzzYuv(data, size);
  return 0;
}
