#pragma once
// Working buffers for the bodies of parallel loops, owned by the stage that runs the loop (no
// thread_local: a pool thread's thread_local is freed only when that thread ends, which is how BUG-5
// in doc/stability.md leaked). A body takes one buffer set for its range and gives it back at its end;
// the pool keeps what it has handed out, so once as many sets exist as bodies run at once (the thread
// count), nothing is allocated any more. A body must not rely on what a set held before: it may come
// from any earlier body, on any thread.
#include <memory>
#include <mutex>
#include <vector>

namespace vs {

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

private:
  void giveBack(std::unique_ptr<T> item) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(item));
  }

  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace vs
