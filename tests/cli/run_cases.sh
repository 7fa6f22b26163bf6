#!/bin/bash
# The case functions below are called from tests/cli/cases.sh (sourced).
# shellcheck disable=SC2317,SC2086,SC1091
# Runs the bad-input cases of tests/cli/cases.sh against the tristereo program
# and checks each response (exit code and message), then either prints the
# table of docs/reliability.md or checks that the doc holds that very table.
#
# usage: tests/cli/run_cases.sh TRISTEREO MAKE_BAD_FILES WORKDIR [--check-doc DOC | --write-doc DOC]
#
# Every case runs with a time limit (CLI_CASES_TIMEOUT seconds, default 60)
# and an address-space limit (CLI_CASES_VMEM_KB, default 1000000 = ~1 GB;
# 0 = none, needed under AddressSanitizer), so a hang or a reader that
# allocates what a header claims shows up as a failed case.
# Exit status: 0 when every case answered as expected (and the doc matches).
set -u
if [ $# -lt 3 ]; then
  echo "usage: $0 TRISTEREO MAKE_BAD_FILES WORKDIR [--check-doc DOC | --write-doc DOC]" >&2
  exit 2
fi
T=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
export BAD=$2  # read by tests/cli/cases.sh
W=$3
mode=${4:-}
doc=${5:-}
here=$(cd "$(dirname "$0")" && pwd)
timeout_s=${CLI_CASES_TIMEOUT:-60}
vmem_kb=${CLI_CASES_VMEM_KB:-1000000}

rm -rf "$W" && mkdir -p "$W" || exit 1
# Cases that must fit in 100 MB of address space call this first; with
# CLI_CASES_VMEM_KB=0 (sanitizers reserve terabytes) it does nothing.
vmem_limit_100mb() { [ "${CLI_CASES_VMEM_KB:-1}" = 0 ] || ulimit -v 100000; }
export -f vmem_limit_100mb
export CLI_CASES_VMEM_KB=$vmem_kb
W=$(cd "$W" && pwd)

n=0 n_error=0 n_warning=0 n_crash=0 n_hang=0 n_garbage=0 n_wrong=0
rows=""

# Paths and the program's location never appear in the table.
# Neither does the number of CPUs of the machine that ran them.
normalise() {
  sed -e "s|$W|W|g" -e "s|$T|tristereo|g" -e 's/|/\\|/g' \
      -e 's/--threads [0-9]* with only [0-9]* CPUs allowed/--threads N+1 with only N CPUs allowed/'
}

# run KIND EXIT REGEX DESCRIPTION COMMAND [AFTER_CHECK AFTER_DESCRIPTION]
#   KIND error: expects exit EXIT and REGEX (grep -E) on stderr's first line.
#   KIND warning: expects exit 0 and REGEX on a stderr line starting "warning:".
#   AFTER_CHECK: a shell test on the state afterwards (e.g. the file that was
#   at an output path is still there), run in W.
run() {
  local kind=$1 want=$2 regex=$3 what=$4 cmd=$5 after=${6:-} after_what=${7:-}
  n=$((n + 1))
  (
    [ "$vmem_kb" != 0 ] && ulimit -v "$vmem_kb"
    cd "$W" && exec timeout "$timeout_s" bash -c "$cmd"
  ) > "$W/.out" 2> "$W/.err"
  local rc=$? verdict="" first exit_ok=0
  if [ "$kind" = error ]; then [ "$rc" = "$want" ] && exit_ok=1; else [ "$rc" = 0 ] && exit_ok=1; fi
  if [ "$kind" = warning ]; then first=$(grep -m1 '^warning:' "$W/.err"); else first=$(head -n 1 "$W/.err"); fi
  if [ "$rc" = 124 ]; then verdict=hang; n_hang=$((n_hang + 1))
  elif [ "$rc" -ge 128 ] || grep -qE 'Sanitizer|terminate called|bad_alloc|Segmentation|Aborted' "$W/.err"; then
    verdict=crash; n_crash=$((n_crash + 1))
  elif [ $rc = 0 ] && [ "$kind" = error ]; then verdict="silent (exit 0)"; n_garbage=$((n_garbage + 1))
  elif [ $rc = 0 ] && [ -z "$first" ]; then verdict="silent (no warning)"; n_garbage=$((n_garbage + 1))
  elif [ $exit_ok = 0 ] || ! printf '%s\n' "$first" | grep -qE -- "$regex"; then
    verdict="wrong answer"; n_wrong=$((n_wrong + 1))
  elif [ -n "$after" ] && ! (cd "$W" && bash -c "$after"); then
    verdict="after-check failed: $after"; n_wrong=$((n_wrong + 1))
  else
    verdict=ok
    if [ "$kind" = error ]; then n_error=$((n_error + 1)); else n_warning=$((n_warning + 1)); fi
  fi
  if [ "$verdict" != ok ]; then
    { echo "FAIL case $n ($what): $verdict, exit $rc (want $want), expected /$regex/"
      echo "  command: $cmd"; sed 's/^/  stderr: /' "$W/.err" | head -n 5; } >&2
  fi
  local shown_cmd msg checked="cli.cases #$n"
  shown_cmd=$(printf '%s' "$cmd" | normalise)
  msg=$(printf '%s' "$first" | normalise)
  [ -n "$after_what" ] && checked="$checked; then: $after_what"
  rows="$rows| $n | $what | \`$shown_cmd\` | $rc | $msg | $checked |
"
}

. "$here/cases.sh"

table="| # | bad input | command | exit | response (first line of stderr) | checked by |
|--:|---|---|--:|---|---|
$rows
| tried | clear error | warning | crash | hang | silent garbage | wrong answer |
|--:|--:|--:|--:|--:|--:|--:|
| $n | $n_error | $n_warning | $n_crash | $n_hang | $n_garbage | $n_wrong |"

status=0
[ $((n_crash + n_hang + n_garbage + n_wrong)) = 0 ] || status=1
case "$mode" in
  --write-doc)
    # ENVIRON, not -v: awk would expand the backslashes of messages like "\x00".
    TABLE="$table" awk '
      /<!-- cases:begin -->/ { print; print ENVIRON["TABLE"]; skip = 1; next }
      /<!-- cases:end -->/ { skip = 0 }
      !skip { print }' "$doc" > "$doc.new" && mv "$doc.new" "$doc" ;;
  --check-doc)
    awk '/<!-- cases:end -->/ { skip = 0 } skip { print } /<!-- cases:begin -->/ { skip = 1 }' "$doc" > "$W/.doc-table"
    printf '%s\n' "$table" > "$W/.run-table"
    if [ "$vmem_kb" = 0 ]; then
      # Without the address-space limit (sanitizers) the cases that run under
      # it answer differently (still a clear error, checked above): compare the rest.
      grep -v 'vmem_limit_100mb' "$W/.doc-table" > "$W/.doc-table.t" && mv "$W/.doc-table.t" "$W/.doc-table"
      grep -v 'vmem_limit_100mb' "$W/.run-table" > "$W/.run-table.t" && mv "$W/.run-table.t" "$W/.run-table"
    fi
    if ! diff -u "$W/.doc-table" "$W/.run-table" >&2; then
      echo "FAIL: $doc does not hold the table this run produced (rerun with --write-doc $doc)" >&2
      status=1
    fi ;;
  *) printf '%s\n' "$table" ;;
esac
echo "cases: $n tried, $n_error clear errors, $n_warning warnings, $n_crash crashes, $n_hang hangs, $n_garbage silent, $n_wrong wrong"
[ $status = 0 ] && echo "all cases answered as expected"
exit $status
