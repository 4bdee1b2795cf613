#!/usr/bin/env python3
"""Checks that every relative link in README.md and docs/ resolves.

Markdown links and images, [text](target) and ![alt](target), must name a file or folder
that exists (relative to the file that links), and a #fragment must match a heading of the
target (GitHub's anchors). A path written as code, `docs/...`, `bench/...`, `scripts/...`,
must exist relative to the repository root. Exit status 1 lists what does not resolve.
Usage: scripts/check_links.py [FILE.md ...]   (default: README.md and docs/**/*.md)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
CODE_PATH = re.compile(r"`((?:docs|bench|scripts|assets|tests)/[^`\s*<>…]+)`")
FENCE = re.compile(r"^(```|~~~)")


def anchors(md):
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    out, fenced = set(), False
    for line in md.read_text(encoding="utf-8").splitlines():
        if FENCE.match(line):
            fenced = not fenced
        m = None if fenced else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            text = re.sub(r"[^\w\- ]", "", m.group(1).lower())
            slug, n = text.replace(" ", "-"), 1
            while slug in out:
                slug = f"{text.replace(' ', '-')}-{n}"
                n += 1
            out.add(slug)
    return out


def check(md):
    errors, fenced = [], False
    for number, line in enumerate(md.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        for target in LINK.findall(line):
            if re.match(r"^[a-z]+:", target):  # http:, https:, mailto:
                continue
            path, _, fragment = target.partition("#")
            dest = (md.parent / path).resolve() if path else md
            if not dest.exists():
                errors.append(f"{md.relative_to(ROOT)}:{number}: {target}: no such file")
            elif fragment and dest.suffix == ".md" and fragment not in anchors(dest):
                errors.append(f"{md.relative_to(ROOT)}:{number}: {target}: no such heading")
        for path in CODE_PATH.findall(line):
            if any(c in path for c in "{}$<") or "not committed" in line:
                continue
            if not (ROOT / path.rstrip("/.,:;")).exists() and not any(ROOT.glob(path)):
                errors.append(f"{md.relative_to(ROOT)}:{number}: `{path}`: no such path")
    return errors


def main(argv):
    files = [pathlib.Path(a).resolve() for a in argv] or \
        [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
    errors = [e for f in files for e in check(f)]
    print("\n".join(errors) if errors else f"check_links: {len(files)} files, every relative link resolves")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
