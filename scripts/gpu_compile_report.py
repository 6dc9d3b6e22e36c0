#!/usr/bin/env python3
"""Offline GPU compile report of every msmcl kernel variant, and its budgets.

msmcl-kernel-variants (tests/gpu_compile/kernel_variants.cpp) writes each program variant exactly as
the library assembles it; this script compiles every one for
  AMD    gfx906, gfx90a, gfx1030, gfx1100  clang-15 + libclc-15 (amdgcn--amdhsa.bc)
  Intel  tgllp, acm-g10                    ocloc (intel-opencl-icd, unpacked by
                                           scripts/install-deps.sh, no ICD registered)
  NVIDIA sm_80                             clang-15 + libclc-15 (nvptx64--nvidiacl.bc);
                                           Debian has no ptxas: stack bytes and
                                           ld/st.local counts from the PTX
and prints per kernel registers, spills, local memory, private/stack bytes, SIMD width
(Intel) and waves per SIMD (AMD, docs/gpu-readiness.md explains the model), as a markdown
table and JSON. --check asserts the budgets (exit 1 on a breach); a missing toolchain exits
77 (ctest: skipped) unless MSMCL_REQUIRE_GPU_TOOLCHAINS=1, which makes it a failure.

usage: gpu_compile_report.py --variants-tool build/tests/gpu_compile/msmcl-kernel-variants
           [--json out.json] [--markdown out.md] [--check] [--full] [--jobs N]
"""
import argparse
import concurrent.futures
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

SKIP = 77

# --- AMD: occupancy model per target -------------------------------------------------------
# One LDS pool serves every SIMD of a compute unit (gfx9: 64 KiB per CU of 4 SIMDs) or of a
# work-group processor (gfx10+: 128 KiB per WGP of 4 SIMD32s), allocated in 512-byte
# granules to whole work-groups. Registers per SIMD lane and their allocation granules are
# LLVM's (AMDGPUBaseInfo); gfx1100 has the 1.5x register file of RDNA3 (1536 per lane).
AMD_TARGETS = {
    "gfx906": dict(lds_pool=65536, simds=4, cus_per_pool=1, max_waves=10, vgprs={64: 256}, granule={64: 4},
                   sgpr_total=800, sgpr_granule=16),
    "gfx90a": dict(lds_pool=65536, simds=4, cus_per_pool=1, max_waves=8, vgprs={64: 512}, granule={64: 8},
                   sgpr_total=800, sgpr_granule=16),
    "gfx1030": dict(lds_pool=131072, simds=4, cus_per_pool=2, max_waves=16, vgprs={32: 1024, 64: 512},
                    granule={32: 8, 64: 4}, sgpr_total=None, sgpr_granule=None),
    "gfx1100": dict(lds_pool=131072, simds=4, cus_per_pool=2, max_waves=16, vgprs={32: 1536, 64: 768},
                    granule={32: 24, 64: 12}, sgpr_total=None, sgpr_granule=None),
}
LDS_GRANULE = 512
INTEL_DEVICES = ["tgllp", "acm-g10"]
NVPTX_ARCH = "sm_80"


def align(value, granule):
    return (value + granule - 1) // granule * granule


