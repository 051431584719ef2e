#include "Synth/ScratchPool.h"

#include <cstdlib>  // brings in the C library's feature macros (__GLIBC__)
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace vs {

namespace {

// Below this, operator new (the huge-page heap): for a small picture the page faults of 4 KiB pages
// cost more time than the few MiB that huge pages make resident (Art, 688x554: 3 MiB doubles; 5 ms
// more CPU on a 60 ms run with every estimate on 4 KiB pages).
constexpr size_t kMappedFrom = size_t(4) << 20;

}  // namespace

void* untouchedAllocate(size_t bytes, bool& mapped) {
  mapped = false;
#if defined(__linux__) && defined(MADV_NOHUGEPAGE)
  if (bytes >= kMappedFrom) {
    void* data = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (data == MAP_FAILED) throw std::bad_alloc();
    madvise(data, bytes, MADV_NOHUGEPAGE);  // advice only: where it is refused, huge pages may serve it
    mapped = true;
    return data;
  }
#endif
  return ::operator new(bytes == 0 ? 1 : bytes);
}

void untouchedFree(void* data, size_t bytes, bool mapped) {
  if (!data) return;
#if defined(__linux__)
  if (mapped) {
    munmap(data, bytes);
    return;
  }
#else
  (void)bytes;
  (void)mapped;
#endif
  ::operator delete(data);
}

}  // namespace vs
