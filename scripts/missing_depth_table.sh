#!/usr/bin/env bash
# The table of issue 32: mean PSNR-Y per scene with each reading of depth level 0 (today's default,
# MissingDepthLevel=0, MissingDepthLevel=0 MissingDepthFill=1, and whatever extra settings are given
# as further columns), for the 19 Middlebury 2005/2006 scenes, open3d, Teddy/Venus and the SceneGen
# demo. Prints a Markdown table; with a column `auto`, also the decision ViewSyn printed.
#   scripts/missing_depth_table.sh [-b BIN] [-d DATA] [-v VIEW] [-j JOBS] [-t TOOL] [COLUMN=SETTINGS ...]
#   e.g. scripts/missing_depth_table.sh -v view3 'default=MissingDepthLevel=-1' 'auto='
# A column is NAME=SETTINGS, SETTINGS a space-separated list of Key=Value (may be empty).
# Without columns: default (-1), missing (0), filled (0 + fill), auto (the tool's default).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$root/Bin data=${VS_DATA_DIR:-$root/../shared/data} view=view3 jobs=2 tool=ViewSyn
while getopts b:d:v:j:t: opt; do
  case $opt in
    b) bin=$(cd "$OPTARG" && pwd) ;; d) data=$(cd "$OPTARG" && pwd) ;; v) view=$OPTARG ;;
    j) jobs=$OPTARG ;; t) tool=$OPTARG ;; *) sed -n 2,9p "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
columns=("$@")
[ ${#columns[@]} -gt 0 ] || columns=('default=MissingDepthLevel=-1' 'missing=MissingDepthLevel=0'
  'filled=MissingDepthLevel=0 MissingDepthFill=1' 'auto=')
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Scenes: folder and config (relative to the data folder).
scenes=()
for d in "$data"/middlebury2005/* "$data"/middlebury2006/*; do scenes+=("${d#$data/}:synth_${view}_general.cfg"); done
case $view in view2 | view3 | view4) [ -f "$data/open3d/RGBD5/synth_${view}_general.cfg" ] && scenes+=("open3d/RGBD5:synth_${view}_general.cfg") ;; esac
for d in middlebury2001/Venus middlebury2003/TeddyH; do
  [ -f "$data/$d/synth_${view}_general.cfg" ] && scenes+=("$d:synth_${view}_general.cfg")
done
if [ -x "$bin/SceneGen" ] && [ "$tool" = ViewSyn ]; then
  (cd "$root" && "$bin/SceneGen" cfg/demo/scenegen.cfg OutputFolder="$work/demo" > /dev/null 2>&1) &&
    scenes+=("demo:$work/demo") || echo "SceneGen demo failed; left out" >&2
fi

# One job per (scene, column): its log goes to work/<scene>__<column>.log.
joblist=$work/jobs
: > "$joblist"
for s in "${scenes[@]}"; do
  for c in "${columns[@]}"; do printf '%s\t%s\t%s\n' "${s%%:*}" "${s#*:}" "$c" >> "$joblist"; done
done
run_one() {
  local scene=$1 cfg=$2 column=$3 name=${3%%=*} settings=${3#*=}
  local log="$WORK/$(echo "$scene" | tr / _)__$name.log"
  if [ "$scene" = demo ]; then
    (cd "$ROOT/cfg/demo" && "$BIN/$TOOL" viewsyn_cam1.cfg Threads=1 \
      CameraParameterFile="$cfg/cameras.txt" LeftViewImageName="$cfg/texture_cam0.yuv" \
      RightViewImageName="$cfg/texture_cam2.yuv" LeftDepthMapName="$cfg/depth_cam0.yuv" \
      RightDepthMapName="$cfg/depth_cam2.yuv" ReferenceVirtualViewImageName="$cfg/texture_cam1.yuv" \
      OutputVirtualViewImageName="$WORK/$name.demo.yuv" $settings) > "$log" 2>&1 || echo "FAILED" >> "$log"
  else
    (cd "$DATA/$scene" && "$BIN/$TOOL" "$cfg" Threads=1 ReferenceVirtualViewImageName="$VIEW.yuv" \
      OutputVirtualViewImageName="$WORK/$(echo "$scene" | tr / _).$name.yuv" $settings) > "$log" 2>&1 ||
      echo "FAILED" >> "$log"
  fi
}
export -f run_one
export VIEW=$view WORK=$work ROOT=$root BIN=$bin DATA=$data TOOL=$tool
tr '\n' '\0' < "$joblist" | xargs -0 -P "$jobs" -I{} bash -c 'IFS=$'"'"'\t'"'"' read -r a b c <<< "{}"; run_one "$a" "$b" "$c"'

# The table.
mean_psnr() {  # the mean PSNR-Y the log printed
  grep -E '^mean PSNR' "$1" | grep -oE '[0-9]+\.[0-9]+' | head -1
}
header="| scene |" rule="|---|"
for c in "${columns[@]}"; do header+=" ${c%%=*} |"; rule+="---|"; done
header+=" decision |"; rule+="---|"
echo "$header"; echo "$rule"
declare -A sum count
for s in "${scenes[@]}"; do
  scene=${s%%:*} row="| $scene |" decision=""
  for c in "${columns[@]}"; do
    name=${c%%=*} log="$work/$(echo "$scene" | tr / _)__$name.log"
    p=$(mean_psnr "$log" || true)
    [ -n "$p" ] || { p="fail"; sed 's/^/    /' "$log" | tail -5 >&2; }
    row+=" $p |"
    case $scene in middlebury200[56]/*) [ "$p" = fail ] || { sum[$name]=$(echo "${sum[$name]:-0} + $p" | bc -l); count[$name]=$((${count[$name]:-0} + 1)); } ;; esac
    if [ "$name" = auto ]; then decision=$(grep -E 'depth level 0 \(auto\)' "$log" | sed 's/^.*(auto), //' | tr '\n' ';' || true); fi
  done
  echo "$row $decision |"
done
row="| Middlebury mean |"
for c in "${columns[@]}"; do
  name=${c%%=*}
  row+=" $(printf '%.2f' "$(echo "${sum[$name]:-0} / ${count[$name]:-1}" | bc -l)") |"
done
echo "$row |"
