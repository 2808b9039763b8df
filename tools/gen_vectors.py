#!/usr/bin/env python3
"""Writes the C test vectors in tests/vectors/ from the numpy reference.

Every module in tools/vectorgen/ (not starting with '_') provides
``generate() -> dict[str, str]``: file name -> file text. With --check, the
files are compared with the committed ones instead (numbers to the last
digits another CPU's libm may change, vectorgen._emit.vectors_differ), and
the exit status is 1 if any differs, so the test command proves the vectors
are reproducible.
"""
import argparse
import difflib
import importlib
import pathlib
import pkgutil
import sys

TOOLS = pathlib.Path(__file__).resolve().parent
ROOT = TOOLS.parent

import vectorgen
from vectorgen._emit import REGEN_RTOL, vectors_differ


def all_files(only=None):
    files = {}
    for info in sorted(pkgutil.iter_modules(vectorgen.__path__), key=lambda i: i.name):
        if info.name.startswith("_") or (only and info.name not in only):
            continue
        module = importlib.import_module("vectorgen." + info.name)
        for name, text in module.generate().items():
            if name in files:
                raise SystemExit(f"two generators write {name}")
            files[name] = text
    return files


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare with tests/vectors/ instead of writing")
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "tests" / "vectors")
    parser.add_argument("--only", nargs="+", metavar="MODULE",
                        help="only these generators (names in tools/vectorgen/)")
    args = parser.parse_args()

    files = all_files(args.only)
    bad = 0
    for name, text in files.items():
        path = args.out / name
        if args.check:
            old = path.read_text() if path.exists() else ""
            why = vectors_differ(old, text)
            if why is not None:
                bad += 1
                print(f"{path}: {why}")
                diff = difflib.unified_diff(old.splitlines(), text.splitlines(),
                                            str(path), "regenerated", lineterm="", n=1)
                print("\n".join(list(diff)[:20]))
        else:
            args.out.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
    if args.check:
        if bad:
            print(f"{bad} of {len(files)} vector files differ from a fresh generation")
            return 1
        print(f"{len(files)} vector files regenerate (numbers within {REGEN_RTOL:g})")
    else:
        print(f"wrote {len(files)} vector files to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
