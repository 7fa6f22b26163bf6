#!/usr/bin/python3
"""Every scene of ../shared/data and how its set is scored: the one list the
project's scripts (score_all.py, results.py) read.

The four sets (see ../shared/data/README.md): middlebury (v2: Tsukuba, Venus,
Teddy, Cones), middlebury2014 (quarter size), kitti2015, eth3d. Each folder's
datasets.tsv gives the scenes; the v2 file lacks the gt_* columns, whose fixed
names its own README gives (disp_left.png = value / gt_scale, nonocc.png,
all.png).

Metrics, as the data README scores the peers (invalid = bad, only pixels with
known ground truth): v2 bad > 1 px on nonocc and on all (the v2 masks);
Middlebury 2014 and ETH3D bad > 2 px on every known-GT pixel; KITTI D1 (error
> 3 px and > 5 % of gt) on every known-GT pixel. On every set also the
sub-pixel accuracy (SUBPIXEL_METRICS): bad > 0.5 px, bad > 1 px and the
end-point error on every known-GT pixel.

Usage as a program: scripts/datasets.py [--data DIR] prints the list.
"""
import argparse
import csv
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# $TRISTEREO_DATA_DIR (as the tests read it), else ../shared/data beside the checkout.
DEFAULT_DATA = os.environ.get("TRISTEREO_DATA_DIR") or os.path.join(ROOT, "..", "shared", "data")

# Set folder -> (label, metrics). A metric is (column label, `tristereo eval
# --json` key, region), region "nonocc" (the scene's mask, eval --mask),
# "all_mask" (v2 all.png) or "all" (every known-GT pixel, no mask).
SETS = [
    ("middlebury", "Middlebury v2", [("bad 1 px nonocc", "bad_1", "nonocc"),
                                     ("bad 1 px all", "bad_1", "all_mask")]),
    ("middlebury2014", "Middlebury 2014 (quarter)", [("bad 2 px", "bad_2", "all")]),
    ("kitti2015", "KITTI 2015", [("D1", "d1", "all")]),
    ("eth3d", "ETH3D", [("bad 2 px", "bad_2", "all")]),
]

# Sub-pixel accuracy, the same on every set: bad > 0.5 px and > 1 px (invalid
# = bad, as above) and the end-point error (the mean |d - gt| of the pixels
# that have a disparity, with the invalid share beside it), on every known-GT
# pixel: v2's all.png mask, every known pixel of the other sets. Each entry is
# (column label, `tristereo eval --json` key).
SUBPIXEL_METRICS = [("bad 0.5 px", "bad_0_5"), ("bad 1 px", "bad_1"), ("EPE px", "epe")]
SUBPIXEL_REGION = {"middlebury": "all_mask"}  # the region of the other sets: "all"

# The v2 peers: only set means exist, measured and given in issue #14's text
# ("Depth that holds ...": OpenCV StereoSGBM 3-way blockSize 5 and libelas on
# the four v2 scenes, bad > 1 px, invalid = bad). Per-scene peers of the other
# sets come from the data README's table (read_readme_peers).
V2_PEER_MEANS = {
    "source": "issue #14, \"Depth that holds ...\"",
    "bad 1 px nonocc": {"SGBM": 11.4, "libelas": 6.8},
    "bad 1 px all": {"SGBM": 17.4, "libelas": 12.1},
}

PEERS = ("SGBM", "StereoBM", "libelas")  # the README table's columns, in order


class Scene:
    """One rectified pair with its ground truth and scoring rule."""

    def __init__(self, set_name, set_label, name, directory, width, height, ndisp, gt, gt_format,
                 gt_scale, nonocc, all_mask, metrics):
        self.set = set_name
        self.set_label = set_label
        self.name = name
        self.dir = directory
        self.left = os.path.join(directory, "left.png")
        self.right = os.path.join(directory, "right.png")
        self.width, self.height, self.ndisp = width, height, ndisp
        self.gt = gt                # ground-truth file
        self.gt_format = gt_format  # `tristereo eval --gt-format`: png8, pfm or kitti
        self.gt_scale = gt_scale    # png8 only (v2 gt_scale)
        self.nonocc = nonocc        # mask file (255 = non-occluded) or None
        self.all_mask = all_mask    # v2 all.png or None
        self.metrics = metrics      # [(label, json key, region)]

    @property
    def subpixel_region(self):
        """The region SUBPIXEL_METRICS are scored on (one of self.metrics' regions)."""
        return SUBPIXEL_REGION.get(self.set, "all")

    @property
    def id(self):
        return "%s/%s" % (self.set, self.name)

    def eval_args(self, region):
        """The `tristereo eval` options after DISP GT for one region."""
        args = ["--gt-format", self.gt_format]
        if self.gt_format == "png8":
            args += ["--gt-scale", str(self.gt_scale)]
        if region == "nonocc":
            args += ["--mask", self.nonocc]
        elif region == "all_mask":
            args += ["--mask", self.all_mask]
        return args

    def __repr__(self):
        return "Scene(%s, %dx%d, ndisp %d)" % (self.id, self.width, self.height, self.ndisp)


