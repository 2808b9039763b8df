#!/usr/bin/env python3
"""Every file path and pdtfit symbol the documents name must exist, and
docs/design.md's module table must state the dependencies the code has.

Reads README.md, CHANGELOG.md's newest section and docs/*.md; in each
`code span` finds
- paths (a word with a slash or a known file ending): must exist relative
  to the repository root, to the document's folder, or, for a bare file
  name, somewhere in the tree;
- pdtfit symbols (pdt_*, PDT_*): must be defined or declared in the C
  sources (lib/, port/, tools/, tests/, examples/, docs/examples/), or be a
  CMake option or test name.
Names the CHANGELOG gives as renamed from (before an arrow) are old names
and are skipped. docs/ident-engine.md's plan must be the one the code has
(tools/engine_plan.py). Exit status 1 with one line per missing name.

    python3 tools/check_docs.py
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

import engine_plan

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


IGNORED_DEPS = {"common", "config", "status"}


def strip_comments(text):
    return re.sub(r"/\*.*?\*/", "", text, flags=re.S)


def module_deps():
    """{module: set of modules it uses} from lib/'s sources and headers: a
    module uses another when it calls a function, names a type or a
    constant that the other's header declares."""
    public = sorted((ROOT / "lib/include/pdt").glob("pdt_*.h"))
    heads = public + sorted((ROOT / "lib/src").glob("pdt_*.h"))
    # A private header or source named after a public module (pdt_cost_kernel.h,
    # pdt_ident_ga.c) is part of it; one that is not (pdt_ga.h) is a
    # private module of its own.
    mods = {h.stem[len("pdt_"):] for h in public}

    def module_of(stem):
        name = stem[len("pdt_"):]
        return max((m for m in mods if name == m or name.startswith(m + "_")), key=len, default=name)

    decl = {}
    for h in heads:
        mod = module_of(h.stem)
        if mod == "internal":
            continue
        t = strip_comments(h.read_text())
        for n in re.findall(r"\b(pdt_\w+)\s*\(", t) + re.findall(r"\}\s*(pdt_\w+_t)\s*;", t) + \
                re.findall(r"#define\s+(PDT_\w+)", t) + \
                re.findall(r"^\s+(PDT_[A-Z0-9_]+)\s*=", t, flags=re.M):
            decl.setdefault(n, mod)
    deps = {}
    for f in heads + sorted((ROOT / "lib/src").glob("pdt_*.c")):
        mod = module_of(f.stem)
        if mod == "internal":
            continue
        t = strip_comments(f.read_text())
        used = deps.setdefault(mod, set())
        for n in set(re.findall(r"\b(pdt_\w+|PDT_\w+)\b", t)):
            m = decl.get(n)
            if m and m != mod and m not in IGNORED_DEPS:
                used.add(m)
    return deps


def check_design_table():
    """docs/design.md's module table states each module's dependencies."""
    text = (ROOT / "docs/design.md").read_text()
    rows = re.findall(r"^\| `pdt_(\w+)`(?: \(private\))? \| ([^|]*)\|", text, flags=re.M)
    actual = module_deps()
    bad = []
    documented = set()
    for mod, deps in rows:
        documented.add(mod)
        deps = re.sub(r"\([^)]*\)", "", deps)  # a remark on why
        said = {d.strip() for d in deps.replace("—", "").split(",") if d.strip()} - IGNORED_DEPS
        if mod in actual and said != actual[mod]:
            bad.append("docs/design.md: `pdt_%s` depends on %s, the table says %s" %
                       (mod, ", ".join(sorted(actual[mod])) or "nothing", ", ".join(sorted(said)) or "nothing"))
    for mod in sorted(set(actual) - documented - IGNORED_DEPS):
        bad.append("docs/design.md: module `pdt_%s` is not in the table" % mod)
    return bad


def main():
    stale_plan = engine_plan.stale()
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
    table = check_design_table()
    if stale_plan:
        table.append(stale_plan)
    for line in table:
        print(line)
    if missing or table:
        print("%d dangling name(s) in the documents, %d wrong module dependencies or stale plans" %
              (len(missing), len(table)))
        return 1
    print("documents: every path and symbol they name exists")
    return 0


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    sys.exit(main())
