"""The Python keywords against the command line's model options: the same
options, defaults and ranges, refused and accepted alike; keywords that the
chosen model does not use are refused; values of the wrong kind get messages
that name the keyword; colour arrays say their channel order."""
import json
import os
import re
import subprocess

import numpy as np
import pytest

import tristereo

from test_tristereo import CLI, DATA, cli, read_pfm, require_data

# Options that need others to reach their whole range (the table marks the
# narrowed ones; the path penalties' sum must also fit 16 bits: a 3x3 census
# keeps the largest cost small enough).
CONTEXT = {
    "max_area": {"min_area": 1},
    "min_area": {"max_area": 1024},
    "dmin": {"ndisp": 1},
    "p1": {"p2": 16000, "census": 3},
    "p2": {"p1": 0, "census": 3},
    "gamma_color": {"cost": "ad", "weights": "adaptive"},
    "gamma_proximity": {"cost": "ad", "weights": "adaptive"},
    "weights": {"cost": "ad"},
    "truncation": {"cost": "ad"},
    "ad_weight": {"cost": "ad_census"},
    "lambda_q4": {"optimizer": "dp"},
    "gap": {"optimizer": "dp"},
    "support_trunc": {"support_prior": 300},
    "support_conf": {"support_prior": 300},
    "support_uniqueness": {"support_prior": 300},
    "plane_seg_fine": {"support_prior": 300},
    "plane_seg_coarse": {"support_prior": 300},
    "plane_min": {"support_prior": 300},
    "plane_tol": {"support_prior": 300},
}


def help_options():
    """{option: (metavar, text)} of `tristereo match --help`'s model options."""
    text = cli("match", "--help")
    section = text[text.index("Model options"):text.index("Run options")]
    entries = {}
    for m in re.finditer(r"^  --([a-z0-9-]+)(?: (\S+))?(.*?)(?=^  --|\Z)", section, re.M | re.S):
        entries[m.group(1)] = (m.group(2) or "", " ".join(m.group(3).split()))
    return entries


def cli_text(value):
    """A Python keyword's value as the command line's option text."""
    if isinstance(value, bool):
        raise AssertionError("flags have no text")
    if isinstance(value, tuple):
        return f"{value[0]}x{value[1]}"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def cli_args(kw):
    args = []
    for k, v in kw.items():
        o = OPTIONS[k]
        args += [o["option"], cli_text(v)]
    return args


OPTIONS = {o["keyword"]: o for o in tristereo.model_options()}


def test_every_cli_model_option_is_a_keyword_with_its_default_and_range():
    entries = help_options()
    assert len(entries) >= 25, entries
    by_option = {o["option"]: o for o in OPTIONS.values()}
    assert sorted(by_option) == sorted("--" + name for name in entries)
    defaults = tristereo.Pipeline(64, 48, ndisp=16).params
    for name, (metavar, text) in entries.items():
        o = by_option["--" + name]
        if o["kind"] == "flag":
            # --dense is dense=True, --no-subpixel is subpixel=False: off by default.
            assert defaults[o["keyword"]] == (o["keyword"] == "subpixel"), name
            continue
        if name == "ndisp":
            assert "(required)" in text
            with pytest.raises(ValueError, match="^ndisp is required"):
                tristereo.Pipeline(64, 48)
        else:
            default = re.search(r"\(default ([^;)]+)", text).group(1)
            assert default == (o["default"] if name == "mode" else cli_text(defaults[o["keyword"]])), name
            assert o["default"] == (defaults.get(o["keyword"]) if name != "mode" else "default")
        if o["kind"] == "choice":
            assert metavar.split("|") == [str(c) for c in o["choices"]], name
        else:
            lo, hi = re.findall(r"(-?[0-9.]+)\.\.(-?[0-9.]+)", text)[-1]
            assert (float(lo), float(hi)) == (o["min"], o["max"]), name


