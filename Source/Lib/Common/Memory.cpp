#include "Common/Memory.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>  // brings in the C library's feature macros (__GLIBC__)
#include <string_view>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace vs {

namespace {

bool heapKept = false;  // keepFreedMemoryForReuse() has raised the thresholds
std::atomic<size_t> smallPagesFrom{size_t(4) << 20};

}  // namespace

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  const bool mapped = mallopt(M_MMAP_THRESHOLD, 256 << 20) == 1;  // blocks up to 256 MiB come from the heap
  const bool trimmed = mallopt(M_TRIM_THRESHOLD, 1 << 30) == 1;   // free heap is kept up to 1 GiB
  // One arena: the worker threads' blocks come from the same heap (kept, and advised for huge pages
  // by reserveHugePageHeap) instead of arenas of their own, each mapped, faulted 4 KiB at a time and
  // trimmed apart. Allocation is rare once a run's buffers have grown, so their lock costs nothing.
  // glibc fixes the arena limit when a second thread first allocates: this must come before.
  mallopt(M_ARENA_MAX, 1);
  heapKept = mapped && trimmed;
#endif
}

bool hugePagesWanted(const char* variable, bool byDefault) {
  if (variable && std::string_view(variable) == "1") return true;
  if (variable && std::string_view(variable) == "0") return false;
  return byDefault;
}

bool reserveHugePageHeap(size_t bytes, bool byDefault) {
#if defined(__GLIBC__) && defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(__SANITIZE_ADDRESS__)
  if (!heapKept) return false;
  // The output is the same either way; only the time differs (Memory.h).
  if (!hugePagesWanted(std::getenv("VS_HUGE_PAGES"), byDefault)) return false;
  // Blocks below the mmap threshold come from the top of the heap, one after the other; freed, they
  // return to it and stay (below the trim threshold). Only their headers are written.
  constexpr size_t kChunk = size_t(192) << 20, kHugePage = size_t(2) << 20;
  constexpr int kMostChunks = 4;
  void* chunks[kMostChunks] = {};
  bytes = std::min(bytes, size_t(kMostChunks) * kChunk);
  for (int k = 0; k < kMostChunks && size_t(k) * kChunk < bytes; ++k) {
    chunks[k] = std::malloc(kChunk);
    if (!chunks[k]) break;
    const uintptr_t begin = (uintptr_t(chunks[k]) + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
    const uintptr_t end = (uintptr_t(chunks[k]) + kChunk) & ~uintptr_t(kHugePage - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // advice only
  }
  for (void* chunk : chunks) std::free(chunk);
  return true;
#else
  (void)bytes;
  (void)byDefault;
  return false;
#endif
}

void setSmallPageBuffersFrom(size_t bytes) { smallPagesFrom.store(bytes, std::memory_order_relaxed); }

size_t smallPageBuffersFrom() { return smallPagesFrom.load(std::memory_order_relaxed); }

}  // namespace vs
