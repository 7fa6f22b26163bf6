#!/usr/bin/python3
"""Runs bench/bench_peers and bench/bench_pipeline (Google Benchmark) and writes
docs/performance-tables.md.

bench_peers: tristereo's frame and its stages against OpenCV's StereoBM and
StereoSGBM (3-way) on the same frames, one thread, in one run; every stage is
printed as a ratio to StereoBM's frame of that run, per scene.

bench_pipeline: bench/bench_machine runs just before and just after it: the
2-thread/1-thread ceiling of plain loops on this machine at that time, to read
the pipeline's thread speed-ups against (a shared VM's ceiling moves with its
neighbours).

Usage: /usr/bin/python3 scripts/perf_report.py [--build build] [--repetitions 5]
                                               [--only peers|pipeline] [--reuse]
All ratios are computed from the medians of one run of one benchmark binary:
stages vs StereoBM, SIMD vs scalar per stage, sparse vs dense, N threads vs 1.
--only runs one of the two and takes the other's tables from its JSON file of the
last run (each section names the run it comes from).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


REUSE = False  # --reuse: tables from the JSON files of the last run, nothing is run


def run_bench(cmd):
    if REUSE:
        return
    print(" ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, stdout=sys.stderr)


def machine_ceilings(build, tag):
    """Medians of bench_machine: {loop name: 2-thread / 1-thread items per second}."""
    exe = os.path.join(build, "bench", "bench_machine")
    out_json = os.path.join(build, "bench_machine_%s.json" % tag)
    cmd = [exe, "--benchmark_repetitions=5", "--benchmark_report_aggregates_only=true",
           "--benchmark_enable_random_interleaving=true",
           "--benchmark_out=" + out_json, "--benchmark_out_format=json"]
    run_bench(cmd)
    with open(out_json) as f:
        data = json.load(f)
    rate = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        # machine/<loop>[/<KiB>]/real_time/threads:<n>
        parts = b["run_name"].split("/")
        loop = "/".join(p for p in parts[1:] if p != "real_time" and not p.startswith("threads:"))
        rate[(loop, int(parts[-1].split(":")[1]))] = b["items_per_second"]
    return {loop: rate[(loop, 2)] / rate[(loop, 1)] for (loop, t) in rate if t == 1 and (loop, 2) in rate}


def tritree_scaling(build):
    """Medians of bench_tritree on the synthetic scene: (pooled 2T speed-up,
    independent builds 2T throughput ratio, pooled 1T ms, pooled 2T ms)."""
    exe = os.path.join(build, "bench", "bench_tritree")
    out_json = os.path.join(build, "bench_tritree.json")
    cmd = [exe, "--benchmark_filter=synthetic640x480", "--benchmark_repetitions=5",
           "--benchmark_report_aggregates_only=true", "--benchmark_enable_random_interleaving=true",
           "--benchmark_out=" + out_json, "--benchmark_out_format=json"]
    run_bench(cmd)
    with open(out_json) as f:
        data = json.load(f)
    med = {b["run_name"]: b for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
    pooled = {t: med["tritree/synthetic640x480/threads:%d/real_time" % t]["real_time"] for t in (1, 2)}
    indep = {t: med["tritree_independent/synthetic640x480/real_time/threads:%d" % t]["items_per_second"]
             for t in (1, 2)}
    return pooled[1] / pooled[2], indep[2] / indep[1], pooled[1], pooled[2]


def describe_loop(loop):
    if loop == "alu":
        return "arithmetic in registers"
    kib = int(loop.split("/")[1])
    return "random 4-byte reads, %d MiB per thread" % (kib // 1024)


def repetitions_of(data):
    """How many repetitions the run made (the most any benchmark of it has)."""
    reps = [b.get("repetitions", 1) for b in data["benchmarks"]]
    return max(reps) if reps else 0


def machine_of(ctx):
    return "Machine: %s, %d CPUs, %s MHz; load average at start %s." % (
        ctx.get("host_name", "?"), ctx.get("num_cpus", 0), ctx.get("mhz_per_cpu", "?"),
        ", ".join("%.2f" % x for x in ctx.get("load_avg", [])))


# bench_peers' scenes in the order of the tables, with what they are.
PEER_SCENES = [("teddy", "Middlebury v2 teddy 450x375"), ("cones", "Middlebury v2 cones 450x375"),
               ("synthetic640x480", "synthetic 640x480"), ("kitti000000", "KITTI 2015 000000 1242x375")]


def peers_section(a):
    """tristereo's stages as ratios to StereoBM's frame, from one run of bench_peers."""
    exe = os.path.join(a.build, "bench", "bench_peers")
    out_json = os.path.join(a.build, "bench_peers.json")
    run_bench([exe, "--benchmark_repetitions=%d" % a.repetitions, "--benchmark_display_aggregates_only=true",
               "--benchmark_enable_random_interleaving=true",
               "--benchmark_out=" + out_json, "--benchmark_out_format=json"])
    with open(out_json) as f:
        data = json.load(f)
    med = {}  # (scene, D, what) -> median aggregate; what = sparse, dense, stereobm, sgbm3way
    kernels = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        parts = b["run_name"].split("/")
        if parts[0] == "frame" and parts[3] == "paper":  # frame/<scene>/D<d>/paper/sparse/<kernels>/t1
            med[(parts[1], int(parts[2][1:]), "paper")] = b
        elif parts[0] == "frame":  # frame/<scene>/D<d>/<mode>/<kernels>/t1
            med[(parts[1], int(parts[2][1:]), parts[3])] = b
            kernels[(parts[1], int(parts[2][1:]))] = parts[4]
        elif parts[0] == "peer":  # peer/<scene>/D<d>/<matcher>
            med[(parts[1], int(parts[2][1:]), parts[3])] = b
    ctx = data["context"]
    lines = ["## tristereo against OpenCV, one thread\n",
             "From one run of `bench/bench_peers` (%s; Google Benchmark, %d repetitions in random interleaving, "
             "medians; OpenCV %s). %s Every column is a median over the repetitions; a ratio is the stage's "
             "median over StereoBM's median frame time in the same run. tristereo: default parameters, "
             "best kernel set, one worker; StereoBM block 9, XSOBEL prefilter; SGBM MODE_SGBM_3WAY block 5, "
             "P1 600, P2 2400 (../shared/data/README.md). Same gray frames for all (BT.601).\n" % (
                 ctx.get("date", "?"), repetitions_of(data),
                 "in this run" if ctx.get("opencv", "").startswith("yes") else "absent: no peer rows",
                 machine_of(ctx))]
    scenes = [(s, d) for s, _ in PEER_SCENES for d in sorted({k[1] for k in med if k[0] == s})]
    label = dict(PEER_SCENES)
    ms = lambda b: b["real_time"]  # the benchmarks report milliseconds
    lines.append("| scene | D | kernels | StereoBM ms | SGBM 3-way ms | tristereo sparse frame ms | "
                 "tritree | cost | DP | support prior | interpolation | **tritree + interpolation** | sparse frame | "
                 "dense frame | paper mode frame | SGBM 3-way | sparse / dense frame |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for s, d in scenes:
        sp, de, pa = med.get((s, d, "sparse")), med.get((s, d, "dense")), med.get((s, d, "paper"))
        bm, sg = med.get((s, d, "stereobm")), med.get((s, d, "sgbm3way"))
        if not sp:
            continue
        ratio = lambda v: "%.2fx" % (v / ms(bm)) if bm else "-"
        lines.append("| %s | %d | %s | %s | %s | %.2f | %s | %s | %s | %s | %s | **%s** | %s | %s | %s | %s | %s |" % (
            label[s], d, kernels[(s, d)], "%.2f" % ms(bm) if bm else "-", "%.2f" % ms(sg) if sg else "-",
            sp["total_ms"], ratio(sp["tritree_ms"]), ratio(sp["cost_ms"]), ratio(sp["dp_ms"]),
            ratio(sp["prior_ms"]) if "prior_ms" in sp else "-", ratio(sp["interp_ms"]), ratio(sp["tritree_ms"] + sp["interp_ms"]), ratio(sp["total_ms"]),
            ratio(de["total_ms"]) if de else "-", ratio(pa["total_ms"]) if pa else "-",
            ratio(ms(sg)) if sg else "-",
            "%.3f" % (sp["total_ms"] / de["total_ms"]) if de else "-"))
    lines.append("\nThe stage columns (tritree .. SGBM 3-way) are multiples of StereoBM's frame time. "
                 "tristereo's stages in ms (same run):\n")
    lines.append("| scene | D | mode | tritree | cost | DP | support prior | fill | interpolation | frame |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    for s, d in scenes:
        for mode in ("sparse", "dense", "paper"):
            b = med.get((s, d, mode))
            if b:
                lines.append("| %s | %d | %s | %.2f | %.2f | %.2f | %s | %.2f | %.2f | %.2f |" % (
                    label[s], d, "paper mode (sparse)" if mode == "paper" else mode, b["tritree_ms"],
                    b["cost_ms"], b["dp_ms"], "%.2f" % b["prior_ms"] if "prior_ms" in b else "-",
                    b.get("fill_ms", 0.0), b["interp_ms"], b["total_ms"]))
    lines.append("")
    return lines


def pipeline_section(a):
    """The tables of bench_pipeline (with bench_machine and bench_tritree around it)."""
    exe = os.path.join(a.build, "bench", "bench_pipeline")
    out_json = os.path.join(a.build, "bench_pipeline.json")
    # Random interleaving spreads the repetitions of each benchmark over the whole
    # run, so slow drifts of a shared machine hit every configuration alike.
    # The JSON keeps every repetition (the frame_pair table shows their range);
    # the console shows only the aggregates.
    cmd = [exe, "--benchmark_repetitions=%d" % a.repetitions, "--benchmark_display_aggregates_only=true",
           "--benchmark_enable_random_interleaving=true",
           "--benchmark_out=" + out_json, "--benchmark_out_format=json"]
    if a.filter:
        cmd.append("--benchmark_filter=" + a.filter)
    before = machine_ceilings(a.build, "before")
    run_bench(cmd)
    after = machine_ceilings(a.build, "after")
    tritree = tritree_scaling(a.build)
    with open(out_json) as f:
        data = json.load(f)
    med = {}
    pairs = {}  # frame_pair run name -> its repetitions, each with its own median of pairs
    census = {}  # (scene, D) -> ms of the census work at every pixel (census_pixels/<scene>/D<d>/<kernels>)
    priors = {}  # (scene, D) -> the prior_pair median (frames without and with the support prior)
    for b in data["benchmarks"]:
        if b["run_name"].startswith("prior_pair/") and b.get("aggregate_name") == "median":
            _, scene, d = b["run_name"].split("/")[:3]
            priors[(scene, int(d[1:]))] = b
            continue
        if b["run_name"].startswith("frame_pair/") and b.get("run_type") == "iteration":
            pairs.setdefault(b["run_name"], []).append(b)
            continue
        if b["run_name"].startswith("census_pixels/") and b.get("aggregate_name") == "median":
            _, scene, d = b["run_name"].split("/")[:3]
            census[(scene, int(d[1:]))] = b["census_pixels_ms"]
            continue
        if b.get("aggregate_name") != "median" or not b["run_name"].startswith("frame/"):
            continue
        name = b["run_name"]  # frame/<scene>/D<d>/<mode>/<kernels>/t<threads>
        _, scene, d, mode, kernels, threads = name.split("/")[:6]
        med[(scene, int(d[1:]), mode, kernels, int(threads[1:]))] = b
    ctx = data["context"]
    lines = ["## The pipeline: kernel sets, sparse vs dense, threads\n",
             "From one run of `bench/bench_pipeline` (%s; Google Benchmark, %d repetitions in random interleaving, "
             "medians; each repetition averages its iterations). %s Times in ms per frame. The frames of "
             "this section run without the support prior (the same work for every kernel set, mode and "
             "thread count); its cost is in the last table of the section and in bench_peers' table above.\n" % (
                 ctx.get("date", "?"), repetitions_of(data), machine_of(ctx)),
             ]
    keys = sorted(med)
    scenes = sorted({k[0] for k in keys}, key=lambda s: (not s.startswith("synthetic"), s))
    kernel_order = ["scalar", "sse2", "avx2", "neon"]
    lines.append("### Per stage, one thread\n")
    lines.append("| scene | D | mode | kernels | tritree | cost aggregation | DP | interpolation | total | "
                 "cost speed-up vs scalar | total speed-up vs scalar | Mdisp/s |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for s in scenes:
        for d in sorted({k[1] for k in keys if k[0] == s}):
            for mode in ("sparse", "dense"):
                base = med.get((s, d, mode, "scalar", 1))
                for kern in kernel_order:
                    b = med.get((s, d, mode, kern, 1))
                    if not b:
                        continue
                    lines.append("| %s | %d | %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %s | %s | %.0f |" % (
                        s, d, mode, kern, b["tritree_ms"], b["cost_ms"], b["dp_ms"], b["interp_ms"], b["total_ms"],
                        "%.2fx" % (base["cost_ms"] / b["cost_ms"]) if base else "-",
                        "%.2fx" % (base["total_ms"] / b["total_ms"]) if base else "-", b["Mdisp_per_s"]))
    lines.append("\n### Sparse vs dense, one thread (best kernel set)\n")
    lines.append("*bound*: the sparse frame / dense frame that a sparse frame with no work of its own and "
                 "per-sample work exactly f times the dense frame's would reach, f = samples / pixels: "
                 "(T + C + f R) / dense, with T the dense frame's tritree (both modes build it), C the census "
                 "transform and per-pixel Hamming costs (`census_pixels`, both modes do them at every pixel) "
                 "and R = dense - T - C - the dense interpolation (docs/performance.md, \"Sparse against dense\").\n")
    lines.append("| scene | D | kernels | samples sparse | DP ms sparse / dense | DP ratio | "
                 "cost ms sparse / dense | frame ms sparse / dense | frame ratio | census at every pixel ms | bound |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for s in scenes:
        for d in sorted({k[1] for k in keys if k[0] == s}):
            for kern in reversed(kernel_order):
                sp, de = med.get((s, d, "sparse", kern, 1)), med.get((s, d, "dense", kern, 1))
                if sp and de:
                    c = census.get((s, d))
                    bound = "-"
                    if c is not None:
                        f = sp["samples"] / de["samples"]
                        rest = de["total_ms"] - de["tritree_ms"] - c - de["interp_ms"]
                        bound = "%.3f" % ((de["tritree_ms"] + c + f * rest) / de["total_ms"])
                    lines.append("| %s | %d | %s | %d | %.2f / %.2f | %.3f | %.2f / %.2f | %.2f / %.2f | %.3f | %s | %s |" % (
                        s, d, kern, sp["samples"], sp["dp_ms"], de["dp_ms"], sp["dp_ms"] / de["dp_ms"],
                        sp["cost_ms"], de["cost_ms"], sp["total_ms"], de["total_ms"], sp["total_ms"] / de["total_ms"],
                        "%.2f" % c if c is not None else "-", bound))
                    break
    lines.append("\n### Threads (best kernel set, synthetic 640x480)\n")
    lines.append("| D | mode | threads | tritree | cost aggregation | DP | interpolation | total | speed-up vs 1 thread |")
    lines.append("|---|---|---|---|---|---|---|---|---|")
    for (s, d, mode, kern, t) in keys:
        if not s.startswith("synthetic"):
            continue
        if not any(k[4] > 1 for k in keys if k[:4] == (s, d, mode, kern)):
            continue
        b, one = med[(s, d, mode, kern, t)], med[(s, d, mode, kern, 1)]
        lines.append("| %d | %s | %d (%s) | %.2f | %.2f | %.2f | %.2f | %.2f | %.2fx |" % (
            d, mode, t, kern, b["tritree_ms"], b["cost_ms"], b["dp_ms"], b["interp_ms"], b["total_ms"],
            one["total_ms"] / b["total_ms"]))
    if pairs:
        lines.append("\n### Threads, paired frames (best kernel set)\n")
        lines.append("`frame_pair/...`: frames of a 1-thread and an N-thread pipeline in alternation, each pair "
                     "meeting the same moment of the machine. Each run takes the median over its pairs; the "
                     "runs are spread over the whole benchmark run by the random interleaving. Shown: the "
                     "median of the runs' medians, and their range. Each pair also runs N independent "
                     "1-thread frames at once, one per pinned CPU: *ceiling* is their throughput over one "
                     "frame's, what the machine gives N cores at that moment without any sharing, and "
                     "*of ceiling* is speed-up / ceiling per pair (1.00: the parallel pipeline loses nothing "
                     "beyond what running N frames side by side costs).\n")
        lines.append("| scene | D | mode | threads | runs x pairs | 1 thread ms | N threads ms | speed-up | "
                     "range of runs | ceiling | of ceiling | tritree | matching (cost + DP) | interpolation |")
        lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for name in sorted(pairs, key=lambda n: (not n.split("/")[1].startswith("synthetic"), n.split("/")[1],
                                                 int(n.split("/")[2][1:]), n)):
            runs = pairs[name]
            _, scene, d, mode, kern, tt = name.split("/")[:6]
            m = lambda key: statistics.median(r[key] for r in runs)
            lines.append("| %s | %s | %s | %s (%s) | %d x %d | %.2f | %.2f | **%.2fx** | %.2f-%.2fx | %.2fx | %.2f | "
                         "%.2fx | %.2fx | %s |" % (
                scene, d[1:], mode, tt.split("_t")[-1], kern, len(runs), runs[0]["pairs"], m("t1_ms"), m("tN_ms"),
                m("speedup"), min(r["speedup"] for r in runs), max(r["speedup"] for r in runs),
                m("ceiling"), m("of_ceiling"),
                m("speedup_tritree"), m("speedup_matching"),
                "%.2fx" % m("speedup_interp") if mode == "sparse" else "-"))
    if priors:
        lines.append("\n### The support prior, one worker\n")
        lines.append("Frames without and with the support prior (docs/model.md section 6b) in alternation "
                     "(`prior_pair`, best kernel set), medians:\n")
        lines.append("| scene | D | frame without ms | frame with ms | prior stage ms | with / without |")
        lines.append("|---|---|---|---|---|---|")
        for (scene, d), b in sorted(priors.items(), key=lambda kv: (not kv[0][0].startswith("synthetic"), kv[0])):
            lines.append("| %s | %d | %.2f | %.2f | %.2f | %.2fx |" % (
                scene, d, b["off_ms"], b["on_ms"], b["prior_ms"], b["ratio"]))
    lines.append("\n### Machine ceiling for 2 threads (bench/bench_machine, before and after the run above)\n")
    lines.append("The same loop on 1 and on 2 pinned threads, each with its own data: items per second "
                 "with 2 threads / with 1. A stage cannot be expected to scale better than the loop it resembles.\n")
    lines.append("| loop | before | after |")
    lines.append("|---|---|---|")
    for loop in sorted(before, key=lambda l: (l != "alu", int(l.split("/")[1]) if "/" in l else 0)):
        lines.append("| %s | %.2fx | %s |" % (describe_loop(loop), before[loop],
                                             "%.2fx" % after[loop] if loop in after else "-"))
    lines.append("\nThe tritree, the stage that scales least (bench/bench_tritree, synthetic 640x480, medians of 5, "
                 "run after the above): the pooled build on 2 workers against 1 took %.2f / %.2f ms, **%.2fx**; "
                 "two independent single-threaded builds side by side ran at **%.2fx** the throughput of one. "
                 "These are separate repetitions, not pairs: on this machine a single-threaded build has "
                 "measured anywhere from 26 to 38 ms within minutes, so compare them only roughly; the "
                 "paired ceiling above is the steadier reference." % (tritree[2], tritree[3], tritree[0], tritree[1]))
    return lines


# The heading each section starts with in the output file.
SECTION_HEADINGS = {"peers": "## tristereo against OpenCV", "pipeline": "## The pipeline"}


def kept_section(path, name):
    """The lines of section `name` in the existing output file, or []."""
    try:
        with open(path) as f:
            text = f.read().split("\n")
    except FileNotFoundError:
        return []
    starts = [i for i, l in enumerate(text) if any(l.startswith(h) for h in SECTION_HEADINGS.values())]
    for k, i in enumerate(starts):
        if text[i].startswith(SECTION_HEADINGS[name]):
            end = starts[k + 1] if k + 1 < len(starts) else len(text)
            return [l for l in text[i:end]]
    return []


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--filter", default="", help="--benchmark_filter for bench_pipeline")
    ap.add_argument("--only", choices=["peers", "pipeline"],
                    help="run only this benchmark; the other's tables come from its JSON of the last run")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "performance-tables.md"))
    ap.add_argument("--reuse", action="store_true",
                    help="write the tables from the JSON files of the last run without running anything")
    a = ap.parse_args()
    global REUSE
    lines = ["# Performance tables\n",
             "Generated by `/usr/bin/python3 scripts/perf_report.py` (docs/performance.md, \"How to measure it on "
             "your own board\", says how to rerun it); each section names the benchmark run it comes from.\n"]
    for name, section in (("peers", peers_section), ("pipeline", pipeline_section)):
        REUSE = a.reuse or (a.only is not None and a.only != name)
        try:
            part = section(a)
            lines += part
            if name == "peers":
                print("\n".join(part))  # the ratios to StereoBM on the console too
        except FileNotFoundError as e:
            if not REUSE:
                raise
            # Keep the section the file already has (it names the run it came from).
            kept = kept_section(a.out, name)
            print("no %s JSON (%s): %s" % (name, e, "kept the file's section" if kept else "section left out"),
                  file=sys.stderr)
            lines += kept
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", a.out)


if __name__ == "__main__":
    main()
