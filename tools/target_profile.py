#!/usr/bin/env python3
"""Where a target core's instructions go: runs a target test program (the
one tools/port_figures.py builds for each core) under QEMU with QEMU's log
of the blocks it translates and executes, and counts, for every call of
one library function (pdt_identify), the instructions each function ran
inside that call. Writes docs/reports/target-profile.md.

    python3 tools/port_figures.py --only arm-none-eabi-cm4.cmake  # the builds
    python3 tools/target_profile.py                  # the report, every build
    python3 tools/target_profile.py --build build/port-riscv32-imac-float

The counts are QEMU's executed translation blocks times their instructions
(`-d in_asm,exec,nochain`, the same `-icount shift=0` as the target test),
attributed to the function whose symbol covers each instruction. A call
begins when the function's entry runs and ends when a block at one of its
call sites' return addresses runs. The program's own count of the same
call (its port's tick counter) is printed beside the sum, to check both.
"""
import argparse
import bisect
import collections
import datetime
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "reports" / "target-profile.md"
# The builds profiled by default: (title, build directory, what the
# program's two identifications are).
BUILDS = [
    ("Cortex-M4F (MPS2 AN386), float", "build/port-arm-none-eabi-cm4-float",
     ["FOPDT, n = 1000", "SOPDT, n = 1000"]),
    ("RISC-V rv32imafc (virt), float", "build/port-riscv32-imafc-float",
     ["FOPDT, n = 1000", "SOPDT, n = 1000"]),
    ("Cortex-M0 (nRF51 of the micro:bit), float", "build/port-arm-none-eabi-cm0-float",
     ["FOPDT, n = 200", "SOPDT, n = 200"]),
]
TOP = 25
INSN = re.compile(r"^0x([0-9a-f]+):")
# The program's own count of each identification (tests/target/check_ident.c).
OWN = re.compile(r"identify (FOPDT|SOPDT) n=(\d+): .* = (\d+) instructions")


class Symbols:
    """Function symbols of an ELF: the name covering an address."""

    def __init__(self, nm, elf):
        rows = []
        out = subprocess.run([nm, "-n", "-S", "--defined-only", str(elf)], check=True,
                             capture_output=True, text=True).stdout
        for line in out.splitlines():
            p = line.split()
            if len(p) == 4 and p[2] in "tTwW":
                rows.append((int(p[0], 16), int(p[1], 16), p[3]))
        rows.sort()
        self.start = [r[0] for r in rows]
        self.rows = rows

    def name(self, pc):
        i = bisect.bisect_right(self.start, pc) - 1
        if i >= 0 and pc < self.rows[i][0] + max(self.rows[i][1], 2):
            return self.rows[i][2]
        return "?"

    def address(self, name):
        for a, _, n in self.rows:
            if n == name:
                return a
        sys.exit("no symbol %s" % name)


