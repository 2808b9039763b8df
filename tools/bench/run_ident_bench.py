#!/usr/bin/env python3
"""Identification benchmark of pdtfit: writes docs/reports/benchmarks.md.

Usage (from the repository root):

    python3 tools/bench/run_ident_bench.py            # full: about 45 min on 2 cores, a
                                                      # few with the reference cache filled
    python3 tools/bench/run_ident_bench.py --quick    # a few cases, under a minute,
                                                      # into build/bench/benchmarks-quick.md
    python3 tools/bench/run_ident_bench.py --update-certainty
                                                      # section 6 only, from docs/reports/certainty.md
    python3 tools/bench/run_ident_bench.py --update-speed
                                                      # sections 4 to 6 only (a few minutes)
    options: --jobs N (worker processes, default: all cores), --out FILE

It configures and builds the float library, the `pdtfit` command line and
the timing program tools/bench/ident_speed.c into build/bench (-O2), then:

1. accuracy on records with a known FOPDT/SOPDT truth, pdtfit against an
   output-error least-squares reference written with scipy;
2. FOPDT/SOPDT approximations of the Astrom-Hagglund test batch;
3. reliability of the global search over 100 seeds on hard cases;
4. speed (in-process timing, callgrind instruction counts, the fast scipy
   reference of fastref.py timed on the same data);
5. workspace memory;
6. the certainty battery's counts, copied from docs/reports/certainty.md (written by
   tools/bench/certainty.py, which takes longer and is run on its own).

Everything is seeded; the same machine and versions give the same document
(the timings apart). The scipy reference fits (benchlib.Reference) depend
on the records alone and are kept in build/bench/reference-cache, under a
hash of the record and of the reference's code (PDT_REFERENCE_CACHE: another
folder, or "off"): run again after a change to pdtfit, the script refits
nothing.
"""
from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import pathlib
import platform
import re
import string
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy

from pdtbench import benchlib as bl
from pdtbench.benchlib import ROOT
from pdtbench import fastref
from pdtsupport import provenance, template

BUILD = ROOT / "build" / "bench"
PDTFIT = BUILD / "tools" / "pdtfit"
SPEED = BUILD / "tools" / "bench" / "pdt_ident_speed"
N_REC = 1500          # samples per accuracy record
FLOOR = 1e-3          # absolute floor of the per-seed target comparison
TARGET_SNR = 20       # the accuracy target holds on the sets at this SNR and above


# ------------------------------------------------------------------ build

def build():
    cfg = ["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
           "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_C_FLAGS_RELEASE=-O2 -DNDEBUG",
           "-DPDT_BUILD_TESTS=OFF", "-DPDT_REAL_DOUBLE=OFF"]
    subprocess.run(cfg, check=True, stdout=subprocess.DEVNULL)
    # A tree under active development may fail to build for a moment:
    # retry a few times before giving up.
    for attempt in range(6):
        r = subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdtfit_cli",
                            "pdt_ident_speed"], capture_output=True, text=True)
        if r.returncode == 0:
            return
        time.sleep(20)
    sys.exit("build failed:\n" + r.stdout[-3000:] + r.stderr[-3000:])


