#!/usr/bin/env python3
"""Raw GL budget of the nodes (issue 22): passes and drawables reach the GPU through the renderer's
commands (PassCommands, Renderer), which go through its state cache; the raw GL calls that remain
in nodes/ are counted here and each one must say why it is raw.

    gl_budget.py [SOURCE_DIR]

A raw call is `gl` + an upper-case letter + name + `(` (the figure of
`grep -o "\\bgl[A-Z][A-Za-z0-9]*(" FILE | wc -l`), outside `//` comments, in every .cpp and .h under
nodes/. Fails (exit 1)
  - naming each file and its count when the total is above BUDGET;
  - naming file:line for a raw call without a reason: a `// GL:` comment on the call's own line, or
    in the comment block right above it: the nearest line starting with `//` among the 6 lines
    above the call (not looking past a blank line), together with the `//` lines directly above
    that one, must contain `GL:`. One comment may so cover a short run of calls that serve one
    purpose.
Prints the per-file counts and the total on success ("gl budget ok"). Standard library only.
"""

import os
import re
import sys

BUDGET = 49
WINDOW = 6
DIR = "nodes"
EXTENSIONS = (".cpp", ".h")
CALL = re.compile(r"\bgl[A-Z][A-Za-z0-9]*\(")
MARK = "GL:"


def code_part(line):
    """The line without a trailing `//` comment (string literals with `//` are not expected in calls)."""
    i = line.find("//")
    return line if i < 0 else line[:i]


def has_reason(lines, i):
    """Whether the raw call on line i (0-based) carries a `// GL:` comment (see the module doc)."""
    own = lines[i].find("//")
    if own >= 0 and MARK in lines[i][own:]:
        return True
    for j in range(i - 1, max(-1, i - 1 - WINDOW), -1):
        text = lines[j].strip()
        if not text:
            return False  # a blank line ends the block
        if text.startswith("//"):
            k = j
            while k >= 0 and lines[k].strip().startswith("//"):
                if MARK in lines[k]:
                    return True
                k -= 1
            return False
    return False


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    base = os.path.join(root, DIR)
    counts, missing = {}, []
    for dirpath, dirnames, filenames in os.walk(base):
        dirnames.sort()
        for name in sorted(filenames):
            if not name.endswith(EXTENSIONS):
                continue
            path = os.path.join(dirpath, name)
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8") as f:
                lines = f.read().split("\n")
            n = 0
            for i, line in enumerate(lines):
                calls = len(CALL.findall(code_part(line)))
                if not calls:
                    continue
                n += calls
                if not has_reason(lines, i):
                    missing.append(f"{rel}:{i + 1}: raw GL call without a '// {MARK}' comment: {line.strip()}")
            if n:
                counts[rel] = n
    total = sum(counts.values())
    for rel, n in sorted(counts.items()):
        print(f"{rel}: {n}")
    print(f"total: {total} raw GL calls in {DIR}/ (budget {BUDGET})")
    failed = False
    if total > BUDGET:
        print(f"FAIL: {total} raw GL calls in {DIR}/, over the budget of {BUDGET}:")
        for rel, n in sorted(counts.items(), key=lambda kv: -kv[1]):
            print(f"  {rel}: {n}")
        print("  use the renderer's commands (PassCommands, Renderer) instead")
        failed = True
    for m in missing:
        print("FAIL: " + m)
    if missing:
        failed = True
    if failed:
        return 1
    print("gl budget ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
