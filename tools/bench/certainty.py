#!/usr/bin/env python3
"""Certainty battery of pdtfit's identification: writes docs/reports/certainty.md.

Usage (from the repository root):

    python3 tools/bench/certainty.py                  # 1000 seeds per case
    python3 tools/bench/certainty.py --smoke          # 20 seeds, a few sets,
                                                      # into build/bench/certainty-smoke.md
    options: --seeds N (closed-loop and hard cases), --set-seeds N (the other
    benchmark sets), --jobs N (worker processes, default: all cores),
    --out FILE, --json FILE (every run's verdict, one line each, written as
    the batches finish), --cases REGEX (only the cases whose label matches),
    --reference FILE (a previous run's --json: its reference optimum of each
    record instead of the nine-start fit and the grid search, which take
    most of the time; the reference is then the least of it and this run's
    polishes, so a verdict can only be stricter)
    --answers FILE (only the driver's answers, no reference and no
    document: minutes instead of hours), --compare OLD NEW (two --answers
    files of two versions, record by record: when every answer is the same,
    so is every verdict of the document)
    environment: PDT_CERTAINTY_DRIVER, a driver built elsewhere to use
    instead of building build/bench (to compare two versions of the library)

It builds tools/bench/certainty.c (the driver: closed-loop records of known
plants, pdt_identify with the library's defaults) into build/bench, then,
for every case and seed, one record (the seed sets the noise) identified
once (the same seed is the search's seed), and judges each answer against a
reference optimum of the same criterion found independently of pdtfit:

- the cases: relay (asymmetric, and symmetric around the rest point) and
  PI closed loops of FOPDT, SOPDT and integrating plants (certainty.c), the three hard cases of the reliability section of
  docs/reports/benchmarks.md, and every accuracy set of run_ident_bench.py, their
  records made by benchlib exactly as there (with the noise seed varying);
- the reference optimum: the least cost of fastref.FastRef's nine-start
  output-error fit, its dense dead-time grid with polish, its polish from
  the true parameters and its polish from pdtfit's answer (a better optimum
  near pdtfit's answer still counts against pdtfit's answer);
- a run is *wrong* when its cost exceeds the reference optimum by more than
  1 %; refused (a status other than OK) and flagged (a nonzero result flag,
  when the library has them) runs are counted apart.
"""
from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import pathlib
import re
import string
import subprocess
import sys
import tempfile
import time

import numpy as np

from pdtbench import benchlib as bl
from pdtbench import coarse_bench as cb
from pdtbench import fastref
from pdtbench import run_ident_bench as rb
from pdtbench.benchlib import ROOT, models
from pdtsupport import provenance, template

BUILD = ROOT / "build" / "bench"
# PDT_CERTAINTY_DRIVER: a driver built elsewhere (another build of the
# library), used as it is instead of building build/bench.
DRIVER = pathlib.Path(os.environ.get("PDT_CERTAINTY_DRIVER",
                                     BUILD / "tools" / "bench" / "pdt_certainty"))
WRONG = 1.01          # cost ratio to the reference optimum that counts as wrong
FAR = 1.1             # ... and as clearly another basin rather than a short polish
BATCH = 25            # seeds per driver call


def build():
    if "PDT_CERTAINTY_DRIVER" in os.environ:
        return
    cfg = ["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
           "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_C_FLAGS_RELEASE=-O2 -DNDEBUG",
           "-DPDT_BUILD_TESTS=OFF", "-DPDT_REAL_DOUBLE=OFF"]
    subprocess.run(cfg, check=True, stdout=subprocess.DEVNULL)
    r = subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdt_certainty"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("build failed:\n" + r.stdout[-3000:] + r.stderr[-3000:])


# ------------------------------------------------------------------ cases

def driver_cases():
    out = subprocess.run([str(DRIVER), "cases"], capture_output=True, text=True, check=True)
    return [json.loads(line) for line in out.stdout.splitlines()]