def machine():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout
    cache = (BUILD / "CMakeCache.txt").read_text()
    m = re.search(r"CMAKE_C_COMPILER:\w+=(.*)", cache)
    comp = m.group(1) if m else "cc"
    ver = subprocess.run([comp, "--version"], capture_output=True, text=True).stdout
    return {"cpu": cpu, "cores": os.cpu_count(), "compiler": (ver or cc).splitlines()[0],
            "python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "os": platform.platform()}


# ------------------------------------------------------------------ 1. accuracy

def truths():
    return [
        bl.fopdt_truth("F1: K=2, tau/Td=0.1", 2.0, 0.5, 5.03),
        bl.fopdt_truth("F2: K=2, tau/Td=1", 2.0, 3.0, 3.03),
        bl.fopdt_truth("F3: K=2, tau/Td=10", 2.0, 20.0, 2.03),
        bl.fopdt_truth("F4: K=-0.5, tau/Td=3", -0.5, 6.0, 2.03),
        bl.sopdt_truth("S1: overdamped zeta=1.5", 1.5, 0.4, 1.5, 1.73),
        bl.sopdt_truth("S2: underdamped zeta=0.3", 0.8, 0.5, 0.3, 2.33),
        bl.integ_truth("S3: integrating", 0.05, 3.0, 1.93),
    ]


def record_ts(truth, n=N_REC):
    """Ts for a record of 4 settling times; 3 significant digits."""
    ts = 4.0 * truth.settle / n
    e = math.floor(math.log10(ts))
    return round(ts, 2 - e)


def accuracy_sets(quick):
    T = truths()
    sets = []
    if quick:
        for i in (1, 5):
            for exc in ("step", "prbs", "relay"):
                sets.append((i, exc, 20, False))
        return sets
    for i in range(len(T)):
        for exc in ("step", "pulse", "prbs", "chirp", "relay"):
            sets.append((i, exc, 20, False))
        for snr in (10, 30, 40):
            sets.append((i, "prbs", snr, False))
        sets.append((i, "prbs", 30, True))
        sets.append((i, "relay", 30, True))
    return sets


def model_name(truth):
    return "fopdt" if truth.kind == "fopdt" else "sopdt"


def _judge(truth, m, y0, u, y, Ts, t, href):
    e = bl.param_errors(truth, m)
    try:
        h = bl.step_model(m, t)
        iae = bl.niae(h, href, t)
    except ValueError:
        iae = math.inf
    return {"err": e, "worst": max(e.values()), "iae": iae,
            "cost": bl.oe_cost(m, y0, u, y, Ts)}


def accuracy_task(args):
    ti, exc, snr, quant, seed = args
    truth = truths()[ti]
    Ts = record_ts(truth)
    u, y, info = bl.make_record(truth, exc, N_REC, Ts, snr, quant, seed)
    t = bl.step_grid(truth.settle * 1.5)
    href = bl.step_model(truth.model(), t)
    out = {"set": (ti, exc, snr, quant), "seed": seed}
    mname = model_name(truth)
    costs = ["simulation"]
    if exc in bl.RETURNS_TO_REST and truth.kind != "integ":
        costs.append("combined")
    for cost in costs:
        j = bl.run_pdtfit(PDTFIT, u, y, Ts, mname, cost=cost, seed=seed)
        key = "pdtfit" if cost == "simulation" else "pdtfit_combined"
        if "error" in j:
            out[key] = {"error": j["error"], "worst": math.inf, "iae": math.inf, "err": {}}
            continue
        m, y0 = bl.model_from_json(j)
        out[key] = _judge(truth, m, y0, u, y, Ts, t, href)
        out[key]["evaluations"] = j["evaluations"]
    out["ref"] = reference_fit(truth, u, y, Ts, t, href)
    return out


def reference_model(u, y, Ts, mname):
    """The reference on one record: of two independent scipy output-error
    fits (the trust-region one of benchlib.Reference and the
    Levenberg-Marquardt one of fastref.FastRef, which start from different
    shapes), the one with the lower output-error cost. Returns its model,
    its offset and its name ("trf" or "lm")."""
    trf = bl.Reference(u, y, Ts, mname)
    m_trf, off_trf, _ = trf.fit()
    lm = fastref.FastRef(u, y, Ts, mname)
    _, x = lm.fit()
    m_lm, off_lm = lm.model_of(x)
    if bl.oe_cost(m_lm, off_lm, u, y, Ts) < bl.oe_cost(m_trf, off_trf, u, y, Ts):
        return m_lm, off_lm, "lm"
    return m_trf, off_trf, "trf"


def reference_fit(truth, u, y, Ts, t, href):
    """The reference judged like pdtfit's answer; "source" names the fit
    taken."""
    m, off, source = reference_model(u, y, Ts, model_name(truth))
    return dict(_judge(truth, m, off, u, y, Ts, t, href), source=source)


def meets_target(p, ref):
    """The per-seed accuracy target: pdtfit's worst parameter error (p) at
    most 1.1 x the reference's plus FLOOR."""
    return p["worst"] <= 1.1 * ref["worst"] + FLOOR


def missed_seeds(results):
    """The seeds that missed the target (SNR >= TARGET_SNR) with the default cost: the worst
    errors and both answers' output-error costs on the record, which tell
    a search that stopped short from a record whose least-squares answer
    lies farther from the truth than another local fit."""
    out = []
    for r in sorted(results, key=lambda r: (r["set"], r["seed"])):
        p, f = r.get("pdtfit"), r["ref"]
        if r["set"][2] < TARGET_SNR or p is None or meets_target(p, f):
            continue
        name = truths()[r["set"][0]].name
        if "cost" not in p or not f["cost"] > 0:
            out.append(f"- {name}, {set_label(r['set'])}, seed {r['seed']}: no model to "
                       f"compare ({p.get('error', 'a model of the wrong kind')}).")
            continue
        ratio = p["cost"] / f["cost"]
        out.append(f"- {name}, {set_label(r['set'])}, seed {r['seed']}: worst error "
                   f"{fmt(p['worst'])} against the reference's {fmt(f['worst'])}; "
                   f"output-error cost {ratio:.6f} x the reference's"
                   f"{' (pdtfit fits the record better)' if ratio < 1 else ''}.")
    if out:
        out.insert(0, "\nThe seeds that missed it:\n")
    return out


def pct(x, q):
    x = np.asarray(x, float)
    if x.size == 0:
        return math.nan
    return float(np.percentile(x, q)) if np.all(np.isfinite(x)) or q < 100 else math.inf


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if math.isinf(v):
        return "fail"
    if v == 0:
        return "0"
    if abs(v) >= 100:
        return f"{v:.0f}"
    return f"{v:.{digits}g}"


def set_label(s):
    ti, exc, snr, quant = s
    return f"{exc}, {snr} dB" + (", quantised" if quant else "")


def accuracy_report(results, seeds):
    T = truths()
    by_set = {}
    for r in results:
        by_set.setdefault(r["set"], []).append(r)
    lines = []
    summary = []
    for ti, truth in enumerate(T):
        if not any(s[0] == ti for s in by_set):
            continue
        names = list(bl.param_errors(truth, truth.model()).keys())
        lines.append(f"\n### {truth.name}\n")
        p = truth.params
        desc = ", ".join(f"{k} = {v:g}" for k, v in p.items())
        lines.append(f"Truth: {desc}, Td = {truth.Td:g} s; Ts = {record_ts(truth):g} s, "
                     f"{N_REC} samples; Td errors are divided by "
                     f"{'tau' if truth.kind == 'fopdt' else ('1/wn' if truth.kind == 'sopdt' else 'T')}"
                     f" = {truth.scale:g} s.\n")
        head = "| record | fit | " + " | ".join(f"{n} med / p90" for n in names) + \
            " | step IAE med / p90 | failed |"
        lines.append(head)
        lines.append("|" + "---|" * (head.count("|") - 1))
        for s in sorted((s for s in by_set if s[0] == ti), key=lambda s: (s[3], s[2], s[1])):
            rs = by_set[s]
            for key, label in (("pdtfit", "pdtfit"), ("pdtfit_combined", "pdtfit combined"),
                               ("ref", "reference")):
                rows = [r[key] for r in rs if key in r]
                if not rows:
                    continue
                ok = [r for r in rows if "error" not in r]
                cells = []
                for n in names:
                    v = [r["err"][n] for r in ok]
                    cells.append(f"{fmt(pct(v, 50))} / {fmt(pct(v, 90))}")
                iae = [r["iae"] for r in ok]
                cells.append(f"{fmt(pct(iae, 50))} / {fmt(pct(iae, 90))}")
                cells.append(str(len(rows) - len(ok)))
                lines.append(f"| {set_label(s)} | {label} | " + " | ".join(cells) + " |")
            if s[2] >= TARGET_SNR:
                met = sum(1 for r in rs if meets_target(r["pdtfit"], r["ref"]))
                metc = None
                if any("pdtfit_combined" in r for r in rs):
                    metc = sum(1 for r in rs if meets_target(r["pdtfit_combined"], r["ref"]))
                summary.append((truth.name, set_label(s), met, metc, len(rs)))
    return lines, summary


# ------------------------------------------------------------------ 2. Astrom-Hagglund

def ah_plants(quick):
    P = []

    def lag(T):
        return [T, 1.0]

    def mul(*ps):
        r = np.array([1.0])
        for p in ps:
            r = np.polymul(r, p)
        return r
    if quick:
        return [bl.HighOrder("P1 T=1", [1.0], lag(1.0), 1.0),
                bl.HighOrder("P4 n=4", [1.0], mul(*[lag(1.0)] * 4))]
    for T in (0.1, 1.0, 10.0):
        P.append(bl.HighOrder(f"P1 T={T:g}", [1.0], lag(T), 1.0))
    for T in (0.1, 1.0, 10.0):
        P.append(bl.HighOrder(f"P2 T={T:g}", [1.0], mul(lag(T), lag(T)), 1.0))
    for T in (0.1, 0.5, 2.0):
        P.append(bl.HighOrder(f"P3 T={T:g}", [1.0], mul(lag(1.0), lag(T), lag(T))))
    for n in (3, 5, 8):
        P.append(bl.HighOrder(f"P4 n={n}", [1.0], mul(*[lag(1.0)] * n)))
    for a in (0.2, 0.5, 0.8):
        P.append(bl.HighOrder(f"P5 alpha={a:g}", [1.0],
                              mul(lag(1.0), lag(a), lag(a * a), lag(a ** 3))))
    for L in (0.1, 0.5, 0.9):
        P.append(bl.HighOrder(f"P6 L={L:g}", [1.0], mul([1.0, 0.0], lag(1.0 - L)), L))
    for T in (1.0, 2.0, 5.0):
        P.append(bl.HighOrder(f"P7 T={T:g}", [T], mul(lag(T), lag(0.5)), 0.5))
    for a in (0.1, 0.5, 1.0):
        P.append(bl.HighOrder(f"P8 alpha={a:g}", [-a, 1.0], mul(*[lag(1.0)] * 3)))
    for T in (0.1, 0.5, 1.0):
        P.append(bl.HighOrder(f"P9 T={T:g}", [1.0], mul(lag(1.0), [T * T, 1.4 * T, 1.0])))
    return P


def residence_time(p):
    """Mean residence time L + den'(0)/den(0) - num'(0)/num(0); for an
    integrator, L + its lag (1 for P6)."""
    if p.den[-1] == 0.0:
        return 1.0
    return p.L + p.den[-2] / p.den[-1] - p.num[-2] / p.num[-1] if p.num.size > 1 \
        else p.L + p.den[-2] / p.den[-1]


def phase_crossover(p, Tar):
    w = np.logspace(-3, 3, 20000) / Tar
    ph = np.unwrap(np.angle(p.freq(w)))
    ph -= 2 * math.pi * round(ph[0] / (2 * math.pi))   # start near 0 (or -pi/2)
    i = np.argmax(ph <= -math.pi)
    return float(w[i])


def ah_record(idx, quick, exc):
    """A-H plant idx: a record of 20 Tar in N_REC samples at 30 dB (a chirp
    then rests for its last 30 %, so it ends settled), and the true step
    response on the grid its IAE is taken over. Returns the plant, Tar,
    whether it integrates, u, y, Ts, the grid and the true response."""
    p = ah_plants(quick)[idx]
    Tar = residence_time(p)
    integ = p.den[-1] == 0.0
    n = N_REC
    Ts = 20.0 * Tar / n
    du = bl.excitation(exc, n, Ts, Tar, bl.Rng(4242 + idx))
    if exc == "chirp":
        du[int(0.7 * n):] = 0.0
    yc = p.simulate(Ts, bl.AMP * du)
    sigma = float(np.std(yc)) / 10.0 ** (30 / 20.0)
    u = bl.U0 + bl.AMP * du
    y = bl.Y0 + yc + sigma * bl.Rng(99 + idx).normal(n)
    tend = 5.0 if integ else 4.0 * Tar
    t = np.linspace(0.0, tend, 2001)
    href = p.simulate(t[1] - t[0], np.ones(t.size))
    return p, Tar, integ, u, y, Ts, t, href


def ah_task(args):
    idx, quick = args
    p, Tar, integ, u, y, Ts, t, href = ah_record(idx, quick, "prbs")
    wu = phase_crossover(p, Tar)
    w = np.logspace(-2, 0, 200) * wu
    G = p.freq(w)
    out = {"name": p.name, "Ts": Ts, "wu": wu, "tend": float(t[-1]), "fits": {}}
    for model in ("fopdt", "sopdt"):
        j = bl.run_pdtfit(PDTFIT, u, y, Ts, model)
        mr, _, _ = reference_model(u, y, Ts, model)
        for key, m in (("pdtfit", None if "error" in j else bl.model_from_json(j)[0]),
                       ("ref", mr)):
            if m is None:
                out["fits"][(model, key)] = None
                continue
            h = bl.step_model(m, t)
            Gm = bl.model_freq(m, w)
            out["fits"][(model, key)] = {
                "iae": bl.niae(h, href, t),
                "ferr": float(np.max(np.abs(Gm - G) / np.abs(G))),
                "model": m}
    return out


WEIGHT_EXCITATIONS = ("prbs", "pulse", "chirp")
WEIGHT_VARIANTS = (("simulation", "simulation", ()),
                   ("combined, uniform W", "combined", ("--weight", "uniform")),
                   ("combined, control band", "combined", ("--weight", "control")))


def weight_task(args):
    """One A-H plant, one excitation that returns to rest (the frequency
    cost needs it): step IAE of pdtfit's FOPDT and SOPDT under the time cost
    and the combined cost with each weighting."""
    idx, exc, quick = args
    p, _, integ, u, y, Ts, t, href = ah_record(idx, quick, exc)
    out = {"name": p.name, "exc": exc, "integ": integ, "iae": {}}
    for model in ("fopdt", "sopdt"):
        for label, cost, extra in WEIGHT_VARIANTS:
            j = bl.run_pdtfit(PDTFIT, u, y, Ts, model, cost=cost, extra=extra)
            out["iae"][(model, label)] = (None if "error" in j else
                                          bl.niae(bl.step_model(bl.model_from_json(j)[0], t),
                                                  href, t))
    return out


def weight_report(res):
    """Geometric mean step IAE per model, excitation and weighting over the
    non-integrating plants, and how often each combined weighting beats or
    loses to the time cost by more than 2 %."""
    lines = ["| model | record | " + " | ".join(v[0] for v in WEIGHT_VARIANTS) +
             " | control band vs simulation: better / worse | control vs uniform: better / worse |",
             "|---|---|" + "---|" * (len(WEIGHT_VARIANTS) + 2)]
    for model in ("fopdt", "sopdt"):
        for exc in WEIGHT_EXCITATIONS:
            rows = [r for r in res if r["exc"] == exc and not r["integ"]]
            vals = {v[0]: np.array([r["iae"][(model, v[0])] if r["iae"][(model, v[0])]
                                    is not None else np.inf for r in rows])
                    for v in WEIGHT_VARIANTS}
            cells = []
            for v in WEIGHT_VARIANTS:
                x = vals[v[0]]
                cells.append(fmt(math.exp(float(np.mean(np.log(x))))) if np.all(np.isfinite(x))
                             else "fail")
            c, s_, un = (vals["combined, control band"], vals["simulation"],
                         vals["combined, uniform W"])
            cells.append(f"{int(np.sum(c < 0.98 * s_))} / {int(np.sum(c > 1.02 * s_))}")
            cells.append(f"{int(np.sum(c < 0.98 * un))} / {int(np.sum(c > 1.02 * un))}")
            lines.append(f"| {model} | {exc} | " + " | ".join(cells) + " |")
    return lines


def describe(m):
    if isinstance(m, bl.models.Fopdt):
        return f"K {m.K:.3g}, tau {m.tau:.3g}, Td {m.Td:.3g}"
    if m.b == 0:
        return f"Ki {m.k / m.a:.3g}, T {1 / m.a:.3g}, Td {m.Td:.3g}"
    n = bl.models.to_natural(m)
    return f"K {n.K:.3g}, wn {n.wn:.3g}, zeta {n.zeta:.3g}, Td {m.Td:.3g}"


# ------------------------------------------------------------------ 3. reliability

def rel_cases(quick):
    c = [("underdamped SOPDT (zeta 0.25), chirp", bl.sopdt_truth("R1", 1.0, 0.5, 0.25, 2.33), "chirp"),
         ("FOPDT with Td = 5 tau, PRBS", bl.fopdt_truth("R2", 2.0, 2.0, 10.03), "prbs"),
         ("integrating SOPDT, PRBS", bl.integ_truth("R3", 0.05, 3.0, 1.93), "prbs")]
    return c[:1] if quick else c


def rel_record(case):
    name, truth, exc = case
    Ts = record_ts(truth)
    u, y, _ = bl.make_record(truth, exc, N_REC, Ts, 30, False, 1)
    return u, y, Ts


def profiled_cost(m, u, y, Ts):
    """Mean square residual over the samples pdtfit scores (the whole
    record), gain and offset re-fitted in closed form: the shape and dead
    time alone decide it."""
    unit = bl.simulate(m, Ts, np.asarray(u) - u[0])
    A = np.column_stack([unit, np.ones(unit.size)])
    yy = np.asarray(y)
    coef = np.linalg.lstsq(A, yy, rcond=None)[0]
    return float(np.mean((yy - A @ coef) ** 2))


def rel_task(args):
    ci, kind, seed, quick = args
    case = rel_cases(quick)[ci]
    u, y, Ts = rel_record(case)
    model = model_name(case[1])
    if kind == "pdtfit":
        j = bl.run_pdtfit(PDTFIT, u, y, Ts, model, seed=seed)
        if "error" in j:
            return (ci, kind, seed, math.inf, 0)
        m, _ = bl.model_from_json(j)
        return (ci, kind, seed, profiled_cost(m, u, y, Ts), j["evaluations"])
    ref = bl.Reference(u, y, Ts, model)
    if kind == "ref9":
        m, _, _ = ref.fit()
    else:   # one local fit from a random dead time
        td = bl.Rng(5000 + seed).uniform() * ref.T / 3
        m, _, _ = ref.fit(td_starts=[td])
    return (ci, kind, seed, profiled_cost(m, u, y, Ts), ref.nfev)


# ------------------------------------------------------------------ 4/5. speed, memory

def write_bin(path, u, y):
    np.concatenate([np.asarray(u, "<f8"), np.asarray(y, "<f8")]).tofile(path)


def time_reference(u, y, Ts, model, reps):
    """The fast nine-start reference (fastref.FastRef.fit) on one record:
    its median wall time over reps runs, evaluations and cost."""
    times = []
    for _ in range(reps):
        ref = fastref.FastRef(u, y, Ts, model)
        t0 = time.perf_counter()
        c, _ = ref.fit()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), ref.nfev, c


