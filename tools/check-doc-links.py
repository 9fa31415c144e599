#!/usr/bin/env python3
"""Check the project's Markdown documentation.

Usage: check-doc-links.py [SOURCE_DIR]

Checks README.md, CHANGELOG.md and docs/*.md:
- every relative Markdown link or image points to a file or folder that exists
  (anchors after '#' are ignored; http(s)/mailto links are not checked);
- README.md has at most 400 lines;
- no file mentions issue numbers ("issue 13", "issues #4") or paths to ../shared.
Exit status 0 when all is well, 1 with one line per problem otherwise.
"""
import re
import sys
from pathlib import Path

MAX_README_LINES = 400
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
ISSUE = re.compile(r"\bissues? #?\d+", re.IGNORECASE)
SHARED = "../shared"


def strip_code(text):
    """Blank out fenced code blocks and inline code, keeping line numbers."""
    out = []
    fence = None
    for line in text.split("\n"):
        stripped = line.lstrip()
        if fence is None and (stripped.startswith("```") or stripped.startswith("~~~")):
            fence = stripped[:3]
            out.append("")
            continue
        if fence is not None:
            if stripped.startswith(fence):
                fence = None
            out.append("")
            continue
        out.append(re.sub(r"`[^`]*`", "", line))
    return out


def check_file(path, root, problems):
    text = path.read_text(encoding="utf-8")
    rel = path.relative_to(root)
    for number, line in enumerate(text.split("\n"), 1):
        if ISSUE.search(line):
            problems.append(f"{rel}:{number}: mentions an issue number: {ISSUE.search(line).group(0)!r}")
        if SHARED in line:
            problems.append(f"{rel}:{number}: names a path to {SHARED}")
    for number, line in enumerate(strip_code(text), 1):
        for match in LINK.finditer(line):
            target = match.group(1)
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
                continue
            file_part = target.split("#", 1)[0].split("?", 1)[0]
            if not file_part:
                continue
            resolved = (path.parent / file_part).resolve()
            if not resolved.exists():
                problems.append(f"{rel}:{number}: broken link {target}")
            elif root.resolve() not in resolved.parents and resolved != root.resolve():
                problems.append(f"{rel}:{number}: link {target} leaves the repository")


def main(argv):
    root = Path(argv[1] if len(argv) > 1 else Path(__file__).resolve().parent.parent)
    files = [root / "README.md", root / "CHANGELOG.md"] + sorted((root / "docs").glob("*.md"))
    problems = []
    for path in files:
        if not path.is_file():
            problems.append(f"{path.relative_to(root)}: missing")
            continue
        check_file(path, root, problems)
    readme = root / "README.md"
    if readme.is_file():
        lines = len(readme.read_text(encoding="utf-8").splitlines())
        if lines > MAX_README_LINES:
            problems.append(f"README.md: {lines} lines, more than {MAX_README_LINES}")
    for problem in problems:
        print(f"check-doc-links: {problem}")
    if problems:
        return 1
    print(f"check-doc-links: {len(files)} files, all links resolve")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
