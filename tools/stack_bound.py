#!/usr/bin/env python3
"""Worst-case stack of every public pdtfit function on the Cortex-M4F,
proven from the compiler's call graph.

How:
  1. lib/ is built for the Cortex-M4F (the flags of
     cmake/arm-none-eabi-cm4.cmake, -Os, as tools/size_report.py builds it)
     in both real types, with -fcallgraph-info=su: gcc writes, per source
     file, every function's own frame (bytes, "static" when it is fixed)
     and every call it makes.
  2. Calls that leave the library (newlib's libm and libc, libgcc) get the
     bound of the callee found by reading its machine code in the
     toolchain's own multilib archives: the bytes its pushes, vpushes and
     `sub sp` take (all of them added, as if every one ran in one call:
     an upper bound) plus the worst of what it calls, recursively.
  3. A built-in the call graph lists but the object code never references
     (a float operation the FPU does inline) costs nothing.
  4. The bound of a function is its frame plus the worst bound of its
     callees. A cycle (recursion), a frame that is not static, an indirect
     call or an external function whose code cannot be found stops the
     script: then there is no proof.

Usage: python3 tools/stack_bound.py [--check | --write | --update-limits]
  (default)        print the table
  --check          fail (exit 1) when a bound exceeds its limit in
                   tools/stack_limits.txt (tools/test.sh runs this)
  --write          also rewrite docs/reports/stack.md (its prose in
                   tools/stack_bound.md.in)
  --update-limits  rewrite tools/stack_limits.txt from the bounds found
                   (each rounded up to a multiple of 64 B), for review
"""
import argparse
import pathlib
import re
import string
import subprocess
import sys

from pdtsupport import provenance

ROOT = pathlib.Path(__file__).resolve().parent.parent
TOOLCHAIN = ROOT / "cmake" / "arm-none-eabi-cm4.cmake"
LIMITS = ROOT / "tools" / "stack_limits.txt"
REPORT = ROOT / "docs" / "reports" / "stack.md"
TEMPLATE = pathlib.Path(__file__).with_name("stack_bound.md.in")


def cpu_flags():
    text = TOOLCHAIN.read_text()
    return re.search(r'CMAKE_C_FLAGS_INIT "([^"]*)"', text).group(1)


def build(real_double):
    out = ROOT / "build" / ("stack-cm4-double" if real_double else "stack-cm4-float")
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(out), "-G", "Ninja",
                    f"-DCMAKE_TOOLCHAIN_FILE={TOOLCHAIN}", "-DPDT_BUILD_TESTS=OFF",
                    "-DPDT_BUILD_TOOLS=OFF", f"-DPDT_REAL_DOUBLE={'ON' if real_double else 'OFF'}",
                    f"-DCMAKE_C_FLAGS={cpu_flags()} -fcallgraph-info=su"],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(out), "--target", "pdtfit"], check=True,
                   stdout=subprocess.DEVNULL)
    return out


NODE = re.compile(r'^node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')


def read_callgraph(out):
    """Frames {title: (name, bytes)} and calls {title: set(titles)}."""
    frames, calls = {}, {}
    cis = sorted((out / "lib").rglob("*.ci"))
    if not cis:
        sys.exit(f"no .ci files under {out}/lib: does the compiler know -fcallgraph-info?")
    for ci in cis:
        for line in ci.read_text().splitlines():
            m = NODE.match(line)
            if m:
                title, label = m.groups()
                parts = label.split("\\n")
                if len(parts) >= 3 and "bytes" in parts[2]:
                    size = re.match(r"(\d+) bytes \(([^)]*)\)", parts[2])
                    if size.group(2) != "static":
                        sys.exit(f"{parts[0]}: frame is {size.group(2)}, not static: no bound")
                    frames[title] = (parts[0], int(size.group(1)))
                continue
            m = EDGE.match(line)
            if m:
                src, dst = m.groups()
                if dst == "__indirect_call":
                    sys.exit(f"{src}: indirect call: no bound")
                calls.setdefault(src, set()).add(dst)
    return frames, calls


def undefined_symbols(out):
    lib = out / "lib" / "libpdtfit.a"
    res = subprocess.run(["arm-none-eabi-nm", "-u", str(lib)], check=True, capture_output=True,
                         text=True).stdout
    return {line.split()[-1] for line in res.splitlines() if line.strip().startswith("U ")}


def multilib(name):
    flags = cpu_flags().split()
    if name == "libgcc.a":
        cmd = ["arm-none-eabi-gcc", *flags, "-print-libgcc-file-name"]
    else:
        cmd = ["arm-none-eabi-gcc", *flags, f"-print-file-name={name}"]
    return pathlib.Path(subprocess.run(cmd, check=True, capture_output=True,
                                       text=True).stdout.strip()).resolve()


