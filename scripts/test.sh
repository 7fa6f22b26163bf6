#!/bin/sh
# The test command: on a fresh Debian 12 machine (as root, or with sudo),
# installs what it needs, builds and runs every test. Stages, in order:
#   install      scripts/install-deps.sh test (+ cross: the ARM compilers,
#                qemu-user and the target libraries)
#   lint         shellcheck on every script in scripts/, .ci/ and tests/
#   build        native Release build with warnings as errors (library,
#                program, tests, benchmarks)
#   ctest        the whole GoogleTest suite (kernel sets chosen at run time)
#   kernels-SET  the suite again with TRISTEREO_KERNELS=SET forced, for every
#                set this build compiled and this CPU runs but the default one
#                (the ctest stage's), less the tests that name every set
#                themselves and the command-line ones
#   python       the Python bindings' pytest suite (scripts/python-test.sh)
#   consumer-native  examples/consumer built against the INSTALLED package
#                (find_package and pkg-config; static, then shared) and run
#                (scripts/consumer-test.sh native)
#   tsan         the thread-pool, tritree and pipeline thread tests under
#                ThreadSanitizer (scripts/tsan-test.sh)
#   asan         the whole suite built with clang++ (warnings as errors) under
#                AddressSanitizer + UndefinedBehaviorSanitizer, every report
#                fatal, and run (scripts/sanitize-test.sh asan): the clang
#                build and the sanitized run in one job
#   fuzz         every libFuzzer harness of tests/fuzz (built in the asan
#                stage's tree): its corpus and regression inputs replayed,
#                then fuzzed 20 s (TRISTEREO_FUZZ_SECONDS) under ASan + UBSan
#                (scripts/fuzz-test.sh)
#   aarch64, armhf  the whole suite cross-built (warnings as errors) and run
#                under qemu-user (scripts/cross-test.sh)
#   consumer-aarch64  the consumer against the installed aarch64 build, run
#                under qemu (scripts/consumer-test.sh aarch64)
# Every stage prints what it ran and its counts; the command ends with one
# summary line per stage and exits non-zero if any stage failed.
#
# Environment:
#   TRISTEREO_SKIP_CROSS=1   leave out the ARM stages (e.g. no qemu wanted)
#   TRISTEREO_TEST_SUBSET=exactness   the fresh-root job's subset: build the
#                exactness tests only and run them natively and on each ARM
#                target (no kernel-set reruns, no TSan)
#   TRISTEREO_ALLOW_MISSING_DATA=1   tests that need ../shared/data skip
#                instead of failing when it is absent
#   TRISTEREO_CROSS_ARCHS="aarch64 armhf"   the ARM stages to build and run
#                (both are installed either way); the fresh-root job runs
#                aarch64 only, as this command on the host runs both in full
#   TRISTEREO_EXACT_CROSS_TARGETS, TRISTEREO_EXACT_CROSS_REGEX   with the
#                exactness subset, the ARM stages' targets and tests (default:
#                every exactness test; the fresh-root job builds and runs the
#                golden digests and the SIMD kernels only: the host's command
#                runs the whole suite under qemu)
#   TRISTEREO_TEST_WERROR=ON   the native build's warnings as errors; the
#                fresh-root job turns it off so that its exactness build
#                reuses the main job's objects (the same compiler already
#                built every target with -Werror in this command on the host)
set -u
cd "$(dirname "$0")/.." || exit 1
jobs=$(nproc)
subset="${TRISTEREO_TEST_SUBSET:-all}"
case "$subset" in
  all|exactness) ;;
  *) echo "test: TRISTEREO_TEST_SUBSET='$subset' (expected all or exactness)" >&2; exit 2 ;;
esac
cross=1
[ "${TRISTEREO_SKIP_CROSS:-0}" = "1" ] && cross=0
cross_archs="${TRISTEREO_CROSS_ARCHS:-aarch64 armhf}"
for a in $cross_archs; do
  case "$a" in
    aarch64|armhf) ;;
    *) echo "test: TRISTEREO_CROSS_ARCHS='$cross_archs' (expected aarch64 and/or armhf)" >&2; exit 2 ;;
  esac
