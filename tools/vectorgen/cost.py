"""Test vectors of the cost functions (lib/src/pdt_cost.c) from pdtref.cost.

Four records, each made by exact continuous-time simulation (superposition
of closed-form step responses of the true plant, so no discretisation code is
involved), plus pseudo-random noise from a 32-bit integer LCG, then quantised
to multiples of 2^-12 like an ADC reading: the values are exact in float, so
both C builds score the same numbers as the reference.

- ``fopdt_step``: FOPDT plant, a step then a PRBS, n = 300;
- ``sopdt_chirp``: underdamped SOPDT, a chirp, n = 600, delay_max automatic;
- ``integ``: integrating SOPDT (b = 0), pulses, n = 400, delay_min > 0;
- ``reverse``: reverse-acting FOPDT (K < 0), PRBS, n = 256.

Each record has candidate models (the truth and perturbed ones, FOPDT and
SOPDT, dead times on and off the sample grid). For each candidate the header
holds its two discrete models (exact ZOH with the fractional dead time, and
with the dead time rounded to whole samples; derived here from the sampled
step response, independently of pdtref.discrete and of the C code) and the
costs in COST_COL_* order.
"""
import collections

import numpy as np


from pdtref import cost as ref
from pdtsupport.rng import SplitMix64 as Rng

from . import _emit

FILE = "cost_vectors.h"
QUANTUM = 1.0 / 4096.0

Fopdt = collections.namedtuple("Fopdt", "K tau Td")
Sopdt = collections.namedtuple("Sopdt", "k a b Td")
Dmodel = collections.namedtuple("Dmodel", "delay order a b d")

# Weights of the two combined costs stored in the last columns.
PHI_A = (1.0, 0.5)  # COMBINED, SIMULATION, FRACTIONAL, offset, UNIFORM
PHI_B = (2.0, 1.0)  # COMBINED, PREDICTION, INTEGER, no offset, BAND

COLUMNS = (
    "PRED_FRAC", "PRED_FRAC_OFS", "SIM_FRAC", "SIM_FRAC_OFS",
    "PRED_INT", "PRED_INT_OFS", "SIM_INT", "SIM_INT_OFS",
    "CF_UNIFORM", "CF_BAND", "CF_CUSTOM", "COMB_A", "COMB_B",
)


def _poles(m):
    if isinstance(m, Fopdt):
        return np.array([-1.0 / m.tau + 0j])
    return np.roots([1.0, m.a, m.b]).astype(complex)


def step(m, t):
    """Closed-form unit-step response (dead time included), 0 before Td."""
    t = np.asarray(t, dtype=float) - m.Td
    tp = np.maximum(t, 0.0)
    if isinstance(m, Fopdt):
        h = -m.K * np.expm1(-tp / m.tau)
    elif m.b == 0.0:
        h = m.k * (tp / m.a + np.expm1(-m.a * tp) / (m.a * m.a))
    else:
        l1, l2 = _poles(m)
        h = m.k * (1.0 / (l1 * l2) + np.exp(l1 * tp) / (l1 * (l1 - l2))
                   + np.exp(l2 * tp) / (l2 * (l2 - l1))).real
    return np.where(t > 0.0, h, 0.0)


