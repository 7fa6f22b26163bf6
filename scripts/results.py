#!/usr/bin/python3
"""Regenerates docs/results.md (and docs/img/mesh_vs_psnr.png) from the project's own commands.

Usage: scripts/results.sh   (builds, then runs this with Debian's python3 + matplotlib)
       /usr/bin/python3 scripts/results.py [--tristereo build/tristereo] [--data ../shared/data]
Every number in the output comes from `tristereo match` / `tristereo eval` runs made here
(scripts/score_all.py for the table per data set), except the peers' numbers, which
scripts/datasets.py reads from ../shared/data/README.md and issue #14.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import datasets  # noqa: E402
import score_all  # noqa: E402
import sparsification  # noqa: E402


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("command failed: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    return r.stdout


def scenes(data):
    return [(s.name, s.ndisp, s.gt_scale) for s in datasets.scenes(data, ["middlebury"])]


def fmt1(v):
    return "%.1f" % v if isinstance(v, (int, float)) else "–"


def every_set_section(exe, data, w):
    """One table per set: ours (sparse, dense, and the paper mode when the
    program has it) beside the peers, ms per frame, and a summary line."""
    help_text = run([exe, "match", "--help"])
    modes = [("sparse", []), ("dense", ["--dense"])]
    if "--mode default|paper" in help_text:
        modes.append(("paper mode", ["--mode", "paper"]))
    peers = datasets.read_readme_peers(data)
    runs = {}
    for label, extra in modes:
        try:
            sc, res = score_all.score(exe, data, extra, jobs=1)
        except score_all.RunError as e:
            sys.exit("results: %s" % e)
        runs[label] = (extra, res, score_all.summarise(sc, res, peers))
    all_scenes = datasets.scenes(data)
    w("## Every data set of ../shared/data\n")
    w("Scored as ../shared/data/README.md scores the peers: a pixel is bad when its error exceeds "
      "the threshold or it has no disparity (invalid = bad); only pixels with known ground truth count; "
      "Middlebury 2014 and ETH3D bad > 2 px and KITTI D1 (> 3 px and > 5 %% of gt) on every known-GT "
      "pixel, Middlebury v2 bad > 1 px on its nonocc and all masks. Modes: %s. One thread; ms = the "
      "pipeline's own total for that frame (`--stats`), one run, the machine shared with other jobs: "
      "a guide, not a benchmark. Peers: OpenCV 4.6 StereoSGBM (MODE_SGBM_3WAY), StereoBM and libelas "
      "per scene from ../shared/data/README.md; for v2 only their means exist (%s). "
      "The same tables, quicker, for tuning: `scripts/score_all.py [-- match options]`.\n" % (
          ", ".join("%s (`%s`)" % (l, " ".join(e) or "defaults") for l, e in modes),
          datasets.V2_PEER_MEANS["source"]))
    for set_name, set_label, metrics in datasets.SETS:
        set_scenes = [s for s in all_scenes if s.set == set_name]
        w("### %s\n" % set_label)
        per_scene_peers = set_name != "middlebury"
        for m_label, _, _ in metrics:
            cols = ["scene", "D", "metric"] + ["%s" % l for l in runs]
            if per_scene_peers:
                cols += ["SGBM 3-way", "StereoBM", "libelas"]
            cols += ["ms %s" % l for l in runs]
            w("| " + " | ".join(cols) + " |")
            w("|---|--:|---|" + "--:|" * (len(cols) - 3))
            for s in set_scenes:
                row = [s.name, str(s.ndisp), m_label]
                row += [fmt1(runs[l][1][s.id]["metrics"][m_label]) for l in runs]
                if per_scene_peers:
                    p = peers.get(s.id, {})
                    row += [fmt1(p.get(k)) for k in datasets.PEERS]
                row += ["%.0f" % runs[l][1][s.id]["ms"] for l in runs]
                w("| " + " | ".join(row) + " |")
            row = ["**mean**", "", m_label]
            row += ["**%s**" % fmt1(runs[l][2][set_name]["metrics"][m_label]["ours"]) for l in runs]
            m0 = runs["sparse"][2][set_name]["metrics"][m_label]
            if per_scene_peers:
                row += [fmt1(m0.get(k)) for k in datasets.PEERS]
            row += ["%.0f" % runs[l][2][set_name]["ms_mean"] for l in runs]
            w("| " + " | ".join(row) + " |")
            if not per_scene_peers:
                w("\nPeers (means over the four scenes, %s): SGBM 3-way %.1f %%, libelas %.1f %%." % (
                    m0["peer_source"], m0["SGBM"], m0["libelas"]))
            w("")
        for l in runs:
            for m_label, m in runs[l][2][set_name]["metrics"].items():
                worse = m.get("worse_than_SGBM")
                if worse is not None:
                    w("- %s, %s: %d of %d scenes worse than SGBM%s." % (
                        l, m_label, len(worse), len(set_scenes),
                        (" (" + ", ".join(x.split("/")[1] for x in worse) + ")") if worse else ""))
        w("")
    subpixel_section(runs, all_scenes, w)


def subpixel_section(runs, all_scenes, w):
    """Bad 0.5 px, bad 1 px and the end-point error of every scene and set, per mode."""
    labels = [m[0] for m in datasets.SUBPIXEL_METRICS]
    w("### Sub-pixel accuracy, every set\n")
    w("Every known-GT pixel of every scene (Middlebury v2: its all.png mask): bad > 0.5 px and > 1 px "
      "(invalid = bad, as above) and the end-point error (EPE: the mean |d - gt| in px of the pixels "
      "that have a disparity; *invalid* is the share of known-GT pixels without one, which the EPE "
      "leaves out). ../shared/data/README.md gives no peer numbers for these. Set rows: the mean of "
      "the set's scenes.\n")
    cols = ["scene"]
    for label in labels:
        cols += ["%s %s" % (label, l) for l in runs]
    cols += ["invalid %% %s" % l for l in runs]
    w("| " + " | ".join(cols) + " |")
    w("|---|" + "--:|" * (len(cols) - 1))
    for set_name, set_label, _ in datasets.SETS:
        ids = [s.id for s in all_scenes if s.set == set_name]
        for sid in ids + [None]:
            if sid is None:
                vals = {l: runs[l][2][set_name]["subpixel"] for l in runs}
                row = ["**%s**" % set_label]
            else:
                vals = {l: runs[l][1][sid]["subpixel"] for l in runs}
                row = [sid]
            for label in labels + ["invalid %"]:
                for l in runs:
                    v = vals[l][label]
                    cell = "%.2f" % v if label.startswith("EPE") else "%.1f" % v
                    row.append("**%s**" % cell if sid is None else cell)
            w("| " + " | ".join(row) + " |")
    w("")


def confidence_section(exe, data, w):
    """State shares, measured and filled error rates, sparsification curves
    (scripts/sparsification.py) and their plot."""
    thresholds = [128, sparsification.ROBOT_MIN_CONFIDENCE]
    rows, set_rows, report = sparsification.measure(exe, data, None, thresholds, [], jobs=1)
    plot = os.path.join(ROOT, "docs", "img", "sparsification.png")
    try:
        sparsification.plot(set_rows, plot)
    except ImportError:
        plot = None
    for line in sparsification.markdown(rows, set_rows, report, thresholds, plot):
        w(line)


def match(exe, scene_dir, ndisp, tmp, tag, extra, repeats):
    """Runs match `repeats` times; returns (stats of the median-total run, paths)."""
    disp = os.path.join(tmp, tag + ".pfm")
    samples = os.path.join(tmp, tag + "_samples.csv")
    runs = []
    for i in range(repeats):
        stats = os.path.join(tmp, "%s_%d.json" % (tag, i))
        run([exe, "match", os.path.join(scene_dir, "left.png"), os.path.join(scene_dir, "right.png"),
             "--ndisp", str(ndisp), "--threads", "1", "--disp", disp, "--samples", samples,
             "--stats", stats] + extra)
        with open(stats) as f:
            runs.append(json.load(f))
    runs.sort(key=lambda s: s["ms"]["total"])
    med = dict(runs[len(runs) // 2])
    # Per-stage medians over the repeats (each stage separately).
    med["ms"] = {k: statistics.median(r["ms"][k] for r in runs) for k in runs[0]["ms"]}
    return med, disp, samples


def evaluate(exe, disp, scene_dir, gt_scale, mask, samples, tmp, tag):
    out = os.path.join(tmp, tag + "_eval.json")
    cmd = [exe, "eval", disp, os.path.join(scene_dir, "disp_left.png"), "--gt-scale", str(gt_scale),
           "--mask", os.path.join(scene_dir, mask + ".png"), "--json", out]
    if samples:
        cmd += ["--samples", samples]
    run(cmd)
    with open(out) as f:
        return json.load(f)


def fmt_bad(s):
    return "%.2f / %.2f / %.2f" % (s["bad_0_5"], s["bad_1"], s["bad_2"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tristereo", default=os.path.join(ROOT, "build", "tristereo"))
    ap.add_argument("--data", default=datasets.DEFAULT_DATA)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "results.md"))
    a = ap.parse_args()
    exe = a.tristereo
    tmp = tempfile.mkdtemp(prefix="tristereo-results-")
    info = run([exe, "info"])
    lines = []
    w = lines.append
    w("# Results on ../shared/data\n")
    w("Generated by `scripts/results.sh` (this file is overwritten; do not edit by hand). "
      "Default parameters unless stated (`tristereo match --help`), one thread, default kernel set. "
      "Data: ../shared/data (its README cites the sources; research evaluation use only).\n")
    w("Machine and build (`tristereo info`):\n\n```\n" + info.strip() + "\n```\n")
    every_set_section(exe, a.data, w)
    confidence_section(exe, a.data, w)
    w("## Middlebury v2 in detail\n")
    w("Bad-pixel rates Middlebury v2 style: percentage of pixels of the mask whose disparity "
      "error exceeds 0.5 / 1 / 2 px; invalid counts as bad.\n")

    rows, timing_rows, mesh_rows = [], [], []
    means = {"sparse_nonocc": [], "dense_nonocc": [], "sparse_all": [], "dense_all": []}
    for name, ndisp, gt_scale in scenes(a.data):
        sdir = os.path.join(a.data, "middlebury", name)
        s_stats, s_disp, s_samples = match(exe, sdir, ndisp, tmp, name + "_sparse", [], a.repeats)
        d_stats, d_disp, d_samples = match(exe, sdir, ndisp, tmp, name + "_dense", ["--dense"], a.repeats)
        res = {}
        for mask in ("nonocc", "all"):
            res["sparse", mask] = evaluate(exe, s_disp, sdir, gt_scale, mask, s_samples, tmp, name + "_s_" + mask)
            res["dense", mask] = evaluate(exe, d_disp, sdir, gt_scale, mask, d_samples, tmp, name + "_d_" + mask)
        means["sparse_nonocc"].append(res["sparse", "nonocc"]["dense"]["bad_1"])
        means["dense_nonocc"].append(res["dense", "nonocc"]["dense"]["bad_1"])
        means["sparse_all"].append(res["sparse", "all"]["dense"]["bad_1"])
        means["dense_all"].append(res["dense", "all"]["dense"]["bad_1"])
        rows.append((name, ndisp, s_stats, res))
        timing_rows.append((name, s_stats, d_stats))

    w("### Accuracy (bad > 0.5 / 1 / 2 px, %)\n")
    w("| scene | D | sparse, at the samples (nonocc) | dense, at the same samples (nonocc) | "
      "sparse + interpolation, dense map (nonocc) | dense map (nonocc) | sparse map (all) | dense map (all) |")
    w("|---|---|---|---|---|---|---|---|")
    for name, ndisp, s_stats, res in rows:
        w("| %s | %d | %s | %s | %s | %s | %s | %s |" % (
            name, ndisp, fmt_bad(res["sparse", "nonocc"]["samples"]), fmt_bad(res["dense", "nonocc"]["samples"]),
            fmt_bad(res["sparse", "nonocc"]["dense"]), fmt_bad(res["dense", "nonocc"]["dense"]),
            fmt_bad(res["sparse", "all"]["dense"]), fmt_bad(res["dense", "all"]["dense"])))
    mean = lambda v: sum(v) / len(v)
    v2p = datasets.V2_PEER_MEANS
    w("\nMean bad > 1 px over the four scenes, dense output map: **sparse %.2f %% nonocc / %.2f %% all**; "
      "dense %.2f %% nonocc / %.2f %% all. Peers (%s): OpenCV StereoSGBM (3-way, blockSize 5) "
      "%.1f %% nonocc / %.1f %% all; libelas %.1f %% / %.1f %%.\n" % (
          mean(means["sparse_nonocc"]), mean(means["sparse_all"]), mean(means["dense_nonocc"]),
          mean(means["dense_all"]), v2p["source"], v2p["bad 1 px nonocc"]["SGBM"], v2p["bad 1 px all"]["SGBM"],
          v2p["bad 1 px nonocc"]["libelas"], v2p["bad 1 px all"]["libelas"]))

    # Stage columns from --stats itself, so new stages appear without editing this file.
    stages = [k for k in timing_rows[0][1]["ms"] if k != "total"]
    matching = [k for k in stages if k not in ("tritree", "interpolation")]
    w("### Mesh and time per stage (median of %d runs, ms, one thread)\n" % a.repeats)
    cols = (["scene", "vertices", "sample fraction", "triangles", "forced splits"] +
            ["sparse: %s" % k.replace("_", " ") for k in stages] + ["sparse total"] +
            ["dense: %s" % k.replace("_", " ") for k in matching] + ["dense total",
             "matching sparse/dense", "frame sparse/dense"])
    w("| " + " | ".join(cols) + " |")
    w("|---|" + "--:|" * (len(cols) - 1))
    for name, s, d in timing_rows:
        ms_s, ms_d = s["ms"], d["ms"]
        m_s, m_d = sum(ms_s[k] for k in matching), sum(ms_d[k] for k in matching)
        w("| " + " | ".join([name, "%d" % s["vertices"], "%.3f" % s["sample_fraction"], "%d" % s["triangles"],
                             "%d" % s["forced_splits"]] +
                            ["%.2f" % ms_s[k] for k in stages] + ["%.2f" % ms_s["total"]] +
                            ["%.2f" % ms_d[k] for k in matching] + ["%.2f" % ms_d["total"],
                             "%.3f" % (m_s / m_d) if m_d > 0 else "–",
                             "%.3f" % (ms_s["total"] / ms_d["total"]) if ms_d["total"] > 0 else "–"]) + " |")
    w("\nThe paper claims sparse DP takes at most half the time of dense DP. \"matching\" is the stages "
      "between the tritree and the interpolation (%s); \"frame\" includes the tritree and interpolation, "
      "which dense mode also runs (for the mesh).\n" % ", ".join(k.replace("_", " ") for k in matching))

    # Mesh size against the PSNR threshold.
    psnrs = [30, 32.5, 35, 37.5, 40, 42.5, 45, 47.5, 50]
    w("### Mesh size against the PSNR threshold (A_max = 100 px^2)\n")
    w("| scene | " + " | ".join("%.1f dB" % p for p in psnrs) + " |")
    w("|---|" + "---|" * len(psnrs))
    series = {}
    for name, ndisp, gt_scale in scenes(a.data):
        sdir = os.path.join(a.data, "middlebury", name)
        counts = []
        for p in psnrs:
            st, disp, _ = match(exe, sdir, ndisp, tmp, "%s_psnr%s" % (name, p), ["--psnr", str(p)], 1)
            ev = evaluate(exe, disp, sdir, gt_scale, "nonocc", None, tmp, "%s_psnr%s" % (name, p))
            counts.append((st["vertices"], st["sample_fraction"], st["forced_splits"], ev["dense"]["bad_1"]))
        series[name] = counts
        w("| %s | " % name + " | ".join("%d (%.1f%%, %d forced) %.2f" % (v, 100 * f, fs, b)
                                        for v, f, fs, b in counts) + " |")
    w("| mean bad > 1 px (nonocc) | " + " | ".join(
        "%.2f" % (sum(series[n][i][3] for n in series) / len(series)) for i in range(len(psnrs))) + " |")
    w("\nCells: vertices (sample fraction, forced splits) and the bad > 1 px rate (nonocc) of the "
      "sparse pipeline's dense map at that threshold.\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        os.makedirs(os.path.join(ROOT, "docs", "img"), exist_ok=True)
        fig, ax = plt.subplots(figsize=(6, 4))
        for name, counts in series.items():
            ax.plot(psnrs, [100 * c[1] for c in counts], marker="o", label=name)
        ax.set_xlabel("PSNR threshold (dB)")
        ax.set_ylabel("mesh vertices (% of pixels)")
        ax.set_title("Tritree mesh size vs PSNR threshold (A_max = 100)")
        ax.grid(True, alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(ROOT, "docs", "img", "mesh_vs_psnr.png"), dpi=100)
        w("![mesh size vs PSNR](img/mesh_vs_psnr.png)\n")
    except ImportError:
        w("(matplotlib not installed: plot skipped)\n")
    w("### Defaults and the measurements behind them\n")
    w("The defaults of this run, as `tristereo match --stats` reports them: `%s`. "
      "Why they are the defaults is docs/tuning.md, included here:\n" % json.dumps(timing_rows[0][1].get("params", {})))
    tuning = os.path.join(ROOT, "docs", "tuning.md")
    if os.path.exists(tuning):
        with open(tuning) as f:
            body = f.read().split("\n")
        w("\n".join(("##" + l) if l.startswith("## ") else l for l in body[1:]))
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", a.out)


if __name__ == "__main__":
    main()