def cli_accepts(kw, ndisp=16):
    """Whether `tristereo match` takes these options: usage errors (exit 2)
    come before the (missing) images are opened (exit 1)."""
    args = ["match", "nope.png", "nope.png"] + (["--ndisp", str(ndisp)] if "ndisp" not in kw else [])
    r = subprocess.run([CLI, *args, *cli_args(kw)], capture_output=True, text=True)
    assert r.returncode in (1, 2), r.stderr
    return r.returncode == 1, r.stderr.strip()


def py_accepts(kw, ndisp=16):
    if "ndisp" in kw:
        kw = dict(kw)
        ndisp = kw.pop("ndisp")
    try:
        tristereo.Pipeline(64, 48, ndisp=ndisp, threads=1, **kw)
        return True, ""
    except ValueError as e:
        return False, str(e)


def probes(o):
    if o["kind"] == "choice":
        return [c for c in o["choices"]] + (["bogus"] if isinstance(o["choices"][0], str) else [5])
    if o["kind"] == "decimal":
        return [o["min"] - 0.1, o["min"], o["max"], o["max"] + 0.1]
    lo, hi = o["min"], o["max"]
    values = [lo - 1, lo, hi, hi + 1]
    if o["kind"] == "size":
        return [(v, lo) for v in values]  # the other side at its smallest: W*H stays small
    return values


@pytest.mark.parametrize("keyword", [k for k, o in OPTIONS.items() if o["kind"] != "flag"])
def test_python_and_cli_accept_and_refuse_the_same_values(keyword):
    o = OPTIONS[keyword]
    for value in probes(o):
        kw = {**CONTEXT.get(keyword, {}), keyword: value}
        cli_ok, cli_msg = cli_accepts(kw)
        py_ok, py_msg = py_accepts(kw)
        assert cli_ok == py_ok, (kw, cli_msg, py_msg)
        if o["kind"] != "choice":
            # The table's range, when nothing narrows it, is exactly what is accepted.
            inside = o["min"] <= (value[0] if isinstance(value, tuple) else value) <= o["max"]
            assert py_ok == inside, (kw, py_msg)
        if not py_ok:
            # Both name the option as their user spells it.
            assert py_msg.startswith(keyword), py_msg
            assert o["option"] in cli_msg, cli_msg
            assert "Unable to cast" not in py_msg and "_q4 =" not in py_msg.replace("lambda_q4", "")


def other_value(needed, values):
    """A value of option `needed` outside `values` ("dp", "ad|ad_census", "!-1"; a flag's bool)."""
    if isinstance(values, bool):
        return not values
    if values.startswith("!"):
        return int(values[1:])
    return next(c for c in OPTIONS[needed]["choices"] if str(c) not in values.split("|"))


@pytest.mark.parametrize("keyword", [k for k, o in OPTIONS.items() if o["needs"]])
def test_keywords_of_another_model_are_refused(keyword):
    o = OPTIONS[keyword]
    needed, values = o["needs"]
    value = o["default"]
    wrong = other_value(needed, values)
    with pytest.raises(ValueError, match=rf"^{keyword} has no effect with {needed}=.*: it is used only with {needed}"):
        tristereo.Pipeline(64, 48, ndisp=16, **{needed: wrong, keyword: value})
    # With the model it belongs to, the same keyword is taken.
    if isinstance(values, bool):
        right = values
    else:
        right = values.split("|")[0] if not values.startswith("!") else 16
        right = int(right) if isinstance(OPTIONS[needed]["default"], int) else right
    extra = {"cost": "ad"} if keyword in ("gamma_color", "gamma_proximity") else {}
    p = tristereo.Pipeline(64, 48, ndisp=16, **{**extra, needed: right, keyword: value})
    assert p.params[keyword] == value


