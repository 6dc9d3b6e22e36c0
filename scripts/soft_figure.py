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

from difference_figure import draw, load_png


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
        return load_png(f"{args.out_dir}/{args.scene}_{name}.png", legend, crop)

    panels = [
        ("PCSS (double precision)", load("soft_pcss"), "gray"),
        (f"published: {stats.get('soft_published', '')}", load("soft_published"), "gray"),
        (f"refined (default): {stats.get('soft', '')}", load("soft"), "gray"),
        (None, None, None),
        ("published - PCSS (in light)", load("soft_published_diff_pm0.5", True), None),
        ("refined - PCSS (in light)", load("soft_diff_pm0.5", True), None),
    ]
    draw(panels, args.output, 0.5, "method - PCSS in light: blue darker, red lighter (light leak)")


if __name__ == "__main__":
    main()
