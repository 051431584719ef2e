#include "Synth/Parallel.h"

#include <sched.h>

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace vs {

namespace {

// Set while a thread runs a loop's body: a loop started there runs on that thread alone.
thread_local bool insideLoop = false;

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
  void start() {
    std::lock_guard<std::mutex> busy(busy_);  // not while a loop runs
    startWorkers(threads_.load(std::memory_order_relaxed) - 1);
  }

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
      ++generation_;
    }
    wake_.notify_all();  // no system call unless a worker sleeps
    work(body, count, stripes);
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
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
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
  uint64_t generation_ = 0;  // counts the loops started, so that a worker sees each one once
  int done_ = 0, active_ = 0;  // stripes done; workers inside the loop
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

void startWorkerThreads() { pool().start(); }

void parallelStripes(int count, int stripes, const std::function<void(int, int)>& body) {
  if (count <= 0) return;
  pool().run(count, stripes, body);
}

}  // namespace vs
