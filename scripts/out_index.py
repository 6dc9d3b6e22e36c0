#!/usr/bin/env python3
"""Writes OUT_DIR/index.html: the main job's output as one page a person can read.

Every PNG of OUT_DIR (and OUT_DIR/quality/) with a caption that says what it shows, its
colour scale and its figures (read from the text and JSON files the main job writes beside
the images: soft_vs_pcss.txt, scatter_vs_marched.txt, vulkan_vs_opencl.txt,
quality/quality.json); the quality table (quality.md); advice on which format to use, drawn
from the measured quality table; and a link to every other file. The page is self-contained:
relative links, inline style, one small inline script (it marks images that fail to decode,
data-decoded="no", which the headless-browser test reads back). Standard library only.

    python3 scripts/out_index.py out            # writes out/index.html
    python3 scripts/out_index.py out --check    # also: exit 1 if an image has no specific caption
"""
import argparse
import html
import json
import os
import re
import sys

# Bits per texel of each method of the quality table (docs/formats.md; VSM: two moments).
BITS = {"moments128": 128, "msm64": 64, "nlq64": 64, "nlq32": 32, "vsm64": 64, "vsm32": 32, "evsm2_32": 32,
        "evsm2_32_lbr0.15": 32, "evsm4_64": 64, "evsm4_64_lbr0.15": 64, "evsm4_128": 128, "evsm4_128_lbr0.15": 128,
        "esm32": 32}
FORMATS = ("moments128", "msm64", "nlq64", "nlq32")
MAPS = {"256": "256x256 map (4x MSAA), 160x120 view", "1024": "1024x1024 map, 640x480 view"}

SHADOW_SCALE_LIT = "grey: the view's lighting times the light that reaches each receiver (ambient + direct x (1 - shadow))"
SHADOW_SCALE_PLAIN = "grey: white lit, black fully shadowed"
DIFF_BAR = ("the colour bar below the image: blue at -{r}, white at 0, red at +{r} "
            "(tools/signed_difference.hpp; saturated beyond)")


def read_text(out, name):
    path = os.path.join(out, name)
    return open(path, encoding="utf-8").read() if os.path.exists(path) else ""


def line_for(text, pattern):
    """The first line of `text` that matches `pattern`, without what the pattern matched."""
    for line in text.splitlines():
        match = re.search(pattern, line)
        if match:
            return line[match.end():].strip()
    return None


def quality_figures(s):
    """One method's figures against the PCF truth, from quality.json."""
    return (f"vs PCF truth (quality table): {100 * s['share_above_3pct']:.2f}% of receivers off by > 3%, "
            f"{s['count_above_10pct']} by > 10%, max {s['max']:.4f}, mean {s['mean']:.5f}")


def scene_words(name):
    scene, _, size = name.rpartition("_")
    return f"{scene} scene, {MAPS.get(size, size)}"