def test_support_prior_keywords_are_refused_in_dense_mode():
    # On by default, the prior works on the mesh: dense frames go without it,
    # and its keywords have no effect there; turning it off is always taken.
    for keyword, value in (("support_prior", 300), ("support_trunc", 4), ("plane_min", 6)):
        with pytest.raises(ValueError, match=rf"^{keyword} has no effect with dense=True: the support prior works"):
            tristereo.Pipeline(64, 48, ndisp=16, dense=True, **{keyword: value})
    assert tristereo.Pipeline(64, 48, ndisp=16, dense=True, support_prior=0).params["support_prior"] == 0
    assert tristereo.Pipeline(64, 48, ndisp=16).params["support_prior"] == 300


def test_paper_mode_and_keywords_change_the_output_like_the_cli(tmp_path):
    cli("synth", tmp_path, "--width", 160, "--height", 120, "--ndisp", 24, "--seed", 5)
    left, right = (tristereo.read_image(tmp_path / n) for n in ("left.png", "right.png"))
    stats = tmp_path / "stats.json"
    digests = set()
    for kw in [{}, {"mode": "paper"}, {"mode": "paper", "lambda_q4": 80, "gap": "inv"},
               {"paths": 8, "p1": 100, "p2": 600, "p2_edge": 0, "uniqueness": 20},
               {"cost": "ad_census", "ad_weight": 16, "census": (7, 5), "lr_max_diff": 8, "lr_source": "mirror"},
               {"fill": "none"}, {"window": 5, "subpixel": False}, {"cost": "ad", "weights": "adaptive",
                                                                     "gamma_color": 12, "truncation": 20}]:
        out = tristereo.Pipeline(160, 120, ndisp=24, threads=1, **kw).process(left, right)
        args = ["match", tmp_path / "left.png", tmp_path / "right.png", "--ndisp", 24, "--threads", 1,
                "--stats", stats, "--disp", tmp_path / "d.pfm"] + cli_args({k: v for k, v in kw.items()
                                                                            if k != "subpixel"})
        if kw.get("subpixel") is False:
            args.append("--no-subpixel")
        cli(*args)
        s = json.loads(stats.read_text())
        assert s["vertices"] == out.vertices.shape[0], kw
        # The rejection counts are the command line's.
        assert (out.samples, out.uniqueness_rejected, out.lr_rejected, out.filled, out.prior_redecided,
                out.prior_recovered, out.prior_lost) == (
            s["validity"]["samples"], s["validity"]["uniqueness_rejected"], s["validity"]["lr_rejected"],
            s["validity"]["filled"], s["validity"]["prior_redecided"], s["validity"]["prior_recovered"],
            s["validity"]["prior_lost"]), kw
        cpp = read_pfm(tmp_path / "d.pfm")
        valid = out.disp_q4 != tristereo.INVALID_DISP_Q4
        assert np.array_equal(np.isinf(cpp), ~valid) and np.array_equal(cpp[valid], out.disparity[valid]), kw
        digests.add(out.digest)
    assert len(digests) == 8  # each set of keywords changed the output
    # The default model's checks reject some samples on this scene, and fill them.
    out = tristereo.Pipeline(160, 120, ndisp=24).process(left, right)
    assert out.uniqueness_rejected > 0 and out.lr_rejected > 0
    # The support prior chooses some again: it gives some invalid samples a
    # disparity and may take one from a valid sample; the fill gives the rest one.
    assert out.prior_redecided > 0 and out.timings_ms["prior"] > 0
    assert out.filled == out.uniqueness_rejected + out.lr_rejected - out.prior_recovered + out.prior_lost
    assert tristereo.Pipeline(160, 120, ndisp=24, fill="none").process(left, right).filled == 0


