#!/bin/sh
# Installs what building needs (scripts/install-deps.sh main: compiler, CMake,
# libraries; no test or benchmark frameworks) and builds the library and the
# program build/tristereo (Release). The test command (scripts/test.sh)
# reconfigures the same tree with the tests and benchmarks on.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh main
scripts/configure.sh build -S . -DCMAKE_BUILD_TYPE=Release \
  -DTRISTEREO_BUILD_TESTS=OFF -DTRISTEREO_BUILD_BENCH=OFF -DTRISTEREO_BUILD_APPS=ON
cmake --build build -j"$(nproc)" --target tristereo_cli
