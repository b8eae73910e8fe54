#!/usr/bin/env python3
"""Checks that scripts/test.sh runs before building (docs/architecture.md, "Code shape"):
no function in src/, apps/ or python/src/ longer than 100 lines (a definition starting in column 0
up to its closing brace in column 0), and no reference to files outside the repository
(the design notes beside the clone). Prints each offence; exit status 1 if any."""
import pathlib
import re
import sys

MAX_LINES = 100
# The folder beside the clone, spelled in parts so that this file does not match itself.
OUTSIDE = re.compile(r"\.\./" + "shared" + r"/|" + "shared" + r"/(DESIGN|STYLE)\.md")
ROOT = pathlib.Path(__file__).resolve().parent.parent
NOT_A_FUNCTION = ("//", "#", "namespace", "}", "struct", "class", "using", "template", "static_assert", "enum",
                  "extern", "typedef")


def long_functions(path):
    lines = path.read_text().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        if line and not line[0].isspace() and not line.startswith(NOT_A_FUNCTION) and "(" in line:
            j = i
            while j < len(lines) and not lines[j].rstrip().endswith(("{", ";")):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{"):
                k = j + 1
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                if k - i + 1 > MAX_LINES:
                    yield f"{path.relative_to(ROOT)}:{i + 1}: {k - i + 1} lines (at most {MAX_LINES}): {line.strip()[:70]}"
                i = k
        i += 1


def outside_references(path):
    for n, line in enumerate(path.read_text(errors="replace").split("\n"), 1):
        if OUTSIDE.search(line):
            yield f"{path.relative_to(ROOT)}:{n}: refers to a file outside the repository"


def main():
    problems = []
    for folder in ("src", "apps", "python/src"):
        for path in sorted((ROOT / folder).rglob("*.cpp")):
            problems += long_functions(path)
    for pattern in ("*.md", "*.h", "*.cpp", "*.py"):
        for path in sorted(ROOT.rglob(pattern)):
            rel = path.relative_to(ROOT).parts
            if rel[0] in ("build", ".cache", ".git") or "node_modules" in rel:
                continue
            if path.name == "check-code-shape.py":
                continue
            problems += outside_references(path)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