# The identification's stages by the functions that run them
# (lib/src/pdt_ident.c, run_stage), each counted with what it calls.
STAGES = (("set-up (pdt_ident_init, the coarse record)",
           ("pdt_ident_init", "pdt_ident_coarse_start")),
          ("the screen for gross errors (running median, its bound, the test)",
           ("pdt_ident_screen_high", "pdt_ident_screen_median", "pdt_ident_screen_bound",
            "pdt_ident_screen_step")),
          ("population: evaluations", ("pdt_ident_ga_eval_parent", "pdt_ident_ga_eval_offspring")),
          ("population: breeding (tournament, SBX, mutation, sharing)", ("pdt_ident_ga_breed",)),
          ("refinement of the niches (Nelder-Mead)", ("pdt_ident_refine_begin",
                                                      "pdt_ident_refine_step")),
          ("Newton polish and dead-time probe", ("pdt_ident_polish_step",
                                                 "pdt_ident_polish_probe")),
          ("a search's finish and the vote", ("pdt_ident_finish",)),
          ("dead-time profile", ("pdt_ident_profile_step",)),
          ("the whole record after the coarse one", ("pdt_ident_coarse_fine",)),
          ("uncertainty (Fisher information)", ("pdt_ident_std", "pdt_ident_std_pass")),
          ("the evidence and the initial state's tests",
           ("pdt_ident_std_evidence", "pdt_ident_std_lags", "pdt_ident_std_state")))


