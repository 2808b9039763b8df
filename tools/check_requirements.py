#!/usr/bin/env python3
"""Exit 0 if every pinned package in the requirements file is installed at
exactly its pinned version, else name the ones that are not and exit 1.

    python3 tools/check_requirements.py tools/requirements.txt
"""
import argparse
import importlib.metadata
import sys

ap = argparse.ArgumentParser(description=__doc__,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("requirements", help="a file of NAME==VERSION lines (# comments allowed)")
args = ap.parse_args()
bad = []
for line in open(args.requirements):
    line = line.split("#")[0].strip()
    if not line:
        continue
    name, _, want = line.partition("==")
    try:
        have = importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        have = None
    if have != want:
        bad.append(f"{name} {have or 'missing'} (want {want})")
if bad:
    print("Python packages to install: " + ", ".join(bad))
    sys.exit(1)
