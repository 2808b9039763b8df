#!/usr/bin/env python3
"""Instructions per sample per evaluation of the identification's evaluation
(pdt_cost_profile on the simulation criterion, N = 2000), on x86 (callgrind,
inclusive count of each case function of tools/bench/kernel_count.c) and on
the Cortex-M4F (QEMU mps2-an386 with -icount shift=0: one port tick is 40
instructions), for this tree and for a base commit (the same program built
with -DKB_BASELINE against the base's library). Also builds the cost tests
in both real types and takes the accuracy of the evaluation against the
double numpy reference from test_cost_profile's output. Writes the whole
report docs/reports/kernel.md from the template kernel_report.md.in beside
this file, naming the commit and the machine.

Usage: python3 tools/bench/count_instructions.py [--base REV] [--check]
--check prints the report without writing it.
"""
import argparse
import pathlib
import re
import subprocess
import string
import sys
import tempfile

from pdtsupport import provenance

ROOT = pathlib.Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "tools" / "bench" / "kernel_count.c"
OUT = ROOT / "docs" / "reports" / "kernel.md"
TEMPLATE = pathlib.Path(__file__).with_name("kernel_report.md.in")
CASES = ["kb_fopdt_hint", "kb_fopdt_cold", "kb_sopdt_hint", "kb_sopdt_cold",
         "kb_fopdt_many4", "kb_sopdt_many4", "kb_fopdt_shift4", "kb_sopdt_shift4"]
CM4 = ["-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"]
QEMU = ["qemu-system-arm", "-machine", "mps2-an386", "-cpu", "cortex-m4", "-nographic",
        "-monitor", "none", "-serial", "none", "-semihosting-config",
        "enable=on,target=native", "-icount", "shift=0,align=off,sleep=off", "-kernel"]


def sources(tree):
    return sorted(str(p) for p in (tree / "lib" / "src").glob("*.c"))


def includes(tree):
    return ["-I" + str(tree / "lib" / "include"), "-I" + str(tree / "lib" / "src"),
            "-I" + str(ROOT / "port"), "-I" + str(ROOT / "tools" / "sim")]


def parse_cases(text):
    """case NAME n N evaluations R ticks T -> {NAME: (N, R, T)}"""
    out = {}
    for m in re.finditer(r"case (\w+) n (\d+) evaluations (\d+) ticks (\d+)", text):
        out[m.group(1)] = (int(m.group(2)), int(m.group(3)), int(m.group(4)))
    return out


def host_counts(tree, defs, work):
    exe = work / "kernel_host"
    subprocess.run(["gcc", "-O3", "-DNDEBUG", "-std=c99", *defs, *includes(tree),
                    *sources(tree), str(ROOT / "port" / "host" / "pdt_port_host.c"),
                    str(PROGRAM), "-lm", "-o", str(exe)], check=True)
    out = work / "callgrind.out"
    run = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                          str(exe)], check=True, capture_output=True, text=True)
    cases = parse_cases(run.stdout)
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], check=True,
                         capture_output=True, text=True).stdout
    res = {}
    for name, (n, reps, _) in cases.items():
        m = re.search(r"([\d,]+) \([^)]*\)\s+\S*:" + name + r"\b", ann)
        if m:
            res[name] = int(m.group(1).replace(",", "")) / (n * reps)
    return res


def cm4_counts(tree, defs, work):
    elf = work / "kernel_cm4.elf"
    port = ROOT / "port" / "cm4-mps2"
    common = ROOT / "port" / "common"  # the target ports' shared report and stack paint
    subprocess.run(["arm-none-eabi-gcc", *CM4, "-Os", "-std=c99", *defs, *includes(tree),
                    "-I" + str(port), "-I" + str(common), *sources(tree),
                    str(port / "startup_mps2_an386.c"), str(port / "pdt_port_cm4.c"),
                    *sorted(str(f) for f in common.glob("*.c")), str(PROGRAM), "-T" + str(port / "mps2_an386.ld"),
                    "-L" + str(port), "-nostartfiles", "--specs=nano.specs", "-Wl,--gc-sections",
                    "-lm", "-o", str(elf)], check=True)
    run = subprocess.run([*QEMU, str(elf)], capture_output=True, text=True, timeout=600)
    text = run.stdout + run.stderr
    return {name: ticks * 40 / (n * reps) for name, (n, reps, ticks) in parse_cases(text).items()}


def base_tree(rev, work):
    tree = work / "base"
    tree.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "lib"], check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    return tree


