#!/bin/sh
# The test command: on a fresh Debian 12 machine, installs what it needs, builds
# and runs every test:
#   1. native Release build, the whole GoogleTest suite (ctest);
#   2. the whole suite again with each kernel set forced (TRISTEREO_KERNELS);
#   3. the thread-pool tests under ThreadSanitizer;
#   4. the whole suite cross-built for aarch64 and armhf, run under qemu-user.
# Set TRISTEREO_SKIP_CROSS=1 to skip step 4 (e.g. on a machine without qemu).
set -eu
cd "$(dirname "$0")/.."
jobs=$(nproc)
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"
if [ -x scripts/kernel-sets-test.sh ]; then scripts/kernel-sets-test.sh build; fi
if [ -x scripts/tsan-test.sh ]; then scripts/tsan-test.sh; fi
if [ "${TRISTEREO_SKIP_CROSS:-0}" != "1" ] && [ -x scripts/cross-test.sh ]; then
  scripts/cross-test.sh all
fi
echo "tristereo: all tests passed"