def regs_bytes(operands):
    """Bytes a push/vpush register list takes: r and s registers 4, d 8."""
    total = 0
    for item in operands.strip("{} ").split(","):
        item = item.strip()
        m = re.match(r"([rsd])(\d+)-[rsd](\d+)$", item)
        if m:
            kind, a, b = m.group(1), int(m.group(2)), int(m.group(3))
            total += (b - a + 1) * (8 if kind == "d" else 4)
        elif item:
            total += 8 if item.startswith("d") else 4
    return total


FUNC = re.compile(r"^[0-9a-f]+ <([^>]+)>:$")
CALL_RELOC = re.compile(r"R_ARM_THM_(CALL|JUMP24|JUMP19)\s+(\S+)")
LOCAL_CALL = re.compile(r"^(bl|b\.w|b)\s+[0-9a-f]+ <([^+>]+)>")


def read_archives():
    """{symbol: (frame bytes, set of callees)} from the external archives."""
    funcs = {}
    for name in ("libm.a", "libc.a", "libgcc.a"):
        path = str(multilib(name))
        text = subprocess.run(["arm-none-eabi-objdump", "-dr", "--no-show-raw-insn", path],
                              check=True, capture_output=True, text=True).stdout
        cur = None
        member = None
        at = {}  # (member, address) -> the label objdump shows there
        for line in text.splitlines():
            if line.endswith("file format elf32-littlearm"):
                member = line.split(":")[0].strip()
                continue
            m = FUNC.match(line)
            if m:
                cur = m.group(1)
                if cur not in funcs:
                    funcs[cur] = [0, set(), name, False]
                    at[(member, int(line.split()[0], 16))] = cur
                else:
                    cur = None  # a second definition (another member): keep the first
                continue
            if cur is None:
                continue
            m = CALL_RELOC.search(line)
            if m:
                funcs[cur][1].add(m.group(2))
                continue
            fields = line.split("\t")
            if len(fields) < 2 or not fields[0].strip().endswith(":"):
                continue
            insn = fields[1].strip()
            ops = fields[2].strip() if len(fields) > 2 else ""
            if insn in ("push", "push.w", "vpush", "stmdb.w", "stmdb", "vstmdb") and \
                    (insn.startswith(("push", "vpush")) or ops.startswith("sp!")):
                funcs[cur][0] += regs_bytes(ops.split("!", 1)[-1] if "!" in ops else ops)
            elif insn in ("sub", "sub.w", "subw") and re.match(r"sp, (sp, )?#", ops):
                funcs[cur][0] += int(re.search(r"#(\d+)", ops).group(1))
            elif insn.startswith(("sub", "mov")) and re.match(r"sp, (sp, )?r\d+$", ops):
                funcs[cur][3] = True  # a frame sized at run time
            elif insn.startswith("str") and "[sp, #-" in ops and ops.endswith("]!"):
                funcs[cur][0] += int(re.search(r"#-(\d+)", ops).group(1))
            m = LOCAL_CALL.match(f"{insn} {ops}")
            if m and m.group(2) != cur:
                funcs[cur][1].add(m.group(2))
        # Aliases (several names at one address, e.g. __aeabi_cdcmple) share
        # the code of the label objdump printed there.
        syms = subprocess.run(["arm-none-eabi-nm", "-A", "--defined-only", path], check=True,
                              capture_output=True, text=True).stdout
        for line in syms.splitlines():
            where, _, rest = line.rpartition(":")
            parts = rest.split()
            if len(parts) == 3 and parts[1] in "TtWw" and parts[2] not in funcs:
                primary = at.get((where.split(":")[-1], int(parts[0], 16)))
                if primary is not None:
                    funcs[parts[2]] = funcs[primary]
    return funcs


class Bounds:
    def __init__(self, frames, calls, used, archive):
        self.frames, self.calls, self.used, self.archive = frames, calls, used, archive
        self.memo, self.ext_memo = {}, {}

    def external(self, sym, path=()):
        if sym in self.ext_memo:
            return self.ext_memo[sym]
        if sym in path:
            sys.exit(f"recursion in the external code: {' -> '.join(path + (sym,))}")
        if sym not in self.archive:
            sys.exit(f"{sym}: no code found in libm, libc or libgcc: no bound")
        frame, callees, _lib, dynamic = self.archive[sym]
        if dynamic:
            sys.exit(f"{sym}: frame sized at run time: no bound")
        worst = max((self.external(c, path + (sym,)) for c in callees), default=0)
        self.ext_memo[sym] = frame + worst
        return frame + worst

    def bound(self, title, path=()):
        """(bytes, chain of names) of the deepest path from title."""
        if title in self.memo:
            return self.memo[title]
        if title in path:
            sys.exit(f"recursion: {' -> '.join(path + (title,))}")
        if title not in self.frames:
            if title not in self.used:
                res = (0, [])  # listed by the call graph, done inline
            else:
                ext = self.external(title)
                res = (ext, [f"{title} ({ext}, libm/libc/libgcc)"])
            self.memo[title] = res
            return res
        name, frame = self.frames[title]
        best = (0, [])
        for callee in sorted(self.calls.get(title, ())):
            b = self.bound(callee, path + (title,))
            if b[0] > best[0]:
                best = b
        res = (frame + best[0], [f"{name} ({frame})"] + best[1])
        self.memo[title] = res
        return res