def _rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    for r in rows:
        for key in ("name", "width", "height", "ndisp", "gt_scale"):
            if not r.get(key):
                raise ValueError("%s: scene row without '%s': %r" % (path, key, r))
    return rows


def scenes(data=DEFAULT_DATA, sets=None):
    """Every scene of every set (or of `sets`), in a fixed order. A missing
    set folder raises FileNotFoundError naming it."""
    out = []
    for set_name, label, metrics in SETS:
        if sets and set_name not in sets:
            continue
        folder = os.path.join(data, set_name)
        tsv = os.path.join(folder, "datasets.tsv")
        if not os.path.exists(tsv):
            raise FileNotFoundError("no %s (the data set '%s'; see ../shared/data/README.md)" % (tsv, set_name))
        for r in _rows(tsv):
            d = os.path.join(folder, r["name"])
            if set_name == "middlebury":
                gt, fmt = os.path.join(d, "disp_left.png"), "png8"
                nonocc, all_mask = os.path.join(d, "nonocc.png"), os.path.join(d, "all.png")
            else:
                fmt = {"pfm": "pfm", "kitti16": "kitti"}.get(r["gt_format"])
                if fmt is None:
                    raise ValueError("%s: scene %s: unknown gt_format %r" % (tsv, r["name"], r["gt_format"]))
                gt = os.path.join(d, r["gt_file"])
                nonocc = None if r["noc_mask"] in ("", "none") else os.path.join(d, r["noc_mask"])
                all_mask = None
            out.append(Scene(set_name, label, r["name"], d, int(r["width"]), int(r["height"]),
                             int(r["ndisp"]), gt, fmt, int(r["gt_scale"]), nonocc, all_mask, metrics))
    return out


def split_match_options(argv):
    """(the script's own arguments, the match options after a lone "--")."""
    if "--" not in argv:
        return argv, []
    i = argv.index("--")
    return argv[:i], argv[i + 1:]


def read_readme_peers(data=DEFAULT_DATA):
    """{"set/scene": {"metric": "bad 2 px", "SGBM": 23.4, "StereoBM": 36.5,
    "libelas": 8.0}} from the table of ../shared/data/README.md."""
    path = os.path.join(data, "README.md")
    peers = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"^\|\s*([a-z0-9]+/[A-Za-z0-9_]+)\s*\|\s*([^|]+?)\s*\|"
                         r"\s*([0-9.]+)\s*\|\s*([0-9.]+)\s*\|\s*([0-9.]+)\s*\|\s*$", line)
            if m:
                peers[m.group(1)] = {"metric": m.group(2)}
                for name, value in zip(PEERS, m.group(3, 4, 5)):
                    peers[m.group(1)][name] = float(value)
    if not peers:
        raise ValueError("%s: no peer table found (| set/scene | metric | SGBM | BM | libelas |)" % path)
    return peers


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=DEFAULT_DATA)
    a = ap.parse_args()
    peers = read_readme_peers(a.data)
    for s in scenes(a.data):
        p = peers.get(s.id)
        print("%-26s %4dx%-4d ndisp %3d  gt %-5s %-16s mask %-14s %s%s" % (
            s.id, s.width, s.height, s.ndisp, s.gt_format, os.path.basename(s.gt),
            os.path.basename(s.nonocc) if s.nonocc else "-", ", ".join(m[0] for m in s.metrics),
            "  peers SGBM %.1f libelas %.1f" % (p["SGBM"], p["libelas"]) if p else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
