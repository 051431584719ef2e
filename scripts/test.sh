#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs the whole test suite with CTest;
# then builds the tree once more with AddressSanitizer and UndefinedBehaviorSanitizer (build-asan,
# whose executables stay in build-asan/Bin so that Bin/ keeps the normal ones) and runs the whole
# suite again. Any sanitizer report fails the test that triggered it. Between the two, a third build
# with runtime dispatch (build-dispatch, -DVS_X86_64_LEVEL=dispatch: the kernels for every x86-64
# level, everything else at the baseline, SSE2 only, so every scalar and SSE2 fallback is what runs
# there) compiles only the tests and tools and runs the golden-output test (the same MD5s as the
# vector build), the version test and the unit tests of the stages that have fallbacks, once per
# x86-64 level the machine runs (capped by VS_X86_64_LEVEL).
# Set VS_DATA_DIR / VS_SAMPLES_DIR to point the data tests elsewhere (default ../shared/...);
# VS_SKIP_SANITIZE=1 skips the sanitizer run (for a quick local check; CI runs both).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
start=$(date +%s)
bash scripts/build.sh build
echo "build: $(( $(date +%s) - start )) s"
start=$(date +%s)
(cd build && ctest --output-on-failure -j"$(nproc)")
echo "tests: $(( $(date +%s) - start )) s"

start=$(date +%s)
cmake -S . -B build-dispatch -DCMAKE_BUILD_TYPE=Release -DVS_X86_64_LEVEL=dispatch \
  -DVS_BIN_OUTPUT_DIR="$PWD/build-dispatch/Bin" \
  -DVS_TEST_SOURCES='/(GoldenOutput|Raster|RowWarp|Blend|Synth|HoleFill|Cracks|EdgeAlign|Occlusion|Version)Test\.cpp$' >/dev/null
cmake --build build-dispatch -j"$(nproc)" --target UnitTests RegressionTests
echo "runtime-dispatch build: $(( $(date +%s) - start )) s"
start=$(date +%s)
# The CPU's highest level, as the dispatch build's ViewSyn finds it; then the tests at every level up
# to it, capped by the environment variable (the tools the golden-output test runs inherit it).
top=$(build-dispatch/Bin/ViewSyn --version | sed -n 's/^x86-64 level: x86-64-v\([234]\).*/\1/p')
top=${top:-1}
for level in $(seq 1 "$top"); do
  echo "runtime-dispatch build capped at x86-64 level $level"
  (cd build-dispatch && VS_X86_64_LEVEL=$level ctest --output-on-failure -j"$(nproc)" -E "ExperimentRunner|InstalledConsumer|SlurmExecutor|ShardTemporal")
done
echo "runtime-dispatch tests (levels 1 to $top): $(( $(date +%s) - start )) s"

if [[ "${VS_SKIP_SANITIZE:-0}" == 1 ]]; then
  echo "sanitizer run skipped (VS_SKIP_SANITIZE=1)"
  exit 0
fi
start=$(date +%s)
bash scripts/build.sh build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVS_SANITIZE=ON \
  -DVS_BIN_OUTPUT_DIR="$PWD/build-asan/Bin"
echo "sanitizer build: $(( $(date +%s) - start )) s"
start=$(date +%s)
asan="check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/Test/lsan.supp:print_suppressions=0"
# Every test but those that load Mesa's OpenGL driver (names with "Mesh"), with leak detection.
(cd build-asan && ASAN_OPTIONS="detect_leaks=1:$asan" ctest --output-on-failure -j"$(nproc)" -E Mesh)
# Mesa keeps a few blocks until exit and unloads its driver before LeakSanitizer looks, so their
# stacks cannot be told apart from ours (Test/lsan.supp holds what can be): those tests run with
# AddressSanitizer and UBSan but without leak detection.
(cd build-asan && ASAN_OPTIONS="detect_leaks=0:$asan" ctest --output-on-failure -j"$(nproc)" -R Mesh)
echo "sanitizer tests: $(( $(date +%s) - start )) s"
