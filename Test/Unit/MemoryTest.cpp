// keepFreedMemoryForReuse (Common/Memory.h): frame-sized blocks come from the heap, not from a
// mapping of their own that is unmapped (and re-faulted page by page) on every frame.
#include <gtest/gtest.h>

#include <cstdlib>

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

}  // namespace
}  // namespace vs
