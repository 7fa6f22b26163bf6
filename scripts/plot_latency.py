#!/usr/bin/python3
"""Latency histogram from the per-frame CSV of `tristereo profile --csv`.

    /usr/bin/python3 scripts/plot_latency.py frames.csv -o latency_hist.png [--title T]

Left panel: histogram of the total frame time with p50/p90/p99 marked (numpy's
default linear percentile, the definition the profiler uses, so the lines sit
on the numbers of its report). Right panel: every stage per frame, stacked,
to show whether slow frames come from one stage or from all of them (a
preempted frame is slow everywhere). Needs matplotlib and numpy (Debian:
python3-matplotlib); only the CSV module is used for reading.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display on a board or in CI
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_frames(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        sys.exit(f"{path}: empty file")
    header, body = rows[0], rows[1:]
    for needed in ("frame", "total_ms"):
        if needed not in header:
            sys.exit(f"{path}: no '{needed}' column (is this a `tristereo profile --csv` file?)")
    if not body:
        sys.exit(f"{path}: no frames")
    cols = {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}
    stages = [h for h in header if h.endswith("_ms") and h not in ("total_ms", "cpu_ms")]
    return cols, stages


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", help="per-frame CSV written by tristereo profile --csv")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    ap.add_argument("--title", default="", help="figure title (e.g. board, size, D)")
    ap.add_argument("--bins", type=int, default=40)
    args = ap.parse_args()

    cols, stages = read_frames(args.csv)
    total = cols["total_ms"]
    p50, p90, p99 = np.percentile(total, [50, 90, 99])

    fig, (ax_h, ax_t) = plt.subplots(1, 2, figsize=(11, 4), gridspec_kw={"width_ratios": [1, 1.4]})
    ax_h.hist(total, bins=args.bins, color="#4c72b0", edgecolor="white")
    for value, name, style in ((p50, "p50", "-"), (p90, "p90", "--"), (p99, "p99", ":")):
        ax_h.axvline(value, color="#c44e52", linestyle=style, label=f"{name} {value:.2f} ms")
    ax_h.set_xlabel("frame time [ms]")
    ax_h.set_ylabel("frames")
    ax_h.set_title(f"{len(total)} frames, mean {total.mean():.2f} ms")
    ax_h.legend(fontsize=8)

    frames = cols["frame"]
    ax_t.stackplot(frames, *[cols[s] for s in stages], labels=[s[:-3] for s in stages], alpha=0.85)
    ax_t.plot(frames, total, color="black", linewidth=0.7, label="total")
    if "cpu_ms" in cols:
        # Process CPU time: below the total when the frame waited (preempted,
        # other load) or above it when several workers ran in parallel.
        ax_t.plot(frames, cols["cpu_ms"], color="black", linewidth=0.7, linestyle="--", label="cpu")
    ax_t.set_xlabel("measured frame")
    ax_t.set_ylabel("ms")
    ax_t.set_xlim(frames[0], frames[-1] if len(frames) > 1 else frames[0] + 1)
    ax_t.legend(fontsize=8, loc="upper right", ncol=2)
    ax_t.set_title("stages per frame (stacked)")

    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print(f"{args.output}: p50 {p50:.3f} ms, p90 {p90:.3f} ms, p99 {p99:.3f} ms, "
          f"max {total.max():.3f} ms over {len(total)} frames")


if __name__ == "__main__":
    main()
