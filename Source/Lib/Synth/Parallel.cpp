#include "Synth/Parallel.h"

#include <sched.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>

namespace vs {

namespace {

// Set while a thread runs a loop's body: a loop started there runs on that thread alone.
thread_local bool insideLoop = false;

// How long a thread that waits for the pool (a worker for the next loop, the loop's caller for its
// last stripes) first polls before it sleeps on a condition variable: VS_POOL_SPIN_US in the
// environment, in microseconds; 0 (the default) sleeps at once. A frame runs dozens of short loops with
// a little serial work between them, and on a virtual machine whose idle vCPUs halt, waking a sleeping
// thread may cost tens of microseconds a loop; but on a loaded machine the polling thread takes the
// core the other threads need, and there every spin measured was slower (doc/speed.md, "Cold starts
// and the pool's wake-ups"), so it is off unless asked for. Bounded either way, so that a pool idle
// between frames or runs sleeps.
int64_t spinNanoseconds() {
  static const int64_t ns = [] {
    const char* e = std::getenv("VS_POOL_SPIN_US");
    return e && *e ? int64_t(std::max(0L, std::strtol(e, nullptr, 10))) * 1000 : int64_t(0);
  }();
  return ns;
}

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// Polls ready() for at most spinNanoseconds(); true once it holds.
template <class Ready>
bool spinUntil(const Ready& ready) {
  const int64_t limit = spinNanoseconds();
  if (limit <= 0) return ready();
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    for (int k = 0; k < 64; ++k) {
      if (ready()) return true;
      cpuRelax();
    }
    if (std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count() >= limit)
      return ready();
  }
}

// The pool: workers - 1 threads beside the caller's. One loop at a time holds it (`busy`); its
// stripes are taken one by one from an atomic counter by whichever thread is free, so that the split
// into stripes, not the threads' speed, decides which body call writes what.
class Pool {
public:
  void setThreads(int threads) {
    std::lock_guard<std::mutex> busy(busy_);
    threads_.store(std::max(1, threads), std::memory_order_relaxed);
  }
  int threads() const { return threads_.load(std::memory_order_relaxed); }

  void run(int count, int stripes, const std::function<void(int, int)>& body) {
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    const int threads = threads_.load(std::memory_order_relaxed);
    if (insideLoop || !busy.owns_lock() || threads <= 1 || count <= 1) {
      runAlone(count, body);
      return;
    }
    if (stripes <= 0) stripes = 4 * threads;
    stripes = std::min(stripes, count);
    if (stripes <= 1) {
      runAlone(count, body);
      return;
    }
    startWorkers(threads - 1);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      body_ = &body;
      count_ = count;
      stripes_ = stripes;
      helpers_ = threads - 1;
      next_.store(0, std::memory_order_relaxed);
      done_ = 0;
      error_ = nullptr;
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();  // no system call unless a worker sleeps
    work(body, count, stripes);
    spinUntil([&] {
      return done_.load(std::memory_order_acquire) == stripes && active_.load(std::memory_order_acquire) == 0;
    });
    std::unique_lock<std::mutex> lock(mutex_);
    // Every stripe done, and no worker still inside this loop (one that woke late and found no stripe
    // left must not read the next loop's counter with this loop's body).
    finished_.wait(lock, [&] { return done_ == stripes_ && active_ == 0; });
    body_ = nullptr;
    if (error_) std::rethrow_exception(error_);
  }

private:
  static void runAlone(int count, const std::function<void(int, int)>& body) {
    const bool outer = insideLoop;
    insideLoop = true;
    try {
      body(0, count);
    } catch (...) {
      insideLoop = outer;
      throw;
    }
    insideLoop = outer;
  }

  // Takes stripes until none is left; the stripe s is [s * count / stripes, (s + 1) * count / stripes).
  void work(const std::function<void(int, int)>& body, int64_t count, int64_t stripes) {
    int finished = 0;
    std::exception_ptr error;
    insideLoop = true;
    for (int s; (s = next_.fetch_add(1, std::memory_order_relaxed)) < stripes;) {
      try {
        body(int(s * count / stripes), int((s + 1) * count / stripes));
      } catch (...) {
        if (!error) error = std::current_exception();
      }
      ++finished;
    }
    insideLoop = false;
    if (finished == 0) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (error && !error_) error_ = error;
    done_ += finished;
    if (done_ == stripes_ && active_ == 0) finished_.notify_one();
  }

  void startWorkers(int wanted) {
    while (int(workers_.size()) < wanted) {
      const int index = int(workers_.size());
      workers_.emplace_back([this, index] { serve(index); });
      // Left to the process's exit: a worker waits on the condition variable, owns nothing, and
      // joining it would only delay the exit.
      workers_.back().detach();
    }
  }

  void serve(int index) {
    uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (generation_.load(std::memory_order_relaxed) == seen) {
        lock.unlock();
        spinUntil([&] { return generation_.load(std::memory_order_acquire) != seen; });
        lock.lock();
      }
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_relaxed) != seen; });
      seen = generation_.load(std::memory_order_relaxed);
      if (index >= helpers_ || body_ == nullptr) continue;  // not wanted in this loop, or it is over
      const std::function<void(int, int)>& body = *body_;
      const int count = count_, stripes = stripes_;
      ++active_;
      lock.unlock();
      work(body, count, stripes);
      lock.lock();
      if (--active_ == 0 && done_ == stripes_) finished_.notify_one();
    }
  }

  std::mutex busy_;  // held by the loop that uses the pool
  std::atomic<int> threads_{availableCores()};  // read by loops that do not hold the pool, too
  std::vector<std::thread> workers_;

  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_, finished_;
  // Changed under the mutex only; atomic so that a spinning thread may poll them without it.
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> done_{0}, active_{0};  // stripes done; workers inside the loop
  const std::function<void(int, int)>* body_ = nullptr;
  int count_ = 0, stripes_ = 0, helpers_ = 0;
  std::exception_ptr error_;
  std::atomic<int> next_{0};
};

// Never destroyed: its detached workers may still wait on its members while the process exits.
Pool& pool() {
  static Pool* const instance = new Pool;
  return *instance;
}

}  // namespace

int availableCores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, int(std::thread::hardware_concurrency()));
}

void setWorkerThreads(int threads) { pool().setThreads(threads > 0 ? threads : availableCores()); }

int workerThreads() { return pool().threads(); }

void parallelStripes(int count, int stripes, const std::function<void(int, int)>& body) {
  if (count <= 0) return;
  pool().run(count, stripes, body);
}

}  // namespace vs
