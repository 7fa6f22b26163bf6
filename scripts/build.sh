#!/bin/sh
# Installs what building needs (scripts/install-deps.sh main: compiler, CMake,
# libraries; no test or benchmark frameworks) and builds the library and the
# program build/tristereo (Release). The test command (scripts/test.sh)
# reconfigures the same tree with the tests and benchmarks on.
#
# A tree configured before keeps its choice of tests and benchmarks: turning
# them off here (as a fresh tree has them) would leave their last binaries in
# build/, which `cmake --build build` then no longer rebuilds, so a later
# benchmark or ctest run would measure old code without a word.
set -eu
cd "$(dirname "$0")/.."
cached() {  # cached NAME: NAME's value in build/'s cache (empty when none)
  if [ -f build/CMakeCache.txt ]; then sed -n "s/^$1:BOOL=//p" build/CMakeCache.txt | head -n 1; fi
}
tests=$(cached TRISTEREO_BUILD_TESTS)
bench=$(cached TRISTEREO_BUILD_BENCH)
scripts/install-deps.sh main
scripts/configure.sh build -S . -DCMAKE_BUILD_TYPE=Release \
  -DTRISTEREO_BUILD_TESTS="${tests:-OFF}" -DTRISTEREO_BUILD_BENCH="${bench:-OFF}" -DTRISTEREO_BUILD_APPS=ON
cmake --build build -j"$(nproc)" --target tristereo_cli
