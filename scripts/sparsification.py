#!/usr/bin/python3
"""How well the state and confidence maps (docs/model.md section 7) rank the
pixels, on every scene of ../shared/data.

For each scene: `tristereo match` with the given options (the defaults unless
told) writes the disparity (PFM), --valid and --confidence; every pixel with
known ground truth is then scored by the set's rule (docs/results.md): bad >
2 px for Middlebury v2 (its all.png mask), Middlebury 2014 and ETH3D, KITTI's
D1 (> 3 px and > 5 % of the ground truth); an invalid pixel counts as bad.

Printed per scene and per set (the set's pixels pooled):
- all: the error rate of every known-GT pixel;
- measured / filled / invalid: the share of the known-GT pixels in each
  state, and the error rate of the measured and of the filled ones;
- the sparsification curve: the error rate of the pixels kept when the
  least confident are removed first, at 100 fractions kept (pixels of equal
  confidence leave together: within such a group the rate is the group's
  mean, as for a random order), its area (the mean over the fractions) and
  the oracle's area (the same errors, removed worst first);
- for each --min-confidence threshold C asked for (--thresholds): the pixels
  a run with --min-confidence C keeps (one more run per scene), their share
  and error rate, and that rate over the all rate. These are the pixels of
  confidence >= C in the run without it except those on a triangle's edge
  whose third vertex is below C (that vertex does not weigh on the pixel's
  disparity, hence not on its confidence, but makes its triangle invalid;
  docs/model.md section 7).

--check C also runs one scene per set with --min-confidence C, checks that
every pixel it keeps has confidence >= C, and prints the share of those
pixels it does not keep.

Usage: scripts/sparsification.py --tristereo build/tristereo [--data DIR]
       [--sets a,b] [--thresholds 128,144] [--json OUT] [--plot OUT.png]
       [--markdown] [--check C] [-- extra match options]
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import datasets  # noqa: E402  (scripts/datasets.py)

FRACTIONS = np.arange(1, 101) / 100.0


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind != b"Pf":
            raise ValueError("%s: not a gray PFM (%r)" % (path, kind))
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4", count=w * h)
    return np.flipud(data.reshape(h, w)).astype(np.float64)


def read_gt(scene):
    """Ground-truth disparity and the mask of pixels that count."""
    if scene.gt_format == "pfm":
        gt = read_pfm(scene.gt)
        known = np.isfinite(gt)
    elif scene.gt_format == "kitti":
        raw = cv2.imread(scene.gt, cv2.IMREAD_UNCHANGED).astype(np.float64)
        gt = raw / 256.0
        known = raw > 0
    else:  # png8 (Middlebury v2): value / gt_scale, 0 = unknown; scored on all.png
        raw = cv2.imread(scene.gt, cv2.IMREAD_GRAYSCALE).astype(np.float64)
        gt = raw / scene.gt_scale
        known = raw > 0
        if scene.all_mask:
            known &= cv2.imread(scene.all_mask, cv2.IMREAD_GRAYSCALE) == 255
    gt[~known] = 0
    return gt, known


def metric_of(scene):
    return "D1" if scene.set == "kitti2015" else "bad 2 px"


def errors(scene, disp, gt, known):
    """Boolean 'bad' per known pixel (invalid = bad)."""
    valid = np.isfinite(disp)
    err = np.abs(np.where(valid, disp, 0) - gt)
    if scene.set == "kitti2015":
        bad = (err > 3) & (err > 0.05 * gt)
    else:
        bad = err > 2
    return (bad | ~valid)[known]


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise RuntimeError("exit %d: %s\n%s" % (r.returncode, " ".join(cmd), r.stderr))


def match_scene(exe, scene, extra, workdir, min_confidence=None):
    tag = "%s_%s%s" % (scene.set, scene.name, "" if min_confidence is None else "_c%d" % min_confidence)
    paths = {k: os.path.join(workdir, tag + ext) for k, ext in
             (("disp", ".pfm"), ("valid", "_valid.png"), ("confidence", "_conf.png"))}
    cmd = [exe, "match", scene.left, scene.right, "--ndisp", str(scene.ndisp), "--threads", "1"] + extra
    if min_confidence is not None:
        cmd += ["--min-confidence", str(min_confidence)]
    cmd += ["--disp", paths["disp"], "--valid", paths["valid"], "--confidence", paths["confidence"]]
    run(cmd)
    return (read_pfm(paths["disp"]), cv2.imread(paths["valid"], cv2.IMREAD_UNCHANGED),
            cv2.imread(paths["confidence"], cv2.IMREAD_UNCHANGED))


def score_scene(exe, scene, extra, workdir, thresholds=()):
    """Errors, states and confidences of the known-GT pixels, and for each
    threshold C the pixels a run with --min-confidence C keeps (their
    disparities are the run's without it, docs/model.md section 7)."""
    disp, state, conf = match_scene(exe, scene, extra, workdir)
    gt, known = read_gt(scene)
    kept = {}
    for c in thresholds:
        disp_c, _, _ = match_scene(exe, scene, extra, workdir, c)
        kept[c] = np.isfinite(disp_c)[known]
    return {"bad": errors(scene, disp, gt, known), "state": state[known], "conf": conf[known], "kept": kept}


def curve(bad, conf):
    """Error rate of the most confident fraction f of the pixels, for each f
    of FRACTIONS; ties leave together (the group's mean rate inside it)."""
    order = np.argsort(-conf.astype(np.int32), kind="stable")
    c, b = conf[order], bad[order].astype(np.float64)
    n = len(b)
    cum = np.concatenate([[0.0], np.cumsum(b)])
    # Group boundaries of equal confidence.
    starts = np.concatenate([[0], np.flatnonzero(np.diff(c)) + 1])
    ends = np.concatenate([starts[1:], [n]])
    rates = []
    for f in FRACTIONS:
        k = max(1, int(round(f * n)))
        g = np.searchsorted(ends, k, side="left")  # the group holding the k-th pixel
        s, e = starts[g], ends[g]
        errs = cum[s] + (cum[e] - cum[s]) * (k - s) / (e - s)
        rates.append(errs / k)
    return np.array(rates)


def oracle_curve(bad):
    n, e = len(bad), float(np.sum(bad))
    k = np.maximum(1, np.round(FRACTIONS * n))
    return np.maximum(0.0, k - (n - e)) / k


def summarise(bad, state, conf, thresholds, kept_at):
    n = len(bad)
    out = {"pixels": int(n), "all": float(np.mean(bad))}
    for name, s in (("measured", 2), ("filled", 1), ("invalid", 0)):
        m = state == s
        out[name + "_share"] = float(np.mean(m))
        out[name + "_rate"] = float(np.mean(bad[m])) if np.any(m) else None
    cv = curve(bad, conf)
    ov = oracle_curve(bad)
    out["curve"] = [float(v) for v in cv]
    out["oracle"] = [float(v) for v in ov]
    out["auc"] = float(np.mean(cv))
    out["oracle_auc"] = float(np.mean(ov))
    out["at_65"] = float(cv[64])
    out["thresholds"] = {}
    for c in thresholds:
        kept = kept_at[c]
        share = float(np.mean(kept))
        rate = float(np.mean(bad[kept])) if np.any(kept) else None
        out["thresholds"][str(c)] = {"share": share, "rate": rate,
                                     "ratio": rate / out["all"] if rate is not None and out["all"] > 0 else None}
    return out


def pct(v):
    return "-" if v is None else "%.1f" % (100 * v)


def print_table(rows, thresholds, out=sys.stdout):
    head = "%-26s %-8s %6s %7s %6s %7s %6s %6s %6s %6s" % (
        "scene", "metric", "all", "meas %", "meas", "fill %", "fill", "inv %", "AUC", "oracle")
    for c in thresholds:
        head += "   C>=%-3d kept  rate ratio" % c
    print(head, file=out)
    for label, metric, r in rows:
        line = "%-26s %-8s %6s %7s %6s %7s %6s %6s %6s %6s" % (
            label, metric, pct(r["all"]), pct(r["measured_share"]), pct(r["measured_rate"]),
            pct(r["filled_share"]), pct(r["filled_rate"]), pct(r["invalid_share"]), pct(r["auc"]),
            pct(r["oracle_auc"]))
        for c in thresholds:
            t = r["thresholds"][str(c)]
            line += "   %12s %5s %5s" % (pct(t["share"]), pct(t["rate"]),
                                          "-" if t["ratio"] is None else "%.2f" % t["ratio"])
        print(line, file=out)


def plot(sets, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, (label, metric, r) in enumerate(sets):
        colour = "C%d" % i
        ax.plot(100 * FRACTIONS, 100 * np.array(r["curve"]), color=colour,
                label="%s (%s): AUC %.1f" % (label, metric, 100 * r["auc"]))
        ax.plot(100 * FRACTIONS, 100 * np.array(r["oracle"]), color=colour, linestyle=":",
                label="  oracle: AUC %.1f" % (100 * r["oracle_auc"]))
    ax.set_xlabel("pixels kept (%), least confident removed first")
    ax.set_ylabel("error rate of the kept pixels (%)")
    ax.set_title("Sparsification by confidence (dotted: oracle)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


# The --min-confidence value docs/model.md section 7 suggests for robots, and
# the target for it: on KITTI and Middlebury 2014, the pixels kept are
# at least 65 % of those with ground truth and their error rate at most 0.3
# times the rate of all of them (invalid counted bad) without it.
ROBOT_MIN_CONFIDENCE = 144
TARGET_SETS = ("middlebury2014", "kitti2015")
TARGET_SHARE, TARGET_RATIO = 0.65, 0.3


def measure(exe, data, sets, thresholds, extra, jobs=2, check=None):
    """Scores every scene -> (rows per scene, rows per set, report dict).
    With `check`, also verifies a --min-confidence run on one scene per set
    (RuntimeError when it keeps other pixels)."""
    scenes = datasets.scenes(data, sets)
    with tempfile.TemporaryDirectory(prefix="sparsification_") as work:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = [pool.submit(score_scene, exe, s, extra, work, thresholds) for s in scenes]
            results = [f.result() for f in futures]
        if check is not None:
            seen = set()
            for s, r in zip(scenes, results):
                if s.set in seen:
                    continue
                seen.add(s.set)
                disp, _, _ = match_scene(exe, s, extra, work, check)
                gt, known = read_gt(s)
                kept, above = np.isfinite(disp)[known], r["conf"] >= check
                if np.any(kept & ~above):
                    raise RuntimeError("%s with --min-confidence %d keeps pixels of confidence below %d"
                                       % (s.id, check, check))
                print("check: %s with --min-confidence %d keeps %d of the %d known-GT pixels of confidence >= %d"
                      " (%.2f %% dropped: on edges of triangles with a vertex below it)"
                      % (s.id, check, int(np.count_nonzero(kept)), int(np.count_nonzero(above)), check,
                         100.0 * (1 - np.count_nonzero(kept) / max(1, np.count_nonzero(above)))), file=sys.stderr)
    rows, set_rows, report = [], [], {"options": extra, "scenes": {}, "sets": {}}
    for s, r in zip(scenes, results):
        summary = summarise(r["bad"], r["state"], r["conf"], thresholds, r["kept"])
        rows.append((s.id, metric_of(s), summary))
        report["scenes"][s.id] = summary
    for set_name, label, _ in datasets.SETS:
        members = [(s, r) for s, r in zip(scenes, results) if s.set == set_name]
        if not members:
            continue
        pooled = [np.concatenate([r[k] for _, r in members]) for k in ("bad", "state", "conf")]
        kept_at = {c: np.concatenate([r["kept"][c] for _, r in members]) for c in thresholds}
        summary = summarise(pooled[0], pooled[1], pooled[2], thresholds, kept_at)
        set_rows.append((label, metric_of(members[0][0]), summary))
        report["sets"][set_name] = summary
    return rows, set_rows, report


def markdown(rows, set_rows, report, thresholds, plot_path=None):
    """The section of docs/results.md (scripts/results.py writes it)."""
    out = []
    w = out.append
    w("## Measured, filled and confidence\n")
    w("Every pixel's state and confidence (docs/model.md section 7; `tristereo match --valid "
      "--confidence`), defaults, one run per scene, scored as the table per set above but with bad > 2 px "
      "for Middlebury v2 too (its all.png mask), KITTI D1; invalid = bad; only known-GT pixels. *share*: of "
      "the known-GT pixels; *rate*: error rate of those pixels. The sparsification curve removes the least "
      "confident pixels first (equal confidences together) and gives the error rate of those kept; AUC is "
      "its mean over 1..100 %% kept, the oracle's the same for a perfect ranking of the same errors. "
      "*C >= c*: what `--min-confidence c` keeps (with c >= 128 only measured pixels). "
      "Rerun: `scripts/sparsification.py --tristereo build/tristereo --thresholds %s`.\n"
      % ",".join(str(t) for t in thresholds))
    head = "| set | metric | all | measured share | measured rate | filled share | filled rate | invalid share " \
           "| AUC | oracle AUC |"
    rule = "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|"
    for c in thresholds:
        head += " C >= %d kept | rate | x all |" % c
        rule += "--:|--:|--:|"
    for title, table in (("Per set (the set's pixels pooled)", set_rows), ("Per scene", rows)):
        w("%s, %%:\n" % title)
        w(head)
        w(rule)
        for label, metric, r in table:
            line = "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                label, metric, pct(r["all"]), pct(r["measured_share"]), pct(r["measured_rate"]),
                pct(r["filled_share"]), pct(r["filled_rate"]), pct(r["invalid_share"]), pct(r["auc"]),
                pct(r["oracle_auc"]))
            for c in thresholds:
                t = r["thresholds"][str(c)]
                line += " %s | %s | %s |" % (pct(t["share"]), pct(t["rate"]),
                                              "-" if t["ratio"] is None else "%.2f" % t["ratio"])
            w(line)
        w("")
    if str(ROBOT_MIN_CONFIDENCE) in next(iter(report["sets"].values()))["thresholds"]:
        w("Target of issue #39 with `--min-confidence %d` (docs/model.md section 7): kept share >= %d %% "
          "and rate <= %.1f x all, per set:\n" % (ROBOT_MIN_CONFIDENCE, round(100 * TARGET_SHARE), TARGET_RATIO))
        for set_name in TARGET_SETS:
            r = report["sets"].get(set_name)
            if r is None:
                continue
            t = r["thresholds"][str(ROBOT_MIN_CONFIDENCE)]
            met = t["share"] >= TARGET_SHARE and t["ratio"] is not None and t["ratio"] <= TARGET_RATIO
            w("- %s: %s %% kept, rate %s %% = %.2f x all (%s %%): %s." % (
                set_name, pct(t["share"]), pct(t["rate"]), t["ratio"], pct(r["all"]), "met" if met else "not met"))
        w("")
    if plot_path:
        w("![sparsification curves](img/%s)\n" % os.path.basename(plot_path))
    return out


def main(argv):
    argv, extra = datasets.split_match_options(argv)
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tristereo", required=True)
    ap.add_argument("--data", default=datasets.DEFAULT_DATA)
    ap.add_argument("--sets", default=None, help="comma-separated set folders (default: all)")
    ap.add_argument("--thresholds", default="128,%d" % ROBOT_MIN_CONFIDENCE,
                    help="comma-separated --min-confidence values to report")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", default=None)
    ap.add_argument("--plot", default=None)
    ap.add_argument("--markdown", action="store_true", help="print the docs/results.md section instead")
    ap.add_argument("--check", type=int, default=None)
    a = ap.parse_args(argv)
    thresholds = [int(t) for t in a.thresholds.split(",") if t]
    try:
        rows, set_rows, report = measure(a.tristereo, a.data, a.sets.split(",") if a.sets else None, thresholds,
                                         extra, a.jobs, a.check)
    except RuntimeError as e:
        print("sparsification: %s" % e, file=sys.stderr)
        return 1
    if a.plot:
        plot(set_rows, a.plot)
    if a.markdown:
        print("\n".join(markdown(rows, set_rows, report, thresholds, a.plot)))
    else:
        if a.check is not None:
            print("check: --min-confidence %d keeps only pixels of confidence >= %d" % (a.check, a.check))
        print("options: %s" % (" ".join(extra) if extra else "(defaults)"))
        print("Per scene (%; meas/fill = error rate of the measured/filled pixels, their share in 'meas %'/'fill %'):")
        print_table(rows, thresholds)
        print("\nPer set (pixels pooled):")
        print_table(set_rows, thresholds)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(report, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