def public_functions():
    names = set()
    for h in sorted((ROOT / "lib" / "include" / "pdt").glob("*.h")):
        for m in re.finditer(r"^[a-z][\w ]*?\**\b(pdt_\w+)\(", h.read_text(), re.M):
            names.add(m.group(1))
    return sorted(names)


def analyse(real_double):
    out = build(real_double)
    frames, calls = read_callgraph(out)
    used = undefined_symbols(out)
    archive = read_archives()
    b = Bounds(frames, calls, used, archive)
    res = {}
    for f in public_functions():
        if f in frames:
            res[f] = b.bound(f)
    externals = {s: b.ext_memo[s] for s in sorted(b.ext_memo)}
    return res, externals, archive


def read_limits():
    limits = {}
    if LIMITS.exists():
        for line in LIMITS.read_text().splitlines():
            line = line.split("#", 1)[0].split()
            if len(line) == 3:
                limits[(line[0], line[1])] = int(line[2])
    return limits


def table(fl, db):
    lines = ["| function | float (B) | double (B) | deepest chain, float (own frame in B) |",
             "|---|---:|---:|---|"]
    for f in sorted(fl, key=lambda k: (-fl[k][0], k)):
        chain = " → ".join(fl[f][1])
        lines.append(f"| `{f}` | {fl[f][0]} | {db[f][0]} | {chain} |")
    return "\n".join(lines)


def ext_table(ef, ed, archive):
    lines = ["| function | library | bound (B) |", "|---|---|---:|"]
    for s in sorted(set(ef) | set(ed)):
        if s in ef or s in ed:
            lines.append(f"| `{s}` | {archive[s][2]} | {max(ef.get(s, 0), ed.get(s, 0))} |")
    return "\n".join(lines)


def write_report(fl, db, ef, ed, archive):
    """docs/reports/stack.md from its template and the bounds found."""
    gcc = subprocess.run(["arm-none-eabi-gcc", "--version"], capture_output=True,
                         text=True).stdout.splitlines()[0]
    deepest = min(fl, key=lambda k: (-fl[k][0], k))
    REPORT.write_text(string.Template(TEMPLATE.read_text()).substitute(
        gcc=gcc, flags=cpu_flags(), deepest=deepest, deepest_float=fl[deepest][0],
        deepest_double=db[deepest][0], table=table(fl, db),
        externals=ext_table(ef, ed, archive), **provenance.fields()))
    print(f"wrote {REPORT.relative_to(ROOT)}")


def main():
    ap = argparse.ArgumentParser()
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--check", action="store_true")
    g.add_argument("--write", action="store_true")
    g.add_argument("--update-limits", action="store_true")
    args = ap.parse_args()
    fl, ef, archive = analyse(False)
    db, ed, _ = analyse(True)
    body = table(fl, db)
    print(body)
    if args.update_limits:
        rows = ["# Stack limits of the public functions on the Cortex-M4F, bytes, checked by",
                "# tools/stack_bound.py --check (tools/test.sh). Written by --update-limits",
                "# (the bound found, rounded up to a multiple of 64): review a change.",
                "# function real limit"]
        for f in sorted(fl):
            for real, v in (("float", fl[f][0]), ("double", db[f][0])):
                rows.append(f"{f} {real} {(v + 63) // 64 * 64}")
        LIMITS.write_text("\n".join(rows) + "\n")
        print(f"wrote {LIMITS.relative_to(ROOT)}")
        return 0
    limits = read_limits()
    bad = []
    for f in sorted(fl):
        for real, v in (("float", fl[f][0]), ("double", db[f][0])):
            lim = limits.get((f, real))
            if lim is None:
                bad.append(f"{f} ({real}): {v} B, no limit in {LIMITS.name}")
            elif v > lim:
                bad.append(f"{f} ({real}): {v} B exceeds its limit {lim} B")
    if args.write:
        write_report(fl, db, ef, ed, archive)
    if bad:
        print("stack bounds over their limits (tools/stack_limits.txt):\n  " + "\n  ".join(bad))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
