#!/usr/bin/env bash
# The whole GoogleTest suite built with another compiler or under sanitizers
# (the test command's asan stage: clang and the sanitizers in one build).
#
#   scripts/sanitize-test.sh clang [BUILD_DIR]   clang++ Release, warnings as
#                                                errors, the whole suite
#   scripts/sanitize-test.sh asan  [BUILD_DIR]   clang++ with AddressSanitizer +
#                                                UndefinedBehaviorSanitizer
#                                                (TRISTEREO_SANITIZE: every
#                                                report aborts), the whole suite
#                                                less the exactness checks on
#                                                whole data frames (below)
#
# TRISTEREO_ASAN_FUZZ=1 (asan only) also builds the libFuzzer harnesses in the
# same tree (TRISTEREO_FUZZ: coverage feedback in every object), so that the
# fuzz stage runs them without compiling the library a third time
# (scripts/fuzz-test.sh with TRISTEREO_FUZZ_PREBUILT=1); the test command does.
#
# Why clang at all: GCC and clang differ where C++ leaves things unspecified
# (the order in which a call's arguments are evaluated hid a clock-test bug
# for as long as only GCC built the suite), and clang's UBSan checks more
# (float-to-int overflow among them) than GCC's. ctest -j uses every core.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode="${1:-}"
cxx="$(command -v clang++-14 || command -v clang++ || true)"
if [[ -z "${cxx}" ]]; then
  echo "sanitize-test: no clang++ found: run scripts/install-deps.sh test" >&2
  exit 1
fi
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
case "${mode}" in
  clang)
    build="${2:-${repo}/build-clang}"
    flags=(-DCMAKE_BUILD_TYPE=Release -DTRISTEREO_BUILD_BENCH=ON) ;;
  asan)
    build="${2:-${repo}/build-asan}"
    # -O1: sanitizer reports keep their frames; benchmarks are not run here.
    flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g"
           -DTRISTEREO_SANITIZE=ON -DTRISTEREO_BUILD_BENCH=OFF
           "-DTRISTEREO_FUZZ=$([[ "${TRISTEREO_ASAN_FUZZ:-0}" == 1 ]] && echo ON || echo OFF)")
    export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}"
    export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
    symbolizer="$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)"
    [[ -n "${symbolizer}" ]] && export ASAN_SYMBOLIZER_PATH="${symbolizer}" ;;
  *)
    echo "usage: scripts/sanitize-test.sh clang|asan [BUILD_DIR]" >&2
    exit 2 ;;
esac

"${repo}/scripts/configure.sh" "${build}" -S "${repo}" -DCMAKE_CXX_COMPILER="${cxx}" "${launcher[@]}" \
  -DTRISTEREO_WERROR=ON -DTRISTEREO_BUILD_TESTS=ON -DTRISTEREO_BUILD_APPS=ON \
  -DTRISTEREO_BUILD_PYTHON=OFF "${flags[@]}"
cmake --build "${build}" -j"$(nproc)"
cd "${build}"
excluded=()
if [[ "${mode}" == asan ]]; then
  # The two tests that call mlockall (real-time mode) skip themselves under a
  # sanitizer, which would lock its shadow memory; they are left out here so
  # the report lists no skipped test (they run in the native and kernel-set
  # stages, and in `sanitize-test.sh clang`).
  # Also left out: the exactness checks on whole frames of ../shared/data
  # (369 s of the 662 s of CPU the suite took here under ASan with the fuzz
  # harnesses' coverage feedback) for code the smaller random and special-size
  # tests run too, and the soak script's short run (46 s: 60 VGA frames); they
  # run natively, per kernel set and (but the soak) under the ARM emulators.
  # The Middlebury bit-exact sweeps run on tsukuba and venus only: teddy and
  # cones go through the same code at larger sizes (17 s of native CPU, about
  # ten times that under ASan).
  excluded=(-E '^(ThreadPoolRealtime\.AppliesToEveryWorkerOrChangesNothing|Realtime\.EnableRealtimeSucceedsOrExplains|GoldenDigest\.(Middlebury|OtherSetsDefaults)|TritreeReference\.MiddleburyAtDefaultAndOtherPsnr|PipelineThreads\.(MiddleburyIdenticalAcrossThreadsAndKernels|EveryDataSceneIdenticalFromOneToSixteenWorkers)|All/MiddleburyBitExact\.[A-Za-z]+/(teddy|cones) .*|scripts\.soak_short)$')
fi
ctest --output-on-failure --no-tests=error -j"$(nproc)" "${excluded[@]}"
