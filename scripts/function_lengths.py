#!/usr/bin/python3
"""Lines per C++ function, by brace matching: the project keeps functions short enough to read at
once (at most --max lines, signature to closing brace).

    scripts/function_lengths.py [--max 60] [--exclude FILE]... [--list] PATH...

PATHs are files or folders (every .cpp and .hpp in them). Exit status 1 when a function is longer
than --max (the offenders are printed); --list prints every function over --max and a summary.

A heuristic, not a parser: comments, string and character literals (raw strings included) are
blanked, then every '{' whose enclosing scopes are only namespaces, classes or extern blocks and
whose head (the text since the previous ';', '{' or '}') has a parameter list and no '=' outside
brackets opens a function body. Lambdas count towards the function they are in; a variable's
brace initializer ('= {...}') is not a function.
"""
import argparse
import os
import re
import sys


def blank_literals(text):
    """The text with comments and literals replaced by spaces (newlines kept, so lines count)."""
    out = []
    i, n = 0, len(text)
    keep = lambda s: "".join(c if c == "\n" else " " for c in s)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(keep(text[i:j]))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(keep(text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + keep(text[i + 2:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and text[i + 1 : i + 2].isalnum():
                out.append(c)  # a digit separator (1'000'000)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + keep(text[i + 1 : j]) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def outside_brackets(head):
    """The head with everything inside (), [] and <> removed (templates, parameters)."""
    depth, out = 0, []
    for c in head:
        if c in "([":
            depth += 1
        elif c in ")]":
            depth = max(0, depth - 1)
        elif depth == 0:
            out.append(c)
    return "".join(out)


def scope_of(head):
    """What a '{' after `head` opens: namespace, class, function or other."""
    words = re.sub(r"\s+", " ", head).strip()
    if re.match(r"^(inline )?namespace\b", words) or re.match(r'^extern ""', words):
        return "namespace"
    if "(" not in words or re.search(r"\b(class|struct|union|enum)\b[^(]*$", words):
        if re.search(r"\b(class|struct|union|enum)\b", words) and "=" not in outside_brackets(words):
            return "class"
        return "other"
    if "=" in outside_brackets(words.replace("operator", " ")).replace("==", ""):
        return "other"  # a variable's initializer (a lambda, a list)
    return "function"


def functions(path):
    """(name, first line, last line) of every function defined in `path`."""
    text = blank_literals(open(path, encoding="utf-8", errors="replace").read())
    stack, found = [], []  # stack: (kind, head, start line)
    head_start = 0
    line_at = lambda pos: text.count("\n", 0, pos) + 1
    for pos, c in enumerate(text):
        if c in ";{}" and c != "{":
            if c == "}" and stack:
                kind, head, start = stack.pop()
                if kind == "function":
                    found.append((head, start, line_at(pos)))
            head_start = pos + 1
            continue
        if c != "{":
            continue
        # Preprocessor lines are not part of a head (blanked, so that lines still count).
        head = re.sub(r"(?m)^[ \t]*#.*$", lambda m: " " * len(m.group(0)), text[head_start:pos])
        in_function = any(k not in ("namespace", "class") for k, _, _ in stack)
        kind = "inner" if in_function else scope_of(head)
        first = head_start + len(head) - len(head.lstrip())
        name = re.findall(r"([~\w:]+|operator\S+)\s*\(", head)
        stack.append((kind, name[0] if name else "?", line_at(first)))
        head_start = pos + 1
    return [(n, a, b) for n, a, b in found]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--max", type=int, default=60)
    ap.add_argument("--exclude", action="append", default=[], help="a file name to skip")
    ap.add_argument("--list", action="store_true", help="print a summary as well")
    a = ap.parse_args()
    files = []
    for p in a.paths:
        if os.path.isdir(p):
            files += sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith((".cpp", ".hpp")))
        else:
            files.append(p)
    files = [f for f in files if os.path.basename(f) not in a.exclude]
    rows = [(b - s + 1, f, n, s) for f in files for n, s, b in functions(f)]
    long = sorted((r for r in rows if r[0] > a.max), reverse=True)
    for length, f, name, start in long:
        print(f"{f}:{start}: {name}: {length} lines (more than {a.max})")
    if a.list:
        longest = max(rows) if rows else (0, "-", "-", 0)
        print(f"{len(files)} files, {len(rows)} functions, {len(long)} over {a.max} lines; "
              f"longest {longest[2]} ({longest[1]}) {longest[0]} lines")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