def stage_shares(out, total):
    """Instructions of each stage in one callgrind run: the calls from the
    sequencer (pdt_ident_step) and from pdt_identify, each with what it
    calls. The rest (the sequencer itself, the result) is "other"."""
    text = subprocess.run(["callgrind_annotate", "--tree=calling", "--inclusive=yes",
                           "--threshold=100", str(out)], capture_output=True, text=True,
                          check=True).stdout
    calls, caller = {}, None
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+) \([ \d.]+%\)\s+([*>])\s+\S*?:(\w+)", line)
        if not m:
            caller = None if not line.strip() else caller
            continue
        ir, mark, fn = int(m.group(1).replace(",", "")), m.group(2), m.group(3)
        if mark == "*":
            caller = fn
        elif caller in ("pdt_ident_step", "run_stage", "pdt_identify"):
            calls[fn] = calls.get(fn, 0) + ir
    shares = [(label, sum(calls.get(f, 0) for f in fns)) for label, fns in STAGES]
    shares.append(("other (the sequencer, the result)", total - sum(v for _, v in shares)))
    return shares


def speed_section(quick, tmp):
    Ns = (500, 2000) if quick else (500, 1000, 1200, 2000, 4000, 8000)
    reps = 3 if quick else 9
    cases = [("fopdt", bl.fopdt_truth("F2", 2.0, 3.0, 3.03)),
             ("sopdt", bl.sopdt_truth("S2", 0.8, 0.5, 0.3, 2.33))]
    have_vg = subprocess.run(["which", "valgrind"], capture_output=True).returncode == 0
    rows = []
    for model, truth in cases:
        Ts = record_ts(truth)
        for N in Ns:
            u, y, _ = bl.make_record(truth, "prbs", N, Ts, 30, False, 1)
            f = pathlib.Path(tmp) / f"{model}_{N}.bin"
            write_bin(f, u, y)
            res = json.loads(subprocess.run([str(SPEED), "time", str(f), f"{Ts:.17g}", model,
                                             str(reps)], capture_output=True, text=True,
                                            check=True).stdout)
            row = {"model": model, "N": N, **res}
            # the reference right after pdtfit, on the same record and core
            row["ref_s"], row["ref_nfev"], ref_cost = time_reference(u, y, Ts, model,
                                                                     max(3, reps // 3))
            j = bl.run_pdtfit(PDTFIT, u, y, Ts, model)
            if "error" not in j:
                m, _ = bl.model_from_json(j)
                row["ref_cost_ratio"] = ref_cost / profiled_cost(m, u, y, Ts)
            if have_vg and (not quick or N == 2000):
                out = pathlib.Path(tmp) / f"cg_{model}_{N}.out"
                subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                                "--collect-atstart=no", "--toggle-collect=pdt_identify",
                                str(SPEED), "once", str(f), f"{Ts:.17g}", model],
                               capture_output=True, text=True, check=True)
                ir = None
                for line in out.read_text().splitlines():
                    if line.startswith("totals:") or line.startswith("summary:"):
                        ir = int(line.split()[1])
                row["Ir"] = ir
                row["ir_per_sample_eval"] = ir / (res["evaluations"] * N) if ir else None
                if N == 2000 and ir:
                    row["stages"] = stage_shares(out, ir)
            rows.append(row)
    mem = []
    for N in (500, 2000, 8000):
        mem.append(json.loads(subprocess.run([str(SPEED), "workspace", str(N)],
                                             capture_output=True, text=True,
                                             check=True).stdout))
    return rows, mem


