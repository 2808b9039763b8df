#!/usr/bin/env python3
"""Measures the identification engine's structure against the rules of
docs/ident-engine.md, and fails when a figure grows past its limit in
tools/engine_structure_limits.txt.

    python3 tools/check_engine_structure.py [--cc CC] [--write-limits]

The figures:
  cycles       cycles of lib/src's file-level dependency graph: file A
               depends on file B when A's object uses a symbol B's object
               defines (nm on objects compiled here, so it needs no build)
  cycle_files  the files in those cycles: merging two cycles into one
               larger lowers the first figure, not this one
  phase_writes assignments of an identification phase (`phase = PH_...`)
               in lib/src files other than the sequencer, pdt_ident.c
  kind_tests   places outside the model-kind layer (the files in
               KIND_LAYER: lib/src/pdt_model.c and its private header) that
               tell the model kinds apart: a comparison with an enumerator
               of pdt_model_kind_t (==, !=, <, >, <=, >=, with either side
               first, so `kind == X ? a : b` counts) or a `case` label of
               one, in lib/src's sources and headers and lib/include's
               headers; and in the layer, a `default:` label, which would
               keep -Wswitch from naming a switch a new kind must fill
  lag_branches places outside the layer that branch on a kind's lag or
               parameter count (`pdt_model_kind_lags(k) == 1u` and the
               like): where the branch then reads one form of the model's
               union it is a kind test by another name, which -Wswitch
               cannot see either, and that code belongs behind the layer
  union_members
               the members of the model's union (`p.fopdt`, `p.sopdt`)
               named outside the layer in lib/src: code outside it reads
               and builds a model through pdt_model_view_t, so that a kind
               the view describes needs no code there
  stage_state  structs of the engine's stage state defined in the public
               header lib/include/pdt/pdt_ident.h: those no prototype names,
               directly or through a struct it holds (they belong in
               pdt/private/pdt_ident_state.h)
  state_phases comparisons (== or !=) of a member of the engine's state
               with a whole literal other than 0 in the stage files
               (lib/src/pdt_ident_*.c), the configuration's aside: a field
               whose value 1, 2, ... says which code runs next is a phase
               hidden from the plan (`c->x.stage == 2u`). A heuristic:
               a loop's index tested for its first steps counts too

Each limit is the figure the code has; the engine's rules ask for 0. A
change that lowers a figure lowers its limit with --write-limits, so the
figures only go down.
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
SRC = ROOT / "lib" / "src"
LIMITS = ROOT / "tools" / "engine_structure_limits.txt"
SEQUENCER = "pdt_ident.c"
PHASE_WRITE = re.compile(r"\bphase\s*=\s*PH_\w+")
KIND_LAYER = ("pdt_model.c", "pdt_model_priv.h")
MODEL_H = ROOT / "lib" / "include" / "pdt" / "pdt_model.h"


def symbols(cc, tmp):
    """{file: (defined, used)} for every lib/src/*.c, from nm."""
    out = {}
    for src in sorted(SRC.glob("*.c")):
        obj = pathlib.Path(tmp) / (src.stem + ".o")
        subprocess.run([cc, "-std=c99", "-O1", "-c", "-I", str(ROOT / "lib" / "include"),
                        "-I", str(SRC), str(src), "-o", str(obj)], check=True)
        nm = subprocess.run(["nm", "-P", str(obj)], check=True, capture_output=True,
                            text=True).stdout
        defined, used = set(), set()
        for line in nm.splitlines():
            parts = line.split()
            if len(parts) < 2:
                continue
            (used if parts[1] == "U" else defined).add(parts[0])
        out[src.name] = (defined, used)
    return out


def graph(syms):
    """File A -> file B when A uses a symbol B defines."""
    owner = {}
    for name, (defined, _) in syms.items():
        for s in defined:
            owner.setdefault(s, name)
    return {name: sorted({owner[s] for s in used if s in owner and owner[s] != name})
            for name, (_, used) in syms.items()}


def cycles(g):
    """The strongly connected components of more than one file (Tarjan's
    algorithm, iterative)."""
    index, low, on, stack, comps, counter = {}, {}, set(), [], [], [0]
    for root in g:
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, i = work.pop()
            if i == 0:
                index[v] = low[v] = counter[0]
                counter[0] += 1
                stack.append(v)
                on.add(v)
            for j in range(i, len(g[v])):
                w = g[v][j]
                if w not in index:
                    work.append((v, j + 1))
                    work.append((w, 0))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        comps.append(sorted(comp))
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[v])
    return comps


def strip_comments(text):
    return re.sub(r"/\*.*?\*/|//[^\n]*", "", text, flags=re.S)


def grep_counts(pattern, files):
    """{file name: matches} over files, comments stripped."""
    out = {}
    for f in files:
        n = len(pattern.findall(strip_comments(f.read_text())))
        if n:
            out[f.name] = n
    return out


def kind_enumerators(header_text):
    """The enumerators of pdt_model_kind_t in the text of pdt_model.h."""
    m = re.search(r"typedef enum pdt_model_kind \{(.*?)\} pdt_model_kind_t;",
                  strip_comments(header_text), re.S)
    return re.findall(r"\b(PDT_\w+)\s*(?:=[^,}]*)?(?:,|$)", m.group(1).strip())


def kind_test_pattern(names):
    """A comparison with one of the enumerators names, either side first,
    or a case label of one."""
    alt = "(?:%s)\\b" % "|".join(map(re.escape, names))
    op = r"(?:[!=<>]=|<(?!<)|>(?!>))"
    return re.compile(r"(?<![-<>])%s[\s(]*%s|\b%s[\s)]*%s|\bcase[\s(]+%s" % (op, alt, alt, op, alt))


