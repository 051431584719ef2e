// MD5: RFC 1321's own test suite (appendix A.5), chunked updates against one update, and a file
// against coreutils' md5sum where it is installed (an independent implementation).
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Error.h"
#include "Common/Md5.h"

namespace {

TEST(Md5, Rfc1321TestSuite) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "d41d8cd98f00b204e9800998ecf8427e"},
      {"a", "0cc175b9c0f1b6a831c399e269772661"},
      {"abc", "900150983cd24fb0d6963f7d28e17f72"},
      {"message digest", "f96b697d7cb7938d525a2f31aaf161d0"},
      {"abcdefghijklmnopqrstuvwxyz", "c3fcd3d76192e4007dfb496cca67e13b"},
      {"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789", "d174ab98d277d9f5a5611c2c9f419d9f"},
      {"12345678901234567890123456789012345678901234567890123456789012345678901234567890",
       "57edf4a22be3c955ac49da2e2107b67a"},
  };
  for (const auto& [text, digest] : cases) EXPECT_EQ(vs::md5Hex(text, std::string(text).size()), digest) << text;
}

TEST(Md5, ChunkedUpdatesEqualOneUpdate) {
  std::mt19937 random(5);
  std::vector<uint8_t> bytes(10000);
  for (uint8_t& b : bytes) b = uint8_t(random());
  const std::string whole = vs::md5Hex(bytes.data(), bytes.size());
  for (size_t chunk : {1, 3, 55, 56, 63, 64, 65, 127, 4096}) {
    vs::Md5 md5;
    for (size_t i = 0; i < bytes.size(); i += chunk) md5.update(bytes.data() + i, std::min(chunk, bytes.size() - i));
    EXPECT_EQ(md5.hexDigest(), whole) << "chunks of " << chunk;
  }
  // One byte changed changes the digest.
  bytes[5000] ^= 1;
  EXPECT_NE(vs::md5Hex(bytes.data(), bytes.size()), whole);
}

TEST(Md5, FileEqualsCoreutilsMd5sum) {
  const std::string path = testing::TempDir() + "md5_test.bin";
  std::vector<char> bytes(3 * (1 << 20) + 17);
  std::mt19937 random(7);
  for (char& b : bytes) b = char(random());
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  EXPECT_EQ(vs::md5OfFile(path), vs::md5Hex(bytes.data(), bytes.size()));
  std::FILE* pipe = popen(("md5sum '" + path + "' 2>/dev/null").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char line[128] = {};
  const bool got = std::fgets(line, sizeof line, pipe) != nullptr;
  pclose(pipe);
  if (!got) GTEST_SKIP() << "md5sum is not installed: the file digest was checked against md5Hex only";
  EXPECT_EQ(vs::md5OfFile(path), std::string(line).substr(0, 32));
  std::remove(path.c_str());
  EXPECT_THROW(vs::md5OfFile(path), vs::InputError);
}

}  // namespace