# ------------------------------------------------------------------ 6. certainty

def certainty_section():
    """The summary of docs/reports/certainty.md (its run and its tables), headings
    moved one level down, after the section's introduction (the template's
    certainty part); a pointer when it has not been generated."""
    parts = template.parts(PARTS)
    path = ROOT / "docs" / "reports" / "certainty.md"
    if not path.exists():
        return [parts["certainty_missing"].substitute()]
    doc = [parts["certainty"].substitute()]
    keep = False
    for line in path.read_text().splitlines():
        if line.startswith("## Run"):
            keep = True
            continue
        if line.startswith("### Examples"):
            keep = False
        if not keep or line.startswith("## Summary"):
            continue
        doc.append("#" + line if line.startswith("###") else line)
    return doc


def speed_rows(speed):
    """The speed table's rows and the targets met or missed."""
    rows = []
    for r in speed:
        ir = r.get("ir_per_sample_eval")
        rc = r.get("ref_cost_ratio")
        tot = "-" if not r.get("Ir") else f"{r['Ir'] / 1e6:.1f}"
        rows.append(f"| {r['model']} | {r['N']} | {r['evaluations']} | "
                    f"{1e3 * r['median_s']:.2f} | {tot} | "
                    f"{'-' if ir is None else f'{ir:.1f}'} | "
                    f"{1e3 * r['ref_s']:.1f} ({r['ref_nfev']}) | "
                    f"{'-' if rc is None else f'{rc:.3g}'} | "
                    f"{r['ref_s'] / r['median_s']:.1f} x |")
    targets = []
    for model, lim in (("fopdt", 1.0), ("sopdt", 5.0)):
        r = [x for x in speed if x["model"] == model and x["N"] == 2000]
        if r:
            r = r[0]
            ms = 1e3 * r["median_s"]
            su = r["ref_s"] / r["median_s"]
            targets.append(f"- {model.upper()} at N = 2000: {ms:.2f} ms against the {lim:g} ms "
                           f"target: **{'met' if ms <= lim else 'missed'}**; {su:.1f} x faster "
                           f"than the fast reference.")
    return "\n".join(rows), targets


