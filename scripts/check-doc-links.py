#!/usr/bin/env python3
"""Checks the relative links of README.md and docs/**/*.md: every target file or folder must
exist, and every #anchor must name a heading of its target (GitHub's heading ids).
Usage: python3 scripts/check-doc-links.py [FILE.md ...]   Exit 1 on a broken link."""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
link = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def slugs(md):
    seen, out, fence = {}, set(), False
    for line in md.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fence = not fence
        if fence or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip()
        s = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
        n = seen.get(s, 0)
        seen[s] = n + 1
        out.add(s if n == 0 else f"{s}-{n}")
    return out


def check(md):
    bad, fence = [], False
    for no, line in enumerate(md.read_text(encoding="utf-8").splitlines(), 1):
        if line.startswith("```"):
            fence = not fence
        if fence:
            continue
        for target in link.findall(re.sub(r"`[^`]*`", "", line)):
            if re.match(r"[a-z]+:", target):
                continue
            path, _, anchor = target.partition("#")
            dest = (md.parent / path).resolve() if path else md
            if not dest.exists():
                bad.append(f"{md.relative_to(root)}:{no}: {target}: no such file")
            elif anchor and dest.suffix == ".md" and anchor not in slugs(dest):
                bad.append(f"{md.relative_to(root)}:{no}: {target}: no heading #{anchor}")
    return bad


files = [pathlib.Path(f).resolve() for f in sys.argv[1:]] or \
    [root / "README.md", *sorted((root / "docs").rglob("*.md"))]
problems = [p for f in files for p in check(f)]
print("\n".join(problems) if problems else f"{len(files)} files, every relative link resolves")
sys.exit(1 if problems else 0)
