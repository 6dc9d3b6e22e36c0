#!/usr/bin/env python3
"""Before/after figure of moment soft shadows against brute-force PCSS (docs/soft_shadows.md).

Reads the main job's PNGs of one scene (<scene>_soft_pcss.png, <scene>_soft_published.png,
<scene>_soft.png and the two signed differences <scene>_soft[_published]_diff_pm0.5.png)
and soft_vs_pcss.txt from OUT_DIR, and writes one PNG: PCSS, the published method and the
refined default in the top row, their signed differences from PCSS below (red: lighter
than PCSS, blue: darker, full colour at +-0.5; the colour map of tools/signed_difference.hpp).

    python3 scripts/soft_figure.py out railing_1024 docs/images/soft_railing_1024.png [--crop X0,Y0,X1,Y1]
"""
import argparse
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap  # noqa: E402

# tools/signed_difference.hpp: ColorBrewer RdBu (9 classes), white centre, blue = -range.
ANCHORS = ["#2166ac", "#4393c3", "#92c5de", "#d1e5f0", "#ffffff", "#fddbc7", "#f4a582", "#d6604d", "#b2182b"]
LEGEND_ROWS = 20  # the gap and bar the difference PNGs carry below the image


def statistics(path, scene):
    """'lighter by > 0.3: x%, p99 y' per method from soft_vs_pcss.txt."""
    found = {}
    with open(path) as lines:
        for line in lines:
            match = re.match(r"(\S+) (soft|soft_published) vs PCSS: .*p99 \|d\| ([0-9.]+).*lighter by > 0.3: ([0-9.]+)%", line)
            if match and match.group(1) == scene:
                found[match.group(2)] = f"{match.group(4)}% lighter by > 0.3, p99 {match.group(3)}"
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("scene")
    parser.add_argument("output")
    parser.add_argument("--crop", default="", help="X0,Y0,X1,Y1 of the view to show (default: all)")
    args = parser.parse_args()
    stats = statistics(f"{args.out_dir}/soft_vs_pcss.txt", args.scene)
    crop = [int(v) for v in args.crop.split(",")] if args.crop else None

    def load(name, legend=False):
        image = mpimg.imread(f"{args.out_dir}/{args.scene}_{name}.png")
        if legend:
            image = image[:-LEGEND_ROWS]
        if crop:
            image = image[crop[1]:crop[3], crop[0]:crop[2]]
        return image

    panels = [
        ("PCSS (double precision)", load("soft_pcss"), "gray"),
        (f"published: {stats.get('soft_published', '')}", load("soft_published"), "gray"),
        (f"refined (default): {stats.get('soft', '')}", load("soft"), "gray"),
        (None, None, None),
        ("published - PCSS (in light)", load("soft_published_diff_pm0.5", True), None),
        ("refined - PCSS (in light)", load("soft_diff_pm0.5", True), None),
    ]
    height, width = panels[0][1].shape[:2]
    figure, axes = plt.subplots(2, 3, figsize=(3 * width / 100, 2 * height / 100 + 0.9), dpi=100)
    for axis, (title, image, cmap) in zip(axes.flat, panels):
        axis.axis("off")
        if image is None:
            continue
        axis.imshow(image, cmap=cmap, vmin=0, vmax=1, interpolation="nearest")
        axis.set_title(title, fontsize=9)
    # The legend of the difference panels, in the empty slot.
    colormap = LinearSegmentedColormap.from_list("signed_difference", ANCHORS)
    bar = figure.add_axes([0.06, 0.22, 0.25, 0.04])
    figure.colorbar(plt.cm.ScalarMappable(cmap=colormap, norm=plt.Normalize(-0.5, 0.5)), cax=bar,
                    orientation="horizontal", ticks=[-0.5, -0.25, 0, 0.25, 0.5])
    bar.set_xlabel("method - PCSS in light: blue darker, red lighter (light leak)", fontsize=8)
    bar.tick_params(labelsize=8)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.94, bottom=0.02, wspace=0.02, hspace=0.14)
    figure.savefig(args.output, dpi=100)


if __name__ == "__main__":
    main()
