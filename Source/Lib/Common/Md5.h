#pragma once
// MD5 (RFC 1321) of bytes and files, for pinning outputs: the golden-output test and the tools'
// --verify option compare a file's digest with a stored one (as dav1d's --verify does). MD5 is used
// here as a checksum of our own outputs, never for security.
#include <cstddef>
#include <cstdint>
#include <string>

namespace vs {

class Md5 {
public:
  Md5();
  void update(const void* data, size_t bytes);
  // The digest as 32 lower-case hexadecimal digits; the object is spent afterwards (VS_CHECK).
  std::string hexDigest();

private:
  void block(const uint8_t* chunk);

  uint32_t state_[4];
  uint64_t totalBytes_ = 0;
  uint8_t pending_[64];
  size_t pendingBytes_ = 0;
  bool finished_ = false;
};

std::string md5Hex(const void* data, size_t bytes);
// The MD5 of a whole file; throws InputError naming the file when it cannot be read.
std::string md5OfFile(const std::string& path);

}  // namespace vs
