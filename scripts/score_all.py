#!/usr/bin/python3
"""Scores tristereo on every scene of ../shared/data beside OpenCV's and libelas's numbers.

Usage: scripts/score_all.py [--tristereo BIN] [--data DIR] [--jobs 2] [--sets a,b]
                            [--scenes x,y] [--json OUT.json] [--baseline OLD.json]
                            [--keep DIR] [-- extra match options]

For each scene (scripts/datasets.py): `tristereo match LEFT RIGHT --ndisp N
<extra> --disp D.pfm --stats S.json` (with --threads 1 unless the extra options
say otherwise, so --jobs pairs run side by side), then `tristereo eval` by the
set's metric (data README: invalid = bad, every known-GT pixel; v2 on its
masks). Prints one table per set (per-scene metric, ms per frame, the peers),
its sub-pixel accuracy on every known-GT pixel (bad 0.5 px, bad 1 px, the
end-point error and the invalid share the EPE leaves out) and a summary: one line per set, our mean against SGBM's and libelas's, and how
many scenes are worse than SGBM. --baseline OLD.json (an earlier --json) adds
the change per scene and the earlier set means. Exit 1 when a match or an eval fails (the
command and its message are printed), 2 for usage errors.

ms per frame is the pipeline's own `--stats` total of that one run: with
--jobs > 1 the runs share the machine, so treat it as a rough guide; the
benchmarks (bench/) are the measurement.
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import datasets  # noqa: E402  (scripts/datasets.py)


class RunError(Exception):
    pass


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise RunError("exit %d: %s\n%s%s" % (r.returncode, " ".join(cmd), r.stdout, r.stderr))
    return r


def score_scene(exe, scene, extra, workdir):
    """match + eval of one scene -> dict of results; RunError on failure."""
    tag = "%s_%s" % (scene.set, scene.name)
    disp = os.path.join(workdir, tag + ".pfm")
    stats = os.path.join(workdir, tag + "_stats.json")
    cmd = [exe, "match", scene.left, scene.right, "--ndisp", str(scene.ndisp)] + extra
    if "--threads" not in extra:
        cmd += ["--threads", "1"]
    cmd += ["--disp", disp, "--stats", stats]
    match_warnings = [l for l in run(cmd).stderr.splitlines() if l.strip()]
    with open(stats) as f:
        st = json.load(f)
    res = {"id": scene.id, "set": scene.set, "name": scene.name, "ndisp": scene.ndisp,
           "ms": st["ms"]["total"], "vertices": st.get("vertices"),
           "sample_fraction": st.get("sample_fraction"), "metrics": {}, "eval": {},
           "warnings": match_warnings, "disp": disp}
    regions = [m[2] for m in scene.metrics]
    if scene.subpixel_region not in regions:
        regions.append(scene.subpixel_region)
    for region in regions:
        out = os.path.join(workdir, "%s_%s_eval.json" % (tag, region))
        r = run([exe, "eval", disp, scene.gt] + scene.eval_args(region) + ["--json", out])
        res["warnings"] += [l for l in r.stderr.splitlines() if l.strip()]
        with open(out) as f:
            res["eval"][region] = json.load(f)["dense"]
    for label, key, region in scene.metrics:
        res["metrics"][label] = res["eval"][region][key]
    # Sub-pixel accuracy on every known-GT pixel (datasets.SUBPIXEL_METRICS) and
    # the invalid share beside the end-point error, which leaves those pixels out.
    ev = res["eval"][scene.subpixel_region]
    res["subpixel"] = {label: ev[key] for label, key in datasets.SUBPIXEL_METRICS}
    res["subpixel"]["invalid %"] = 100.0 * ev["invalid"] / max(1, ev["evaluated"])
    return res


def score(exe, data, extra, jobs=2, sets=None, workdir=None, names=None):
    """Scores every scene (of `sets`; named `names`, as name or set/name);
    returns (scenes, results by scene id)."""
    scenes = datasets.scenes(data, sets)
    if names:
        unknown = [n for n in names if not any(n in (s.name, s.id) for s in scenes)]
        if unknown:
            raise ValueError("--scenes: no scene %s (scripts/datasets.py lists them)" % ", ".join(unknown))
        scenes = [s for s in scenes if s.name in names or s.id in names]
    own_tmp = workdir is None
    workdir = workdir or tempfile.mkdtemp(prefix="tristereo-score-")
    os.makedirs(workdir, exist_ok=True)
    results, failures = {}, []
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            futures = {pool.submit(score_scene, exe, s, extra, workdir): s for s in scenes}
            for fut in concurrent.futures.as_completed(futures):
                s = futures[fut]
                try:
                    results[s.id] = fut.result()
                except RunError as e:
                    failures.append("%s: %s" % (s.id, e))
    finally:
        if own_tmp:
            shutil.rmtree(workdir, ignore_errors=True)
    if failures:
        raise RunError("\n".join(sorted(failures)))
    return scenes, results


def summarise(scenes, results, peers):
    """Per set: our mean per metric, the peers' means over the same scenes,
    and the scenes worse than SGBM (per-scene peers only)."""
    out = {}
    for set_name, label, metrics in datasets.SETS:
        ids = [s.id for s in scenes if s.set == set_name]
        if not ids:
            continue
        entry = {"label": label, "scenes": len(ids), "metrics": {}}
        for m_label, _, _ in metrics:
            ours = statistics.mean(results[i]["metrics"][m_label] for i in ids)
            m = {"ours": ours}
            if set_name == "middlebury":
                m.update(datasets.V2_PEER_MEANS[m_label])
                m["peer_source"] = datasets.V2_PEER_MEANS["source"]
            elif all(i in peers for i in ids):
                for p in datasets.PEERS:
                    m[p] = statistics.mean(peers[i][p] for i in ids)
                m["worse_than_SGBM"] = [i for i in ids if results[i]["metrics"][m_label] > peers[i]["SGBM"]]
                m["peer_source"] = "../shared/data/README.md"
            entry["metrics"][m_label] = m
        entry["subpixel"] = {label: statistics.mean(results[i]["subpixel"][label] for i in ids)
                             for label in SUBPIXEL_LABELS}
        entry["ms_mean"] = statistics.mean(results[i]["ms"] for i in ids)
        out[set_name] = entry
    return out


SUBPIXEL_LABELS = [m[0] for m in datasets.SUBPIXEL_METRICS] + ["invalid %"]


def fmt(v):
    return "%.1f" % v if isinstance(v, (int, float)) else "-"


def delta(ours, base):
    return "%+.1f" % (ours - base) if isinstance(base, (int, float)) else "-"


def fmt_subpixel(label, v):
    """EPE in px with two decimals (0.1 px is a large change), rates in % with one."""
    if not isinstance(v, (int, float)):
        return "-"
    return "%.2f" % v if label.startswith("EPE") else "%.1f" % v


def delta_subpixel(label, ours, base):
    if not isinstance(base, (int, float)):
        return "-"
    return "%+.2f" % (ours - base) if label.startswith("EPE") else "%+.1f" % (ours - base)


def print_tables(scenes, results, peers, summary, extra, baseline=None, out=sys.stdout):
    """baseline: a previous --json output; adds a change column per metric."""
    w = lambda s="": print(s, file=out)
    base_scenes = (baseline or {}).get("scenes", {})
    w("tristereo match %s (all known-GT pixels unless a mask is named; invalid = bad; %%)" %
      (" ".join(extra) if extra else "(defaults)"))
    if baseline is not None:
        w("change column: against %s" % (" ".join(baseline.get("match_args", [])) or "(defaults)"))
    for set_name, entry in summary.items():
        w()
        set_scenes = [s for s in scenes if s.set == set_name]
        labels = [m[0] for m in set_scenes[0].metrics]
        w("## %s" % entry["label"])
        per_scene_peers = set_name != "middlebury"
        # Invalid pixels (counted as bad above), shown once the matcher leaves any (--fill none).
        region0 = set_scenes[0].metrics[0][2]
        inv = {s.id: 100.0 * results[s.id]["eval"][region0]["invalid"] /
               max(1, results[s.id]["eval"][region0]["evaluated"]) for s in set_scenes}
        show_inv = any(v > 0 for v in inv.values())
        head = "%-12s" % "scene"
        for l in labels:
            head += "%18s" % l + ("%8s" % "change" if baseline is not None else "")
        if show_inv:
            head += "%9s" % "invalid"
        if per_scene_peers:
            head += "%8s%10s%9s" % ("SGBM", "StereoBM", "libelas")
        w(head + "%9s" % "ms")
        for s in set_scenes:
            r = results[s.id]
            line = "%-12s" % s.name
            for l in labels:
                line += "%18s" % fmt(r["metrics"][l])
                if baseline is not None:
                    line += "%8s" % delta(r["metrics"][l], base_scenes.get(s.id, {}).get("metrics", {}).get(l))
            note = ""
            if show_inv:
                line += "%9s" % fmt(inv[s.id])
            if per_scene_peers:
                p = peers.get(s.id, {})
                line += "%8s%10s%9s" % (fmt(p.get("SGBM")), fmt(p.get("StereoBM")), fmt(p.get("libelas")))
                if p and r["metrics"][labels[0]] > p["SGBM"]:
                    note = "  worse than SGBM"
            w(line + "%9s" % fmt(r["ms"]) + note)
        line = "%-12s" % "mean"
        for l in labels:
            line += "%18s" % fmt(entry["metrics"][l]["ours"])
            if baseline is not None:
                ids = [s.id for s in set_scenes]
                old = [base_scenes[i]["metrics"].get(l) for i in ids if i in base_scenes]
                line += "%8s" % (delta(entry["metrics"][l]["ours"], statistics.mean(old))
                                 if len(old) == len(ids) else "-")
        if show_inv:
            line += "%9s" % fmt(statistics.mean(inv.values()))
        if per_scene_peers:
            m = entry["metrics"][labels[0]]
            line += "%8s%10s%9s" % (fmt(m.get("SGBM")), fmt(m.get("StereoBM")), fmt(m.get("libelas")))
        w(line + "%9s" % fmt(entry["ms_mean"]))
        if not per_scene_peers:
            for l in labels:
                m = entry["metrics"][l]
                w("  peers, %s (means, %s): SGBM %.1f, libelas %.1f" % (l, m["peer_source"], m["SGBM"], m["libelas"]))
        # Sub-pixel accuracy: every known-GT pixel (v2: all.png); no peer numbers exist for these.
        w("sub-pixel, every known-GT pixel (EPE: mean |d - gt| in px of the pixels with a disparity; "
          "invalid: their share, bad at every threshold):")
        head = "%-12s" % "scene"
        for l in SUBPIXEL_LABELS:
            head += "%12s" % l + ("%8s" % "change" if baseline is not None else "")
        w(head)
        for s in set_scenes + [None]:
            vals = results[s.id]["subpixel"] if s else entry["subpixel"]
            if s:
                old = base_scenes.get(s.id, {}).get("subpixel", {})
            else:
                old_sets = (baseline or {}).get("sets", {}).get(set_name, {})
                old = old_sets.get("subpixel", {}) if old_sets.get("scenes") == entry["scenes"] else {}
            line = "%-12s" % (s.name if s else "mean")
            for l in SUBPIXEL_LABELS:
                line += "%12s" % fmt_subpixel(l, vals[l])
                if baseline is not None:
                    line += "%8s" % delta_subpixel(l, vals[l], old.get(l))
            w(line)
    warned = [(i, r["warnings"]) for i, r in sorted(results.items()) if r["warnings"]]
    if warned:
        w()
        for i, ws in warned:
            for x in ws:
                w("%s: %s" % (i, x))
    w()
    w("summary (ours vs SGBM vs libelas, set means):")
    base_sets = (baseline or {}).get("sets", {})
    for set_name, entry in summary.items():
        for m_label, m in entry["metrics"].items():
            worse = m.get("worse_than_SGBM")
            if worse is not None:
                verdict = "worse than SGBM: %d of %d%s" % (
                    len(worse), entry["scenes"],
                    (" (" + ", ".join(x.split("/")[1] for x in worse) + ")") if worse else "")
            else:
                verdict = "mean %s SGBM's" % ("worse than" if m["ours"] > m["SGBM"] else "better than")
            old = base_sets.get(set_name, {}).get("metrics", {}).get(m_label, {}).get("ours")
            was = " (was %.1f)" % old if old is not None and base_sets[set_name]["scenes"] == entry["scenes"] else ""
            w("  %-15s %-16s ours %5.1f%s  SGBM %5.1f  libelas %5.1f  %s" % (
                set_name, m_label, m["ours"], was, m["SGBM"], m["libelas"], verdict))
    w("sub-pixel (set means, every known-GT pixel; no peer numbers in ../shared/data/README.md):")
    for set_name, entry in summary.items():
        old_set = base_sets.get(set_name, {})
        old = old_set.get("subpixel", {}) if old_set.get("scenes") == entry["scenes"] else {}
        w("  %-15s %s" % (set_name, "  ".join(
            "%s %s%s" % (l, fmt_subpixel(l, entry["subpixel"][l]),
                         " (was %s)" % fmt_subpixel(l, old[l]) if l in old else "")
            for l in SUBPIXEL_LABELS)))


def main(argv):
    argv, extra = datasets.split_match_options(argv)
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 usage="%(prog)s [options] [-- extra match options]")
    ap.add_argument("--tristereo", default=os.path.join(datasets.ROOT, "build", "tristereo"))
    ap.add_argument("--data", default=datasets.DEFAULT_DATA)
    ap.add_argument("--jobs", type=int, default=2, help="scenes matched at once (default 2)")
    ap.add_argument("--sets", default="", help="comma-separated subset of " +
                    ",".join(s[0] for s in datasets.SETS))
    ap.add_argument("--json", help="also write every number here")
    ap.add_argument("--scenes", default="", help="comma-separated scene names (e.g. motorcyclee,pianol)")
    ap.add_argument("--baseline", help="a previous --json output: adds a change column and 'was' values")
    ap.add_argument("--keep", help="keep the disparity maps and JSON files in this folder")
    a = ap.parse_args(argv)
    if a.jobs < 1:
        ap.error("--jobs must be >= 1")
    sets = [s for s in a.sets.split(",") if s]
    unknown = [s for s in sets if s not in [x[0] for x in datasets.SETS]]
    if unknown:
        ap.error("--sets: unknown set(s) %s" % ", ".join(unknown))
    if not (os.path.isfile(a.tristereo) and os.access(a.tristereo, os.X_OK)):
        ap.error("--tristereo %s: no such program (build it: cmake --build build --target tristereo_cli)" % a.tristereo)
    try:
        peers = datasets.read_readme_peers(a.data)
        baseline = None
        if a.baseline:
            with open(a.baseline) as f:
                baseline = json.load(f)
        names = [n for n in a.scenes.split(",") if n]
        scenes, results = score(a.tristereo, a.data, extra, a.jobs, sets or None, a.keep, names or None)
    except (OSError, ValueError) as e:
        print("score_all: %s" % e, file=sys.stderr)
        return 1
    except RunError as e:
        print("score_all: a run failed:\n%s" % e, file=sys.stderr)
        return 1
    summary = summarise(scenes, results, peers)
    print_tables(scenes, results, peers, summary, extra, baseline)
    if a.json:
        for r in results.values():
            if not a.keep:
                r.pop("disp", None)
        with open(a.json, "w") as f:
            json.dump({"tristereo": a.tristereo, "match_args": extra, "scenes": results,
                       "sets": summary, "peers": {i: peers[i] for i in results if i in peers},
                       "v2_peer_means": datasets.V2_PEER_MEANS}, f, indent=1, sort_keys=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
