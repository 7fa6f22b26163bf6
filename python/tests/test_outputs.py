"""The module's depth and file writers against `tristereo match`'s files, byte
for byte, from the same frame."""
import filecmp
import os

import numpy as np
import pytest

import tristereo

from test_tristereo import cli, read_pfm, require_data

CAMERA = (200.0, 0.1, 80.0, 60.0, 1.5)  # focal px, baseline m, cx, cy, doffs
CAMERA_ARG = "200,0.1,80,60,1.5"


def same_files(a, b):
    assert filecmp.cmp(a, b, shallow=False), f"{a} and {b} differ"


@pytest.mark.parametrize("ascii_ply", [False, True])
def test_writers_write_the_programs_files(tmp_path, ascii_ply):
    cli("synth", tmp_path, "--width", 160, "--height", 120, "--ndisp", 24, "--seed", 5)
    lp, rp = tmp_path / "left.png", tmp_path / "right.png"
    left, right = tristereo.read_image(lp), tristereo.read_image(rp)
    out = tristereo.Pipeline(160, 120, ndisp=24, threads=1).process(left, right)
    c, p = tmp_path / "cli", tmp_path / "py"
    c.mkdir()
    p.mkdir()
    for disp, depth in (("d.png", "z.pfm"), ("d.pfm", "z.png")):
        args = ["match", lp, rp, "--ndisp", 24, "--threads", 1, "--camera", CAMERA_ARG, "--disp", c / disp,
                "--depth", c / depth]
        if disp == "d.png":
            args += ["--disp-color", c / "c.png", "--mesh", c / "m.ply", "--points", c / "p.ply"]
            if ascii_ply:
                args.append("--mesh-ascii")
        cli(*args)
        tristereo.write_disparity(p / disp, out.disp_q4)
        report = tristereo.write_depth(p / depth, tristereo.depth(out.disp_q4, CAMERA))
        assert report["valid"] + report["invalid"] == 160 * 120
        same_files(c / disp, p / disp)
        same_files(c / depth, p / depth)
    tristereo.write_disparity_color(p / "c.png", out.disp_q4, 0, 24)
    faces = tristereo.write_mesh_ply(p / "m.ply", out, left, camera=CAMERA, binary=not ascii_ply)
    # The program writes measured pixels and vertices only (no --points-include-filled).
    points = tristereo.write_points_ply(p / "p.ply", out.disp_q4, left, CAMERA, binary=not ascii_ply,
                                        state=out.state)
    for name in ("c.png", "m.ply", "p.ply"):
        same_files(c / name, p / name)
    assert faces["faces_written"] > 0 and points > 0
    # The depth array is the PFM's, NaN where the PFM has +inf.
    z, zf = tristereo.depth(out.disp_q4, CAMERA), read_pfm(c / "z.pfm")
    assert np.array_equal(np.isnan(z), np.isinf(zf)) and np.array_equal(z[~np.isnan(z)], zf[~np.isinf(zf)])
    valid = ~np.isnan(z)
    d = out.disparity[valid]
    assert np.allclose(z[valid], 200.0 * 0.1 / (d + 1.5), rtol=1e-6)


def test_bgr_colours_in_the_mesh_are_the_pngs(tmp_path):
    try:
        import cv2
    except ImportError:
        pytest.fail("OpenCV's Python module is missing (Debian: python3-opencv; scripts/install-deps.sh test)")
    d = os.path.join(require_data("middlebury"), "teddy")
    lp, rp = os.path.join(d, "left.png"), os.path.join(d, "right.png")
    left, right = cv2.imread(lp), cv2.imread(rp)
    h, w = left.shape[:2]
    out = tristereo.Pipeline(w, h, ndisp=64, threads=1).process(left, right, order="bgr")
    cli("match", lp, rp, "--ndisp", 64, "--threads", 1, "--mesh", tmp_path / "cli.ply")
    tristereo.write_mesh_ply(tmp_path / "py.ply", out, left, order="bgr")
    same_files(tmp_path / "cli.ply", tmp_path / "py.ply")


