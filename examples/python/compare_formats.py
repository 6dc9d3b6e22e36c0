#!/usr/bin/env python3
"""Filters a shipped depth map into every format, shades the shipped view with each and
prints each format's error against 128-bit moments (msmcl's Python module, docs/python.md).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/compare_formats.py [--lookup nearest]
"""
import argparse
import pathlib

import numpy as np

import msmcl

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
FORMATS = {"moments128": 128, "msm64": 64, "nlq64": 64, "nlq32": 32}  # bits per texel

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--map", default=DATA / "railing_256x256_4x.exr", help="depth map EXR")
parser.add_argument("--view", default=DATA / "railing_view_160x120.exr", help="receivers EXR (U, V, Z)")
parser.add_argument("--lookup", default="bilinear", choices=["nearest", "bilinear", "dither"])
parser.add_argument("--device", default=None, help="gpu, cpu, an index or a name (default: as msmcl)")
args = parser.parse_args()

ctx = msmcl.Context(args.device)
depth = msmcl.read_depth(args.map)          # float32 (H, W, S)
receivers = msmcl.read_receivers(args.view)  # float32 (H, W, 3): u, v, depth
shadow = {f: ctx.shade(ctx.filter(depth, format=f), receivers, lookup=args.lookup) for f in FORMATS}

reference = shadow["moments128"].astype(np.float64)
print(f"{pathlib.Path(args.map).name}, {depth.shape[1]}x{depth.shape[0]}, {depth.shape[2] if depth.ndim == 3 else 1} "
      f"samples; {receivers.shape[1]}x{receivers.shape[0]} receivers, {args.lookup} lookup; "
      f"device {ctx.device['name']}")
print("shadow intensity of each format against moments128:")
print(f"{'format':<11} {'bits':>4} {'max |diff|':>11} {'mean |diff|':>12} {'rms':>10} {'> 0.01':>8}")
for format, bits in FORMATS.items():
    diff = np.abs(shadow[format] - reference)
    print(f"{format:<11} {bits:>4} {diff.max():>11.3e} {diff.mean():>12.3e} {np.sqrt(np.mean(diff ** 2)):>10.3e} "
          f"{np.mean(diff > 0.01):>8.2%}")
