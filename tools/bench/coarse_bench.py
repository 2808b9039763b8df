#!/usr/bin/env python3
"""The coarse record against the whole record: writes docs/reports/coarse-benchmark.md.

Usage (from the repository root):

    python3 tools/bench/coarse_bench.py [--seeds 40] [--rare-seeds 1000] [--jobs N]
                                        [--out FILE]

Every record is identified twice by the `pdtfit` command line (float build
in build/bench, made by the certainty or identification benchmark, or
PDTFIT_BIN): with the defaults, whose searches run on a coarse record
where the record allows (docs/ident-engine.md), and with `--coarse 1`,
the whole record throughout. Both answers are scored by the same
criterion (the identification's own cost, which the JSON reports), so an
answer of the default that is worse than the whole record's by more than
1 % with no flag is a loss the coarse record caused. The plants are chosen
to include processes too fast for a coarse record (a time constant of 1.5
samples) and noisy records (10 dB), where the shape check or the answer's
check must send the search back to the whole record. The rows where 40
seeds show the search least sure of itself (noisy PRBS records of the
slower processes) run again with --rare-seeds seeds each, to count the
rare failures as well.

Everything is seeded; the same build gives the same document.
"""
from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import pathlib
import string
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from pdtsupport import provenance  # noqa: E402
from pdtsupport.plant import simulate  # noqa: E402
from pdtsupport.rng import SplitMix64  # noqa: E402

PDTFIT = pathlib.Path(os.environ.get("PDTFIT_BIN", ROOT / "build" / "bench" / "tools" / "pdtfit"))
N = 1200
TS = 1.0
TAUS = (1.5, 4.0, 12.0, 40.0)   # samples
SNRS = (10, 20, 30)              # dB
EXCITATIONS = ("steps", "prbs")
MODELS = ("fopdt", "sopdt")
WORSE = 1.01
TEMPLATE = pathlib.Path(__file__).with_name("coarse_bench.md.in")
# The rows run again with --rare-seeds: PRBS bits of 4 samples under 10 dB
# of noise, where 40 seeds show the most flags.
RARE = (("fopdt", 12.0, "prbs", 10), ("sopdt", 12.0, "prbs", 10))


def excitation(kind, tau, rng, n=N):
    """Multi-level steps held 2 to 6 time constants (at least 10 samples),
    or ("prbs") a binary square wave whose level flips after every bit of
    a third of the time constant (at least one sample), after 40 samples
    at rest, n samples in all. Not random: its period makes the cost
    repeat along the dead time, the hardest input of the set for a global
    search."""
    u = np.zeros(n)
    k, level = 40, 1.0
    if kind == "steps":
        lo, hi = max(10, int(2 * tau)), max(20, int(6 * tau))
    else:
        lo = hi = max(1, int(round(tau / 3)))
    while k < n:
        hold = rng.integers(lo, hi + 1)
        u[k:k + hold] = level * (0.5 + 0.5 * rng.uniform()) if kind == "steps" else level
        level = -level if kind == "prbs" or rng.uniform() < 0.7 else level
        k += hold
    return u


def record(model, tau, kind, snr, seed, n=N):
    rng = SplitMix64.keyed(seed, int(tau * 10), snr, EXCITATIONS.index(kind),
                           MODELS.index(model))
    u = excitation(kind, tau, rng, n)
    # A dead time of half the time constant plus 2.3 samples, on the
    # simulator's grid of a twentieth of a sample.
    Td = round((0.5 * tau + 2.3) * 20) / 20 * TS
    if model == "fopdt":
        num, den = [1.5], [tau * TS, 1.0]
    else:
        den = np.polymul([tau * TS, 1.0], [tau * TS / 3, 1.0])
        num = [1.5]
    y = simulate(num, den, Td, u, TS)
    sd = np.std(y) * 10 ** (-snr / 20)
    return 40.0 + u, 350.0 + y + sd * rng.normal(n)


def identify(path, model, extra):
    r = subprocess.run([str(PDTFIT), "identify", "--model", model, "--fs", "1", *extra, path],
                       capture_output=True, text=True)
    if not r.stdout:
        return {"refused": r.stderr.strip()}
    return json.loads(r.stdout)


def task(args):
    model, tau, kind, snr, seed = args
    u, y = record(model, tau, kind, snr, seed)
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("u,y\n")
        for a, b in zip(u, y):
            f.write(f"{float(a)!r},{float(b)!r}\n")
        path = f.name
    try:
        d = identify(path, model, [])
        w = identify(path, model, ["--coarse", "1"])
    finally:
        os.unlink(path)
    return args, d, w


