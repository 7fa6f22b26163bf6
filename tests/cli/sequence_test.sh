#!/bin/sh
# match --folder / --list (a recorded run in one process) against one-pair
# match runs of the same pairs: every output byte-identical; a corrupt, a
# missing and a wrong-size frame in the middle skipped and named (exit 1);
# bad output patterns refused (exit 2); --quiet.
# usage: tests/cli/sequence_test.sh TRISTEREO WORKDIR
set -u
T=$1
d=$2
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
rm -rf "$d" && mkdir -p "$d/seq" "$d/one" "$d/out" || exit 1
M="--ndisp 16 --camera 200,0.1,48,32"
# Three different synthetic pairs, numbered from 1 in the folder.
for i in 1 2 3; do
  "$T" synth "$d/s$i" --width 96 --height 64 --ndisp 16 --seed "$i" > /dev/null || exit 1
  cp "$d/s$i/left.png" "$d/seq/left_000$i.png" && cp "$d/s$i/right.png" "$d/seq/right_000$i.png" || exit 1
  # shellcheck disable=SC2086
  "$T" match "$d/s$i/left.png" "$d/s$i/right.png" $M --disp "$d/one/disp_$i.pfm" --disp-color "$d/one/color_$i.png" \
    --mesh "$d/one/mesh_$i.ply" --samples "$d/one/samples_$i.csv" --depth "$d/one/depth_$i.png" \
    --points "$d/one/points_$i.ply" --valid "$d/one/valid_$i.png" --confidence "$d/one/conf_$i.png" \
    > /dev/null 2>&1 || exit 1
done
outs() {  # outs DIR: the output options as patterns into DIR
  echo "--disp $1/disp_%d.pfm --disp-color $1/color_%d.png --mesh $1/mesh_%d.ply --samples $1/samples_%d.csv --depth $1/depth_%d.png --points $1/points_%d.ply --valid $1/valid_%d.png --confidence $1/conf_%d.png"
}
same() {  # same DIR I J: DIR's frame I outputs equal the one-pair run J's
  for o in disp_$2.pfm:disp_$3.pfm color_$2.png:color_$3.png mesh_$2.ply:mesh_$3.ply samples_$2.csv:samples_$3.csv \
           depth_$2.png:depth_$3.png points_$2.ply:points_$3.ply valid_$2.png:valid_$3.png conf_$2.png:conf_$3.png; do
    cmp -s "$1/${o%%:*}" "$d/one/${o##*:}" || fail "$1/${o%%:*} differs from one/${o##*:}"
  done
}

# The folder, with two workers: outputs of frames 1..3, stats lines, summary.
# shellcheck disable=SC2086,SC2046
"$T" match --folder "$d/seq" $M $(outs "$d/out") --stats "$d/out/stats.jsonl" --threads 2 > "$d/stdout" 2> "$d/stderr"
rc=$?
[ $rc = 0 ] || fail "folder run: exit $rc: $(cat "$d/stderr")"
for i in 1 2 3; do same "$d/out" "$i" "$i"; done
[ -e "$d/out/disp_0.pfm" ] && fail "a frame 0 was written"
[ "$(wc -l < "$d/out/stats.jsonl")" = 3 ] || fail "stats.jsonl has not 3 lines"
grep -q '^{"frame": 2, "left": "[^"]*/seq/left_0002.png", "right": "[^"]*/seq/right_0002.png", "implementation": ' \
  "$d/out/stats.jsonl" || fail "stats.jsonl's second line: $(sed -n 2p "$d/out/stats.jsonl")"
python3 -c 'import json,sys; [json.loads(l) for l in open(sys.argv[1])]' "$d/out/stats.jsonl" 2> /dev/null ||
  ! command -v python3 > /dev/null || fail "stats.jsonl is not one JSON object per line"
grep -q '^3 frames: 3 done, 0 failed; [0-9.]* fps' "$d/stdout" || fail "summary: $(cat "$d/stdout")"
grep -q '^median ms: tritree [0-9.]*, ' "$d/stdout" || fail "summary's medians: $(cat "$d/stdout")"
# No progress line when stderr is not a terminal: only the mesh writer's warnings.
grep -qv '^warning: --mesh ' "$d/stderr" && fail "stderr has more than warnings: $(cat "$d/stderr")"

# --quiet: nothing on stdout.
# shellcheck disable=SC2086
"$T" match --folder "$d/seq" $M --disp "$d/out/q_%d.pfm" --quiet > "$d/stdout" 2>&1 || fail "--quiet run failed"
[ -s "$d/stdout" ] && fail "--quiet printed: $(cat "$d/stdout")"
cmp -s "$d/out/q_2.pfm" "$d/one/disp_2.pfm" || fail "--quiet's q_2.pfm differs"

