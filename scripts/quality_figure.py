"""The main job's comparison of the filterable representations on one view (docs/representations.md).

For each bit budget (32, 64, 128 bits per texel) a row of shadows, one column per
representation of that size (msmcl-quality's shadow PNGs), with its signed difference from
the PCF truth underneath (its error PNGs, truth - method: red where the method is lighter,
i.e. leaks), and the colour bar of the differences at the bottom. Each title carries the
method's banner leak (mean, and the share of banner receivers leaking more than 0.1) where
the view has a banner, and its share of receivers more than 3% from the truth.

usage: quality_figure.py QUALITY_DIR QUALITY_JSON SCENE OUTPUT.png
"""
import json
import sys

from difference_figure import ANCHORS, load_png

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap  # noqa: E402

# The methods of each bit budget, in the order the columns show them.
BUDGETS = [
    (32, ["nlq32", "vsm32", "evsm2_32", "evsm2_32_lbr0.15", "esm32"]),
    (64, ["msm64", "nlq64", "vsm64", "evsm4_64", "evsm4_64_lbr0.15"]),
    (128, ["moments128", "evsm4_128", "evsm4_128_lbr0.15"]),
]
ERROR_RANGE = 0.1  # msmcl-quality's error images: full colour at |truth - method| >= 0.1


def title(method):
    """The method's name and its figures from quality.json."""
    text = method["method"]
    leak = method.get("banner_leak")
    text += "\n> 3% from truth: {:.2f}%".format(100 * method["vs_pcf_truth"]["share_above_3pct"])
    if leak:
        text += "\nleak {:.4f}, {:.1f}% > 0.1".format(leak["mean"], 100 * leak["share_above_0_1"])
    return text


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    quality_dir, quality_json, scene_name, output = sys.argv[1:]
    scenes = {s["scene"]: s for s in json.load(open(quality_json))["scenes"]}
    if scene_name not in scenes:
        sys.exit("quality_figure.py: no scene %s in %s" % (scene_name, quality_json))
    methods = {m["method"]: m for m in scenes[scene_name]["methods"]}
    columns = max(len(names) for _, names in BUDGETS)
    prefix = "%s/%s_" % (quality_dir, scene_name)
    height, width = load_png(prefix + "moments128_shadow.png").shape[:2]
    rows = 2 * len(BUDGETS)
    # Text in proportion to the panels; each panel's three title lines, the suptitle and the
    # colour bar in inches of their own.
    font = max(8.0, width / 45.0)
    title_inches, top_inches, bottom_inches = 3.8 * font / 72.0, 0.6 * font / 8.0, 1.0 * font / 8.0
    panel_inches = height / 100.0
    figure_height = rows * (panel_inches + title_inches) + top_inches + bottom_inches
    figure, axes = plt.subplots(rows, columns, figsize=(columns * width / 100, figure_height), dpi=100, squeeze=False)
    for axis in axes.flat:
        axis.axis("off")
    for budget, (bits, names) in enumerate(BUDGETS):
        for column, name in enumerate(n for n in names if n in methods):
            shadow = axes[2 * budget][column]
            shadow.imshow(load_png(prefix + name + "_shadow.png"), cmap="gray", vmin=0, vmax=1,
                          interpolation="nearest")
            shadow.set_title("%d bits: %s" % (bits, title(methods[name])), fontsize=font)
            difference = axes[2 * budget + 1][column]
            difference.imshow(load_png(prefix + name + "_error.png", legend=True), interpolation="nearest")
            difference.set_title("PCF truth - %s" % name, fontsize=font)
    figure.subplots_adjust(left=0.01, right=0.99, top=1 - (top_inches + title_inches) / figure_height,
                           bottom=bottom_inches / figure_height, wspace=0.03, hspace=title_inches / panel_inches)
    # The colour bar of every difference panel, along the bottom.
    bar = figure.add_axes([0.3, 0.55 * bottom_inches / figure_height, 0.4, 0.12 * bottom_inches / figure_height])
    colormap = LinearSegmentedColormap.from_list("signed_difference", ANCHORS)
    figure.colorbar(plt.cm.ScalarMappable(cmap=colormap, norm=plt.Normalize(-ERROR_RANGE, ERROR_RANGE)), cax=bar,
                    orientation="horizontal", ticks=[-ERROR_RANGE, -ERROR_RANGE / 2, 0, ERROR_RANGE / 2, ERROR_RANGE])
    bar.set_xlabel("PCF truth - method (shadow intensity): red = lighter than the truth (leaks), blue = darker",
                   fontsize=font)
    bar.tick_params(labelsize=font)
    figure.suptitle("%s: every representation by bits per texel, against the PCF truth" % scene_name, fontsize=1.2 * font,
                    y=1 - 0.2 * top_inches / figure_height)
    figure.savefig(output, dpi=100)


if __name__ == "__main__":
    main()
