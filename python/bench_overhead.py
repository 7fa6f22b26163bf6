#!/usr/bin/python3
"""Per-call cost of the Python module beside OpenCV's matchers, on the same arrays.

For each call of Pipeline.process() the overhead is the wall time Python saw
minus the frame's own time (out.timings_ms["total"], measured by the library
around the frame): what the binding adds (argument checks, the lock, the GIL,
copying the output into NumPy arrays, BGR conversion), with fresh output
arrays per call and with out= (the last output's arrays filled again). cv2.StereoBM and
cv2.StereoSGBM (MODE_SGBM_3WAY) run on the same arrays for scale; everything
runs with one thread (cv2.setNumThreads(1), threads=1).

Usage: python/bench_overhead.py [--build BUILD] [--scene middlebury/teddy]
                                [--calls 200] [--warmup 20]
Needs the module built (PYTHONPATH or --build) and OpenCV's Python module
(Debian: python3-opencv). Prints one table in Markdown.
"""
import argparse
import os
import statistics
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def percentile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, int(round(q / 100 * (len(s) - 1))))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"), help="build tree with python/tristereo")
    ap.add_argument("--data", default=os.path.join(os.path.dirname(REPO), "shared", "data"))
    ap.add_argument("--scene", default="middlebury/teddy")
    ap.add_argument("--ndisp", type=int, default=64)
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=20)
    args = ap.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import cv2
    import numpy as np
    import tristereo

    cv2.setNumThreads(1)
    d = os.path.join(args.data, args.scene)
    bgr_l, bgr_r = cv2.imread(os.path.join(d, "left.png")), cv2.imread(os.path.join(d, "right.png"))
    if bgr_l is None or bgr_r is None:
        sys.exit(f"bench_overhead: cannot read {d}/left.png and right.png")
    gray_l, gray_r = cv2.cvtColor(bgr_l, cv2.COLOR_BGR2GRAY), cv2.cvtColor(bgr_r, cv2.COLOR_BGR2GRAY)
    h, w = gray_l.shape

    rows = []
    load = os.getloadavg()[0]

    t0 = time.perf_counter()
    p = tristereo.Pipeline(w, h, ndisp=args.ndisp, threads=1)
    configure_ms = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    first = p.process(bgr_l, bgr_r, order="bgr")
    first_ms = (time.perf_counter() - t0) * 1e3

    # The variants take turns call by call, so that a busy machine slows them alike.
    variants = [("tristereo gray (H, W)", gray_l, gray_r, None, False),
                ("tristereo gray (H, W), out= the last output", gray_l, gray_r, None, True),
                ("tristereo BGR (H, W, 3), order='bgr'", bgr_l, bgr_r, "bgr", False)]
    wall = [[] for _ in variants]
    frame = [[] for _ in variants]
    last = [None for _ in variants]
    for i in range(args.warmup + args.calls):
        for k, (_, left, right, order, reuse) in enumerate(variants):
            t = time.perf_counter()
            out = p.process(left, right, order=order, out=last[k] if reuse else None)
            last[k] = out
            ms = (time.perf_counter() - t) * 1e3
            if i >= args.warmup:
                wall[k].append(ms)
                frame[k].append(out.timings_ms["total"])
    for k, (name, *_) in enumerate(variants):
        over = [a - b for a, b in zip(wall[k], frame[k])]
        rows.append((name, statistics.median(wall[k]), percentile(wall[k], 90), statistics.median(frame[k]),
                     min(over), statistics.median(over), percentile(over, 90)))

    def time_cv(matcher, left, right):
        wall = []
        for i in range(args.warmup + args.calls):
            t = time.perf_counter()
            matcher.compute(left, right)
            if i >= args.warmup:
                wall.append((time.perf_counter() - t) * 1e3)
        return wall

    num_disp = (args.ndisp + 15) // 16 * 16
    bm = cv2.StereoBM_create(numDisparities=num_disp, blockSize=9)
    sgbm = cv2.StereoSGBM_create(minDisparity=0, numDisparities=num_disp, blockSize=5, P1=600, P2=2400,
                                 uniquenessRatio=10, speckleWindowSize=100, speckleRange=2, disp12MaxDiff=1,
                                 mode=cv2.STEREO_SGBM_MODE_SGBM_3WAY)
    for name, m, left, right in [("cv2.StereoBM.compute (gray, blockSize 9)", bm, gray_l, gray_r),
                                 ("cv2.StereoSGBM.compute (BGR, 3-way, blockSize 5)", sgbm, bgr_l, bgr_r)]:
        wall = time_cv(m, left, right)
        rows.append((name, statistics.median(wall), percentile(wall, 90), None, None, None, None))

    print(f"{args.scene} {w}x{h}, ndisp {args.ndisp}, one thread, {args.calls} calls after {args.warmup} "
          f"(tristereo {tristereo.__version__}, kernels {p.kernels}; OpenCV {cv2.__version__}, NumPy {np.__version__})")
    print(f"configure {configure_ms:.1f} ms, first frame {first_ms:.1f} ms (its own {first.timings_ms['total']:.1f} ms)")
    print()
    print(f"load average before the run: {load:.2f} on {os.cpu_count()} CPUs")
    print()
    print("| call | wall p50 ms | wall p90 ms | frame p50 ms | overhead min ms | overhead p50 ms | overhead p90 ms |")
    print("|---|--:|--:|--:|--:|--:|--:|")
    fmt = lambda v: "" if v is None else f"{v:.2f}"  # noqa: E731
    for r in rows:
        print(f"| {r[0]} | " + " | ".join(fmt(v) for v in r[1:]) + " |")


if __name__ == "__main__":
    main()
