#!/usr/bin/env python3
"""Predicts a frame's time on N workers from one-worker frame traces.

    tristereo profile --threads 1 --trace t1.json --trace-frames 10 [pair and model options]
    tristereo profile --threads 1 --schedule-workers 4 --trace t4.json ...   (and 8, 16)
    tristereo profile --threads 2 --trace m2.json ...
    tristereo profile --threads 2 --trace c2.json ...   (another run, for --contention)
    scripts/scaling_model.py t1.json t4.json t8.json t16.json --measured m2.json --contention c2.json

A trace (docs/profiling.md) holds, per frame, the stages on the pipeline
track and, on the worker's track, every ThreadPool run and the work items it
took with their durations. The path passes are cut into work items for the
workers the frame was planned for (`--schedule-workers`, default the worker
count; up to two workers the cut is the same), so each worker count N >= 3 is
predicted from a one-worker trace cut for N. Each frame is replayed on N
workers by a list scheduler:

- the time of a frame outside every run (the caller's serial steps) stays
  serial;
- the path run ("path tile" items, args pass/band/tile) is two wavefronts at
  once (src/aggregate/path_matcher.cpp): a tile waits for the tile before it
  in its band, for the band above to be `lead` tiles ahead, and for the band
  N / 2 + 2 bands back to be done (from 3 workers on; 1 up to 2); a band of rows is started by the first pass to
  reach it, the other pass starts it once the first has done it; a free
  worker takes the ready tile of the lowest band of its own pass (even
  workers forward, odd ones backward), else of the other pass (unless the
  passes are cut into whole rows: up to two workers); a band's
  decision ("decide band") follows its last tile on the same worker;
- a run with other items (rows of costs, rows of the tritree's tiles, rows of
  interpolation tiles, a fill round's walk split in its chunks) hands them out
  in order to whichever worker is free (WorkChunks); the run's time outside
  its items (e.g. the side task the first worker takes) is one more item;
- a run without items (the right rows' preparation) is taken to divide
  evenly: such runs are listed as "even" in the report.

By itself the model knows nothing of memory bandwidth or caches: where a
measured frame is slower than the prediction, the difference is what the
workers cost each other in the memory system. `--contention C2` measures
that cost on this machine: per stage and kind of work item, the items' time
in a frame of a two-worker trace (C2, recorded apart from the --measured
one) over their time in the one-worker trace (medians over the frames). Two
path passes that stream their costs and sums at once, for instance, take
longer per tile than one. The prediction is then made again with each work
item's duration multiplied by its factor f at 2 workers and, for N workers,
by 1 + (f - 1)(N - 1) where f > 1 (each further worker streaming at once
costs what the second one did: this machine's memory system shared by N
workers, not a bigger machine's), f itself where f <= 1 (items that gain
from caches split between cores gain no more). Serial steps are not scaled.
The census costs' rows are the reference: they measured 0.94-1.04 on quiet
two-worker traces here (compute-bound), so their factor in the calibration is
taken as other processes' share of the cores at that time and divided out of
every kind's (the comparison with --measured also shows it put back).
"""
import argparse
import heapq
import json
import statistics
import sys

