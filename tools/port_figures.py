"""The figures of every target core: builds the target test program for each
toolchain file in cmake/ (float, and double where given), runs it under its
emulator through ctest (label target) and collects what the program reports:
the library's flash, its RAM (context, workspace, the program's stack
high-water mark) and the instructions of a FOPDT and a SOPDT identification
and of the worst pdt_autotune_scan. Writes the whole report
docs/reports/port-figures.md (its prose in tools/port_figures.md.in), which
docs/port.md links.

    python3 tools/port_figures.py [--only NAME ...] [--check]

--check runs the float builds and only checks that every line parses;
--only measures the named toolchains and prints their rows, writing nothing;
--no-run writes the report from the builds' last runs (ctest's logs).
A target is a row of TARGETS: a name, its toolchain file, the real types
measured and the size tool of its compiler.
"""
import argparse
import datetime
import pathlib
import re
import subprocess
import sys

from pdtsupport import provenance as run_provenance

ROOT = pathlib.Path(__file__).resolve().parents[1]
REPORT = ROOT / "docs" / "reports" / "port-figures.md"
TEMPLATE = pathlib.Path(__file__).with_name("port_figures.md.in")

# name, toolchain file, real types, size tool
TARGETS = [
    ("Cortex-M0 (nRF51 of the micro:bit)", "arm-none-eabi-cm0.cmake", ["float"],
     "arm-none-eabi-size"),
    ("Cortex-M4F (MPS2 AN386)", "arm-none-eabi-cm4.cmake", ["float", "double"],
     "arm-none-eabi-size"),
    ("Cortex-M33 (MPS2 AN505)", "arm-none-eabi-cm33.cmake", ["float", "double"],
     "arm-none-eabi-size"),
    ("RISC-V rv32imac (virt)", "riscv32-imac.cmake", ["float"], "riscv64-unknown-elf-size"),
    ("RISC-V rv32imafc (virt)", "riscv32-imafc.cmake", ["float", "double"],
     "riscv64-unknown-elf-size"),
]

IDENT = re.compile(r"info identify (FOPDT|SOPDT) n=(\d+): (\d+) evaluations, \d+ generations, "
                   r"\d+ ticks = (\d+) instructions, stack (\d+) bytes")
SCAN = re.compile(r"info autotune (FOPDT|SOPDT): worst pdt_autotune_scan in (\w+) (\d+) "
                  r"instructions")
AT = re.compile(r"info autotune (FOPDT|SOPDT): .*; stack (\d+) bytes; workspace (\d+) bytes")
MEM = re.compile(r"info memory: pdt_ident_t (\d+) B, pdt_autotune_t (\d+) B; workspace: "
                 r"identification of (\d+) samples \(SOPDT\) (\d+) B, autotune of capacity "
                 r"(\d+) (\d+) B")
HWM = re.compile(r"info stack high-water mark of the program (\d+) of (\d+) bytes")


def build_dir(toolchain, real):
    return ROOT / "build" / f"port-{toolchain.removesuffix('.cmake')}-{real}"


def last_run(toolchain, real):
    """The console of the last run in the build directory (ctest's log)."""
    out = build_dir(toolchain, real)
    return (out / "Testing" / "Temporary" / "LastTest.log").read_text(), out


def build_and_run(toolchain, real):
    """The target test's console and the build directory of one build."""
    name = toolchain.removesuffix(".cmake")
    out = build_dir(toolchain, real)
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(out), "-G", "Ninja",
                    f"-DCMAKE_TOOLCHAIN_FILE={ROOT / 'cmake' / toolchain}",
                    "-DPDT_BUILD_TESTS=OFF", "-DPDT_BUILD_TOOLS=OFF",
                    "-DPDT_BUILD_TARGET_TESTS=ON", "-DPDT_WERROR=ON",
                    f"-DPDT_REAL_DOUBLE={'ON' if real == 'double' else 'OFF'}"],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(out), "-j", "2"], check=True,
                   stdout=subprocess.DEVNULL)
    res = subprocess.run(["ctest", "--test-dir", str(out), "-L", "target", "-V"],
                         capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"{name} {real}: the target test failed:\n{res.stdout[-3000:]}")
    return res.stdout, out


def library_flash(out, size_tool):
    """Code and initialised data of every module of libpdtfit.a, bytes."""
    objs = sorted(str(p) for p in (out / "lib").rglob("*.obj")) or \
        sorted(str(p) for p in (out / "lib").rglob("*.o"))
    rows = subprocess.run([size_tool, "-t", *objs], check=True, capture_output=True,
                          text=True).stdout.splitlines()
    text, data = rows[-1].split()[:2]
    return int(text) + int(data)