def return_sites(objdump, elf, fn):
    """The return address of every call of fn: the address after the call
    instruction (Thumb bl, RISC-V jal or auipc + jalr)."""
    out = subprocess.run([objdump, "-d", str(elf)], check=True, capture_output=True,
                         text=True).stdout
    sites = set()
    for raw in out.splitlines():
        # address: \t bytes \t mnemonic \t operands <target>
        p = raw.split("\t")
        if len(p) >= 4 and p[2].strip() in ("bl", "jal", "jalr", "call") and \
                p[-1].rstrip().endswith("<%s>" % fn):
            size = sum(len(h) // 2 for h in p[1].split())
            sites.add(int(p[0].strip().rstrip(":"), 16) + size)
    if not sites:
        sys.exit("no call of %s in %s" % (fn, elf))
    return sites


def qemu_command(build):
    """The target test's QEMU command, from ctest."""
    out = subprocess.run(["ctest", "--test-dir", str(build), "-N", "-V", "-L", "target"],
                         check=True, capture_output=True, text=True).stdout
    m = re.search(r"Test command: (.*)", out)
    if not m:
        sys.exit("%s: no target test (build it with tools/port_figures.py)" % build)
    return shlex.split(m.group(1))


def tools_of(build):
    """nm and objdump beside the build's compiler."""
    found = list((build / "CMakeFiles").glob("*/CMakeCCompiler.cmake"))
    if not found:
        sys.exit("%s: not a configured build" % build)
    cc = re.search(r'set\(CMAKE_C_COMPILER "(.*?)"\)', found[0].read_text()).group(1)
    prefix = re.sub(r"gcc(-[0-9.]+)?$", "", pathlib.Path(cc).name)
    return prefix + "nm", prefix + "objdump"


def profile(build, fn, calls_max):
    """[(Counter of instructions per function, total)] for each call of fn
    (the first calls_max, 0: all), the program's console, and the
    library's function names."""
    build = (ROOT / build).resolve()
    cmd = qemu_command(build)
    elf = pathlib.Path(cmd[cmd.index("-kernel") + 1])  # the program QEMU loads
    nm, objdump = tools_of(build)
    syms = Symbols(nm, elf)
    lib = set(re.findall(r"^[0-9a-f]+ [tT] (\S+)$",
                         subprocess.run([nm, str(build / "lib" / "libpdtfit.a")],
                                        capture_output=True, text=True).stdout, re.M))
    entry, sites = syms.address(fn), return_sites(objdump, elf, fn)
    with tempfile.TemporaryDirectory() as tmp:
        fifo = os.path.join(tmp, "log")
        os.mkfifo(fifo)
        at = cmd.index("-kernel")
        with open(os.path.join(tmp, "console"), "w+") as console:
            proc = subprocess.Popen(cmd[:at] + ["-d", "in_asm,exec,nochain", "-D", fifo] +
                                    cmd[at:], stdout=console, stderr=subprocess.STDOUT, cwd=tmp)
            with open(fifo) as log:
                calls = count_calls(log, syms, entry, sites, calls_max)
                stopped = proc.poll() is None and calls_max != 0
                if stopped:
                    # The calls asked for are read: the rest of the program
                    # is not needed once it has printed its own count of
                    # the last one.
                    drain(log, console, len(calls))
                    proc.kill()
            proc.wait()
            console.seek(0)
            text = console.read()
    if not stopped and proc.returncode != 0:
        sys.exit("%s: the target program failed:\n%s" % (build, text[-2000:]))
    return calls, text, lib


def drain(log, console, count):
    """Reads on in the log until the console holds the program's own count
    of count identifications (or the log ends)."""
    for i, _ in enumerate(log):
        # Read through a file of its own: the program writes through the
        # console's, and a seek there would move where it writes.
        if i % 100000 == 0:
            with open(console.name) as printed:
                if len(OWN.findall(printed.read())) >= count:
                    return


def count_calls(log, syms, entry, sites, calls_max=0):
    """Reads QEMU's log: the blocks' instructions from in_asm, then each
    executed block counted in the call it runs in; after calls_max calls
    (0: all) it stops reading. Executions are counted per translation and
    spread over functions at the end: the log has a line per block run,
    tens of millions of them. Under -icount QEMU keeps translations of one
    address with other bounds side by side (it cuts a block short where
    the instruction budget ends), so a run is matched to its translation
    by the host address of the translated code that its Trace line names:
    a block runs right after it is translated, and that first run binds
    the address to the translation."""
    versions = []  # every translation: {function: instructions}
    starts = []    # its guest address
    by_host = {}   # host address of translated code -> translation
    latest = {}    # guest address -> its latest translation
    pending = None  # a translation whose first run is still to come
    current = None
    runs = []       # per call: Counter of translations
    inside = None
    for line in log:
        if line[0] == "T":
            current = None
            i = line.find("[")
            if i < 0:
                continue
            # Trace N: host [flags/pc/...]: the pc is the 8 hex digits
            # after the first '/'
            pc = int(line[i + 10:i + 18], 16) & ~1
            host = line[line.find(":") + 1:i].strip()
            if pending is not None and starts[pending] == pc:
                by_host[host] = pending
            pending = None
            if inside is None:
                if pc != entry:
                    continue
                inside = collections.Counter()
                runs.append(inside)
            elif pc in sites:
                inside = None
                if calls_max and len(runs) == calls_max:
                    break
                continue
            index = by_host.get(host)
            if index is None or starts[index] != pc:
                index = latest.get(pc, -1)
            inside[index] += 1
            continue
        m = INSN.match(line)
        if m:
            pc = int(m.group(1), 16)
            if current is None:
                current = collections.Counter()
                latest[pc] = pending = len(versions)
                versions.append(current)
                starts.append(pc)
            current[syms.name(pc)] += 1
        elif line.startswith("IN:") or not line.strip():
            current = None
    calls = []
    for run in runs:
        per = collections.Counter()
        for index, times in run.items():
            for name, insns in (versions[index] if index >= 0 else {"?": 1}).items():
                per[name] += insns * times
        calls.append((per, sum(per.values())))
    return calls


def fmt(n):
    return "{:,}".format(n).replace(",", " ")


def call_label(labels, i):
    return labels[i] if i < len(labels) else "call %d" % (i + 1)


def runtime_of(counter, lib):
    """The instructions of a call outside the library: the runtime."""
    return sum(v for k, v in counter.items() if k not in lib)


def section(title, build, labels, fn, calls, console, lib):
    own = [int(m.group(3)) for m in OWN.finditer(console)]
    lines = ["## %s" % title, "",
             "`%s` (its `tests/target` program, as `tools/port_figures.py` builds it)." % build, ""]
    for i, (counter, total) in enumerate(calls):
        label = call_label(labels, i)
        check = (", the program's own count %s" % fmt(own[i])) if i < len(own) else ""
        libc = runtime_of(counter, lib)
        lines += ["### `%s`: %s" % (fn, label), "",
                  "%s instructions%s. The runtime (every function not in `libpdtfit.a`): "
                  "%s (%.1f %%)." %
                  (fmt(total), check, fmt(libc), 100.0 * libc / total), "",
                  "| function | in | instructions | share |", "|---|---|---:|---:|"]
        for name, n in counter.most_common(TOP):
            lines.append("| `%s` | %s | %s | %.1f %% |" % (
                name, "pdtfit" if name in lib else "runtime", fmt(n), 100.0 * n / total))
        rest = total - sum(n for _, n in counter.most_common(TOP))
        lines += ["| the other %d functions | | %s | %.1f %% |" % (
            max(len(counter) - TOP, 0), fmt(rest), 100.0 * rest / total), ""]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", nargs="*", help="target build directories (default: all three)")
    ap.add_argument("--function", default="pdt_identify")
    ap.add_argument("--calls", type=int, default=2,
                    help="stop after this many calls of the function (0: run the "
                         "program to its end); the target tests identify twice")
    ap.add_argument("--out", default=str(DOC))
    a = ap.parse_args()
    builds = [b for b in BUILDS if not a.build or b[1] in [x.rstrip("/") for x in a.build]]
    if a.build and not builds:
        builds = [(b, b, []) for b in a.build]
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    qemu = subprocess.run(["qemu-system-arm", "--version"], capture_output=True,
                          text=True).stdout.splitlines()[0]
    lines = ["# Where the target cores' instructions go", "",
             "Generated by `python3 tools/target_profile.py` (do not edit by hand) at "
             "commit %s, %s, %s." % (commit, datetime.date.today().isoformat(), qemu), "",
             "Each target test program of [port-figures.md](port-figures.md) ran under QEMU "
             "with `-icount shift=0` and QEMU's log of the blocks it executed. Each "
             "identification's instructions (one call of `%s`, from its entry to its "
             "return) are counted in the function that ran them: the evaluation kernel "
             "(`pdt_cost_kernel`, with its loops inlined), the GA's breeding and "
             "sharing, and the rest of pdtfit; the *runtime* is what the program links "
             "besides: the C library's mathematics (`expf`, `expm1f`, `powf` and the "
             "wrappers around them) and, on a core without an FPU, the compiler's "
             "software floating point. The program's own count (its tick counter) is "
             "given beside each sum; the two differ by the counter's resolution and "
             "the few instructions between its readings and the call." % a.function, ""]
    summary = ["| core and build | identification | instructions | `pdt_cost_kernel` | runtime "
               "| the rest of pdtfit |", "|---|---|---:|---:|---:|---:|"]
    body = []
    for title, build, labels in builds:
        calls, console, lib = profile(build, a.function, a.calls)
        body += section(title, build, labels, a.function, calls, console, lib)
        for i, (counter, total) in enumerate(calls):
            kernel = counter.get("pdt_cost_kernel", 0)
            runtime = runtime_of(counter, lib)
            summary.append("| %s | %s | %s | %.1f %% | %.1f %% | %.1f %% |" % (
                title, call_label(labels, i), fmt(total),
                100.0 * kernel / total, 100.0 * runtime / total,
                100.0 * (total - kernel - runtime) / total))
    lines += summary + [""] + body
    pathlib.Path(a.out).write_text("\n".join(lines).rstrip() + "\n")
    print("wrote", a.out)


if __name__ == "__main__":
    main()
