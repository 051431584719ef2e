// SynthBench: seconds per frame of every ViewSyn stage, median of N runs, on the SceneGen demo at
// three sizes and on the real Middlebury configs, with 1 and 2 threads; and the wall clock of the
// whole ViewSyn process on the same job (what VSRS's figures are). See --help and doc/speed.md.
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "Bench.h"
#include "Common/CommandLine.h"
#include "Common/Error.h"

int main(int argc, char** argv) {
  vs::CommandLineTool tool;
  tool.name = "SynthBench";
  tool.description =
      "times ViewSyn's stages (read, depth warp, texture warp, blend, hole fill, write) on\n"
      "one frame, whole pipeline with file I/O, median of N runs, for each case and thread count; then\n"
      "the same job as a whole ViewSyn process (start-up and first touch of its memory included, as in\n"
      "VSRS's figures), median of N runs.";
  tool.synopsis = {"[options] [CONFIG.cfg ...]   CONFIG.cfg: further ViewSyn configs to time"};
  tool.options = {
      {"--runs", {"N"}, "runs per case (default 5)", vs::integerValues(1, 1000)},
      {"--threads", {"LIST"}, "thread counts, e.g. 1,2 (default 1,2)", vs::integerListValue(1, 256)},
      {"--work", {"DIR"}, "folder for generated scenes and outputs (default: a new temporary folder in $TMPDIR,\n"
                          "                            removed afterwards)"},
      {"--data", {"DIR"}, "real data (default $VS_DATA_DIR or ../shared/data): Middlebury configs are timed"},
      {"--no-demo", {}, "skip the SceneGen demo at 640x480, 1024x768 and 1920x1080"},
      {"--no-data", {}, "skip the real data"},
      {"--all-scenes", {}, "every Middlebury 2005/2006 scene (default: Art, Books, Aloe)"},
      {"--no-process", {}, "skip the whole-process runs (columns proc s/MP and proc fps, and the section below)"},
      {"--whole-process-only", {}, "only the whole-process section: Art view 3 general and 1D config (one frame) and the\n"
                                   "                            demo at 1920x1080 (30 frames), default threads: warm (median of --runs: wall\n"
                                   "                            and CPU seconds), cold, peak memory"},
      {"--cold-wait", {"S"}, "seconds idle before each cold whole-process run (default 30; 0: no cold runs)",
       vs::integerValues(0, 3600)},
      {"--vsrs", {"PATH"}, "a VSRS 4.2 executable (shared/tools/build_vsrs.sh): the whole-process section runs it too,\n"
                           "                            from a folder of links to each scene, and prints VSRS / ViewSyn\n"
                           "                            (wall clock and CPU seconds)"},
  };
  tool.notes = "Exit codes: 0 done, 1 a folder or run failed (the message says which), 2 bad usage.";
  tool.runsWithoutArguments = true;
  tool.run = [](const vs::CommandLine& line) {
    vs::BenchSettings settings;
    settings.runs = int(line.integer("--runs", settings.runs));
    settings.threadCounts.clear();
    for (const int64_t threads : line.integerList("--threads", {1, 2})) settings.threadCounts.push_back(int(threads));
    settings.work = line.text("--work");
    const char* env = std::getenv("VS_DATA_DIR");
    settings.data = line.text("--data", env && *env ? env : "../shared/data");
    settings.demo = !line.has("--no-demo");
    settings.real = !line.has("--no-data");
    settings.allScenes = line.has("--all-scenes");
    settings.process = !line.has("--no-process");
    settings.configs = line.positional;
    settings.wholeProcessOnly = line.has("--whole-process-only");
    settings.coldWait = double(line.integer("--cold-wait", 30));
    settings.vsrs = line.text("--vsrs");
    if (!settings.vsrs.empty() && access(settings.vsrs.c_str(), X_OK) != 0)
      throw vs::InputError("--vsrs " + settings.vsrs + ": not an executable file");
    return vs::runBench(settings);
  };
  return vs::runCommandLine(argc, argv, tool);
}
