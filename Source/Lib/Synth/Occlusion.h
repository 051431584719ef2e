#pragma once
// The occlusion rule between warped views (doc/algorithms.md, "Blending"): a sample that only one
// view shows fills a hole of the other views. A disocclusion reveals surfaces behind the foreground,
// but not far behind everything around the hole: a sample farther than every surface the other views
// show around it is a misplaced one, typically a sample of unknown depth coded as the far plane.
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "Synth/Layer.h"
#include "Synth/ScratchPool.h"

namespace vs {

// The standard allocator, but for a vector's new elements, which are left as they come (default-
// initialised: for doubles, not written): resize() touches no memory, whose pages are faulted in where
// they are first written.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <class U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// Working buffers. The synthesizer frees the per-sample ones after the texture steps, so that the next
// step reuses their memory (Synthesizer.cpp); a sequence keeps `around`'s mapping between frames.
// `around` is written and read at the candidates only, which are few: an UntouchedBuffer (not zeroed
// when it grows, its untouched pages never faulted in: ScratchPool.h). `above` is not zeroed either:
// with two views it holds the candidates' samples above, packed, and only their pages are touched
// (heap memory, which the steps after reuse once it is freed). The others are written over every
// sample before they are read.
struct OcclusionScratch {
  std::vector<uint8_t> soleView;       // per sample: the one view that covers it, or none
  std::vector<uint8_t> candidateRows;  // per row: whether it holds a candidate
  std::vector<uint8_t> stillBehind;    // per candidate: behind the surroundings of every view so far (> 2 views)
  UntouchedBuffer<double> around;      // per candidate: the surroundings in the view looked at
  // More than two views: per sample, the nearest valid sample above it in the view looked at. Two
  // views: the candidates' samples above, packed per range of columns (Occlusion.cpp).
  std::vector<double, UninitialisedAllocator<double>> above;
  std::vector<double> columnLast;  // per column: the last valid sample met by a column scan (and, two views,
                                   // a row of samples above laid out at the candidates)
};

// Drops (sets to kNoDepth) every sample of `views` that exactly one view k covers, when weights[k] is
// below 1 and, in every other view o, the sample lies more than `behind` (inverse depth) behind the
// surroundings of its spot in o. The surroundings in o: along the sample's row, and along its column,
// the nearest valid samples of o on both sides, when there are both; the farther (smaller inverse
// depth) of all those. A view o without surroundings there (a hole of o open on one side of both
// lines, such as a strip along the picture's border that o cannot see) keeps the sample. A view of
// weight 1 (the virtual camera sits on it) shows what the virtual camera sees and keeps every sample.
// Every decision is made on the layers as they come in. All layers have one size; at most 254 views.
void rejectMisplacedSamples(const std::vector<WarpedLayer*>& views, const std::vector<double>& weights, double behind,
                            OcclusionScratch& scratch);

}  // namespace vs