STAGES = ["tritree", "costs", "paths", "row dp", "support prior", "right pass", "fill", "interpolation"]
# The contention's reference: work items that do not contend in the memory
# system here, so that their slowdown on two workers is the machine's load.
REFERENCE_KIND = ("costs", "cost rows")


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
    inline), grouped by stage, kind and (the tritree's rows) phase."""
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
            # Each item's gap: the time since the run's previous item (or its
            # start), in which the worker claimed it.
            end = r0
            for e in items:
                e["gap"] = max(0.0, e["ts"] - end)
                end = max(end, e["ts"] + e["dur"])
            runs.append({"start": r0, "dur": r["dur"], "items": items, "stage": stage_of(stages, r0, r1)})
        for e in w0:
            if e["name"] == "run" or not inside(e, t0, t1):
                continue
            if any(inside(e, r["ts"], r["ts"] + r["dur"]) for r in run_spans):
                continue
            # The tritree's phases follow one another on a pool (each waits
            # for the one before): a group each.
            phase = e["args"].get("a", 0) if e["name"] == "tritree rows" else 0
            key = (stage_of(stages, e["ts"], e["ts"] + e["dur"]), e["name"], phase)
            loose.setdefault(key, []).append(e)
        plan = None
        for st in stages:
            if st["name"] == "paths":
                plan = (st["args"]["a"], st["args"]["b"] & 255, st["args"]["b"] >> 8)  # cols, leads
        frames.append({"dur": f["dur"], "stages": stages, "runs": runs, "loose": loose, "plan": plan,
                       "schedule": f["args"].get("b", 1)})
    return frames


def paths_run(tiles, decides, plan, workers, speeds=None):
    """Makespan of the two path passes' tiles on `workers` workers;
    speeds[w]: worker w's speed against the traced one (default 1)."""
    cols, leads = plan[0], (plan[1], plan[2])
    speeds = speeds or [1.0] * workers
    in_flight = 1 if workers <= 2 else workers // 2 + 2  # path_matcher.cpp bands_in_flight
    # A one-worker trace runs the forward pass first on every band and the
    # backward pass second (it adds to S, and decides): a tile's time is taken
    # by its pass, at its place (band of image rows, tile in image x order),
    # whichever role it gets in the replay. Its pass, not its role, sets it:
    # at D = 128 a backward tile took 2.3x a forward one in a one-worker trace
    # of the synthetic 640x480 frame, and in a two-worker trace, where the
    # roles change halfway down, each pass's tiles still took 0.90-0.96x
    # their one-worker time (the 2.3x is the backward direction's).
    keys = [set(), set()]
    for t in tiles:
        keys[t["args"]["a"]].add((t["args"]["b"], t["args"]["c"]))
    bands = 1 + max(b for p in (0, 1) for b, _ in keys[p])
    image_band = lambda p, k: k if p == 0 else bands - 1 - k
    image_col = lambda p, c: c if p == 0 else cols - 1 - c
    pass_dur = ({}, {})  # forward, backward
    for t in tiles:
        p, k, c = t["args"]["a"], t["args"]["b"], t["args"]["c"]
        pass_dur[p][(image_band(p, k), image_col(p, c))] = t["dur"]
    dur = [{key: None for key in keys[0]}, {key: None for key in keys[1]}]
    done_at = [{}, {}]
    band_done = [[None] * bands, [None] * bands]
    next_col = [[0] * bands, [0] * bands]
    low = [0, 0]
    first = [None] * bands  # the pass that started each band of rows first
    free = [(0.0, w) for w in range(workers)]
    heapq.heapify(free)
    remaining = len(dur[0]) + len(dur[1])
    end_all = 0.0

    def ready_time(p, k):
        c = next_col[p][k]
        if c >= cols:
            return None
        deps = []
        if c > 0:
            deps.append(done_at[p].get((k, c - 1)))
        if k > 0:
            deps.append(done_at[p].get((k - 1, min(cols - 1, c + leads[p]))))
        if c == 0:
            if k >= in_flight:
                deps.append(band_done[p][k - in_flight])
            j = image_band(p, k)
            if first[j] is not None and first[j] != p:
                deps.append(band_done[1 - p][image_band(1 - p, j)])
        if any(d is None for d in deps):
            return None
        return max(deps, default=0.0)

    while remaining:
        t, w = heapq.heappop(free)
        own = w % 2
        best = None
        # A pass cut into whole rows is one chain: with two or more workers,
        # each keeps to its own pass (path_matcher.cpp).
        for p in ((own, 1 - own) if workers == 1 or cols > 1 else (own,)):
            for k in range(low[p], min(bands, low[p] + in_flight)):
                r = ready_time(p, k)
                if r is None:
                    continue
                start = max(t, r)
                if best is None or start < best[2] - 1e-9:
                    best = (p, k, start)
                if r <= t:
                    break
            if best is not None and best[2] <= t:
                break
        if best is None:
            # Nothing this worker may take can start before another worker
            # finishes a tile: wait for the next one to (or stop, when its
            # passes are done).
            passes = (own, 1 - own) if workers == 1 or cols > 1 else (own,)
            if all(low[p] >= bands for p in passes):
                continue
            later = [x for x, _ in free if x > t]
            if not later:
                raise RuntimeError("scaling_model: no tile can start")
            heapq.heappush(free, (min(later), w))
            continue
        p, k, start = best
        c = next_col[p][k]
        if c == 0 and first[image_band(p, k)] is None:
            first[image_band(p, k)] = p
        j = image_band(p, k)
        end = start + pass_dur[p].get((j, image_col(p, c)), 0.0) / speeds[w]
        done_at[p][(k, c)] = end
        next_col[p][k] = c + 1
        if c == cols - 1:
            band_done[p][k] = end
            j = image_band(p, k)
            if first[j] != p:  # the second pass decides the band
                end += decides.get(j, 0.0) / speeds[w]
            while low[p] < bands and band_done[p][low[p]] is not None:
                low[p] += 1
        remaining -= 1
        end_all = max(end_all, end)
        heapq.heappush(free, (end, w))
    return end_all


def split_fill(items):
    """A fill round walked whole by one worker ("fill items" over a..b)
    is shared in chunks of c triangles when it has two or more: its time is
    split in proportion."""
    out = []
    for i in items:
        a, b, c = i["args"].get("a", 0), i["args"].get("b", 0), i["args"].get("c", 0)
        if i["name"] == "fill items" and c > 0 and b - a > c:
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


def contention_at(factor, workers):
    """An item's slowdown on `workers` workers from its factor measured on 2
    (the module's docstring)."""
    if workers < 2:
        return 1.0
    if factor <= 1.0 or workers == 2:
        return factor
    return 1.0 + (factor - 1.0) * (workers - 1)


def item_times(frame):
    """Per (stage, item kind): the items' summed time in a one-worker frame
    (frames_of) (us)."""
    out = {}
    for r in frame["runs"]:
        for i in r["items"]:
            key = (r["stage"], i["name"])
            out[key] = out.get(key, 0.0) + i["dur"]
    for (stage, name, _), items in frame["loose"].items():
        out[(stage, name)] = out.get((stage, name), 0.0) + sum(i["dur"] for i in items)
    return out


def item_times_per_frame(events):
    """Per frame of a trace on any number of workers: per (stage, item kind)
    the items' summed time over every worker (us)."""
    pipe = [e for e in events if e["tid"] == 0]
    items = [e for e in events if e["tid"] >= 1 and e["name"] != "run"]
    out = []
    for f in (e for e in pipe if e["name"] == "frame"):
        t0, t1 = f["ts"], f["ts"] + f["dur"]
        stages = [e for e in pipe if e["name"] != "frame" and e["ts"] >= t0 - 1e-3 and e["ts"] + e["dur"] <= t1 + 1e-3]
        times = {}
        for i in items:
            if i["ts"] >= t0 - 1e-3 and i["ts"] + i["dur"] <= t1 + 1e-3:
                key = (stage_of(stages, i["ts"], i["ts"] + i["dur"]), i["name"])
                times[key] = times.get(key, 0.0) + i["dur"]
        out.append(times)
    return out


def contention_factors(one_worker_frames, two_worker_events):
    """Per (stage, item kind): the median over frames of the items' time on
    two workers over their median on one (only kinds both traces hold)."""
    one = [item_times(f) for f in one_worker_frames]
    two = item_times_per_frame(two_worker_events)
    factors = {}
    for key in set().union(*one) & set().union(*two):
        t1 = statistics.median(t.get(key, 0.0) for t in one)
        t2 = statistics.median(t.get(key, 0.0) for t in two)
        if t1 > 0 and t2 > 0:
            factors[key] = t2 / t1
    return factors


def slowed(frame, factors, workers):
    """The frame with every work item's duration multiplied by its kind's
    contention on `workers` workers (runs keep their time outside items)."""
    if not factors:
        return frame
    scale = lambda stage, i: dict(i, dur=i["dur"] * contention_at(factors.get((stage, i["name"]), 1.0), workers))
    runs = []
    for r in frame["runs"]:
        items = [scale(r["stage"], i) for i in r["items"]]
        outside = r["dur"] - sum(i["dur"] for i in r["items"])
        runs.append(dict(r, items=items, dur=outside + sum(i["dur"] for i in items)))
    loose = {k: [scale(k[0], i) for i in v] for k, v in frame["loose"].items()}
    return dict(frame, runs=runs, loose=loose)


def predict(frame, workers, speeds=None, factors=None):
    """Per stage and in total, the predicted frame on `workers` workers (us);
    the serial parts run on worker 0 (speeds[0]). factors: the memory
    contention per (stage, item kind) measured on two workers (none: no
    contention)."""
    speeds = speeds or [1.0] * workers
    stages = {}
    even = set()
    base = frame
    frame = slowed(frame, factors, workers)
    for r in frame["runs"]:
        tiles = [i for i in r["items"] if i["name"] == "path tile"]
        if tiles:
            # A tile's or decision's gap goes with it: every worker claims its
            # own (in a one-worker trace cut for 16, 30 ns a tile, 0.24 ms a
            # frame); the rest of the run stays serial.
            tiles = [dict(i, dur=i["dur"] + i.get("gap", 0.0)) for i in tiles]
            decides = {i["args"]["a"]: i["dur"] + i.get("gap", 0.0) for i in r["items"] if i["name"] == "decide band"}
            covered = sum(i["dur"] for i in tiles) + sum(decides.values())
            t = paths_run(tiles, decides, frame["plan"], workers, speeds) + max(0.0, r["dur"] - covered) / speeds[0]
        elif r["items"]:
            covered = sum(i["dur"] for i in r["items"])
            t = chunks(r["items"], max(0.0, r["dur"] - covered), workers, speeds)
        else:
            t = r["dur"] / sum(speeds)
            even.add(r["stage"])
        stages[r["stage"]] = stages.get(r["stage"], 0.0) + t
    for (stage, _, _), items in frame["loose"].items():
        stages[stage] = stages.get(stage, 0.0) + chunks(items, 0.0, workers, speeds)
    # What a stage spent outside runs and items (the caller's serial steps)
    # stays on one worker, counted in that stage; so do the gaps between stages.
    spans = [st for st in frame["stages"] if st["name"] in STAGES]
    within = lambda o, st: o is not st and st["ts"] <= o["ts"] + 1e-3 and o["ts"] + o["dur"] <= st["ts"] + st["dur"] + 1e-3
    own = {}
    for st in spans:
        inner = sum(o["dur"] for o in spans if within(o, st) and not any(within(o, m) for m in spans if within(m, st)))
        own[st["name"]] = own.get(st["name"], 0.0) + st["dur"] - inner
    used = {}  # from the frame as traced: the stage's time outside runs and items stays as it was
    for r in base["runs"]:
        used[r["stage"]] = used.get(r["stage"], 0.0) + r["dur"]
    for (stage, _, _), items in base["loose"].items():
        used[stage] = used.get(stage, 0.0) + sum(i["dur"] for i in items)
    for name, t in own.items():
        stages[name] = stages.get(name, 0.0) + max(0.0, t - used.get(name, 0.0)) / speeds[0]
    top = [st for st in spans if not any(within(st, m) for m in spans)]
    serial = max(0.0, frame["dur"] - sum(st["dur"] for st in top)) / speeds[0]
    total = serial + sum(stages.values())
    return total, stages, even


def median_frame(frames):
    """One frame whose every part is the median over frames of the same pair
    (the same items in the same order): each item's duration, each run's time
    outside its items, each stage's time outside its runs and items, the gaps
    between stages. An item that another process preempted in one frame does
    not count as the item's own cost."""
    first = frames[0]
    shape = lambda f: ([len(r["items"]) for r in f["runs"]], sorted((k, len(v)) for k, v in f["loose"].items()),
                       [st["name"] for st in f["stages"]])
    if any(shape(f) != shape(first) for f in frames[1:]):
        sys.exit("scaling_model: --same-frames, but the frames differ in their runs, items or stages")
    med = statistics.median
    out = {"plan": first["plan"], "schedule": first["schedule"], "stages": [], "runs": [], "loose": {}}
    for j, r in enumerate(first["runs"]):
        items = [dict(it, dur=med([f["runs"][j]["items"][m]["dur"] for f in frames]),
                      gap=med([f["runs"][j]["items"][m]["gap"] for f in frames])) for m, it in enumerate(r["items"])]
        rest = med([f["runs"][j]["dur"] - sum(i["dur"] for i in f["runs"][j]["items"]) for f in frames])
        out["runs"].append(dict(r, dur=sum(i["dur"] for i in items) + rest, items=items))
    for k, items in first["loose"].items():
        out["loose"][k] = [dict(it, dur=med([f["loose"][k][m]["dur"] for f in frames])) for m, it in enumerate(items)]
    # A stage: the median of its own time (outside its runs and loose items)
    # plus its runs' and items' median times.
    for j, st in enumerate(first["stages"]):
        def inner(f, st_f):
            t0, t1 = st_f["ts"], st_f["ts"] + st_f["dur"]
            runs = sum(r["dur"] for r in f["runs"] if r["start"] >= t0 - 1e-3 and r["start"] + r["dur"] <= t1 + 1e-3)
            loose = sum(i["dur"] for v in f["loose"].values() for i in v
                        if i["ts"] >= t0 - 1e-3 and i["ts"] + i["dur"] <= t1 + 1e-3)
            return runs + loose
        own = med([f["stages"][j]["dur"] - inner(f, f["stages"][j]) for f in frames])
        out["stages"].append(dict(st, dur=own + inner(out, dict(st, dur=first["stages"][j]["dur"]))
                                  if False else own))
        out["stages"][-1]["_own"] = own
    # Rebuild the stage durations from the median parts, on frame 0's timeline
    # (containment only uses frame 0's times).
    for j, st in enumerate(out["stages"]):
        t0, t1 = first["stages"][j]["ts"], first["stages"][j]["ts"] + first["stages"][j]["dur"]
        runs = sum(r["dur"] for r in out["runs"] if r["start"] >= t0 - 1e-3 and r["start"] + r["dur"] <= t1 + 1e-3)
        loose = sum(i["dur"] for v in out["loose"].values() for i in v
                    if i["ts"] >= t0 - 1e-3 and i["ts"] + i["dur"] <= t1 + 1e-3)
        st["dur"] = st.pop("_own") + runs + loose
        st["ts"] = first["stages"][j]["ts"]
    gaps = med([f["dur"] - sum(st["dur"] for st in f["stages"] if not any(
        o is not st and o["ts"] <= st["ts"] + 1e-3 and st["ts"] + st["dur"] <= o["ts"] + o["dur"] + 1e-3
        for o in f["stages"])) for f in frames])
    top = [st for st in out["stages"] if not any(
        o is not st and o["ts"] <= st["ts"] + 1e-3 and st["ts"] + st["dur"] <= o["ts"] + o["dur"] + 1e-3
        for o in first["stages"])]
    out["dur"] = gaps + sum(st["dur"] for st in top)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("traces", nargs="+",
                    help="one-worker traces: the first cut for 1 worker (tristereo profile --threads 1 --trace FILE), "
                         "the others cut for N workers (--schedule-workers N)")
    ap.add_argument("--measured", help="a trace of the same frames on 2 (or more) workers, to compare with")
    ap.add_argument("--contention", metavar="C2",
                    help="another two-worker trace of the same frames: the memory contention per stage and kind of "
                         "work item, applied to a second prediction (see above)")
    ap.add_argument("--slow", type=float, metavar="S",
                    help="also predict each count with its last worker at speed S (e.g. 0.5: a core half as fast, "
                         "an A55 beside A76s) beside the ideal, the work of N - 1 + S equal workers")
    ap.add_argument("--same-frames", action="store_true",
                    help="the traces' frames are one pair repeated (profile --left/--right): replay one frame "
                         "whose every duration is the median over them")
    args = ap.parse_args()
    per_count = {}  # workers -> frames cut for them
    for path in args.traces:
        events, workers = load(path)
        if workers != 1:
            sys.exit(f"scaling_model: {path} was recorded with {workers} workers; give one-worker traces")
        frames = frames_of(events)
        if not frames:
            sys.exit(f"scaling_model: {path} holds no frame")
        if args.same_frames:
            frames = [median_frame(frames)]
        schedule = frames[0]["schedule"]
        for n in ([1, 2] if schedule <= 2 else [schedule]):
            per_count.setdefault(n, frames)
    if 1 not in per_count:
        sys.exit("scaling_model: the first trace must be cut for one worker (no --schedule-workers)")

    factors, measured_factors, outside_load = {}, {}, 1.0
    if args.contention:
        c_events, c_workers = load(args.contention)
        if c_workers != 2:
            sys.exit(f"scaling_model: {args.contention} was recorded with {c_workers} workers; --contention takes 2")
        measured_factors = contention_factors(per_count[1], c_events)
        # The census costs' rows are compute-bound here (factor 0.94-1.04 in
        # quiet two-worker traces): a factor above 1 there is another process
        # taking the cores during the calibration, not the memory system, and
        # every kind is divided by it.
        outside_load = max(1.0, measured_factors.get(REFERENCE_KIND, 1.0))
        factors = {k: f / outside_load for k, f in measured_factors.items()}

    def median_prediction(n, speeds=None, with_factors=None):
        preds = [predict(f, n, speeds, with_factors) for f in per_count[n]]
        stages = {}
        for _, st, _ in preds:
            for k, v in st.items():
                stages.setdefault(k, []).append(v)
        even = set().union(*(e for _, _, e in preds))
        return statistics.median(t for t, _, _ in preds), {k: statistics.median(v) for k, v in stages.items()}, even

    counts = sorted(per_count)
    rows = {n: median_prediction(n) for n in counts}
    base_total, base_stages, _ = rows[1]
    names = [s for s in STAGES + ["other"] if s in base_stages]

    def table(title, rows):
        print(title)
        print(f"{'workers':>8} {'frame':>15}" + "".join(f" {s:>17}" for s in names))
        even = set()
        for n in counts:
            total, st, ev = rows[n]
            even |= ev
            line = f"{n:>8} {total / 1000:8.2f} ({base_total / total:4.2f}x)"
            for s in names:
                line += f" {st[s] / 1000:8.2f} ({base_stages[s] / st[s]:5.2f}x)" if st.get(s) else f" {'':>17}"
            print(line)
        if even:
            print("runs without work items, taken to divide evenly: " + ", ".join(sorted(even)))

    table("scaling model: medians in ms (speed-up over 1 worker); N >= 3 from the traces cut for N", rows)
    slowed_rows = {}
    if factors:
        print("memory contention measured on 2 workers (items' time on 2 workers / on 1), per stage and item kind: " +
              ", ".join(f"{st} {kind} {f:.2f}" for (st, kind), f in sorted(measured_factors.items())))
        if outside_load > 1.0:
            print(f"  of which other processes (the {REFERENCE_KIND[1]}' factor, compute-bound): {outside_load:.2f}; "
                  "the memory system's: " + ", ".join(f"{st} {kind} {f:.2f}" for (st, kind), f in sorted(factors.items())))
        slowed_rows = {n: median_prediction(n, with_factors=factors) for n in counts}
        table("with that contention (N workers: 1 + (f - 1)(N - 1) where f > 1; this machine's memory system)",
              slowed_rows)
    if args.slow:
        print(f"one worker at speed {args.slow}: predicted frame, and against the ideal "
              f"(1-worker frame / (N - 1 + {args.slow})){'; with contention after /' if factors else ''}")
        for n in counts:
            if n < 2:
                continue
            ideal = base_total / (n - 1 + args.slow)
            line = ""
            for f, r in [(None, rows)] + ([(factors, slowed_rows)] if factors else []):
                slow = median_prediction(n, [1.0] * (n - 1) + [args.slow], f)[0]
                line += (" / " if line else "") + (f"{slow / 1000:8.2f} ms; all at full speed {r[n][0] / 1000:.2f} ms; "
                                                  f"ideal {ideal / 1000:.2f} ms; slow / ideal = {slow / ideal:.2f}")
            print(f"{n:>8} {line}")
    if args.measured:
        m_events, m_workers = load(args.measured)
        m_frames = frames_of(m_events)
        measured = statistics.median(f["dur"] for f in m_frames)
        if m_workers not in rows:
            sys.exit(f"scaling_model: no trace cut for {m_workers} workers to compare {args.measured} with")
        predicted = rows[m_workers][0]
        line = (f"measured on {m_workers} workers: {measured / 1000:.2f} ms (median of {len(m_frames)} frames); "
                f"predicted {predicted / 1000:.2f} ms: prediction / measured = {predicted / measured:.3f}")
        if factors:
            p2 = slowed_rows[m_workers][0]
            line += f"; with contention {p2 / 1000:.2f} ms: {p2 / measured:.3f}"
            if outside_load > 1.0 and m_workers == 2:
                p2l = median_prediction(2, with_factors=measured_factors)[0]
                line += f"; with the calibration's other processes too {p2l / 1000:.2f} ms: {p2l / measured:.3f}"
        print(line)


if __name__ == "__main__":
    main()
