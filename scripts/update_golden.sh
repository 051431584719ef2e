#!/usr/bin/env bash
# Rewrites Test/golden.md5, the MD5s the golden-output test (Test/Regression/GoldenOutputTest.cpp)
# pins, and prints every digest that changed as "golden: NAME: OLD -> NEW". Only for an intended
# change of pictures: say in the commit which outputs changed and why. Build dir: $1 (default build).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
cmake --build "$build_dir" --target RegressionTests ViewSyn MeshRender SceneGen -j"$(nproc)" > /dev/null
VS_UPDATE_GOLDEN=1 "$build_dir/Test/RegressionTests" --gtest_filter='Golden*' --gtest_brief=1 | grep '^golden:' ||
  echo "no golden digest changed"
git --no-pager diff --stat -- Test/golden.md5
