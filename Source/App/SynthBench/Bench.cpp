// SynthBench's benchmark (see main.cpp and doc/speed.md): seconds per frame of every ViewSyn stage,
// median of N runs, on the SceneGen demo at three sizes and on the real Middlebury configs, and the
// wall clock of the whole ViewSyn process on the same job.
#include "Bench.h"

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Scene/SceneGen.h"
#include "Synth/ViewSynRenderer.h"

extern char** environ;  // the environment the whole-process runs inherit (POSIX)

namespace vs {

namespace {

namespace fs = std::filesystem;

// A fresh folder under the system's temporary folder ($TMPDIR), removed with everything in it when
// this goes out of scope; nothing when `wanted` is false.
struct TemporaryFolder {
  fs::path path;
  explicit TemporaryFolder(bool wanted) {
    if (!wanted) return;
    std::string name = (fs::temp_directory_path() / "synthbench-XXXXXX").string();
    if (!mkdtemp(name.data())) throw InputError(name + ": cannot create a temporary folder");
    path = name;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    if (!path.empty()) fs::remove_all(path, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
};

struct Case {
  std::string name;
  std::string config;
  std::vector<std::string> overrides;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// One whole process: wall-clock seconds, CPU seconds (user + system, all its threads) and peak
// resident memory (MiB).
struct ProcessRun {
  double seconds = 0, cpuSeconds = 0, peakMiB = 0;
};

// Runs `exe` with `args` in `folder` (empty: this process's), its output discarded; throws when it
// fails.
ProcessRun runProcess(const fs::path& exe, const std::vector<std::string>& args, const fs::path& folder = {}) {
  std::vector<std::string> words = {exe.string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  const std::string where = folder.string();
  if (!where.empty()) posix_spawn_file_actions_addchdir_np(&actions, where.c_str());
  const auto start = std::chrono::steady_clock::now();
  pid_t child = 0;
  const int spawned = posix_spawn(&child, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  struct rusage usage = {};
  if (spawned != 0 || wait4(child, &status, 0, &usage) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(exe.string() + " failed on " + (args.empty() ? std::string() : args[0]) +
                         (where.empty() ? std::string() : " in " + where) + " (run it by hand to see why)");
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          seconds(usage.ru_utime) + seconds(usage.ru_stime), double(usage.ru_maxrss) / 1024.0};  // ru_maxrss: KiB
}

// Wall-clock seconds of one run of `exe` with `args`, its output discarded; throws when it fails.
double processSeconds(const fs::path& exe, const std::vector<std::string>& args) { return runProcess(exe, args).seconds; }

std::string demoConfig(const fs::path& work, int width, int height, int frames = 1) {
  const fs::path folder = work / ("demo_" + std::to_string(width) + "x" + std::to_string(height) +
                                  (frames > 1 ? "_" + std::to_string(frames) : std::string()));
  const fs::path config = folder / "viewsyn_cam1.cfg";
  if (fs::exists(config)) return config.string();
  const Config sceneConfig =
      Config::fromText(sceneGenOptionTable(), "", "SynthBench", ".",
                           {"Scene=demo", "SourceWidth=" + std::to_string(width), "SourceHeight=" + std::to_string(height),
                            "TotalNumberOfFrames=" + std::to_string(frames), "OutputFolder=" + folder.string()});
  std::ostringstream quiet;
  generateScene(readSceneGenSettings(sceneConfig), quiet);
  return config.string();
}

// What a user waits for: whole processes with the config's own (default) thread count, warm (median
// of `runs`) and cold (one run after `coldWait` seconds idle), and their peak memory; the median CPU
// seconds of the warm runs, which a loaded machine inflates less than the wall clock.
struct ProcessFigures {
  double warm = 0, warmCpu = 0, cold = 0, peakMiB = 0;
};

ProcessFigures timeProcess(const fs::path& exe, const std::vector<std::string>& args, const fs::path& folder, int runs,
                           double coldWait) {
  ProcessFigures figures;
  if (coldWait > 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(coldWait));
    const ProcessRun run = runProcess(exe, args, folder);
    figures.cold = run.seconds;
    figures.peakMiB = run.peakMiB;
  }
  std::vector<double> seconds, cpuSeconds;
  for (int r = 0; r < runs; ++r) {
    const ProcessRun run = runProcess(exe, args, folder);
    seconds.push_back(run.seconds);
    cpuSeconds.push_back(run.cpuSeconds);
    figures.peakMiB = std::max(figures.peakMiB, run.peakMiB);
  }
  figures.warm = median(seconds);
  figures.warmCpu = median(cpuSeconds);
  return figures;
}

// A folder for VSRS's run of `config`, which takes no overrides: links to every file beside the
// config except its output, which VSRS then writes here.
fs::path vsrsFolder(const fs::path& work, const std::string& name, const fs::path& config, const std::string& output) {
  std::string tag = name;
  for (char& c : tag)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  const fs::path folder = work / ("vsrs_" + tag);
  fs::create_directories(folder);
  const fs::path source = fs::absolute(config).parent_path();
  for (const auto& entry : fs::directory_iterator(source)) {
    const fs::path link = folder / entry.path().filename();
    if (entry.path().filename() == fs::path(output).filename() || fs::exists(fs::symlink_status(link))) continue;
    fs::create_symlink(entry.path(), link);
  }
  return folder;
}

void printProcessFigures(const ProcessFigures& f, bool cold) {
  std::printf(" %9.4f %9.4f", f.warm, f.warmCpu);
  if (cold) std::printf(" %9.4f %6.2fx", f.cold, f.cold / f.warm);
  std::printf(" %9.1f", f.peakMiB);
}

// The whole-process section: Art view 3 (general and 1D configs, one frame) and the SceneGen demo at
// 1920x1080 (30 frames), ViewSyn and, given, VSRS.
void runUserCases(const BenchSettings& settings, const fs::path& work, const fs::path& viewSyn) {
  struct Job {
    std::string name, config;
  };
  std::vector<Job> jobs;
  const fs::path art = fs::path(settings.data) / "middlebury2005" / "Art";
  if (settings.real && fs::is_directory(art)) {
    jobs.push_back({"Art view 3 general", (art / "synth_view3_general.cfg").string()});
    jobs.push_back({"Art view 3 1D config", (art / "synth_view3_1d.cfg").string()});
  }
  if (settings.demo) jobs.push_back({"demo 1920x1080, 30 frames", demoConfig(work, 1920, 1080, 30)});
  if (jobs.empty()) return;
  const bool cold = settings.coldWait > 0, vsrs = !settings.vsrs.empty();
  std::printf("\nwhole process, default threads, %d warm runs (median wall and CPU seconds)%s\n", settings.runs,
              cold ? (", cold: one run after " + formatNumber("%g", settings.coldWait) + " s idle").c_str() : "");
  std::printf("%-28s %9s %9s", "case", "warm s", "CPU s");
  if (cold) std::printf(" %9s %7s", "cold s", "c/w");
  std::printf(" %9s", "peak MiB");
  if (vsrs) {
    std::printf(" | %9s %9s", "VSRS s", "CPU s");
    if (cold) std::printf(" %9s %7s", "cold s", "c/w");
    std::printf(" %9s %9s %9s", "peak MiB", "VSRS/us", "CPU");
  }
  std::printf("\n");
  const OptionTable table = viewSynOptionTable();
  for (const Job& job : jobs) {
    const ProcessFigures ours = timeProcess(
        viewSyn, {job.config, "OutputVirtualViewImageName=" + (work / "process_out.yuv").string()}, {}, settings.runs,
        settings.coldWait);
    std::printf("%-28s", job.name.c_str());
    printProcessFigures(ours, cold);
    if (vsrs) {
      const std::string output = Config::load(table, job.config, {}).getString("OutputVirtualViewImageName");
      const fs::path folder = vsrsFolder(work, job.name, job.config, output);
      const ProcessFigures theirs = timeProcess(fs::absolute(settings.vsrs), {fs::path(job.config).filename().string()},
                                                folder, settings.runs, settings.coldWait);
      std::printf(" |");
      printProcessFigures(theirs, cold);
      std::printf(" %8.1fx %8.1fx", theirs.warm / ours.warm, theirs.warmCpu / ours.warmCpu);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
}

}  // namespace

int runBench(const BenchSettings& settings) {
  const fs::path data = settings.data;
  const bool demo = settings.demo, real = settings.real, allScenes = settings.allScenes;
  bool process = settings.process;
  const int runs = settings.runs;
  const std::vector<int>& threadCounts = settings.threadCounts;
  std::vector<Case> cases;
  for (const std::string& config : settings.configs) cases.push_back({fs::path(config).stem().string(), config, {}});
  // Where told, or a fresh temporary folder that is removed afterwards: never the working directory.
  const TemporaryFolder temporary(settings.work.empty());
  const fs::path work = settings.work.empty() ? temporary.path : fs::path(settings.work);
  std::error_code error;
  fs::create_directories(work, error);
  if (error || !fs::is_directory(work, error))
    throw InputError("--work " + work.string() + ": cannot create the folder (" +
                         (error ? error.message() : std::string("not a folder")) + ")");
  if (demo)
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{640, 480}, {1024, 768}, {1920, 1080}}) {
      const std::string config = demoConfig(work, w, h);
      cases.push_back({"demo " + std::to_string(w) + "x" + std::to_string(h) + " general", config, {"SynthesisMode=0"}});
      cases.push_back({"demo " + std::to_string(w) + "x" + std::to_string(h) + " 1D", config, {"SynthesisMode=1"}});
    }
  if (real && fs::is_directory(data)) {
    for (const char* set : {"middlebury2005", "middlebury2006"}) {
      if (!fs::is_directory(data / set)) continue;
      std::vector<fs::path> scenes;
      for (const auto& entry : fs::directory_iterator(data / set)) scenes.push_back(entry.path());
      std::sort(scenes.begin(), scenes.end());
      for (const fs::path& scene : scenes) {
        const std::string name = scene.filename().string();
        if (!allScenes && name != "Art" && name != "Books" && name != "Aloe") continue;
        cases.push_back({name + " general", (scene / "synth_view3_general.cfg").string(), {}});
        // The same settings on the 1D path: the paths' speeds compared (issue: 1D vs general).
        cases.push_back({name + " general as 1D", (scene / "synth_view3_general.cfg").string(), {"SynthesisMode=1"}});
        cases.push_back({name + " 1D config", (scene / "synth_view3_1d.cfg").string(), {}});
      }
    }
  } else if (real) {
    std::fprintf(stderr, "SynthBench: %s is absent: real data skipped\n", data.string().c_str());
  }

  // ViewSyn beside this executable, for the whole-process runs.
  const fs::path viewSyn = fs::read_symlink("/proc/self/exe").parent_path() / "ViewSyn";
  if (process && !fs::exists(viewSyn)) {
    std::fprintf(stderr, "SynthBench: no %s: whole-process runs skipped\n", viewSyn.string().c_str());
    process = false;
  }
  if (!settings.wholeProcessOnly)
    std::printf("%-28s %3s %8s %8s %8s %8s %8s %8s %9s %9s %7s %10s %8s\n", "case", "thr", "read", "d.warp", "t.warp",
              "blend", "holes", "write", "s/frame", "s/MP", "fps", "proc s/MP", "proc fps");
  const OptionTable table = viewSynOptionTable();
  std::map<std::string, double> medians;  // "case|threads" -> median s/frame, for the ratios below
  for (const Case& c : cases)
    for (int threads : threadCounts) {
      if (settings.wholeProcessOnly) break;
      std::vector<std::string> overrides = c.overrides;
      overrides.push_back("Threads=" + std::to_string(threads));
      overrides.push_back("TotalNumberOfFrames=1");
      overrides.push_back("OutputVirtualViewImageName=" + (work / "bench_out.yuv").string());
      const Config config = Config::load(table, c.config, overrides);
      std::vector<double> stage[7];
      double megapixels = 0;
      for (int r = 0; r < runs; ++r) {
        const RunSummary summary = runViewSyn(config, nullptr);
        const StageTimes& t = summary.times;
        const double values[7] = {t.read, t.depthWarp, t.textureWarp, t.blend, t.holeFill, t.write, t.total()};
        for (int k = 0; k < 7; ++k) stage[k].push_back(values[k]);
        megapixels = double(config.getInt("SourceWidth")) * double(config.getInt("SourceHeight")) / 1e6;
      }
      const double total = median(stage[6]);
      medians[c.name + "|" + std::to_string(threads)] = total;
      medians[c.name + "|warp|" + std::to_string(threads)] = median(stage[1]) + median(stage[2]);
      std::printf("%-28s %3d %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f %9.4f %9.4f %7.1f", c.name.c_str(), threads,
                  median(stage[0]), median(stage[1]), median(stage[2]), median(stage[3]), median(stage[4]),
                  median(stage[5]), total, total / megapixels, 1.0 / total);
      if (process) {
        // The same job as its own process: start-up, first touch of every buffer and exit included.
        std::vector<std::string> args = {c.config};
        args.insert(args.end(), overrides.begin(), overrides.end());
        std::vector<double> seconds;
        for (int r = 0; r < runs; ++r) seconds.push_back(processSeconds(viewSyn, args));
        const double wall = median(seconds);
        std::printf(" %10.4f %8.1f", wall / megapixels, 1.0 / wall);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  if (process) runUserCases(settings, work, viewSyn);
  // The 1D path against the general path on the same settings and data: whole frame, and the two
  // warp stages alone (blending and hole filling are shared).
  bool header = false;
  for (const Case& c : cases) {
    const std::string suffix = " general as 1D";
    if (c.name.size() <= suffix.size() || c.name.compare(c.name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string general = c.name.substr(0, c.name.size() - suffix.size()) + " general";
    for (int threads : threadCounts) {
      const std::string t = std::to_string(threads);
      if (!medians.count(general + "|" + t)) continue;
      if (!header) std::printf("\n%-28s %3s %14s %14s\n", "general / 1D path", "thr", "whole frame", "warp stages");
      header = true;
      std::printf("%-28s %3d %13.2fx %13.2fx\n", general.c_str(), threads,
                  medians[general + "|" + t] / medians[c.name + "|" + t],
                  medians[general + "|warp|" + t] / medians[c.name + "|warp|" + t]);
    }
  }
  return 0;
}

}  // namespace vs
