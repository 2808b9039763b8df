#!/usr/bin/env python3
"""Real measured records and logger faults: writes docs/reports/real-data.md.

Usage (from the repository root, after building the pdtfit program):

    python3 tools/bench/real_data.py [--pdtfit PATH] [--jobs N] [--out FILE]

For each record of tests/data/real/ (the files as committed, read by the
program with the options that record needs), `pdtfit identify` fits a
FOPDT and a SOPDT with its defaults. Next to each, an output-error optimum
computed here with scipy on the same problem: the same samples (those the
reader found missing and those the identification left out, as its JSON
lists them), the same input before the record (u[0], or --u-before), the
same initial state (at rest; or, where the JSON says it was estimated,
the free response of the model's state fitted with the gain and offset),
the same output offset (fixed at the rest level where pdtfit's offset is
that level, else free). The reference separates the linear parameters
(gain, offset, initial state: least squares) from the nonlinear ones
(time constants or a, b and the dead time), evaluates a grid over the
dead time and the time scale, and polishes the six best grid points with
scipy.optimize.least_squares. Both answers are scored by the same
function: the mean square of the residual over the samples fitted, the
pdtfit model with its own printed offset. Target: pdtfit within 1 % of the
reference's cost, no record refused.

Then the faults of a logger (issue "Field data"), each put into the output
of every real record and of two simulated noisy records (a FOPDT and a
SOPDT): one historian marker, -9999, 9999, 32767, -32768, 65535 or 1e6, at
one of two positions, as a number the program is not told about, as the
same number declared with --bad-value, and as marker text (#N/A, NaN, an
empty cell, ERR, #VALUE!, Bad Input); a dropout of 10 samples to 0, as
numbers and as empty cells; and a marker in the input (#N/A, or -9999
declared). Each answer is compared with the clean record's
answer of the same model: within 2 % in K and 5 % in tau (FOPDT) or wn
(SOPDT) it is right; refused (no model) or with a flag the clean answer
does not have it is caught; anything else is silently wrong.

The prose of the report is tools/bench/real_data.md.in; this script fills in
its tables. Everything is deterministic: the same commit, machine and
versions give the same document.
"""
from __future__ import annotations

import argparse
import csv
import io
import json
import math
import multiprocessing as mp
import os
import pathlib
import platform
import string
import subprocess
import tempfile

import numpy as np
import scipy
import scipy.optimize as so

from pdtbench import benchlib as bl
from pdtbench.benchlib import ROOT, models

DATA = ROOT / "tests" / "data" / "real"
TEMPLATE = pathlib.Path(__file__).with_name("real_data.md.in")
OUT = ROOT / "docs" / "reports" / "real-data.md"

# name, file, u column, y column, program options, input before the record
# (None: u[0]), what the record is.
REAL = [
    ("gas_furnace", "gas_furnace.csv", "input_gas_rate", "co2", ["--fs", "%.17g" % (1.0 / 9.0)],
     None, "Box-Jenkins gas furnace (series J), 296 samples at 9 s"),
    ("tclab_step_run2", "tclab_step_run2.csv", "Q1", "T1", ["--u-before", "0"], 0.0,
     "TCLab heater 1 step to 50 % from the first row, 901 samples at about 1 s"),
]
MODELS = ("fopdt", "sopdt")
MARKER_VALUES = (-9999.0, 9999.0, 32767.0, -32768.0, 65535.0, 1e6)
MARKER_TEXTS = ("#N/A", "NaN", "", "ERR", "#VALUE!", "Bad Input")
POSITIONS = (0.3, 0.65)   # of the record's length
DROPOUT = 10
SIMULATED = [
    # name, model, K, (tau,) or (wn, zeta), Td, Ts, n, noise std / output span
    ("sim_fopdt", "fopdt", 1.5, (4.0,), 0.5, 0.1, 800, 0.01),
    ("sim_sopdt", "sopdt", 1.0, (0.8, 0.6), 0.5, 0.1, 800, 0.01),
]


