#!/bin/sh
# scripts/configure.sh never builds on a tree that a failed configure left
# behind (the aarch64 job once rebuilt at -O0 that way), and keeps a good one.
# Usage: configure_stale_test.sh REPO WORKDIR
set -u
repo=$1
work=$2
src="$repo/tests/scripts/tiny-project"
fail() {
  echo "FAIL: $1"
  for f in "$work"/*.log; do echo "--- $f"; cat "$f"; done
  exit 1
}
rm -rf "$work"
mkdir -p "$work"

# 1. A configure that stops at the compiler check, as when the cross compiler
#    is not installed yet: it must fail, and it leaves a cache behind.
if sh "$repo/scripts/configure.sh" "$work/b" -S "$src" -DCMAKE_BUILD_TYPE=Release \
     -DCMAKE_CXX_COMPILER=no-such-g++ >"$work/1.log" 2>&1; then
  fail "configure with a missing compiler succeeded"
fi
[ -f "$work/b/CMakeCache.txt" ] || fail "setup: the failed configure left no CMakeCache.txt"

# 2. Configuring again (the compiler now "installed": the default one) must
#    start from a clean tree and end with optimised Release flags.
sh "$repo/scripts/configure.sh" "$work/b" -S "$src" -DCMAKE_BUILD_TYPE=Release >"$work/2.log" 2>&1 ||
  fail "second configure failed"
grep -q "removing the stale build tree" "$work/2.log" || fail "the stale tree was not removed"
grep -q '^CMAKE_CXX_FLAGS_RELEASE:STRING=.*-O' "$work/b/CMakeCache.txt" || fail "Release flags without -O"
[ -f "$work/b/.tristereo-configured" ] || fail "no stamp after a good configure"

# 3. A good tree is kept.
sh "$repo/scripts/configure.sh" "$work/b" -S "$src" -DCMAKE_BUILD_TYPE=Release >"$work/3.log" 2>&1 ||
  fail "third configure failed"
if grep -q "removing" "$work/3.log"; then fail "a good tree was removed"; fi

rm -rf "$work"
echo "configure.sh: stale tree removed, release flags checked, good tree kept"
