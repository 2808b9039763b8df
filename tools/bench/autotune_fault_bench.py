#!/usr/bin/env python3
"""Fault benchmark of pdtfit's autotune: the Astrom-Hagglund batch under a
real plant's faults, and the closed-loop retune.

Usage (from the repository root):

    nice build/venv/bin/python tools/bench/autotune_fault_bench.py [--jobs N]
        [--seeds N] [--bin PDTFIT] [--out FILE] [--json FILE]

(the venv of tools/test.sh, in which the tools' packages are installed).

Builds the float `pdtfit` into build/autotune-bench (unless --bin names
one) and runs `pdtfit autotune-sim` for every plant of the batch
(autotune_bench.batch) x experiment (relay, PRBS, step) x fault (none and
each fault alone, at the sizes of the table FAULTS below, scaled to the
plant) x seed, then the closed-loop retune (`--closed-loop`) of every plant
from a detuned and from an aggressive PI. Each completed run's gains are
judged on the TRUE plant by the program's own loop figures (`loop`): its Ms
and whether the loop settled. An unsafe loop is one that did not settle or
has Ms above 3.

Writes docs/reports/autotune-faults.md from the template
autotune_fault_report.md beside this script. Everything is seeded; the same
build gives the same report.
"""
from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import pathlib
import platform
import string
import subprocess

from pdtbench import autotune_bench as ab  # the batch of plants, the Nyquist test

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "autotune-bench"
OUT = ROOT / "docs" / "reports" / "autotune-faults.md"
TEMPLATE = pathlib.Path(__file__).resolve().parent / "autotune_fault_report.md"

AMP = 1.0                  # input change of the experiments
NOISE = 0.01               # noise std, fraction of the response
EXPERIMENTS = ("relay", "prbs", "step")
# Fault sizes, as the issue sets them: fractions of the experiment's step A,
# of the response R = |K| A (|K| A T for an integrating plant), per plant
# time scale T (the sum of its lags, pair and dead time).
FAULTS = {
    "none": "no fault",
    "load": "a load of 0.3 A at the plant's input, half-way through the experiment",
    "drift": "a drift of 0.02 R per time scale T",
    "quantise": "a quantisation of 0.02 R",
    "u-rate": "a rate limit of A per T / 20",
    "stiction": "a backlash of 0.05 A",
    "u-rate, position": "the rate limit, the actuator's position read (--actuator-position)",
    "stiction, position": "the backlash, the actuator's position read (--actuator-position)",
}
MS_OK, MS_UNSAFE = 2.2, 3.0
# The closed-loop retune's starting PI, from the plant's SIMC-like scale:
# Kc = f / |K| and Ti = T; for an integrating plant Kc = f / (|K| T) and
# Ti = 4 T / f (SIMC's ratio, so that a detuned PI is slow, not
# underdamped).
START = {"detuned": 0.2, "aggressive": 1.6}
# Its experiments: a set-point step of the response, and a set-point dither
# (a PRBS of a fifth of it).
CLOSED = {"step": 1.0, "prbs": 0.2}


def plant_args(p):
    """The plant as autotune-sim's options, and its time scale and gain."""
    num, den = list(p.num), list(p.den)
    args, lags, zeros = [], [], []
    if p.fam == "P6":
        T = 1.0 - p.L
        lags = [T] if T > 0 else []
        K, integ = 1.0, True
    elif p.fam == "P9":
        T = float(p.label.split("=")[1])
        lags, K, integ = [1.0], 1.0, False
        args += ["--plant-wn", f"{1.0 / T:.9g}", "--plant-zeta", "0.7"]
    else:
        _, lags, zeros, _ = p.half
        K, integ = p.gain(), False
    args = ["--plant-gain", f"{K:.9g}"] + args
    if lags:
        args += ["--plant-lags", ",".join(f"{x:.9g}" for x in lags)]
    if zeros:
        args += ["--plant-zeros", ",".join(f"{z:.9g}" for z in zeros)]
    if integ:
        args += ["--plant-integrating"]
    if p.L > 0:
        args += ["--plant-delay", f"{p.L:.9g}"]
    T = sum(lags) + p.L + (1.4 * float(p.label.split("=")[1]) if p.fam == "P9" else 0.0)
    if integ:
        T += max(sum(lags), 1.0)
    R = abs(K) * AMP * (T if integ else 1.0)
    del num, den
    return args, T, K, R


def fault_args(fault, T, R, t_mid):
    if fault == "load":
        return ["--load-step", f"{t_mid:.9g}:{0.3 * AMP:.9g}"]
    if fault == "drift":
        return ["--drift", f"{0.02 * R / T:.9g}"]
    if fault == "quantise":
        return ["--quantise", f"{0.02 * R:.9g}"]
    if fault.endswith(", position"):
        return fault_args(fault.split(",")[0], T, R, t_mid) + ["--actuator-position"]
    if fault == "u-rate":
        return ["--u-rate", f"{AMP / (T / 20.0):.9g}"]
    if fault == "stiction":
        return ["--stiction", f"{0.05 * AMP:.9g}"]
    return []


