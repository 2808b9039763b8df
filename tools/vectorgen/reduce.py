"""Test vectors of the model reduction (lib/src/pdt_reduce.c) from pdtref.reduce.

Cases: the paper's system (17), with and without a controller period h; the
Astrom-Hagglund batch P1-P5, P7, P8 (P6, an integrator, and P9, a complex
pole pair, are outside the reduction's input form of real lags); cases
built to take each left-half-plane zero rule (T1, T1a, T1b, T2, T3 with and
without the 5 theta clamp) for a FOPDT and a SOPDT; models that have no
result (a SOPDT from one lag, a zero without a lag to cancel, no phase
crossover); and pseudo-random models from splitmix64. Every number is
rounded to float32 first so that both C builds see what the reference saw;
random cases whose rule comparisons come within 1e-3 of a tie are skipped, so
float and double rounding take the same branches.

Per case i (RED_VEC_COUNT cases):
- ``red_plant[4 i ..]``: k, theta0, h, 0; ``red_nl[i]``, ``red_nz[i]`` and
  ``red_lag_off[i]``, ``red_zero_off[i]`` into ``red_lags``, ``red_zeros``;
- per order o (0 FOPDT, 1 SOPDT), index 2 i + o:
  ``red_half_status``, ``red_half_rules``, ``red_half_passes``,
  ``red_half[4 (2 i + o) ..]``: K, tau, Td, 0 (FOPDT) or k, a, b, Td (form 2);
  ``red_sung_status``, ``red_sung_kind`` (1 FOPDT, 2 SOPDT),
  ``red_sung_check`` (0: the SOPDT fit is too close to its fallback
  threshold to compare; the C result only has to be valid), ``red_sung[..]``
  as for the half rule;
- ``red_wu_status[i]``, ``red_wu[i]``.
Rows with a non-zero status hold zeros.
"""
import math

import numpy as np

from pdtref import reduce as R
from pdtsupport.rng import SplitMix64 as Rng

from . import _emit

FILE = "reduce_vectors.h"
NO_FORM = -7


def f32(x):
    return float(np.float32(x))


def plant(k, lags, zeros=(), theta0=0.0):
    return R.Plant(f32(k), tuple(f32(t) for t in lags), tuple(f32(z) for z in zeros),
                   f32(theta0))


def uniforms(seed):
    """splitmix64 uniform floats in [0, 1)."""
    rng = Rng.keyed(seed)
    while True:
        yield rng.uniform()


def random_cases(count, seed=12345):
    rnd = uniforms(seed)
    out = []
    while len(out) < count:
        n = 2 + int(next(rnd) * 5)
        lags = [10 ** (-1.5 + 2.5 * next(rnd)) for _ in range(n)]
        zeros = []
        for _ in range(int(next(rnd) * 3)):
            z = 10 ** (-1.5 + 2.0 * next(rnd))
            zeros.append(z if next(rnd) < 0.6 else -z)
        theta0 = 0.0 if next(rnd) < 0.3 else 2.0 * next(rnd)
        k = (0.2 + 4 * next(rnd)) * (1 if next(rnd) < 0.8 else -1)
        h = 0.0 if next(rnd) < 0.6 else 0.2 * next(rnd)
        p = plant(k, lags, zeros, theta0)
        if all(_robust(p, o, f32(h)) for o in (1, 2)):
            out.append((p, f32(h)))
    return out


def _robust(p, order, h):
    try:
        r = R.half_rule(p, order, h)
    except R.NoFormError:
        return True
    return r.margin > 1e-3


