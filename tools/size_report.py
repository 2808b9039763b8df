#!/usr/bin/env python3
"""Builds lib/ for the Cortex-M4F (float and double real type) and writes the
code and data size of every module to docs/reports/size.md.

Usage: python3 tools/size_report.py [--check]
--check only builds and prints the table (the test command uses it), without
rewriting docs/reports/size.md. The prose is the template size_report.md.in
beside this file.
"""
import argparse
import pathlib
import string
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
TOOLCHAIN = ROOT / "cmake" / "arm-none-eabi-cm4.cmake"


def build(real_double):
    out = ROOT / "build" / ("size-cm4-double" if real_double else "size-cm4-float")
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(out), "-G", "Ninja",
                    f"-DCMAKE_TOOLCHAIN_FILE={TOOLCHAIN}", "-DPDT_BUILD_TESTS=OFF",
                    "-DPDT_BUILD_TOOLS=OFF", "-DPDT_WERROR=ON",
                    f"-DPDT_REAL_DOUBLE={'ON' if real_double else 'OFF'}"],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(out), "--target", "pdtfit"], check=True,
                   stdout=subprocess.DEVNULL)
    objs = sorted((out / "lib").rglob("*.obj")) + sorted((out / "lib").rglob("*.o"))
    res = subprocess.run(["arm-none-eabi-size", *map(str, objs)], check=True,
                         capture_output=True, text=True).stdout.splitlines()[1:]
    sizes = {}
    for line in res:
        text, data, bss, _dec, _hex, name = line.split(None, 5)
        module = pathlib.Path(name).name.split(".")[0]
        sizes[module] = (int(text), int(data), int(bss))
    return sizes


def flags():
    return ("arm-none-eabi-gcc -std=c99 -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 "
            "-mfloat-abi=hard -Os (CMake MinSizeRel), strict warnings as errors")


def table(f, d):
    lines = ["| module | text (float) | data + bss (float) | text (double) | data + bss (double) |",
             "|---|---:|---:|---:|---:|"]
    tf = td = 0
    for module in sorted(f):
        a, b = f[module], d[module]
        tf += a[0]
        td += b[0]
        lines.append(f"| {module} | {a[0]} | {a[1] + a[2]} | {b[0]} | {b[1] + b[2]} |")
    lines.append(f"| **total** | **{tf}** | 0 | **{td}** | 0 |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    f = build(False)
    d = build(True)
    assert all(v[1] + v[2] == 0 for v in list(f.values()) + list(d.values())), \
        "lib/ must have no static data"
    body = table(f, d)
    print(body)
    if args.check:
        return 0
    ver = next(line.split('"')[1] for line in
               (ROOT / "lib/include/pdt/pdt_common.h").read_text().splitlines()
               if "PDT_VERSION_STRING" in line)
    gcc = subprocess.run(["arm-none-eabi-gcc", "--version"], capture_output=True,
                         text=True).stdout.splitlines()[0]
    template = string.Template((ROOT / "tools" / "size_report.md.in").read_text())
    (ROOT / "docs" / "reports" / "size.md").write_text(
        template.substitute(version=ver, flags=flags(), gcc=gcc, table=body))
    print("wrote docs/reports/size.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