def verdict(d, w):
    if "refused" in d or "refused" in w:
        return "refused"
    if d["flags"]:
        return "flagged"
    if d["cost"] > WORSE * w["cost"]:
        return "worse"
    if w["cost"] > WORSE * d["cost"]:
        return "better"
    return "same"


def rare_section(results):
    """The RARE rows with many seeds: the table's rows, and each failure
    listed, not only counted."""
    rows = {}
    for (m, t, k, s, seed), d, w in results:
        rows.setdefault((m, t, k, s), []).append((seed, d, w))
    out, worst = [], []
    for (m, t, k, s), runs in rows.items():
        v = [verdict(d, w) for _, d, w in runs]
        flag_w = sum(1 for _, _, w in runs if "refused" not in w and w["flags"])
        whole_worse = sum(1 for _, d, w in runs if verdict(d, w) == "better" and not w["flags"])
        out.append(f"| {m} | {t:g} | {k} | {s} dB | {len(v)} | {v.count('same')} | "
                   f"{v.count('flagged')} / {flag_w} | **{v.count('worse')}** | "
                   f"{whole_worse} | {v.count('refused')} |")
        worst += [(m, t, k, s, seed, d["cost"] / w["cost"]) for seed, d, w in runs
                  if verdict(d, w) == "worse"]
    listed = ""
    if worst:
        listed = ("\nDefault worse, each (the default's cost over the whole record's):\n\n"
                  + "".join(f"- {m} tau {t:g}, {k}, {s} dB, seed {seed}: {r:.3f}\n"
                            for m, t, k, s, seed, r in worst))
    return {"rare_rows": "\n".join(out), "rare_worst": listed}


def main_rows(results):
    """The main table's rows and the count of worse answers in all records."""
    rows = {}
    for (m, t, k, s, _), d, w in results:
        rows.setdefault((m, t, k, s), []).append((d, w))
    total = {"worse": 0, "n": 0}
    lines = []
    for (m, t, k, s), pairs in rows.items():
        v = [verdict(d, w) for d, w in pairs]
        ok = [d for d, _ in pairs if "refused" not in d]
        co = [d["coarse"] for d in ok]
        ev_d = [d["evaluations"] for d in ok]
        ev_w = [w["evaluations"] for _, w in pairs if "refused" not in w]
        flag_w = sum(1 for _, w in pairs if "refused" not in w and w["flags"])
        total["worse"] += v.count("worse")
        total["n"] += len(v)
        lines.append(f"| {m} | {t:g} | {k} | {s} dB | {len(v)} | "
                     f"{int(np.median(co)) if co else '-'} | {sum(1 for c in co if c == 1)} | "
                     f"{v.count('same')} | {v.count('better')} | **{v.count('worse')}** | "
                     f"{v.count('flagged')} / {flag_w} | {v.count('refused')} | "
                     f"{int(np.median(ev_d)) if ev_d else '-'} / "
                     f"{int(np.median(ev_w)) if ev_w else '-'} |")
    return "\n".join(lines), total


def render(results, rare_results, seeds, rare_seeds):
    """The report: the template coarse_bench.md.in with the tables."""
    rows, total = main_rows(results)
    return string.Template(TEMPLATE.read_text()).substitute(
        seeds=str(seeds), rare_seeds=str(rare_seeds), worse_factor=f"{WORSE}", n=str(N),
        worse=str(total["worse"]), records=str(total["n"]), rows=rows,
        **rare_section(rare_results), **provenance.fields())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--rare-seeds", type=int, default=1000)
    ap.add_argument("--jobs", type=int, default=os.cpu_count())
    ap.add_argument("--out", default=str(ROOT / "docs" / "reports" / "coarse-benchmark.md"))
    a = ap.parse_args()
    if not PDTFIT.exists():
        sys.exit(f"{PDTFIT} not found: run tools/bench/certainty.py or run_ident_bench.py first, "
                 "or set PDTFIT_BIN")
    tasks = [(m, t, k, s, seed) for m in MODELS for t in TAUS for k in EXCITATIONS
             for s in SNRS for seed in range(1, a.seeds + 1)]
    rare_tasks = [(*r, seed) for r in RARE for seed in range(1, a.rare_seeds + 1)]
    with mp.Pool(a.jobs) as pool:
        results = pool.map(task, tasks, chunksize=8)
        rare_results = pool.map(task, rare_tasks, chunksize=8)
    pathlib.Path(a.out).write_text(render(results, rare_results, a.seeds, a.rare_seeds))
    total = main_rows(results)[1]
    print(f"wrote {a.out}: {total['worse']} worse in {total['n']}")


if __name__ == "__main__":
    main()
