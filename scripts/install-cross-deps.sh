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
# Usage: scripts/install-cross-deps.sh [aarch64|armhf|all]... [--refresh]
# Every target named is installed ("all" = aarch64 armhf; no target = all).
# Idempotent: a target whose packages are already unpacked and complete is
# skipped unless --refresh is given. Ends by checking every compiler, qemu
# program, target library and header it promised (exit 1 naming what is
# missing). Runs as root, or through sudo.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
deps_name="install-cross-deps"

targets=""
refresh=0
add_target() {
  case " $targets " in *" $1 "*) ;; *) targets="$targets $1" ;; esac
}
for arg in "$@"; do
  case "$arg" in
    aarch64|armhf) add_target "$arg" ;;
    all) add_target aarch64; add_target armhf ;;
    --refresh) refresh=1 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "install-cross-deps: unknown argument '$arg' (expected aarch64, armhf, all or --refresh)" >&2; exit 2 ;;
  esac
done
[ -n "$targets" ] || targets=" aarch64 armhf"
targets=${targets# }

# shellcheck source=scripts/deps-lib.sh
. "$here/deps-lib.sh"
DEPS_ROOT="${TRISTEREO_CROSS_DEPS_ROOT:-/opt/tristereo/cross-deps}"
# Target packages: the compiled libraries the build links, and their runtime
# libraries (dependencies beyond libc/libstdc++ spelled out by hand, since the
# rest of their dependency closure is the toolchain's own libc).
TARGET_PKGS="libpng-dev libpng16-16 zlib1g-dev zlib1g libgpiod-dev libgpiod2 libbenchmark-dev libbenchmark1debian"

triple_of() {
  case "$1" in
    aarch64) echo aarch64-linux-gnu ;;
    armhf) echo arm-linux-gnueabihf ;;
  esac
}
qemu_of() {
  case "$1" in
    aarch64) echo qemu-aarch64 ;;
    armhf) echo qemu-arm ;;
  esac
}

# The files the build and the tests under qemu need from one target's unpacked
# packages; prints the missing ones.
target_missing_files() {
  _dest="$DEPS_ROOT/$(triple_of "$1")"
  _lib="$_dest/usr/lib/$(triple_of "$1")"
  for _f in usr/include/png.h usr/include/zlib.h usr/include/gpiod.h usr/include/benchmark/benchmark.h; do
    [ -e "$_dest/$_f" ] || echo "$_dest/$_f"
  done
  for _f in libpng16.so libz.so libgpiod.so libbenchmark.so; do
    [ -e "$_lib/$_f" ] || echo "$_lib/$_f"
  done
}

added_archs=""
restore_archs() {
  # Nothing of the target architectures is installed through dpkg, so leave
  # the host's dpkg configuration as it was: a foreign architecture would make
  # every later `apt-get update` depend on that architecture's indexes too.
  for _arch in $added_archs; do
    $deps_sudo dpkg --remove-architecture "$_arch"
  done
  added_archs=""
}
trap restore_archs EXIT

# ---------------------------------------------------------------- host side
host_pkgs="g++ make cmake pkg-config libeigen3-dev libxsimd-dev googletest qemu-user"
for t in $targets; do
  host_pkgs="$host_pkgs g++-$(triple_of "$t")"
done
# shellcheck disable=SC2086
deps_install $host_pkgs

# ---------------------------------------------------------------- target side
for t in $targets; do
  case "$t" in
    aarch64) arch=arm64 ;;
    armhf) arch=armhf ;;
  esac
  triple=$(triple_of "$t")
  dest="$DEPS_ROOT/$triple"
  stamp="$dest/.tristereo-packages"
  if [ "$refresh" -eq 0 ] && [ -f "$stamp" ] && [ "$(head -n 1 "$stamp")" = "$TARGET_PKGS" ]; then
    if [ -z "$(target_missing_files "$t")" ]; then
      echo "install-cross-deps: $triple: target libraries already in $dest"
      continue
    fi
    echo "install-cross-deps: $triple: $dest is incomplete; unpacking again"
  fi
  if ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    $deps_sudo dpkg --add-architecture "$arch"
    added_archs="$added_archs $arch"
    deps_updated=0  # the new architecture's indexes are not there yet
  fi
  deps_apt_update
  work=$(mktemp -d)
  # apt's download sandbox user (_apt) must be able to write there.
  chmod 0777 "$work"
  pkgs=""
  for p in $TARGET_PKGS; do pkgs="$pkgs $p:$arch"; done
  # shellcheck disable=SC2086
  if ! (cd "$work" && apt-get -q download $pkgs); then
    echo "install-cross-deps: $triple: downloading the target packages ($pkgs) failed" >&2
    rm -rf "$work"
    exit 1
  fi
  $deps_sudo rm -rf "$dest"
  $deps_sudo mkdir -p "$dest"
  for deb in "$work"/*.deb; do
    $deps_sudo dpkg-deb -x "$deb" "$dest"
  done
  # Debian's dev symlinks may be absolute (usr/lib/<triple>/libz.so ->
  # /lib/<triple>/libz.so.1.2.13); re-point them inside $dest, relatively.
  find "$dest" -type l -lname '/*' | while read -r link; do
    $deps_sudo ln -sfnr "$dest$(readlink "$link")" "$link"
  done
  { echo "$TARGET_PKGS"; (cd "$work" && find . -name '*.deb' | sed 's|^\./||' | sort); } | $deps_sudo tee "$stamp" >/dev/null
  rm -rf "$work"
  echo "install-cross-deps: $triple: unpacked $(($(wc -l <"$stamp") - 1)) packages into $dest"
done
restore_archs

# ---------------------------------------------------------------- what was promised
# shellcheck disable=SC2086
deps_need_pkg $host_pkgs
deps_need_cmd cmake "build system"
deps_need_file /usr/src/googletest/CMakeLists.txt "GoogleTest sources"
deps_need_file /usr/include/xsimd/xsimd.hpp "xsimd headers"
deps_need_file /usr/share/eigen3/cmake/Eigen3Config.cmake "Eigen's CMake package"
for t in $targets; do
  triple=$(triple_of "$t")
  deps_need_cmd "$triple-g++" "$t C++ cross compiler"
  deps_need_cmd "$triple-gcc" "$t C cross compiler"
  deps_need_cmd "$(qemu_of "$t")" "runs the $t tests (qemu-user)"
  deps_need_file "/usr/$triple/lib/libstdc++.so.6" "$t C++ runtime for qemu -L"
  deps_checked=$((deps_checked + 8))  # the files target_missing_files looks for
  for f in $(target_missing_files "$t"); do
    deps_problem "file $f ($t target library or header)"
  done
done
deps_verify "targets: $targets"