class Catalogue:
    """Captions by file name: (title, what it shows, colour scale, figures or None)."""

    def __init__(self, out):
        self.out = out
        self.soft = read_text(out, "soft_vs_pcss.txt")
        self.scatter = read_text(out, "scatter_vs_marched.txt")
        self.vulkan = read_text(out, "vulkan_vs_opencl.txt")
        self.quality = {}
        quality = read_text(out, "quality/quality.json")
        if quality:
            for scene in json.loads(quality)["scenes"]:
                self.quality[scene["scene"]] = {m["method"]: m for m in scene["methods"]}

    def caption(self, relative):
        name = os.path.basename(relative)[:-4]
        if relative.startswith("quality/"):
            return self.quality_caption(name)
        rules = [
            (r"^(\w+_(?:256|1024))_(" + "|".join(FORMATS) + r")_(bilinear|nearest)_vulkan_diff$", self.vulkan_diff),
            (r"^(\w+_(?:256|1024))_(" + "|".join(FORMATS) + r")_(bilinear|nearest)_vulkan$", self.vulkan_shadow),
            (r"^(\w+_(?:256|1024))_(" + "|".join(FORMATS) + r")_(bilinear|nearest)$", self.shadow),
            (r"^(\w+_(?:256|1024))_(soft|soft_published)_diff_pm([0-9.]+)$", self.soft_diff),
            (r"^(\w+_(?:256|1024))_(soft|soft_published|soft_pcss)$", self.soft_shadow),
            (r"^(\w+_1024)_soft_vs_pcss$", self.soft_figure),
            (r"^(\w+)_1024_representations$", self.representations_figure),
            (r"^(\w+)_nlq64_lookups$", self.lookups),
            (r"^smoke_1024_hard$", self.smoke),
            (r"^smoke_1024_(moments128|nlq64|soft)$", self.smoke),
            (r"^(\w+)_scatter([46])_diff$", self.scatter_diff),
            (r"^(\w+)_(scatter[46]|marched128|marched1024)$", self.scatter_image),
            (r"^(\w+)_scatter_vs_marched$", self.scatter_figure),
        ]
        for pattern, describe in rules:
            match = re.match(pattern, name)
            if match:
                return describe(*match.groups())
        return None

    def shadow(self, scene, format, lookup):
        lit = scene.endswith("1024")
        # The quality table measures the 1024^2 scenes with the bilinear lookup.
        measured = self.quality.get(scene.rpartition("_")[0], {}).get(format) if lit and lookup == "bilinear" else None
        figures = measured and quality_figures(measured["vs_pcf_truth"])
        return (f"{scene}: {format}, {lookup} lookup",
                f"The shadow of the {scene_words(scene)}, shaded from the {format} map "
                f"({BITS[format]} bits per texel) with the {lookup} lookup.",
                SHADOW_SCALE_LIT if lit else SHADOW_SCALE_PLAIN, figures)

    def vulkan_shadow(self, scene, format, lookup):
        return (f"{scene}: {format} in Vulkan",
                f"The same shadow as {scene}_{format}_{lookup}.png, shaded by shaders/msm.glsl in Vulkan from the "
                f"{format} KTX2 file.", SHADOW_SCALE_LIT, None)

    def vulkan_diff(self, scene, format, lookup):
        figures = line_for(self.vulkan, rf"{scene} {format} {lookup}, Vulkan - OpenCL: ")
        scale = {"nlq32": "1e-06", "msm64": "0.0001"}.get(format, "the value printed on the bar")
        return (f"{scene}: {format}, Vulkan - OpenCL",
                "Shadow intensity from Vulkan (b) minus OpenCL (a): red where the Vulkan shadow is darker, blue "
                "where lighter.", DIFF_BAR.format(r=scale), figures)

    def soft_shadow(self, scene, method):
        what = {"soft": "moment soft shadow mapping with msmcl's refinements",
                "soft_published": "moment soft shadow mapping as published",
                "soft_pcss": "brute-force PCSS in double precision (the reference)"}[method]
        return (f"{scene}: {method.replace('_', ' ')}",
                f"Soft shadow of a directional light of finite size, {scene_words(scene)}: {what}.",
                SHADOW_SCALE_LIT if scene.endswith("1024") else SHADOW_SCALE_PLAIN, None)

    def soft_diff(self, scene, method, range_):
        figures = line_for(self.soft, rf"^{scene} {method} vs PCSS: ")
        return (f"{scene}: {method.replace('_', ' ')} - PCSS",
                "Light of the moment soft shadow minus light of brute-force PCSS: red lighter than PCSS, blue darker.",
                DIFF_BAR.format(r=range_), figures)

    def soft_figure(self, scene):
        return (f"{scene}: soft shadows against PCSS",
                "PCSS, both moment soft shadow variants and their differences from PCSS in one figure.",
                "grey shadows; differences in the colour map of the bar drawn in the figure (+-0.5)",
                "; ".join(f"{m}: {line_for(self.soft, rf'^{scene} {m} vs PCSS: ')}"
                          for m in ("soft", "soft_published") if line_for(self.soft, rf"^{scene} {m} vs PCSS: "))
                or None)

    def representations_figure(self, scene):
        leaks = {m: v["banner_leak"]["mean"] for m, v in self.quality.get(scene, {}).items() if "banner_leak" in v}
        return (f"{scene}: every representation by bits per texel",
                "The shadow of each representation at 32, 64 and 128 bits per texel (columns) and its signed "
                "difference from the PCF truth below; the titles give the share off by > 3% and the banner leak.",
                "grey shadows; differences in the colour map of the bar drawn in the figure (+-0.1)",
                ("banner leak (mean): " + ", ".join(f"{m} {v:.4f}" for m, v in leaks.items())) if leaks else None)

    def lookups(self, scene):
        return (f"{scene}: the lookups of nlq64, magnified",
                "A 240x160 crop of the 640x480 view of a 256x256 nlq64 map, zoomed 2x, four panels named above "
                "them: nearest, bilinear, dither (one frame), the mean of 64 dither frames.",
                SHADOW_SCALE_LIT, None)

    def smoke(self, method="hard"):
        what = {"hard": "the hard shadow of the opaque scene and the smoke planes (a preview of the depth map)",
                "moments128": "the shadow through translucent smoke from the moments128 map",
                "nlq64": "the shadow through translucent smoke from the nlq64 map",
                "soft": "the soft shadow through translucent smoke (summed-area table)"}[method]
        return (f"smoke_1024: {method}", f"Translucent occluders, 8 smoke planes before the banner: {what}.",
                SHADOW_SCALE_LIT, None)

    def scatter_image(self, scene, method):
        what = {"scatter4": "prefiltered single scattering from 4 moments",
                "scatter6": "prefiltered single scattering from 6 moments",
                "marched128": "ray marching of the hard shadow map, 128 samples per view ray",
                "marched1024": "ray marching, 1024 samples per view ray (the truth)"}[method]
        return (f"{scene}: {method}", f"Light shafts in the {scene} scene: {what}.",
                "grey: in-scattered radiance, white at the scene's white point", None)

    def scatter_diff(self, scene, moments):
        figures = line_for(self.scatter, rf"{scene}_scatter{moments}\.exr vs ")
        return (f"{scene}: {moments} moments - truth",
                "Lit fraction of each view ray, prefiltered minus 1024-sample ray marching: red lighter, blue darker.",
                DIFF_BAR.format(r="0.1"), figures and "vs " + figures)

    def scatter_figure(self, scene):
        return (f"{scene}: scattering against ray marching",
                "The truth, both moment counts and their differences in one figure with a numbered legend.",
                "grey radiance; differences in the colour map of the bar drawn in the figure (+-0.1)", None)

    def quality_caption(self, name):
        for scene, methods in self.quality.items():
            if not name.startswith(scene + "_"):
                continue
            rest = name[len(scene) + 1:]
            if rest in ("pcf_truth", "pcf_constant_bias"):
                what = ("percentage-closer filtering with per-sample receiver planes (the ground truth)"
                        if rest == "pcf_truth" else "percentage-closer filtering with a constant receiver depth")
                return (f"{scene}: {rest.replace('_', ' ')}", f"Shadow intensity, {what}.",
                        "grey: black lit (0), white fully shadowed (1)", None)
            if rest == "nlq64_vs_moments128":
                return (f"{scene}: where nlq64 differs from moments128",
                        "The moments128 shadow in grey; receivers where nlq64 differs by more than 3% in orange, "
                        "by more than 10% in red.",
                        "grey 0.85 lit .. 0.25 shadowed; orange > 3%, red > 10% (legend below the image)", None)
            method, _, kind = rest.rpartition("_")
            if method in methods and kind in ("shadow", "error"):
                figures = quality_figures(methods[method]["vs_pcf_truth"])
                if kind == "shadow":
                    return (f"{scene}: {method}", f"Shadow intensity from {method} ({BITS.get(method, '?')} bits).",
                            "grey: black lit (0), white fully shadowed (1)", figures)
                return (f"{scene}: {method} - PCF truth",
                        f"Light of {method} minus light of the PCF truth: red lighter (leaks), blue darker.",
                        DIFF_BAR.format(r="0.1"), figures)
        return None