def cases():
    out = []
    paper = R.paper_plant()
    paper = plant(paper.k, paper.lags, paper.zeros, paper.theta0)
    out.append((paper, 0.0))
    out.append((paper, f32(0.1)))
    out.append((paper, f32(0.05)))
    # Astrom-Hagglund batch
    for T in (0.1, 1.0, 10.0):
        out.append((plant(1, (T,), (), 1.0), 0.0))            # P1
    for T in (0.1, 1.0, 10.0):
        out.append((plant(1, (T, T), (), 1.0), 0.0))          # P2
    for T in (0.1, 0.5, 2.0, 10.0):
        out.append((plant(1, (1.0, T, T)), 0.0))              # P3
    for n in (3, 4, 6, 8):
        out.append((plant(1, (1.0,) * n), 0.0))               # P4
    for a in (0.1, 0.3, 0.5, 0.7, 0.9):
        out.append((plant(1, (1.0, a, a * a, a ** 3)), 0.0))  # P5
    for T, L in ((1.0, 0.1), (2.0, 0.5), (5.0, 0.3), (10.0, 0.9)):
        out.append((plant(T, (T, 1.0 - L), (), L), 0.0))      # P7
    for a in (0.1, 0.5, 1.1):
        out.append((plant(1, (1.0, 1.0, 1.0), (-a,)), 0.0))   # P8
    # one rule per case, FOPDT
    out.append((plant(1, (3.0, 0.5), (4.0,), 0.2), 0.0))      # T1
    out.append((plant(1, (0.5, 0.3), (0.8,), 0.6), 0.0))      # T1a
    out.append((plant(1, (0.5, 0.3), (0.8,), 1.0), 0.0))      # T1b
    out.append((plant(1, (10.0, 1.0), (9.0,)), 0.0))          # T2
    out.append((plant(1, (10.0, 1.0), (2.0,), 0.3), 0.0))     # T3, clamped
    # one rule per case, SOPDT
    out.append((plant(1.5, (3.0, 2.0, 0.5), (4.0,), 0.2), 0.0))  # T1
    out.append((plant(1, (0.5, 0.4, 0.3), (0.8,), 0.6), 0.0))    # T1a
    out.append((plant(1, (0.5, 0.4, 0.3), (0.8,), 1.0), 0.0))    # T1b
    out.append((plant(1, (10.0, 3.0, 1.0), (9.0,)), 0.0))        # T2
    out.append((plant(1, (10.0, 4.0, 1.0), (2.0,), 0.1), 0.0))   # T3, clamped
    # T3 clamped with its lag in the dead time: the delay moves away from an
    # unstable fixed point for several passes until rule T2 takes over
    out.append((plant(1, (0.36512213, 0.021476748), (0.032494574,)), 0.0))
    # several zeros of both kinds, negative gain, h
    out.append((plant(-2, (5.0, 2.0, 1.0, 0.5, 0.1), (1.5, 0.3, -0.2), 0.7), f32(0.2)))
    out.append((plant(0.5, (4.0, 4.0, 0.7, 0.2), (0.6, 0.15, -0.4, -0.1), 0.25), 0.0))
    # no result: a zero too many; two lags and no delay (no crossover)
    out.append((plant(1, (1.0,), (0.5, 0.2), 0.5), 0.0))
    out.append((plant(1, (2.0, 1.0)), 0.0))
    out += random_cases(16)
    return out


def _half(p, order, h):
    try:
        r = R.half_rule(p, order, h)
    except R.NoFormError:
        return NO_FORM, 0, 0, [0.0] * 4
    if order == 1:
        vals = [r.K, r.T[0], r.Td, 0.0]
    else:
        vals = [*R.sopdt_form2(r.K, *r.T), r.Td]
    return 0, r.rules, r.passes, vals


def _sung(p, order):
    try:
        r = R.sung(p, order)
    except R.NoFormError:
        return NO_FORM, 0, 1, [0.0] * 4
    check = 1
    if order == 2:
        q1, q2 = r.q
        z2 = (q1 / math.sqrt(q2) + 2) / 4 if q2 > 0 else -1.0
        # near the fallback thresholds float and double may decide apart
        if abs(q2) < 1e-3 * (1 + q1 * q1) or abs(z2) < 1e-3:
            check = 0
    if r.kind == "fopdt":
        return 0, 1, check, [r.K, r.tau, r.Td, 0.0]
    return 0, 2, check, [*R.sopdt_natural_form2(r.K, r.tau, r.zeta), r.Td]


def generate():
    cs = cases()
    pl, nl, nz, loff, zoff, lags, zeros = [], [], [], [], [], [], []
    hs, hr, hp, hv = [], [], [], []
    ss, sk, sc, sv = [], [], [], []
    ws, wv = [], []
    for p, h in cs:
        pl += [p.k, p.theta0, h, 0.0]
        loff.append(len(lags))
        zoff.append(len(zeros))
        nl.append(len(p.lags))
        nz.append(len(p.zeros))
        lags += p.lags
        zeros += p.zeros
        for order in (1, 2):
            st, rules, passes, vals = _half(p, order, h)
            hs.append(st)
            hr.append(rules)
            hp.append(passes)
            hv += vals
            st, kind, check, vals = _sung(p, order)
            ss.append(st)
            sk.append(kind)
            sc.append(check)
            sv += vals
        try:
            ws.append(0)
            wv.append(R.ultimate(p))
        except R.NoFormError:
            ws[-1] = NO_FORM
            wv.append(0.0)
    body = (
        f"#define RED_VEC_COUNT {len(cs)}\n\n"
        + _emit.array("double", "red_plant", pl)
        + _emit.int_array("int", "red_nl", nl)
        + _emit.int_array("int", "red_nz", nz)
        + _emit.int_array("int", "red_lag_off", loff)
        + _emit.int_array("int", "red_zero_off", zoff)
        + _emit.array("double", "red_lags", lags)
        + _emit.array("double", "red_zeros", zeros)
        + _emit.int_array("int", "red_half_status", hs)
        + _emit.int_array("unsigned", "red_half_rules", hr)
        + _emit.int_array("unsigned", "red_half_passes", hp)
        + _emit.array("double", "red_half", hv)
        + _emit.int_array("int", "red_sung_status", ss)
        + _emit.int_array("int", "red_sung_kind", sk)
        + _emit.int_array("int", "red_sung_check", sc)
        + _emit.array("double", "red_sung", sv)
        + _emit.int_array("int", "red_wu_status", ws)
        + _emit.array("double", "red_wu", wv)
    )
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/reduce.py (pdtref.reduce)")}
