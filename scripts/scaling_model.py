#!/usr/bin/env python3
"""Predicts a frame's time on N workers from a one-worker frame trace.

    tristereo profile --threads 1 --trace one.json --trace-frames 10 [model options]
    tristereo profile --threads 2 --trace two.json --trace-frames 10 [same options]
    scripts/scaling_model.py one.json --measured two.json

The trace (docs/profiling.md) holds, per frame, the stages on the pipeline
track and, on the worker's track, every ThreadPool run and the work items it
took with their durations. Each frame is replayed on N = 1, 2, 4, 8, 16
workers by a list scheduler:

- the time of a frame outside every run (the caller's serial steps) stays
  serial;
- a run of path tiles (kind "path tile", args pass/band/tile) is a wavefront:
  a tile waits for the tile before it in its band, for the band above to be
  `lead` tiles ahead, and for the band in_flight = N + 1 bands back to be done
  (platform/wavefront.hpp); a free worker takes the ready tile of the lowest
  band; a band's decision ("decide band") follows its last tile on the same
  worker;
- a run with other items (rows of costs, rows of interpolation tiles) hands
  them out in order to whichever worker is free (WorkChunks); the run's time
  outside its items (e.g. the side task the first worker takes) is one more
  item;
- a run without items (the tritree's, the fill's, the right rows') is taken to
  divide evenly: such runs are listed as "even" in the report.

The model knows nothing of memory bandwidth or caches: where the measured
2-worker frame is slower than the prediction, the difference is what the
workers lose to each other outside the schedule.
"""
import argparse
import heapq
import json
import statistics
import sys

STAGES = ["tritree", "costs", "paths forward", "paths backward", "row dp", "right pass", "fill",
          "interpolation"]


def load(path):
    with open(path) as f:
        data = json.load(f)
    events = [e for e in data["traceEvents"] if e.get("ph") == "X"]
    workers = data.get("otherData", {}).get("workers", 1)
    return events, workers


def stage_of(stages, t0, t1):
    """The innermost stage span holding [t0, t1] ("other" when none)."""
    best = None
    for st in stages:
        if st["name"] in STAGES and st["ts"] <= t0 + 1e-3 and t1 <= st["ts"] + st["dur"] + 1e-3:
            if best is None or st["dur"] < best["dur"]:
                best = st
    return best["name"] if best else "other"


def frames_of(events):
    """Per frame: its span, its stages, worker 0's runs with their items, and
    the items worker 0 ran outside any run (a one-worker pool runs some stages
    inline), grouped by stage and kind."""
    pipe = sorted((e for e in events if e["tid"] == 0), key=lambda e: e["ts"])
    w0 = sorted((e for e in events if e["tid"] == 1), key=lambda e: (e["ts"], -e["dur"]))
    frames = []
    for f in (e for e in pipe if e["name"] == "frame"):
        t0, t1 = f["ts"], f["ts"] + f["dur"]
        inside = lambda e, a, b: e["ts"] >= a - 1e-3 and e["ts"] + e["dur"] <= b + 1e-3
        stages = [e for e in pipe if e["name"] != "frame" and inside(e, t0, t1)]
        runs, loose = [], {}
        run_spans = [e for e in w0 if e["name"] == "run" and inside(e, t0, t1)]
        for r in run_spans:
            r0, r1 = r["ts"], r["ts"] + r["dur"]
            items = [e for e in w0 if e["name"] != "run" and inside(e, r0, r1)]
            runs.append({"start": r0, "dur": r["dur"], "items": items, "stage": stage_of(stages, r0, r1)})
        for e in w0:
            if e["name"] == "run" or not inside(e, t0, t1):
                continue
            if any(inside(e, r["ts"], r["ts"] + r["dur"]) for r in run_spans):
                continue
            key = (stage_of(stages, e["ts"], e["ts"] + e["dur"]), e["name"])
            loose.setdefault(key, []).append(e)
        plans = {0: None, 1: None}
        for st in stages:
            if st["name"] in ("paths forward", "paths backward"):
                plans[0 if st["name"] == "paths forward" else 1] = (st["args"]["a"], st["args"]["b"])
        frames.append({"dur": f["dur"], "stages": stages, "runs": runs, "loose": loose, "plans": plans})
    return frames


