#!/usr/bin/env python3
"""Every relative link of README.md and docs/**/*.md must lead somewhere, and the index
docs/README.md must link every document of docs/.

A link `[text](path)` or `![alt](path)` must name a file or folder that exists, relative to
the document; `path#anchor` (or `#anchor` alone) must also name a heading of that Markdown
file, as GitHub makes anchors of headings. Links inside code are not links. Web addresses
are not checked (the test runs without a network).

    check_links.py REPOSITORY_ROOT      exit 0, or 1 and one line per problem
"""
import re
import sys
from pathlib import Path

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")


def prose_lines(path):
    """(line number, text) of the lines outside fenced code, code spans blanked out."""
    inside = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield number, CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line)


def slug(heading):
    """GitHub's anchor of a heading: the text without markup, lower case, punctuation
    dropped except '-' and '_', spaces turned into '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = re.sub(r"<[^>]+>", "", text).lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        found, seen = set(), {}
        inside = False
        for line in path.read_text(encoding="utf-8").splitlines():
            if FENCE.match(line):
                inside = not inside
                continue
            match = None if inside else HEADING.match(line)
            if match:
                base = slug(match.group(2))
                count = seen.get(base, 0)
                seen[base] = count + 1
                found.add(base if count == 0 else f"{base}-{count}")
            for name in re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", line):
                found.add(name)
        cache[path] = found
    return cache[path]


def broken_links(root):
    documents = [root / "README.md"] + sorted((root / "docs").rglob("*.md"))
    indexed = set()
    for document in (d for d in documents if d.is_file()):
        for number, line in prose_lines(document):
            for target in LINK.findall(line):
                if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target):
                    continue  # https:, mailto: ...
                path_part, _, anchor = target.partition("#")
                linked = (document.parent / path_part).resolve() if path_part else document
                where = f"{document.relative_to(root)}:{number}"
                if document == root / "docs" / "README.md":
                    indexed.add(linked)
                if not linked.exists():
                    yield f"{where}: {target}: no such file"
                elif anchor and linked.suffix == ".md" and anchor not in anchors(linked):
                    yield f"{where}: {target}: no heading with the anchor #{anchor}"
    # The index lists every document of docs/ (its own folder's pages, not subfolders).
    for document in sorted((root / "docs").glob("*.md")):
        if document.name != "README.md" and document.resolve() not in indexed:
            yield f"docs/README.md: {document.name} is not in the index"


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    broken = list(broken_links(root))
    for line in broken:
        print(line)
    if broken:
        print(f"{len(broken)} problems in the links of README.md and docs/")
        return 1
    print("every relative link of README.md and docs/ resolves; docs/README.md indexes every document")
    return 0


if __name__ == "__main__":
    sys.exit(main())
