#!/usr/bin/env bash
# Runs one libFuzzer harness of tests/fuzz for a while (docs/fuzzing.md).
#
#   scripts/fuzz.sh HARNESS MINUTES [libFuzzer options...]
#   scripts/fuzz.sh --list
#   scripts/fuzz.sh --limits HARNESS    (the per-input limits, as libFuzzer options)
#
# HARNESS: png, pnm, pfm, disp_png, calib, cli or pipeline. MINUTES may be a
# decimal (0.5 = 30 s). Builds the harnesses first (clang, ASan + UBSan,
# build dir $TRISTEREO_FUZZ_BUILD, default build-fuzz), then fuzzes from the
# committed seeds (tests/fuzz/corpus/HARNESS) and regression inputs
# (tests/fuzz/regressions/HARNESS). What it finds that adds coverage goes to
# the working corpus $TRISTEREO_FUZZ_CORPUS (default BUILD/corpus/HARNESS),
# never into the repository; a crashing, leaking, slow or memory-hungry input
# (beyond the per-input limits that `scripts/fuzz.sh --limits HARNESS`
# prints: 2 s wall time for the file readers, 5 s for cli and pipeline, and
# 256 MB, both for the RSS and for any one allocation; $TRISTEREO_FUZZ_TIMEOUT
# and $TRISTEREO_FUZZ_RSS_MB override them) is saved under
# BUILD/artifacts/HARNESS/ and fails the run. Ends with one line:
#   fuzz HARNESS: passed|FAILED, N executions in S s, cov C, ft F, corpus K,
#   slowest input T s, peak RSS M MB
# (cov: code edges reached; ft: libFuzzer's finer coverage features; T is
# whole seconds, rounded down).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
harnesses="png pnm pfm disp_png calib cli pipeline"
if [[ "${1:-}" == "--list" ]]; then
  echo "${harnesses}"
  exit 0
fi
if [[ $# -lt 2 ]]; then
  echo "usage: scripts/fuzz.sh HARNESS MINUTES [libFuzzer options...]   (HARNESS: ${harnesses})" >&2
  exit 2
fi
harness=$2
[[ "$1" != "--limits" ]] && harness=$1
if [[ " ${harnesses} " != *" ${harness} "* ]]; then
  echo "fuzz: unknown harness '${harness}' (expected one of: ${harnesses})" >&2
  exit 2
fi
# Per-input limits, the same for this script's runs and the test command's
# replay (scripts/fuzz-test.sh): small enough that a reader that allocates or
# works beyond what its few-KiB input holds fails, as issue 41's 52-byte PNG
# would have (2.1 GB, 8-15 s). The slowest input of a 30-minute run stays
# under 1 s (docs/fuzzing.md); cli and pipeline run whole frames, hence 5 s.
case "${harness}" in
  cli|pipeline) timeout_s=5 ;;
  *) timeout_s=2 ;;
esac
timeout_s="${TRISTEREO_FUZZ_TIMEOUT:-${timeout_s}}"
rss_mb="${TRISTEREO_FUZZ_RSS_MB:-256}"
# -malloc_limit_mb: one allocation above the limit fails at once, before it is
# touched (the RSS check samples once a second and would miss a short spike).
limits=(-timeout="${timeout_s}" -rss_limit_mb="${rss_mb}" -malloc_limit_mb="${rss_mb}")
if [[ "$1" == "--limits" ]]; then
  echo "${limits[*]}"
  exit 0
fi
minutes=$2
shift 2
if ! seconds=$(awk -v m="${minutes}" 'BEGIN { if (m !~ /^[0-9]+(\.[0-9]+)?$/ || m <= 0) exit 1; s = int(m * 60 + 0.5); print (s < 1 ? 1 : s) }'); then
  echo "fuzz: MINUTES must be a positive number, got '${minutes}'" >&2
  exit 2
fi