def markdown_html(text):
    """The quality table's Markdown (headings, paragraphs, pipe tables) as HTML."""
    parts, table, paragraph = [], [], []

    def flush():
        if paragraph:
            parts.append("<p>" + html.escape(" ".join(paragraph)) + "</p>")
            paragraph.clear()
        if table:
            rows = [r for r in table if not re.match(r"^\|[\s:|-]+\|$", r)]
            cells = [[html.escape(c.strip()) for c in r.strip().strip("|").split("|")] for r in rows]
            head = "".join(f"<th>{c}</th>" for c in cells[0])
            body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in cells[1:])
            parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
            table.clear()

    for line in text.splitlines():
        if line.startswith("|"):
            if paragraph:
                flush()
            table.append(line)
            continue
        if table:
            flush()
        heading = re.match(r"^(#+) (.*)", line)
        if heading:
            flush()
            level = min(len(heading.group(1)) + 2, 6)
            parts.append(f"<h{level}>{html.escape(heading.group(2))}</h{level}>")
        elif line.strip():
            paragraph.append(line.strip())
        else:
            flush()
    flush()
    return "\n".join(parts)


def advice(quality_json):
    """Which format to use, from the measured table: per scene each format's bits and its share of
    receivers more than 3% from 128-bit moments and from the PCF truth; the smallest format within
    3% of moments128 on 99% of the receivers of every scene."""
    scenes = quality_json["scenes"]
    rows, within = [], {f: True for f in FORMATS}
    for scene in scenes:
        for m in scene["methods"]:
            name = m["method"]
            v128, truth = m["vs_moments128"]["share_above_3pct"], m["vs_pcf_truth"]["share_above_3pct"]
            leak = m.get("banner_leak", {}).get("mean")
            rows.append((scene["scene"], name, BITS.get(name, "?"), v128, truth, leak))
            if name in within and v128 > 0.01:
                within[name] = False
    smallest = min((f for f in FORMATS if within[f]), key=lambda f: BITS[f], default="moments128")
    table = ("<table><thead><tr><th>scene</th><th>method</th><th>bits per texel</th><th>&gt; 3% from moments128</th>"
             "<th>&gt; 3% from PCF truth</th><th>banner leak (mean)</th></tr></thead><tbody>")
    for scene, name, bits, v128, truth, leak in rows:
        table += (f"<tr><td>{html.escape(scene)}</td><td>{name}</td><td>{bits}</td><td>{100 * v128:.2f}%</td>"
                  f"<td>{100 * truth:.2f}%</td><td>{'-' if leak is None else f'{leak:.4f}'}</td></tr>")
    table += "</tbody></table>"
    keeps = ", ".join(f for f in FORMATS if within[f])
    worst = {name: max(r[3] for r in rows if r[1] == name) for name in {r[1] for r in rows}}
    smaller = [f for f in FORMATS if BITS[f] < BITS[smallest]]
    text = (f"<p><strong>Use {smallest}</strong> ({BITS[smallest]} bits per texel): the smallest format whose "
            f"shadow stays within 3% of 128-bit moments on at least 99% of the receivers of every measured scene "
            f"(formats that do: {keeps}; moments128 is the reference). ")
    if smaller:
        text += ("Where memory matters most: " + ", ".join(
            f"{f} ({BITS[f]} bits) is more than 3% off on up to {100 * worst[f]:.2f}% of a scene's receivers"
            for f in smaller if f in worst) + ". ")
    leaks = {r[1]: r[5] for r in rows if r[5] is not None}
    vsm = [m for m in leaks if m.startswith("vsm")]
    if vsm and smallest in leaks:
        text += (f"Variance shadow maps, for comparison: banner leak {max(leaks[m] for m in vsm):.4f} against "
                 f"{leaks[smallest]:.4f} for {smallest}. ")
    text += "The numbers come from this run's quality table (quality/quality.json).</p>"
    return text + table


PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>msmcl main job: {title}</title>
<style>
body {{ font: 15px/1.45 sans-serif; margin: 1.5em auto; max-width: 1400px; padding: 0 1em; color: #222; }}
figure {{ display: inline-block; vertical-align: top; margin: 0 1em 1.5em 0; max-width: 660px; }}
figure img {{ max-width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }}
figcaption {{ font-size: 13px; }} figcaption .scale, figcaption .figures {{ color: #555; display: block; }}
table {{ border-collapse: collapse; font-size: 13px; margin: 0.5em 0 1.5em; }}
td, th {{ border: 1px solid #ccc; padding: 2px 6px; text-align: right; }}
td:first-child, th:first-child {{ text-align: left; }}
</style></head>
<body>
<h1>msmcl main job: {title}</h1>
<p>Written by scripts/main.sh (scripts/out_index.py). Sections: {toc}.</p>
{body}
<script>
// Marks every image that did not decode (data-decoded="no"); the browser test reads this back.
window.addEventListener("load", function () {{
  var images = document.images, broken = 0;
  for (var i = 0; i < images.length; i++) {{
    var ok = images[i].complete && images[i].naturalWidth > 0;
    images[i].setAttribute("data-decoded", ok ? "yes" : "no");
    if (!ok) broken++;
  }}
  document.body.setAttribute("data-images-checked", String(images.length));
  document.body.setAttribute("data-images-broken", String(broken));
}});
</script>
</body></html>
"""

SECTIONS = [
    ("formats", "Shadows of every format", r"_(bilinear|nearest)$"),
    ("vulkan", "The same textures in Vulkan", r"_vulkan(_diff)?$"),
    ("soft", "Soft shadows", r"_soft"),
    ("lookups", "Lookups", r"_lookups$"),
    ("smoke", "Translucent occluders", r"^smoke_"),
    ("scatter", "Single scattering", r"_(scatter|marched)"),
    ("quality", "Quality images", r"^quality/"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--title", default="out/")
    parser.add_argument("--check", action="store_true", help="exit 1 if an image has no specific caption")
    args = parser.parse_args()
    out = args.out_dir
    catalogue = Catalogue(out)

    files = sorted(os.path.relpath(os.path.join(d, f), out).replace(os.sep, "/")
                   for d, _, names in os.walk(out) for f in names if f != "index.html")
    images = [f for f in files if f.endswith(".png")]
    sections = {key: [] for key, _, _ in SECTIONS}
    sections["other"] = []
    uncaptioned = []
    for image in images:
        caption = catalogue.caption(image)
        if caption is None:
            uncaptioned.append(image)
            caption = (image, "An image of the main job that this page does not describe yet.", "unknown", None)
        stem = image[:-4]
        key = next((k for k, _, p in SECTIONS if re.search(p, stem)), "other")
        sections[key].append((image, caption))

    body, toc = [], []
    quality_json = read_text(out, "quality/quality.json")
    if quality_json:
        toc.append('<a href="#advice">which format</a>')
        body.append('<h2 id="advice">Which format</h2>\n' + advice(json.loads(quality_json)))
    quality_md = read_text(out, "quality.md")
    if quality_md:
        toc.append('<a href="#quality-table">quality table</a>')
        body.append('<h2 id="quality-table">Quality table</h2>\n<p>From <a href="quality.md">quality.md</a>.</p>\n' +
                    markdown_html(quality_md))
    for key, heading in [(k, h) for k, h, _ in SECTIONS] + [("other", "Other images")]:
        if not sections[key]:
            continue
        toc.append(f'<a href="#{key}">{heading.lower()}</a>')
        body.append(f'<h2 id="{key}">{heading}</h2>')
        for image, (title, what, scale, figures) in sections[key]:
            src = html.escape(image, quote=True)
            body.append(
                f'<figure><a href="{src}"><img src="{src}" alt="{html.escape(title, quote=True)}"></a>'
                f"<figcaption><strong>{html.escape(title)}</strong> ({html.escape(image)}). {html.escape(what)}"
                f'<span class="scale">Scale: {html.escape(scale)}</span>'
                + (f'<span class="figures">Figures: {html.escape(figures)}</span>' if figures else "")
                + "</figcaption></figure>")
    toc.append('<a href="#files">every file</a>')
    body.append('<h2 id="files">Every file</h2>\n<ul>' + "".join(
        f'<li><a href="{html.escape(f, quote=True)}">{html.escape(f)}</a> ({os.path.getsize(os.path.join(out, f))} bytes)</li>'
        for f in files) + "</ul>")

    page = PAGE.format(title=html.escape(args.title), toc=", ".join(toc), body="\n".join(body))
    with open(os.path.join(out, "index.html"), "w", encoding="utf-8") as file:
        file.write(page)
    print(f"out_index: {len(images)} images, {len(files)} files in {os.path.join(out, 'index.html')}")
    for image in uncaptioned:
        print(f"out_index: no caption for {image}", file=sys.stderr)
    return 1 if args.check and uncaptioned else 0


if __name__ == "__main__":
    sys.exit(main())