# ------------------------------------------------------------ records

class Record:
    """One record as the program reads it: a CSV text, the options, and
    the u and y it holds (y NaN where a cell is missing)."""

    def __init__(self, name, text, options, u_before, what):
        self.name, self.text, self.options = name, text, list(options)
        self.u_before, self.what = u_before, what

    def columns(self):
        return self.options[self.options.index("--u") + 1], \
            self.options[self.options.index("--y") + 1]


def load_real(entry):
    name, fname, ucol, ycol, opts, u_before, what = entry
    # As committed, line ends and all (the TCLab file's are "\r\r\n").
    text = (DATA / fname).read_bytes().decode("utf-8")
    return Record(name, text, ["--u", ucol, "--y", ycol, *opts], u_before, what)


def simulated(entry):
    name, kind, K, shape, Td, Ts, n, rel = entry
    u = 50.0 + 0.0 * np.arange(n)
    rng = bl.Rng(20260 + n + len(name))
    k, level = n // 20, 1.0
    while k < n:
        hold = int(20 + 60 * rng.uniform())
        u[k:k + hold] = 50.0 + level * (5.0 + 5.0 * rng.uniform())
        level, k = -level, k + hold
    m = models.Fopdt(K, shape[0], Td) if kind == "fopdt" else \
        models.Sopdt(K * shape[0] ** 2, 2 * shape[1] * shape[0], shape[0] ** 2, Td)
    yc = bl.simulate(m, Ts, u - 50.0)
    y = 20.0 + yc + rel * float(np.ptp(yc)) * np.array(bl.Rng(77 + n).normal(n))
    t = np.arange(n) * Ts
    text = "t,u,y\n" + "".join(f"{a:.6f},{b:.10g},{c:.10g}\n" for a, b, c in zip(t, u, y))
    return Record(name, text, ["--u", "u", "--y", "y"], None,
                  f"simulated {kind.upper()}, {n} samples, noise {100 * rel:g} % of the span")


def read_columns(rec):
    """u, y of the record's text as floats (NaN where not a number)."""
    ucol, ycol = rec.columns()
    rows = [r for r in csv.reader(io.StringIO(rec.text.replace("\r", ""))) if r]
    head = [h.strip().lower() for h in rows[0]]
    iu, iy = head.index(ucol.lower()), head.index(ycol.lower())

    def num(s):
        try:
            return float(s)
        except ValueError:
            return math.nan
    body = rows[1:]
    return np.array([num(r[iu]) for r in body]), np.array([num(r[iy]) for r in body])


def with_fault(rec, rows_to_set, cell, declare=None, name="", column=1):
    """The record with the output cell (column 0: the input's) of the given
    data rows replaced."""
    col = rec.columns()[column]
    rows = [r for r in csv.reader(io.StringIO(rec.text.replace("\r", ""))) if r]
    iy = [h.strip().lower() for h in rows[0]].index(col.lower())
    for k in rows_to_set:
        rows[1 + k][iy] = cell
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    opts = rec.options + (["--bad-value", declare] if declare is not None else [])
    return Record(name, out.getvalue(), opts, rec.u_before, rec.what)


# ------------------------------------------------------------ pdtfit

def run_pdtfit(binary, rec, model):
    """(exit status, JSON or None, stderr) of `pdtfit identify` on rec."""
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write(rec.text)
        path = f.name
    try:
        res = subprocess.run([str(binary), "identify", "--model", model, *rec.options, path],
                             capture_output=True, text=True, timeout=300)
    finally:
        os.unlink(path)
    out = json.loads(res.stdout) if res.returncode in (0, 3) and res.stdout else None
    return res.returncode, out, res.stderr.strip().replace(path, rec.name + ".csv")


def model_of(j):
    return bl.model_from_json(j)[0]


def left_out(j, n):
    """The samples the answer was fitted without, as far as its JSON lists
    them: the reader's missing ones and the identification's exclusions."""
    mask = np.ones(n, bool)
    for key in ("missing", "excluded"):
        v = j.get(key)
        if isinstance(v, dict):
            mask[[i for i in v.get("first", []) if i < n]] = False
    return mask


