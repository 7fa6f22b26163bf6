#!/usr/bin/python3
"""A rectified pair beside its disparity map, from the CLI's own outputs.

    tristereo rectify L.png R.png --rig ... --out-left rl.png --out-right rr.png
    tristereo match L.png R.png --rig ... --ndisp 64 --disp-color dc.png
    /usr/bin/python3 scripts/plot_rectified.py rl.png rr.png dc.png -o figure.png [--title T]

Three panels (rectified left, rectified right, colour disparity) with a few
horizontal lines across both rectified images: a point and its match must sit
on the same line. The pixels are the PNGs' own (nearest-neighbour display, no
smoothing). Needs matplotlib and numpy (Debian: python3-matplotlib).
docs/img/rectified_euroc_0000.png is this script's output on EuRoC pair 0
(docs/rectification.md says how).
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files only; no display on a board or in CI
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("left")
    ap.add_argument("right")
    ap.add_argument("disp_color")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--lines", type=int, default=8, help="horizontal guide lines (0: none)")
    ap.add_argument("--dpi", type=int, default=80)
    a = ap.parse_args()
    imgs = [mpimg.imread(p) for p in (a.left, a.right, a.disp_color)]
    h, w = imgs[0].shape[:2]
    fig, axes = plt.subplots(1, 3, figsize=(3 * w / 160, h / 160 + 0.5), dpi=a.dpi)
    for ax, img, name in zip(axes, imgs, ("rectified left", "rectified right", "disparity (match --rig)")):
        ax.imshow(img, cmap="gray" if img.ndim == 2 else None, vmin=0, vmax=1, interpolation="nearest")
        ax.set_title(name, fontsize=9)
        ax.set_axis_off()
    for ax in axes[:2]:
        for k in range(1, a.lines + 1):
            ax.axhline(k * h / (a.lines + 1), color="yellow", linewidth=0.5)
    if a.title:
        fig.suptitle(a.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(a.out, dpi=a.dpi)


if __name__ == "__main__":
    main()