def truth_model(c):
    """pdtref model of a driver case's plant."""
    p = c["p"]
    if c["plant"] == "fopdt":
        return models.Fopdt(p[0], p[1], c["Td"])
    if c["plant"] == "sopdt":
        return models.sopdt_from_natural(p[0], p[1], p[2], c["Td"])
    return models.sopdt_from_integ(p[0], p[1], c["Td"])


def bench_cases(smoke):
    """The reliability section's hard cases (SNR 30 dB) and the accuracy
    sets of run_ident_bench.py: (label, truth index or truth, excitation,
    snr, quantised, hard)."""
    out = []
    for name, truth, exc in rb.rel_cases(False):
        out.append((f"benchmark hard case: {name}, 30 dB", truth, exc, 30, False, True))
    T = rb.truths()
    sets = rb.accuracy_sets(False)
    if smoke:
        sets = [s for s in sets if s[1] == "relay" and s[2] == 20][:2]
    for ti, exc, snr, quant in sets:
        out.append((f"benchmark set {T[ti].name}: {rb.set_label((ti, exc, snr, quant))}",
                    T[ti], exc, snr, quant, False))
    return out


# Open-loop records under much noise and a fast input (coarse_bench.py's
# records): (model, tau in samples, input, SNR, samples). Its "prbs" is a
# square wave flipping after every bit of a third of the time constant:
# the cost repeats along the dead time with its period, and under 10 dB
# one search ends a period off several times in a hundred; the rows with
# the most flags in the coarse benchmark, and their neighbours. The last
# record is long: its dead-time range (a third of it) is scored by the
# profile every 11 samples, and the input's basins lie 2 samples apart.
NOISY = (("fopdt", 4.0, "prbs", 10, cb.N), ("fopdt", 12.0, "prbs", 10, cb.N),
         ("fopdt", 40.0, "prbs", 10, cb.N), ("sopdt", 4.0, "prbs", 30, cb.N),
         ("sopdt", 12.0, "prbs", 10, cb.N), ("sopdt", 4.0, "prbs", 10, 4000))


def noisy_label(c):
    m, tau, _, snr, n = c
    return (f"{m.upper()}, tau {tau:g} samples, square wave of bits tau / 3, {snr} dB" +
            ("" if n == cb.N else f", {n} samples"))


def noisy_truth(c):
    """The plant of coarse_bench.record in pdtref's form."""
    m, tau = c[0], c[1]
    Td = round((0.5 * tau + 2.3) * 20) / 20 * cb.TS
    if m == "fopdt":
        return models.Fopdt(1.5, tau * cb.TS, Td)
    t1, t2 = tau * cb.TS, tau * cb.TS / 3
    return models.Sopdt(1.5 / (t1 * t2), (t1 + t2) / (t1 * t2), 1 / (t1 * t2), Td)


def model_of_line(j):
    if j["model"] == "fopdt":
        return models.Fopdt(j["K"], j["tau"], j["Td"])
    return models.Sopdt(j["k"], j["a"], j["b"], j["Td"])


def describe(m):
    if isinstance(m, models.Fopdt):
        return f"FOPDT K {m.K:.3g}, tau {m.tau:.3g}, Td {m.Td:.3g}"
    if m.b <= 0:
        return f"integrator Ki {m.k / m.a:.3g}, T {1 / m.a:.3g}, Td {m.Td:.3g}"
    n = models.to_natural(m)
    return f"SOPDT K {n.K:.3g}, wn {n.wn:.3g}, zeta {n.zeta:.3g}, Td {m.Td:.3g}"


# --reference: a previous run's verdicts by (kind, case, seed). Set before
# the worker processes fork, which inherit it.
CACHE: dict = {}
# --answers: the driver's answers only, no reference optimum and no verdict
# (set before the workers fork, as CACHE).
ANSWERS_ONLY = False