def kind_tests(root=ROOT):
    """{file: count} of the kind tests outside the layer and of the
    default labels in it."""
    names = kind_enumerators((root / MODEL_H.relative_to(ROOT)).read_text())
    src = root / "lib" / "src"
    files = sorted(src.glob("*.[ch]")) + sorted((root / "lib" / "include").rglob("*.h"))
    out = grep_counts(kind_test_pattern(names),
                      [f for f in files if f.name not in KIND_LAYER])
    layer = grep_counts(re.compile(r"\bdefault\s*:"), [src / n for n in KIND_LAYER])
    out.update({"%s (default labels)" % k: v for k, v in layer.items()})
    return out


LAG_BRANCH = re.compile(r"\bpdt_model_kind_(?:lags|params)\s*\([^()]*\)\s*[!=]=")


def lag_branches(root=ROOT):
    """{file: count} of the branches on a kind's lag or parameter count
    outside the layer."""
    src = root / "lib" / "src"
    return grep_counts(LAG_BRANCH, [f for f in sorted(src.glob("*.[ch]"))
                                    if f.name not in KIND_LAYER])


UNION_MEMBER = re.compile(r"\bp\s*\.\s*(?:fopdt|sopdt)\b")


def union_members(root=ROOT):
    """{file: count} of the union's members named outside the layer."""
    src = root / "lib" / "src"
    return grep_counts(UNION_MEMBER, [f for f in sorted(src.glob("*.[ch]"))
                                      if f.name not in KIND_LAYER])


# A member (x->a, x.a.b) == or != a whole literal from 1 up, the literal a
# whole operand (not `2u * n`), the configuration's members aside, and a
# model view's `lags` (pdt_model_view: which of its two forms the view
# holds, data of the model, not a phase of the engine).
STATE_PHASE = re.compile(r"\b(?!cfg\b)\w+(?:\s*(?:->|\.)\s*(?!cfg\b)\w+)+(?<!\blags)\s*[!=]=\s*[1-9][0-9]*[uU]?\b"
                         r"(?!\s*[-+*/%.])")


def state_phases(root=ROOT):
    """{file: count} of the comparisons of a state member with a literal
    from 1 up in the engine's stage files."""
    src = root / "lib" / "src"
    return grep_counts(STATE_PHASE, sorted(src.glob("pdt_ident_*.c")))


def stage_structs():
    """Structs pdt_ident.h defines that only the context holds: not named
    by a prototype, nor held by a struct a prototype names (the config,
    the data, the result and theirs), pdt_ident_t's own members aside."""
    text = (ROOT / "lib" / "include" / "pdt" / "pdt_ident.h").read_text()
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    bodies = {m.group(2): m.group(1) for m in
              re.finditer(r"typedef struct \w+ \{(.*?)\} (\w+_t);", text, re.S)}
    rest = re.sub(r"typedef struct \w+ \{.*?\} \w+_t;", "", text, flags=re.S)
    named = re.compile(r"\bpdt_ident(?:_\w+)?_t\b")
    interface = set(named.findall(rest))
    todo = [t for t in interface if t != "pdt_ident_t"]
    while todo:
        for t in named.findall(bodies.get(todo.pop(), "")):
            if t not in interface:
                interface.add(t)
                todo.append(t)
    return sorted(t for t in bodies if t not in interface)


def measure(cc):
    with tempfile.TemporaryDirectory() as tmp:
        comps = cycles(graph(symbols(cc, tmp)))
    files = sorted(SRC.glob("*.c"))
    phase = grep_counts(PHASE_WRITE, [f for f in files if f.name != SEQUENCER])
    kind = kind_tests()
    lags = lag_branches()
    members = union_members()
    structs = stage_structs()
    hidden = state_phases()
    figures = {"cycles": len(comps), "cycle_files": sum(len(c) for c in comps),
               "phase_writes": sum(phase.values()),
               "kind_tests": sum(kind.values()), "lag_branches": sum(lags.values()),
               "union_members": sum(members.values()),
               "stage_state": len(structs), "state_phases": sum(hidden.values())}
    detail = {"cycles": [" <-> ".join(c) for c in comps], "cycle_files": [],
              "phase_writes": ["%s: %d" % kv for kv in sorted(phase.items())],
              "kind_tests": ["outside the layer " + ", ".join(KIND_LAYER)] +
                            ["%s: %d" % kv for kv in sorted(kind.items())],
              "lag_branches": ["%s: %d" % kv for kv in sorted(lags.items())],
              "union_members": ["%s: %d" % kv for kv in sorted(members.items())],
              "stage_state": structs,
              "state_phases": ["%s: %d" % kv for kv in sorted(hidden.items())]}
    return figures, detail


def read_limits():
    limits = {}
    for line in LIMITS.read_text().splitlines():
        line = line.split("#", 1)[0].split()
        if len(line) == 2:
            limits[line[0]] = int(line[1])
    return limits


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cc", default="cc", help="C compiler for the objects (default cc)")
    ap.add_argument("--write-limits", action="store_true",
                    help="set every limit to the measured figure")
    args = ap.parse_args(argv)
    figures, detail = measure(args.cc)
    limits = read_limits()
    bad = []
    for key, value in figures.items():
        limit = limits.get(key, 0)
        print("%-13s %3d (limit %d)" % (key, value, limit))
        for line in detail[key]:
            print("    " + line)
        if value > limit:
            bad.append("%s grew to %d, above its limit %d" % (key, value, limit))
    if args.write_limits:
        head = [l for l in LIMITS.read_text().splitlines() if l.startswith("#")]
        LIMITS.write_text("\n".join(head + ["%s %d" % kv for kv in figures.items()]) + "\n")
        return 0
    for line in bad:
        print("check_engine_structure: " + line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
