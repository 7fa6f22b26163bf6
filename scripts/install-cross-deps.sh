#!/bin/sh
# Installs what the ARM cross builds need on a Debian 12 (bookworm) host:
#   - host side: the cross compilers, qemu-user, CMake, and the header-only
#     libraries (Eigen, xsimd) and GoogleTest sources, which serve every target;
#   - target side: Debian's own arm64/armhf builds of libpng, zlib, libgpiod and
#     Google Benchmark, unpacked into /opt/tristereo/cross-deps/<triple>/ (the
#     default TRISTEREO_CROSS_DEPS of toolchains/linux-gnu-common.cmake).
#
# Why unpack instead of `apt-get install libpng-dev:arm64`: multiarch packages
# are "Multi-Arch: same", so dpkg insists that libpng16-16:arm64 has exactly the
# version of the host's libpng16-16:amd64 (likewise libssl3, linux-libc-dev,
# ... that libc6-dev:arm64 drags in). Whenever the host was installed from a
# different snapshot than the target indexes (or one index fails to download,
# as bookworm-security's armhf index does on our mirror), apt refuses with
# "unmet dependencies". Unpacking the .debs gives the same files without tying
# the host's packages to the target's. libc and libstdc++ come from the cross
# toolchain packages (/usr/<triple>).
#
# Usage: scripts/install-cross-deps.sh [aarch64|armhf|all] [--refresh]
# Idempotent: a target whose packages are already unpacked is skipped unless
# --refresh is given. Runs as root, or through sudo.
set -eu

targets="all"
refresh=0
for arg in "$@"; do
  case "$arg" in
    aarch64|armhf|all) targets="$arg" ;;
    --refresh) refresh=1 ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) echo "install-cross-deps: unknown argument '$arg' (expected aarch64, armhf, all or --refresh)" >&2; exit 2 ;;
  esac
done
[ "$targets" = "all" ] && targets="aarch64 armhf"

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
APT="$SUDO env DEBIAN_FRONTEND=noninteractive apt-get -q -o DPkg::Lock::Timeout=600"
DEPS_ROOT="${TRISTEREO_CROSS_DEPS_ROOT:-/opt/tristereo/cross-deps}"
# Target packages: the compiled libraries the build links, and their runtime
# libraries (dependencies beyond libc/libstdc++ spelled out by hand, since the
# rest of their dependency closure is the toolchain's own libc).
TARGET_PKGS="libpng-dev libpng16-16 zlib1g-dev zlib1g libgpiod-dev libgpiod2 libbenchmark-dev libbenchmark1debian"

updated=0
added_archs=""
apt_update() {
  [ "$updated" -eq 1 ] && return 0
  updated=1
  # A partial failure (one index of one suite) is reported and tolerated: the
  # downloads below fail loudly if what they need is really missing.
  if ! $APT update; then
    echo "install-cross-deps: warning: apt-get update reported errors (see above); continuing with the indexes that did download" >&2
  fi
}

host_missing() {
  missing=""
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
  done
  echo "$missing"
}

# ---------------------------------------------------------------- host side
host_pkgs="cmake make pkg-config libeigen3-dev libxsimd-dev googletest qemu-user"
for t in $targets; do
  case "$t" in
    aarch64) host_pkgs="$host_pkgs g++-aarch64-linux-gnu" ;;
    armhf) host_pkgs="$host_pkgs g++-arm-linux-gnueabihf" ;;
  esac
done
# shellcheck disable=SC2086
missing=$(host_missing $host_pkgs)
if [ -n "$missing" ]; then
  apt_update
  # shellcheck disable=SC2086
  $APT install -y --no-install-recommends $missing
fi

# ---------------------------------------------------------------- target side
for t in $targets; do
  case "$t" in
    aarch64) arch=arm64; triple=aarch64-linux-gnu ;;
    armhf) arch=armhf; triple=arm-linux-gnueabihf ;;
  esac
  dest="$DEPS_ROOT/$triple"
  stamp="$dest/.tristereo-packages"
  if [ "$refresh" -eq 0 ] && [ -f "$stamp" ] && [ "$(head -n 1 "$stamp")" = "$TARGET_PKGS" ]; then
    echo "install-cross-deps: $triple: target libraries already in $dest"
    continue
  fi
  if ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    $SUDO dpkg --add-architecture "$arch"
    added_archs="$added_archs $arch"
    updated=0  # the new architecture's indexes are not there yet
  fi
  apt_update
  work=$(mktemp -d)
  # apt's download sandbox user (_apt) must be able to write there.
  chmod 0777 "$work"
  pkgs=""
  for p in $TARGET_PKGS; do pkgs="$pkgs $p:$arch"; done
  # shellcheck disable=SC2086
  (cd "$work" && apt-get -q download $pkgs)
  $SUDO rm -rf "$dest"
  $SUDO mkdir -p "$dest"
  for deb in "$work"/*.deb; do
    $SUDO dpkg-deb -x "$deb" "$dest"
  done
  # Debian's dev symlinks may be absolute (usr/lib/<triple>/libz.so ->
  # /lib/<triple>/libz.so.1.2.13); re-point them inside $dest, relatively.
  find "$dest" -type l -lname '/*' | while read -r link; do
    $SUDO ln -sfnr "$dest$(readlink "$link")" "$link"
  done
  { echo "$TARGET_PKGS"; (cd "$work" && find . -name '*.deb' | sed 's|^\./||' | sort); } | $SUDO tee "$stamp" >/dev/null
  rm -rf "$work"
  echo "install-cross-deps: $triple: unpacked $(($(wc -l <"$stamp") - 1)) packages into $dest"
done

# Nothing of the target architectures is installed through dpkg, so leave the
# host's dpkg configuration as it was: a foreign architecture would make every
# later `apt-get update` depend on that architecture's indexes too.
for arch in $added_archs; do
  $SUDO dpkg --remove-architecture "$arch"
done
