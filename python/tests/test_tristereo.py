"""The Python bindings against the C++ program, bit for bit, and their behaviour
on bad input, strides, the GIL and repeated calls.

Environment: TRISTEREO_CLI (the tristereo program of the same build),
TRISTEREO_DATA_DIR (default: ../shared/data beside the repository),
TRISTEREO_ALLOW_MISSING_DATA=1 (tests that need the data skip instead of failing).
"""
import os
import re
import subprocess
import sys
import threading
import time
import tracemalloc

import numpy as np
import pytest

import tristereo

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get("TRISTEREO_CLI", os.path.join(REPO, "build", "tristereo"))
DATA = os.environ.get("TRISTEREO_DATA_DIR", os.path.join(os.path.dirname(REPO), "shared", "data"))


def require_data(data_set):
    """The project's rule for missing data: fail naming the folder, unless allowed."""
    folder = os.path.join(DATA, data_set)
    if os.path.isfile(os.path.join(folder, "datasets.tsv")):
        return folder
    if os.environ.get("TRISTEREO_ALLOW_MISSING_DATA") == "1":
        pytest.skip(f"no {folder} (TRISTEREO_ALLOW_MISSING_DATA=1)")
    pytest.fail(f"stereo data set '{data_set}' not found at {folder} (put ../shared beside the "
                "project, or set TRISTEREO_ALLOW_MISSING_DATA=1 to skip the tests that need it)")


def ndisp_of(folder, scene):
    with open(os.path.join(folder, "datasets.tsv")) as f:
        header = f.readline().split()
        col = header.index("ndisp")
        for line in f:
            fields = line.split()
            if fields and fields[0] == scene:
                return int(fields[col])
    raise AssertionError(f"{scene} not in {folder}/datasets.tsv")


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"Pf"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4", count=w * h)
    return data.reshape(h, w)[::-1]


def cli(*args):
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True).stdout


def check_equals_cpp(left_path, right_path, ndisp, tmp_path):
    """Module output == the C++ program's, on the same files with the defaults."""
    left, right = tristereo.read_image(left_path), tristereo.read_image(right_path)
    h, w = left.shape[:2]
    out = tristereo.Pipeline(w, h, ndisp=ndisp).process(left, right, order="rgb" if left.ndim == 3 else None)
    # The whole output (mesh, sample disparities, dense map): its digest is the
    # float reference's, as `tristereo verify` prints it.
    text = cli("verify", left_path, right_path, "--ndisp", ndisp, "--thread-counts", "1")
    assert "\nbit-exact" in "\n" + text, text
    assert re.search(r"reference digest ([0-9a-f]+)", text).group(1) == out.digest
    # The dense map, array for array, against `match --disp X.pfm`.
    pfm = tmp_path / "disp.pfm"
    cli("match", left_path, right_path, "--ndisp", ndisp, "--disp", pfm, "--threads", "1")
    cpp = read_pfm(pfm)
    valid = out.disp_q4 != tristereo.INVALID_DISP_Q4
    assert np.array_equal(np.isinf(cpp), ~valid)
    assert np.array_equal(cpp[valid], out.disparity[valid])
    assert np.array_equal(np.isnan(out.disparity), ~valid)
    assert np.array_equal(out.disparity[valid] * 16, out.disp_q4[valid].astype(np.float32))
    assert out.vertices.shape == (out.vertex_disp_q4.shape[0], 2)
    assert out.triangles.shape[1] == 3 and out.triangles.max() < out.vertices.shape[0]
    return out


def test_synthetic_scene_equals_cpp(tmp_path):
    cli("synth", tmp_path, "--width", 160, "--height", 120, "--ndisp", 24, "--seed", 5)
    check_equals_cpp(tmp_path / "left.png", tmp_path / "right.png", 24, tmp_path)


@pytest.mark.parametrize("data_set,scene", [
    ("middlebury", "tsukuba"), ("middlebury", "venus"), ("middlebury", "teddy"), ("middlebury", "cones"),
    ("middlebury2014", "adirondack"), ("middlebury2014", "motorcyclee"),
    ("kitti2015", "000000"), ("eth3d", "playground"),
])
def test_shared_data_equals_cpp(data_set, scene, tmp_path):
    folder = require_data(data_set)
    d = os.path.join(folder, scene)
    check_equals_cpp(os.path.join(d, "left.png"), os.path.join(d, "right.png"), ndisp_of(folder, scene), tmp_path)


def scene_arrays(tmp_path, w=96, h=64, ndisp=16):
    cli("synth", tmp_path, "--width", w, "--height", h, "--ndisp", ndisp, "--seed", 3)
    return tristereo.read_image(tmp_path / "left.png"), tristereo.read_image(tmp_path / "right.png")


