#!/usr/bin/env bash
# The fresh-machine promise, checked: builds a minimal Debian 12 root with
# debootstrap from Debian's package registry, clones the commit under test into
# it with ../shared beside it, and runs inside it, as root, the README's two
# commands:
#   1. scripts/demo.sh (the main job); its outputs must exist and be non-empty;
#   2. TRISTEREO_TEST_SUBSET=exactness scripts/test.sh: every install step
#      (native and the ARM cross toolchains, qemu-user, target libraries),
#      the script lint, the native build and the exactness tests, and the
#      aarch64 build with its exactness tests under qemu (armhf installed and
#      checked; the host's test command builds and runs it in full).
# Nothing installed on this machine can help: the root starts with only what
# debootstrap's minbase variant, git and ca-certificates bring.
#
# Usage: scripts/fresh-root-test.sh [COMMIT]     (default: HEAD; run as root)
# Environment:
#   TRISTEREO_FRESH_ROOT_WORK   where the root is made (default
#                               /var/tmp/tristereo-fresh-root); removed at the end
#   TRISTEREO_FRESH_ROOT_CACHE  where the debootstrap tarball is cached between
#                               runs (default /var/cache/tristereo); only the bare
#                               minbase root is cached, never an install step
#   TRISTEREO_FRESH_ROOT_MAX_AGE_DAYS  rebuild the cached tarball when older
#                               (default 7)
#   TRISTEREO_FRESH_ROOT_KEEP=1 keep the root afterwards (to look inside)
#   TRISTEREO_DEBIAN_MIRROR     default: the host's Debian mirror
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
commit="$(git -C "${repo}" rev-parse "${1:-HEAD}")"
work="${TRISTEREO_FRESH_ROOT_WORK:-/var/tmp/tristereo-fresh-root}"
cache="${TRISTEREO_FRESH_ROOT_CACHE:-/var/cache/tristereo}"
max_age="${TRISTEREO_FRESH_ROOT_MAX_AGE_DAYS:-7}"
suite=bookworm
root="${work}/root"
say() { echo "==== fresh-root: $*"; }
die() { echo "fresh-root: FAILED: $*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot and bind mounts)"
shared="$(cd "${repo}/.." && pwd)/shared"
[ -d "${shared}/data" ] || die "no ${shared}/data: the job runs with ../shared beside the clone"

# The host's Debian mirror (deb822 or one-line sources), else deb.debian.org.
host_mirror() {
  local uri=""
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    uri="$(sed -n 's/^URIs: *\([^ ]*\/debian\)\/\{0,1\}$/\1/p' /etc/apt/sources.list.d/debian.sources | head -n 1)"
  fi
  if [ -z "${uri}" ] && [ -f /etc/apt/sources.list ]; then
    uri="$(sed -n 's/^deb \(\[[^]]*\] \)\{0,1\}\([^ ]*\/debian\)\/\{0,1\} .*/\2/p' /etc/apt/sources.list | head -n 1)"
  fi
  echo "${uri:-http://deb.debian.org/debian}"
}
mirror="${TRISTEREO_DEBIAN_MIRROR:-$(host_mirror)}"
security="${mirror%/debian}/debian-security"

t_start=$(date +%s)
timings=""
lap() {  # lap NAME T0: one line of the closing table
  timings="${timings}
  $(printf '%-28s %5s s' "$1" $(($(date +%s) - $2)))"
}

cleanup() {
  local rc=$?
  if [ -d "${root}" ]; then
    # Innermost first; a lazy unmount if something still holds a mount.
    for m in "${root}/work/shared" "${root}/dev/pts" "${root}/dev" "${root}/sys" "${root}/proc"; do
      if mountpoint -q "${m}"; then umount "${m}" 2>/dev/null || umount -l "${m}"; fi
    done
    if [ "${TRISTEREO_FRESH_ROOT_KEEP:-0}" = "1" ]; then
      say "root kept at ${root}"
    else
      rm -rf "${root}"
    fi
  fi
  exit "${rc}"
}
trap cleanup EXIT

# ---------------------------------------------------------------- base root (cached)
t0=$(date +%s)
if ! command -v debootstrap >/dev/null 2>&1; then
  say "installing debootstrap on the host"
  DEBIAN_FRONTEND=noninteractive apt-get -q -o DPkg::Lock::Timeout=600 install -y --no-install-recommends debootstrap ||
    { apt-get -q update && DEBIAN_FRONTEND=noninteractive apt-get -q install -y --no-install-recommends debootstrap; }
fi
mkdir -p "${cache}" "${work}"
recipe="debootstrap --variant=minbase --include=git,ca-certificates ${suite} ${mirror}"
tarball="${cache}/debian12-minbase.tar.gz"
if [ -f "${tarball}" ] && [ "$(cat "${tarball}.recipe" 2>/dev/null)" = "${recipe}" ] &&
   [ -z "$(find "${tarball}" -mtime +"${max_age}")" ]; then
  say "base root: cached ${tarball} (made $(date -r "${tarball}" '+%F %R'); ${recipe})"
else
  say "base root: ${recipe}"
  rm -rf "${work}/base"
  debootstrap --variant=minbase --include=git,ca-certificates "${suite}" "${work}/base" "${mirror}" \
    >"${work}/debootstrap.log" 2>&1 || { tail -n 30 "${work}/debootstrap.log" >&2; die "debootstrap failed"; }
  tar -C "${work}/base" -czf "${tarball}.tmp" .
  mv "${tarball}.tmp" "${tarball}"
  echo "${recipe}" >"${tarball}.recipe"
  rm -rf "${work}/base"
fi
lap "base root" "${t0}"

# ---------------------------------------------------------------- a fresh copy of it
t0=$(date +%s)
rm -rf "${root}"
mkdir -p "${root}"
tar -C "${root}" -xzf "${tarball}"
# The registry a user's Debian 12 machine uses: the release, its updates and security.
rm -f "${root}/etc/apt/sources.list"
cat >"${root}/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: ${mirror}
Suites: ${suite} ${suite}-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: ${security}
Suites: ${suite}-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
cp /etc/resolv.conf "${root}/etc/resolv.conf"
mount -t proc proc "${root}/proc"
mount -t sysfs sys "${root}/sys"
mount --bind /dev "${root}/dev"
mount --bind /dev/pts "${root}/dev/pts"
mkdir -p "${root}/work/shared"
mount --bind -o ro "${shared}" "${root}/work/shared"
# Only what is committed: the clone of the commit under test.
git clone --quiet --no-local "${repo}" "${root}/work/tristereo"
git -C "${root}/work/tristereo" checkout --quiet --detach "${commit}"
say "root ${root}: Debian ${suite} minbase + git + ca-certificates; clone of ${commit} at /work/tristereo, ../shared bind-mounted read-only"
# shellcheck disable=SC2016  # expanded by the root's shell
chroot "${root}" /bin/sh -c 'for c in g++ cmake make pkg-config qemu-aarch64 aarch64-linux-gnu-g++; do command -v $c >/dev/null && echo "  (unexpected: $c already present)"; done; true'
lap "fresh copy + clone" "${t0}"

in_root() {  # in_root COMMAND: as root in the clone, with a clean environment
  chroot "${root}" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 CI="${CI:-}" /bin/sh -c "cd /work/tristereo && $1"
}

# ---------------------------------------------------------------- 1. the main job
t0=$(date +%s)
say "main job: scripts/demo.sh (inside the root)"
in_root "scripts/demo.sh" || die "the main-job command scripts/demo.sh failed inside the fresh root"
outputs="left.png right.png gt_disp.pfm sparse_disp.pfm sparse_disp_color.png sparse_stats.json
         dense_disp.pfm dense_disp_color.png dense_stats.json mesh.ply
         tsukuba_disp.pfm tsukuba_disp_color.png tsukuba_mesh.ply tsukuba_samples.csv tsukuba_stats.json"
n=0
for f in ${outputs}; do
  p="${root}/work/tristereo/demo-out/${f}"
  [ -s "${p}" ] || die "the main job did not write demo-out/${f} (missing or empty)"
  n=$((n + 1))
done
say "main job: ${n} outputs in demo-out/, each non-empty"
lap "main job (demo.sh)" "${t0}"

# ---------------------------------------------------------------- 2. the test command
t0=$(date +%s)
# aarch64 only: the host's test command builds and runs both ARM targets in
# full, and armhf's toolchain and libraries are still installed and checked
# here. Warnings are not errors here: the same compiler built every target
# with -Werror on the host, and this way the exactness build reuses the main
# job's objects instead of compiling the library a second time.
# Under qemu only the golden digests and the SIMD kernels: enough to show the
# toolchain, the target libraries and qemu work from this root's installs; the
# host's command runs every test under qemu.
fresh_env="TRISTEREO_TEST_SUBSET=exactness TRISTEREO_CROSS_ARCHS=aarch64 TRISTEREO_TEST_WERROR=OFF"
fresh_env="${fresh_env} TRISTEREO_EXACT_CROSS_TARGETS='golden_digest_test simd_kernels_test'"
fresh_env="${fresh_env} TRISTEREO_EXACT_CROSS_REGEX='^(GoldenDigest|Sets/SimdKernels)'"
say "test command: ${fresh_env} scripts/test.sh (inside the root)"
rc=0
in_root "${fresh_env} scripts/test.sh" || rc=$?
lap "test command (exactness)" "${t0}"

echo
say "summary for ${commit}${timings}
  $(printf '%-28s %5s s' total $(($(date +%s) - t_start)))"
[ "${rc}" -eq 0 ] || die "the test command failed inside the fresh root (its summary above names the stage)"
echo "fresh-root: 2 passed, 0 failed"
