// keepFreedMemoryForReuse (Common/Memory.h): frame-sized blocks come from the heap, not from a
// mapping of their own that is unmapped (and re-faulted page by page) on every frame; and
// reserveHugePageHeap, asked for huge pages: the blocks allocated after it lie where transparent huge
// pages are allowed.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

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
  reserveHugePageHeap(size_t(96) << 20, true);
  char* block = static_cast<char*>(std::malloc(size_t(32) << 20));
  ASSERT_NE(block, nullptr);
  // "always" makes every mapping eligible; "madvise" only those advised, which is what is tested.
  EXPECT_EQ(hugePageEligible(block + (size_t(16) << 20)), 1) << "transparent huge pages: " << modes;
  std::free(block);
#endif
}

// VS_HUGE_PAGES overrides the caller's default both ways; anything but 1 or 0 leaves it.
TEST(Memory, HugePagesEnvironmentVariableOverridesTheDefault) {
  for (const bool byDefault : {false, true}) {
    EXPECT_TRUE(hugePagesWanted("1", byDefault));
    EXPECT_FALSE(hugePagesWanted("0", byDefault));
    EXPECT_EQ(hugePagesWanted(nullptr, byDefault), byDefault);
    EXPECT_EQ(hugePagesWanted("", byDefault), byDefault);
    EXPECT_EQ(hugePagesWanted("yes", byDefault), byDefault);
  }
}

// Whether `address` lies in the mapping /proc/self/smaps names [heap] (the main arena's).
bool inMainHeap(const void* address) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  const uintptr_t at = reinterpret_cast<uintptr_t>(address);
  while (std::getline(maps, line)) {
    unsigned long long begin = 0, end = 0;
    char dash = 0;
    std::istringstream header(line);
    if (header >> std::hex >> begin >> dash >> end && dash == '-' && at >= begin && at < end)
      return line.find("[heap]") != std::string::npos;
  }
  return false;
}

// A worker thread's blocks come from the main heap (where reserveHugePageHeap's advice and the kept
// free memory are), not from an arena of its own. glibc fixes the arena limit when a second thread
// first allocates, which other tests of this process have long done: the check runs in a new process
// of this test program that runs only this test.
TEST(Memory, WorkerThreadsAllocateFromTheMainHeap) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "the sanitizer's allocator does not take glibc's settings";
#elif !defined(__GLIBC__) || !defined(__linux__)
  GTEST_SKIP() << "not glibc on Linux: the setting does not apply";
#else
  if (std::getenv("VS_MEMORY_TEST_CHILD")) {
    keepFreedMemoryForReuse();
    void* fromMain = std::malloc(size_t(1) << 20);
    void* fromWorker = nullptr;
    std::thread worker([&] { fromWorker = std::malloc(size_t(1) << 20); });
    worker.join();
    ASSERT_TRUE(inMainHeap(fromMain)) << "the main thread's block is not in [heap]";
    EXPECT_TRUE(inMainHeap(fromWorker)) << "the worker's block is not in the main heap";
    std::free(fromWorker);
    std::free(fromMain);
    return;
  }
  const std::string command = "VS_MEMORY_TEST_CHILD=1 '" + std::filesystem::read_symlink("/proc/self/exe").string() +
                              "' --gtest_filter=Memory.WorkerThreadsAllocateFromTheMainHeap > /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << "the check in a new process failed (run: " << command << ")";
#endif
}

}  // namespace
}  // namespace vs
