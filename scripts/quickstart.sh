#!/usr/bin/env bash
# The README's first command: installs what is needed (Debian packages), builds, then runs the main
# job with the ready configs of cfg/demo: SceneGen renders the demo scene (cfg/scenes/demo.scene: 3
# cameras, 1024x768, 10 frames, exact depth and ground truth) into out/demo, and ViewSyn synthesizes
# the middle camera from its two neighbours, printing PSNR against the ground truth and seconds per
# frame. With the data sets in ../shared/data, `Bin/ViewSyn cfg/art_view3.cfg` does the same for a
# real scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh build
Bin/SceneGen cfg/demo/scenegen.cfg
Bin/ViewSyn cfg/demo/viewsyn_cam1.cfg
