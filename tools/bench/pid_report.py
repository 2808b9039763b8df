#!/usr/bin/env python3
"""Writes docs/reports/pid-accuracy.md: how closely the discrete PID (pdt_pid, as the
numpy reference tools/pdtref/pid.py computes it; tests/test_pid.c checks the
C against that reference) reproduces the continuous design in closed loop,
and what the scan period costs in robustness.

For SIMC gains on the half-rule FOPDT and SOPDT of the paper's system (17):
- the largest deviation of the sampled loop's output from the continuous
  loop's, for a unit set-point step and a unit load step at the plant input,
  and the integral of absolute error (IAE) of both, at several scan periods;
- Ms, gain and phase margin of the continuous design (what pdtfit tune
  prints) and of the same gains with the dead time lengthened by Ts / 2,
  the usual model of the zero-order hold.

The prose is the template pid_report.md.in beside this file.

Usage: python3 tools/bench/pid_report.py [--print]
"""
import argparse
import pathlib
import string
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEMPLATE = pathlib.Path(__file__).with_name("pid_report.md.in")

from pdtref import models as M
from pdtref import pid as P
from pdtref import tune as T
from pdtsupport import provenance

T_END = 25.0
GRID = 0.1
PERIODS = (0.01, 0.02, 0.05, 0.1)          # at most GRID: compared on the grid
ROB_PERIODS = (0.01, 0.05, 0.1, 0.2, 0.5)


def cases():
    out = []
    for name, m, form in (("FOPDT (1, 2.5, 1.47), SIMC PI", M.Fopdt(1.0, 2.5, 1.47), T.PI),
                          ("SOPDT (1, 2, 1.2, 0.77), SIMC PID",
                           M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77), T.PID)):
        st, r = T.compute(m, T.SIMC, form)
        assert st == 0
        out.append((name, m, r))
    return out


def iae(y, target, dt):
    return float(np.sum(np.abs(y - target)) * dt)


def accuracy_rows():
    t = np.arange(0.0, T_END + GRID / 2, GRID)
    rows = []
    for name, m, r in cases():
        g = r["ideal"]
        gains = (g["Kc"], g["tauI"], g["tauD"], g["Tf"])
        theta = m.Td
        for label, rr, dd in (("set-point", 1.0, 0.0), ("load", 0.0, 1.0)):
            yc = P.continuous_loop(m, gains, t, r=rr, d=dd)
            iae_c = iae(yc, rr, GRID)
            for Ts in PERIODS:
                s = r["series"]
                cfg = P.config(Ts=Ts, form=P.SERIES, Kc=s["Kc"], Ti=s["tauI"], Td=s["tauD"],
                               Tf=s["Tf"], N=0.0, u_min=-1e3, u_max=1e3)
                n = int(round(T_END / Ts)) + 1
                yd, _ = P.discrete_loop(m, cfg, n, r=rr, d=dd)
                yd = yd[::int(round(GRID / Ts))]
                peak_c = float(np.max(yc) - rr) if rr else float(np.max(np.abs(yc)))
                peak_d = float(np.max(yd) - rr) if rr else float(np.max(np.abs(yd)))
                rows.append((name, label, Ts, Ts / theta, float(np.max(np.abs(yd - yc))),
                             peak_c, peak_d, iae_c, iae(yd, rr, GRID)))
    return rows


def sampled_ms(m, r, Ts, npts=40000):
    """Ms of the sampled loop itself: the plant's exact ZOH model with its
    fractional dead time and the PID's z-transfer function from pv to u,
    |1 / (1 + L(e^{jwTs}))| maximised over a log grid of w up to pi / Ts."""
    g = r["ideal"]
    K, Ti, Td, Tf = g["Kc"], g["tauI"], g["tauD"], g["Tf"]
    l, Phi, G0, G1, C = P.plant_sampled(m, Ts)
    a = np.exp(-Ts / Tf) if Tf > 0 else 0.0
    w = np.geomspace(1e-3, np.pi / Ts, npts)
    z = np.exp(1j * w * Ts)
    zi = 1.0 / z
    ctrl = K + K * Ts / (2 * Ti) * (1 + zi) / (1 - zi) + K * Td * (1 - a) / Ts * (1 - zi) / (1 - a * zi)
    n = Phi.shape[0]
    G = np.empty(w.shape, dtype=complex)
    for i, zz in enumerate(z):
        x = np.linalg.solve(zz * np.eye(n) - Phi, G0 + G1 / zz)
        G[i] = (C @ x) * zz ** (-l)
    return float(np.max(np.abs(1.0 / (1.0 + ctrl * G))))


def robustness_rows():
    rows = []
    for name, m, r in cases():
        f = r["fig"]
        rows.append((name, 0.0, f["Ms"], f["gm"], f["pm_deg"], None))
        for Ts in ROB_PERIODS:
            mh = m._replace(Td=m.Td + Ts / 2)
            fh = T.robustness(mh, r["ideal"])
            rows.append((name, Ts, fh["Ms"], fh["gm"], fh["pm_deg"], sampled_ms(m, r, Ts)))
    return rows


def render():
    """The report: the template pid_report.md.in with the two tables' rows."""
    acc = []
    for name, label, Ts, ratio, err, pc, pd, ic, idd in accuracy_rows():
        acc.append(f"| {name} | {label} | {Ts:g} | {ratio:.3f} | {err:.5f} | {pc:.4f} | "
                   f"{pd:.4f} | {ic:.4f} | {idd:.4f} |")
    rob = []
    for name, Ts, ms, gm, pm, msz in robustness_rows():
        zs = "" if msz is None else f"{msz:.3f}"
        rob.append(f"| {name} | {Ts:g} | {ms:.3f} | {gm:.3f} | {pm:.1f} | {zs} |")
    return string.Template(TEMPLATE.read_text()).substitute(
        accuracy_rows="\n".join(acc), robustness_rows="\n".join(rob), **provenance.fields())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--print", action="store_true", help="print instead of writing the file")
    args = ap.parse_args()
    text = render()
    if args.print:
        print(text)
    else:
        (ROOT / "docs" / "reports" / "pid-accuracy.md").write_text(text)
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
