#!/usr/bin/env python3
"""Several records of one process: writes docs/reports/several-records.md.

Usage (from the repository root, after building the pdtfit program):

    python3 tools/bench/several_records.py [--pdtfit PATH] [--seeds N] [--out FILE]

Every case of pdtbench.joint_fit.PLANTS at N noise seeds, and the real
gas-furnace record cut into two segments, identified by `pdtfit identify
--model M A.csv B.csv` and compared with the independent joint fit of
pdtbench.joint_fit; then callgrind's instruction count of one record
against two. The prose is tools/bench/several_records.md.in.
"""
import argparse
import json
import pathlib
import re
import subprocess
import tempfile

import numpy as np

from pdtbench import joint_fit
from pdtbench.benchlib import ROOT
from pdtbench.real_data import commit, machine

TEMPLATE = pathlib.Path(__file__).with_name("several_records.md.in")
OUT = ROOT / "docs" / "reports" / "several-records.md"
GAS = ROOT / "tests" / "data" / "real" / "gas_furnace.csv"


def write_records(tmp, records):
    """Each record as a CSV with a time column; the paths."""
    paths = []
    for i, (u, y, fs) in enumerate(records):
        p = pathlib.Path(tmp) / f"rec{i}.csv"
        t = np.arange(len(u)) / fs
        rows = ["t,u,y"] + ["%.17g,%.17g,%.17g" % row for row in zip(t, u, y)]
        p.write_text("\n".join(rows) + "\n")
        paths.append(str(p))
    return paths


def identify(binary, kind, paths, extra=(), wrap=()):
    res = subprocess.run([*wrap, str(binary), "identify", "--model", kind, *extra, *paths],
                         capture_output=True, text=True, timeout=1200)
    if res.returncode not in (0, 3):
        raise RuntimeError(res.stderr)
    return json.loads(res.stdout), res.stderr


def gas_segments():
    data = np.loadtxt(GAS, delimiter=",", skiprows=1)
    u, y = data[:, 0], data[:, 1]
    return [(u[:150], y[:150], 1.0 / 9.0), (u[150:], y[150:], 1.0 / 9.0)]


def cases(seeds):
    for name in sorted(joint_fit.PLANTS):
        for seed in range(1, seeds + 1):
            kind, recs = joint_fit.plant_records(name, seed)
            yield f"{name}, seed {seed}", kind, recs
    for kind in ("fopdt", "sopdt"):
        yield "gas furnace in two segments", kind, gas_segments()


def case_rows(binary, seeds):
    rows, worst = [], 0.0
    for label, kind, recs in cases(seeds):
        with tempfile.TemporaryDirectory() as tmp:
            j, _ = identify(binary, kind, write_records(tmp, recs))
        (w, name), _, ratio = joint_fit.compare(kind, recs, joint_fit.model_of(j))
        worst = max(worst, w)
        pars = ", ".join(f"{k} {v:.5g}" for k, v in
                         joint_fit.printed(joint_fit.model_of(j)).items())
        ts = " / ".join("%g s" % (1.0 / fs) for _, _, fs in recs)
        rows.append(f"| {label} | {kind} | {ts} | {pars} | {w:.2e} ({name}) | {ratio:.6f} |")
    head = ["| case | model | periods | pdtfit | largest difference | cost ratio |",
            "|---|---|---|---|---:|---:|"]
    return "\n".join(head + rows), worst, len(rows)


def instructions(binary, paths, extra=()):
    _, err = identify(binary, "fopdt", paths, ["--initial", "rest", *extra],
                      ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null"])
    return int(re.search(r"Collected : (\d+)", err).group(1))


def work_table(binary):
    kind, recs = joint_fit.plant_records("fopdt_slow", 1)
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_records(tmp, recs)
        one, two = instructions(binary, paths[:1]), instructions(binary, paths)
        whole = instructions(binary, paths[:1], ["--coarse", "1"])
    return "\n".join(["| records | samples | instructions | per sample |",
                      "|---|---:|---:|---:|",
                      f"| one | 400 | {one:,} | {one / 400:,.0f} |",
                      f"| one, searched whole: `--coarse 1` | 400 | {whole:,} | "
                      f"{whole / 400:,.0f} |",
                      f"| two | 700 | {two:,} | {two / 700:,.0f} |",
                      f"| two over one | | {two / one:.2f} | |"]).replace(",", " ").replace(
                          "one  searched", "one, searched")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pdtfit", default=str(ROOT / "build" / "dev" / "tools" / "pdtfit"))
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--out", default=str(OUT))
    args = ap.parse_args(argv)
    table, worst, count = case_rows(args.pdtfit, args.seeds)
    build = "double" if "dbl" in args.pdtfit or "double" in args.pdtfit else "float"
    text = TEMPLATE.read_text().format(commit=commit(), machine=machine(), build=build,
                                       seeds=args.seeds, cases_table=table, count=count,
                                       worst=f"{worst:.2e}", work_table=work_table(args.pdtfit))
    pathlib.Path(args.out).write_text(text)
    print(f"wrote {args.out}: worst {worst:.2e} over {count} cases")


if __name__ == "__main__":
    main()