def zoh(m, Ts, delay_samples=None):
    """Exact ZOH model of m (dead time m.Td, or delay_samples * Ts if given):
    A(q) from the sampled poles, B(q) = A(q) (1 - q) S(q) with S the sampled
    step response, which has exactly three non-zero terms after the delay."""
    if delay_samples is not None:
        m = m._replace(Td=delay_samples * Ts)
    x = m.Td / Ts
    l = int(np.floor(x + 1e-9))
    lam = _poles(m) * Ts
    one_minus_p = -np.expm1(lam)
    if isinstance(m, Fopdt):
        order = 1
        a = [-(1.0 - one_minus_p[0].real), 0.0]
        d = [one_minus_p[0].real, 0.0]
    else:
        order = 2
        p = np.exp(lam)
        a = [-(p[0] + p[1]).real, (p[0] * p[1]).real]
        d = [(one_minus_p[0] + one_minus_p[1]).real, (one_minus_p[0] * one_minus_p[1]).real]
    s = step(m, np.arange(l + 10) * Ts)
    g = np.diff(np.concatenate([[0.0], s]))
    beta = np.convolve([1.0, a[0], a[1]][:order + 1], g)[:l + 10]
    scale = max(1.0, np.max(np.abs(beta)))
    assert np.all(np.abs(beta[:l + 1]) <= 1e-12 * scale)
    assert np.all(np.abs(beta[l + 4:]) <= 1e-9 * scale), beta
    return Dmodel(l, order, a, list(beta[l + 1:l + 4]), d)


def simulate_exact(m, u, u0, Ts):
    """Output deviations at the samples for a held input: the sum of the
    step responses to each input change."""
    ud = np.asarray(u, dtype=float) - u0
    du = np.diff(np.concatenate([[0.0], ud]))
    n = len(ud)
    k = np.arange(n)
    lag = (k[:, None] - k[None, :]) * Ts
    return (np.where(lag > 0.0, step(m, np.maximum(lag, 0.0)), 0.0) * du[None, :]).sum(axis=1)


def quantise(x):
    return np.round(np.asarray(x) / QUANTUM) * QUANTUM


def _record(name, truth, Ts, n, u0, y0, u, noise, seed, delay_min, delay_max, cands):
    rng = Rng.keyed(seed)
    u = quantise(u)
    y = quantise(y0 + simulate_exact(truth, u, u0, Ts) + rng.noise(noise, n))
    return dict(name=name, Ts=Ts, n=n, u0=u0, y0=y0, u=u, y=y,
                delay_min=delay_min, delay_max=delay_max, cands=cands)


def records():
    out = []

    # FOPDT, step at 1 s then PRBS from 15 s; Td = 12.3 samples.
    n, Ts = 300, 0.1
    rng = Rng.keyed(0xC0570001)
    t = np.arange(n)
    u = 50.0 + np.where(t >= 10, 4.0, 0.0) + np.where(t >= 150, 3.0 * rng.signs(n, 7), 0.0)
    truth = Fopdt(2.0, 3.0, 1.23)
    cands = [truth, Fopdt(2.2, 2.4, 1.53), Fopdt(1.8, 3.6, 0.91), Fopdt(2.0, 3.0, 1.2),
             Sopdt(2.0 / 2.5, 1.5 / 2.5 + 0.0, 1.0 / 2.5, 0.87), Fopdt(-1.0, 1.0, 3.02)]
    out.append(_record("fopdt_step", truth, Ts, n, 50.0, 20.0, u, 0.05, 0xC0570002,
                       0, 40, cands))

    # Underdamped SOPDT (K 1.5, wn 1.2, zeta 0.3), chirp 0.02 -> 1 Hz.
    n, Ts = 600, 0.05
    tt = np.arange(n) * Ts
    f0, f1, T = 0.02, 1.0, n * Ts
    u = 10.0 + np.sin(2.0 * np.pi * (f0 * tt + (f1 - f0) * tt * tt / (2.0 * T)))
    wn, zeta, K = 1.2, 0.3, 1.5
    truth = Sopdt(K * wn * wn, 2.0 * zeta * wn, wn * wn, 0.81)
    cands = [truth, Sopdt(K * wn * wn * 1.1, 2.0 * 0.4 * wn, wn * wn, 0.93),
             Sopdt(2.0, 1.0, 1.3, 0.66), Fopdt(1.5, 1.1, 0.97), Fopdt(1.2, 0.5, 1.41)]
    out.append(_record("sopdt_chirp", truth, Ts, n, 10.0, -5.0, u, 0.02, 0xC0570003,
                       0, None, cands))

    # Integrating SOPDT: Ki 0.4 /s, lag 2 s (k = 0.2, a = 0.5, b = 0), Td 0.5 s.
    n, Ts = 400, 0.1
    t = np.arange(n)
    u = (np.where((t >= 20) & (t < 60), 1.0, 0.0) - np.where((t >= 150) & (t < 190), 1.5, 0.0)
         + np.where((t >= 260) & (t < 300), 0.5, 0.0))
    truth = Sopdt(0.2, 0.5, 0.0, 0.5)
    cands = [truth, Sopdt(0.22, 0.4, 0.0, 0.73), Sopdt(0.2, 0.5, 0.01, 0.5),
             Sopdt(0.15, 0.6, 0.0, 0.26), Fopdt(8.0, 20.0, 1.04)]
    out.append(_record("integ", truth, Ts, n, 0.0, 100.0, u, 0.03, 0xC0570004,
                       2, 30, cands))

    # Reverse-acting FOPDT, K = -0.8, tau 5 s, Td 2 s = 4 samples.
    n, Ts = 256, 0.5
    rng = Rng.keyed(0xC0570005)
    u = 30.0 + 5.0 * rng.signs(n, 9)
    truth = Fopdt(-0.8, 5.0, 2.0)
    cands = [truth, Fopdt(-0.7, 6.0, 2.3), Fopdt(0.8, 5.0, 2.0),
             Sopdt(-0.8 / 4.0, 1.2 / 4.0 + 0.0, 1.0 / 4.0, 1.6)]
    out.append(_record("reverse", truth, Ts, n, 30.0, 70.0, u, 0.02, 0xC0570006,
                       1, 20, cands))
    return out


