#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs the whole test suite with CTest.
# Set VS_DATA_DIR / VS_SAMPLES_DIR to point the data tests elsewhere (default ../shared/...).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
start=$(date +%s)
bash scripts/build.sh build
echo "build: $(( $(date +%s) - start )) s"
start=$(date +%s)
(cd build && ctest --output-on-failure -j"$(nproc)")
echo "tests: $(( $(date +%s) - start )) s"
