"""The module from many threads: a shared Pipeline gives each caller its own
frame's result, and separate Pipelines run at the same time."""
import os
import subprocess
import sys
import threading
import time

import numpy as np

import tristereo

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get("TRISTEREO_CLI", os.path.join(REPO, "build", "tristereo"))

# Sizes chosen so that a frame of one size can never pass for another's:
# every output array's shape differs between them; pairs of the same size
# differ in content (and in the BGR path: gray or colour arrays).
SIZES = [(96, 64, 1), (64, 48, 2), (128, 96, 3), (40, 30, 4)]


def scenes(tmp_path):
    pairs = []
    for w, h, seed in SIZES:
        d = tmp_path / f"s{w}x{h}"
        subprocess.run([CLI, "synth", d, "--width", str(w), "--height", str(h), "--ndisp", "16",
                        "--seed", str(seed)], check=True, capture_output=True)
        pairs.append((tristereo.read_image(d / "left.png"), tristereo.read_image(d / "right.png")))
    # Two more pairs of the first size (the shape alone cannot tell them apart):
    # the first pair with its images shifted by one column, and mirrored.
    l0, r0 = pairs[0]
    pairs.append((np.ascontiguousarray(np.roll(l0, 1, axis=1)), np.ascontiguousarray(np.roll(r0, 1, axis=1))))
    pairs.append((np.ascontiguousarray(l0[::-1]), np.ascontiguousarray(r0[::-1])))
    return pairs


def colour_pairs(pairs):
    """BGR versions of two pairs (their channels differ), through the
    Pipeline's own gray buffers: those must not be shared between callers either."""
    out = []
    for l, r in pairs[1:3]:
        out.append(tuple(np.ascontiguousarray(np.dstack([x, np.roll(x, 2, axis=1), x[::-1]])) for x in (l, r)))
    return out


def snapshot(out):
    return (out.digest, out.disp_q4.copy(), out.vertices.copy(), out.triangles.copy(), out.vertex_disp_q4.copy())


def same(a, b):
    return a[0] == b[0] and all(np.array_equal(x, y) for x, y in zip(a[1:], b[1:]))


def test_one_pipeline_shared_by_8_threads_gives_each_its_own_result(tmp_path):
    pairs = scenes(tmp_path)
    w = max(p[0].shape[1] for p in pairs)
    h = max(p[0].shape[0] for p in pairs)
    p = tristereo.Pipeline(w, h, ndisp=16, threads=2)
    calls_of = [(l, r, None) for l, r in pairs] + [(l, r, "bgr") for l, r in colour_pairs(pairs)]
    expected = [snapshot(p.process(*c)) for c in calls_of]
    # The eight results are all different, so a swapped one cannot go unseen.
    assert len({e[0] for e in expected}) == len(calls_of)

    calls, threads = 200, 8
    errors = []
    barrier = threading.Barrier(threads)

    def worker(t):
        barrier.wait()  # start together, to overlap as much as possible
        rng = np.random.default_rng(t)
        for i in range(calls):
            k = int(rng.integers(len(calls_of)))
            got = snapshot(p.process(*calls_of[k]))
            if not same(got, expected[k]):
                errors.append((t, i, k, got[0], expected[k][0]))

    old = sys.getswitchinterval()
    sys.setswitchinterval(1e-5)  # switch threads as often as possible
    try:
        ts = [threading.Thread(target=worker, args=(t,)) for t in range(threads)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()
    finally:
        sys.setswitchinterval(old)
    assert not errors, f"{len(errors)} of {calls * threads} results were not the caller's: {errors[:5]}"


def test_outputs_of_earlier_calls_stay_as_they_were(tmp_path):
    # The arrays returned are the caller's: later frames do not change them.
    pairs = scenes(tmp_path)
    p = tristereo.Pipeline(128, 96, ndisp=16, threads=1)
    first = p.process(*pairs[0])
    kept = snapshot(first)
    for l, r in pairs[1:]:
        p.process(l, r)
    assert same(snapshot(first), kept)


def test_separate_pipelines_run_at_the_same_time(tmp_path):
    # A long frame on pipeline A; while it runs, short frames on pipeline B
    # from this thread. B's frame can start and finish inside A's only if A's
    # process() holds neither the GIL nor any lock B needs. With forced GIL
    # switches out of the way (30 s), the outcome does not depend on timing.
    cli_dir = tmp_path / "big"
    subprocess.run([CLI, "synth", cli_dir, "--width", "640", "--height", "480", "--ndisp", "64", "--seed", "7"],
                   check=True, capture_output=True)
    big = tristereo.read_image(cli_dir / "left.png"), tristereo.read_image(cli_dir / "right.png")
    small = scenes(tmp_path)[3]
    a = tristereo.Pipeline(640, 480, ndisp=64, threads=1, dense=True)  # dense: a long frame
    b = tristereo.Pipeline(40, 30, ndisp=16, threads=1)
    state = {"a_calls": 0, "in_a": False, "done": False}

    def run_a():
        for _ in range(3):
            state["in_a"] = True
            a.process(*big)
            state["a_calls"] += 1
            state["in_a"] = False
        state["done"] = True

    inside = 0
    old = sys.getswitchinterval()
    sys.setswitchinterval(30)
    try:
        t = threading.Thread(target=run_a)
        t.start()
        while not state["done"]:
            if state["in_a"]:
                before = state["a_calls"]
                b.process(*small)
                if state["in_a"] and state["a_calls"] == before:
                    inside += 1  # B's whole frame ran while A was inside one frame
            time.sleep(0)
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert inside > 0
