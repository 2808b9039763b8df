#!/usr/bin/env python3
"""Fails when a C function under the given paths (default: tools/) is longer
than the limit (default 80 lines, braces excluded).

    python3 tools/check_function_length.py [--max 80] [--allow FILE] [PATH ...]

A function is what the project's style makes of it: its opening brace alone
at the start of a line (or ending a signature that starts the line), its
closing brace at the start of a line. --allow names a file of functions
that may be longer for now, one `PATH FUNCTION` a line (# starts a
comment); each is reported, and an entry that no longer needs to be there
is named so that it can go.
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


def allowed(path):
    """The (path, function) pairs of an allow-list file."""
    out = set()
    for line in pathlib.Path(path).read_text().splitlines():
        words = line.split("#", 1)[0].split()
        if words:
            if len(words) != 2:
                sys.exit(f"{path}: expected `PATH FUNCTION`: {line}")
            out.add((words[0], words[1]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=80)
    ap.add_argument("--allow", help="file of `PATH FUNCTION` lines that may be longer")
    ap.add_argument("paths", nargs="*", default=[str(ROOT / "tools")])
    args = ap.parse_args(argv)
    allow = allowed(args.allow) if args.allow else set()
    files = []
    for p in (pathlib.Path(a).resolve() for a in args.paths):
        files += sorted(p.rglob("*.[ch]")) if p.is_dir() else [p]
    long, excused = [], set()
    for f in files:
        path = str(f.relative_to(ROOT) if f.is_relative_to(ROOT) else f)
        for line, name, n in functions(f):
            if n <= args.max:
                continue
            where = f"{path}:{line}: {name}() has {n} lines (at most {args.max})"
            if (path, name) in allow:
                excused.add((path, name))
                print(where, "(allowed for now)")
            else:
                long.append(where)
                print(where)
    for path, name in sorted(allow - excused):
        print(f"{path}: {name}() is on the allow-list and not over {args.max} lines here")
    count = sum(1 for f in files for _ in functions(f))
    print(f"{count} functions in {len(files)} files, {len(long)} over {args.max} lines"
          + (f", {len(excused)} allowed for now" if excused else ""))
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
