#!/usr/bin/env python3
"""Fails when a C function under the given paths (default: tools/) is longer
than the limit (default 80 lines, braces excluded).

    python3 tools/check_function_length.py [--max 80] [PATH ...]

A function is what the project's style makes of it: its opening brace alone
at the start of a line (or ending a signature that starts the line), its
closing brace at the start of a line.
"""
import argparse
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
SIGNATURE = re.compile(r"^[A-Za-z_].*\)\s*\{\s*$")


def functions(path):
    """(first line, name, body lines) of every function in a C file."""
    lines = path.read_text(errors="replace").splitlines()
    start, name = None, None
    for i, line in enumerate(lines):
        if start is None and (line == "{" or SIGNATURE.match(line)):
            start = i
            sig = lines[i - 1] if line == "{" and i else line
            j = i - 1
            while line == "{" and j > 0 and "(" not in sig:
                j -= 1
                sig = lines[j] + " " + sig
            m = re.search(r"([A-Za-z_]\w*)\s*\(", sig)
            name = m.group(1) if m else "?"
        elif start is not None and line.startswith("}"):
            yield start + 1, name, i - start - 1
            start = None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=80)
    ap.add_argument("paths", nargs="*", default=[str(ROOT / "tools")])
    args = ap.parse_args(argv)
    files = []
    for p in map(pathlib.Path, args.paths):
        files += sorted(p.rglob("*.[ch]")) if p.is_dir() else [p]
    long = [(f, line, name, n) for f in files for line, name, n in functions(f) if n > args.max]
    for f, line, name, n in long:
        print(f"{f.relative_to(ROOT) if f.is_relative_to(ROOT) else f}:{line}: {name}() has "
              f"{n} lines (at most {args.max})")
    count = sum(1 for f in files for _ in functions(f))
    print(f"{count} functions in {len(files)} files, {len(long)} over {args.max} lines")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
