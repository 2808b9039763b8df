#!/usr/bin/env python3
"""Exit 0 if every pinned package in the requirements file is installed at
exactly its pinned version, else name the ones that are not and exit 1."""
import importlib.metadata
import sys

bad = []
for line in open(sys.argv[1]):
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
