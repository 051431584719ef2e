#!/usr/bin/env bash
# Checks that two builds of ViewSyn write byte-identical views: a change meant to make ViewSyn faster
# must not change its output. Runs both builds' ViewSyn on a fixed set of real configs (the 19
# Middlebury 2005/2006 scenes with seven settings that reach every path: general and 1D configs, the
# general config on the 1D path, missing depth with MissingDepthFill, Filter 2 with
# BoundaryNoiseRemoval, Filter 0 Precision 1 IvsrsInpaint 0 SplattingOption 1, ColorSpace 1; the
# Teddy sets; open3d; SceneGen's moving 10-frame demo, general and 1D) with 1 and 2 threads, and
# compares the outputs' checksums.
#
# Usage: scripts/compare_outputs.sh BIN_A BIN_B [DATA_DIR]
#   BIN_A, BIN_B  folders holding a ViewSyn each (e.g. a worktree's Bin/ built at the base commit)
#   DATA_DIR      the data sets (default: $VS_DATA_DIR, else ../shared/data)
# Exit status: 0 all identical, 1 some output differs or a run failed, 2 bad usage, 77 no data.
set -uo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 2 ]]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
binA=$(cd "$1" && pwd) || exit 2
binB=$(cd "$2" && pwd) || exit 2
data=${3:-${VS_DATA_DIR:-../shared/data}}
for b in "$binA" "$binB"; do
  [[ -x "$b/ViewSyn" ]] || { echo "compare_outputs: no executable ViewSyn in $b" >&2; exit 2; }
done
if [[ ! -d "$data/middlebury2005" ]]; then
  echo "compare_outputs: no Middlebury data in $data (set VS_DATA_DIR or pass DATA_DIR): nothing compared" >&2
  exit 77
fi
data=$(cd "$data" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

runs=0 differ=0 failed=0
# compare DIR CONFIG [Key=Value ...]
compare() {
  local dir=$1 cfg=$2
  shift 2
  [[ -f "$dir/$cfg" ]] || return 0
  local sums=()
  for b in "$binA" "$binB"; do
    if ! (cd "$dir" && "$b/ViewSyn" "$cfg" OutputVirtualViewImageName="$work/out.yuv" "$@" >"$work/log" 2>&1); then
      echo "FAILED  $b/ViewSyn $dir/$cfg $*" >&2
      sed 's/^/    /' "$work/log" | tail -3 >&2
      failed=$((failed + 1))
      return 0
    fi
    sums+=("$(md5sum <"$work/out.yuv" | cut -d' ' -f1)")
  done
  runs=$((runs + 1))
  if [[ "${sums[0]}" != "${sums[1]}" ]]; then
    echo "DIFFERS $dir/$cfg $*"
    differ=$((differ + 1))
  fi
}

# A moving 10-frame sequence (SceneGen's demo, rendered by BIN_B's SceneGen when it has one): what
# only sequences reach, the 1D path's TemporalImprovementOption and reading ahead.
demo=""
if [[ -x "$binB/SceneGen" ]] && "$binB/SceneGen" Scene=demo OutputFolder="$work/demo" >/dev/null 2>&1; then
  demo="$work/demo"
else
  echo "compare_outputs: no SceneGen in $binB: the demo sequence is not compared" >&2
fi

for threads in 1 2; do
  if [[ -n "$demo" ]]; then
    compare "$demo" viewsyn_cam1.cfg Threads=$threads
    compare "$demo" viewsyn_cam1.cfg SynthesisMode=1 Threads=$threads
  fi
  for dir in "$data"/middlebury2005/* "$data"/middlebury2006/*; do
    [[ -d "$dir" ]] || continue
    compare "$dir" synth_view3_general.cfg Threads=$threads
    compare "$dir" synth_view3_1d.cfg Threads=$threads
    compare "$dir" synth_view3_general.cfg SynthesisMode=1 Threads=$threads
    compare "$dir" synth_view3_general.cfg MissingDepthLevel=0 MissingDepthFill=1 Threads=$threads
    compare "$dir" synth_view2_general.cfg Filter=2 Precision=4 BoundaryNoiseRemoval=1 Threads=$threads
    compare "$dir" synth_view4_general.cfg Filter=0 Precision=1 IvsrsInpaint=0 SynthesisMode=1 SplattingOption=1 Threads=$threads
    compare "$dir" synth_view4_general.cfg Filter=2 Precision=2 ColorSpace=1 Threads=$threads
  done
  for dir in "$data"/middlebury2003/*; do
    [[ -d "$dir" ]] || continue
    compare "$dir" synth_view4_1d.cfg Threads=$threads
    compare "$dir" synth_view5_general.cfg Threads=$threads
  done
  for cfg in "$data"/open3d/*/*.cfg; do
    [[ -f "$cfg" ]] || continue
    compare "$(dirname "$cfg")" "$(basename "$cfg")" Threads=$threads
  done
done

echo "compare_outputs: $runs runs compared, $differ differ, $failed failed"
[[ $differ -eq 0 && $failed -eq 0 ]]
