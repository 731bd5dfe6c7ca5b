#!/usr/bin/env python3
"""Source size limits (issue 22): no function in scenegraph/ or nodes/ longer than MAX_FUNCTION lines,
and scenegraph/src/Renderer.cpp no longer than MAX_RENDERER lines.

    size_check.py [SOURCE_DIR]

Prints every function over the limit as file:line, its name and length, then the longest function
and Renderer.cpp's line count; exits 1 when a limit is exceeded. Standard library only.

Function detection is heuristic: comments, string and character literals (raw strings included)
and preprocessor lines are blanked; a `{` at namespace or class scope whose declaration has a
parameter list (`(...)` followed by qualifiers, a trailing return type or a constructor's
initialisers) opens a function, and its length runs from that line to the matching `}`. Lambdas
and local classes count towards the function that holds them.
"""

import os
import re
import sys

MAX_FUNCTION = 120
MAX_RENDERER = 400
DIRS = ("scenegraph", "nodes")
EXTENSIONS = (".cpp", ".h", ".hpp", ".cc")
RENDERER = "scenegraph/src/Renderer.cpp"


def blank(text):
    """The text with comments, literals and preprocessor lines replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#" or (line_start and c in " \t" and text[i:].lstrip(" \t").startswith("#")):
            # A preprocessor line, with its continuations.
            j = i
            while j < n:
                k = text.find("\n", j)
                if k < 0:
                    k = n
                if k > 0 and text[k - 1] == "\\":
                    j = k + 1
                    continue
                break
            out.append(re.sub(r"[^\n]", " ", text[i:k]))
            i = k
            continue
        if c == "\n":
            out.append(c)
            i += 1
            line_start = True
            continue
        if c not in " \t":
            line_start = False
        if text.startswith("//", i):
            k = text.find("\n", i)
            k = n if k < 0 else k
            out.append(" " * (k - i))
            i = k
            continue
        if text.startswith("/*", i):
            k = text.find("*/", i + 2)
            k = n if k < 0 else k + 2
            out.append(re.sub(r"[^\n]", " ", text[i:k]))
            i = k
            continue
        raw = re.match(r'(?:u8|[uUL])?R"([^()\\\s]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = text.find(")" + raw.group(1) + '"', i + raw.end())
            k = n if end < 0 else end + len(raw.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:k]))
            i = k
            continue
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):  # not a digit separator
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            k = min(j + 1, n)
            out.append(" " * (k - i))
            i = k
            continue
        out.append(c)
        i += 1
    return "".join(out)


QUALIFIERS = {"const", "noexcept", "override", "final", "mutable", "volatile", "&", "&&", "try"}


def classify(header):
    """What a `{` opens at namespace or class scope, from the declaration text before it."""
    h = " ".join(header.split())
    h = re.sub(r"^(?:(?:public|private|protected)\s*:\s*)+", "", h)
    if re.match(r"^(?:inline\s+)?namespace\b", h) or re.match(r'^extern\s*$', h) or h.startswith("extern "):
        return "namespace"
    stripped = re.sub(r"^template\s*<.*?>\s*", "", h)
    if re.match(r"^(?:enum)\b", stripped):
        return "other"
    if re.match(r"^(?:class|struct|union)\b", stripped) and "(" not in stripped.split("{")[0].split("=")[0]:
        return "class"
    if "(" not in h:
        return "other"
    # The parameter list ends at the last `)` at depth 0; what follows decides.
    depth, close = 0, -1
    for idx, ch in enumerate(h):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                close = idx
    if close < 0:
        return "other"
    tail = h[close + 1:].strip()
    if not tail:
        return "function"
    if tail.startswith("->") or tail.startswith(":"):
        return "function"
    words = re.findall(r"&&|&|[A-Za-z_]\w*(?:\([^)]*\))?", tail)
    if words and all(w.split("(")[0] in QUALIFIERS for w in words):
        return "function"
    if re.match(r"^requires\b", tail):
        return "function"
    return "other"


def function_name(header):
    h = " ".join(header.split())
    h = re.sub(r"^template\s*<.*?>\s*", "", h)
    name = r"~?\w+(?:<[^()<>]*>)?"
    m = re.search(r"(operator\s*(?:\(\)|[^\s(]+)|" + name + r"(?:::" + name + r")*)\s*\(", h)
    return m.group(1) if m else h[:40]


def functions(path):
    """(name, first line, length) of every function in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = blank(f.read())
    found = []
    # Scope stack entries: kind ("namespace", "class", "function", "other", "init"), start line, name.
    stack = []
    header, header_line = "", None
    line = 1
    paren = 0
    in_function = lambda: any(k == "function" for k, _, _ in stack)
    for ch in text:
        if ch == "\n":
            line += 1
        if in_function() and ch not in "{}":
            continue
        if ch == "{":
            if in_function():
                stack.append(("other", line, ""))
                continue
            if paren > 0:
                stack.append(("init", line, ""))  # a braced default argument
                continue
            kind = classify(header)
            if kind == "other" and stack and stack[-1][0] in ("namespace", "class", None) and "(" in header \
                    and re.search(r"\)\s*:", " ".join(header.split())):
                kind = "init"  # a brace initialiser in a constructor's initialiser list
            if kind == "function":
                stack.append(("function", header_line or line, function_name(header)))
            else:
                stack.append((kind, line, ""))
                if kind in ("namespace", "class"):
                    header, header_line = "", None
            continue
        if ch == "}":
            if not stack:
                continue
            kind, start, name = stack.pop()
            if kind == "function":
                found.append((name, start, line - start + 1))
                header, header_line = "", None
            elif kind == "class":
                header, header_line = "", None
            elif kind == "other" and not in_function():
                header += "{}"
            continue
        if in_function():
            continue
        if stack and stack[-1][0] in ("other", "init"):
            continue  # inside an aggregate or enum body
        if ch == "(":
            paren += 1
        elif ch == ")":
            paren = max(0, paren - 1)
        if ch == ";" and paren == 0:
            header, header_line = "", None
            continue
        if ch == ":" and paren == 0 and re.search(r"\b(?:public|private|protected)\s*$", header):
            header, header_line = "", None
            continue
        if not ch.isspace() and header_line is None:
            header_line = line
        header += ch
    return found


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    over, longest, count = [], None, 0
    for d in DIRS:
        for base, dirs, files in os.walk(os.path.join(root, d)):
            dirs.sort()
            for name in sorted(files):
                if not name.endswith(EXTENSIONS):
                    continue
                path = os.path.join(base, name)
                rel = os.path.relpath(path, root)
                for fn, start, length in functions(path):
                    count += 1
                    if longest is None or length > longest[2]:
                        longest = (f"{rel}:{start}", fn, length)
                    if length > MAX_FUNCTION:
                        over.append((rel, start, fn, length))
    with open(os.path.join(root, RENDERER), encoding="utf-8") as f:
        renderer_lines = sum(1 for _ in f)
    failed = False
    for rel, start, fn, length in over:
        print(f"{rel}:{start}: function {fn} is {length} lines (limit {MAX_FUNCTION})")
        failed = True
    if renderer_lines > MAX_RENDERER:
        print(f"{RENDERER}: {renderer_lines} lines (limit {MAX_RENDERER})")
        failed = True
    if longest:
        print(f"longest function: {longest[1]} at {longest[0]}, {longest[2]} lines ({count} functions checked)")
    print(f"{RENDERER}: {renderer_lines} lines")
    if failed:
        print("size check FAILED")
        return 1
    print(f"size check ok: no function over {MAX_FUNCTION} lines, Renderer.cpp within {MAX_RENDERER}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
