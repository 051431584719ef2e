#include "Pipeline/SequenceInputs.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <thread>
#include <utility>

#include "Common/Error.h"
#include "Common/ParallelRows.h"
#include "Common/Timing.h"

namespace vs {

SequenceInputs::SequenceInputs(const SynthesisSettings& settings) : settings_(settings) {
  const SynthesisSettings& s = settings;
  for (const ReferenceView& view : s.references) {
    textures_.push_back(std::make_unique<YuvReader>(view.texturePath, s.textureFormat));
    depths_.push_back(std::make_unique<YuvReader>(view.depthPath, view.depthFormat));
  }
  if (!s.referenceViewPath.empty()) truth_ = std::make_unique<YuvReader>(s.referenceViewPath, s.virtualFormat());
  available_ = s.frameCount;
  auto limit = [&](const YuvReader& reader) {
    const int64_t count = reader.frameCount();
    if (s.startFrame >= count)
      throw InputError(reader.path() + ": StartFrame " + std::to_string(s.startFrame) + " is beyond the end of the file (" +
                       std::to_string(count) + " whole frames of " + std::to_string(reader.format().frameBytes()) + " bytes)");
    if (count - s.startFrame < available_) {
      available_ = count - s.startFrame;
      shortest_ = reader.path();
    }
  };
  for (size_t k = 0; k < textures_.size(); ++k) {
    limit(*textures_[k]);
    limit(*depths_[k]);
  }
  if (truth_) limit(*truth_);
  current_.textures.resize(textures_.size());
  current_.depths.resize(depths_.size());
  ahead_.textures.resize(textures_.size());
  ahead_.depths.resize(depths_.size());
  // What is read ahead is sized now, before the first frame's buffers: it then lies below them on
  // the heap instead of among them, where the reading thread would otherwise place it while the first
  // frame allocates (a run of one frame reads nothing ahead). So is the truth's buffer, which the
  // reading thread fills from the second frame on.
  if (available_ > 1) {
    for (size_t k = 0; k < textures_.size(); ++k) {
      ahead_.textures[k].resize(size_t(textures_[k]->format().frameBytes()));
      const FrameFormat& depth = depths_[k]->format();
      ahead_.depths[k].resize(size_t(depth.width) * size_t(depth.height) * size_t(depth.bytesPerSample()));
    }
    if (truth_) truthFrame_.reset(truth_->format());
  }
  // The first frame is read when the loop asks for it, on the calling thread and beside it; each next
  // one on the reading thread while the frame before is rendered.
}

SequenceInputs::~SequenceInputs() {
  if (!reader_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  asked_.notify_one();
  reader_.join();  // after the read under way, if any
}

void SequenceInputs::readAhead() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    asked_.wait(lock, [this] { return stop_ || askedFrame_ >= 0 || askedTruth_ >= 0; });
    if (stop_) return;
    const int64_t f = askedFrame_, t = askedTruth_;
    askedFrame_ = askedTruth_ = -1;
    lock.unlock();
    // Runs a read outside the lock; what it threw is handed to the waiting frame under the lock.
    auto caught = [](auto&& read) -> std::exception_ptr {
      try {
        read();
      } catch (...) {
        return std::current_exception();
      }
      return nullptr;
    };
    // The truth first: the frame being rendered waits for it at its end.
    if (t >= 0) {
      std::exception_ptr error = caught([&] { truth_->read(settings_.startFrame + t, truthFrame_); });
      lock.lock();
      truthError_ = error;
      truthOver_ = true;
      done_.notify_all();
      lock.unlock();
    }
    if (f >= 0) {
      std::exception_ptr error = caught([&] {
        for (size_t k = 0; k < textures_.size(); ++k) {
          textures_[k]->readBytes(settings_.startFrame + f, false, ahead_.textures[k]);
          depths_[k]->readBytes(settings_.startFrame + f, true, ahead_.depths[k]);
        }
      });
      lock.lock();
      readError_ = error;
      readOver_ = true;
      done_.notify_all();
    } else {
      lock.lock();
    }
  }
}

const Y4mHeader* SequenceInputs::y4mTexture() const {
  for (const auto& texture : textures_)
    if (texture->y4m()) return texture->y4m();
  return nullptr;
}

std::string SequenceInputs::shortfall() const {
  return shortest_ + " holds only " + std::to_string(available_) + " frames from StartFrame " +
         std::to_string(settings_.startFrame) + ", but TotalNumberOfFrames is " + std::to_string(settings_.frameCount);
}