def test_values_of_the_wrong_kind_name_the_keyword():
    cases = [
        (dict(window="abc"), ValueError, r"^window: 'abc' is not a size \(W or WxH"),
        (dict(window=(3, "a")), TypeError, r"^window must be an int, a \(width, height\) pair"),
        (dict(threads=10**12), ValueError, r"^threads must be 0 \(one per CPU\) \.\. 256, got 1000000000000$"),
        (dict(threads=-1), ValueError, r"^threads must be 0"),
        (dict(threads="2"), TypeError, r"^threads must be an int, got str '2'"),
        (dict(psnr=float("nan")), ValueError, r"^psnr: 'nan' is not a number$"),
        (dict(psnr=float("inf")), ValueError, r"^psnr: 'inf' is not a finite number$"),
        (dict(psnr=9.94), ValueError, r"^psnr 9.94 is out of range \[10, 70\] dB$"),
        (dict(psnr="44"), TypeError, r"^psnr must be a number, got str"),
        (dict(dmin=10**30), ValueError, r"^dmin 1000000000000000000000000000000 is out of range"),
        (dict(dmin=1.0), TypeError, r"^dmin must be an int, got float 1.0"),
        (dict(dmin=True), TypeError, r"^dmin must be an int, got bool True"),
        (dict(dense=1), TypeError, r"^dense must be True or False, got int 1"),
        (dict(cost=1), TypeError, r"^cost must be one of the strings ad, census, ad_census, got int 1"),
        (dict(cost="sad"), ValueError, r"^cost: unknown cost 'sad' \(expected ad, census or ad_census\)"),
        (dict(paths=6), ValueError, r"^paths must be 4 or 8, not '6'"),
        (dict(kernels="avx512"), ValueError, r"avx512"),
        (dict(cpus="3-1"), ValueError, r"^cpus: "),
        (dict(mode="fast"), ValueError, r"^mode must be default or paper, not 'fast'"),
    ]
    for kw, exc, pattern in cases:
        with pytest.raises(exc, match=pattern):
            tristereo.Pipeline(64, 48, ndisp=16, **kw)
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'asw_gamma_color' \(known: .*gamma_color"):
        tristereo.Pipeline(64, 48, ndisp=16, asw_gamma_color=10)
    # NumPy's scalars are numbers too (sizes and settings often come from arrays).
    p = tristereo.Pipeline(64, 48, ndisp=np.int64(16), window=(np.int32(5), np.uint8(3)), psnr=np.float32(41.5),
                           paths=np.int16(8), threads=np.int64(1), cpus=[np.int64(0)])
    assert (p.params["ndisp"], p.params["window"], p.params["psnr"], p.params["paths"]) == (16, (5, 3), 41.5, 8)
    with pytest.raises(TypeError, match="dense must be True or False"):
        tristereo.Pipeline(64, 48, ndisp=16, dense=np.int64(1))
    # A float psnr in tenths is kept; the keyword's value reads back.
    assert tristereo.Pipeline(64, 48, ndisp=16, psnr=41.5).params["psnr"] == 41.5
    assert tristereo.Pipeline(64, 48, ndisp=16, window="5x3").params["window"] == (5, 3)
    assert tristereo.Pipeline(64, 48, ndisp=16, threads=1, cpus=[0], pin=False).threads == 1


def test_read_image_takes_bytes_and_pathlike_paths(tmp_path):
    cli("synth", tmp_path, "--width", 48, "--height", 32, "--ndisp", 8, "--seed", 1)
    png = tmp_path / "left.png"
    ref = tristereo.read_image(str(png))
    assert np.array_equal(tristereo.read_image(png), ref)
    assert np.array_equal(tristereo.read_image(os.fsencode(png)), ref)
    # A file name that is not UTF-8 (POSIX allows any bytes but / and NUL).
    odd = os.path.join(os.fsencode(tmp_path), b"l\xff.png")
    with open(png, "rb") as src, open(odd, "wb") as dst:
        dst.write(src.read())
    assert np.array_equal(tristereo.read_image(odd), ref)
    # The error names the path itself, not the bytes object's repr.
    with pytest.raises(OSError) as e:
        tristereo.read_image(os.fsencode(tmp_path / "missing.png"))
    assert f"'{tmp_path / 'missing.png'}'" in str(e.value) and "b'" not in str(e.value)


def test_colour_arrays_need_their_channel_order(tmp_path):
    cli("synth", tmp_path, "--width", 48, "--height", 32, "--ndisp", 8, "--seed", 1)
    left, right = tristereo.read_image(tmp_path / "left.png"), tristereo.read_image(tmp_path / "right.png")

    def colour(gray):  # three different channels
        return np.dstack([gray, np.roll(gray, 1, axis=1), gray[::-1]])

    rgb_l, rgb_r = colour(left), colour(right)
    p = tristereo.Pipeline(48, 32, ndisp=8, threads=1)
    with pytest.raises(ValueError, match=r"left has 3 channels: say their order, order='bgr' \(OpenCV"):
        p.process(rgb_l, rgb_r)
    with pytest.raises(ValueError, match="order='gray'"):
        p.process(rgb_l, rgb_r, order="gray")
    with pytest.raises(ValueError, match="gray array but order='rgb'"):
        p.process(left, right, order="rgb")
    with pytest.raises(ValueError, match="order must be 'bgr'"):
        p.process(rgb_l, rgb_r, order="BGR")
    ref = p.process(rgb_l, rgb_r, order="rgb").digest
    bgr_l, bgr_r = np.ascontiguousarray(rgb_l[:, :, ::-1]), np.ascontiguousarray(rgb_r[:, :, ::-1])
    assert p.process(bgr_l, bgr_r, order="bgr").digest == ref
    # rgb[:, :, ::-1] itself (a view with negative channel strides) is copied, same answer.
    assert p.process(rgb_l[:, :, ::-1], rgb_r[:, :, ::-1], order="bgr").digest == ref
    # Read in the wrong order, the frame differs: the test can tell.
    assert p.process(bgr_l, bgr_r, order="rgb").digest != ref
    bgr = bgr_l
    # A BGR frame larger than the configuration is refused before it is converted.
    big = np.zeros((33, 48, 3), np.uint8)
    with pytest.raises(ValueError, match="larger than the configured 48x32"):
        p.process(big, big, order="bgr")
    with pytest.raises(ValueError, match="right"):
        p.process(bgr, bgr[:, :-1], order="bgr")


def test_opencv_bgr_arrays_give_the_cli_output_on_the_png(tmp_path):
    try:
        import cv2
    except ImportError:
        pytest.fail("OpenCV's Python module is missing (Debian: python3-opencv; scripts/install-deps.sh test)")
    folder = require_data("middlebury")
    d = os.path.join(folder, "teddy")
    left, right = cv2.imread(os.path.join(d, "left.png")), cv2.imread(os.path.join(d, "right.png"))
    png = tristereo.read_image(os.path.join(d, "left.png"))
    assert left.ndim == 3 and np.array_equal(left, png[:, :, ::-1])  # BGR: the PNG's channels reversed
    h, w = left.shape[:2]
    out = tristereo.Pipeline(w, h, ndisp=64, threads=1).process(left, right, order="bgr")
    pfm = tmp_path / "d.pfm"
    cli("match", os.path.join(d, "left.png"), os.path.join(d, "right.png"), "--ndisp", 64, "--threads", 1,
        "--disp", pfm)
    cpp = read_pfm(pfm)
    valid = out.disp_q4 != tristereo.INVALID_DISP_Q4
    assert np.array_equal(np.isinf(cpp), ~valid)
    assert np.array_equal(cpp[valid], out.disparity[valid])
    text = cli("verify", os.path.join(d, "left.png"), os.path.join(d, "right.png"), "--ndisp", 64,
               "--thread-counts", "1")
    assert re.search(r"reference digest ([0-9a-f]+)", text).group(1) == out.digest
    # Taken as RGB, the same arrays give another map: the order matters here.
    wrong = tristereo.Pipeline(w, h, ndisp=64, threads=1).process(left, right, order="rgb")
    assert np.count_nonzero(wrong.disp_q4 != out.disp_q4) > 1000
