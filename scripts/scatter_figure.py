#!/usr/bin/env python3
"""Figure of prefiltered single scattering against ray marching (docs/quality.md, Single scattering).

Reads the main job's PNGs of one scene from OUT_DIR (<scene>_marched1024.png, the truth;
<scene>_scatter6.png, <scene>_scatter4.png and their signed differences from the truth,
<scene>_scatter6_diff.png, <scene>_scatter4_diff.png) and scatter_vs_marched.txt (the
figures `msmcl-scatter-quality compare` printed), and writes one PNG: the three images in
the top row, the differences of each view ray's lit fraction below (red: lighter than the
truth, blue: darker, full colour at +-0.1; the colour map of tools/signed_difference.hpp).

    python3 scripts/scatter_figure.py out hall docs/images/scatter_hall.png
"""
import argparse
import re

from difference_figure import draw, load_png


def statistics(path, scene):
    """'mean x, p99 y' of the lit fraction per moment count, from scatter_vs_marched.txt."""
    found = {}
    with open(path) as lines:
        for line in lines:
            match = re.search(r"(\w+)_scatter(\d)\.exr vs \d+-sample ray marching, lit fraction: mean ([0-9.]+), p99 ([0-9.]+)",
                              line)
            if match and match.group(1) == scene:
                found[match.group(2)] = f"mean {match.group(3)}, p99 {match.group(4)}"
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("scene")
    parser.add_argument("output")
    parser.add_argument("--range", type=float, default=0.1, help="the differences' full-colour value (as drawn)")
    args = parser.parse_args()
    stats = statistics(f"{args.out_dir}/scatter_vs_marched.txt", args.scene)

    def load(name, legend=False):
        return load_png(f"{args.out_dir}/{args.scene}_{name}.png", legend)

    panels = [
        ("ray marching, 1024 samples (truth)", load("marched1024"), "gray"),
        ("6 moments", load("scatter6"), "gray"),
        ("4 moments", load("scatter4"), "gray"),
        (None, None, None),
        (f"6 moments - truth: {stats.get('6', '')}", load("scatter6_diff", True), None),
        (f"4 moments - truth: {stats.get('4', '')}", load("scatter4_diff", True), None),
    ]
    draw(panels, args.output, args.range, "lit fraction of a view ray - truth: blue darker, red lighter")


if __name__ == "__main__":
    main()
