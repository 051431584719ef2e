#include "Synth/ScratchPool.h"

#include <cstdlib>  // brings in the C library's feature macros (__GLIBC__)
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "Common/Memory.h"

namespace vs {

void* untouchedAllocate(size_t bytes, bool& mapped) {
  mapped = false;
#if defined(__linux__) && defined(MADV_NOHUGEPAGE)
  if (bytes >= smallPageBuffersFrom()) {
    void* data = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (data == MAP_FAILED) throw std::bad_alloc();
    madvise(data, bytes, MADV_NOHUGEPAGE);  // advice only: where it is refused, huge pages may serve it
    mapped = true;
    return data;
  }
#endif
  return ::operator new(bytes == 0 ? 1 : bytes);
}

void untouchedForget(void* data, size_t bytes) {
#if defined(__linux__)
  if (data) madvise(data, bytes, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
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
