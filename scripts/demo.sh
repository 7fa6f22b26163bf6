#!/bin/sh
# The main job on a built-in default, on a fresh Debian 12 machine: installs
# what it needs (scripts/build.sh: compiler, CMake, libraries; no test
# frameworks, no plotting), builds build/tristereo, then runs `tristereo demo`
# (synthetic scene with exact ground truth -> sparse and dense matching, scores,
# reference check, files in demo-out/) and, when ../shared/data is present,
# `tristereo match` on Tsukuba.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
build/tristereo info
build/tristereo demo demo-out
data=../shared/data/middlebury/tsukuba
if [ -f "$data/left.png" ]; then
  echo
  echo "Middlebury Tsukuba (../shared/data):"
  build/tristereo match "$data/left.png" "$data/right.png" --ndisp 16 \
    --disp demo-out/tsukuba_disp.pfm --disp-color demo-out/tsukuba_disp_color.png \
    --mesh demo-out/tsukuba_mesh.ply --samples demo-out/tsukuba_samples.csv \
    --stats demo-out/tsukuba_stats.json --threads 0
  build/tristereo eval demo-out/tsukuba_disp.pfm "$data/disp_left.png" --gt-scale 16 \
    --mask "$data/nonocc.png" --samples demo-out/tsukuba_samples.csv
fi
