#!/usr/bin/env python3
"""The output offset on under-modelled plants: writes docs/reports/offset-benchmark.md.

Usage (from the repository root):

    python3 tools/bench/offset_bench.py [--quick] [--jobs N] [--out FILE]

(The scipy reference fits are kept in the reference cache of
benchlib.Reference, as for run_ident_bench.py.)

The 27 plants of the Astrom-Hagglund batch (run_ident_bench.py, section 2),
each recorded as there (20 mean residence times in 1500 samples, 30 dB) with
a PRBS, a step and a pulse that start from rest (a twentieth of the record),
three noise seeds each, are identified as a FOPDT and as a SOPDT by
`pdtfit identify` twice: with the output offset fitted with the model
(`--offset estimate`) and with its default
(`--offset auto`: the rest window's level when the record starts at rest).
Next to them, the fast scipy output-error fit of fastref.py (the offset
fitted, nine starts), the reference a plain fit from another package gives.
Reported per model and record: the median and 90th percentile of the step
response's normalised IAE against the true plant's (in percent of the
final value, over 4 residence times; P6, the integrator, over 5 s of its
ramp) and of the DC gain's relative error (P6 excluded), and how often
auto is better or worse than estimate by more than 5 % of the IAE.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import pathlib
import string
import time

import numpy as np

from pdtbench import benchlib as bl
from pdtbench import fastref
from pdtbench import run_ident_bench as rb
from pdtbench.benchlib import ROOT
from pdtsupport import provenance

EXCITATIONS = ("prbs", "step", "pulse")
SEEDS = (1, 2, 3)
MODELS = ("fopdt", "sopdt")  # each with its section in offset_bench.md.in
TEMPLATE = pathlib.Path(__file__).with_name("offset_bench.md.in")
VARIANTS = (("estimate", ("--offset", "estimate")), ("auto", ("--offset", "auto")))


def record(idx, quick, exc, seed):
    """A-H plant idx recorded with excitation exc and noise seed seed (as
    run_ident_bench.ah_record, the seeds varied)."""
    p = rb.ah_plants(quick)[idx]
    Tar = rb.residence_time(p)
    integ = p.den[-1] == 0.0
    n = rb.N_REC
    Ts = 20.0 * Tar / n
    du = bl.excitation(exc, n, Ts, Tar, bl.Rng(4242 + idx + 1000 * seed))
    yc = p.simulate(Ts, bl.AMP * du)
    sigma = float(np.std(yc)) / 10.0 ** (30 / 20.0)
    u = bl.U0 + bl.AMP * du
    y = bl.Y0 + yc + sigma * bl.Rng(99 + idx + 1000 * seed).normal(n)
    tend = 5.0 if integ else 4.0 * Tar
    t = np.linspace(0.0, tend, 2001)
    href = p.simulate(t[1] - t[0], np.ones(t.size))
    return p, integ, u, y, Ts, t, href


def dc_gain(m):
    return m.K if hasattr(m, "K") else (m.k / m.b if m.b != 0 else float("inf"))


def task(args):
    idx, quick, exc, seed = args
    p, integ, u, y, Ts, t, href = record(idx, quick, exc, seed)
    k_true = None if integ else float(np.real(p.freq(np.array([0.0]))[0]))
    out = []
    for model in MODELS:
        fits = {}
        for name, extra in VARIANTS:
            j = bl.run_pdtfit(rb.PDTFIT, u, y, Ts, model, extra=extra)
            fits[name] = None if "error" in j else bl.model_from_json(j)[0]
        mr, _, _ = bl.Reference(u, y, Ts, model).fit()
        fits["reference"] = mr
        row = {"plant": p.name, "exc": exc, "seed": seed, "model": model}
        for name, m in fits.items():
            if m is None:
                row[name] = None
                continue
            iae = 100.0 * bl.niae(bl.step_model(m, t), href, t)
            kerr = None if k_true is None else abs(dc_gain(m) / k_true - 1.0)
            row[name] = {"iae": iae, "kerr": kerr}
        out.append(row)
    return out


def stats(vals):
    v = np.array([x for x in vals if x is not None and np.isfinite(x)])
    if v.size == 0:
        return "-"
    return f"{np.median(v):.3g} / {np.percentile(v, 90):.3g}"


def model_rows(rows, model):
    """One model's table rows: per excitation and over all records."""
    out = []
    for exc in EXCITATIONS + ("all",):
        sel = [r for r in rows if r["model"] == model and (exc == "all" or r["exc"] == exc)]

        def col(name, key):
            return [None if r[name] is None else r[name][key] for r in sel]
        better = sum(1 for r in sel if r["auto"] and r["estimate"] and
                     r["auto"]["iae"] < 0.95 * r["estimate"]["iae"])
        worse = sum(1 for r in sel if r["auto"] and r["estimate"] and
                    r["auto"]["iae"] > 1.05 * r["estimate"]["iae"])
        label = f"**all ({len(sel)})**" if exc == "all" else f"{exc} ({len(sel)})"
        out.append(
            f"| {label} | {stats(col('estimate', 'iae'))} | {stats(col('auto', 'iae'))} "
            f"| {stats(col('reference', 'iae'))} | {stats(col('estimate', 'kerr'))} "
            f"| {stats(col('auto', 'kerr'))} | {stats(col('reference', 'kerr'))} "
            f"| {better} / {worse} |")
    return "\n".join(out)


def report(rows, quick, seconds):
    """The report: the template offset_bench.md.in with the tables' rows."""
    worst = sorted((r for r in rows if r["auto"] and r["estimate"]),
                   key=lambda r: r["auto"]["iae"] / max(r["estimate"]["iae"], 1e-12))[-5:]
    values = {f"{model}_rows": model_rows(rows, model) for model in MODELS}
    values.update(
        per_model=str(len(rows) // len(MODELS)),
        worst_list="\n".join(f"- {r['model'].upper()} {r['plant']}, {r['exc']}, seed {r['seed']}: "
                             f"IAE {r['auto']['iae']:.3g} % (estimate {r['estimate']['iae']:.3g} %)"
                             for r in reversed(worst)),
        minutes=f"{seconds / 60:.1f}", quick_note=" (--quick: two plants)" if quick else "",
        **provenance.fields())
    return string.Template(TEMPLATE.read_text()).substitute(values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", default=str(ROOT / "docs" / "reports" / "offset-benchmark.md"))
    args = ap.parse_args()
    rb.build()
    t0 = time.time()
    plants = len(rb.ah_plants(args.quick))
    tasks = [(i, args.quick, exc, s) for i in range(plants) for exc in EXCITATIONS for s in SEEDS]
    with mp.Pool(args.jobs) as pool:
        rows = [r for out in pool.map(task, tasks) for r in out]
    text = report(rows, args.quick, time.time() - t0)
    pathlib.Path(args.out).write_text(text)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