def judge(u, y, Ts, kind, truth, line, key=None):
    """One run's verdict: the driver's line plus the reference optimum and
    the cost ratio. With a previous run's verdict of the same record (key
    in CACHE), its reference optimum stands for the nine-start fit and the
    grid search (the records are the same, seed for seed): the reference
    is then the least of it and this run's polishes, never above what the
    full search would give."""
    if ANSWERS_ONLY:
        return {k: v for k, v in line.items() if k != "seconds"}
    out = {"seed": line["seed"], "status": line["status"],
           "evaluations": line.get("evaluations"), "seconds": line.get("seconds"),
           "coarse": line.get("coarse")}
    if line["status"] != 0:
        out["verdict"] = "refused"
        out["status_name"] = line.get("status_name")
        return out
    out["flags"] = line.get("flags", 0)
    ref = fastref.FastRef(u, y, Ts, kind)
    m = model_of_line(line)
    c_p = ref.cost_of(m)
    old = CACHE.get(key)
    if old is not None and "ref" in old:
        c9 = old.get("ref9", math.inf)
        cg = old.get("refgrid", math.inf)
        c_prev = old["ref"]
    else:
        c9, _ = ref.fit()
        cg, _ = ref.grid_fit(ntd=96)
        c_prev = math.inf
    c_t, _ = ref.polish(ref.x_of(truth))
    c_pp, _ = ref.polish(ref.x_of(m))
    c_ref = min(c9, cg, c_t, c_pp, c_p, c_prev)
    ratio = c_p / c_ref if c_ref > 0 else 1.0
    if math.isinf(c9):
        # A reference run that did not keep the two searches' costs: its
        # counts of their misses stand.
        missed9, missed = old.get("ref9_missed", False), old.get("search_missed", False)
    else:
        missed9, missed = c9 > WRONG * c_ref, min(c9, cg) > WRONG * c_ref
    out.update({"cost": c_p, "ref": c_ref, "ratio": ratio, "ref9": c9, "refgrid": cg,
                "ref9_missed": bool(missed9), "search_missed": bool(missed),
                "fit": line.get("fit"), "model": describe(m)})
    wrong = not (ratio <= WRONG)
    out["verdict"] = ("flagged-" if out["flags"] else "") + ("wrong" if wrong else "right")
    return out


def closed_task(args):
    ci, s0, count = args
    c = driver_cases()[ci]
    n = c["n"]
    with tempfile.NamedTemporaryFile(suffix=".bin", delete=False) as f:
        dump = f.name
    try:
        res = subprocess.run([str(DRIVER), "run", str(ci), str(s0), str(count), dump],
                             capture_output=True, text=True, check=True)
        recs = np.fromfile(dump, dtype=np.float64).reshape(count, 3, n)
    finally:
        os.unlink(dump)
    lines = [json.loads(x) for x in res.stdout.splitlines()]
    truth = truth_model(c)
    return [("closed", ci, judge(recs[j, 0], recs[j, 1], c["Ts"], c["model"], truth, lines[j],
                                 ("closed", ci, lines[j]["seed"])))
            for j in range(count)]


def bench_task(args):
    bi, s0, count, smoke = args
    label, truth, exc, snr, quant, hard = bench_cases(smoke)[bi]
    Ts = rb.record_ts(truth)
    kind = rb.model_name(truth)
    recs = [bl.make_record(truth, exc, rb.N_REC, Ts, snr, quant, s)[:2]
            for s in range(s0, s0 + count)]
    with tempfile.NamedTemporaryFile(suffix=".bin", delete=False) as f:
        path = f.name
        for u, y in recs:
            f.write(np.concatenate([u, y]).astype("<f8").tobytes())
    try:
        res = subprocess.run([str(DRIVER), "file", path, str(rb.N_REC), f"{Ts:.17g}", kind,
                              str(s0)], capture_output=True, text=True, check=True)
    finally:
        os.unlink(path)
    lines = [json.loads(x) for x in res.stdout.splitlines()]
    return [("bench", bi, judge(u, y, Ts, kind, truth.model(), line, ("bench", bi, line["seed"])))
            for (u, y), line in zip(recs, lines)]