def autotune_sim(binary, args):
    r = subprocess.run([binary, "autotune-sim", *args], capture_output=True, text=True)
    line = r.stdout.splitlines()[0] if r.stdout else "{}"
    try:
        return json.loads(line)
    except json.JSONDecodeError:
        return {"status": "CRASH", "stderr": r.stderr}


def verdict(out, p, T):
    """completed / refused, and for a completed run its Ms (the program's,
    on the true plant with the hold's half scan) and safety: the Nyquist
    criterion on the true loop (autotune_bench.robustness), and whether the
    program's noise-free set-point and load steps settled in 20 T."""
    loop = out.get("loop")
    if out.get("status") != "PDT_OK" or not loop:
        return {"done": False, "status": out.get("status", "?")}
    ms = loop.get("Ms_true")
    ms = float("inf") if ms is None else float(ms)
    pid = out["tune"]["pid"]
    g = (float(pid["Kc"]), float(pid["Ti"]) if pid["Ti"] else math.inf, float(pid["Td"]),
         float(pid["Tf"]))
    _, stable = ab.robustness(p, g, T)
    return {"done": True, "status": "PDT_OK", "Ms": ms, "stable": stable,
            "settled": bool(loop.get("stable")), "unsafe": (not stable) or ms > MS_UNSAFE}


def run_open(job):
    binary, p, exp, seed, extra = job
    args, T, K, R = plant_args(p)
    base = [*args, *extra, "--experiment", exp, "--amplitude", f"{AMP:g}",
            "--noise", f"{NOISE * R:.9g}", "--seed", str(seed)]
    clean = autotune_sim(binary, base)
    dur = float(clean.get("experiment", {}).get("duration", 10.0 * T))
    settle = 20 * 4 * float(clean.get("scan_period", T / 200.0))
    t_mid = settle + 0.5 * max(dur - settle, 0.0)
    rows = []
    for fault in FAULTS:
        out = clean if fault == "none" else autotune_sim(
            binary, base + fault_args(fault, T, R, t_mid))
        v = verdict(out, p, T)
        v.update(plant=p.name, exp=exp, fault=fault, seed=seed,
                 scans=out.get("scans", 0), samples=out.get("samples", 0),
                 retries=out.get("repeats", 0), shift=out.get("shift"),
                 drift=out.get("drift", 0.0),
                 spread=(out.get("relay") or {}).get("spread"))
        rows.append(v)
    return rows


def run_closed(job):
    binary, p, start, exp, seed = job
    args, T, K, R = plant_args(p)
    integ = "--plant-integrating" in args
    f = START[start]
    kc = math.copysign(f / abs(K) / (T if integ else 1.0), K)
    ti = 4.0 * T / f if integ else T
    out = autotune_sim(binary, [*args, "--closed-loop", "--initial-gains", f"{kc:.9g},{ti:.9g}",
                                "--experiment", exp, "--amplitude", f"{CLOSED[exp] * AMP:g}",
                                "--noise", f"{NOISE * R:.9g}", "--seed", str(seed)])
    v = verdict(out, p, T)
    v.update(plant=p.name, start=start, exp=exp, seed=seed)
    cl = out.get("closed_loop") or {}
    v["Ms_before"] = cl.get("Ms_before")
    v["kept_old"] = not v["done"]
    # A refused retune leaves the old gains: judge those.
    if not v["done"] and v.get("Ms_before") is not None:
        v["unsafe_kept"] = float(v["Ms_before"]) > MS_UNSAFE
    return [v]


def build():
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
                    "-DCMAKE_BUILD_TYPE=Release", "-DPDT_BUILD_TESTS=OFF",
                    "-DPDT_REAL_DOUBLE=OFF"], check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdtfit_cli", "-j2"],
                   check=True, stdout=subprocess.DEVNULL)
    return str(BUILD / "tools" / "pdtfit")


def pct(a, b):
    return f"{100.0 * a / b:.1f} %" if b else "-"


def summary_rows(rows, key, keys):
    lines = []
    for k in keys:
        sel = [r for r in rows if r[key] == k]
        done = [r for r in sel if r["done"]]
        good = [r for r in done if r["Ms"] <= MS_OK]
        unsafe = [r for r in done if r["unsafe"]]
        ms = sorted(r["Ms"] for r in done)
        worst = f"{ms[-1]:.2f}" if ms else "-"
        med = f"{ms[len(ms) // 2]:.2f}" if ms else "-"
        lines.append(f"| {k} | {len(sel)} | {len(done)} ({pct(len(done), len(sel))}) | "
                     f"{len(good)} ({pct(len(good), len(done))}) | {med} | {worst} | "
                     f"{len(unsafe)} |")
    return "\n".join(lines)


