#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plots the JSON rows of msmcl-bench with matplotlib.

    python3 scripts/plot_bench.py bench.json [bench.png] [--samples 4]

One column per texture format, three rows: the median time of each case (ms, log scale),
its throughput (GB/s of the bytes it reads and writes) and the fraction of the memory roof
it reaches (the copy of the same bytes timed beside it: copy ms / case ms). The x axis is
the map size (texels per side, log scale). Colours tell the cases apart; with several
sample counts in the file, line styles tell the sample counts apart (or --samples picks
one). Rows without a time (the build and first-call rows, whose size is a configuration
rather than a sweep) and the command-line batch rows (batch_cli, batch_loop) are left out
of the lines.
"""

import argparse
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402  (after the backend choice)
from matplotlib import ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

FORMATS = ["moments128", "msm64", "nlq64", "nlq32"]
METRICS = [
    ("ms_median", "median time (ms)", True),
    ("gb_per_s", "throughput (GB/s)", True),
    ("copy_roof_fraction", "fraction of the copy roof", False),
]
LINE_STYLES = ["-", "--", ":", "-."]


def load_rows(path):
    """The bench's rows: a JSON array of objects with case, size, samples, format and timings."""
    try:
        rows = json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        raise SystemExit(f"plot_bench: {path}: {e}")
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise SystemExit(f"plot_bench: {path}: expected a JSON array of rows")
    return rows


def series(rows, case, samples, fmt, metric):
    """(size, value) points of one line, sorted by size; rows without the metric skipped."""
    points = sorted(
        (r["size"], r[metric])
        for r in rows
        if r.get("case") == case and r.get("samples") == samples and r.get("format") == fmt
        and isinstance(r.get(metric), (int, float)) and isinstance(r.get("size"), int)
    )
    return [p[0] for p in points], [p[1] for p in points]


def plot(rows, out_path, only_samples=None):
    # The command-line batch rows time N files through whole processes, not one map on the
    # device: they are compared with each other (loop_over_batch), not plotted here.
    rows = [
        r for r in rows
        if isinstance(r.get("ms_median"), (int, float)) and not str(r.get("case")).startswith("batch_")
    ]
    if only_samples is not None:
        rows = [r for r in rows if r.get("samples") == only_samples]
    if not rows:
        raise SystemExit("plot_bench: no timed rows to plot")
    formats = [f for f in FORMATS if any(r.get("format") == f for r in rows)]
    cases = sorted({r["case"] for r in rows})
    sample_counts = sorted({r["samples"] for r in rows})
    sizes = sorted({r["size"] for r in rows})
    colours = plt.get_cmap("tab20" if len(cases) > 10 else "tab10")

    fig, axes = plt.subplots(len(METRICS), len(formats), figsize=(4.2 * len(formats) + 2.5, 9.5),
                             squeeze=False, sharex=True)
    for column, fmt in enumerate(formats):
        for row_index, (metric, label, log_scale) in enumerate(METRICS):
            ax = axes[row_index][column]
            for case_index, case in enumerate(cases):
                for samples_index, samples in enumerate(sample_counts):
                    x, y = series(rows, case, samples, fmt, metric)
                    if not x:
                        continue
                    ax.plot(x, y, marker="o", markersize=3.5, linewidth=1.4,
                            color=colours(case_index % colours.N),
                            linestyle=LINE_STYLES[samples_index % len(LINE_STYLES)])
            ax.set_xscale("log", base=2)
            ax.set_xticks(sizes)
            ax.set_xticklabels([str(s) for s in sizes])
            if log_scale:
                # Log scale labelled 1, 2, 5 per decade in plain numbers (0.2, 5, 100).
                ax.set_yscale("log")
                ax.yaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
                ax.yaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
                ax.yaxis.set_minor_formatter(ticker.NullFormatter())
            if metric == "copy_roof_fraction":
                ax.axhline(1.0, color="grey", linewidth=0.8)
            ax.grid(True, which="both", alpha=0.3)
            if column == 0:
                ax.set_ylabel(label)
            if row_index == 0:
                ax.set_title(fmt)
            if row_index == len(METRICS) - 1:
                ax.set_xlabel("map size (texels per side)")

    # One legend for the figure: cases by colour, sample counts by line style.
    handles = [Line2D([], [], color=colours(i % colours.N), marker="o", label=case) for i, case in enumerate(cases)]
    if len(sample_counts) > 1:
        handles += [Line2D([], [], color="black", linestyle=LINE_STYLES[i % len(LINE_STYLES)],
                           label=f"{s} sample{'s' if s != 1 else ''}") for i, s in enumerate(sample_counts)]
    fig.legend(handles=handles, loc="center right", frameon=False)
    device = rows[0].get("device", "")
    samples_text = ", ".join(str(s) for s in sample_counts)
    fig.suptitle(f"msmcl-bench on {device} (samples per texel: {samples_text})")
    fig.tight_layout(rect=(0, 0, 0.88, 0.96))
    fig.savefig(out_path, dpi=110)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description="Plot msmcl-bench JSON rows (ms, GB/s, fraction of the roof).")
    parser.add_argument("json", help="the file msmcl-bench --json wrote")
    parser.add_argument("png", nargs="?", help="output PNG (default: the JSON path with .png)")
    parser.add_argument("--samples", type=int, help="plot only this sample count")
    args = parser.parse_args(argv)
    out = args.png or str(Path(args.json).with_suffix(".png"))
    plot(load_rows(args.json), out, args.samples)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1:])