def stage_block(speed):
    """Where one identification's instructions go, by stage; empty without
    stage counts."""
    staged = [r for r in speed if r.get("stages")]
    if not staged:
        return ""
    lines = ["", "Where the instructions of one identification at N = 2000 go, by stage "
             "(the same callgrind runs; each stage with all it calls, the cost "
             "evaluations included):\n",
             "| stage | " + " | ".join(f"{r['model'].upper()} (M)" for r in staged) +
             " | " + " | ".join(f"{r['model'].upper()} share" for r in staged) + " |",
             "|---|" + "---|" * (2 * len(staged))]
    for i, (label, _) in enumerate(staged[0]["stages"]):
        vals = [r["stages"][i][1] for r in staged]
        lines.append(f"| {label} | " + " | ".join(f"{v / 1e6:.2f}" for v in vals) + " | " +
                     " | ".join(f"{100 * v / r['Ir']:.1f} %" for v, r in zip(vals, staged)) +
                     " |")
    return "\n".join(lines) + "\n\n"


def speed_memory_doc(speed, mem, load_before, load_after):
    """Sections 4 and 5 of the document: the template
    run_ident_bench_speed.md.in with the tables, as two entries of the
    document's list (the heading, then the rest: --update-speed puts its
    note between them)."""
    rows, targets = speed_rows(speed)
    memory = [f"| {model} | {c} | " + " | ".join(str(m[f"{model}_{c}"]) for m in mem) + " |"
              for model in ("fopdt", "sopdt")
              for c in ("prediction", "simulation", "frequency", "combined")]
    text = string.Template(SPEED_TEMPLATE.read_text()).substitute(
        load_before=f"{load_before:.2f}", load_after=f"{load_after:.2f}", speed_rows=rows,
        targets_and_stages=("\n".join(targets) + "\n" if targets else "") + stage_block(speed),
        real_bytes=str(mem[0]["real_bytes"]), ctx=str(mem[0]["ctx"]),
        memory_rows="\n".join(memory))
    head, rest = text.split("\n\n", 1)
    return [head + "\n", rest]


