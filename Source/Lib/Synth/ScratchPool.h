#pragma once
// Working buffers for the bodies of parallel loops, owned by the stage that runs the loop (no
// thread_local: a pool thread's thread_local is freed only when that thread ends, which is how BUG-5
// in doc/stability.md leaked). A body takes one buffer set for its range and gives it back at its end;
// the pool keeps what it has handed out, so once as many sets exist as bodies run at once (the thread
// count), nothing is allocated any more. A body must not rely on what a set held before: it may come
// from any earlier body, on any thread.
#include <cstddef>
#include <new>
#include <memory>
#include <mutex>
#include <type_traits>
#include <vector>

namespace vs {

// UntouchedBuffer's memory: `bytes` not written; `mapped` says how it was obtained, for untouchedFree.
// Throws std::bad_alloc when there is none.
void* untouchedAllocate(size_t bytes, bool& mapped);
void untouchedFree(void* data, size_t bytes, bool mapped);
// A mapped UntouchedBuffer's pages are handed back to the system (the next write faults in a zeroed
// page): each frame's holes write other samples, and without this a sequence kept every page any
// frame had written (the 1920x1080 demo: 15 MiB resident after 3 frames, 36 MiB after 30).
void untouchedForget(void* data, size_t bytes);

template <class T>
class ScratchPool {
public:
  // A set of buffers held for one body; returned to the pool when the lease goes out of scope.
  class Lease {
  public:
    Lease(ScratchPool& pool, std::unique_ptr<T> item) : pool_(pool), item_(std::move(item)) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { pool_.giveBack(std::move(item_)); }
    T& operator*() const { return *item_; }
    T* operator->() const { return item_.get(); }

  private:
    ScratchPool& pool_;
    std::unique_ptr<T> item_;
  };

  ScratchPool() = default;
  // A copy or a move starts empty: buffer sets are never shared between owners.
  ScratchPool(const ScratchPool&) {}
  ScratchPool(ScratchPool&&) noexcept {}
  ScratchPool& operator=(const ScratchPool&) { return *this; }
  ScratchPool& operator=(ScratchPool&&) noexcept { return *this; }

  Lease take() {
    std::unique_ptr<T> item;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        item = std::move(free_.back());
        free_.pop_back();
      }
    }
    if (!item) item = std::make_unique<T>();
    return Lease(*this, std::move(item));
  }

  // Makes sure the pool holds at least `count` sets and passes each to `prepare` (to size its
  // buffers): where a run frees large buffers in order and allocates others in their place, sets
  // grown here, before those buffers, do not end up among them, splitting the memory they leave
  // (Synthesizer::keepAheadOfSpentBuffers). Not while bodies hold sets.
  template <class Prepare>
  void prepare(size_t count, const Prepare& prepare) {
    std::lock_guard<std::mutex> lock(mutex_);
    while (free_.size() < count) free_.push_back(std::make_unique<T>());
    for (std::unique_ptr<T>& item : free_) prepare(*item);
  }

private:
  void giveBack(std::unique_ptr<T> item) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(item));
  }

  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

// A frame-sized working buffer whose contents are left unset when it grows: for buffers that are
// written only where they are later read (the occlusion rule's surroundings, at its candidates). A
// std::vector would zero every element, touching every page of memory that is then never read;
// this one allocates without writing, so pages nothing writes are never faulted in. resize() keeps
// the memory when the size does not grow, and its contents are unspecified after a resize.
//
// A large one (Common/Memory.h: smallPageBuffersFrom(), 1 or 4 MiB by the picture size, or never
// where the heap is not on huge pages, as in a run of one frame by default) is mapped
// apart from the heap and asked to stay on 4 KiB pages: the heap is on transparent huge pages, where
// one written sample makes its whole 2 MiB page resident, so a sparsely written buffer there became
// resident almost whole (at 1920x1080 the hole filling's estimates were 83 MB per picture sample, of
// which the demo's holes touched about 15; they are stored per hole since, HoleFill.h). Dense buffers
// keep the huge pages.
template <class T>
class UntouchedBuffer {
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>,
                "UntouchedBuffer holds plain values only");

public:
  UntouchedBuffer() = default;
  UntouchedBuffer(const UntouchedBuffer&) = delete;
  UntouchedBuffer& operator=(const UntouchedBuffer&) = delete;
  ~UntouchedBuffer() { release(); }

  void resize(size_t size) {
    if (size > capacity_) {
      release();
      data_ = static_cast<T*>(untouchedAllocate(size * sizeof(T), mapped_));
      capacity_ = size;
    } else if (mapped_ && ++reuses_ % kReusesPerForget == 0) {
      untouchedForget(data_, capacity_ * sizeof(T));
    }
    size_ = size;
  }
  size_t size() const { return size_; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }

  // Gives the memory back (size and capacity 0).
  void release() {
    untouchedFree(data_, capacity_ * sizeof(T), mapped_);
    data_ = nullptr;
    capacity_ = size_ = 0;
  }

private:
  T* data_ = nullptr;
  size_t size_ = 0, capacity_ = 0;
  bool mapped_ = false;  // data_ is a mapping of its own (else from operator new)
  // Resizes that kept a mapping: every kReusesPerForget-th hands its pages back (untouchedForget), so
  // that what a sequence keeps resident is what about that many frames touched, not what all did,
  // for a kReusesPerForget-th of the page faults of handing them back every frame (doc/speed.md).
  static constexpr unsigned kReusesPerForget = 8;
  unsigned reuses_ = 0;
};

// Frees a std::vector's memory (clear() keeps it): for a buffer nothing reads any more, so that what is
// allocated next takes that memory from the heap instead of fresh pages.
template <class Vector>
void releaseMemory(Vector& v) {
  Vector().swap(v);
}

}  // namespace vs
