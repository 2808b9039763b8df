#!/usr/bin/env python3
"""The reported uncertainty against the Monte-Carlo spread: writes
docs/reports/uncertainty.md from tools/bench/uncertainty_template.md.

For each case (FOPDT and SOPDT, a step and a PRBS, white and coloured
noise of 3 % of the response's span) it identifies the same plant on
--seeds records that differ only in their noise with `pdtfit identify`
(default options, so the uncertainty is the program's default: the Fisher
information for a FOPDT, the bootstrap for a SOPDT) and compares, for every
printed parameter, the root mean square of the reported std with the
standard deviation of the estimates over the seeds (the ratio the target
0.75-1.33 applies to), and counts how often the truth lies in the reported
95 % interval ("ci95", else estimate +/- 1.96 std).

    python3 tools/bench/uncertainty.py [--seeds 100] [--bin build/.../pdtfit]
"""
import argparse
import concurrent.futures
import datetime
import json
import math
import pathlib
import platform
import subprocess
import tempfile

import numpy as np

from pdtsupport.plant import simulate
from pdtsupport.rng import SplitMix64

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEMPLATE = pathlib.Path(__file__).with_name("uncertainty_template.md")
OUT = ROOT / "docs" / "reports" / "uncertainty.md"
TS = 0.1
N = 800
NOISE = 0.03  # of the response's span
PHI = 0.8  # the coloured noise's AR(1) pole
PLANTS = {
    # name: (model, num, den, Td, the printed truth)
    "fopdt": ("fopdt", [2.0], [5.0, 1.0], 1.33, {"K": 2.0, "tau": 5.0, "Td": 1.33}),
    "sopdt": ("sopdt", [1.5], list(np.polymul([4.0, 1.0], [1.5, 1.0])), 0.83,
              {"K": 1.5, "wn": 1 / math.sqrt(6.0), "zeta": 5.5 / (2 * math.sqrt(6.0)),
               "Td": 0.83, "tau1": 4.0, "tau2": 1.5, "a": 5.5 / 6.0, "b": 1 / 6.0}),
}


