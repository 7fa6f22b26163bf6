#!/usr/bin/env bash
# ThreadSanitizer run of the thread-pool tests and of every test that runs the
# tritree or the pipeline on a pool (the tritree's tiles, the path passes and
# rows handed out on demand, banded output).
#
#   scripts/tsan-test.sh [build-dir] [ctest -R regex]
#
# Configures a separate build with -DTRISTEREO_TSAN=ON, builds only the test
# executables needed, and runs them through ctest. Some kernels (high
# vm.mmap_rnd_bits, e.g. 6.x defaults) place mappings where TSan's shadow
# layout does not expect them and TSan dies with "unexpected memory mapping";
# the script detects that and reruns with address randomisation disabled
# (setarch -R), which is only a property of this test process.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-${repo}/build-tsan}"
regex="${2:-^(ThreadPool|Affinity|WorkChunks|HomeChunks|SideWork|Wavefront|FrameTrace|Tritree\.IdenticalForAnyThreadCount|TritreePredecessors|PathAggregation|FillThreads|PipelineThreads\.(SyntheticScene|RandomParameters|WorkersArePinned|SecondPipeline|Reconfigure)|SupportPrior\.IdenticalForAnyWorkerCount)}"
targets=(thread_pool_test work_chunks_test wavefront_test frame_trace_test platform_test tritree_test tritree_predecessors_test paths_test sample_fill_test pipeline_threads_test support_prior_test)
jobs="${TSAN_JOBS:-$(nproc)}"
locks_memory='^(ThreadPoolRealtime\.AppliesToEveryWorkerOrChangesNothing|Realtime\.EnableRealtimeSucceedsOrExplains)$'

cmake -S "${repo}" -B "${build}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTRISTEREO_TSAN=ON -DTRISTEREO_BUILD_BENCH=OFF -DTRISTEREO_BUILD_APPS=OFF
cmake --build "${build}" -j"${jobs}" --target "${targets[@]}"

# halt_on_error makes a race fail the test instead of only printing a report.
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 ${TSAN_OPTIONS:-}"

runner=()
probe_log="$(mktemp)"
trap 'rm -f "${probe_log}"' EXIT
if ! "${build}/tests/thread_pool_test" --gtest_list_tests >/dev/null 2>"${probe_log}"; then
  if grep -q "unexpected memory mapping" "${probe_log}"; then
    echo "tsan-test: TSan rejects this kernel's memory layout; rerunning under setarch -R" >&2
    runner=(setarch "$(uname -m)" -R)
  else
    cat "${probe_log}" >&2
    exit 1
  fi
fi

cd "${build}"
# The two tests that call mlockall (real-time mode) skip themselves under a
# sanitizer, which would lock its shadow memory; they are left out here so the
# report lists no skipped test (they run in the native and kernel-set stages).
"${runner[@]}" ctest --output-on-failure -R "${regex}" -E "${locks_memory}"