def max_groups_per_cu(waves_per_group):
    # LLVM's AMDGPU limit on resident work-groups per compute unit (barrier resources).
    return 40 if waves_per_group == 1 else min(40 // waves_per_group, 16)


def amd_occupancy(target, kernel):
    """Waves per SIMD and what limits them, for one kernel's metadata."""
    t = AMD_TARGETS[target]
    wave = kernel["wavefront_size"]
    group = kernel["group_size"]
    waves_per_group = math.ceil(group / wave)
    simds = t["simds"]
    # Groups resident in one LDS pool: by LDS, by registers, by the hardware limit.
    limits = {}
    lds = kernel["lds_bytes"]
    limits["LDS"] = t["lds_pool"] // align(lds, LDS_GRANULE) if lds > 0 else 10 ** 9
    vgpr_waves = min(t["max_waves"], t["vgprs"][wave] // max(align(kernel["vgpr"], t["granule"][wave]), 1))
    limits["VGPR"] = vgpr_waves * simds // waves_per_group
    if t["sgpr_total"]:
        sgpr_waves = min(t["max_waves"], t["sgpr_total"] // max(align(kernel["sgpr"], t["sgpr_granule"]), 1))
        limits["SGPR"] = sgpr_waves * simds // waves_per_group
    limits["waves"] = t["max_waves"] * simds // waves_per_group
    limits["groups"] = max_groups_per_cu(waves_per_group) * t["cus_per_pool"]
    groups = min(limits.values())
    limiter = min(limits, key=lambda k: limits[k])
    return groups * waves_per_group / simds, limiter


# --- Toolchains ----------------------------------------------------------------------------
def find_toolchains():
    clang = os.environ.get("MSMCL_CLANG") or shutil.which("clang-15")
    clc = os.environ.get("MSMCL_LIBCLC_DIR", "/usr/lib/clc")
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    ocloc_root = os.environ.get("MSMCL_OCLOC_DIR") or os.path.join(cache, "msmcl", "ocloc")
    found = {
        "clang": clang,
        "amdgcn_bc": os.path.join(clc, "amdgcn--amdhsa.bc"),
        "nvptx_bc": os.path.join(clc, "nvptx64--nvidiacl.bc"),
        "ocloc": os.path.join(ocloc_root, "usr", "bin", "ocloc"),
        "ocloc_lib": os.path.join(ocloc_root, "usr", "lib", "x86_64-linux-gnu"),
    }
    missing = []
    if not clang:
        missing.append("clang-15 (apt-get install clang-15)")
    for key, package in (("amdgcn_bc", "libclc-15"), ("nvptx_bc", "libclc-15")):
        if not os.path.exists(found[key]):
            missing.append(f"{found[key]} ({package})")
    if not os.access(found["ocloc"], os.X_OK):
        missing.append(f"{found['ocloc']} (scripts/install-deps.sh unpacks intel-opencl-icd there)")
    return found, missing


def run(command, env=None, cwd=None):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=cwd, text=True)
    if result.returncode != 0:
        raise RuntimeError(" ".join(command[:3]) + "...: " + (result.stderr or result.stdout)[-2000:])
    return result.stdout


def clang_command(tools, source, target_args, builtins, output, options):
    # Drivers define __OPENCL_VERSION__, clang alone only __OPENCL_C_VERSION__.
    return ([tools["clang"], "-x", "cl"] + options.split() +
            ["-D__OPENCL_VERSION__=120", "-O3", "-w", "-nogpulib"] + target_args +
            ["-Xclang", "-mlink-builtin-bitcode", "-Xclang", builtins, "-S", source, "-o", output])


def compile_amd(tools, source, options, target, work):
    output = os.path.join(work, os.path.basename(source) + "." + target + ".s")
    run(clang_command(tools, source, ["-target", "amdgcn--amdhsa", "-mcpu=" + target], tools["amdgcn_bc"], output,
                      options))
    text = open(output).read()
    os.remove(output)
    metadata = text[text.index("amdhsa.kernels:"):text.index("amdhsa.target:")]
    kernels = {}
    for block in re.split(r"\n  - ", metadata)[1:]:
        # Kernel-level keys are indented 4 spaces; argument keys deeper.
        fields = dict(re.findall(r"^    \.([a-z_]+):\s+(\S+)$", block, re.M))
        reqd = re.search(r"\.reqd_workgroup_size:\s*\n\s+- (\d+)\n\s+- (\d+)\n\s+- (\d+)", block)
        # Without a required size the host lets the driver choose (256 on AMD for 1D ranges).
        group = int(reqd.group(1)) * int(reqd.group(2)) * int(reqd.group(3)) if reqd else 256
        kernels[fields["name"]] = {
            "vgpr": int(fields["vgpr_count"]),
            "sgpr": int(fields["sgpr_count"]),
            "vgpr_spill": int(fields.get("vgpr_spill_count", 0)),
            "sgpr_spill": int(fields.get("sgpr_spill_count", 0)),
            "lds_bytes": int(fields["group_segment_fixed_size"]),
            "private_bytes": int(fields["private_segment_fixed_size"]),
            "dynamic_stack": fields.get("uses_dynamic_stack") == "true",
            "wavefront_size": int(fields["wavefront_size"]),
            "group_size": group,
        }
    for kernel in kernels.values():
        kernel["waves_per_simd"], kernel["limiter"] = amd_occupancy(target, kernel)
    return kernels


def compile_nvptx(tools, source, options, work):
    output = os.path.join(work, os.path.basename(source) + ".ptx")
    run(clang_command(tools, source, ["-target", "nvptx64--nvidiacl", "-march=" + NVPTX_ARCH], tools["nvptx_bc"],
                      output, options))
    text = open(output).read()
    os.remove(output)
    kernels = {}
    # One block per function; a kernel's own stack is its __local_depot, and what it calls.
    blocks = re.split(r"\n(?=(?:\.visible |\.weak |\.extern )?\.(?:entry|func) )", text)
    for block in blocks:
        entry = re.match(r"(?:\.visible |\.weak )?\.entry\s+(\w+)", block)
        if not entry:
            continue
        stack = sum(int(b) for b in re.findall(r"\.local \.align \d+ \.b8\s+\w+\[(\d+)\]", block))
        kernels[entry.group(1)] = {
            "stack_bytes": stack,
            "local_loads": len(re.findall(r"\bld\.local\b", block)),
            "local_stores": len(re.findall(r"\bst\.local\b", block)),
            "calls": len(re.findall(r"\bcall(?:\.uni)?\b", block)),
        }
    return kernels


def compile_intel(tools, source, options, device, work):
    dump = tempfile.mkdtemp(prefix="ocloc-" + device + "-", dir=work)
    env = dict(os.environ, IGC_ShaderDumpEnable="1", IGC_DumpToCustomDir=dump,
               LD_LIBRARY_PATH=tools["ocloc_lib"] + os.pathsep + os.environ.get("LD_LIBRARY_PATH", ""))
    run([tools["ocloc"], "compile", "-q", "-file", os.path.abspath(source), "-device", device, "-options", options,
         "-output_no_suffix", "-output", os.path.join(dump, "binary")], env=env, cwd=dump)
    kernels = {}
    for cos in sorted(glob.glob(os.path.join(dump, "*.cos"))):
        text = open(cos, errors="replace").read()
        name = re.search(r"Kernel Name = (\w+)", text)
        if not name:
            continue

        def field(key):
            match = re.search(r"\b" + key + r"\s*=\s*(\d+)", text)
            return int(match.group(1)) if match else 0

        simd = re.search(r"_simd(\d+)_", os.path.basename(cos))
        asm = cos[:-4] + ".asm"
        spill = 0
        if os.path.exists(asm):
            match = re.search(r"^//\.spill size (\d+)", open(asm, errors="replace").read(), re.M)
            spill = int(match.group(1)) if match else 0
        kernels[name.group(1)] = {
            "simd": int(simd.group(1)) if simd else field("LargestCompiledSIMDSize"),
            "grf": field("NumGRFRequired"),
            "spill_bytes": spill,
            "scratch_bytes": field("PerThreadScratchSpace"),
            "private_bytes": field("PerThreadPrivateMemorySize"),
            "slm_bytes": field("TotalInlineLocalMemorySize"),
        }
    shutil.rmtree(dump, ignore_errors=True)
    return kernels


# --- Report --------------------------------------------------------------------------------
def layers_of(variant):
    for define in variant["defines"]:
        if define.startswith("MSM_LAYERS="):
            return int(define.split("=")[1])
    return 0


def row_key(variant, kernel, gpu_kernels):
    """Report rows: a kernel, with translucent variants of 1 and 8 layers apart, and the
    CPU variants of a GPU-path kernel (scatter's CPU row tiling) apart."""
    key = kernel["name"]
    layers = layers_of(variant)
    if layers and variant["file"] != "sat_translucent.cl":
        key += f" ({layers} layer{'s' if layers > 1 else ''})"
    if not kernel["gpu_path"] and kernel["name"] in gpu_kernels:
        key += " (CPU variant)"
    return key


def compile_all(tools, variants, directory, jobs):
    tasks = []
    for index, variant in enumerate(variants):
        source = os.path.join(directory, variant["source"])
        for target in AMD_TARGETS:
            tasks.append((index, target, lambda s=source, o=variant["options"], t=target: compile_amd(
                tools, s, o, t, directory)))
        # Intel's compiler takes 10 s and more for the CPU-only programs: GPU-path ones only.
        for device in INTEL_DEVICES if any(k["gpu_path"] for k in variant["kernels"]) else []:
            tasks.append((index, device, lambda s=source, o=variant["options"], d=device: compile_intel(
                tools, s, o, d, directory)))
        tasks.append((index, "nvptx", lambda s=source, o=variant["options"]: compile_nvptx(tools, s, o, directory)))
    # Slow compiles (big programs, Intel) first, so the pool drains evenly.
    tasks.sort(key=lambda task: (task[1] not in INTEL_DEVICES, -os.path.getsize(
        os.path.join(directory, variants[task[0]]["source"]))))
    results = {}
    failures = []
    seconds = {}

    def timed(task):
        start = time.time()
        try:
            return task[2]()
        finally:
            seconds[task[1]] = seconds.get(task[1], 0.0) + time.time() - start

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(timed, task): task for task in tasks}
        for future in concurrent.futures.as_completed(futures):
            index, target, _ = futures[future]
            try:
                results[(index, target)] = future.result()
            except Exception as error:  # a compile error is a finding, reported below
                failures.append(f"{variants[index]['source']} ({variants[index]['file']} "
                                f"{' '.join(variants[index]['defines'])}) for {target}: {error}")
    return results, failures, seconds


def build_rows(variants, results):
    """Per report row and target: the worst figures over the row's variants."""
    rows = {}
    targets = list(AMD_TARGETS) + INTEL_DEVICES + ["nvptx"]
    gpu_kernels = {k["name"] for v in variants for k in v["kernels"] if k["gpu_path"]}
    for index, variant in enumerate(variants):
        for kernel in variant["kernels"]:
            key = row_key(variant, kernel, gpu_kernels)
            row = rows.setdefault(key, {"kernel": kernel["name"], "file": variant["file"],
                                        "gpu_path": kernel["gpu_path"], "layers": layers_of(variant),
                                        "variants": 0, "targets": {}})
            row["variants"] += 1
            for target in targets:
                figures = results.get((index, target), {}).get(kernel["name"])
                if figures is None:
                    # Compiled, yet the kernel is absent: a catalogue that names a wrong kernel.
                    if (index, target) in results:
                        row["targets"].setdefault(target, {})["missing"] = True
                    continue
                worst = row["targets"].setdefault(target, {})
                for field, value in figures.items():
                    if field == "limiter":
                        continue
                    if field in ("waves_per_simd", "simd"):
                        if field not in worst or value < worst[field]:
                            worst[field] = value
                            if field == "waves_per_simd":
                                worst["limiter"] = figures["limiter"]
                    elif isinstance(value, bool):
                        worst[field] = worst.get(field, False) or value
                    else:
                        worst[field] = max(worst.get(field, value), value)
    return rows


def waves_text(value):
    return f"{value:g}"


def markdown(rows, elapsed, jobs, variant_count):
    lines = []
    lines.append(f"{variant_count} program variants; worst figure over each row's variants. "
                 f"GPU path: `automatic` can pick it on a GPU; CPU-only and explicit-only baselines are exempt "
                 f"from the budgets.")
    lines.append("")
    lines.append("AMD (clang-15 + libclc-15): VGPRs, spills (VGPR+SGPR), LDS bytes, private bytes, waves per SIMD "
                 "(limiter)")
    lines.append("")
    header = "| kernel | path | " + " | ".join(AMD_TARGETS) + " |"
    lines.append(header)
    lines.append("| --- | --- |" + " --- |" * len(AMD_TARGETS))
    order = sorted(rows, key=lambda k: (not rows[k]["gpu_path"], rows[k]["file"], k))
    for key in order:
        row = rows[key]
        cells = []
        for target in AMD_TARGETS:
            f = row["targets"].get(target, {})
            if "vgpr" not in f:
                cells.append("-")
                continue
            cells.append(f"{f['vgpr']} v, {f['vgpr_spill'] + f['sgpr_spill']} sp, {f['lds_bytes']} L, "
                         f"{f['private_bytes']} p, **{waves_text(f['waves_per_simd'])}** ({f['limiter']})")
        lines.append(f"| `{key}` | {'GPU' if row['gpu_path'] else 'CPU/baseline'} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append("Intel (ocloc 22.43) and NVIDIA (PTX for sm_80): SIMD width, GRF, spill bytes, private bytes, "
                 "SLM bytes; PTX stack bytes and ld/st.local")
    lines.append("")
    lines.append("| kernel | path | " + " | ".join(INTEL_DEVICES) + " | nvptx stack, ld/st.local |")
    lines.append("| --- | --- |" + " --- |" * (len(INTEL_DEVICES) + 1))
    for key in order:
        row = rows[key]
        cells = []
        for device in INTEL_DEVICES:
            f = row["targets"].get(device, {})
            if "grf" not in f:
                cells.append("-")
                continue
            cells.append(f"SIMD{f['simd']}, {f['grf']} GRF, {max(f['spill_bytes'], f['scratch_bytes'])} sp, "
                         f"{f['private_bytes']} p, {f['slm_bytes']} L")
        f = row["targets"].get("nvptx", {})
        cells.append(f"{f['stack_bytes']} B, {f['local_loads']}/{f['local_stores']}" if "stack_bytes" in f
                     else "-")
        lines.append(f"| `{key}` | {'GPU' if row['gpu_path'] else 'CPU/baseline'} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append(f"Compiled in {elapsed:.0f} s with {jobs} parallel jobs.")
    return "\n".join(lines) + "\n"


# --- Predictions ---------------------------------------------------------------------------
# Compulsory bytes per kernel on a reference workload (every input read once, every output
# written once; caches assumed to catch the guard bands and neighbouring texel fetches):
# a 2048^2 depth map with S = 4 samples into nlq64 (8 bytes per texel), the SAT of the same
# map (16 bytes per texel), 1920x1080 receivers shaded from it, single scattering with a
# 1024^2 moments128 light map, a 1024^2 rectified map and 1920x1080 pixels.
MAP = 2048 * 2048
RECEIVERS = 1920 * 1080
RECTIFIED = 1024 * 1024
PREDICTED_KERNELS = [
    ("filter_fused_gpu", MAP * (4 * 4 + 8), "depths (S=4) in, nlq64 out"),
    ("filter_resolve", MAP * (4 * 4 + 16), "depths in, float4 moments out"),
    ("filter_horizontal", MAP * (16 + 16), "float4 moments in and out"),
    ("filter_vertical_quantize", MAP * (16 + 8), "float4 moments in, nlq64 out"),
    ("sat_tile_totals", MAP * (4 * 4 + 1), "depths in, carries out (1/16 of the table)"),
    ("sat_tile_scan", MAP * (4 * 4 + 1 + 16), "depths and carries in, table out"),
    ("sat_column_carries", MAP * 1, "column totals in place (1/32 of the table, both ways)"),
    ("shade", RECEIVERS * 16 + MAP * 8, "receivers (u, v, z) in, intensity out, the map once"),
    ("sat_soft_shade", RECEIVERS * 16 + MAP * 16, "receivers in, intensity out, the table once"),
    ("scatter_prefilter", RECTIFIED * (16 + 8), "moments128 map once, 64-bit texels out"),
    ("scatter_evaluate", RECEIVERS * (4 + 4) + RECTIFIED * 8, "camera depth in, radiance out, the map once"),
]
# (GPU, report target whose occupancy applies, bytes per second). NVPTX has no occupancy
# without ptxas: full occupancy assumed.
PREDICTION_GPUS = [
    ("AMD Instinct MI210 (gfx90a)", "gfx90a", 1.6e12),
    ("AMD Radeon RX 6800 XT (gfx1030)", "gfx1030", 512e9),
    ("NVIDIA H200 (sm_90, PTX for sm_80)", None, 4.8e12),
]
# Rule of thumb, not a measurement: a memory-bound kernel reaches peak bandwidth from this
# many waves per SIMD on, and proportionally less below.
SATURATING_WAVES = 4


def predictions(rows):
    lines = ["Predicted times (**predictions**, not measurements): compulsory bytes / (peak bandwidth x "
             f"min(1, waves per SIMD / {SATURATING_WAVES})), worst variant's occupancy", ""]
    lines.append("| kernel | bytes moved | MB | " + " | ".join(name for name, _, _ in PREDICTION_GPUS) + " |")
    lines.append("| --- | --- | ---: |" + " ---: |" * len(PREDICTION_GPUS))
    table = []
    for kernel, bytes_moved, what in PREDICTED_KERNELS:
        cells = []
        entry = {"kernel": kernel, "bytes": bytes_moved, "what": what, "ms": {}}
        for name, target, bandwidth in PREDICTION_GPUS:
            waves = rows.get(kernel, {}).get("targets", {}).get(target, {}).get("waves_per_simd") if target else None
            share = 1.0 if waves is None else min(1.0, waves / SATURATING_WAVES)
            ms = bytes_moved / (bandwidth * share) * 1e3 if share > 0 else float("inf")
            entry["ms"][name] = round(ms, 4)
            cells.append(f"{ms:.3f} ms" + ("" if waves is None else f" ({waves:g} w)"))
        table.append(entry)
        lines.append(f"| `{kernel}` | {what} | {bytes_moved / 1e6:.1f} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n", table


# --- Budgets -------------------------------------------------------------------------------
def check_budgets(rows, failures):
    breaches = list("compile failed: " + f for f in failures)

    def need(condition, text):
        if not condition:
            breaches.append(text)

    for key, row in rows.items():
        if not row["gpu_path"]:
            continue
        for target, f in row["targets"].items():
            if f.get("missing"):
                breaches.append(f"{key} on {target}: kernel missing from the compiled program")
                continue
            if target in AMD_TARGETS:
                need(f["vgpr_spill"] + f["sgpr_spill"] == 0,
                     f"{key} on {target}: {f['vgpr_spill']} VGPR and {f['sgpr_spill']} SGPR spills")
                need(f["private_bytes"] == 0 and not f["dynamic_stack"],
                     f"{key} on {target}: {f['private_bytes']} private bytes (stack arrays or spills)")
            elif target in INTEL_DEVICES:
                need(f["spill_bytes"] == 0 and f["scratch_bytes"] == 0,
                     f"{key} on {target}: {max(f['spill_bytes'], f['scratch_bytes'])} bytes of GRF spills")
                need(f["private_bytes"] == 0, f"{key} on {target}: {f['private_bytes']} private bytes")
            else:
                need(f["stack_bytes"] == 0, f"{key} on {target}: {f['stack_bytes']} stack bytes "
                                            f"({f['local_loads']} ld.local, {f['local_stores']} st.local)")

    def waves(key, target):
        return rows.get(key, {}).get("targets", {}).get(target, {}).get("waves_per_simd", 0)

    # The paper's fused kernel (opaque), the GPU SAT build, the 8-layer translucent variant.
    need(waves("filter_fused_gpu", "gfx90a") >= 3, f"filter_fused_gpu: {waves('filter_fused_gpu', 'gfx90a')} "
                                                  f"waves/SIMD on gfx90a, budget 3")
    need(waves("filter_fused_gpu", "gfx1030") >= 12, f"filter_fused_gpu: {waves('filter_fused_gpu', 'gfx1030')} "
                                                    f"waves/SIMD on gfx1030, budget 12")
    for kernel in ("sat_tile_totals", "sat_tile_scan"):
        need(waves(kernel, "gfx90a") >= 4, f"{kernel}: {waves(kernel, 'gfx90a')} waves/SIMD on gfx90a, budget 4")
    translucent = "filter_fused_gpu (8 layers)"
    need(translucent in rows, "no 8-layer variant of filter_fused_gpu in the report")
    need(waves(translucent, "gfx906") >= 2, f"{translucent}: {waves(translucent, 'gfx906')} waves/SIMD on gfx906, "
                                            f"budget 2")
    return breaches


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--variants-tool")
    parser.add_argument("--json")
    parser.add_argument("--markdown")
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--full", action="store_true")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--work", help="keep the assembled sources here (default: a temporary folder)")
    parser.add_argument("--sources", help="compile the variants already in this folder (variants.json)")
    args = parser.parse_args()

    tools, missing = find_toolchains()
    if missing:
        message = "gpu_compile_report: missing toolchain: " + "; ".join(missing)
        if os.environ.get("MSMCL_REQUIRE_GPU_TOOLCHAINS") == "1":
            print(message + " (MSMCL_REQUIRE_GPU_TOOLCHAINS=1: failing)", file=sys.stderr)
            return 1
        print(message + " (skipped)", file=sys.stderr)
        return SKIP

    start = time.time()
    directory = args.sources or args.work or tempfile.mkdtemp(prefix="msmcl-gpu-compile-")
    try:
        if not args.sources:
            run([args.variants_tool, directory] + (["--full"] if args.full else []))
        variants = json.load(open(os.path.join(directory, "variants.json")))
        results, failures, seconds = compile_all(tools, variants, directory, args.jobs)
        rows = build_rows(variants, results)
    finally:
        if not args.work and not args.sources:
            shutil.rmtree(directory, ignore_errors=True)
    elapsed = time.time() - start

    report = markdown(rows, elapsed, args.jobs, len(variants))
    predicted_text, predicted = predictions(rows)
    report += "\n" + predicted_text
    breaches = check_budgets(rows, failures)
    if args.markdown:
        with open(args.markdown, "w") as out:
            out.write(report)
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"variants": len(variants), "seconds": round(elapsed, 1), "jobs": args.jobs,
                       "compile_seconds": {t: round(v, 1) for t, v in seconds.items()},
                       "failures": failures, "budget_breaches": breaches, "kernels": rows,
                       "predictions": predicted}, out, indent=1)
    print(report)
    for failure in failures:
        print("compile failure: " + failure, file=sys.stderr)
    if args.check:
        for breach in breaches:
            print("budget: " + breach, file=sys.stderr)
        print(f"gpu_compile_report: {len(breaches)} budget breaches", file=sys.stderr)
        return 1 if breaches else 0
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