# ------------------------------------------------------------------ document

# The report's introduction (what is measured, and how), kept beside this file.
INTRO = pathlib.Path(__file__).with_name("run_ident_bench.md.in")
# Sections 4 and 5 (speed and memory).
SPEED_TEMPLATE = pathlib.Path(__file__).with_name("run_ident_bench_speed.md.in")
# The prose of the machine and sections 1 to 3 (part results), of section 6
# (certainty, certainty_missing) and of --update-speed's note, read by
# pdtsupport.template.parts.
PARTS = pathlib.Path(__file__).with_name("run_ident_bench_parts.md.in")


def summary_rows(summary):
    """Section 1's summary table: the seeds meeting the target per set."""
    rows = []
    for name, lab, met, metc, n in summary:
        c = "-" if metc is None else f"{metc}/{n}"
        rows.append(f"| {name} | {lab} | {met}/{n}{'' if met == n else ' (missed)'} | {c} |")
    return rows


def batch_rows(ah):
    """Section 2's rows and the count of pdtfit's fits worse than the reference's."""
    rows, worse = [], 0
    for r in ah:
        cells = []
        for key in (("fopdt", "pdtfit"), ("fopdt", "ref"), ("sopdt", "pdtfit"), ("sopdt", "ref")):
            f = r["fits"][key]
            cells.append("fail" if f is None else f"{fmt(f['iae'])} / {fmt(f['ferr'])}")
        for mdl in ("fopdt", "sopdt"):
            fp, fr = r["fits"][(mdl, "pdtfit")], r["fits"][(mdl, "ref")]
            if fp is None or (fr is not None and fp["iae"] > 1.1 * fr["iae"] + FLOOR):
                worse += 1
        ms = r["fits"][("sopdt", "pdtfit")]
        rows.append(f"| {r['name']} | {r['wu']:.3g} | " + " | ".join(cells) +
                    f" | {describe(ms['model']) if ms else '-'} |")
    return rows, worse


def reliability_rows(rel, quick):
    """Section 3's rows: each case's success against the best cost found."""
    rows = []
    for ci, case in enumerate(rel_cases(quick)):
        rs = [r for r in rel if r[0] == ci]
        best = min(r[3] for r in rs)
        ok = lambda r: r[3] <= 1.01 * best  # noqa: E731
        p = [r for r in rs if r[1] == "pdtfit"]
        r1 = [r for r in rs if r[1] == "ref1"]
        r9 = [r for r in rs if r[1] == "ref9"][0]
        ev = [r[4] for r in p]
        worst = max(r[3] for r in p) / best
        rows.append(f"| {case[0]} | {sum(map(ok, p))}/{len(p)} (worst cost {worst:.3g} x best) | "
                    f"{int(np.median(ev))} / {max(ev)} | "
                    f"{'within 1 %' if ok(r9) else f'{r9[3] / best:.3g} x best'} "
                    f"({r9[4]} evaluations) | {sum(map(ok, r1))}/{len(r1)} |")
    return rows