def unlisted(j):
    """Samples the identification left out beyond those its JSON lists."""
    v = j.get("excluded")
    if not isinstance(v, dict):
        return 0
    return max(0, int(v.get("count", 0)) - len(v.get("first", [])))


def rest_level(u, y, u0):
    """The output's mean before the input first moves from u0, when that
    rest lasts n/40 samples or more (what --offset auto polishes on), else
    None."""
    moved = np.nonzero(u != u0)[0]
    k1 = int(moved[0]) if moved.size else u.size
    ok = np.isfinite(y[:k1])
    return float(np.mean(y[:k1][ok])) if k1 >= u.size / 40 and ok.any() else None


def initial_of(j):
    v = j.get("initial")
    return v if isinstance(v, str) else "rest"


# ------------------------------------------------------------ the reference

def free_columns(m, Ts, n, initial):
    """The free response of the model's state (initial 'estimate'): one
    column per state, from the poles of the lag."""
    if initial != "estimate":
        return []
    t = np.arange(n) * Ts
    if isinstance(m, models.Fopdt):
        return [np.exp(-t / m.tau)]
    disc = m.a * m.a - 4.0 * m.b
    if disc > 1e-12 * m.a * m.a:
        r = math.sqrt(disc)
        return [np.exp((-m.a + r) / 2 * t), np.exp((-m.a - r) / 2 * t)]
    if disc < -1e-12 * m.a * m.a:
        w = math.sqrt(-disc) / 2
        e = np.exp(-m.a / 2 * t)
        return [e * np.cos(w * t), e * np.sin(w * t)]
    e = np.exp(-m.a / 2 * t)
    return [e, t * e]


def linear_fit(resp, y, mask, columns, y0=None):
    """Least squares of y on the response (gain 1 in resp, or fixed when
    y0 is given) and the free columns and offset; (residual, coefficients)."""
    if y0 is None:
        A = np.column_stack([resp, np.ones(resp.size)] + columns)
        target = y
    else:
        if not columns:
            return y - y0 - resp, np.zeros(0)
        A = np.column_stack(columns)
        target = y - y0 - resp
    coef = np.linalg.lstsq(A[mask], target[mask], rcond=None)[0]
    return target - A @ coef, coef


def score(m, y0, rec_u, rec_y, Ts, u0, mask, initial):
    """The mean square residual of model m with offset y0 over the samples
    fitted (the initial state, if estimated, fitted)."""
    resp = bl.simulate(m, Ts, rec_u - u0)
    r, _ = linear_fit(resp, rec_y, mask, free_columns(m, Ts, rec_u.size, initial), y0)
    return float(np.mean(r[mask] ** 2))


