#!/usr/bin/env python3
"""Cold and warm whole ViewSyn processes: per round and build in turn, WAIT seconds idle, one cold run,
then three warm runs; prints each run, then per build the medians of cold and warm runs (wall, CPU of
all threads by perf stat task-clock, system CPU, the log's frame total) and their ratios.

Usage: scripts/cold_warm.py ROUNDS WAIT FOLDER CONFIG BIN_A [BIN_B ...]
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
rounds, wait, folder, config = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3], sys.argv[4]
bins = [os.path.abspath(b) for b in sys.argv[5:]]
work = tempfile.mkdtemp()


def run(b):
    counters = os.path.join(work, 'perf')
    command = ['perf', 'stat', '-x,', '-e', 'task-clock', '-o', counters, os.path.join(b, 'ViewSyn'), config,
               'OutputVirtualViewImageName=' + os.path.join(work, 'out.yuv')]
    start = time.perf_counter()
    child = subprocess.Popen(command, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    log = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        sys.exit(f"{' '.join(command)} failed ({status})")
    cpu = [float(line.split(',')[0]) / 1000 for line in open(counters) if 'task-clock' in line][0]
    frame = [line for line in log.splitlines() if line.startswith('seconds per frame')]
    frame = float(frame[0].split('total ')[1].split()[0]) if frame else float('nan')
    return (wall, cpu, usage.ru_stime, frame)


results = {b: {'cold': [], 'warm': []} for b in bins}
for r in range(rounds):
    for b in bins:
        time.sleep(wait)
        cold = run(b)
        warm = [run(b) for _ in range(3)]
        results[b]['cold'].append(cold)
        results[b]['warm'] += warm
        print(f"round {r} {b}: cold wall {cold[0]:.4f} cpu {cold[1]:.4f} sys {cold[2]:.3f} frame {cold[3]:.4f}; warm walls "
              + ' '.join(f"{w[0]:.4f}" for w in warm) + "; load " + open('/proc/loadavg').read().split()[0], flush=True)
for b in bins:
    for k, name in enumerate(['wall', 'cpu', 'system cpu', 'frame']):
        cold = statistics.median(x[k] for x in results[b]['cold'])
        warm = statistics.median(x[k] for x in results[b]['warm'])
        print(f"{b} {name}: cold {cold:.4f} warm {warm:.4f} cold/warm {cold / warm:.2f}")