def wavefront(tiles, decides, cols, lead, workers, speeds=None):
    """Makespan of one pass's tiles on `workers` workers (lowest band first);
    speeds[w]: worker w's speed against the traced one (default 1)."""
    speeds = speeds or [1.0] * workers
    in_flight = 1 if workers == 1 else workers + 1
    dur = {(t["args"]["b"], t["args"]["c"]): t["dur"] for t in tiles}
    bands = 1 + max(b for b, _ in dur)
    done_at = {}
    band_done = [None] * bands
    next_col = [0] * bands
    free = [(0.0, w) for w in range(workers)]  # (time each worker is free, worker)
    heapq.heapify(free)
    low = 0
    remaining = len(dur)
    while remaining:
        t, w = heapq.heappop(free)
        # The lowest band whose next tile is ready by time t; else wait for the
        # earliest tile that becomes ready.
        best = None
        earliest = None
        for k in range(low, min(bands, low + in_flight)):
            c = next_col[k]
            if c >= cols:
                continue
            deps = []
            if c > 0:
                deps.append(done_at.get((k, c - 1)))
            if k > 0:
                deps.append(done_at.get((k - 1, min(cols - 1, c + lead))))
            if k >= in_flight and c == 0:
                deps.append(band_done[k - in_flight])
            if any(d is None for d in deps):
                continue
            ready = max(deps, default=0.0)
            if ready <= t:
                best = (k, c, t)
                break
            if earliest is None or ready < earliest[2]:
                earliest = (k, c, ready)
        pick = best or earliest
        if pick is None:  # cannot happen: the lowest band's next tile always can
            raise RuntimeError("scaling_model: no tile can start")
        k, c, start = pick
        d = dur.get((k, c), 0.0) / speeds[w]
        end = start + d
        done_at[(k, c)] = end
        if c == cols - 1:
            end += decides.get(k, 0.0) / speeds[w]
            band_done[k] = end
            while low < bands and band_done[low] is not None:
                low += 1
        next_col[k] = c + 1
        remaining -= 1
        heapq.heappush(free, (end, w))
    return max(list(done_at.values()) + [b for b in band_done if b is not None] + [0.0])


def split_fill(items):
    """A fill round walked whole by one worker ("fill triangles" over a..b)
    is shared in chunks of c triangles when it has two or more: its time is
    split in proportion."""
    out = []
    for i in items:
        a, b, c = i["args"].get("a", 0), i["args"].get("b", 0), i["args"].get("c", 0)
        if i["name"] == "fill triangles" and c > 0 and b - a > c:
            parts = (b - a + c - 1) // c
            out += [dict(i, dur=i["dur"] * min(c, b - a - k * c) / (b - a)) for k in range(parts)]
        else:
            out.append(i)
    return out


def chunks(items, extra, workers, speeds=None):
    """Independent items handed out in order to the first free worker."""
    items = split_fill(items)
    speeds = speeds or [1.0] * workers
    free = [(0.0, w) for w in range(workers)]
    heapq.heapify(free)
    for d in ([extra] if extra > 0 else []) + [i["dur"] for i in items]:
        t, w = heapq.heappop(free)
        heapq.heappush(free, (t + d / speeds[w], w))
    return max(t for t, _ in free)


def predict(frame, workers, speeds=None):
    """Per stage and in total, the predicted frame on `workers` workers (us);
    the serial parts run on worker 0 (speeds[0])."""
    speeds = speeds or [1.0] * workers
    stages = {}
    even = set()
    for r in frame["runs"]:
        tiles = [i for i in r["items"] if i["name"] == "path tile"]
        if tiles:
            p = tiles[0]["args"]["a"]
            cols, lead = frame["plans"][p]
            decides = {i["args"]["a"]: i["dur"] for i in r["items"] if i["name"] == "decide band"}
            covered = sum(i["dur"] for i in tiles) + sum(decides.values())
            t = wavefront(tiles, decides, cols, lead, workers, speeds) + max(0.0, r["dur"] - covered) / speeds[0]
        elif r["items"]:
            covered = sum(i["dur"] for i in r["items"])
            t = chunks(r["items"], max(0.0, r["dur"] - covered), workers, speeds)
        else:
            t = r["dur"] / sum(speeds)
            even.add(r["stage"])
        stages[r["stage"]] = stages.get(r["stage"], 0.0) + t
    for (stage, _), items in frame["loose"].items():
        stages[stage] = stages.get(stage, 0.0) + chunks(items, 0.0, workers, speeds)
    # What a stage spent outside runs and items (the caller's serial steps)
    # stays on one worker, counted in that stage; so do the gaps between stages.
    spans = [st for st in frame["stages"] if st["name"] in STAGES]
    within = lambda o, st: o is not st and st["ts"] <= o["ts"] + 1e-3 and o["ts"] + o["dur"] <= st["ts"] + st["dur"] + 1e-3
    own = {}
    for st in spans:
        inner = sum(o["dur"] for o in spans if within(o, st) and not any(within(o, m) for m in spans if within(m, st)))
        own[st["name"]] = own.get(st["name"], 0.0) + st["dur"] - inner
    used = {}
    for r in frame["runs"]:
        used[r["stage"]] = used.get(r["stage"], 0.0) + r["dur"]
    for (stage, _), items in frame["loose"].items():
        used[stage] = used.get(stage, 0.0) + sum(i["dur"] for i in items)
    for name, t in own.items():
        stages[name] = stages.get(name, 0.0) + max(0.0, t - used.get(name, 0.0)) / speeds[0]
    top = [st for st in spans if not any(within(st, m) for m in spans)]
    serial = max(0.0, frame["dur"] - sum(st["dur"] for st in top)) / speeds[0]
    total = serial + sum(stages.values())
    return total, stages, even


