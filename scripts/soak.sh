#!/bin/sh
# Soak of the default model: many frames of one synthetic 640x480 pair at
# D = 128 on two workers, then three checks on the profile's JSON:
#   - resident memory flat: max - start <= 1 MiB over the measured loop
#     (sampled after warm-up, every frames/100 frames);
#   - p99 latency of the last 1000 frames within TOL % of the first 1000's
#     (wall clock; the CPU time per frame is printed beside it, since on a
#     shared machine the wall clock follows the other jobs);
#   - the last frame's outputs identical to the first's (same input).
#
# Usage: scripts/soak.sh [BUILD_DIR] [-- extra profile options]
# Environment:
#   TRISTEREO_SOAK_FRAMES   measured frames (default 10000)
#   TRISTEREO_SOAK_THREADS  workers (default 2)
#   TRISTEREO_SOAK_P99_TOL  tolerance of the p99 check in percent (default 10)
#   TRISTEREO_SOAK_OUT      folder for soak.json and soak.csv (default: a
#                           temporary folder, removed at the end)
# Exits 1 when a check fails, 2 on a usage error.
set -eu
cd "$(dirname "$0")/.."
build=build
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
  build=$1
  shift
fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
frames=${TRISTEREO_SOAK_FRAMES:-10000}
threads=${TRISTEREO_SOAK_THREADS:-2}
tol=${TRISTEREO_SOAK_P99_TOL:-10}
case "$frames$threads$tol" in
  *[!0-9]*|'') echo "soak: TRISTEREO_SOAK_FRAMES, _THREADS and _P99_TOL take whole numbers" >&2; exit 2 ;;
esac
tool="$build/tristereo"
[ -x "$tool" ] || { echo "soak: no $tool (build it first: cmake --build $build --target tristereo_cli)" >&2; exit 2; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=${TRISTEREO_SOAK_OUT:-$tmp}
mkdir -p "$out"
"$tool" synth "$tmp/scene" --width 640 --height 480 --ndisp 128 >/dev/null
echo "soak: $frames frames of $tmp/scene (640x480, D = 128), $threads workers, default model"
start=$(date +%s)
"$tool" profile --left "$tmp/scene/left.png" --right "$tmp/scene/right.png" --ndisp 128 \
  --frames "$frames" --warmup 20 --threads "$threads" --quiet \
  --json "$out/soak.json" --csv "$out/soak.csv" "$@"
echo "soak: the loop took $(($(date +%s) - start)) s; reports in $out"

python3 - "$out/soak.json" "$tol" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
tol = float(sys.argv[2])
rss, drift, outs = r["rss"], r["drift"], r["outputs"]
failed = 0

def check(name, ok, detail):
    global failed
    print(f"  {name}: {'passed' if ok else 'FAILED'} ({detail})")
    failed += not ok

grow_kib = (rss["max_mb"] - rss["start_mb"]) * 1024
check("rss", grow_kib <= 1024,
      f"start {rss['start_mb']:.3f} MiB, max {rss['max_mb']:.3f} MiB, end {rss['end_mb']:.3f} MiB: "
      f"max - start {grow_kib:.0f} KiB, limit 1024 KiB; {rss['samples']} samples")
n = drift["window_frames"]
cpu_change = 100.0 * (drift["last_cpu"]["p99_ms"] - drift["first_cpu"]["p99_ms"]) / drift["first_cpu"]["p99_ms"]
check("p99", abs(drift["p99_change_pct"]) <= tol,
      f"wall p99 of the first {n} frames {drift['first']['p99_ms']:.3f} ms, of the last {n} "
      f"{drift['last']['p99_ms']:.3f} ms ({drift['p99_change_pct']:+.1f} %, limit {tol:g} %); "
      f"CPU per frame p99 {drift['first_cpu']['p99_ms']:.3f} -> {drift['last_cpu']['p99_ms']:.3f} ms "
      f"({cpu_change:+.1f} %); p50 {drift['first']['p50_ms']:.3f} -> {drift['last']['p50_ms']:.3f} ms")
check("outputs", outs["same_input"] and outs["identical"],
      f"frame {outs['first_frame']} {outs['first_digest']}, frame {outs['last_frame']} {outs['last_digest']}")
print(f"soak: {3 - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
EOF
