#!/bin/sh
# Configures a CMake build tree, and never silently reuses a stale one.
#
# Usage: scripts/configure.sh BUILD_DIR [cmake arguments...]
#        (run from the repository root, or pass -S yourself)
#
# Why: a configure that failed (say, the cross compiler was not installed yet)
# leaves a CMakeCache.txt behind with values cached from the failed attempt
# (an empty CMAKE_CXX_FLAGS_RELEASE among them). Configuring again on top of it
# "succeeds" and builds at -O0 without a word. So:
#   - a tree whose last configure did not finish (no stamp) is removed first;
#   - so is a tree whose cached compiler is gone;
#   - after configuring, the flags of the build type are checked (an optimised
#     type must carry -O), and the stamp is written only then.
set -eu
if [ $# -lt 1 ]; then
  echo "usage: scripts/configure.sh BUILD_DIR [cmake arguments...]" >&2
  exit 2
fi
dir=$1
shift
stamp="$dir/.tristereo-configured"
cache="$dir/CMakeCache.txt"

cache_value() {  # cache_value NAME: the cached value of NAME (empty when absent)
  sed -n "s/^$1:[A-Z]*=//p" "$cache" | head -n 1
}

if [ -f "$cache" ]; then
  reason=""
  if [ ! -f "$stamp" ]; then
    reason="its last configure did not finish"
  else
    cxx=$(cache_value CMAKE_CXX_COMPILER)
    if [ -n "$cxx" ] && [ ! -x "$cxx" ] && ! command -v "$cxx" >/dev/null 2>&1; then
      reason="its compiler $cxx is gone"
    fi
  fi
  if [ -n "$reason" ]; then
    echo "configure: removing the stale build tree $dir ($reason)"
    rm -rf "$dir"
  fi
fi
rm -f "$stamp"
cmake -B "$dir" "$@"

type=$(cache_value CMAKE_BUILD_TYPE)
case "$type" in
  Release|RelWithDebInfo|MinSizeRel)
    utype=$(echo "$type" | tr '[:lower:]' '[:upper:]')
    flags=$(cache_value "CMAKE_CXX_FLAGS_$utype")
    case "$flags" in
      *-O*) ;;
      *)
        echo "configure: $dir: CMAKE_CXX_FLAGS_$utype is '$flags' (no -O): the cache is stale; remove $dir and configure again" >&2
        exit 1 ;;
    esac ;;
esac
echo "$*" >"$stamp"
