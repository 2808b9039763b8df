#!/usr/bin/env python3
"""Writes docs/reports/avr-atmega2560.md, which docs/port.md links, from the
AVR target test program's report under simavr.

    python3 tools/avr_report.py [ELF]

ELF defaults to build/test-avr/tests/target/avr/pdt_target_avr.elf (build it
as docs/port.md says). The report's prose is tools/avr_report.md.in; the
figures are the program's own lines and avr-size's. Fails if a check of the
run failed.
"""
import argparse
import platform
import re
import subprocess
import sys
from pathlib import Path
from string import Template

ROOT = Path(__file__).resolve().parent.parent
ELF = ROOT / "build/test-avr/tests/target/avr/pdt_target_avr.elf"
REPORT = ROOT / "docs/reports/avr-atmega2560.md"
HZ = 16e6


def run_program(elf):
    r = subprocess.run(["simavr", "-m", "atmega2560", "-f", "16000000", str(elf)],
                       capture_output=True, text=True, timeout=900)
    text = re.sub(r"\x1b\[[0-9;]*m", "", r.stdout + r.stderr)
    lines = [l.rstrip(".") for l in text.splitlines()]
    if not any("ALL PASSED" in l for l in lines):
        sys.exit("the AVR target test program did not pass:\n" + "\n".join(lines))
    return lines


def grab(lines, pattern):
    """The groups of the first line matching pattern."""
    for l in lines:
        m = re.search(pattern, l)
        if m:
            return m.groups()
    sys.exit("no line matches %r" % pattern)


def num(x):
    return "{:,}".format(int(x)).replace(",", " ")


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        for l in Path("/proc/cpuinfo").read_text().splitlines():
            if l.startswith("model name"):
                cpu = l.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return "%s, %s" % (platform.machine(), cpu)


def versions():
    gcc = subprocess.run(["avr-gcc", "--version"], capture_output=True, text=True).stdout
    dpkg = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "simavr"],
                          capture_output=True, text=True).stdout.strip()
    return gcc.splitlines()[0], "simavr " + (dpkg or "(version unknown)")


def commit():
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                          capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--", "lib", "tests", "port"],
                           cwd=ROOT, capture_output=True, text=True).stdout.strip()
    return head + (" with local changes" if dirty else "")


def autotune_rows(lines):
    rows = []
    for phase in ("settle", "excite", "identify", "tune"):
        cyc, calls = grab(lines, r"worst pdt_autotune_scan in %s (\d+) cycles .*; (\d+) calls" % phase)
        rows.append("| %s (%s calls) | %s | %.3g ms |" % (phase.upper(), calls, num(cyc),
                                                            int(cyc) / HZ * 1e3))
    return rows


def figures(lines, elf):
    f = {}
    f["flash"], f["static_ram"], f["arena"], f["reserve"] = grab(
        lines, r"flash (\d+) bytes, static RAM (\d+) bytes .*arena (\d+)\), stack reserve (\d+)")
    f["stack_max"] = grab(lines, r"high-water mark of the program (\d+)")[0]
    model, errs = grab(lines, r"identify FOPDT K=2.*30 dB: (K \S+ tau \S+ Td \S+) .*errors (K .*) tau \(")
    f["ident_model"], f["ident_errors"] = model, errs.replace("K ", "").replace(" tau ", ", ").replace(" Td ", ", ")
    f["ident_n"] = grab(lines, r"identify FOPDT n=(\d+):")[0]
    f["at_capacity"] = grab(lines, r"PRBS, capacity (\d+),")[0]
    ev, cyc, work, ctx, st = grab(lines, r"n=\d+: (\d+) evaluations, (\d+) cycles .*workspace (\d+) \+ context (\d+) bytes, stack (\d+)")
    f.update(ident_evals=ev, ident_cycles=num(cyc), ident_seconds="%.1f" % (int(cyc) / HZ),
             ident_work=work, ident_ctx=ctx, ident_stack=st)
    f["expm1_neg"], f["expm1_pos"] = grab(lines, r"pdt_math_expm1: \d+ arguments, largest error (\S+) ulps at x <= 0, (\S+)")
    f["log1p_err"] = max(grab(lines, r"pdt_math_log1p: \d+ arguments, largest error (\S+) ulps at x <= 0, (\S+)"),
                         key=float)
    f["pid_scenarios"], f["pid_error"] = grab(lines, r"pid: (\d+) scenarios of \d+ scans, largest error (\S+)")
    cyc, st = grab(lines, r"pid: (\d+) cycles per pdt_pid_update .*stack (\d+)")
    f.update(pid_cycles=num(cyc), pid_us="%.0f" % (int(cyc) / HZ * 1e6), pid_stack=st)
    f["at_model"] = grab(lines, r"autotune FOPDT K=2 .*: (K .*)$")[0]
    ev, sc, work, obj, st = grab(lines, r"autotune FOPDT: (\d+) evaluations in (\d+) scans; workspace (\d+) \+ object (\d+) bytes, stack (\d+)")
    f.update(at_evals=ev, at_scans=sc, at_work=work, at_obj=obj, at_stack=st)
    f["at_phases"] = "\n".join(autotune_rows(lines))
    return f


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("elf", nargs="?", type=Path, default=ELF,
                        help="the AVR target test program (default: %(default)s)")
    elf = parser.parse_args().elf
    if not elf.is_file():
        sys.exit("%s not found: build the AVR target tests first (docs/port.md)" % elf)
    lines = run_program(elf)
    f = figures(lines, elf)
    f["commit"], f["machine"] = commit(), machine()
    f["compiler"], f["simulator"] = versions()
    text = Template((ROOT / "tools/avr_report.md.in").read_text()).substitute(f)
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text(text)
    print("wrote %s" % REPORT)


if __name__ == "__main__":
    main()
