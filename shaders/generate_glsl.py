#!/usr/bin/env python3
"""Writes msm.glsl: the hand-written texture-fetch wrappers of shaders/msm.glsl.in around the
device functions of kernels/*.clh that they and a renderer call.

The kernel headers are run through the C preprocessor with MSM_TARGET_GLSL defined (the GLSL
branch of kernels/msm_portable.clh: no storage class or pragma, `precise`, the GLSL names of
the bit casts). Of the preprocessed text this keeps the structs and functions named on the
template's `// @kernel-functions` lines and everything they and the wrappers call, in the
kernels' order, and writes what C has and GLSL lacks in GLSL's form: `typedef struct {...} T;`
as `struct T {...};`, casts `(float)x` as constructors `float(x)`, `(void)` as `()`. A wrapper
with the name of a kernel function takes that function's place (GLSL needs a function
defined before its first call). Each function keeps the comment above it in its header.

Usage: generate_glsl.py --kernels DIR --template shaders/msm.glsl.in --output msm.glsl [--cpp CPP]
"""
import argparse
import os
import re
import subprocess
import sys

HEADERS = ["msm_sat.clh", "msm_scatter.clh", "msm_filterable_shading.clh"]
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
CAST = re.compile(r"\((float|int|uint)\)\s*")
MARKER = "// @kernel-functions"