def band_edges(nf, Ts):
    """Half a bin off the grid, so float and double agree on which bins."""
    nb = nf // 2
    return (2.5 / (nf * Ts), (nb // 4 + 0.5) / (nf * Ts))


def custom_weights(nf):
    nb = nf // 2
    k = np.arange(nb + 1)
    w = (1.0 + 0.5 * np.sin(0.3 * k)) / (1.0 + (k / (0.1 * nb)) ** 2)
    w[k > (8 * nb) // 10] = 0.0
    w[0] = 3.0  # ignored: DC is not scored
    return w


def int_delay(m, Ts):
    return int(np.floor(m.Td / Ts + 0.5))


def costs(rec, m):
    u, y, u0, y0, Ts, lu = rec["u"], rec["y"], rec["u0"], rec["y0"], rec["Ts"], rec["delay_max"]
    nf = ref.fft_size(rec["n"], lu)
    f_lo, f_hi = band_edges(nf, Ts)
    row = []
    for dm in (zoh(m, Ts), zoh(m, Ts, int_delay(m, Ts))):
        for fn in (ref.prediction_cost, ref.simulation_cost):
            for offset in (False, True):
                row.append(fn(u, y, dm, u0, y0, lu, offset))
    row.append(ref.frequency_cost(u, y, m, Ts, u0, y0, lu))
    row.append(ref.frequency_cost(u, y, m, Ts, u0, y0, lu, "band", f_lo, f_hi))
    row.append(ref.frequency_cost(u, y, m, Ts, u0, y0, lu, "custom",
                                  weights=custom_weights(nf)))
    row.append(ref.combined_cost(row[3], row[8], *PHI_A))
    row.append(ref.combined_cost(row[4], row[9], *PHI_B))
    return row


def _params(m):
    if isinstance(m, Fopdt):
        return [m.K, m.tau, m.Td, 0.0]
    return [m.k, m.a, m.b, m.Td]


def _coef(dm):
    return list(dm.a) + list(dm.b) + list(dm.d)


def generate():
    body = []
    body.append("#define COST_NCOL %d\n" % len(COLUMNS))
    for i, c in enumerate(COLUMNS):
        body.append("#define COST_COL_%s %d\n" % (c, i))
    body.append("#define COST_PHI_A_T %s\n#define COST_PHI_A_F %s\n"
                % (_emit.num(PHI_A[0]), _emit.num(PHI_A[1])))
    body.append("#define COST_PHI_B_T %s\n#define COST_PHI_B_F %s\n\n"
                % (_emit.num(PHI_B[0]), _emit.num(PHI_B[1])))
    body.append(
        "/* One record and its candidates. param: FOPDT K, tau, Td, 0 or SOPDT\n"
        " * k, a, b, Td. coef: a0 a1 b0 b1 b2 d0 d1 of the discrete model (see\n"
        " * pdt_discrete.h). delay_max_auto: the config used PDT_DELAY_HALF and\n"
        " * delay_max is the resolved value. */\n"
        "typedef struct cost_vec_set {\n"
        "    const char *name;\n    size_t n;\n    double Ts, u0, y0;\n"
        "    size_t delay_min, delay_max;\n    int delay_max_auto;\n    size_t nf;\n"
        "    double f_lo, f_hi;\n    const double *u, *y, *weights;\n    size_t ncand;\n"
        "    const int *kind;\n    const double *param;\n"
        "    const int *delay_frac;\n    const double *coef_frac;\n"
        "    const int *delay_int;\n    const double *coef_int;\n"
        "    const double *cost;\n} cost_vec_set_t;\n\n")
    table = []
    for rec in records():
        name, n, Ts = rec["name"], rec["n"], rec["Ts"]
        auto = rec["delay_max"] is None
        lu = ref.resolve_delay_max(n, rec["delay_max"])
        rec["delay_max"] = lu
        nf = ref.fft_size(n, lu)
        f_lo, f_hi = band_edges(nf, Ts)
        cands = rec["cands"]
        p = "cost_%s_" % name
        body.append(_emit.array("double", p + "u", rec["u"]))
        body.append(_emit.array("double", p + "y", rec["y"]))
        body.append(_emit.array("double", p + "weights", custom_weights(nf)))
        body.append(_emit.int_array("int", p + "kind",
                                    [1 if isinstance(m, Fopdt) else 2 for m in cands]))
        body.append(_emit.array("double", p + "param", sum((_params(m) for m in cands), [])))
        frac = [zoh(m, Ts) for m in cands]
        intd = [zoh(m, Ts, int_delay(m, Ts)) for m in cands]
        for dm in frac + intd:
            assert rec["delay_min"] <= dm.delay <= lu, (name, dm.delay)
        body.append(_emit.int_array("int", p + "delay_frac", [dm.delay for dm in frac]))
        body.append(_emit.array("double", p + "coef_frac", sum((_coef(dm) for dm in frac), [])))
        body.append(_emit.int_array("int", p + "delay_int", [dm.delay for dm in intd]))
        body.append(_emit.array("double", p + "coef_int", sum((_coef(dm) for dm in intd), [])))
        body.append(_emit.array("double", p + "cost", sum((costs(rec, m) for m in cands), [])))
        body.append("\n")
        table.append(
            "    {\"%s\", %d, %s, %s, %s, %d, %d, %d, %d, %s, %s,\n"
            "     %su, %sy, %sweights, %d, %skind, %sparam,\n"
            "     %sdelay_frac, %scoef_frac, %sdelay_int, %scoef_int, %scost},\n"
            % (name, n, _emit.num(Ts), _emit.num(rec["u0"]), _emit.num(rec["y0"]),
               rec["delay_min"], lu, int(auto), nf, _emit.num(f_lo), _emit.num(f_hi),
               p, p, p, len(cands), p, p, p, p, p, p, p))
    body.append("static const cost_vec_set_t cost_vec_sets[%d] = {\n" % len(table))
    body.append("".join(table))
    body.append("};\n")
    return {FILE: _emit.header(FILE, "".join(body), "tools/pdtref/cost.py")}
