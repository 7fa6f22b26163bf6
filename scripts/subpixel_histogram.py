#!/usr/bin/python3
"""Pixel locking check: how the measured samples' sub-pixel fractions spread, per set of ../shared/data.

Usage: /usr/bin/python3 scripts/subpixel_histogram.py [--tristereo build/tristereo] [--data DIR]
                                                      [--sets a,b] [-- extra match options]

For each scene, `tristereo match ... --fill none --samples S.csv` (one thread): the samples
that kept a disparity are the measured ones. Their disparities are in 1/16 px, so the
fraction d - floor(d) falls in one of 16 bins (0, 1/16, ..., 15/16). A sub-pixel estimate
biased towards whole disparities ("pixel locking") piles the samples into bin 0 and its
neighbours, where the scenes' true disparities spread evenly (the float ground truths of
Middlebury 2014 and ETH3D at the same samples, rounded to 1/16 px, are shown beside; the
PNG ground truths of v2 and KITTI are not read here). Prints, per set (its scenes pooled), the
share of samples per bin in %, and the share in bin 0 and in bins 15, 0, 1 (within 1/16 px
of a whole disparity: 18.75 % when even).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import datasets  # noqa: E402  (scripts/datasets.py)


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind != b"Pf":
            raise ValueError("%s: not a gray PFM" % path)
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4", count=w * h)
    return data.reshape(h, w)[::-1]


def load_gt(scene):
    """Ground truth in px, NaN where unknown; None for PNG ground truths (v2, KITTI),
    whose fractions are not shown."""
    if scene.gt_format != "pfm":
        return None
    g = read_pfm(scene.gt).astype(np.float64)
    g[~np.isfinite(g) | (g == 0)] = np.nan
    return g


def measure(exe, scene, extra, tmp):
    csv = os.path.join(tmp, scene.id.replace("/", "_") + ".csv")
    cmd = [exe, "match", scene.left, scene.right, "--ndisp", str(scene.ndisp), "--threads", "1",
           "--fill", "none"] + extra + ["--samples", csv]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("subpixel_histogram: %s failed:\n%s" % (" ".join(cmd), r.stderr))
    xs, ys, ds = [], [], []
    with open(csv) as f:
        next(f)
        for line in f:
            x, y, d = line.strip().split(",")
            if d == "inf":
                continue
            xs.append(int(x))
            ys.append(int(y))
            ds.append(float(d))
    xs, ys, q4 = np.array(xs), np.array(ys), np.rint(np.array(ds) * 16).astype(np.int64)
    gt = load_gt(scene)
    if gt is None:
        return np.bincount(q4 % 16, minlength=16), None
    gt = gt[ys, xs]
    known = np.isfinite(gt)
    gt_q4 = np.rint(gt[known] * 16).astype(np.int64)
    return np.bincount(q4 % 16, minlength=16), np.bincount(gt_q4 % 16, minlength=16)


def main(argv):
    argv, extra = datasets.split_match_options(argv)
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tristereo", default=os.path.join(datasets.ROOT, "build", "tristereo"))
    ap.add_argument("--data", default=datasets.DEFAULT_DATA)
    ap.add_argument("--sets", default="")
    a = ap.parse_args(argv)
    sets = [s for s in a.sets.split(",") if s] or None
    tmp = tempfile.mkdtemp(prefix="tristereo-subpixel-")
    pooled = {}
    try:
        for scene in datasets.scenes(a.data, sets):
            h, g = measure(a.tristereo, scene, extra, tmp)
            ph, pg = pooled.setdefault(scene.set, (np.zeros(16, np.int64), np.zeros(16, np.int64)))
            ph += h
            if g is not None:
                pg += g
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("tristereo match %s --fill none: measured samples' fraction d - floor(d), %% per 1/16 px bin"
          % (" ".join(extra) or "(defaults)"))
    print("%-16s %-6s %7s %7s  %s" % ("set", "what", "bin 0", "+-1/16", " ".join("%5d" % b for b in range(16))))
    for set_name, (h, g) in pooled.items():
        for what, c in (("ours", h), ("gt", g)) if g.sum() > 0 else (("ours", h),):
            p = 100.0 * c / max(1, c.sum())
            print("%-16s %-6s %7.1f %7.1f  %s" % (set_name, what, p[0], p[15] + p[0] + p[1],
                                                  " ".join("%5.1f" % v for v in p)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