def preprocess(cpp, kernel_dir):
    """The kernel headers preprocessed for GLSL, as (text, file, line) per output line."""
    source = "".join('#include "%s"\n' % h for h in HEADERS)
    command = cpp.split() + ["-undef", "-nostdinc", "-DMSM_TARGET_GLSL", "-I", kernel_dir, "-"]
    result = subprocess.run(command, input=source, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("generate_glsl.py: %s failed:\n%s" % (" ".join(command), result.stderr))
    lines, file, line = [], None, 0
    for text in result.stdout.splitlines():
        marker = re.match(r'# (\d+) "([^"]*)"', text)
        if marker:
            line, file = int(marker.group(1)), marker.group(2)
            continue
        if text.lstrip().startswith("#"):
            text = ""  # a pragma of the OpenCL C compiler (FP_CONTRACT, unroll): not for shaders
        lines.append((text.rstrip(), file, line))
        line += 1
    return lines


def split_items(lines):
    """Top-level structs and functions: dicts with name, text and where they start."""
    items, current, depth, braces = [], [], 0, False
    for text, file, line in lines:
        if not current and not text.strip():
            continue
        current.append((text, file, line))
        for character in text:
            if character == "{":
                depth, braces = depth + 1, True
            elif character == "}":
                depth -= 1
        body = "\n".join(t for t, _, _ in current)
        # A function ends with its closing brace, a struct with the `;` after it.
        finished = depth == 0 and (
            (braces and (text.rstrip().endswith(";") or not body.lstrip().startswith(("typedef", "struct"))))
            or (not braces and text.rstrip().endswith(";")))
        if finished:
            items.append(make_item(current))
            current, braces = [], False
    if current:
        sys.exit("generate_glsl.py: unterminated item at %s:%d" % current[0][1:])
    return items


def make_item(lines):
    text = "\n".join(t for t, _, _ in lines if t.strip())
    typedef = re.match(r"\s*typedef\s+struct\s*(\{.*\})\s*(\w+)\s*;\s*$", text, re.S)
    if typedef:
        name, text = typedef.group(2), "struct %s %s;" % (typedef.group(2), typedef.group(1))
    else:
        declaration = text.split("(", 1)[0].split("{", 1)[0]
        name = IDENTIFIER.findall(declaration)[-1]
    return {"name": name, "text": text.strip(), "file": lines[0][1], "line": lines[0][2]}


def operand_end(text, i):
    """End of the cast-expression that starts at text[i] (C's precedence: unary, postfix)."""
    while text[i] in "-+!~ ":
        i += 1
    cast = CAST.match(text, i)
    if cast:
        return operand_end(text, cast.end())
    if text[i] == "(":
        i = group_end(text, i)
    else:
        token = re.compile(r"[\w.]+").match(text, i)
        if not token:
            sys.exit("generate_glsl.py: cannot read the operand of a cast in: " + text[max(0, i - 60):i + 60])
        i = token.end()
    while i < len(text) and text[i] in "([":
        i = group_end(text, i)
    return i


def group_end(text, i):
    closing = {"(": ")", "[": "]"}[text[i]]
    depth = 0
    for j in range(i, len(text)):
        if text[j] == text[i]:
            depth += 1
        elif text[j] == closing:
            depth -= 1
            if depth == 0:
                return j + 1
    sys.exit("generate_glsl.py: unbalanced %s in: %s" % (text[i], text[i:i + 80]))


def to_glsl(text):
    text = text.replace("(void)", "()")
    while True:
        cast = CAST.search(text)
        if not cast:
            return text
        end = operand_end(text, cast.end())
        operand = text[cast.end():end]
        if operand.startswith("(") and group_end(operand, 0) == len(operand):
            operand = operand[1:-1]
        text = text[:cast.start()] + "%s(%s)" % (cast.group(1), operand) + text[end:]


def comment_above(item, cache):
    """The // lines right above an item in its kernel header."""
    if item["file"] not in cache:
        with open(item["file"]) as f:
            cache[item["file"]] = f.read().split("\n")
    source, k, comment = cache[item["file"]], item["line"] - 2, []
    while k >= 0 and source[k].strip().startswith("//"):
        comment.insert(0, source[k].strip())
        k -= 1
    return comment


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--kernels", required=True)
    parser.add_argument("--template", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--cpp", default="cpp")
    args = parser.parse_args()

    with open(args.template) as f:
        template = f.read().split("\n")
    markers = [k for k, line in enumerate(template) if line.startswith(MARKER)]
    if not markers or markers != list(range(markers[0], markers[-1] + 1)):
        sys.exit("generate_glsl.py: %s needs one block of '%s' lines" % (args.template, MARKER))
    roots = {name for k in markers for name in template[k][len(MARKER):].split()}
    before, after = template[:markers[0]], template[markers[-1] + 1:]
    # The wrappers: blocks of lines between blank lines up to the include guard's #endif,
    # each a function (or struct) with the comment lines above it.
    body = "\n".join(after)
    guard_end = body.rstrip().rfind("#endif")
    trailer, wrappers = body[guard_end:], []
    for block in re.split(r"\n\s*\n", body[:guard_end]):
        code = [line for line in block.split("\n") if line.strip() and not line.lstrip().startswith("//")]
        name = make_item([(line, None, 0) for line in code])["name"] if code else None
        if block.strip():
            wrappers.append({"name": name, "text": block.strip("\n")})
    wrapper_names = {w["name"] for w in wrappers if w["name"]}

    items = split_items(preprocess(args.cpp, args.kernels))
    by_name = {}
    for item in items:
        by_name.setdefault(item["name"], []).append(item)
    missing = sorted(name for name in roots if name not in by_name)
    if missing:
        sys.exit("generate_glsl.py: not in kernels/*.clh: " + " ".join(missing))

    # Everything the roots and the wrappers need, by name.
    needed, queue = set(), list(roots)
    for w in wrappers:
        queue += IDENTIFIER.findall(w["text"])
    while queue:
        name = queue.pop()
        if name in needed or name not in by_name:
            continue
        needed.add(name)
        if name in wrapper_names:
            queue += [i for w in wrappers if w["name"] == name for i in IDENTIFIER.findall(w["text"])]
        else:
            for item in by_name[name]:
                queue += IDENTIFIER.findall(item["text"])

    out, placed, comments = before + [""], set(), {}
    for item in items:
        name = item["name"]
        if name not in needed or name in placed:
            continue
        placed.add(name)
        if name in wrapper_names:
            out += [w["text"] for w in wrappers if w["name"] == name] + [""]
            continue
        out += comment_above(item, comments) + [to_glsl(item["text"]), ""]
    out += [w["text"] + "\n" for w in wrappers if w["name"] not in placed]
    out.append(trailer)
    text = "\n".join(out).rstrip("\n") + "\n"
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output + ".tmp", "w") as f:
        f.write(text)
    os.replace(args.output + ".tmp", args.output)


if __name__ == "__main__":
    main()
