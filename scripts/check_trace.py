#!/usr/bin/env python3
"""Checks a frame trace written by `tristereo profile --trace FILE`.

    scripts/check_trace.py FILE [--workers N] [--frames N]

It must be Chrome trace-event JSON that Perfetto and chrome://tracing open: a
named track per worker and one for the pipeline, complete ("X") events with
ts and dur >= 0; on each worker's track the runs never overlap, nor do the
work items, and every item lies in one of that worker's runs (or, for
worker 0, the caller, in a frame: it runs some work inline); on the
pipeline track the frames never overlap and every stage lies in a frame.
Prints one line starting with "ok:" or exits 1 naming the first problem.
"""
import argparse
import json
import sys

EPS = 1e-3  # us: ts and dur are written with nanosecond digits


def fail(msg):
    print(f"check_trace: {msg}", file=sys.stderr)
    sys.exit(1)


def inside(a, b):
    return a["ts"] >= b["ts"] - EPS and a["ts"] + a["dur"] <= b["ts"] + b["dur"] + EPS


def no_overlap(spans, what):
    spans = sorted(spans, key=lambda e: e["ts"])
    for p, q in zip(spans, spans[1:]):
        if q["ts"] < p["ts"] + p["dur"] - EPS:
            fail(f"{what}: '{q['name']}' at {q['ts']} us starts before '{p['name']}' at {p['ts']} us ends")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--workers", type=int, help="the worker count the trace must have")
    ap.add_argument("--frames", type=int, help="the frame count the trace must have")
    args = ap.parse_args()
    try:
        with open(args.file) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{args.file}: {e}")
    events = data.get("traceEvents")
    if not isinstance(events, list):
        fail("no traceEvents list")
    workers = data.get("otherData", {}).get("workers")
    if args.workers is not None and workers != args.workers:
        fail(f"{workers} workers, expected {args.workers}")
    names = {e["tid"]: e["args"]["name"] for e in events if e.get("ph") == "M" and e.get("name") == "thread_name"}
    if names.get(0) != "pipeline" or any(names.get(w + 1) != f"worker {w}" for w in range(workers)):
        fail(f"track names {names}")
    spans = [e for e in events if e.get("ph") == "X"]
    for e in spans:
        if not all(isinstance(e.get(k), (int, float)) for k in ("ts", "dur")) or e["dur"] < 0 or e["ts"] < 0:
            fail(f"event without ts/dur >= 0: {e}")
        if e["tid"] not in names:
            fail(f"event on an unnamed track: {e}")
    pipe = [e for e in spans if e["tid"] == 0]
    frames = [e for e in pipe if e["name"] == "frame"]
    if not frames:
        fail("no frame")
    if args.frames is not None and len(frames) != args.frames:
        fail(f"{len(frames)} frames, expected {args.frames}")
    no_overlap(frames, "pipeline track")
    for e in pipe:
        if not any(inside(e, f) for f in frames):
            fail(f"stage '{e['name']}' at {e['ts']} us is outside every frame")
    items_total = 0
    for w in range(workers):
        track = [e for e in spans if e["tid"] == w + 1]
        runs = [e for e in track if e["name"] == "run"]
        items = [e for e in track if e["name"] != "run"]
        no_overlap(runs, f"worker {w}'s runs")
        no_overlap(items, f"worker {w}'s items")
        for it in items:
            if not any(inside(it, r) for r in runs) and not (w == 0 and any(inside(it, f) for f in frames)):
                fail(f"worker {w}: '{it['name']}' at {it['ts']} us lies in none of its runs")
        items_total += len(items)
    print(f"ok: {len(frames)} frames, {workers} workers, {len(pipe) - len(frames)} stage spans, "
          f"{items_total} work items, {data.get('otherData', {}).get('dropped', 0)} dropped")


if __name__ == "__main__":
    main()