def test_writer_arguments_are_checked(tmp_path):
    out = tristereo.Pipeline(48, 32, ndisp=8).process(*(np.full((32, 48), 9, np.uint8),) * 2)
    with pytest.raises(ValueError, match="disp_q4 must be an int16"):
        tristereo.write_disparity(tmp_path / "d.png", out.disparity)
    with pytest.raises(ValueError, match="png_scale must be"):
        tristereo.write_disparity(tmp_path / "d.png", out.disp_q4, png_scale="x")
    with pytest.raises(TypeError, match="camera must be a Calibration or"):
        tristereo.depth(out.disp_q4, (1.0, 2.0))
    with pytest.raises(ValueError, match="focal length and baseline must be > 0"):
        tristereo.depth(out.disp_q4, (0.0, 0.1, 1.0, 1.0))
    with pytest.raises(ValueError, match="out of range"):
        tristereo.depth(out.disp_q4, (1e300, 0.1, 1.0, 1.0))
    with pytest.raises(ValueError):
        tristereo.write_disparity(tmp_path / "d.tiff", out.disp_q4)
    assert not os.path.exists(tmp_path / "d.tiff")
    with pytest.raises(OSError):
        tristereo.write_disparity(tmp_path / "missing" / "d.png", out.disp_q4)


@pytest.mark.parametrize("min_confidence", [0, 144])
def test_state_and_confidence_are_the_programs_pngs_on_a_real_pair(tmp_path, min_confidence):
    """Output.state and Output.confidence equal `match --valid/--confidence`
    on KITTI 2015 000000, with and without a minimum confidence."""
    folder = require_data("kitti2015")
    lp, rp = os.path.join(folder, "000000", "left.png"), os.path.join(folder, "000000", "right.png")
    left, right = tristereo.read_image(lp), tristereo.read_image(rp)
    h, w = left.shape[:2]
    out = tristereo.Pipeline(w, h, ndisp=80, threads=2, min_confidence=min_confidence).process(
        left, right, order="rgb")
    cli("match", lp, rp, "--ndisp", 80, "--threads", 1, "--min-confidence", min_confidence,
        "--valid", tmp_path / "v.png", "--confidence", tmp_path / "c.png", "--disp", tmp_path / "d.pfm")
    import cv2
    valid = cv2.imread(str(tmp_path / "v.png"), cv2.IMREAD_UNCHANGED)
    conf = cv2.imread(str(tmp_path / "c.png"), cv2.IMREAD_UNCHANGED)
    assert valid.dtype == np.uint8 and valid.shape == (h, w)
    assert np.array_equal(out.state, valid)
    assert np.array_equal(out.confidence, conf)
    # The disparity is invalid exactly where the state says so.
    assert np.array_equal(np.isinf(read_pfm(tmp_path / "d.pfm")), out.state == 0)
    assert np.array_equal(np.isnan(out.disparity), out.state == 0)
    # Every state occurs without the minimum; with 144 none is filled and
    # every valid pixel is at least that confident.
    counts = np.bincount(out.state.ravel(), minlength=3)
    if min_confidence == 0:
        assert counts[1] > 0 and counts[2] > counts[1]
        assert out.filled > 0 and out.min_confidence_rejected == 0
        assert np.count_nonzero(out.vertex_state == 1) == out.filled
    else:
        assert counts[1] == 0 and counts[2] > 0
        assert out.min_confidence_rejected > 0
        assert np.all(out.confidence[out.state != 0] >= min_confidence)
    assert np.array_equal(out.state, np.where(out.confidence == 0, 0, np.where(out.confidence < 128, 1, 2)))