done
werror="${TRISTEREO_TEST_WERROR:-ON}"
case "$werror" in
  ON|OFF) ;;
  *) echo "test: TRISTEREO_TEST_WERROR='$werror' (expected ON or OFF)" >&2; exit 2 ;;
esac

# The exactness tests: integer path == float reference, SIMD == scalar, golden
# digests (which the ARM builds must reproduce), identical for any thread count.
exact_targets="simd_kernels_test census_path_kernels_test match_reference_test pipeline_reference_test golden_digest_test tritree_reference_test interp_test pipeline_threads_test"
native_extra_targets="tristereo_cli _tristereo"  # the Python stage needs them
exact_regex='^(Sets/SimdKernels|Sets/CensusPathKernels|CensusScalar|PathStepScalar|LrMinScalar|MinOutsideScalar|KernelSets|MatchReference|RandomBitExact|SyntheticBitExact|All/MiddleburyBitExact|GoldenDigest|TritreeReference|Interpolate|PipelineThreads)'

# Left out of the kernel-set reruns: the tests that already run every kernel
# set by name (TRISTEREO_KERNELS only steers KernelChoice::kAuto), and those of
# the command line and scripts, which the suite's own run covers.
kernel_free_regex='^(Sets/|KernelSets/|GoldenDigest\.|PipelineThreads\.[A-Za-z]*AcrossThreadsAndKernels|Rectify\.VerifyCovers|cli\.|scripts\.|fuzz\.)'

# Left out under qemu: the two tests that compare whole data frames across
# 1-16 workers (90 s of the 900 s of test CPU under qemu-aarch64). qemu-user
# runs the guest's threads on the host's memory model, so they can only
# repeat the native and ThreadSanitizer stages' checks; every kernel of the
# target is still checked against scalar and the reference there. And the
# Middlebury bit-exact sweeps on teddy (93 s): cones has its size and D = 60,
# and the golden digests cover teddy's default frame.
cross_exclude_regex='^(PipelineThreads\.(EveryDataSceneIdenticalFromOneToSixteenWorkers|MiddleburyIdenticalAcrossThreadsAndKernels)|All/MiddleburyBitExact\.[A-Za-z]+/teddy .*)$'

summary=""
failed=0
passed=0
log_dir=$(mktemp -d)
trap 'rm -rf "$log_dir"' EXIT

skipped=0
# record NAME STATUS SECONDS DETAIL   (STATUS: passed, FAILED or skipped)
record() {
  summary="$summary
  $(printf '%-14s %-7s %5s s  %s' "$1" "$2" "$3" "$4")"
  case "$2" in
    passed) passed=$((passed + 1)) ;;
    skipped) skipped=$((skipped + 1)) ;;
    *) failed=$((failed + 1)) ;;
  esac
}

# run_logged LOG COMMAND...: runs COMMAND with its output shown live and kept
# in LOG; sets rc to its exit status (a plain pipe into tee would lose it).
run_logged() {
  _log=$1
  shift
  rm -f "$_log.rc"
  { "$@" 2>&1; echo $? >"$_log.rc"; } | tee "$_log"
  rc=$(cat "$_log.rc" 2>/dev/null || echo 1)
}

# ctest_counts LOG: ctest's closing line, or a note that it printed none.
ctest_counts() {
  line=$(grep -E '^[0-9]+% tests passed' "$1" | tail -n 1)
  echo "${line:-no ctest summary}"
}

# run_ctest NAME ctest-args...: one ctest stage, counted from its summary line.
run_ctest() {
  name=$1
  shift
  echo "==== test: $name: ctest $*"
  t0=$(date +%s)
  log="$log_dir/$name.log"
  run_logged "$log" ctest --output-on-failure --no-tests=error "$@"
  counts=$(ctest_counts "$log")
  status=passed
  [ "$rc" -eq 0 ] || status=FAILED
  record "$name" "$status" $(($(date +%s) - t0)) "$counts"
}