def median_frame(frames):
    """One frame whose every duration is the median over frames of the same
    pair (the same items in the same order): a span that another process
    preempted in one frame does not count as the item's own cost."""
    first = frames[0]
    shape = lambda f: ([len(r["items"]) for r in f["runs"]], sorted((k, len(v)) for k, v in f["loose"].items()),
                       len(f["stages"]))
    if any(shape(f) != shape(first) for f in frames[1:]):
        sys.exit("scaling_model: --same-frames, but the frames differ in their runs or items")
    med = lambda xs: statistics.median(xs)
    out = {"dur": med([f["dur"] for f in frames]), "plans": first["plans"], "stages": [], "runs": [], "loose": {}}
    for j, st in enumerate(first["stages"]):
        out["stages"].append(dict(st, dur=med([f["stages"][j]["dur"] for f in frames])))
    for j, r in enumerate(first["runs"]):
        items = [dict(it, dur=med([f["runs"][j]["items"][m]["dur"] for f in frames])) for m, it in enumerate(r["items"])]
        out["runs"].append(dict(r, dur=med([f["runs"][j]["dur"] for f in frames]), items=items))
    for k, items in first["loose"].items():
        out["loose"][k] = [dict(it, dur=med([f["loose"][k][m]["dur"] for f in frames])) for m, it in enumerate(items)]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace", help="a one-worker trace (tristereo profile --threads 1 --trace FILE)")
    ap.add_argument("--measured", help="a trace of the same frames on more workers, to compare with")
    ap.add_argument("--workers", default="1,2,4,8,16", help="worker counts to predict (default 1,2,4,8,16)")
    ap.add_argument("--slow", type=float, metavar="S",
                    help="also predict each count with its last worker at speed S (e.g. 0.5: a core half as fast, "
                         "an A55 beside A76s) beside the ideal, the work of N - 1 + S equal workers")
    ap.add_argument("--same-frames", action="store_true",
                    help="the trace's frames are one pair repeated (profile --left/--right): replay one frame "
                         "whose every duration is the median over them")
    args = ap.parse_args()
    events, workers = load(args.trace)
    if workers != 1:
        sys.exit(f"scaling_model: {args.trace} was recorded with {workers} workers; give a one-worker trace")
    frames = frames_of(events)
    if not frames:
        sys.exit(f"scaling_model: {args.trace} holds no frame")
    if args.same_frames:
        frames = [median_frame(frames)]
    counts = [int(x) for x in args.workers.split(",")]
    rows = {}
    even = set()
    for n in counts:
        totals, per_stage = [], {}
        for f in frames:
            total, stages, ev = predict(f, n)
            even |= ev
            totals.append(total)
            for s, t in stages.items():
                per_stage.setdefault(s, []).append(t)
        rows[n] = (statistics.median(totals), {s: statistics.median(v) for s, v in per_stage.items()})
    base_total, base_stages = rows[counts[0]] if counts[0] == 1 else predict(frames[0], 1)[:2]
    print(f"scaling model: {len(frames)} frame(s) of {args.trace}, medians in ms (speed-up over 1 worker)")
    names = [s for s in STAGES + ["other"] if s in base_stages]
    header = f"{'workers':>8} {'frame':>15}" + "".join(f" {s:>17}" for s in names)
    print(header)
    for n in counts:
        total, st = rows[n]
        line = f"{n:>8} {total / 1000:8.2f} ({base_total / total:4.2f}x)"
        for s in names:
            line += f" {st[s] / 1000:8.2f} ({base_stages[s] / st[s]:5.2f}x)" if st.get(s) else f" {'':>17}"
        print(line)
    if even:
        print("runs without work items, taken to divide evenly: " + ", ".join(sorted(even)))
    if args.slow:
        print(f"one worker at speed {args.slow}: predicted frame, and against the ideal "
              f"(1-worker frame / (N - 1 + {args.slow}))")
        for n in counts:
            if n < 2:
                continue
            speeds = [1.0] * (n - 1) + [args.slow]
            slow = statistics.median(predict(f, n, speeds)[0] for f in frames)
            ideal = base_total / (n - 1 + args.slow)
            even_n = rows[n][0]
            print(f"{n:>8} {slow / 1000:8.2f} ms; all at full speed {even_n / 1000:.2f} ms; "
                  f"ideal {ideal / 1000:.2f} ms; slow / ideal = {slow / ideal:.2f}")
    if args.measured:
        m_events, m_workers = load(args.measured)
        m_frames = frames_of(m_events)
        measured = statistics.median(f["dur"] for f in m_frames)
        predicted = rows[m_workers][0] if m_workers in rows else statistics.median(
            predict(f, m_workers)[0] for f in frames)
        print(f"measured on {m_workers} workers: {measured / 1000:.2f} ms (median of {len(m_frames)} frames); "
              f"predicted {predicted / 1000:.2f} ms: prediction / measured = {predicted / measured:.3f}")


if __name__ == "__main__":
    main()
