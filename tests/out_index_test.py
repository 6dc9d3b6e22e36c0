"""The main job's page (out/index.html, scripts/out_index.py) opened in headless Chromium from
the file system, no network: every image decodes (the page's inline script marks each image
data-decoded="yes" or "no" on load; --dump-dom reads the marks back) and every link and image
source resolves to a file (or an anchor) of the page.

    out_index_test.py --fixture SCRIPTS_DIR   # ctest out_index: a page made from a small fixture,
                                              # then a damaged PNG that must be caught
    out_index_test.py --out OUT_DIR           # the real out/ after scripts/main.sh (exit 77 without it)

Exit 77 (skipped) without chromium.
"""
import argparse
import html.parser
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import urllib.parse
import zlib

CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--virtual-time-budget=20000", "--dump-dom"]


def chromium():
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    print("SKIP: chromium is not installed (scripts/install-deps.sh)")
    sys.exit(77)


class Page(html.parser.HTMLParser):
    """The images (with their decode marks), links and anchors of a dumped page."""

    def __init__(self):
        super().__init__()
        self.images, self.links, self.ids, self.body = [], [], set(), {}

    def handle_starttag(self, tag, attributes):
        attributes = dict(attributes)
        if "id" in attributes:
            self.ids.add(attributes["id"])
        if tag == "img":
            self.images.append((attributes.get("src", ""), attributes.get("data-decoded")))
        elif tag in ("a", "link") and "href" in attributes:
            self.links.append(attributes["href"])
        elif tag == "script" and "src" in attributes:
            self.links.append(attributes["src"])
        elif tag == "body":
            self.body = attributes


def open_in_browser(page_path):
    """The page's DOM after load, as Chromium saw it."""
    with tempfile.TemporaryDirectory(prefix="msmcl_chromium_") as profile:
        result = subprocess.run([chromium()] + CHROMIUM_FLAGS + [f"--user-data-dir={profile}",
                                                                 "file://" + os.path.abspath(page_path)],
                                capture_output=True, text=True, timeout=300)
    if result.returncode != 0 or "<body" not in result.stdout:
        sys.exit(f"chromium failed (exit {result.returncode}):\n{result.stderr[-2000:]}")
    page = Page()
    page.feed(result.stdout)
    return page


def problems_of(page_path):
    """What is wrong with the page: images not decoded, links that lead nowhere."""
    page = open_in_browser(page_path)
    folder = os.path.dirname(os.path.abspath(page_path))
    problems = []
    if page.body.get("data-images-checked") != str(len(page.images)):
        problems.append(f"the page's check ran over {page.body.get('data-images-checked')} of {len(page.images)} images")
    problems += [f"image does not decode: {src}" for src, mark in page.images if mark != "yes"]
    for target in page.links + [src for src, _ in page.images]:
        parsed = urllib.parse.urlparse(target)
        if parsed.scheme or parsed.netloc:
            problems.append(f"link leaves the folder: {target}")
        elif not parsed.path:
            if parsed.fragment not in page.ids:
                problems.append(f"no anchor #{parsed.fragment}")
        elif not os.path.isfile(os.path.join(folder, urllib.parse.unquote(parsed.path))):
            problems.append(f"link to a missing file: {target}")
    print(f"{page_path}: {len(page.images)} images, {len(page.links)} links, {len(problems)} problems")
    return problems


def png(path, width, height, rgb):
    """A small RGB PNG of one colour."""
    rows = b"".join(b"\0" + bytes(rgb) * width for _ in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as file:
        file.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                   chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def make_fixture(out):
    """A few files of each kind the main job writes, with the text and JSON figures beside them."""
    for name in ("railing_256_msm64_bilinear", "railing_1024_nlq32_bilinear_vulkan_diff",
                 "railing_256_soft_diff_pm0.5", "railing_256_nlq64_lookups", "hall_scatter4_diff",
                 "quality/railing_1024_nlq32_error", "quality/railing_1024_pcf_truth"):
        png(os.path.join(out, name + ".png"), 16, 12, (200, 60, 40))
    with open(os.path.join(out, "railing_256_msm64.exr"), "wb") as file:
        file.write(b"v/1\x01 not a real EXR: a file the page links to")
    with open(os.path.join(out, "soft_vs_pcss.txt"), "w") as file:
        file.write("railing_256 soft vs PCSS: pixels 19200, mean |d| 0.0100\n")
    with open(os.path.join(out, "vulkan_vs_opencl.txt"), "w") as file:
        file.write("railing_1024 nlq32 bilinear, Vulkan - OpenCL: 307200 values: max |b - a| 1e-07\n")
    with open(os.path.join(out, "quality.md"), "w") as file:
        file.write("# msmcl quality table\n\nfixture.\n\n| method | >3% |\n| --- | ---: |\n| nlq32 | 1.00% |\n")
    stats = {"share_above_3pct": 0.005, "count_above_3pct": 5, "count_above_10pct": 1, "max": 0.2, "mean": 0.001}
    methods = [{"method": m, "vs_moments128": stats, "vs_pcf_truth": stats} for m in ("moments128", "msm64", "nlq32")]
    with open(os.path.join(out, "quality", "quality.json"), "w") as file:
        json.dump({"scenes": [{"scene": "railing_1024", "methods": methods}]}, file)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fixture", metavar="SCRIPTS_DIR")
    parser.add_argument("--out", metavar="OUT_DIR")
    args = parser.parse_args()
    if args.out:
        page = os.path.join(args.out, "index.html")
        if not os.path.isfile(page):
            print(f"SKIP: {page} does not exist (scripts/main.sh writes it)")
            return 77
        problems = problems_of(page)
    else:
        with tempfile.TemporaryDirectory(prefix="msmcl_out_index_") as out:
            make_fixture(out)
            generator = [sys.executable, os.path.join(args.fixture, "out_index.py"), out, "--check"]
            subprocess.run(generator, check=True)
            problems = problems_of(os.path.join(out, "index.html"))
            # The check must see a damaged image and a missing file: the same page after both.
            with open(os.path.join(out, "railing_256_nlq64_lookups.png"), "r+b") as file:
                file.truncate(40)
            os.remove(os.path.join(out, "soft_vs_pcss.txt"))
            caught = problems_of(os.path.join(out, "index.html"))
            expected = ["image does not decode: railing_256_nlq64_lookups.png", "link to a missing file: soft_vs_pcss.txt"]
            if sorted(caught) != sorted(expected):
                problems.append(f"a damaged PNG and a missing file gave {caught}, expected {expected}")
    for problem in problems:
        print("FAIL:", problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
