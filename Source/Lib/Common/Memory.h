#pragma once
// Process-wide memory settings for the executables.

namespace vs {

// Keeps memory the process frees for its own reuse instead of handing it back to the system at once.
// glibc serves blocks above 128 KiB (a frame-sized buffer) with their own mmap and unmaps them when
// freed, and trims the heap above 128 KiB of free space: every frame's temporary planes were mapped,
// zeroed page by page and unmapped again (about a quarter of a Middlebury frame's time in page
// faults). Raising both thresholds makes those blocks come from the heap and stay there; the
// process's peak memory is unchanged, it is only not returned before exit. No effect outside glibc
// (or under a sanitizer's allocator).
void keepFreedMemoryForReuse();

}  // namespace vs