build="${TRISTEREO_FUZZ_BUILD:-${repo}/build-fuzz}"
cxx="${TRISTEREO_FUZZ_CXX:-$(command -v clang++-14 || command -v clang++ || true)}"
if [[ -z "${cxx}" ]]; then
  echo "fuzz: no clang++ found: run scripts/install-deps.sh fuzz" >&2
  exit 1
fi
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

if [[ "${TRISTEREO_FUZZ_SKIP_BUILD:-0}" != 1 ]]; then
  "${repo}/scripts/configure.sh" "${build}" -S "${repo}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER="${cxx}" "${launcher[@]}" -DTRISTEREO_FUZZ=ON -DTRISTEREO_WERROR=ON \
    -DTRISTEREO_BUILD_TESTS=OFF -DTRISTEREO_BUILD_BENCH=OFF -DTRISTEREO_BUILD_PYTHON=OFF \
    -DTRISTEREO_BUILD_APPS=ON >/dev/null
  cmake --build "${build}" -j"${TRISTEREO_FUZZ_JOBS:-$(nproc)}" --target "fuzz_${harness}"
fi

# Longest input each harness is given: images of a few hundred pixels, a
# calibration file, an argument list, a frame pair of up to 40x40 RGB.
case "${harness}" in
  png|pnm|pfm|disp_png) max_len=8192 ;;
  calib) max_len=4096 ;;
  cli) max_len=512 ;;
  pipeline) max_len=4096 ;;
esac
corpus="${TRISTEREO_FUZZ_CORPUS:-${build}/corpus/${harness}}"
artifacts="${build}/artifacts/${harness}"
mkdir -p "${corpus}" "${artifacts}"
inputs=("${corpus}" "${repo}/tests/fuzz/corpus/${harness}")
[[ -d "${repo}/tests/fuzz/regressions/${harness}" ]] && inputs+=("${repo}/tests/fuzz/regressions/${harness}")
options=(-max_total_time="${seconds}" "${limits[@]}" -max_len="${max_len}"
         -print_final_stats=1 -artifact_prefix="${artifacts}/")
[[ -f "${repo}/tests/fuzz/${harness}.dict" ]] && options+=(-dict="${repo}/tests/fuzz/${harness}.dict")

# ASan keeps freed blocks in a quarantine (256 MB by default) to catch uses
# after free; counted in the RSS, it alone would reach the RSS limit above.
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:allocator_may_return_null=0:quarantine_size_mb=64}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
symbolizer="$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)"
[[ -n "${symbolizer}" ]] && export ASAN_SYMBOLIZER_PATH="${symbolizer}"

log="${build}/fuzz-${harness}.log"
echo "fuzz ${harness}: ${seconds} s, corpus ${corpus}, log ${log}"
start=$(date +%s)
status=passed
if ! "${build}/tests/fuzz/fuzz_${harness}" "${options[@]}" "$@" "${inputs[@]}" >"${log}" 2>&1; then
  status=FAILED
fi
elapsed=$(($(date +%s) - start))
# A report that did not stop the run still fails it.
if grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|fuzz check failed' "${log}"; then
  status=FAILED
fi
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "${log}" | tail -n 1)
slowest=$(sed -n 's/^stat::slowest_unit_time_sec: *//p' "${log}" | tail -n 1)
peak=$(sed -n 's/^stat::peak_rss_mb: *//p' "${log}" | tail -n 1)
last=$(grep -E '^#[0-9]+' "${log}" | grep -E ' cov: ' | tail -n 1 || true)
cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"${last}")
ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"${last}")
corp=$(sed -n 's/.* corp: \([0-9]*\)\/.*/\1/p' <<<"${last}")
if [[ "${status}" == FAILED ]]; then
  echo "---- last lines of ${log}:"
  tail -n 40 "${log}"
  find "${artifacts}" -type f -printf "artifact: %p\n" 2>/dev/null || true
fi
echo "fuzz ${harness}: ${status}, ${execs:-?} executions in ${elapsed} s, cov ${cov:-?}, ft ${ft:-?}, corpus ${corp:-?}, slowest input ${slowest:-?} s, peak RSS ${peak:-?} MB"
[[ "${status}" == passed ]]
