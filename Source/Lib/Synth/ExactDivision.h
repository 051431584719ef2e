#pragma once
// Division by a power of two without a division instruction, bit for bit.
#include <cstdint>
#include <cstring>

namespace vs {

// 1 / d when d is a power of two (of either sign) whose reciprocal is a normal double, else 0. Then
// x * exactReciprocal(d) is x / d bit for bit: both round the same exact quotient, x * 2^-k.
inline double exactReciprocal(double d) {
  uint64_t bits;
  std::memcpy(&bits, &d, sizeof bits);
  const uint64_t exponent = (bits >> 52) & 0x7ff, mantissa = bits & ((uint64_t(1) << 52) - 1);
  if (mantissa != 0 || exponent == 0 || exponent >= 2046) return 0.0;  // not a power of two, 0, subnormal, inf, NaN
  const uint64_t inverse = (bits & (uint64_t(1) << 63)) | ((2046 - exponent) << 52);
  double r;
  std::memcpy(&r, &inverse, sizeof r);
  return r;
}

}  // namespace vs