def noisy_task(args):
    ni, s0, count = args
    c = NOISY[ni]
    recs = [cb.record(c[0], c[1], c[2], c[3], s, c[4]) for s in range(s0, s0 + count)]
    with tempfile.NamedTemporaryFile(suffix=".bin", delete=False) as f:
        path = f.name
        for u, y in recs:
            f.write(np.concatenate([u, y]).astype("<f8").tobytes())
    try:
        res = subprocess.run([str(DRIVER), "file", path, str(c[4]), f"{cb.TS:.17g}", c[0],
                              str(s0)], capture_output=True, text=True, check=True)
    finally:
        os.unlink(path)
    lines = [json.loads(x) for x in res.stdout.splitlines()]
    truth = noisy_truth(c)
    return [("noisy", ni, judge(u, y, cb.TS, c[0], truth, line, ("noisy", ni, line["seed"])))
            for (u, y), line in zip(recs, lines)]


def run_task(t):
    if t[0] == "closed":
        return closed_task(t[1:])
    return noisy_task(t[1:]) if t[0] == "noisy" else bench_task(t[1:])


def batches(n_seeds):
    return [(s, min(BATCH, n_seeds + 1 - s)) for s in range(1, n_seeds + 1, BATCH)]


# ------------------------------------------------------------------ report

def summarise(rows):
    v = [r["verdict"] for r in rows]
    ev = [r["evaluations"] for r in rows if r.get("evaluations")]
    co = [r["coarse"] for r in rows if r.get("coarse")]
    return {"n": len(rows), "right": v.count("right"), "wrong": v.count("wrong"),
            "far": sum(1 for r in rows if r["verdict"] == "wrong" and r["ratio"] > FAR),
            "flagged_right": v.count("flagged-right"), "flagged_wrong": v.count("flagged-wrong"),
            "refused": v.count("refused"),
            "ref9_missed": sum(1 for r in rows if r.get("ref9_missed")),
            "search_missed": sum(1 for r in rows if r.get("search_missed")),
            "ev_med": int(np.median(ev)) if ev else 0,
            "coarse_med": int(np.median(co)) if co else 0,
            "whole": sum(1 for d in co if d == 1),
            "worst": max((r["ratio"] for r in rows if "ratio" in r), default=math.nan)}