def excitation(kind, rng):
    u = np.zeros(N)
    if kind == "step":
        u[N // 10:] = 1.0
    else:  # PRBS: holds of 2 to 6 s after a rest
        k, level = N // 20, 1.0
        while k < N:
            hold = rng.integers(20, 61)
            u[k:k + hold] = level
            level = 1.0 - level
            k += hold
    return u


def record(plant, exc, colour, seed):
    _, num, den, Td, _ = PLANTS[plant]
    u = excitation(exc, SplitMix64.keyed(7))  # the same input for every seed
    y = simulate(num, den, Td, u, TS)
    span = np.ptp(y)
    w = SplitMix64.keyed(1000 + seed).normal(N)
    if colour == "coloured":
        e = np.zeros(N)
        e[0] = w[0]
        for k in range(1, N):
            e[k] = PHI * e[k - 1] + math.sqrt(1 - PHI * PHI) * w[k]
        w = e
    return u, y + NOISE * span * w


def run_one(binary, plant, exc, colour, seed, tmp, extra=()):
    u, y = record(plant, exc, colour, seed)
    path = pathlib.Path(tmp) / f"{plant}-{exc}-{colour}-{seed}.csv"
    np.savetxt(path, np.column_stack([u, y]), delimiter=",", header="u,y", comments="",
               fmt="%.9g")
    res = subprocess.run([binary, "identify", "--model", PLANTS[plant][0], "--fs", str(1 / TS),
                          *extra, str(path)], capture_output=True, text=True)
    path.unlink()
    return json.loads(res.stdout) if res.stdout else None


def case_rows(outs, plant):
    truth = PLANTS[plant][4]
    rows = []
    for key, true in truth.items():
        est = np.array([o[key] for o in outs if o[key] is not None], float)
        sd = np.array([o["std"][key] for o in outs if o["std"][key] is not None], float)
        sd = sd[np.isfinite(sd)]
        spread = est.std(ddof=1)
        rep = math.sqrt(np.mean(sd ** 2)) if len(sd) else float("nan")
        inside = 0
        for o in outs:
            ci = (o.get("ci95") or {}).get(key)
            s = o["std"][key]
            if ci is None and s is not None and o[key] is not None:
                ci = (o[key] - 1.96 * s, o[key] + 1.96 * s)
            inside += ci is not None and ci[0] <= true <= ci[1]
        ratio = rep / spread if spread > 0 else float("nan")
        rows.append((key, true, est.mean(), spread, rep, ratio, inside / len(outs),
                     0.75 <= ratio <= 1.33))
    return rows


def table(case, outs, rows):
    method = outs[0].get("uncertainty")
    lines = [f"### {case}", "",
             f"{len(outs)} records, the uncertainty from `{method}`.", "",
             "| parameter | truth | mean estimate | spread (MC std) | reported std (RMS) "
             "| ratio | truth in the 95 % interval | within 0.75-1.33 |",
             "|---|---:|---:|---:|---:|---:|---:|---|"]
    for key, true, mean, spread, rep, ratio, cover, ok in rows:
        lines.append(f"| {key} | {true:.4g} | {mean:.4g} | {spread:.3g} | {rep:.3g} | "
                     f"{ratio:.2f} | {100 * cover:.0f} % | {'yes' if ok else '**no**'} |")
    return "\n".join(lines) + "\n"


def find_binary():
    for cand in sorted(ROOT.glob("build/*/tools/pdtfit")):
        return str(cand)
    raise SystemExit("no pdtfit program under build/: build it first")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=100, help="records per case (default 100)")
    ap.add_argument("--bin", help="the pdtfit program (default: the first build/*/tools/pdtfit)")
    ap.add_argument("--jobs", type=int, default=2, help="programs run at once (default 2)")
    ap.add_argument("--plants", default="fopdt,sopdt", help="a trial on some plants only")
    ap.add_argument("--option", action="append", default=[],
                    help="an identify option for a trial (e.g. --option=--uncertainty=fisher); "
                         "the report is written to stdout then")
    args = ap.parse_args()
    binary = args.bin or find_binary()
    # The program's default, and for a SOPDT also the Fisher information
    # (what a device reports, pdt_ident_std_printed).
    cases = [(p, e, c, o) for p in args.plants.split(",")
             for o in ((), ("--uncertainty", "fisher")) if p == "sopdt" or not o
             for e in ("step", "prbs") for c in ("white", "coloured")]
    sections, summary, misses = [], [], 0
    with tempfile.TemporaryDirectory() as tmp, \
            concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for plant, exc, colour, opt in cases:
            outs = list(pool.map(lambda s: run_one(binary, plant, exc, colour, s, tmp,
                                                   [*opt, *args.option]), range(args.seeds)))
            outs = [o for o in outs if o is not None]
            rows = case_rows(outs, plant)
            name = f"{plant.upper()}, {exc}, {colour} noise{', --uncertainty fisher' if opt else ''}"
            sections.append(table(name, outs, rows))
            bad = [r[0] for r in rows if not r[7]]
            misses += len(bad)
            summary.append(f"| {name} | {outs[0].get('uncertainty')} | "
                           f"{min(r[5] for r in rows):.2f}-{max(r[5] for r in rows):.2f} | "
                           f"{', '.join(bad) or 'none'} |")
            print(name, "done")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    cpu = platform.processor() or "cpu"
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                   if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    text = TEMPLATE.read_text().format(
        commit=commit, machine=f"{platform.machine()}, {cpu}, "
        f"{platform.system()} {platform.release()}",
        date=datetime.date.today().isoformat(), seeds=args.seeds, n=N, ts=TS,
        noise=int(100 * NOISE), phi=PHI, summary="\n".join(summary), misses=misses,
        sections="\n".join(sections))
    if args.option or args.plants != "fopdt,sopdt":
        print(text)
        return
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(text)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