# run_stage NAME COMMAND...: a script stage, counted from its "NAME: passed"
# summary lines.
run_stage() {
  name=$1
  shift
  echo "==== test: $name: $*"
  t0=$(date +%s)
  run_logged "$log_dir/$name.log" "$@"
  ok=$(grep -c ': passed$' "$log_dir/$name.log")
  bad=$(grep -c ': FAILED' "$log_dir/$name.log")
  status=passed
  [ "$rc" -eq 0 ] || status=FAILED
  record "$name" "$status" $(($(date +%s) - t0)) "$ok passed, $bad failed"
}

finish() {
  echo
  echo "==== test: summary (subset: $subset)$summary"
  echo "stages: $passed passed, $failed failed, $skipped skipped"
  [ "$failed" -eq 0 ] || exit 1
  exit 0
}

# ---------------------------------------------------------------- install
t0=$(date +%s)
profile="test"
[ "$cross" -eq 1 ] && profile=cross
echo "==== test: install: scripts/install-deps.sh $profile"
if scripts/install-deps.sh "$profile"; then
  record install passed $(($(date +%s) - t0)) "profile $profile"
else
  record install FAILED $(($(date +%s) - t0)) "scripts/install-deps.sh $profile (its message above names what is missing)"
  finish
fi

# ---------------------------------------------------------------- shellcheck
t0=$(date +%s)
scripts_checked=$(find scripts .ci tests -type f \( -name '*.sh' -o -path '.ci/run' \) | sort)
n=$(echo "$scripts_checked" | wc -l)
echo "==== test: lint: shellcheck on $n scripts"
# shellcheck disable=SC2086
if shellcheck -x $scripts_checked; then
  record lint passed $(($(date +%s) - t0)) "$n scripts clean"
else
  record lint FAILED $(($(date +%s) - t0)) "$n scripts, findings above"
fi

# ---------------------------------------------------------------- native build
t0=$(date +%s)
echo "==== test: build: native Release, -DTRISTEREO_WERROR=$werror"
build_targets=""
if [ "$subset" = "exactness" ]; then
  build_targets="--target $exact_targets $native_extra_targets"
fi
# shellcheck disable=SC2086
if scripts/configure.sh build -S . -DCMAKE_BUILD_TYPE=Release -DTRISTEREO_WERROR="$werror" \
     -DTRISTEREO_BUILD_TESTS=ON -DTRISTEREO_BUILD_BENCH=ON -DTRISTEREO_BUILD_APPS=ON \
     -DTRISTEREO_BUILD_PYTHON=ON &&
   cmake --build build -j"$jobs" $build_targets; then
  record build passed $(($(date +%s) - t0)) "build/ ($subset)"
  if [ "$subset" = "exactness" ]; then
    run_ctest ctest --test-dir build -j"$jobs" -R "$exact_regex"
  else
    run_ctest ctest --test-dir build -j"$jobs"
    # ---------------------------------------------------------- kernel sets
    sets=$(build/tristereo info 2>/dev/null | sed -n 's/^kernel sets available on this CPU: *//p')
    # The ctest stage ran the suite with the set KernelChoice::kAuto picks.
    auto_set=$(build/tristereo info 2>/dev/null | sed -n 's/^kernel set used by default: *//p')
    if [ -z "$sets" ] || [ -z "$auto_set" ]; then
      record kernels FAILED 0 "'build/tristereo info' printed no 'kernel sets available on this CPU' or 'kernel set used by default' line"
    fi
    for set in $sets; do
      if [ "$set" = "$auto_set" ]; then
        record "kernels-$set" skipped 0 "the default set: the ctest stage ran the suite with it"
        continue
      fi
      TRISTEREO_KERNELS=$set
      export TRISTEREO_KERNELS
      run_ctest "kernels-$set" --test-dir build -j"$jobs" -E "$kernel_free_regex"
    done
    unset TRISTEREO_KERNELS
  fi
  # ---------------------------------------------------------- Python
  echo "==== test: python: scripts/python-test.sh build"
  t0=$(date +%s)
  run_logged "$log_dir/python.log" scripts/python-test.sh build
  status=passed
  [ "$rc" -eq 0 ] || status=FAILED
  record python "$status" $(($(date +%s) - t0)) "pytest: $(grep -E '[0-9]+ (passed|failed)' "$log_dir/python.log" | tail -n 1)"
  run_stage consumer-native scripts/consumer-test.sh native build
