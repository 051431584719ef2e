// keepFreedMemoryForReuse (Common/Memory.h): frame-sized blocks come from the heap, not from a
// mapping of their own that is unmapped (and re-faulted page by page) on every frame; and
// reserveHugePageHeap: the blocks allocated after it lie where transparent huge pages are allowed.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "Common/Memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace vs {
namespace {

TEST(Memory, FrameSizedBlocksComeFromTheHeapOnceSet) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  keepFreedMemoryForReuse();
  // 64 MiB: above glibc's largest automatic mmap threshold (32 MiB), so without the setting this
  // block would always get its own mapping.
  const size_t mappedBefore = mallinfo2().hblkhd;
  void* block = std::malloc(size_t(64) << 20);
  ASSERT_NE(block, nullptr);
  const size_t mappedAfter = mallinfo2().hblkhd;
  std::free(block);
  EXPECT_EQ(mappedAfter, mappedBefore) << "the block was given its own mapping";
#else
  GTEST_SKIP() << "not glibc 2.33 or later: the setting does not apply";
#endif
}

// The "THPeligible" line of /proc/self/smaps for the mapping that holds `address`: 1 where the kernel
// may back it with transparent huge pages; -1 when not found.
int hugePageEligible(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  const uintptr_t at = reinterpret_cast<uintptr_t>(address);
  while (std::getline(smaps, line)) {
    unsigned long long begin = 0, end = 0;
    char dash = 0;
    std::istringstream header(line);
    if (header >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = at >= begin && at < end;
    } else if (inside && line.rfind("THPeligible:", 0) == 0) {
      return std::atoi(line.c_str() + 12);
    }
  }
  return -1;
}

TEST(Memory, BlocksAfterTheReservationMayUseHugePages) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "the sanitizer's allocator does not take glibc's settings";
#elif !defined(__GLIBC__) || !defined(__linux__)
  GTEST_SKIP() << "not glibc on Linux: the reservation does not apply";
#else
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(mode, modes);
  if (modes.empty() || modes.find("[never]") != std::string::npos)
    GTEST_SKIP() << "transparent huge pages are off on this machine (" << modes << ")";
  std::ifstream self("/proc/self/smaps");
  std::string first;
  if (!std::getline(self, first)) GTEST_SKIP() << "no /proc/self/smaps";
  keepFreedMemoryForReuse();
  reserveHugePageHeap(size_t(96) << 20);
  char* block = static_cast<char*>(std::malloc(size_t(32) << 20));
  ASSERT_NE(block, nullptr);
  // "always" makes every mapping eligible; "madvise" only those advised, which is what is tested.
  EXPECT_EQ(hugePageEligible(block + (size_t(16) << 20)), 1) << "transparent huge pages: " << modes;
  std::free(block);
#endif
}

}  // namespace
}  // namespace vs
