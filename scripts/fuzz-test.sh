#!/usr/bin/env bash
# The test command's fuzz stage: builds every libFuzzer harness of tests/fuzz
# (clang, ASan + UBSan), replays the committed seed corpus and regression
# inputs through each, then fuzzes each for a short bounded time from a fresh
# working corpus. Fails on any crash, sanitizer report, failed check, leak,
# or input beyond the per-input limits of `scripts/fuzz.sh --limits HARNESS`
# (2 s for a file reader, 5 s for cli and pipeline; 256 MB of RSS and for any
# one allocation).
#
#   scripts/fuzz-test.sh [SECONDS_PER_HARNESS]    (default 20, or $TRISTEREO_FUZZ_SECONDS)
#
# Prints "  fuzz-HARNESS: passed" (or FAILED) per harness and each run's
# executions and coverage (scripts/fuzz.sh's closing line). With 7 harnesses
# at 20 s the runs take ~2.5 min on top of the build.
set -uo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-${TRISTEREO_FUZZ_SECONDS:-20}}"
build="${TRISTEREO_FUZZ_BUILD:-${repo}/build-fuzz}"
export TRISTEREO_FUZZ_BUILD="${build}"
harnesses=$("${repo}/scripts/fuzz.sh" --list)
cxx="$(command -v clang++-14 || command -v clang++ || true)"
if [[ -z "${cxx}" ]]; then
  echo "fuzz-test: no clang++ found: run scripts/install-deps.sh fuzz" >&2
  exit 1
fi
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

targets=()
for h in ${harnesses}; do targets+=("fuzz_${h}"); done
if [[ "${TRISTEREO_FUZZ_PREBUILT:-0}" == 1 ]]; then
  # Built by an earlier stage (scripts/sanitize-test.sh asan with
  # TRISTEREO_ASAN_FUZZ=1): only checked here.
  for t in "${targets[@]}"; do
    if [[ ! -x "${build}/tests/fuzz/${t}" ]]; then
      echo "fuzz-test: TRISTEREO_FUZZ_PREBUILT=1 but ${build}/tests/fuzz/${t} is missing (did the asan stage build?)" >&2
      exit 1
    fi
  done
  echo "fuzz-test: the harnesses built in ${build} (-O1, ASan + UBSan, coverage feedback)"
else
  set -e
  "${repo}/scripts/configure.sh" "${build}" -S "${repo}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER="${cxx}" "${launcher[@]}" -DTRISTEREO_FUZZ=ON -DTRISTEREO_WERROR=ON \
    -DTRISTEREO_BUILD_TESTS=OFF -DTRISTEREO_BUILD_BENCH=OFF -DTRISTEREO_BUILD_PYTHON=OFF \
    -DTRISTEREO_BUILD_APPS=ON
  cmake --build "${build}" -j"$(nproc)" --target "${targets[@]}"
  set +e
fi

# ASan keeps freed blocks in a quarantine (256 MB by default) to catch uses
# after free; counted in the RSS, it alone would reach the 256 MB limit.
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:allocator_may_return_null=0:quarantine_size_mb=64}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
symbolizer="$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)"
[[ -n "${symbolizer}" ]] && export ASAN_SYMBOLIZER_PATH="${symbolizer}"

work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
failed=0
for h in ${harnesses}; do
  # 1. The committed inputs, each once (sanitized binary, libFuzzer's replay).
  inputs=("${repo}/tests/fuzz/corpus/${h}")
  [[ -d "${repo}/tests/fuzz/regressions/${h}" ]] && inputs+=("${repo}/tests/fuzz/regressions/${h}")
  replay_ok=1
  read -r -a limits <<<"$("${repo}/scripts/fuzz.sh" --limits "${h}")"
  if ! "${build}/tests/fuzz/fuzz_${h}" -runs=0 "${limits[@]}" "${inputs[@]}" \
       >"${work}/replay-${h}.log" 2>&1; then
    replay_ok=0
    tail -n 40 "${work}/replay-${h}.log"
  fi
  # 2. A short run from a fresh working corpus.
  minutes=$(awk -v s="${seconds}" 'BEGIN { printf "%.4f", s / 60 }')
  run_ok=1
  TRISTEREO_FUZZ_SKIP_BUILD=1 TRISTEREO_FUZZ_CORPUS="${work}/corpus-${h}" \
    "${repo}/scripts/fuzz.sh" "${h}" "${minutes}" || run_ok=0
  if [[ ${replay_ok} -eq 1 && ${run_ok} -eq 1 ]]; then
    echo "  fuzz-${h}: passed"
  else
    echo "  fuzz-${h}: FAILED (replay $([[ ${replay_ok} -eq 1 ]] && echo ok || echo failed), run $([[ ${run_ok} -eq 1 ]] && echo ok || echo failed))"
    failed=$((failed + 1))
  fi
done
echo "fuzz-test: ${failed} harness(es) failed"
[[ ${failed} -eq 0 ]]
