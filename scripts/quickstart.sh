#!/usr/bin/env bash
# The README's first command: installs what is needed (Debian packages), builds, then runs the main
# job on the built-in default scene: SceneGen renders the `demo` scene (3 cameras, 1024x768, 10
# frames, exact depth and ground truth) into out/demo, and ViewSyn synthesizes the middle camera from
# its two neighbours, printing PSNR against the ground truth and seconds per frame.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh build
mkdir -p out
Bin/SceneGen Scene=demo OutputFolder=out/demo
Bin/ViewSyn out/demo/viewsyn_cam1.cfg
