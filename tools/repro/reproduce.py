#!/usr/bin/env python3
"""Reproduces Tables 1-3 of Yang and Seested (2013) with the pdtfit library
and writes docs/reports/paper-reproduction.md with its figures docs/img/repro-*.png.

Usage: python3 tools/repro/reproduce.py

Builds the command line into build/release (Release, float) when needed,
regenerates the demo's records of system (17) as CSV files in a temporary
folder, runs every method through `pdtfit identify` and `pdtfit reduce`,
judges every model, the paper's and ours, against the true (17), and writes
the document. Deterministic: the same checkout gives the same files.
"""
import argparse
import json
import pathlib
import subprocess
import tempfile

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]

from pdtrepro import bootstrap
from pdtsupport import provenance
from pdtrepro import system17 as s17
from pdtrepro.system17 import Model

BUILD = ROOT / "build" / "release"
BIN = BUILD / "tools" / "pdtfit"
DOC = ROOT / "docs" / "reports" / "paper-reproduction.md"
IMG = ROOT / "docs" / "img"

TD_MAX = 5.0  # dead-time bound of every search, s (as the demo)
DECIMATE = 4  # bootstrap: 20 Hz -> 5 Hz


def build():
    if not (BUILD / "build.ninja").exists():
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release", "-DPDT_BUILD_TESTS=OFF"], check=True,
                       stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdtfit_cli"], check=True,
                   stdout=subprocess.DEVNULL)


def pdtfit(*args):
    res = subprocess.run([str(BIN)] + [str(a) for a in args], capture_output=True, text=True)
    if res.returncode != 0:
        return None, res.stderr.strip()
    return json.loads(res.stdout), None


def csv_list(values):
    return ",".join(f"{v:.6g}" for v in values)


# ----------------------------------------------------------------- runs

class Row:
    """One line of a table: a model (or a refusal) and where it came from."""

    def __init__(self, name, model=None, paper=None, out=None, note=""):
        self.name, self.model, self.paper, self.out, self.note = name, model, paper, out, note
        self.merit = s17.merit(model) if model is not None else None
        self.paper_merit = s17.merit(paper) if paper is not None else None


def identify(name, csv, kind, method="ga", cost=None, paper=None):
    args = ["identify", "--model", kind, "--method", method, "--td-max", TD_MAX]
    if cost:
        args += ["--cost", cost]
    out, err = pdtfit(*args, csv)
    if out is None:
        return Row(name, paper=paper, note="refused: " + err.removeprefix("pdtfit: "))
    try:
        m = Model.from_json(out, name)
    except ValueError:
        return Row(name, paper=paper, out=out, note="integrating model")
    return Row(name, m, paper, out)


def reduce(name, method, kind, K, lags, zeros, delay, paper=None):
    args = ["reduce", "--method", method, "--model", kind, "--gain", f"{K:.9g}",
            "--lags", csv_list(lags)]
    if zeros:
        args += ["--zeros", csv_list(zeros)]
    if delay:
        args += ["--delay", f"{delay:.9g}"]
    out, err = pdtfit(*args)
    if out is None:
        return Row(name, paper=paper, note="refused: " + err.removeprefix("pdtfit: "))
    return Row(name, Model.from_json(out, name), paper, out)