def parse(console):
    """The figures of one run, from the program's info lines."""
    f = {"ident": {}, "scan": 0, "at_stack": 0}
    for line in console.splitlines():
        if m := IDENT.search(line):
            f["ident"][m[1]] = (int(m[2]), int(m[4]), int(m[5]))
        elif m := SCAN.search(line):
            f["scan"] = max(f["scan"], int(m[3]))
        elif m := AT.search(line):
            f["at_stack"] = max(f["at_stack"], int(m[2]))
        elif m := MEM.search(line):
            f["ctx"] = (int(m[1]), int(m[2]))
            f["work"] = (int(m[3]), int(m[4]), int(m[5]), int(m[6]))
        elif m := HWM.search(line):
            f["hwm"] = (int(m[1]), int(m[2]))
    missing = [k for k in ("ctx", "work", "hwm") if k not in f]
    if missing or set(f["ident"]) != {"FOPDT", "SOPDT"} or not f["scan"]:
        sys.exit(f"the target test's report lacks {missing or 'an identification or a scan'}")
    return f


def mega(n):
    """Instructions in M (three significant digits at least) or k."""
    if n >= 1e8:
        return num(round(n / 1e6)) + " M"
    return f"{n / 1e6:.3g} M" if n >= 1e6 else f"{n / 1e3:.0f} k"


def num(n):
    """n with a space between thousands, as the documents write numbers."""
    return f"{n:,}".replace(",", " ")


def row(name, real, flash, f):
    n_f, fo_i, _ = f["ident"]["FOPDT"]
    n_s, so_i, _ = f["ident"]["SOPDT"]
    ni, wi, cap, wa = f["work"]
    return (f"| {name} | {real} | {num(flash)} | {num(f['ctx'][0])} / {num(f['ctx'][1])} | "
            f"{num(wi)} (n = {ni}) / {num(wa)} (capacity {cap}) | "
            f"{num(f['hwm'][0])} of {num(f['hwm'][1])} | {mega(fo_i)} (n = {n_f}) | "
            f"{mega(so_i)} (n = {n_s}) | {mega(f['scan'])} |")


HEADER = ("| core | build | library flash, B | context: pdt_ident_t / pdt_autotune_t, B | "
          "workspace: identification / autotune, B | stack high-water mark, B | "
          "FOPDT identification | SOPDT identification | worst pdt_autotune_scan |\n"
          "|---|---|---:|---:|---:|---:|---:|---:|---:|")


def provenance():
    """The commit, the day, the machine and the emulator of the run."""
    qemu = subprocess.run(["qemu-system-arm", "--version"], capture_output=True,
                          text=True).stdout.splitlines()[0]
    return (f"commit {run_provenance.commit()}, {datetime.date.today()}, "
            f"{run_provenance.machine()}, {qemu}")


def write(rows, consoles):
    table = HEADER + "\n" + "\n".join(rows)
    REPORT.parent.mkdir(exist_ok=True)
    body = TEMPLATE.read_text().replace("@PROVENANCE@", provenance()).replace("@TABLE@", table)
    logs = "\n".join(f"### {name}, {real}\n\n```\n{c}\n```\n" for name, real, c in consoles)
    REPORT.write_text(body.replace("@CONSOLES@", logs))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="*", help="toolchain files (e.g. riscv32-imac.cmake)")
    ap.add_argument("--check", action="store_true", help="float builds, parse, write nothing")
    ap.add_argument("--no-run", action="store_true",
                    help="read the last run of each build directory instead of running")
    a = ap.parse_args()
    rows, consoles = [], []
    for name, toolchain, reals, size_tool in TARGETS:
        if a.only and toolchain not in a.only:
            continue
        for real in reals[:1] if a.check else reals:
            console, out = (last_run if a.no_run else build_and_run)(toolchain, real)
            f = parse(console)
            rows.append(row(name, real, library_flash(out, size_tool), f))
            lines = [m[1] for ln in console.splitlines()
                     if (m := re.match(r"(?:\d+: )?((?:info|PASS) .*)", ln))]
            consoles.append((name, real, "\n".join(lines)))
            print(rows[-1], flush=True)
    if not a.check and not a.only:
        write(rows, consoles)
    return 0


if __name__ == "__main__":
    sys.exit(main())
