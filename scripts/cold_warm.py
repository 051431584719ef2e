#!/usr/bin/env python3
"""Cold and warm whole processes: per round and case in turn, WAIT seconds idle, one cold run, then
three warm runs; prints each run, then per case the medians of cold and warm runs (wall, CPU of all
threads by perf stat task-clock, system CPU, the log's frame total) and their ratios.

Usage: scripts/cold_warm.py ROUNDS WAIT FOLDER CONFIG CASE [CASE ...]
  CASE  BIN                 BIN/ViewSyn CONFIG OutputVirtualViewImageName=... in FOLDER
        KEY=VALUE,...@BIN   the same with these variables in the environment (e.g. VS_HUGE_PAGES=0@Bin)
        version:BIN         BIN/ViewSyn --version (a trivial process: the machine's own cold start)
        vsrs:EXE            a VSRS executable given CONFIG, run from a folder of links to FOLDER's
                            files (it writes its output there), as SynthBench --vsrs runs it
NOPERF=1 in the environment runs without perf stat (whose own start is in the wall clock); the CPU
column is then user+sys from wait4.
Example: scripts/cold_warm.py 5 30 ../shared/data/middlebury2005/Art synth_view3_general.cfg /tmp/base/Bin Bin
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

if len(sys.argv) < 6:
    sys.exit(__doc__)
rounds, wait, folder, config = int(sys.argv[1]), float(sys.argv[2]), os.path.abspath(sys.argv[3]), sys.argv[4]
cases = sys.argv[5:]
work = tempfile.mkdtemp()


def vsrs_folder():
    links = os.path.join(work, 'vsrs')
    if not os.path.isdir(links):
        os.makedirs(links)
        output = [line.split()[1] for line in open(os.path.join(folder, config))
                  if line.split()[:1] == ['OutputVirtualViewImageName']]
        for name in os.listdir(folder):
            if name not in output:
                os.symlink(os.path.join(folder, name), os.path.join(links, name))
    return links


def command_of(case):
    """(argv, environment, folder) of a case."""
    env = dict(os.environ)
    if case.startswith('version:'):
        return [os.path.join(os.path.abspath(case[8:]), 'ViewSyn'), '--version'], env, folder
    if case.startswith('vsrs:'):
        return [os.path.abspath(case[5:]), config], env, vsrs_folder()
    if '@' in case:
        assignments, case = case.split('@', 1)
        for assignment in assignments.split(','):
            key, value = assignment.split('=', 1)
            env[key] = value
    return [os.path.join(os.path.abspath(case), 'ViewSyn'), config,
            'OutputVirtualViewImageName=' + os.path.join(work, 'out.yuv')], env, folder


def run(case):
    counters = os.path.join(work, 'perf')
    argv, env, cwd = command_of(case)
    command = argv if os.environ.get('NOPERF') else ['perf', 'stat', '-x,', '-e', 'task-clock', '-o', counters] + argv
    start = time.perf_counter()
    child = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    log = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        sys.exit(f"{' '.join(command)} failed ({status})")
    if os.environ.get('NOPERF'):
        cpu = usage.ru_utime + usage.ru_stime
    else:
        cpu = [float(line.split(',')[0]) / 1000 for line in open(counters) if 'task-clock' in line][0]
    frame = [line for line in log.splitlines() if line.startswith('seconds per frame')]
    frame = float(frame[0].split('total ')[1].split()[0]) if frame else float('nan')
    return (wall, cpu, usage.ru_stime, frame)


results = {c: {'cold': [], 'warm': []} for c in cases}
print(os.popen('uptime').read().strip(), flush=True)
for r in range(rounds):
    for c in cases:
        time.sleep(wait)
        cold = run(c)
        warm = [run(c) for _ in range(3)]
        results[c]['cold'].append(cold)
        results[c]['warm'] += warm
        print(f"round {r} {c}: cold wall {cold[0]:.4f} cpu {cold[1]:.4f} sys {cold[2]:.3f} frame {cold[3]:.4f}; warm walls "
              + ' '.join(f"{w[0]:.4f}" for w in warm) + "; load " + open('/proc/loadavg').read().split()[0], flush=True)
print(os.popen('uptime').read().strip())
for c in cases:
    for k, name in enumerate(['wall', 'cpu', 'system cpu', 'frame']):
        cold = statistics.median(x[k] for x in results[c]['cold'])
        warm = statistics.median(x[k] for x in results[c]['warm'])
        print(f"{c} {name}: cold {cold:.4f} warm {warm:.4f} cold/warm {cold / warm if warm else float('nan'):.2f}")