def test_working_memory_is_the_programs(tmp_path):
    # The same library call as `tristereo info` for the same configuration.
    p = tristereo.Pipeline(320, 240, ndisp=32, threads=1)
    text = cli("info", "--max-size", "320x240", "--ndisp", 32, "--threads", 1)
    line = next(l for l in text.splitlines() if l.startswith("working memory: "))
    assert p.working_memory_bytes == int(line.split()[2]), line
    assert p.working_memory_bytes > 320 * 240  # tens of bytes per configured pixel


def test_strides_and_colour_give_the_same_frame(tmp_path):
    left, right = scene_arrays(tmp_path)
    h, w = left.shape
    p = tristereo.Pipeline(w, h, ndisp=16, threads=1)
    ref = p.process(left, right).digest
    # Padded rows (a crop of a wider array): used in place.
    big_l = np.zeros((h, w + 13), np.uint8)
    big_r = np.zeros((h, w + 13), np.uint8)
    big_l[:, 5:5 + w], big_r[:, 5:5 + w] = left, right
    assert p.process(big_l[:, 5:5 + w], big_r[:, 5:5 + w]).digest == ref
    # Every second column of a doubled array (not packed): copied, same answer.
    wide_l = np.repeat(left, 2, axis=1)
    wide_r = np.repeat(right, 2, axis=1)
    assert p.process(wide_l[:, ::2], wide_r[:, ::2]).digest == ref
    # RGB with three equal channels is the same gray image (BT.601 weights sum to 256).
    rgb_l, rgb_r = np.dstack([left] * 3), np.dstack([right] * 3)
    assert p.process(rgb_l, rgb_r, order="rgb").digest == ref
    assert p.process(rgb_l, rgb_r, order="bgr").digest == ref
    # (H, W, 1) is gray too.
    assert p.process(left[:, :, None], right[:, :, None]).digest == ref
    # A Fortran-ordered array.
    assert p.process(np.asfortranarray(left), np.asfortranarray(right)).digest == ref


def test_tritree_keywords_are_the_programs(tmp_path):
    # psnr, max_area and min_area as `match --psnr --max-area --min-area`: the same mesh.
    cli("synth", tmp_path, "--width", 96, "--height", 64, "--ndisp", 16, "--seed", 3)
    left, right = tristereo.read_image(tmp_path / "left.png"), tristereo.read_image(tmp_path / "right.png")
    stats = tmp_path / "stats.json"
    counts = []
    for min_area in (1, 2, 8):
        out = tristereo.Pipeline(96, 64, ndisp=16, psnr=40, max_area=64, min_area=min_area).process(left, right)
        cli("match", tmp_path / "left.png", tmp_path / "right.png", "--ndisp", 16, "--psnr", 40, "--max-area", 64,
            "--min-area", min_area, "--stats", stats)
        assert f'"vertices": {out.vertices.shape[0]},' in stats.read_text()
        counts.append(out.vertices.shape[0])
    assert counts[0] > counts[1] > counts[2]  # a larger minimum area keeps fewer samples
    with pytest.raises(ValueError, match=r"^min_area = 33 is out of range \[1, 32\]"):
        tristereo.Pipeline(96, 64, ndisp=16, min_area=33)


def test_bad_input_raises_with_the_library_message(tmp_path):
    left, right = scene_arrays(tmp_path)
    h, w = left.shape
    p = tristereo.Pipeline(w, h, ndisp=16)
    with pytest.raises(ValueError, match="uint8"):
        p.process(left.astype(np.float32), right)
    with pytest.raises(ValueError, match="shape"):
        p.process(left[None], right[None])
    with pytest.raises(ValueError):
        p.process(left, right[:, :-1])  # sizes differ
    with pytest.raises(ValueError):
        p.process(np.zeros((h + 1, w), np.uint8), np.zeros((h + 1, w), np.uint8))  # above the maximum
    with pytest.raises(ValueError, match=r"^ndisp = 0 is out of range \[1, 256\]"):
        tristereo.Pipeline(w, h, ndisp=0)
    with pytest.raises(ValueError, match="window"):
        tristereo.Pipeline(w, h, ndisp=16, window=4)
    with pytest.raises(TypeError, match="unexpected keyword argument 'ndisps'"):
        tristereo.Pipeline(w, h, ndisps=16)
    with pytest.raises(OSError, match="nope.png"):
        tristereo.read_image(tmp_path / "nope.png")
    bad = tmp_path / "calib.txt"
    bad.write_text("cam0=[1 0 2; 0 1 3; 0 0 1]\ndoffs=0\n")
    with pytest.raises(ValueError, match="key 'baseline'"):
        tristereo.read_calibration(str(bad))


