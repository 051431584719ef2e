#pragma once
// MetricsBench's work (MetricsBench.cpp): main.cpp reads the command line into these options.
#include <string>

#include "Common/Frame.h"

namespace vs {

struct MetricsBenchOptions {
  std::string refPath, testPath;  // empty: a generated pair
  FrameFormat format;             // of the files, or of the generated pair
  int repeat = 5;                 // timed runs per metric
  int threads = 0;                // per metric; 0: all hardware threads
  std::string referenceBinary;    // IV-PSNR 7.1's IVPSNR executable; empty: ours only
};

// Times every metric on the first frame of the pair (and the reference software on the same files)
// and prints the table; returns the exit code. Throws InputError for a file or a reference run that fails.
int runMetricsBench(const MetricsBenchOptions& options);

}  // namespace vs
