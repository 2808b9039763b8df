#!/usr/bin/env python3
"""Runs the demo (float build) and writes docs/reports/paper-experiment.md: its
output verbatim, with the explanation of how it compares with the paper (the
prose is the template paper_experiment.md.in beside this file; the figures
the prose quotes are read from the demo's output, so they cannot drift from
it).

Usage: python3 tools/demo/write_paper_experiment.py
"""
import argparse
import pathlib
import re
import subprocess

from pdtsupport import provenance

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "release"
TEMPLATE = pathlib.Path(__file__).with_name("paper_experiment.md.in")
OUT = ROOT / "docs" / "reports" / "paper-experiment.md"
NAME_WIDTH = 40  # "  %-38s " in pdt_demo.c's rows


def _number(tok):
    """A float, the string of a complex pair, or None for the end of a row."""
    try:
        return float(tok)
    except ValueError:
        return tok if re.fullmatch(r"[-+0-9.]+[-+][0-9.]+j", tok) else None


def rows(out):
    """{(table, name): {"K", "tau", "Td", "iae", "band"}} of the demo's rows;
    table 1 (FOPDT) or 2 (SOPDT). tau is the FOPDT's time constant."""
    table, found = 0, {}
    for line in out.splitlines():
        if line.startswith("Table "):
            table = int(line.split()[1].rstrip(":"))
            continue
        if not line.startswith("  ") or table == 0 or len(line) <= NAME_WIDTH:
            continue
        nums = []
        for tok in line[NAME_WIDTH:].split():
            v = _number(tok)
            if v is None:
                break
            nums.append(v)
        if len(nums) < 5 or isinstance(nums[-3], str):
            continue
        band = re.search(r"band 0-([0-9.]+) Hz", line)
        found[(table, line[2:NAME_WIDTH].strip())] = {
            "K": nums[0], "tau": nums[1], "Td": nums[-4], "iae": nums[-3],
            "band": float(band.group(1)) if band else None}
    return found


def figures(out):
    """The template's fields besides the output."""
    r = rows(out)
    t1 = {name: v for (t, name), v in r.items() if t == 1}
    t2 = {name: v for (t, name), v in r.items() if t == 2}
    sf = t1["pdtfit GA, simulation + frequency"]
    pulses = [t2[f"pdtfit {e}, {c}"]["iae"] for e in ("pulse-1", "pulse-2")
              for c in ("simulation", "simulation + frequency")]
    chirps = [t2[f"pdtfit chirp, {c}"]["iae"] for c in ("simulation", "simulation + frequency")]
    return {
        "uniform_iae": t1["pdtfit GA, sim. + freq., uniform W"]["iae"],
        "band": sf["band"], "sf_iae": sf["iae"], "sf_K": sf["K"], "sf_tau": sf["tau"],
        "sf_Td": sf["Td"], "pf_iae": t1["pdtfit GA, prediction + frequency"]["iae"],
        "pulse_lo": min(pulses), "pulse_hi": max(pulses),
        "best2_iae": t2["best SOPDT by IAE"]["iae"],
        "paper_p1": t2["paper GA, pulse-1"]["iae"], "paper_p2": t2["paper GA, pulse-2"]["iae"],
        "half2_iae": t2["Skogestad half rule (model known)"]["iae"],
        "chirp_lo": min(chirps), "chirp_hi": max(chirps),
        "paper_chirp": t2["paper GA, chirp"]["iae"],
    }


def main():
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
                    "-DCMAKE_BUILD_TYPE=Release", "-DPDT_BUILD_TESTS=OFF"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdt_demo"],
                   check=True, stdout=subprocess.DEVNULL)
    out = subprocess.run([str(BUILD / "tools" / "pdt_demo")], check=True,
                         capture_output=True, text=True).stdout
    OUT.write_text(TEMPLATE.read_text().format(output=out, **figures(out), **provenance.fields()))
    print("wrote docs/reports/paper-experiment.md")


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