class Reference:
    """The output-error optimum by variable projection (module docstring)."""

    def __init__(self, kind, u, y, Ts, u0, mask, initial, y0=None):
        self.kind, self.u, self.y, self.Ts, self.y0 = kind, u, y, Ts, y0
        self.du, self.mask, self.initial = u - u0, mask, initial
        self.n = u.size
        self.T = self.n * Ts
        if kind == "fopdt":
            self.lo = np.array([math.log(Ts / 4), 0.0])
            self.hi = np.array([math.log(2 * self.T), self.T / 3])
        else:
            # log a (1/a from Ts/8 to 2T), 1/zeta in [0, 5] (damping >= 0.2,
            # 0: integrating), Td
            self.lo = np.array([math.log(1.0 / (2 * self.T)), 0.0, 0.0])
            self.hi = np.array([math.log(8.0 / Ts), 5.0, self.T / 3])

    def unit_model(self, x):
        if self.kind == "fopdt":
            return models.Fopdt(1.0, math.exp(x[0]), x[1])
        a = math.exp(x[0])
        b = (a * x[1] / 2.0) ** 2
        return models.Sopdt(b + a / self.T, a, b, x[2])

    def resid(self, x):
        m = self.unit_model(x)
        resp = bl.simulate(m, self.Ts, self.du)
        cols = free_columns(m, self.Ts, self.n, self.initial)
        if self.y0 is None:
            r, coef = linear_fit(resp, self.y, self.mask, cols)
            return r[self.mask], coef
        # The offset fixed: the gain with the free columns.
        r, coef = linear_fit(np.zeros(self.n), self.y - self.y0, self.mask, [resp] + cols, 0.0)
        return r[self.mask], np.concatenate([coef[:1], [self.y0], coef[1:]])

    def grid(self):
        td = np.linspace(0.0, self.T / 3, 25)
        if self.kind == "fopdt":
            return [np.array([lt, d]) for lt in np.linspace(self.lo[0], self.hi[0], 16)
                    for d in td]
        return [np.array([la, iz, d]) for la in np.linspace(self.lo[0], self.hi[0], 12)
                for iz in (0.3, 0.8, 1.4, 2.0, 3.0, 4.5) for d in td]

    def fit(self, starts=()):
        """(model with its gain, offset, cost) of the best start: the six
        best grid points and the given starts, each polished."""
        scored = sorted((float(np.mean(self.resid(x)[0] ** 2)), i, x)
                        for i, x in enumerate(self.grid()))
        best = None
        for x0 in [x for _, _, x in scored[:6]] + [np.clip(s, self.lo, self.hi) for s in starts]:
            x0 = np.clip(x0, self.lo + 1e-9, self.hi - 1e-9)
            r = so.least_squares(lambda x: self.resid(x)[0], x0, bounds=(self.lo, self.hi),
                                 method="trf", x_scale="jac", xtol=1e-12, ftol=1e-12,
                                 gtol=1e-12, max_nfev=600)
            c = float(np.mean(r.fun ** 2))
            if best is None or c < best[0]:
                best = (c, r.x)
        c, x = best
        m = self.unit_model(x)
        _, coef = self.resid(x)
        g, off = coef[0], coef[1]
        if self.kind == "fopdt":
            return models.Fopdt(g, m.tau, m.Td), off, c
        return models.Sopdt(g * m.k, m.a, m.b, m.Td), off, c

    def start_of(self, m):
        """pdtfit's answer as a start of the polish."""
        if isinstance(m, models.Fopdt):
            return np.array([math.log(max(m.tau, 1e-9)), m.Td])
        iz = 2.0 * math.sqrt(max(m.b, 0.0)) / m.a if m.a > 0 else 0.0
        return np.array([math.log(max(m.a, 1e-12)), iz, m.Td])


def real_row(binary, rec, model):
    """pdtfit against the reference on one record and model."""
    status, j, err = run_pdtfit(binary, rec, model)
    row = {"record": rec.name, "model": model, "status": status, "error": err}
    if j is None:
        return row
    u, y = read_columns(rec)
    n = min(u.size, j["n"])
    u, y = u[:n], y[:n]
    u = hold_u(u)
    mask = left_out(j, n) & np.isfinite(y)
    initial = initial_of(j)
    u0 = rec.u_before if rec.u_before is not None else u[0]
    m = model_of(j)
    # The offset: the rest level where pdtfit's is that, else free.
    rest = rest_level(u, y, u0)
    fixed = rest is not None and abs(j["y0"] - rest) <= 1e-6 * max(1.0, abs(rest))
    ref = Reference(model, u, np.where(np.isfinite(y), y, 0.0), j["Ts"], u0, mask, initial,
                    y0=j["y0"] if fixed else None)
    mr, off, c_ref = ref.fit(starts=[ref.start_of(m)])
    _, _, c_own = ref.fit()
    c_pdt = score(m, j["y0"], u, np.where(np.isfinite(y), y, 0.0), j["Ts"], u0, mask, initial)
    row.update(json=j, ref=mr, ref_y0=off, c_ref=c_ref, c_own=c_own, c_pdt=c_pdt,
               ratio=c_pdt / c_ref,
               initial=initial, fitted=int(mask.sum()), n=n, unlisted=unlisted(j),
               offset="rest level" if fixed else "free")
    return row


