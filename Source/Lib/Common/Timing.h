#pragma once
// Seconds per stage of one frame, as the report prints and writes them (Pipeline/RunReport.h).
#include <chrono>

namespace vs {

struct StageTimes {
  double read = 0, depthWarp = 0, textureWarp = 0, blend = 0, holeFill = 0, write = 0;
  double total() const { return read + depthWarp + textureWarp + blend + holeFill + write; }
  StageTimes& operator+=(const StageTimes& o) {
    read += o.read;
    depthWarp += o.depthWarp;
    textureWarp += o.textureWarp;
    blend += o.blend;
    holeFill += o.holeFill;
    write += o.write;
    return *this;
  }
};

// Wall-clock seconds since `start`, for StageTimes.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vs
