#!/usr/bin/env bash
# Times whole one-frame ViewSyn processes of several builds, alternating them run by run (so that a
# change of the machine's load falls on all of them alike), and prints each build's medians: wall
# seconds, CPU seconds of all its threads (perf stat task-clock, when perf can count it) and the
# seconds per stage from the log's last line.
#
# Usage: scripts/alternate_runs.sh [-n RUNS] [-d SCENE_DIR] CONFIG BIN_A [BIN_B ...] [-- KEY=VALUE ...]
#   RUNS       runs per build (default 11)
#   SCENE_DIR  folder the config is run from (default ../shared/data/middlebury2005/Art)
#   CONFIG     config file name in SCENE_DIR, e.g. synth_view3_general.cfg
#   BIN_x      folders holding a ViewSyn each (relative ones from the repository root); keys after --
#              are passed to every run
# Example: scripts/alternate_runs.sh -n 21 synth_view3_1d.cfg /tmp/base/Bin Bin
set -uo pipefail
cd "$(dirname "$0")/.."
runs=11 scene=../shared/data/middlebury2005/Art
while getopts "n:d:" opt; do
  case $opt in
    n) runs=$OPTARG ;;
    d) scene=$OPTARG ;;
    *) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
if [[ $# -lt 2 ]]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
cfg=$1
shift
bins=() keys=()
while [[ $# -gt 0 && $1 != -- ]]; do bins+=("$(cd "$1" && pwd)") || exit 2; shift; done
[[ $# -gt 0 ]] && shift && keys=("$@")
scene=$(cd "$scene" && pwd) || exit 2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
perfOk=0
perf stat -x, -e task-clock -o "$work/probe" true >/dev/null 2>&1 && perfOk=1
cd "$scene" || exit 2
for ((i = 0; i < runs; ++i)); do
  for b in "${bins[@]}"; do
    start=$(date +%s%N)
    if ((perfOk)); then
      perf stat -x, -e task-clock -o "$work/perf" "$b/ViewSyn" "$cfg" "OutputVirtualViewImageName=$work/out.yuv" \
        "${keys[@]}" >"$work/log" 2>&1
    else
      "$b/ViewSyn" "$cfg" "OutputVirtualViewImageName=$work/out.yuv" "${keys[@]}" >"$work/log" 2>&1
    fi || { echo "alternate_runs: $b/ViewSyn failed:" >&2; tail -3 "$work/log" >&2; exit 1; }
    end=$(date +%s%N)
    cpu=nan
    ((perfOk)) && cpu=$(awk -F, '/task-clock/ {print $1 / 1000}' "$work/perf")
    stages=$(sed -nE 's/^seconds per frame: read ([0-9.]+), depth warp ([0-9.]+), texture warp ([0-9.]+), blend ([0-9.]+), hole fill ([0-9.]+), write ([0-9.]+), total ([0-9.]+).*/\1 \2 \3 \4 \5 \6 \7/p' "$work/log")
    echo "$b $(((end - start) / 1000)) $cpu $stages" >>"$work/times"
  done
done
echo "$(uptime)"
python3 - "$work/times" "$cfg" "${bins[@]}" <<'PY'
import statistics, sys
times, cfg, bins = sys.argv[1], sys.argv[2], sys.argv[3:]
names = "wall cpu read depth-warp texture-warp blend hole-fill write total".split()
rows = [line.split() for line in open(times)]
for b in bins:
    mine = [r[1:] for r in rows if r[0] == b]
    medians = [statistics.median(float(r[c]) for r in mine) for c in range(len(names))]
    medians[0] /= 1e6
    print(f"{cfg} {b} (median of {len(mine)}): " + ", ".join(f"{n} {m:.4f}" for n, m in zip(names, medians)))
PY
