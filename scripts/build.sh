#!/bin/sh
# Installs the Debian packages (if missing) and builds build/tristereo (Release).
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
