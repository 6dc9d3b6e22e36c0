"""Shared by the main job's comparison figures (scripts/soft_figure.py, scripts/scatter_figure.py).

A figure is a 2 x 3 grid of panels: images in the top row, their signed differences from a
truth below, and the colour bar of the differences, with its numbers, in the one empty slot.
The difference PNGs come from tools/signed_difference.hpp, whose colour map is restated here.
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap  # noqa: E402

# tools/signed_difference.hpp: ColorBrewer RdBu (9 classes), white centre, blue = -range.
ANCHORS = ["#2166ac", "#4393c3", "#92c5de", "#d1e5f0", "#ffffff", "#fddbc7", "#f4a582", "#d6604d", "#b2182b"]
LEGEND_ROWS = 31  # the gap, bar and labels the difference PNGs carry below the image (kLegendRows)


def load_png(path, legend=False, crop=None):
    """A PNG as an array; `legend`: without the bar below a difference image; `crop`: X0,Y0,X1,Y1."""
    image = mpimg.imread(path)
    if legend:
        image = image[:-LEGEND_ROWS]
    if crop:
        image = image[crop[1]:crop[3], crop[0]:crop[2]]
    return image


def draw(panels, output, value_range, bar_label):
    """Writes the grid: `panels` are six (title, image, colour map) in reading order, one of
    them (None, None, None) where the colour bar of +-`value_range` goes."""
    height, width = next(image for _, image, _ in panels if image is not None).shape[:2]
    figure, axes = plt.subplots(2, 3, figsize=(3 * width / 100, 2 * height / 100 + 0.9), dpi=100)
    empty = None
    for axis, (title, image, cmap) in zip(axes.flat, panels):
        axis.axis("off")
        if image is None:
            empty = axis
            continue
        axis.imshow(image, cmap=cmap, vmin=0, vmax=1, interpolation="nearest")
        axis.set_title(title, fontsize=9)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.94, bottom=0.02, wspace=0.02, hspace=0.14)
    # The legend of the difference panels, across the middle of the empty slot.
    box = empty.get_position()
    bar = figure.add_axes([box.x0 + 0.1 * box.width, box.y0 + 0.45 * box.height, 0.8 * box.width, 0.08 * box.height])
    colormap = LinearSegmentedColormap.from_list("signed_difference", ANCHORS)
    ticks = [-value_range, -value_range / 2, 0, value_range / 2, value_range]
    figure.colorbar(plt.cm.ScalarMappable(cmap=colormap, norm=plt.Normalize(-value_range, value_range)), cax=bar,
                    orientation="horizontal", ticks=ticks)
    bar.set_xlabel(bar_label, fontsize=8)
    bar.tick_params(labelsize=8)
    figure.savefig(output, dpi=100)
