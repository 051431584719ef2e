#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs the whole test suite with CTest.
# The default build is the runtime-dispatch one (VS_X86_64_LEVEL=dispatch: the kernels for every
# x86-64 level, everything else at the baseline, SSE2 only): it also runs under valgrind (CTest
# Valgrind), and the tests of the stages with per-level kernels and scalar fallbacks, the golden-output
# test among them (the same MD5s at every level), run again once per lower x86-64 level the machine
# runs, capped by the environment variable VS_X86_64_LEVEL. A second build, pinned to the machine's
# highest level (-DVS_X86_64_LEVEL=auto, build-pinned, executables in build-pinned/Bin: every file
# compiled for that level), compiles only those tests and runs them: the same output from a build
# whose every loop the compiler vectorised for the machine. Then the tree is built once more with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan, whose executables stay in
# build-asan/Bin so that Bin/ keeps the normal ones) and the whole suite runs again. Any sanitizer
# report fails the test that triggered it.
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

# The tests of the stages with per-level kernels or fallbacks (their gtest suites), by name.
level_tests='(^|/)(Golden|GoldenOutput|Raster|RowWarp|RowKernels|Blend|HoleFill|Interpolation|SubPixelSampler|Synth|ViewProjection|Cracks|EdgeAlign|EdgeAlignOnTheSquare|Occlusion|Version)\.'
start=$(date +%s)
# The CPU's highest level, as the dispatch build's ViewSyn finds it; then those tests at every level
# below it, capped by the environment variable (the tools the golden-output test runs inherit it).
top=$(Bin/ViewSyn --version | sed -n 's/^x86-64 level: x86-64-v\([234]\).*/\1/p')
top=${top:-1}
for level in $(seq 1 $((top - 1))); do
  echo "capped at x86-64 level $level"
  (cd build && VS_X86_64_LEVEL=$level ctest --output-on-failure -j"$(nproc)" -R "$level_tests")
done
echo "tests at the lower x86-64 levels (1 to $((top - 1))): $(( $(date +%s) - start )) s"

start=$(date +%s)
cmake -S . -B build-pinned -DCMAKE_BUILD_TYPE=Release -DVS_X86_64_LEVEL=auto \
  -DVS_BIN_OUTPUT_DIR="$PWD/build-pinned/Bin" \
  -DVS_TEST_SOURCES='/(GoldenOutput|Raster|RowWarp|RowKernels|Blend|Synth|HoleFill|Cracks|EdgeAlign|Occlusion|Version)Test\.cpp$' >/dev/null
cmake --build build-pinned -j"$(nproc)" --target UnitTests RegressionTests
echo "pinned build: $(( $(date +%s) - start )) s"
start=$(date +%s)
(cd build-pinned && ctest --output-on-failure -j"$(nproc)" -R "$level_tests")
echo "pinned build's tests: $(( $(date +%s) - start )) s"

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