def results_doc(run, acc, ah, wres, rel):
    """The machine and sections 1 to 3: the template's results part with the
    tables; run: mach, quick, elapsed (s), jobs, seeds, rel_seeds."""
    quick, seeds = run["quick"], run["seeds"]
    tables, summary = accuracy_report(acc, seeds)
    rows, worse = batch_rows(ah)
    n_integ = sum(1 for r in wres if r["integ"]) // len(WEIGHT_EXCITATIONS)
    return template.parts(PARTS)["results"].substitute(
        **run["mach"], mode="quick" if quick else "full", minutes=f"{run['elapsed'] / 60:.1f}",
        jobs=str(run["jobs"]), seeds=str(seeds), target_snr=str(TARGET_SNR),
        floor=f"{FLOOR:g}", n_lm=str(sum(1 for r in acc if r["ref"]["source"] == "lm")),
        n_acc=str(len(acc)), n_met=str(sum(1 for s in summary if s[2] == s[4])),
        n_sets=str(len(summary)), summary_rows="\n".join(summary_rows(summary)),
        missed_seeds="".join(m + "\n" for m in missed_seeds(acc)),
        accuracy_tables="\n".join(tables), batch_rows="\n".join(rows), batch_worse=str(worse),
        batch_fits=str(2 * len(ah)),
        n_weighted=str(len(wres) // len(WEIGHT_EXCITATIONS) - n_integ),
        weight_tables="\n".join(weight_report(wres)), n_rec=str(N_REC),
        rel_seeds=str(run["rel_seeds"]), ref1_runs=str(run["rel_seeds"] if not quick else 3),
        reliability_rows="\n".join(reliability_rows(rel, quick)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out")
    ap.add_argument("--update-speed", action="store_true",
                    help="only rerun sections 4 and 5 (speed, memory) and replace sections "
                         "4 to 6 of the document, keeping sections 1 to 3")
    ap.add_argument("--update-certainty", action="store_true",
                    help="only replace section 6 of the document with docs/reports/certainty.md's "
                         "summary (after a run of certainty.py)")
    a = ap.parse_args()
    quick = a.quick
    out = pathlib.Path(a.out) if a.out else (
        BUILD / "benchmarks-quick.md" if quick else ROOT / "docs" / "reports" / "benchmarks.md")
    if a.update_speed:
        build()
        text = out.read_text()
        head = text.split("## 4. Speed")[0].rstrip("\n")
        load_before = os.getloadavg()[0]
        with tempfile.TemporaryDirectory() as tmp:
            speed, mem = speed_section(False, tmp)
        load_after = os.getloadavg()[0]
        note = [template.parts(PARTS)["update_speed_note"].substitute(
            date=time.strftime('%Y-%m-%d'), commit=provenance.commit())]
        sm = speed_memory_doc(speed, mem, load_before, load_after)
        doc = [head, ""] + sm[:1] + note + sm[1:] + certainty_section()
        out.write_text("\n".join(doc) + "\n")
        print(f"updated sections 4 to 6 of {out}")
        return
    if a.update_certainty:
        text = out.read_text()
        head = text.split("## 6. Certainty of the global search")[0].rstrip("\n")
        out.write_text(head + "\n\n" + "\n".join(certainty_section()) + "\n")
        print(f"updated section 6 of {out}")
        return
    t_start = time.time()
    build()
    mach = machine()
    seeds = 2 if quick else 10
    rel_seeds = 10 if quick else 100

    # 4 and 5 first and alone, so the timings are not disturbed by the pool.
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        speed, mem = speed_section(quick, tmp)
    load_after = os.getloadavg()[0]
    print(f"speed done {time.time() - t_start:.0f} s", flush=True)

    acc_tasks = [(*s, seed) for s in accuracy_sets(quick) for seed in range(1, seeds + 1)]
    nah = len(ah_plants(quick))
    rel_tasks = []
    for ci in range(len(rel_cases(quick))):
        rel_tasks += [(ci, "pdtfit", s, quick) for s in range(1, rel_seeds + 1)]
        rel_tasks += [(ci, "ref1", s, quick) for s in range(1, (rel_seeds if not quick else 3) + 1)]
        rel_tasks.append((ci, "ref9", 0, quick))
    w_tasks = [(i, e, quick) for i in range(nah) for e in WEIGHT_EXCITATIONS]
    with mp.Pool(a.jobs) as pool:
        ah_async = pool.map_async(ah_task, [(i, quick) for i in range(nah)], chunksize=1)
        w_async = pool.map_async(weight_task, w_tasks, chunksize=1)
        rel_async = pool.map_async(rel_task, rel_tasks, chunksize=4)
        acc = pool.map(accuracy_task, acc_tasks, chunksize=1)
        ah = ah_async.get()
        wres = w_async.get()
        rel = rel_async.get()
    elapsed = time.time() - t_start
    print(f"all done {elapsed:.0f} s", flush=True)

    run = {"mach": mach, "quick": quick, "elapsed": elapsed, "jobs": a.jobs, "seeds": seeds,
           "rel_seeds": rel_seeds}
    doc = [string.Template(INTRO.read_text()).substitute(provenance.fields()),
           results_doc(run, acc, ah, wres, rel)]
    doc += speed_memory_doc(speed, mem, load_before, load_after)

    # ---- 6
    doc += certainty_section()

    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(doc) + "\n")
    print(f"wrote {out} in {elapsed:.0f} s")


if __name__ == "__main__":
    main()