def table(groups):
    lines = ["| case | seeds | OK, right | **OK, wrong** (of which cost > 1.1 x) | "
             "flagged, right | flagged, wrong | "
             "refused | worst cost ratio | evaluations median | coarse D median / whole | "
             "reference: 9 starts / both searches missed |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    tot = {"n": 0, "wrong": 0, "far": 0}
    for label, rows in groups:
        s = summarise(rows)
        for k in tot:
            tot[k] += s[k]
        worst = "-" if math.isnan(s["worst"]) else f"{s['worst']:.3g}"
        lines.append(f"| {label} | {s['n']} | {s['right']} | **{s['wrong']}** ({s['far']}) | "
                     f"{s['flagged_right']} | {s['flagged_wrong']} | {s['refused']} | "
                     f"{worst} | {s['ev_med']} | {s['coarse_med'] or '-'} / {s['whole']} | "
                     f"{s['ref9_missed']} / {s['search_missed']} |")
    return lines, tot


def examples(groups, limit=12):
    out = []
    for label, rows in groups:
        for r in rows:
            if r["verdict"] == "wrong" and len(out) < limit:
                out.append(f"- {label}, seed {r['seed']}: {r['model']}; cost "
                           f"{r['ratio']:.3g} x the optimum, fit {r['fit']:.1f} %, "
                           f"{r['evaluations']} evaluations")
    return out


# The report's introduction: what is measured and how (string.Template, ${n}
# the closed-loop records' length).
INTRO = pathlib.Path(__file__).with_name("certainty.md.in")
# The Run and Summary sections of the report (parts of pdtsupport.template.parts).
RUN = pathlib.Path(__file__).with_name("certainty_run.md.in")
# The report of --compare (string.Template).
COMPARE = pathlib.Path(__file__).with_name("certainty_compare.md.in")


def run_doc(parts, run, mach):
    """The report's Run section: the command, the machine and how long it ran."""
    if run.get("parts"):
        duration = parts["in_parts"].substitute(jobs=run["jobs"], parts="; ".join(
            parts["part"].substitute(
                minutes=f"{p['elapsed'] / 60:.1f}",
                cases=parts["part_cases"].substitute(cases=p["cases"]) if p.get("cases") else "")
            for p in run["parts"]))
    elif run["elapsed"] is None:
        duration = parts["interrupted"].substitute()
    else:
        duration = parts["elapsed"].substitute(
            minutes=f"{run['elapsed'] / 60:.1f}", jobs=run["jobs"],
            resumed=parts["resumed"].substitute() if run.get("resumed") else "")
    return parts["run"].substitute(
        smoke=" --smoke" if run["smoke"] else "", seeds=run["seeds"], set_seeds=run["set_seeds"],
        reference_flag=" --reference FILE" if run.get("reference") else "",
        reference_note=parts["reference_note"].substitute() if run.get("reference") else "",
        duration=duration, **mach)


def summary_doc(parts, groups):
    """The report's Summary: the totals, then each kind of case's table."""
    values = {}
    for kind, gs in groups.items():
        lines, tot = table(gs)
        values.update({f"{kind}_{k}": v for k, v in tot.items()})
        values[f"{kind}_table"] = "\n".join(lines)
    _, tot_all = table([g for gs in groups.values() for g in gs])
    return parts["summary"].substitute(values, **tot_all,
                                       cases=sum(len(gs) for gs in groups.values()))


def write_doc(out, results, cases, bcs, run):
    """docs/reports/certainty.md from the verdicts; run: seeds, set_seeds, smoke,
    jobs, elapsed (s)."""
    def rows_of(kind, i):
        return sorted((r for k, j, r in results if k == kind and j == i), key=lambda r: r["seed"])

    closed = [(c["name"], rows_of("closed", i)) for i, c in enumerate(cases)]
    hard = [(bc[0], rows_of("bench", i)) for i, bc in enumerate(bcs) if bc[5]]
    noisy = [(noisy_label(c), rows_of("noisy", i)) for i, c in enumerate(NOISY)]
    sets = [(bc[0], rows_of("bench", i)) for i, bc in enumerate(bcs) if not bc[5]]
    # A run limited by --cases leaves out the groups it did not run.
    closed, hard, noisy, sets = ([g for g in gs if g[1]] for gs in (closed, hard, noisy, sets))

    parts = template.parts(RUN)
    doc = [string.Template(INTRO.read_text()).substitute(n=str(cases[0]["n"]),
                                                         **provenance.fields()),
           run_doc(parts, run, rb.machine()),
           summary_doc(parts, {"closed": closed, "hard": hard, "noisy": noisy, "sets": sets})]
    ex = examples(closed + hard + noisy + sets)
    if ex:
        doc.append(parts["examples"].substitute(examples="\n".join(ex)))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(doc) + "\n")


