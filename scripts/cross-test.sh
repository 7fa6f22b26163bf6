#!/bin/sh
# Cross-builds tristereo for ARM and runs the whole test suite under qemu-user.
#
# Usage: scripts/cross-test.sh [aarch64|armhf|all]     (default: all)
# Environment:
#   TRISTEREO_CROSS_BUILD_ROOT  where build-cross-<target>/ go (default: the repo)
#   TRISTEREO_CROSS_JOBS        parallel compile and test jobs (default: 2)
#   TRISTEREO_CROSS_BENCH       ON to build bench/ for the target too (default OFF:
#                               benchmarks mean nothing under an emulator)
#   TRISTEREO_CROSS_REQUIRE_SIMD  ON (default) fails the configure step if the
#                               NEON kernels cannot be built, instead of testing
#                               a scalar-only build
#   TRISTEREO_CROSS_SKIP_DEPS   1 to skip scripts/install-cross-deps.sh (the
#                               test command installs and checks them itself)
#   TRISTEREO_CROSS_TARGETS     build only these targets (default: everything)
#   TRISTEREO_CROSS_TEST_REGEX  run only the tests matching it (ctest -R)
#   TRISTEREO_CROSS_TEST_EXCLUDE  leave out the tests matching it (ctest -E)
#   TRISTEREO_CROSS_WERROR      ON (default) makes every warning an error
#
# Build trees are configured through scripts/configure.sh, which removes a tree
# that an earlier failed configure left stale instead of building on it.
# Each target uses its CMake preset (aarch64-release, armhf-release), so the
# toolchain file and its qemu emulator setting make plain ctest run the ARM
# binaries. Exit status: 0 only if every target configured, built and passed.
set -u

repo=$(cd "$(dirname "$0")/.." && pwd)
targets="${1:-all}"
case "$targets" in
  all) targets="aarch64 armhf" ;;
  aarch64|armhf) ;;
  *) echo "cross-test: unknown target '$targets' (expected aarch64, armhf or all)" >&2; exit 2 ;;
esac
build_root="${TRISTEREO_CROSS_BUILD_ROOT:-$repo}"
jobs="${TRISTEREO_CROSS_JOBS:-2}"
bench="${TRISTEREO_CROSS_BENCH:-OFF}"
require_simd="${TRISTEREO_CROSS_REQUIRE_SIMD:-ON}"
werror="${TRISTEREO_CROSS_WERROR:-ON}"
build_targets="${TRISTEREO_CROSS_TARGETS:-}"
test_regex="${TRISTEREO_CROSS_TEST_REGEX:-}"
test_exclude="${TRISTEREO_CROSS_TEST_EXCLUDE:-}"
cd "$repo" || exit 1  # cmake --preset reads CMakePresets.json from here

if [ "${TRISTEREO_CROSS_SKIP_DEPS:-0}" != "1" ]; then
  # shellcheck disable=SC2086
  sh "$repo/scripts/install-cross-deps.sh" $targets || { echo "cross-test: installing cross dependencies failed" >&2; exit 1; }
fi

summary=""
failed=0
now() { date +%s; }

for t in $targets; do
  dir="$build_root/build-cross-$t"
  log_prefix="cross-test[$t]"
  status="passed"
  t0=$(now)
  echo "==== $log_prefix: configure ($dir)"
  if ! sh "$repo/scripts/configure.sh" "$dir" --preset "$t-release" \
       -DTRISTEREO_BUILD_BENCH="$bench" -DTRISTEREO_REQUIRE_SIMD="$require_simd" \
       -DTRISTEREO_WERROR="$werror"; then
    status="CONFIGURE FAILED"
  fi
  t1=$(now)
  if [ "$status" = "passed" ]; then
    echo "==== $log_prefix: build${build_targets:+ (targets: $build_targets)}"
    # shellcheck disable=SC2086
    cmake --build "$dir" -j "$jobs" ${build_targets:+--target $build_targets} || status="BUILD FAILED"
  fi
  t2=$(now)
  tests="-"
  if [ "$status" = "passed" ]; then
    echo "==== $log_prefix: ctest under qemu${test_regex:+ (-R $test_regex)}${test_exclude:+ (-E $test_exclude)}"
    ctest_log="$dir/cross-ctest.log"
    ctest --test-dir "$dir" --output-on-failure --no-tests=error -j "$jobs" \
      ${test_regex:+-R "$test_regex"} ${test_exclude:+-E "$test_exclude"} 2>&1 | tee "$ctest_log"
    # tee hides ctest's exit status from a POSIX shell; its summary line tells.
    tests=$(grep -E '^[0-9]+% tests passed' "$ctest_log" | tail -n 1)
    case "$tests" in
      "100% tests passed"*) ;;
      *) status="TESTS FAILED" ;;
    esac
    [ -n "$tests" ] || tests="no ctest summary"
  fi
  t3=$(now)
  [ "$status" = "passed" ] || failed=1
  summary="$summary
  $t: $status | configure $((t1 - t0)) s, build $((t2 - t1)) s, tests $((t3 - t2)) s | $tests"
done

echo
echo "==== cross-test summary (jobs=$jobs, bench=$bench, werror=$werror)$summary"
exit "$failed"
