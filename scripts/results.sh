#!/bin/sh
# Regenerates docs/results.md and docs/img/mesh_vs_psnr.png from ../shared/data
# (or $TRISTEREO_DATA_DIR): builds build/tristereo, installs matplotlib for the
# plot (scripts/install-deps.sh plot), then runs scripts/results.py, which
# scores every scene of every set (scripts/score_all.py) beside the peers.
# Arguments go to results.py (e.g. --repeats 3, --data DIR).
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
scripts/install-deps.sh plot
/usr/bin/python3 scripts/results.py "$@"
