#pragma once
// SynthBench's benchmark, apart from its command line (main.cpp).
#include <string>
#include <vector>

namespace vs {

struct BenchSettings {
  int runs = 5;                        // runs per case; the median is printed
  std::vector<int> threadCounts = {1, 2};
  std::string work;                    // generated scenes and outputs; empty: a temporary folder, removed afterwards
  std::string data;                    // real data (Middlebury configs)
  bool demo = true;                    // the SceneGen demo at three sizes
  bool real = true;                    // the real data
  bool allScenes = false;              // every Middlebury scene, not only Art, Books, Aloe
  bool process = true;                 // also time whole ViewSyn processes
  std::vector<std::string> configs;    // further ViewSyn configs
  double coldWait = 30;                // seconds idle before each cold whole-process run; 0: no cold runs
  bool wholeProcessOnly = false;       // only the whole-process section (no per-stage table)
  std::string vsrs;                    // a VSRS 4.2 executable to run beside ViewSyn (empty: none)
};

// Prints the table of medians on stdout; throws InputError (a folder that cannot be made, a failed run).
int runBench(const BenchSettings& settings);

}  // namespace vs
