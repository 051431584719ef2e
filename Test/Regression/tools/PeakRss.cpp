// PeakRss REPORT PROGRAM [ARGUMENTS...]: runs PROGRAM and writes "seconds peak-RSS-KiB exit-code" to
// REPORT, like `/usr/bin/time -f "%e %M"` (which a fresh Debian may lack); exits with PROGRAM's code.
//
// Linux carries a process's peak RSS across fork and exec, so a program started straight from a test
// process that has used much memory would report the test's peak. This helper is small, and the
// program it forks starts from its small footprint.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: PeakRss REPORT PROGRAM [ARGUMENTS...]\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) return 125;
  if (pid == 0) {
    execv(argv[2], argv + 2);
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  if (wait4(pid, &status, 0, &usage) != pid) return 125;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::FILE* report = std::fopen(argv[1], "w");
  if (!report) return 125;
  std::fprintf(report, "%.3f %ld %d\n", seconds, usage.ru_maxrss, code);
  std::fclose(report);
  return code;
}