def test_mesh_and_points_keep_filled_ones_only_when_asked(tmp_path):
    cli("synth", tmp_path, "--width", 160, "--height", 120, "--ndisp", 24, "--seed", 5)
    lp, rp = tmp_path / "left.png", tmp_path / "right.png"
    left, right = tristereo.read_image(lp), tristereo.read_image(rp)
    out = tristereo.Pipeline(160, 120, ndisp=24, threads=1).process(left, right)
    cli("match", lp, rp, "--ndisp", 24, "--threads", 1, "--camera", CAMERA_ARG, "--mesh", tmp_path / "m.ply",
        "--points", tmp_path / "p.ply", "--points-include-filled")
    all_faces = tristereo.write_mesh_ply(tmp_path / "pm.ply", out, left, camera=CAMERA, include_filled=True)
    all_points = tristereo.write_points_ply(tmp_path / "pp.ply", out.disp_q4, left, CAMERA)
    same_files(tmp_path / "m.ply", tmp_path / "pm.ply")
    same_files(tmp_path / "p.ply", tmp_path / "pp.ply")
    measured_faces = tristereo.write_mesh_ply(tmp_path / "mm.ply", out, left, camera=CAMERA)
    measured_points = tristereo.write_points_ply(tmp_path / "mp.ply", out.disp_q4, left, CAMERA, state=out.state)
    assert measured_points == np.count_nonzero(out.state == 2) < all_points
    assert 0 < measured_faces["faces_written"] < all_faces["faces_written"]
    with pytest.raises(ValueError, match="state must be a uint8"):
        tristereo.write_points_ply(tmp_path / "x.ply", out.disp_q4, left, CAMERA, state=out.state[:10])


def test_depth_limits_are_the_programs(tmp_path):
    """depth(), write_points_ply() and write_mesh_ply() keep what match's
    --min-disparity/--min-depth/--max-depth keep, byte for byte."""
    cli("synth", tmp_path, "--width", 160, "--height", 120, "--ndisp", 24, "--seed", 3)
    lp, rp = tmp_path / "left.png", tmp_path / "right.png"
    left, right = tristereo.read_image(lp), tristereo.read_image(rp)
    out = tristereo.Pipeline(160, 120, ndisp=24, threads=1).process(left, right)
    z_all = tristereo.depth(out.disp_q4, CAMERA, min_disparity=0)
    lo, hi = np.nanpercentile(z_all, [25, 75])
    for limits, args in (({}, []), ({"min_disparity": 10.0}, ["--min-disparity", "10"]),
                         ({"min_depth": lo, "max_depth": hi}, ["--min-depth", repr(lo), "--max-depth", repr(hi)])):
        c = tmp_path / f"c{len(args)}"
        c.mkdir()
        cli("match", lp, rp, "--ndisp", 24, "--threads", 1, "--camera", CAMERA_ARG, "--depth", c / "z.pfm",
            "--points", c / "p.ply", "--mesh", c / "m.ply", *args)
        z = tristereo.depth(out.disp_q4, CAMERA, **limits)
        zf = read_pfm(c / "z.pfm")
        assert np.array_equal(np.isnan(z), np.isinf(zf)) and np.array_equal(z[~np.isnan(z)], zf[~np.isinf(zf)])
        kept = z[~np.isnan(z)]
        assert kept.size > 0
        if "min_depth" in limits:
            assert kept.min() >= np.float32(lo) * (1 - 1e-6) and kept.max() <= np.float32(hi) * (1 + 1e-6)
            assert kept.size < z_all[~np.isnan(z_all)].size
        tristereo.write_points_ply(c / "pp.ply", out.disp_q4, left, CAMERA, state=out.state, **limits)
        tristereo.write_mesh_ply(c / "pm.ply", out, left, camera=CAMERA, **limits)
        same_files(c / "p.ply", c / "pp.ply")
        same_files(c / "m.ply", c / "pm.ply")
    for bad, word in (({"min_disparity": -1.0}, "min_disparity"), ({"max_depth": float("inf")}, "max_depth"),
                      ({"min_depth": 3.0, "max_depth": 2.0}, "max_depth_m must be above")):
        with pytest.raises(ValueError, match=word):
            tristereo.depth(out.disp_q4, CAMERA, **bad)
