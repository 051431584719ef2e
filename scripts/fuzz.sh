#!/usr/bin/env bash
# Fuzzes the config parser, the camera file parsers (VSRS text, MPEG-I JSON) and the YUV reader with
# libFuzzer (issue 8).
#
#   scripts/fuzz.sh MINUTES [TARGET]   build, then run each target (or TARGET) for MINUTES minutes,
#                                      one after the other
#   scripts/fuzz.sh --merge [TARGET]   fold what the runs found into the committed corpus, minimized
#                                      with -merge=1 (then review and commit Test/Fuzz/corpus)
#
# TARGET: FuzzConfig, FuzzCameraFile, FuzzCameraJson or FuzzYuv. Needs clang (Debian's clang 14 ships libFuzzer).
# Builds into build-fuzz with ASan + UBSan and coverage for the library. Seeds: the configs and the
# camera files of ../shared/vsrs-samples (VS_SAMPLES_DIR), a few generated YUV files, and the
# committed corpus Test/Fuzz/corpus/TARGET; Test/Fuzz/TARGET.dict is the dictionary where there is
# one. New inputs go to build-fuzz/corpus/TARGET, crashes and hangs to build-fuzz/crashes/TARGET; a
# crash input, once fixed, belongs in the committed corpus.
set -euo pipefail
cd "$(dirname "$0")/.."

all_targets="FuzzConfig FuzzCameraFile FuzzCameraJson FuzzYuv"
mode=run
if [[ "${1:-}" == "--merge" ]]; then
  mode=merge
  targets=${2:-$all_targets}
else
  minutes=${1:?usage: scripts/fuzz.sh MINUTES [TARGET] | scripts/fuzz.sh --merge [TARGET]}
  targets=${2:-$all_targets}
fi
samples=${VS_SAMPLES_DIR:-../shared/vsrs-samples}
build=build-fuzz

cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVS_FUZZ=ON \
  -DVS_SANITIZE=ON -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" -DVS_BIN_OUTPUT_DIR="$PWD/$build/Bin" >/dev/null
# shellcheck disable=SC2086
cmake --build "$build" -j"$(nproc)" --target $targets

# Seeds from outside the corpus.
seeds=$build/seeds
rm -rf "$seeds"
mkdir -p "$seeds/FuzzConfig" "$seeds/FuzzCameraFile" "$seeds/FuzzCameraJson" "$seeds/FuzzYuv"
if [[ -d "$samples" ]]; then
  find "$samples/configs" -name '*.cfg' -exec cp {} "$seeds/FuzzConfig/" \;
  find "$samples/cameras" -name '*.txt' -exec sh -c 'cp "$1" "$2/$(basename "$(dirname "$1")")_$(basename "$1")"' \
    _ {} "$seeds/FuzzCameraFile" \;
else
  echo "note: $samples is absent; seeding with the committed corpus only"
fi
# YUV: byte 0 = size (width 1 + b & 7, height 1 + (b >> 3) & 3), byte 1 = chroma (b & 3) and bit
# depth (8 + (b >> 2) % 9), then the file: zeros, a ramp, all ones, and a cut frame.
yuv_seed() {  # name header-octal-bytes count fill
  { printf "$2"; head -c "$3" "$4"; } >"$seeds/FuzzYuv/$1"
}
yuv_seed zeros_8x4_420_8bit '\037\002' 96 /dev/zero
yuv_seed zeros_3x2_444_10bit '\012\011' 72 /dev/zero
yuv_seed random_8x4_400_8bit '\037\000' 100 /dev/urandom
yuv_seed random_2x1_420_16bit '\000\042' 64 /dev/urandom
yuv_seed ones_5x3_444_12bit '\024\021' 200 <(tr '\0' '\001' </dev/zero)

summary=()
for target in $targets; do
  corpus=$build/corpus/$target
  crashes=$build/crashes/$target
  mkdir -p "$corpus" "$crashes"
  if [[ $mode == merge ]]; then
    committed=Test/Fuzz/corpus/$target
    merged=$build/merged/$target
    rm -rf "$merged"
    mkdir -p "$merged" "$committed"
    # Edges only (no hit counters): keeps the committed corpus small (< 200 files a target).
    "$build/Fuzz/$target" -merge=1 -use_counters=0 -timeout=10 -rss_limit_mb=2048 \
      "$merged" "$committed" "$corpus" "$seeds/$target" 2>&1 | tail -n 3
    # Named seeds (regression-*: inputs that once crashed; seed-*: hand-made) stay as they are; the rest
    # is replaced by the merged set, less the copies of the named ones (libFuzzer names by SHA-1).
    find "$committed" -type f ! -name 'regression-*' ! -name 'seed-*' -delete
    for kept in "$committed"/*; do
      [[ -f "$kept" ]] && rm -f "$merged/$(sha1sum "$kept" | cut -d' ' -f1)"
    done
    cp "$merged"/* "$committed"/ 2>/dev/null || true
    echo "$target: $(find "$committed" -type f | wc -l) files, $(du -sb "$committed" | cut -f1) bytes in $committed"
    continue
  fi
  log=$build/$target.log
  dict=()
  [[ -f Test/Fuzz/$target.dict ]] && dict=(-dict="Test/Fuzz/$target.dict")
  echo "== $target: $minutes min"
  set +e
  "$build/Fuzz/$target" -max_total_time=$((minutes * 60)) -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    "${dict[@]}" -artifact_prefix="$crashes/" "$corpus" "Test/Fuzz/corpus/$target" "$seeds/$target" >"$log" 2>&1
  status=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  found=$(find "$crashes" -type f | wc -l)
  line="$target: exit $status, $runs runs, $speed exec/s, $(ls "$corpus" | wc -l) corpus inputs, $found crash/hang files in $crashes"
  echo "$line"
  [[ $status -ne 0 ]] && grep -m 5 -E 'ERROR|SUMMARY|Check failed|runtime error|deadly signal|timeout' "$log" || true
  summary+=("$line")
done
if [[ $mode == run ]]; then
  echo
  echo "fuzz summary ($minutes min per target):"
  printf '  %s\n' "${summary[@]}"
fi