else
  record build FAILED $(($(date +%s) - t0)) "configure or build of build/ failed (see above)"
fi

# ---------------------------------------------------------------- ThreadSanitizer
if [ "$subset" = "all" ]; then
  t0=$(date +%s)
  echo "==== test: tsan: scripts/tsan-test.sh"
  run_logged "$log_dir/tsan.log" scripts/tsan-test.sh
  status=passed
  [ "$rc" -eq 0 ] || status=FAILED
  record tsan "$status" $(($(date +%s) - t0)) "$(ctest_counts "$log_dir/tsan.log")"

  # -------------------------------------------- clang + ASan + UBSan, fuzzing
  t0=$(date +%s)
  echo "==== test: asan: scripts/sanitize-test.sh asan"
  # The fuzz harnesses are built in the asan tree (one clang + sanitizer
  # build of the library instead of two) and run by the fuzz stage.
  run_logged "$log_dir/asan.log" env TRISTEREO_ASAN_FUZZ=1 scripts/sanitize-test.sh asan
  status=passed
  [ "$rc" -eq 0 ] || status=FAILED
  record asan "$status" $(($(date +%s) - t0)) "$(ctest_counts "$log_dir/asan.log")"
  run_stage fuzz env TRISTEREO_FUZZ_BUILD="$PWD/build-asan" TRISTEREO_FUZZ_PREBUILT=1 scripts/fuzz-test.sh
fi

# ---------------------------------------------------------------- ARM under qemu
if [ "$cross" -eq 1 ]; then
  for t in aarch64 armhf; do
    case " $cross_archs " in
      *" $t "*) ;;
      *) record "$t" skipped 0 "not in TRISTEREO_CROSS_ARCHS ($cross_archs): installed and checked, not built"
         continue ;;
    esac
    t0=$(date +%s)
    echo "==== test: $t: scripts/cross-test.sh $t"
    if [ "$subset" = "exactness" ]; then
      export TRISTEREO_CROSS_TARGETS="${TRISTEREO_EXACT_CROSS_TARGETS:-$exact_targets}"
      export TRISTEREO_CROSS_TEST_REGEX="${TRISTEREO_EXACT_CROSS_REGEX:-$exact_regex}"
    else
      export TRISTEREO_CROSS_TEST_EXCLUDE="$cross_exclude_regex"
    fi
    export TRISTEREO_CROSS_SKIP_DEPS=1  # the install stage did it, and checked it
    run_logged "$log_dir/$t.log" scripts/cross-test.sh "$t"
    status=passed
    [ "$rc" -eq 0 ] || status=FAILED
    detail=$(sed -n "s/^  $t: //p" "$log_dir/$t.log" | tail -n 1)
    record "$t" "$status" $(($(date +%s) - t0)) "${detail:-no cross-test summary}"
    if [ "$t" = aarch64 ] && [ "$status" = passed ]; then
      run_stage consumer-aarch64 scripts/consumer-test.sh aarch64 build-cross-aarch64
    fi
  done
else
  echo "==== test: ARM stages left out (TRISTEREO_SKIP_CROSS=1)"
  record aarch64 skipped 0 "TRISTEREO_SKIP_CROSS=1: not built, not run"
  record armhf skipped 0 "TRISTEREO_SKIP_CROSS=1: not built, not run"
fi

finish
