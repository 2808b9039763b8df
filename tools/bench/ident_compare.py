#!/usr/bin/env python3
"""Bit-for-bit comparison of `pdtfit identify` between two builds.

    python3 tools/bench/ident_compare.py run --pdtfit BIN --out FILE
    python3 tools/bench/ident_compare.py diff FILE_A FILE_B

`run` identifies a fixed set of records (known FOPDT, SOPDT and
integrating plants under a PRBS, a step and a relay; with and without
gross errors and missing samples; the two real records of tests/data)
with both models, every criterion and two seeds, and writes each call's
exit code, standard output and standard error as one JSON line. `diff`
prints the calls whose output differs and exits non-zero if any does.
A change meant to leave every result as it was (a faster path to the
same numbers) is checked by running both builds and diffing.
"""
import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

from pdtbench import benchlib as bl

ROOT = pathlib.Path(__file__).resolve().parents[2]
COSTS = ("simulation", "prediction", "frequency", "combined")
SEEDS = (1, 2)


def synthetic():
    """(name, u, y, Ts) of the known-plant records."""
    truths = [bl.fopdt_truth("F2", 2.0, 3.0, 3.03),
              bl.sopdt_truth("S2", 0.8, 0.5, 0.3, 2.33),
              bl.integ_truth("I1", 0.5, 2.0, 1.5)]
    out = []
    for truth in truths:
        Ts = 4.0 * truth.settle / 1500
        Ts = round(Ts, 2 - math.floor(math.log10(Ts)))
        for exc, n in (("prbs", 400), ("prbs", 2000), ("step", 1000), ("relay", 1200)):
            u, y, _ = bl.make_record(truth, exc, n, Ts, 30, False, 1)
            out.append((f"{truth.name}-{exc}-{n}", u, y, Ts))
        u, y, _ = bl.make_record(truth, "prbs", 1000, Ts, 30, False, 2)
        y = np.array(y, dtype=float)
        span = float(np.ptp(y))
        y[[100, 101, 102, 500, 777]] += span * np.array([2.0, 2.1, 1.9, -3.0, 1.5])
        y[[300, 650]] = np.nan
        out.append((f"{truth.name}-gross-1000", u, y, Ts))
    return out


def real_records():
    """(name, u, y, Ts) of the real records in tests/data/real."""
    out = []
    tclab = np.genfromtxt(ROOT / "tests/data/real/tclab_step_run2.csv", delimiter=",",
                          names=True)
    out.append(("tclab", tclab["Q1"], tclab["T1"], 1.0))
    gas = np.genfromtxt(ROOT / "tests/data/real/gas_furnace.csv", delimiter=",", names=True)
    cols = gas.dtype.names
    out.append(("gas_furnace", gas[cols[-2]], gas[cols[-1]], 9.0))
    return out


def identify(binary, u, y, Ts, model, cost, seed):
    """One call's (exit code, stdout, stderr)."""
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("u,y\n")
        f.write("\n".join(f"{a:.12g},{b:.12g}" for a, b in zip(u, y)))
        f.write("\n")
        path = f.name
    try:
        args = [str(binary), "identify", "--model", model, "--cost", cost, "--seed",
                str(seed), "--fs", f"{1.0 / float(Ts):.17g}", path]
        res = subprocess.run(args, capture_output=True, text=True, timeout=300)
    finally:
        os.unlink(path)
    return res.returncode, res.stdout, res.stderr.replace(path, "FILE")


def run(args):
    with open(args.out, "w") as f:
        for name, u, y, Ts in synthetic() + real_records():
            for model in ("fopdt", "sopdt"):
                for cost in COSTS:
                    for seed in SEEDS:
                        key = f"{name} {model} {cost} {seed}"
                        rc, out, err = identify(args.pdtfit, u, y, Ts, model, cost, seed)
                        f.write(json.dumps({"key": key, "rc": rc, "out": out,
                                            "err": err}) + "\n")
                        f.flush()
    return 0


def diff(args):
    """The calls of both files compared; those of one file only counted
    (a run cut short)."""
    a = [json.loads(line) for line in open(args.a)]
    b = {r["key"]: r for r in (json.loads(line) for line in open(args.b))}
    bad = both = 0
    for r in a:
        o = b.get(r["key"])
        if o is None:
            continue
        both += 1
        if (o["rc"], o["out"], o["err"]) != (r["rc"], r["out"], r["err"]):
            bad += 1
            print("differs:", r["key"])
    print(f"{both} calls in both files, {bad} differ; {len(a) - both} only in A, "
          f"{len(b) - both} only in B")
    return 1 if bad or both == 0 else 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--pdtfit", required=True)
    r.add_argument("--out", required=True)
    d = sub.add_parser("diff")
    d.add_argument("a")
    d.add_argument("b")
    args = p.parse_args()
    return run(args) if args.cmd == "run" else diff(args)


if __name__ == "__main__":
    sys.exit(main())