def refusals(rows):
    counts = {}
    for r in rows:
        if not r["done"]:
            key = (r["fault"], r["exp"], r["status"])
            counts[key] = counts.get(key, 0) + 1
    return "\n".join(f"| {f} | {e} | `{s}` | {n} |" for (f, e, s), n in sorted(counts.items())) \
        or "| - | - | - | 0 |"


def closed_rows(rows):
    lines = []
    for start in START:
        for exp in CLOSED:
            sel = [r for r in rows if r["start"] == start and r["exp"] == exp]
            done = [r for r in sel if r["done"]]
            ms = sorted(r["Ms"] for r in done)
            before = sorted(float(r["Ms_before"]) for r in sel if r.get("Ms_before") is not None)
            unsafe = sum(1 for r in done if r["unsafe"])
            after = f"{ms[len(ms) // 2]:.2f} | {ms[-1]:.2f}" if ms else "- | -"
            bef = f"{before[len(before) // 2]:.2f}" if before else "-"
            lines.append(f"| {start} | {exp} | {len(sel)} | {len(done)} | {after} | {unsafe} | "
                         f"{bef} |")
    return "\n".join(lines)


def closed_refusals(rows):
    counts = {}
    for r in rows:
        if not r["done"]:
            key = (r["plant"], r["start"], r["exp"], r["status"])
            counts[key] = counts.get(key, 0) + 1
    return "\n".join(f"| {p} | {st} | {e} | `{s}` | {n} |"
                     for (p, st, e, s), n in sorted(counts.items())) or "| - | - | - | - | 0 |"


def report(open_rows, closed, seeds, binary):
    done = [r for r in open_rows if r["done"]]
    good = [r for r in done if r["Ms"] <= MS_OK]
    unsafe = [r for r in done if r["unsafe"]]
    cdone = [r for r in closed if r["done"]]
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    fields = dict(
        commit=commit or "unknown",
        machine=f"{platform.machine()}, {platform.system()} {platform.release()}, "
                f"Python {platform.python_version()}",
        plants=len(ab.batch()), seeds=seeds, runs=len(open_rows),
        noise=f"{100 * NOISE:g} %",
        fault_table="\n".join(f"| {k} | {v} |" for k, v in FAULTS.items()),
        completed=f"{len(done)} of {len(open_rows)} ({pct(len(done), len(open_rows))})",
        ms_ok=f"{len(good)} of {len(done)} ({pct(len(good), len(done))})",
        unsafe=str(len(unsafe)),
        by_fault=summary_rows(open_rows, "fault", list(FAULTS)),
        by_exp=summary_rows(open_rows, "exp", list(EXPERIMENTS)),
        by_fault_exp="\n".join(
            summary_rows([dict(r, fe=f"{r['fault']} / {r['exp']}") for r in open_rows], "fe",
                         [f"{f} / {e}" for f in FAULTS for e in EXPERIMENTS]).splitlines()),
        refusals=refusals(open_rows),
        closed_runs=str(len(closed)),
        closed_done=f"{len(cdone)} of {len(closed)}",
        closed_unsafe=str(sum(1 for r in cdone if r["unsafe"])),
        closed_kept_unsafe=str(sum(1 for r in closed if r.get("unsafe_kept"))),
        closed_table=closed_rows(closed),
        closed_refused=closed_refusals(closed),
        retried=str(sum(1 for r in open_rows if r.get("retries"))),
        unsettled=str(sum(1 for r in done if not r["settled"])),
    )
    text = string.Template(TEMPLATE.read_text()).substitute(fields)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--bin", default=None)
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--json", default=None, help="also write every run's verdict here")
    ap.add_argument("--extra", default="", help="more autotune-sim options (studies)")
    a = ap.parse_args()
    binary = a.bin or build()
    plants = ab.batch()
    jobs = [(binary, p, e, s, a.extra.split()) for p in plants for e in EXPERIMENTS for s in range(1, a.seeds + 1)]
    cjobs = [(binary, p, st, e, s) for p in plants for st in START for e in CLOSED
             for s in range(1, a.seeds + 1)]
    with mp.Pool(a.jobs) as pool:
        open_rows = [r for rows in pool.map(run_open, jobs) for r in rows]
        closed = [r for rows in pool.map(run_closed, cjobs) for r in rows]
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps({"open": open_rows, "closed": closed}))
    pathlib.Path(a.out).write_text(report(open_rows, closed, a.seeds, binary))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    main()