# A corrupt left image (frame 2), a missing right one (frame 3) and a frame
# of another size (4) in the middle: named, skipped, the others done, exit 1.
mkdir -p "$d/bad" "$d/badout"
cp "$d"/seq/*.png "$d/bad/" && head -c 300 "$d/seq/left_0002.png" > "$d/bad/left_0002.png" && rm "$d/bad/right_0003.png"
"$T" synth "$d/small" --width 64 --height 48 --ndisp 16 --seed 4 > /dev/null || exit 1
cp "$d/small/left.png" "$d/bad/left_0004.png" && cp "$d/small/right.png" "$d/bad/right_0004.png"
cp "$d/s1/left.png" "$d/bad/left_0005.png" && cp "$d/s1/right.png" "$d/bad/right_0005.png"
# shellcheck disable=SC2086,SC2046
"$T" match --folder "$d/bad" $M $(outs "$d/badout") --stats "$d/badout/stats.jsonl" > "$d/stdout" 2> "$d/stderr"
rc=$?
[ $rc = 1 ] || fail "bad frames: exit $rc, not 1"
grep -q "frame 2 (.*/bad/left_0002.png, .*/bad/right_0002.png) skipped: error" "$d/stderr" || fail "frame 2 not named: $(cat "$d/stderr")"
grep -q "frame 3 (.*) skipped: error (.*right_0003.png" "$d/stderr" || fail "frame 3 not named: $(cat "$d/stderr")"
grep -q "frame 4 (.*) skipped: error (size mismatch): the pair is 64x48 but the sequence's first frame is 96x64" \
  "$d/stderr" || fail "frame 4 not named: $(cat "$d/stderr")"
same "$d/badout" 1 1
same "$d/badout" 5 1
for i in 2 3 4; do [ -e "$d/badout/disp_$i.pfm" ] && fail "frame $i has an output"; done
grep -q '^5 frames: 2 done, 3 failed' "$d/stdout" || fail "summary: $(cat "$d/stdout")"
[ "$(wc -l < "$d/badout/stats.jsonl")" = 2 ] || fail "bad run's stats.jsonl has not 2 lines"

# --list: relative to the list's folder, '#' comments, numbered from 0.
mkdir -p "$d/listout"
printf '# a recorded run\nseq/left_0003.png seq/right_0003.png\n\n  s1/left.png\ts1/right.png\n' > "$d/run.txt"
# shellcheck disable=SC2086,SC2046
"$T" match --list "$d/run.txt" $M $(outs "$d/listout") --quiet > /dev/null 2>&1 || fail "--list run failed"
same "$d/listout" 0 3
same "$d/listout" 1 1

# Bad patterns and sequences: exit 2 before any frame is read.
expect2() {  # expect2 REGEX ARGS...
  re=$1; shift
  "$T" match "$@" > /dev/null 2> "$d/stderr"; rc=$?
  [ $rc = 2 ] || fail "$*: exit $rc, not 2"
  grep -qE -- "$re" "$d/stderr" || fail "$*: stderr $(cat "$d/stderr")"
}
expect2 "--disp '[^']*/x.pfm' must contain exactly one %d-style field, found 0" --folder "$d/seq" --ndisp 16 --disp "$d/x.pfm"
expect2 "found 2" --folder "$d/seq" --ndisp 16 --mesh "$d/m_%d_%d.ply"
expect2 "only one %d-style field" --folder "$d/seq" --ndisp 16 --disp "$d/x_%s.pfm"
expect2 "seq/left_0001.png is the LEFT input; refusing to overwrite an input" --folder "$d/seq" --ndisp 16 --disp-color "$d/seq/left_%04d.png"
printf 'seq/left_0001.png seq/right_0001.png\nseq/left_0002.png seq/right_0002.png\n' > "$d/shifted.txt"
expect2 "--disp-color [^ ]*seq/left_0001.png is an input of the sequence \(written for frame 1\)" --list "$d/shifted.txt" \
  --ndisp 16 --disp-color "$d/seq/left_%04d.png"
expect2 "--stats [^ ]*/s.json: extension '.json' is not written; the file must end in .jsonl" --folder "$d/seq" --ndisp 16 --stats "$d/s.json"
expect2 "--folder and --list both name the frames" --folder "$d/seq" --list "$d/run.txt" --ndisp 16
expect2 "no LEFT RIGHT paths beside it" --folder "$d/seq" "$d/s1/left.png" "$d/s1/right.png" --ndisp 16
expect2 "--quiet has no effect without --folder or --list" "$d/s1/left.png" "$d/s1/right.png" --ndisp 16 --quiet
[ -e "$d/x.pfm" ] || [ -e "$d/x_1.pfm" ] && fail "a refused run wrote something"

[ $fails = 0 ] && echo "sequence: all checks passed"
exit $((fails > 0))