def compare_answers(old_path, new_path, out=None, names=None):
    """Record by record, the answers of two --answers runs (two versions of
    the library on the same records): prints the count of equal answers,
    the records only one run has (a run cut short), and each record whose
    status, flags, evaluations, model or cost differ; with out, writes the
    report (certainty_compare.md.in), names saying what each run was.
    Returns 1 if any differs or is missing from one run."""
    def load(path):
        recs = {}
        for text in open(path):
            j = json.loads(text)
            if j.get("kind") != "meta":
                recs[(j.pop("kind"), j.pop("case"), j["seed"])] = j
        return recs
    old, new = load(old_path), load(new_path)
    both = sorted(set(old) & set(new), key=str)
    alone = len(set(old) ^ set(new))
    same = [k for k in both if old[k] == new[k]]
    differ = [f"{k}: {old[k]} -> {new[k]}" for k in both if old[k] != new[k]]
    print(f"{len(same)} of {len(both)} records of both runs give the same answer; "
          f"{alone} records are in one run only")
    print("\n".join(differ))
    if out:
        kinds = sorted({k[0] for k in both})
        label = {"closed": "closed-loop cases", "noisy": "noisy records under a fast square wave",
                 "bench": "the benchmark's hard cases and accuracy sets"}
        rows = [f"| {label.get(kind, kind)} | {sum(k[0] == kind for k in both)} | "
                f"{sum(k[0] == kind for k in same)} |" for kind in kinds]
        names = names or [old_path, new_path]
        text = string.Template(COMPARE.read_text()).substitute(
            machine=provenance.machine(), old=names[0], new=names[1], same=len(same),
            both=len(both), alone=alone, rows="\n".join(rows),
            differ=("\nRecords whose answer differs:\n\n" +
                    "\n".join(f"- {d}" for d in differ) + "\n") if differ else "")
        pathlib.Path(out).write_text(text)
        print(f"wrote {out}")
    return 0 if len(same) == len(both) and alone == 0 else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=1000)
    ap.add_argument("--set-seeds", type=int, default=None,
                    help="seeds of the accuracy sets (default: --seeds)")
    ap.add_argument("--smoke", action="store_true")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--cases", metavar="REGEX",
                    help="only the cases whose label matches (the document then covers "
                         "those alone)")
    ap.add_argument("--reference", metavar="FILE", action="append", default=[],
                    help="a previous run's --json (repeatable): its reference optimum of "
                         "each record stands for the nine-start fit and the grid search, "
                         "which take most of the time; the verdicts can only be stricter")
    ap.add_argument("--out")
    ap.add_argument("--json")
    ap.add_argument("--resume", metavar="FILE",
                    help="keep the verdicts an interrupted run saved with --json and run "
                         "only the batches it did not finish (same seeds options)")
    ap.add_argument("--from-json", metavar="FILE", action="append", default=[],
                    help="write the document from the verdicts a run saved with --json "
                         "(repeatable: runs of parts of the battery on the same code, such "
                         "as a run limited by --cases)")
    ap.add_argument("--answers", metavar="FILE",
                    help="write only the driver's answers (status, flags, evaluations, "
                         "model, cost), one line per record, without the reference optimum "
                         "or the document: a fast run whose file --compare sets beside "
                         "another version's")
    ap.add_argument("--compare", nargs=2, metavar=("OLD", "NEW"),
                    help="compare two --answers files record by record and list the "
                         "records whose answer differs (exit 1 if any does); with --out, "
                         "write the report (docs/reports/certainty-compare.md)")
    ap.add_argument("--names", nargs=2, metavar=("OLD", "NEW"),
                    help="with --compare: what each run was (commit, build), for the report")
    a = ap.parse_args()
    if a.compare:
        sys.exit(compare_answers(*a.compare, out=a.out, names=a.names))
    if a.answers:
        global ANSWERS_ONLY
        ANSWERS_ONLY = True
        a.json = a.answers
    seeds = 20 if a.smoke else a.seeds
    set_seeds = seeds if a.set_seeds is None else a.set_seeds
    if a.smoke:
        set_seeds = min(set_seeds, 10)
    out = pathlib.Path(a.out) if a.out else (
        BUILD / "certainty-smoke.md" if a.smoke else ROOT / "docs" / "reports" / "certainty.md")
    t_start = time.time()
    for path in a.reference:
        for line in open(path):
            j = json.loads(line)
            if j.get("kind") != "meta":
                CACHE[(j["kind"], j["case"], j["seed"])] = j
    build()
    cases = driver_cases()
    bcs = bench_cases(a.smoke)
    if a.from_json:
        results, metas = [], []
        for path in a.from_json:
            for line in open(path):
                j = json.loads(line)
                kind = j.pop("kind")
                if kind == "meta":
                    metas.append(j)
                else:
                    results.append((kind, j.pop("case"), j))
        run = metas[0] if metas else None
        if len(metas) > 1:
            run["parts"] = metas
        if run is None:     # an interrupted run: the counts of what it finished
            run = {"seeds": seeds, "set_seeds": set_seeds, "smoke": a.smoke,
                   "jobs": a.jobs, "elapsed": None}
        write_doc(out, results, cases, bcs, run)
        print(f"wrote {out}")
        return
    # Round-robin over the cases, batch by batch, the closed-loop and hard
    # cases first: a run cut short still has every case at about the same
    # number of seeds.
    queues = [[("closed", ci, s0, cnt) for s0, cnt in batches(seeds)]
              for ci in range(len(cases))]
    queues += [[("bench", bi, s0, cnt, a.smoke) for s0, cnt in batches(seeds)]
               for bi, bc in enumerate(bcs) if bc[5]]
    queues += [[("noisy", ni, s0, cnt) for s0, cnt in batches(seeds)]
               for ni in range(len(NOISY) if not a.smoke else 1)]
    tasks = [q[b] for b in range(max(len(q) for q in queues)) for q in queues if b < len(q)]
    for bi, bc in enumerate(bcs):
        if not bc[5]:
            tasks += [("bench", bi, s0, cnt, a.smoke) for s0, cnt in batches(set_seeds)]
    if a.cases:
        labels = {"closed": [c["name"] for c in cases], "bench": [bc[0] for bc in bcs],
                  "noisy": [noisy_label(c) for c in NOISY]}
        tasks = [t for t in tasks if re.search(a.cases, labels[t[0]][t[1]])]
        if not tasks:
            sys.exit(f"no case matches {a.cases!r}")
    results = []
    if a.resume:    # keep the verdicts of an interrupted run, do the rest
        for line in open(a.resume):
            j = json.loads(line)
            kind = j.pop("kind")
            if kind != "meta":
                results.append((kind, j.pop("case"), j))
        have = {(k, i, r["seed"]) for k, i, r in results}
        tasks = [t for t in tasks if (t[0], t[1], t[2]) not in have]
        print(f"resuming: {len(results)} verdicts kept, {len(tasks)} batches to run", flush=True)
    done = 0
    jf = open(a.json, "a" if a.resume and a.resume == a.json else "w") if a.json else None
    with mp.Pool(a.jobs) as pool:
        for rs in pool.imap_unordered(run_task, tasks, chunksize=1):
            results += rs
            done += 1
            if jf:
                for k, i, r in rs:
                    jf.write(json.dumps({"kind": k, "case": i, **r}) + "\n")
                jf.flush()
            if done % 20 == 0 or done == len(tasks):
                print(f"{done}/{len(tasks)} batches, {time.time() - t_start:.0f} s", flush=True)
    elapsed = time.time() - t_start
    run = {"seeds": seeds, "set_seeds": set_seeds, "smoke": a.smoke, "jobs": a.jobs,
           "elapsed": elapsed, "resumed": bool(a.resume), "reference": bool(a.reference),
           "cases": a.cases}
    if jf:
        jf.write(json.dumps({"kind": "meta", **run}) + "\n")
        jf.close()
    if a.answers:
        print(f"wrote {len(results)} answers to {a.answers} in {elapsed:.0f} s")
        return
    write_doc(out, results, cases, bcs, run)
    print(f"wrote {out} in {elapsed:.0f} s")


if __name__ == "__main__":
    main()
