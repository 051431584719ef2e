#!/usr/bin/env python3
"""Times whole ViewSyn processes of several builds, alternating them run by run, and prints each
build's medians: wall seconds (from the parent), CPU seconds of all threads (perf stat task-clock),
user+sys seconds and peak resident memory (wait4's rusage) and page faults (perf stat).

Usage: scripts/measure_processes.py RUNS FOLDER CONFIG BIN_A [BIN_B ...] [-- KEY=VALUE ...]
  FOLDER  the folder the config is run from; BIN_x folders holding a ViewSyn each, or NAME=VALUE,...@BIN
          to run BIN's with these variables in the environment (e.g. VS_HUGE_PAGES=0@Bin); keys after --
          are passed to every run. NOPERF=1 in the environment runs without perf (no task-clock, faults).
Example: scripts/measure_processes.py 21 ../shared/data/middlebury2005/Art synth_view3_general.cfg /tmp/base/Bin Bin
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

if len(sys.argv) < 5:
    sys.exit(__doc__)
runs, folder, config = int(sys.argv[1]), sys.argv[2], sys.argv[3]
rest = sys.argv[4:]
keys = rest[rest.index('--') + 1:] if '--' in rest else []
bins = rest[:rest.index('--')] if '--' in rest else rest


def split_case(case):
    """(folder of ViewSyn, environment) of BIN or NAME=VALUE,...@BIN."""
    env = dict(os.environ)
    if '@' in case:
        assignments, case = case.split('@', 1)
        for assignment in assignments.split(','):
            key, value = assignment.split('=', 1)
            env[key] = value
    return os.path.abspath(case), env


usePerf = not os.environ.get('NOPERF')
work = tempfile.mkdtemp()
results = {b: [] for b in bins}
for _ in range(runs):
    for b in bins:
        counters = os.path.join(work, 'perf')
        folderOfBin, env = split_case(b)
        command = [os.path.join(folderOfBin, 'ViewSyn'), config, 'OutputVirtualViewImageName=' + os.path.join(work, 'out.yuv')] + keys
        if usePerf:
            command = ['perf', 'stat', '-x,', '-e', 'task-clock,page-faults', '-o', counters] + command
        start = time.perf_counter()
        child = subprocess.Popen(command, cwd=folder, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - start
        if status != 0:
            sys.exit(f"{' '.join(command)} failed ({status})")
        cpu = faults = float('nan')
        for line in open(counters) if usePerf else []:
            fields = line.split(',')
            if len(fields) > 2 and fields[2].startswith('task-clock'):
                cpu = float(fields[0]) / 1000
            if len(fields) > 2 and fields[2].startswith('page-faults'):
                faults = float(fields[0])
        results[b].append((wall, cpu, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, faults))
print(os.popen('uptime').read().strip())
for b in bins:
    m = [statistics.median(r[k] for r in results[b]) for k in range(5)]
    print(f"{b}: wall {m[0]:.4f} s, task-clock {m[1]:.4f} s, user+sys {m[2]:.3f} s, peak {m[3]:.1f} MiB, "
          f"page faults {m[4]:.0f} (medians of {len(results[b])}; wall min {min(r[0] for r in results[b]):.4f} s)")
