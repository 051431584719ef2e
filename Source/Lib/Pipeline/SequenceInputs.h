#pragma once
// The input sequences of a run: every reference view's texture and depth file and the ground truth of
// the virtual view. Opens them all, finds how many frames all of them hold from StartFrame on, and
// reads each next frame's references on a thread of its own while the current one is rendered, as
// the files' bytes (half the memory of samples for 8-bit files), unpacked into the one set of planes
// when the frame begins. The ground truth, read only once a frame is rendered, is read on that thread
// too, into one buffer: each frame's while the frame is rendered (frame 0's with its references).
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "Common/Frame.h"
#include "Common/Scene.h"
#include "Common/Yuv.h"

namespace vs {

class SequenceInputs {
public:
  // Opens every input; throws InputError for a file that cannot be opened or that ends before
  // StartFrame.
  explicit SequenceInputs(const SynthesisSettings& settings);
  // Waits for a read still running (after an error), before the buffers it fills go away, and ends
  // the reading thread.
  ~SequenceInputs();
  SequenceInputs(const SequenceInputs&) = delete;
  SequenceInputs& operator=(const SequenceInputs&) = delete;

  // Frames every input holds from StartFrame on, at most TotalNumberOfFrames.
  int64_t available() const { return available_; }
  // When available() < TotalNumberOfFrames: which file is short and by how much.
  std::string shortfall() const;
  // The header of the first Y4M texture (a Y4M output keeps its frame rate); nullptr without one.
  const Y4mHeader* y4mTexture() const;

  struct FrameInputs {
    std::vector<ReferenceFrame> references;  // one per reference view, in the settings' order
    bool hasTruth = false;                   // the run has a ground truth: truth() gives the frame's
  };
  // The next frame's inputs (rethrows its read error) and starts reading the one after, and this
  // frame's ground truth. `readSeconds`: what the first frame's read took, or for later frames the wait
  // for their read (the read itself overlapped the rendering of the frame before).
  FrameInputs next(double& readSeconds);
  // The ground truth of the frame next() gave last (waits for its read, rethrows its error); valid
  // until the next call of next(). Only when FrameInputs::hasTruth.
  const Frame& truth();

private:
  struct Slot {
    std::vector<Frame> textures;
    std::vector<Plane> depths;
    double seconds = 0;
  };
  // The references of frame `frameIndex` into `slot` and, with `withTruth`, its ground truth into truthFrame_.
  void read(int64_t frameIndex, Slot& slot, bool withTruth, bool sideBySide);
  void readAhead();  // the reading thread: reads each frame asked for into ahead_, and each truth
  void unpackAhead(int64_t frameIndex);  // ahead_ into current_, the views side by side

  const SynthesisSettings& settings_;
  std::vector<std::unique_ptr<YuvReader>> textures_, depths_;
  std::unique_ptr<YuvReader> truth_;
  int64_t available_ = 0;
  std::string shortest_;
  Slot current_;  // the references of the frame next() gave last
  struct AheadBytes {  // the next frame's references as the files' bytes (YuvReader::readBytes)
    std::vector<std::vector<uint8_t>> textures, depths;
  } ahead_;
  Frame truthFrame_;       // the ground truth of the frame next() gave last, once its read is over
  int64_t nextFrame_ = 0;  // 0-based from StartFrame
  // One thread for the whole run reads the frame after the current one (a thread per frame cost its
  // start and the first touch of its stack every frame) and the current one's truth, first. Under
  // mutex_: the frames asked for (-1: none), whether their reads are over and how they failed, and
  // whether the thread is to end.
  std::thread reader_;
  std::mutex mutex_;
  std::condition_variable asked_, done_;
  int64_t askedFrame_ = -1, askedTruth_ = -1;
  bool readOver_ = true, truthOver_ = true, stop_ = false;
  std::exception_ptr readError_, truthError_;
};

}  // namespace vs