def run_all(tmp):
    recs = s17.records()
    csv = {}
    for key, (t, u, y) in recs.items():
        path = tmp / f"{key}.csv"
        np.savetxt(path, np.column_stack([t, u, y]), delimiter=",", header="t,u,y",
                   comments="", fmt="%.10g")
        csv[key] = path

    F, S = Model.fopdt, Model.sopdt_tc
    t1 = [
        identify("ELMS", csv["chirp"], "fopdt", "elms", paper=F(1.04, 3.28, 1.4)),
        identify("E-IV-LMS", csv["chirp"], "fopdt", "eiv", paper=F(0.98, 2.99, 1.45)),
        identify("GA_t, prediction cost (the paper's Ct)", csv["chirp"], "fopdt",
                 cost="prediction", paper=F(1.05, 3.34, 1.4)),
        identify("GA_t, simulation cost", csv["chirp"], "fopdt", cost="simulation"),
        identify("GA, combined cost", csv["chirp"], "fopdt", cost="combined",
                 paper=F(1.0, 2.4, 1.55)),
        reduce("Skogestad half rule (model known)", "skogestad", "fopdt", 1.0, s17.LAGS17,
               s17.ZEROS17, 0.0, paper=F(1.0, 2.5, 1.47)),
        reduce("Sung et al. (model known)", "sung", "fopdt", 1.0, s17.LAGS17, s17.ZEROS17, 0.0,
               paper=F(1.0, 2.86, 1.57)),
    ]
    paper2 = {"chirp-2": S(1.0, 0.74, 2.2, 1.0), "pulse-1": S(1.0, 1.34, 1.74, 0.85),
              "pulse-2": S(1.0, 1.29, 1.8, 0.85)}
    t2 = []
    for key, label in (("chirp-2", "chirp"), ("pulse-1", "pulse-1"), ("pulse-2", "pulse-2")):
        t2.append(identify(f"GA, {label}, combined cost", csv[key], "sopdt", cost="combined",
                           paper=paper2[key]))
        t2.append(identify(f"GA, {label}, simulation cost", csv[key], "sopdt",
                           cost="simulation"))
        t2.append(identify(f"ELMS, {label}", csv[key], "sopdt", "elms"))
        t2.append(identify(f"E-IV-LMS, {label}", csv[key], "sopdt", "eiv"))
    t2.append(reduce("Skogestad half rule (model known)", "skogestad", "sopdt", 1.0,
                     s17.LAGS17, s17.ZEROS17, 0.0, paper=S(1.0, 2.0, 1.2, 0.77)))
    t2.append(reduce("Sung et al. (model known)", "sung", "sopdt", 1.0, s17.LAGS17,
                     s17.ZEROS17, 0.0, paper=S(1.0, 1.99, 1.29, 0.9)))

    # Section 4.5: a higher-order model from the chirp, then reduced.
    import scipy.signal as ss
    t, u, y = recs["chirp"]
    ud = ss.decimate(u - u[0], DECIMATE, ftype="fir", zero_phase=True)
    yd = ss.decimate(y - y[0], DECIMATE, ftype="fir", zero_phase=True)
    Tsd = s17.TS * DECIMATE
    best, cands = bootstrap.estimate(ud, yd, Tsd, int(round(3.0 / Tsd)))
    K, poles, zeros = best["cont"]
    lags = bootstrap.time_constants(poles, 1e-3)
    ztc = bootstrap.time_constants(zeros, 1e-3)
    delay = best["d"] * Tsd
    hi = HighOrder(K, poles, zeros, delay)
    t3 = [
        reduce("Skog-2 FOPDT", "skogestad", "fopdt", K, lags, ztc, delay,
               paper=F(1.0, 4.63, 2.23)),
        reduce("Sung2 FOPDT", "sung", "fopdt", K, lags, ztc, delay, paper=F(1.0, 5.88, 1.4)),
        reduce("Skog-2 SOPDT", "skogestad", "sopdt", K, lags, ztc, delay,
               paper=S(1.0, 1.6, 3.56, 0.9)),
        reduce("Sung2 SOPDT", "sung", "sopdt", K, lags, ztc, delay,
               paper=S(1.0, complex(2.9, -0.5), complex(2.9, 0.5), 0.79)),
    ]
    boot = dict(best=best, cands=cands, lags=lags, zeros=ztc, K=K, delay=delay, model=hi,
                merit=s17.merit(hi))
    return recs, t1, t2, t3, boot


