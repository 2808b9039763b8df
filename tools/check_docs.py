#!/usr/bin/env python3
"""Every file path and pdtfit symbol the documents name must exist.

Reads README.md, CHANGELOG.md's newest section and docs/*.md; in each
`code span` finds
- paths (a word with a slash or a known file ending): must exist relative
  to the repository root, to the document's folder, or, for a bare file
  name, somewhere in the tree;
- pdtfit symbols (pdt_*, PDT_*): must be defined or declared in the C
  sources (lib/, port/, tools/, tests/, examples/, docs/examples/), or be a
  CMake option or test name.
Names the CHANGELOG gives as renamed from (before an arrow) are old names
and are skipped. Exit status 1 with one line per missing name.

    python3 tools/check_docs.py
"""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXT = (".c", ".h", ".py", ".md", ".sh", ".cmake", ".txt", ".json", ".yml", ".toml", ".st",
       ".ld", ".ino", ".in", ".png", ".csv")
SYSTEM_HEADERS = {"math.h", "stdio.h", "stdlib.h", "stdint.h", "stddef.h", "stdbool.h", "string.h",
                  "float.h", "limits.h", "stdarg.h", "time.h", "assert.h", "Arduino.h"}
TOPDIRS = {"lib", "tools", "tests", "docs", "port", "examples", "cmake", "packaging", "zephyr",
           "python", ".ci", ".github"}
# Files that a command in the docs creates, not files of the tree.
GENERATED = re.compile(r"(^|/)(build[^/]*|out|dist)/|\.(csv|png|json)$|^/tmp/|^~")


def tracked():
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True).stdout
    files = [ROOT / f for f in out.split()]
    return [f for f in files if f.exists()]


def symbols(files):
    names = set()
    for f in files:
        if f.suffix in (".c", ".h", ".txt", ".cmake", ".in", ".py", ".sh", ".st", ".ino") or \
                f.name == "CMakeLists.txt":
            names.update(re.findall(r"\b(?:pdt|PDT)_\w+", f.read_text(errors="replace")))
    return names


def spans(text):
    text = re.sub(r"```.*?```", lambda m: m.group(0).replace("`", ""), text, flags=re.S)
    return re.findall(r"`([^`\n]+)`", text)


def newest_changelog(text):
    parts = re.split(r"^## ", text, flags=re.M)
    return parts[1] if len(parts) > 1 else text


def main():
    files = tracked()
    names = symbols(files)
    basenames = {f.name for f in files}
    rel = {str(f.relative_to(ROOT)) for f in files}
    dirs = {str(p.relative_to(ROOT)) for f in files for p in f.parents if p != ROOT and ROOT in p.parents or p == ROOT}
    docs = [ROOT / "README.md", ROOT / "CHANGELOG.md"] + sorted((ROOT / "docs").glob("*.md"))
    missing = []
    for doc in docs:
        text = doc.read_text()
        old = set()
        if doc.name == "CHANGELOG.md":
            text = newest_changelog(text)
            for line in text.split("→")[:-1]:
                old.update(re.findall(r"`([^`]+)`", line.rsplit(";", 1)[-1]))
        for span in spans(text):
            for word in re.findall(r"[\w./\-*]+", span):
                word = word.rstrip(".,:;")
                if not word or word in old or re.search(r"xxx|XXX", word) or word.startswith("."):
                    continue
                if re.match(r"(?:pdt|PDT)_\w+\.\w", word) and not word.endswith(EXT):
                    word = word.split(".", 1)[0]  # a struct member: the type or object
                if re.fullmatch(r"(?:pdt|PDT)_\w+", word):
                    base = word.rstrip("_")
                    if word.endswith("_") or word.endswith("*"):
                        if not any(n.startswith(base) for n in names):
                            missing.append((doc, word))
                    elif word not in names:
                        missing.append((doc, word))
                    continue
                first = word.split("/", 1)[0]
                is_path = ("/" in word and first in TOPDIRS) or \
                    (word.endswith(EXT) and re.fullmatch(r"[\w.\-/]+", word) is not None and
                     not re.match(r"(?:pdt|PDT)_", word))
                if not is_path or GENERATED.search(word) or "*" in word:
                    continue
                w = word.rstrip("/")
                if w in SYSTEM_HEADERS:
                    continue
                if w in rel or w in dirs or (ROOT / w).exists() or (doc.parent / w).exists() or \
                        (ROOT / "lib/include" / w).exists():
                    continue
                if "/" not in w and w in basenames:
                    continue
                missing.append((doc, word))
    for doc, word in missing:
        print("%s: `%s` names nothing in the tree" % (doc.relative_to(ROOT), word))
    if missing:
        print("%d dangling name(s) in the documents" % len(missing))
        return 1
    print("documents: every path and symbol they name exists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
