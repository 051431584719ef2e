#pragma once
// Process-wide memory settings for the executables.
#include <cstddef>

namespace vs {

// Keeps memory the process frees for its own reuse instead of handing it back to the system at once.
// glibc serves blocks above 128 KiB (a frame-sized buffer) with their own mmap and unmaps them when
// freed, and trims the heap above 128 KiB of free space: every frame's temporary planes were mapped,
// zeroed page by page and unmapped again (about a quarter of a Middlebury frame's time in page
// faults). Raising both thresholds makes those blocks come from the heap and stay there; the
// process's peak memory is unchanged, it is only not returned before exit. Threads allocate from that
// one heap too (one arena), so call this before a second thread allocates. No effect outside glibc
// (or under a sanitizer's allocator).
void keepFreedMemoryForReuse();

// Whether a run asks for huge pages: VS_HUGE_PAGES=1 in the environment yes, =0 no, unset (or any
// other value) `byDefault`. `variable` is the variable's value (nullptr: unset).
bool hugePagesWanted(const char* variable, bool byDefault);

// Where hugePagesWanted(getenv("VS_HUGE_PAGES"), byDefault) holds, grows the heap by `bytes` (at most
// 768 MiB) and asks Linux for transparent huge pages over it, so that the frame buffers a run then
// allocates there are faulted in 2 MiB at a time instead of 4 KiB. The memory is only reserved
// (address space): none of it is touched here, and resident memory grows only as the run uses it.
// What the frame loop passes as the default was decided by measuring warm runs and the first run
// after 30 s idle (doc/speed.md, "Cold starts and the pool's wake-ups"): on a virtual machine whose
// host takes back free memory, a huge page may be cleared on memory the host must fault in again, and
// a cold one-frame run of Art took about twice a warm one (none of that on 4 KiB pages), while a warm
// one-frame run costs about a quarter more CPU on 4 KiB pages (7500 page faults against 500) and a
// 30-frame 1080p sequence about a tenth more user CPU (the TLB): so huge pages for sequences, 4 KiB
// pages for a single frame. Does nothing unless keepFreedMemoryForReuse() set the heap up (the
// reservation would otherwise be unmapped when freed), or outside glibc on Linux; where transparent
// huge pages are off, the advice has no effect. Returns whether it asked for huge pages (the heap's
// pages are then those the run's buffers get; false where it did nothing).
bool reserveHugePageHeap(size_t bytes, bool byDefault);

// Buffers written only here and there (Synth/ScratchPool.h: UntouchedBuffer, the occlusion rule's
// surroundings and the hole filling's estimates) of at least this many bytes are mapped apart on 4
// KiB pages instead of coming from the huge-page heap, where one written sample makes its whole 2 MiB
// page resident. Default 4 MiB; a run sets it from its picture size (Pipeline/FrameLoop.cpp): 4 KiB
// pages fault ten times more often, which a small picture's run feels, while a large picture's huge
// pages keep tens of MiB resident for nothing. A run whose heap is not on huge pages sets SIZE_MAX:
// there the heap's freed memory serves them better than fresh pages of a mapping of their own.
void setSmallPageBuffersFrom(size_t bytes);
size_t smallPageBuffersFrom();

}  // namespace vs
