#!/bin/sh
# Regenerates docs/results.md and docs/img/mesh_vs_psnr.png from ../shared/data.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
/usr/bin/python3 scripts/results.py "$@"