def accuracy():
    """The accuracy lines of test_cost_profile in both real types."""
    out = {}
    for real in ("float", "double"):
        build = ROOT / "build" / f"kernel-accuracy-{real}"
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPDT_REAL_DOUBLE={'ON' if real == 'double' else 'OFF'}"],
                       check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", str(build), "-j", "2", "--target",
                        "test_cost_profile"], check=True, stdout=subprocess.DEVNULL)
        run = subprocess.run([str(build / "tests" / "test_cost_profile")], check=True,
                             capture_output=True, text=True)
        out[real] = [ln for ln in (run.stdout + run.stderr).splitlines()
                     if ln.startswith("accuracy n") or ln.startswith("worst relative errors "
                                                                      "against")]
    lines = []
    for m in re.finditer(r"accuracy n\s+(\d+) noise (\S+)\s+su (\S+)\s+sy (\S+)\s*: cost (\S+) "
                         r"gain (\S+) offset (\S+)", "\n".join(out["float"])):
        lines.append("| " + " | ".join(m.groups()) + " |")
    table = ["| N | noise | u scale | y scale | cost | gain | offset |",
             "|---:|---:|---:|---:|---:|---:|---:|", *lines, ""]
    for real in ("float", "double"):
        for ln in out[real]:
            if ln.startswith("worst"):
                table.append(f"- {real} build, {ln}.")
    return "\n".join(table)


def render(accuracy_table, counts_table, base):
    """The report from the template and the two tables."""
    return string.Template(TEMPLATE.read_text()).substitute(
        **provenance.fields(), accuracy=accuracy_table, counts=counts_table,
        base=base)


def fmt(v):
    return "" if v is None else f"{v:.1f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--base", default="7ea2279",
                    help="the base commit measured beside this tree (default: the last "
                    "before the kernel)")
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        (work / "now").mkdir()
        (work / "before").mkdir()
        now_x86 = host_counts(ROOT, [], work / "now")
        now_m4 = cm4_counts(ROOT, [], work / "now")
        base = base_tree(args.base, work)
        before_x86 = host_counts(base, ["-DKB_BASELINE"], work / "before")
        before_m4 = cm4_counts(base, ["-DKB_BASELINE"], work / "before")
    gcc = subprocess.run(["gcc", "--version"], capture_output=True, text=True).stdout.split("\n")[0]
    agcc = subprocess.run(["arm-none-eabi-gcc", "--version"], capture_output=True,
                          text=True).stdout.split("\n")[0]
    qemu = subprocess.run(["qemu-system-arm", "--version"], capture_output=True,
                          text=True).stdout.split("\n")[0]
    what = {
        "kb_fopdt_hint": "FOPDT, one candidate, reference fit given (the search)",
        "kb_fopdt_cold": "FOPDT, one candidate, no reference (`pdt_cost_profile`)",
        "kb_sopdt_hint": "SOPDT, one candidate, reference fit given (the search)",
        "kb_sopdt_cold": "SOPDT, one candidate, no reference (`pdt_cost_profile`)",
        "kb_fopdt_many4": "FOPDT, four candidates in one pass (`pdt_cost_profile_many`)",
        "kb_sopdt_many4": "SOPDT, four candidates in one pass (`pdt_cost_profile_many`)",
        "kb_fopdt_shift4": "FOPDT, one shape at 20 whole-sample dead times from its response "
                           "(`pdt_cost_profile_shift`, the dead-time profile)",
        "kb_sopdt_shift4": "SOPDT, one shape at 20 whole-sample dead times from its response "
                           "(`pdt_cost_profile_shift`, the dead-time profile)",
    }
    lines = [
        f"| evaluation, N = 2000 | x86, `{args.base}` | x86, this commit | M4F, `{args.base}` "
        "| M4F, this commit |",
        "|---|---:|---:|---:|---:|",
    ]
    for c in CASES:
        if c not in now_x86 and c not in now_m4:
            continue
        lines.append(f"| {what[c]} | {fmt(before_x86.get(c))} | {fmt(now_x86.get(c))} | "
                     f"{fmt(before_m4.get(c))} | {fmt(now_m4.get(c))} |")
    lines += [
        "",
        f"Instructions per sample per evaluation (each case: 20 evaluations of candidates "
        f"within 2 % of the optimum's shape, or of the optimum's shape at 20 dead times, "
        f"its response included; the base commit evaluates those one by one). x86: {gcc}, `-O3`, valgrind callgrind, "
        f"inclusive count of the case's function. M4F: {agcc}, `-Os`, {qemu}, "
        f"`-icount shift=0` (ticks x 40).",
    ]
    text = render(accuracy(), "\n".join(lines), args.base)
    if args.check:
        print(text)
        return 0
    OUT.write_text(text)
    print(f"wrote {OUT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
