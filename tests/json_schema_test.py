"""The JSON of `msmcl info --json` and of a batch's `--json` summary against their JSON Schemas
(docs/schemas/), on real outputs: maps of every format in every container (EXR, KTX2, DDS),
summed-area tables, a depth map, receivers, a shadow, and a batch with a file that fails.

Usage: json_schema_test.py MSMCL SCHEMA_DIR DATA_DIR (ctest json_schema). Needs Debian's
python3-jsonschema; exit 77 (skipped) without it.
"""
import json
import os
import subprocess
import sys
import tempfile

try:
    import jsonschema
except ImportError:
    print("SKIP: python3-jsonschema is not installed (scripts/install-deps.sh)")
    sys.exit(77)

msmcl, schema_dir, data_dir = sys.argv[1:4]
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what)


def run(arguments, expect=0):
    result = subprocess.run([msmcl] + arguments, capture_output=True, text=True)
    if result.returncode != expect:
        sys.exit(f"msmcl {' '.join(arguments)}: exit {result.returncode}, expected {expect}\n{result.stderr}")
    return result.stdout


def validator(name):
    with open(os.path.join(schema_dir, name)) as file:
        schema = json.load(file)
    jsonschema.Draft7Validator.check_schema(schema)
    return jsonschema.Draft7Validator(schema)


def validate(validator, document, what):
    errors = sorted(validator.iter_errors(document), key=lambda e: list(e.absolute_path))
    for error in errors:
        failures.append(f"{what}: {list(error.absolute_path)}: {error.message}")
        print(f"FAIL: {what}: at {list(error.absolute_path)}: {error.message}")


info_schema = validator("msmcl-info-1.schema.json")
batch_schema = validator("msmcl-batch-1.schema.json")
depth = os.path.join(data_dir, "railing_256x256_4x.exr")
receivers = os.path.join(data_dir, "railing_view_160x120.exr")

with tempfile.TemporaryDirectory(prefix="msmcl_json_schema_") as work:
    # Every format in every container, tables in every container (one batch each, from
    # JSON manifests of an output and options per entry), a shadow.
    formats = [name for name in info_schema.schema["definitions"]["format"]["enum"] if name != "sat"]
    maps = [{"input": depth, "format": format, "output": os.path.join(work, f"{format}.{container}")}
            for container in ("exr", "ktx2", "dds") for format in formats]
    tables = [{"input": depth, "output": os.path.join(work, f"sat.{container}")} for container in ("exr", "ktx2", "dds")]
    for command, entries, options in (("filter", maps, []), ("sat", tables, ["--max-kernel", "100"])):
        manifest, summary_path = os.path.join(work, f"{command}.json"), os.path.join(work, f"{command}_summary.json")
        with open(manifest, "w") as file:
            json.dump(entries, file)
        run([command, "--list", manifest, "-o", work, "--json", summary_path] + options)
        with open(summary_path) as file:
            validate(batch_schema, json.load(file), f"{command} batch --json")
    files = [depth, receivers] + [entry["output"] for entry in maps + tables]
    shadow = os.path.join(work, "shadow.exr")
    run(["shade", os.path.join(work, "msm64.exr"), receivers, shadow])
    files.append(shadow)

    described = json.loads(run(["info", "--json"] + files))
    validate(info_schema, described, "info --json")
    by_name = {os.path.basename(d["file"]): d for d in described}
    check(len({frozenset(d) for d in described}) == 1, "every description has the same keys")
    # The ambiguous DDS texel type: no format, the candidates instead.
    for name in ("msm64.dds", "nlq64.dds"):
        check(by_name[name]["format"] is None and by_name[name]["candidates"] == ["msm64", "nlq64"],
              f"{name}: format null, candidates msm64 and nlq64")
    check(by_name["nlq32.dds"]["format"] == "nlq32" and by_name["nlq32.dds"]["candidates"] is None,
          "nlq32.dds: format known, no candidates")
    # KTX2 metadata that are numbers are numbers, as in EXR.
    for container in ("exr", "ktx2"):
        record = by_name[f"msm64.{container}"]
        check(record["attributes"]["msmcl:samples"] == 4 and record["samples"] == 4,
              f"msm64.{container}: samples 4 as a number")
        check(isinstance(record["attributes"]["msmcl:sigma"], (int, float)), f"msm64.{container}: sigma a number")
    check(by_name["msm64.dds"]["samples"] is None, "msm64.dds: samples unknown (null)")
    # Each representation's maps are called what they are.
    for format, kind in (("nlq32", "moment shadow map"), ("vsm64", "variance shadow map"),
                         ("evsm4_64", "exponential variance shadow map"), ("esm32", "exponential shadow map")):
        for container in ("exr", "ktx2", "dds"):
            check(by_name[f"{format}.{container}"]["kind"] == kind, f"{format}.{container}: kind {kind}")
    # Every format the schema lists is one `msmcl filter` writes and `info` recognizes.
    for format in formats:
        check(by_name[f"{format}.exr"]["format"] == format, f"{format}.exr: format {format}")

    # A batch with a missing and a damaged input: the summary of every file.
    damaged = os.path.join(work, "damaged.exr")
    with open(depth, "rb") as source, open(damaged, "wb") as target:
        target.write(source.read()[:4096])
    summary_path = os.path.join(work, "summary.json")
    run(["filter", depth, os.path.join(work, "missing.exr"), damaged, "-o", os.path.join(work, "out"),
         "--format", "nlq32", "--json", summary_path], expect=2)
    with open(summary_path) as file:
        summary = json.load(file)
    validate(batch_schema, summary, "batch --json")
    check([f["status"] for f in summary["files"]] == ["written", "bad_input", "bad_input"],
          "batch: one written, two bad inputs")

print(f"{len(described)} descriptions and a batch summary of {len(summary['files'])} files checked")
if failures:
    sys.exit(f"{len(failures)} failures")