def hold_u(u):
    """The reader's hold of a missing u (the u before; the first u read for
    the first ones)."""
    u = u.copy()
    ok = np.isfinite(u)
    first = u[np.argmax(ok)]
    for k in range(u.size):
        if not ok[k]:
            u[k] = u[k - 1] if k else first
    return u


# ------------------------------------------------------------ faults

def fault_cases(rec):
    """(label, kind, record) of every fault put into rec's output."""
    n = len(read_columns(rec)[1])
    out = []
    for p in POSITIONS:
        k = int(p * n)
        for v in MARKER_VALUES:
            cell = "%.10g" % v
            out.append((f"{cell} at {k}", "number", with_fault(rec, [k], cell, name=rec.name)))
            out.append((f"{cell} at {k}, --bad-value", "declared",
                        with_fault(rec, [k], cell, declare=cell, name=rec.name)))
        for t in MARKER_TEXTS:
            out.append((f"\"{t}\" at {k}", "text", with_fault(rec, [k], t, name=rec.name)))
        rows = list(range(k, k + DROPOUT))
        out.append((f"0 at {k}..{k + DROPOUT - 1}", "dropout",
                    with_fault(rec, rows, "0", name=rec.name)))
        out.append((f"empty at {k}..{k + DROPOUT - 1}", "dropout text",
                    with_fault(rec, rows, "", name=rec.name)))
        out.append((f"u \"#N/A\" at {k}", "u marker",
                    with_fault(rec, [k], "#N/A", name=rec.name, column=0)))
        out.append((f"u -9999 at {k}, --bad-value", "u marker",
                    with_fault(rec, [k], "-9999", declare="-9999", name=rec.name, column=0)))
    return out


def main_param(m):
    """K and the time scale compared: tau (FOPDT) or wn (SOPDT)."""
    if isinstance(m, models.Fopdt):
        return m.K, m.tau
    if m.b <= 0:
        return math.inf, 0.0
    return m.k / m.b, math.sqrt(m.b)


def verdict(clean, status, j, clean_flags=()):
    """'right', 'caught' or 'wrong' against the clean record's model: a
    refusal, or a flag the clean record's answer does not have, is a
    catch."""
    if j is None:
        return "caught"
    if set(j.get("flags", [])) - set(clean_flags):
        return "caught"
    K0, s0 = main_param(clean)
    K1, s1 = main_param(model_of(j))
    ok = abs(K1 / K0 - 1) <= 0.02 and abs(s1 / s0 - 1) <= 0.05
    return "right" if ok else "wrong"


def fault_task(args):
    binary, clean, clean_flags, model, label, kind, rec = args
    status, j, err = run_pdtfit(binary, rec, model)
    v = verdict(clean, status, j, clean_flags)
    K, s = main_param(model_of(j)) if j is not None else (math.nan, math.nan)
    return {"record": rec.name, "model": model, "label": label, "kind": kind, "status": status,
            "verdict": v, "K": K, "s": s, "clean": main_param(clean), "error": err.splitlines()[-1] if err else "",
            "flags": j.get("flags", []) if j else [], "clean_flags": list(clean_flags)}


# ------------------------------------------------------------ cut records

CUT_SHARE = 3  # the record cut a third of the way in


