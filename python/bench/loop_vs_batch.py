#!/usr/bin/env python3
"""What a Python loop over msmcl's module costs against one `msmcl filter` batch call on the
same files (docs/python.md, *Cost*): N maps filtered by
    for path in maps: msmcl.write_texture(out, ctx.filter(msmcl.read_depth(path), ...))
against `msmcl filter maps... -o DIR`, in turns, outputs compared byte for byte; then the
module's calls alone, without file I/O (the depth maps already in memory).

    PYTHONPATH=build/python /usr/bin/python3 python/bench/loop_vs_batch.py --cli build/msmcl \
        --scene-tool build/tools/msmcl-scene [--maps 24 --size 512 --samples 4 --format msm64 --reps 3]
"""
import argparse
import os
import pathlib
import shutil
import statistics
import subprocess
import tempfile
import time

import msmcl

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--cli", required=True, help="the msmcl executable")
parser.add_argument("--scene-tool", help="msmcl-scene, for a rendered map (default: a synthetic one)")
parser.add_argument("--maps", type=int, default=24)
parser.add_argument("--size", type=int, default=512)
parser.add_argument("--samples", type=int, default=4)
parser.add_argument("--format", default="msm64")
parser.add_argument("--reps", type=int, default=3)
args = parser.parse_args()


def cpu_of_children():
    t = os.times()
    return t.children_user + t.children_system


def cpu_of_self():
    t = os.times()
    return t.user + t.system


work = pathlib.Path(tempfile.mkdtemp(prefix="msmcl_loop_vs_batch_"))
try:
    # N copies of one map, as the batch measurement of the CLI does.
    first = work / "m0.exr"
    if args.scene_tool:
        subprocess.run([args.scene_tool, "--depth", first, "--width", str(args.size), "--samples", str(args.samples)],
                       check=True, capture_output=True)
    else:
        import numpy as np

        y, x = np.mgrid[0 : args.size, 0 : args.size] / args.size
        depth = 0.5 + 0.3 * np.sin(9 * x) * np.cos(7 * y)
        depth[(x * 8 % 1 < 0.3) & (y > 0.5)] = 0.2
        msmcl.write_depth(first, np.repeat(depth[:, :, None], args.samples, axis=2).astype(np.float32))
    maps = [first] + [work / f"m{i}.exr" for i in range(1, args.maps)]
    for path in maps[1:]:
        shutil.copyfile(first, path)

    def batch():
        out = work / "cli"
        shutil.rmtree(out, ignore_errors=True)
        cpu, start = cpu_of_children(), time.perf_counter()
        subprocess.run([args.cli, "filter", *maps, "-o", out, "--format", args.format], check=True)
        return time.perf_counter() - start, cpu_of_children() - cpu

    def loop():
        out = work / "py"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir()
        cpu, start = cpu_of_self(), time.perf_counter()
        ctx = msmcl.Context()
        for path in maps:
            msmcl.write_texture(out / path.name, ctx.filter(msmcl.read_depth(path), format=args.format))
        return time.perf_counter() - start, cpu_of_self() - cpu

    runs = {"batch": [], "loop": []}
    for _ in range(args.reps):
        runs["batch"].append(batch())
        runs["loop"].append(loop())
        for path in maps:
            assert (work / "py" / path.name).read_bytes() == (work / "cli" / path.name).read_bytes(), path

    # The module's calls alone: maps in memory, the Context's programs built.
    ctx = msmcl.Context()
    depths = [msmcl.read_depth(path) for path in maps]
    ctx.filter(depths[0], format=args.format)
    per_map = {"read_depth": [], "filter": [], "write_texture": []}
    for path, depth in zip(maps, depths):
        start = time.perf_counter()
        msmcl.read_depth(path)
        per_map["read_depth"].append(time.perf_counter() - start)
        start = time.perf_counter()
        texture = ctx.filter(depth, format=args.format)
        per_map["filter"].append(time.perf_counter() - start)
        start = time.perf_counter()
        msmcl.write_texture(work / "alone.exr", texture)
        per_map["write_texture"].append(time.perf_counter() - start)

    n = args.maps
    print(f"{n} maps of {args.size}^2, {args.samples} samples, {args.format}; device {ctx.device['name']}; "
          f"medians of {args.reps} turns; outputs byte-identical")
    for name, label in [("batch", "CLI batch (one msmcl filter call)"), ("loop", "Python loop (read, filter, write)")]:
        wall = statistics.median(w for w, _ in runs[name])
        cpu = statistics.median(c for _, c in runs[name])
        print(f"{label:<36} {wall:6.2f} s wall ({1000 * wall / n:5.0f} ms a map), {cpu:6.2f} s CPU")
    print("module calls per map (medians):", ", ".join(
        f"{name} {1000 * statistics.median(times):.1f} ms" for name, times in per_map.items()))
finally:
    shutil.rmtree(work, ignore_errors=True)