def test_verify_and_calibration(tmp_path):
    left, right = scene_arrays(tmp_path)
    report = tristereo.verify(left, right, ndisp=16, thread_counts=[1, 2])
    assert report.bit_exact
    assert len(report.cases) >= 2 and all(c["identical"] for c in report.cases)
    folder = require_data("middlebury2014")
    c = tristereo.read_calibration(os.path.join(folder, "adirondack", "calib.txt"))
    assert (c.format, c.focal_px, c.doffs_px, c.width, c.height) == ("middlebury", 1038.018, 53.271, 718, 496)
    assert c.baseline_m == pytest.approx(0.176252, rel=1e-12)  # 176.252 mm


def test_process_releases_the_gil(tmp_path):
    left, right = scene_arrays(tmp_path, 320, 240, 32)
    p = tristereo.Pipeline(320, 240, ndisp=32, threads=1)
    p.process(left, right)
    state = {"in_call": False, "done": False}
    seen = [0]

    def worker():
        for _ in range(5):
            state["in_call"] = True
            p.process(left, right)
            state["in_call"] = False
        state["done"] = True

    # With forced GIL switches out of the way (30 s), this thread can run while
    # the worker is inside process() only if process() released the GIL:
    # the outcome does not depend on timing.
    old = sys.getswitchinterval()
    sys.setswitchinterval(30)
    try:
        t = threading.Thread(target=worker)
        t.start()
        while not state["done"]:
            if state["in_call"]:
                seen[0] += 1
            time.sleep(0)  # releases the GIL, so the worker can take it back
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert seen[0] > 0


def rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def test_no_leak_over_1000_calls(tmp_path):
    left, right = scene_arrays(tmp_path)
    p = tristereo.Pipeline(left.shape[1], left.shape[0], ndisp=16, threads=1)
    for _ in range(100):
        p.process(left, right)
    tracemalloc.start()
    rss0 = rss_kib()
    snap0 = tracemalloc.take_snapshot()
    for _ in range(1000):
        out = p.process(left, right)
    del out
    grown = sum(s.size_diff for s in tracemalloc.take_snapshot().compare_to(snap0, "filename"))
    rss1 = rss_kib()
    tracemalloc.stop()
    # Measured: a few KiB of Python objects either way, RSS flat within 1 MiB.
    assert grown < 64 * 1024, grown
    assert rss1 - rss0 < 4096, (rss0, rss1)


def test_out_fills_an_earlier_output_again(tmp_path):
    a = scene_arrays(tmp_path / "a")
    b = [np.ascontiguousarray(x[:, ::-1]) for x in a]  # another frame of the same size
    p = tristereo.Pipeline(96, 64, ndisp=16, threads=1)
    fresh_a, fresh_b = p.process(*a), p.process(*b)
    assert fresh_a.digest != fresh_b.digest
    out = p.process(*a)
    assert out.digest == fresh_a.digest  # computed, and cached, before the refill
    disparity, disp_q4 = out.disparity, out.disp_q4
    again = p.process(*b, out=out)
    assert again is out
    assert again.disparity is disparity and again.disp_q4 is disp_q4  # the same arrays, refilled
    assert again.digest == fresh_b.digest
    assert np.array_equal(again.disp_q4, fresh_b.disp_q4)
    assert np.array_equal(again.vertices, fresh_b.vertices)
    assert np.array_equal(again.disparity, fresh_b.disparity, equal_nan=True)
    # Another size: new arrays of that size.
    small = scene_arrays(tmp_path / "s", 48, 32, 16)
    resized = p.process(*small, out=out)
    assert resized.disparity.shape == (32, 48) and resized.disparity is not disparity
    # A failed call leaves the output as it was.
    kept = (resized.digest, resized.disparity, resized.vertices.copy())
    with pytest.raises(ValueError):
        p.process(*a, out=resized, order="rgb")  # gray arrays with order='rgb'
    with pytest.raises(ValueError):
        p.process(np.zeros((65, 96), np.uint8), np.zeros((65, 96), np.uint8), out=resized)  # above the maximum
    assert resized.digest == kept[0] and resized.disparity is kept[1] and np.array_equal(resized.vertices, kept[2])
    with pytest.raises(TypeError, match="out must be an Output or None"):
        p.process(*a, out=np.zeros((64, 96), np.float32))


def test_out_allocates_no_dense_arrays(tmp_path):
    # NumPy reports its arrays' memory to tracemalloc: with out= a call's peak
    # lacks the two dense arrays a fresh output allocates.
    left, right = scene_arrays(tmp_path, 320, 240, 32)
    p = tristereo.Pipeline(320, 240, ndisp=32, threads=1)
    out = p.process(left, right)
    dense = out.disp_q4.nbytes + out.disparity.nbytes

    def peak(reuse):
        nonlocal out
        tracemalloc.start()
        for _ in range(10):
            out = p.process(left, right, out=out if reuse else None)
        _, top = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        return top

    fresh, refilled = peak(False), peak(True)
    assert fresh - refilled >= 0.9 * dense, (fresh, refilled, dense)