// The files of one frame: each view's texture and depth (every view its own readers and buffers), then
// with `withTruth` the ground truth. sideBySide: the views (and the truth) are read on up to Threads
// threads, for the first frame, which nothing else overlaps; a failure is reported as the first file
// in that order would be read alone.
void SequenceInputs::read(int64_t frameIndex, Slot& slot, bool withTruth, bool sideBySide) {
  const auto start = std::chrono::steady_clock::now();
  const size_t jobs = textures_.size() + (withTruth && truth_ ? 1 : 0);
  auto readJob = [&](size_t j) {
    if (j == textures_.size()) return truth_->read(frameIndex, truthFrame_);
    textures_[j]->read(frameIndex, slot.textures[j]);
    depths_[j]->readLuma(frameIndex, slot.depths[j]);
  };
  const size_t cores = settings_.threads > 0 ? size_t(settings_.threads) : size_t(std::thread::hardware_concurrency());
  const size_t workers = sideBySide ? std::min(jobs, std::max<size_t>(1, cores)) : 1;
  if (workers > 1) {
    std::vector<std::exception_ptr> failed(jobs);
    std::atomic<size_t> nextJob{0};
    auto work = [&] {
      for (size_t j = nextJob++; j < jobs; j = nextJob++) try {
          readJob(j);
        } catch (...) {
          failed[j] = std::current_exception();
        }
    };
    std::vector<std::thread> threads;
    for (size_t w = 1; w < workers; ++w) threads.emplace_back(work);
    work();
    for (std::thread& thread : threads) thread.join();
    for (const std::exception_ptr& failure : failed)
      if (failure) std::rethrow_exception(failure);
  } else {
    for (size_t j = 0; j < jobs; ++j) readJob(j);
  }
  slot.seconds = secondsSince(start);
}

SequenceInputs::FrameInputs SequenceInputs::next(double& readSeconds) {
  const int64_t f = nextFrame_++;
  const auto start = std::chrono::steady_clock::now();
  if (f == 0) {
    read(settings_.startFrame, current_, true, true);
  } else {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      // The truth of the frame before was waited for (truth()) unless the loop did not ask for it.
      done_.wait(lock, [this] { return readOver_ && truthOver_; });
      truthError_ = nullptr;
      if (readError_) std::rethrow_exception(std::exchange(readError_, nullptr));
    }
    unpackAhead(settings_.startFrame + f);
  }
  Slot& current = current_;
  readSeconds = std::max(secondsSince(start), f == 0 ? current.seconds : 0.0);
  const bool readNext = f + 1 < available_, readTruth = f > 0 && truth_;
  if (readNext || readTruth) {
    if (!reader_.joinable()) reader_ = std::thread([this] { readAhead(); });
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (readNext) {
        askedFrame_ = f + 1;
        readOver_ = false;
      }
      if (readTruth) {
        askedTruth_ = f;
        truthOver_ = false;
      }
    }
    asked_.notify_one();
  }
  FrameInputs inputs;
  for (size_t k = 0; k < textures_.size(); ++k) inputs.references.push_back({&current.textures[k], &current.depths[k]});
  inputs.hasTruth = truth_ != nullptr;
  return inputs;
}

void SequenceInputs::unpackAhead(int64_t frameIndex) {
  // A view's texture and depth per job, the jobs on up to Threads threads; a failure is reported as
  // the first file in the order of read() would be.
  const int jobs = int(textures_.size());
  std::vector<std::exception_ptr> failed(size_t(jobs) * 2);
  parallelRows(jobs, metricThreads(settings_.threads), [&](int begin, int end) {
    for (int k = begin; k < end; ++k) {
      try {
        textures_[size_t(k)]->unpack(frameIndex, ahead_.textures[size_t(k)], current_.textures[size_t(k)]);
      } catch (...) {
        failed[size_t(k) * 2] = std::current_exception();
      }
      try {
        depths_[size_t(k)]->unpackLuma(frameIndex, ahead_.depths[size_t(k)], current_.depths[size_t(k)]);
      } catch (...) {
        failed[size_t(k) * 2 + 1] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& failure : failed)
    if (failure) std::rethrow_exception(failure);
}

const Frame& SequenceInputs::truth() {
  VS_CHECK(truth_ && nextFrame_ > 0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return truthOver_; });
  if (truthError_) std::rethrow_exception(std::exchange(truthError_, nullptr));
  return truthFrame_;
}

}  // namespace vs