def cut_record(rec):
    """rec without its first third of rows (the header kept), and without
    --u-before: the input before the cut record is its own first row's."""
    lines = rec.text.split("\n")
    rows = [line for line in lines[1:] if line.strip()]
    text = "\n".join([lines[0]] + rows[len(rows) // CUT_SHARE:]) + "\n"
    opts = list(rec.options)
    if "--u-before" in opts:
        i = opts.index("--u-before")
        del opts[i:i + 2]
    return Record(rec.name + "_cut", text, opts, None, rec.what)


def fmt_main(j):
    """K, the time scale (tau or wn) and Td of an answer, or why none."""
    if j is None:
        return "refused"
    m = model_of(j)
    K, s = main_param(m)
    scale = f"tau {s:.4g} s" if isinstance(m, models.Fopdt) else f"wn {s:.4g} rad/s"
    return f"K {K:.4g}, {scale}, Td {m.Td:.4g} s"


def cut_rows(binary):
    """The whole record's answer against the cut record's, with --initial
    auto (the default) and estimate."""
    rows = []
    for entry in REAL:
        rec = load_real(entry)
        cut = cut_record(rec)
        for model in MODELS:
            _, whole, _ = run_pdtfit(binary, rec, model)
            st_a, auto, err_a = run_pdtfit(binary, cut, model)
            est_rec = Record(cut.name, cut.text, cut.options + ["--initial", "estimate"], None,
                             cut.what)
            st_e, est, err_e = run_pdtfit(binary, est_rec, model)
            rows.append({"record": rec.name, "model": model, "whole": whole, "auto": auto,
                         "est": est, "err_a": err_a, "err_e": err_e})
    return rows


def cut_table(rows):
    out = ["| record | model | whole record | cut, `--initial auto` | initial | flags "
           "| cut, `--initial estimate` | K cut / K whole (estimate) |",
           "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        a, e, w = r["auto"], r["est"], r["whole"]
        why = "" if a is not None else ": " + (r["err_a"].splitlines()[-1] if r["err_a"] else "")
        ratio = "-"
        if e is not None and w is not None:
            ratio = f"{main_param(model_of(e))[0] / main_param(model_of(w))[0]:.4f}"
        out.append(f"| {r['record']} | {r['model']} | {fmt_main(w)} | {fmt_main(a)}{why} "
                   f"| {initial_of(a) if a else '-'} | {', '.join(a['flags']) if a else '-'} "
                   f"| {fmt_main(e)} | {ratio} |")
    return "\n".join(out)


# ------------------------------------------------------------ report

def machine():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores; Python {platform.python_version()}, numpy " \
           f"{np.__version__}, scipy {scipy.__version__}; {platform.platform()}"


def commit():
    r = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short=12", "HEAD"],
                       capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    return r.stdout.strip() + (" (with uncommitted changes)" if dirty else "")


def fmt_model(m, y0=None):
    if isinstance(m, models.Fopdt):
        s = f"K {m.K:.4g}, tau {m.tau:.4g} s, Td {m.Td:.4g} s"
    else:
        K, wn = main_param(m)
        zeta = m.a / (2 * wn) if wn > 0 else math.inf
        s = f"K {K:.4g}, wn {wn:.4g} rad/s, zeta {zeta:.3g}, Td {m.Td:.4g} s"
    return s + (f", y0 {y0:.4g}" if y0 is not None else "")


def real_table(rows):
    out = ["| record | model | pdtfit | reference (scipy) | samples fitted | offset "
           "| initial state | cost pdtfit | cost reference | its own starts | ratio |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "json" not in r:
            out.append(f"| {r['record']} | {r['model']} | refused (exit {r['status']}): "
                       f"{r['error'].splitlines()[-1] if r['error'] else ''} | | | | | | | | |")
            continue
        j = r["json"]
        flags = f" flags {', '.join(j['flags'])}" if j.get("flags") else ""
        out.append(f"| {r['record']} | {r['model']} | {fmt_model(model_of(j), j['y0'])}{flags} "
                   f"| {fmt_model(r['ref'], r['ref_y0'])} | {r['fitted']} of {r['n']}"
                   + (f" ({r['unlisted']} more left out, unlisted)" if r['unlisted'] else "") +
                   " "
                   f"| {r['offset']} | {r['initial']} | {r['c_pdt']:.6g} | {r['c_ref']:.6g} "
                   f"| {r['c_own']:.6g} "
                   f"| {r['ratio']:.5f} |")
    return "\n".join(out)


def fault_tables(results):
    kinds = ("number", "declared", "text", "dropout", "dropout text", "u marker")
    keys = sorted({(r["record"], r["model"]) for r in results}, key=lambda k: (k[0], k[1]))
    out = ["| record | model | " + " | ".join(kinds) + " | right | caught | silently wrong |",
           "|---|---|" + "---|" * (len(kinds) + 3)]
    for rec, model in keys:
        sub = [r for r in results if (r["record"], r["model"]) == (rec, model)]
        cells = []
        for k in kinds:
            s = [r for r in sub if r["kind"] == k]
            cells.append(f"{sum(r['verdict'] == 'right' for r in s)}/{len(s)}")
        tot = {v: sum(r["verdict"] == v for r in sub) for v in ("right", "caught", "wrong")}
        out.append(f"| {rec} | {model} | " + " | ".join(cells) +
                   f" | {tot['right']} | {tot['caught']} | {tot['wrong']} |")
    return "\n".join(out)


def fault_list(results, which):
    sub = [r for r in results if r["verdict"] == which]
    if not sub:
        return "None."
    out = ["| record | model | fault | exit | K (clean) | tau or wn (clean) | flags or message |",
           "|---|---|---|---|---|---|---|"]
    for r in sub:
        why = ", ".join(r["flags"]) if r["flags"] else r["error"].replace("|", "/")
        if r["flags"] and set(r["flags"]) <= set(r["clean_flags"]):
            why += " (as on the clean record)"
        out.append(f"| {r['record']} | {r['model']} | {r['label']} | {r['status']} "
                   f"| {r['K']:.4g} ({r['clean'][0]:.4g}) | {r['s']:.4g} ({r['clean'][1]:.4g}) "
                   f"| {why} |")
    return "\n".join(out)


def summary(rows, results):
    ok = [r for r in rows if "json" in r]
    worst = max((r["ratio"] for r in ok), default=math.nan)
    n = len(results)
    right = sum(r["verdict"] == "right" for r in results)
    caught = sum(r["verdict"] == "caught" for r in results)
    wrong = n - right - caught
    return {"n_real": len(rows), "refused": len(rows) - len(ok), "worst_ratio": f"{worst:.5f}",
            "within": sum(r["ratio"] <= 1.01 for r in ok), "n_faults": n, "right": right,
            "right_pct": f"{100.0 * right / n:.1f}" if n else "0", "caught": caught,
            "wrong": wrong}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pdtfit", default=str(ROOT / "build" / "dev" / "tools" / "pdtfit"),
                    help="the pdtfit program (default build/dev/tools/pdtfit)")
    ap.add_argument("--jobs", type=int, default=2, help="processes for the fault cases")
    ap.add_argument("--out", default=str(OUT), help="the report (default %(default)s)")
    args = ap.parse_args(argv)
    binary = pathlib.Path(args.pdtfit)
    recs = [load_real(e) for e in REAL] + [simulated(e) for e in SIMULATED]
    rows = [real_row(binary, rec, m) for rec in recs[:len(REAL)] for m in MODELS]
    tasks = []
    for rec in recs:
        for model in MODELS:
            status, j, err = run_pdtfit(binary, rec, model)
            if j is None:
                continue
            for label, kind, frec in fault_cases(rec):
                tasks.append((binary, model_of(j), j.get("flags", []), model, label, kind, frec))
    with mp.Pool(args.jobs) as pool:
        results = pool.map(fault_task, tasks)
    fill = {"commit": commit(), "machine": machine(), "real_table": real_table(rows),
            "fault_table": fault_tables(results), "wrong_list": fault_list(results, "wrong"),
            "caught_list": fault_list(results, "caught"),
            "cut_table": cut_table(cut_rows(binary)),
            "records": "\n".join(f"- `{r.name}`: {r.what}; options `{' '.join(r.options)}`"
                                 for r in recs)}
    fill.update(summary(rows, results))
    text = string.Template(TEMPLATE.read_text()).substitute(fill)
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
