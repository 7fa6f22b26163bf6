#!/usr/bin/env python3
"""Draws one frame of a `tristereo profile --trace` file: a row per worker
with its work items coloured by kind, the stages above them.

    scripts/plot_trace.py trace.json -o frame.png [--frame K] [--title T]

The same file opens in Perfetto (ui.perfetto.dev) or chrome://tracing for
zooming; this picture is for documents. Needs matplotlib
(scripts/install-deps.sh plot).
"""
import argparse
import json
import sys

COLOURS = {
    "tritree rows": "#4c72b0", "cost rows": "#dd8452", "path tile": "#55a868", "decide band": "#c44e52",
    "interpolation tiles": "#8172b3", "fill items": "#da8bc3", "run": "#d0d0d0",
    "prior segments": "#8c8c8c", "prior samples": "#64b5cd",
}
STAGE_COLOURS = {
    "tritree": "#4c72b0", "costs": "#dd8452", "paths": "#55a868",
    "row dp": "#55a868", "support prior": "#ccb974", "right pass": "#937860", "fill": "#da8bc3",
    "interpolation": "#8172b3",
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--frame", type=int, default=-1, help="which traced frame (default the last)")
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.patches import Patch
    except ImportError:
        sys.exit("plot_trace: needs matplotlib (scripts/install-deps.sh plot)")
    with open(args.trace) as f:
        data = json.load(f)
    workers = data["otherData"]["workers"]
    spans = [e for e in data["traceEvents"] if e.get("ph") == "X"]
    frames = sorted((e for e in spans if e["tid"] == 0 and e["name"] == "frame"), key=lambda e: e["ts"])
    if not frames:
        sys.exit("plot_trace: no frame in the trace")
    fr = frames[args.frame]
    t0, t1 = fr["ts"], fr["ts"] + fr["dur"]
    inside = [e for e in spans if e["ts"] >= t0 - 1e-3 and e["ts"] + e["dur"] <= t1 + 1e-3]
    ms = lambda us: (us - t0) / 1000.0
    fig, ax = plt.subplots(figsize=(12, 1.2 + 0.55 * (workers + 1)))
    # Stages on top (row 0), workers below (row w + 1): runs as a grey band,
    # items over them.
    for e in inside:
        if e["tid"] == 0 and e["name"] in STAGE_COLOURS:
            ax.broken_barh([(ms(e["ts"]), e["dur"] / 1000.0)], (0.1, 0.8), color=STAGE_COLOURS[e["name"]])
    for e in inside:
        if e["tid"] >= 1:
            y = e["tid"]
            if e["name"] == "run":
                ax.broken_barh([(ms(e["ts"]), e["dur"] / 1000.0)], (y + 0.05, 0.9), color=COLOURS["run"])
    for e in inside:
        if e["tid"] >= 1 and e["name"] != "run":
            ax.broken_barh([(ms(e["ts"]), e["dur"] / 1000.0)], (e["tid"] + 0.15, 0.7),
                           color=COLOURS.get(e["name"], "#999999"), linewidth=0)
    ax.set_ylim(workers + 1, 0)
    ax.set_yticks([0.5] + [w + 1.5 for w in range(workers)])
    ax.set_yticklabels(["stages"] + [f"worker {w}" for w in range(workers)])
    ax.set_xlim(0, (t1 - t0) / 1000.0)
    ax.set_xlabel("ms from the frame's start")
    legend = [Patch(color=c, label=n) for n, c in COLOURS.items()]
    legend += [Patch(color=c, label=n) for n, c in STAGE_COLOURS.items()
               if any(e["tid"] == 0 and e["name"] == n for e in inside)]
    ax.legend(handles=legend, loc="upper center", bbox_to_anchor=(0.5, -0.35), ncol=6, fontsize=8, frameon=False)
    ax.set_title(args.title or f"{args.trace}: frame of {fr['dur'] / 1000.0:.2f} ms on {workers} workers")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"plot_trace: wrote {args.output}")


if __name__ == "__main__":
    main()
