#!/bin/sh
# Installs every Debian package the build, tests, benchmarks and docs need.
# Usage: scripts/install-deps.sh [--cross]   (--cross adds ARM cross compilers, qemu
# and the arm64/armhf multiarch target libraries)
set -eu
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PKGS="build-essential cmake pkg-config libeigen3-dev libxsimd-dev libpng-dev zlib1g-dev
      libgpiod-dev googletest libgtest-dev libbenchmark-dev python3 python3-matplotlib"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  export DEBIAN_FRONTEND=noninteractive
  # A partial index failure (e.g. a foreign-architecture mirror) must not stop
  # the install when the packages we need are reachable.
  $SUDO apt-get update -q || echo "install-deps: apt-get update reported errors; trying the install anyway" >&2
  # shellcheck disable=SC2086
  $SUDO apt-get install -y -q --no-install-recommends $missing
fi
if [ "${1:-}" = "--cross" ]; then
  exec "$(dirname "$0")/install-cross-deps.sh"
fi
