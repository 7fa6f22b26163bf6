#!/bin/sh
# Predicts the default frame on 1-16 workers from one-worker traces and
# compares the 2-worker prediction with a 2-worker trace (docs/threads.md).
#
#   scripts/scaling_report.sh [BUILD_DIR] -- PROFILE_OPTIONS...
#   e.g. scripts/scaling_report.sh -- --left L.png --right R.png --ndisp 80
#
# Records, back to back, with `tristereo profile --frames 30 --trace-frames 20`:
# two workers (the memory contention's calibration); one worker; one worker
# cut for 4, 8 and 16 (--schedule-workers); two workers again (the measured
# frame the prediction is compared with); then runs scripts/scaling_model.py
# on them (--same-frames: give one pair, --left/--right, not the moving
# synthetic sequence). The traces stay in $TMPDIR/tristereo-scaling.XXXXXX,
# whose name is printed.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
build="$repo/build"
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
  build=$1
  shift
fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
if [ ! -x "$build/tristereo" ]; then
  echo "scaling_report: no $build/tristereo (build it first: cmake --build $build)" >&2
  exit 2
fi
dir=$(mktemp -d "${TMPDIR:-/tmp}/tristereo-scaling.XXXXXX")
echo "scaling_report: traces in $dir"
run() {
  "$build/tristereo" profile "$@" --frames 30 --warmup 5 --trace-frames 20 --quiet
}
run "$@" --threads 2 --trace "$dir/t2-contention.json"
run "$@" --threads 1 --trace "$dir/t1.json"
for n in 4 8 16; do
  run "$@" --threads 1 --schedule-workers "$n" --trace "$dir/t1-cut$n.json"
done
run "$@" --threads 2 --trace "$dir/t2.json"
/usr/bin/python3 "$repo/scripts/scaling_model.py" "$dir/t1.json" "$dir/t1-cut4.json" "$dir/t1-cut8.json" \
  "$dir/t1-cut16.json" --same-frames --measured "$dir/t2.json" --contention "$dir/t2-contention.json" --slow 0.5