class HighOrder:
    """The bootstrap's continuous model, K prod(z-terms)/prod(p-terms) e^{-Td s},
    with the members of Model that the figures of merit use."""

    def __init__(self, K, poles, zeros, Td):
        self.K, self.poles, self.zeros, self.Td = K, np.asarray(poles), np.asarray(zeros), Td
        self.kind = "high"

    def freq(self, w):
        s = 1j * np.asarray(w, dtype=float)
        g = np.full_like(s, self.K)
        for z in self.zeros:
            g = g * (1.0 - s / z)
        for p in self.poles:
            g = g / (1.0 - s / p)
        return g * np.exp(-self.Td * s)

    def step(self, t):
        """From the partial fractions of G(s) (distinct poles, G(0) = K):
        h(t) = K + sum_i r_i / p_i e^{p_i t}, r_i the residues."""
        t = np.asarray(t, dtype=float)
        p = self.poles.astype(complex)
        r = np.array([self.K * np.prod(1.0 - pi / self.zeros.astype(complex))
                      / np.prod([1.0 - pi / pj for pj in p if pj != pi])
                      * (-pi) for pi in p])
        y = np.zeros_like(t)
        x = t - self.Td
        on = x > 0
        h = self.K + np.sum((r / p)[:, None] * np.exp(np.outer(p, x[on])), axis=0)
        y[on] = h.real
        return y


# ----------------------------------------------------------------- output

def fmt(v, nd=2):
    if v is None:
        return ""
    if isinstance(v, complex):
        return f"{v.real:.{nd}f}{v.imag:+.{nd}f}j"
    return f"{v:.{nd}f}"


def params(m):
    """K, first and second time constant, Td of a model (None: blanks)."""
    if m is None:
        return ["", "", "", ""]
    T1, T2 = m.time_constants()
    return [fmt(m.K), fmt(T1), fmt(T2) if T2 is not None else "", fmt(m.Td)]


def table(rows, second):
    cols = ["K", "a1", "a2", "Td"] if second else ["K", "tau", "Td"]
    keep = [0, 1, 2, 3] if second else [0, 1, 3]
    head = ("| Method | " + " | ".join(f"paper {c}" for c in cols) + " | "
            + " | ".join(f"pdtfit {c}" for c in cols) + " | fit % | note |")
    lines = [head, "|" + "---|" * (2 * len(cols) + 3)]
    for r in rows:
        p = [params(r.paper)[i] for i in keep]
        o = [params(r.model)[i] for i in keep]
        fit = fmt(r.out["fit"], 1) if r.out and "fit" in r.out else ""
        lines.append(f"| {r.name} | " + " | ".join(p) + " | " + " | ".join(o)
                     + f" | {fit} | {r.note} |")
    return "\n".join(lines)


def merit_table(rows, extra=()):
    lines = ["| Model | IAE paper | IAE pdtfit | max dev. paper | max dev. pdtfit "
             "| freq. err. paper | freq. err. pdtfit |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        pm, om = r.paper_merit, r.merit
        lines.append(f"| {r.name} | {fmt(pm and pm.iae, 3)} | {fmt(om and om.iae, 3)} | "
                     f"{fmt(pm and pm.maxdev, 3)} | {fmt(om and om.maxdev, 3)} | "
                     f"{fmt(pm and pm.ferr, 3)} | {fmt(om and om.ferr, 3)} |")
    for name, m in extra:
        lines.append(f"| {name} | | {fmt(m.iae, 3)} | | {fmt(m.maxdev, 3)} | | "
                     f"{fmt(m.ferr, 3)} |")
    return "\n".join(lines)


def main():
    build()
    with tempfile.TemporaryDirectory(prefix="pdtfit-repro-") as d:
        recs, t1, t2, t3, boot = run_all(pathlib.Path(d))
    from pdtrepro import figures
    IMG.mkdir(parents=True, exist_ok=True)
    figs = figures.make_all(IMG, recs, t1, t2, t3, boot)[1:]
    from pdtrepro import document
    DOC.write_text(document.render(t1, t2, t3, boot, figs, table, merit_table, provenance.fields()))
    print(f"wrote {DOC.relative_to(ROOT)} and {len(figs)} figures in "
          f"{IMG.relative_to(ROOT)}/")


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
