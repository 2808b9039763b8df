"""Test vectors of the least-squares delay scans (lib/src/pdt_ls.c) from
pdtref.ls.

Records are made by exact continuous-time simulation (the sum of closed-form
step responses to each change of the held input, the dead time a whole
number of samples), so the sampled data obey the ZOH prediction model
exactly and ELMS must recover the truth on the noise-free ones. Operating
points are engineering-like (u0 = 40, y0 = 350). Noisy records add integer
LCG noise and are quantised to 2^-12 (exact in float as well as double);
noise-free records are not quantised (quantisation would be noise).

- ``fopdt_clean``: FOPDT, PRBS, noise-free;
- ``sopdt_clean``: overdamped reverse-acting SOPDT, PRBS, noise-free;
- ``sopdt_step``: underdamped SOPDT, one step at k = 5, noise-free, scored
  on the whole record;
- ``fopdt_noisy``: FOPDT, PRBS, noise std about 12 % of the response swing;
- ``sopdt_noisy``: overdamped SOPDT, PRBS, noisy.

Each case (record, model, method, delay bounds) holds the reference's cost
per delay (-1 for a skipped delay), the chosen delay, model, operating
point, cost and discrete estimate, and the truth.
"""
import numpy as np


from pdtref import ls as ref
from pdtsupport.rng import SplitMix64 as Rng

from . import _emit

FILE = "ls_vectors.h"
QUANTUM = 1.0 / 4096.0


def step_response(truth, t):
    """Unit-step response of the truth without its dead time, t >= 0.
    truth: ("fopdt", K, tau) or ("sopdt", k, a, b) in form (2)."""
    t = np.asarray(t, dtype=float)
    if truth[0] == "fopdt":
        _, K, tau = truth
        return K * (1.0 - np.exp(-t / tau))
    _, k, a, b = truth
    l1, l2 = np.roots([1.0, a, b]).astype(complex)
    h = k * (1.0 / (l1 * l2) + np.exp(l1 * t) / (l1 * (l1 - l2))
             + np.exp(l2 * t) / (l2 * (l2 - l1)))
    return h.real


def simulate(truth, delay, u, Ts):
    """Sampled output deviation for the held input u (deviation from u[0]),
    dead time delay * Ts."""
    du = np.diff(np.concatenate([[u[0]], u]))
    n = len(u)
    y = np.zeros(n)
    for j in np.nonzero(du)[0]:
        t = (np.arange(n) - j - delay) * Ts
        y += np.where(t > 0.0, step_response(truth, np.maximum(t, 0.0)), 0.0) * du[j]
    return y


def quantise(x):
    return np.round(np.asarray(x) / QUANTUM) * QUANTUM


def sopdt_from_tc(K, T1, T2):
    """Form (2) of K / ((T1 s + 1)(T2 s + 1))."""
    return ("sopdt", K / (T1 * T2), (T1 + T2) / (T1 * T2), 1.0 / (T1 * T2))


def sopdt_from_natural(K, wn, zeta):
    return ("sopdt", K * wn * wn, 2.0 * zeta * wn, wn * wn)


def records():
    recs = []

    def add(name, truth, delay, Ts, u, y0, noise=0.0, seed=0):
        y = y0 + simulate(truth, delay, u, Ts)
        if noise > 0.0:
            y = quantise(y + Rng.keyed(seed).noise(noise, len(u)))
            u = quantise(u)
        recs.append(dict(name=name, truth=truth, delay=delay, Ts=Ts, u=np.asarray(u, float),
                         y=np.asarray(y, float), noisy=noise > 0.0))

    # The seeds give the records what tests/test_ls.c asserts of them: an
    # input move within the first 17 samples of fopdt_clean; on sopdt_noisy,
    # E-IV's delay exact and ELMS's not.
    n = 300
    add("fopdt_clean", ("fopdt", 2.5, 8.0), 5, 1.0,
        40.0 + 4.0 * Rng.keyed(0x15000006).signs(n, 6), 350.0)
    n = 400
    add("sopdt_clean", sopdt_from_tc(-1.5, 6.0, 2.5), 3, 0.5,
        40.0 + 5.0 * Rng.keyed(0x15000002).signs(n, 9), 350.0)
    n = 300
    u = 40.0 + np.where(np.arange(n) >= 5, 6.0, 0.0)
    add("sopdt_step", sopdt_from_natural(0.8, 0.5, 0.35), 4, 0.2, u, 350.0)
    n = 600
    add("fopdt_noisy", ("fopdt", 2.0, 10.0), 4, 1.0,
        40.0 + 5.0 * Rng.keyed(0x15000003).signs(n, 12), 350.0, noise=2.0, seed=0x15000004)
    n = 800
    add("sopdt_noisy", sopdt_from_tc(1.2, 5.0, 2.0), 6, 0.5,
        40.0 + 5.0 * Rng.keyed(0x15000005).signs(n, 14), 350.0, noise=0.1, seed=0x15000007)
    return recs


# (record, method, delay_min, delay_max, whole_record)
CASES = (
    ("fopdt_clean", "elms", 0, 20, False),
    ("fopdt_clean", "eiv", 2, 20, False),
    ("sopdt_clean", "elms", 0, 15, False),
    ("sopdt_clean", "eiv", 0, 15, False),
    ("sopdt_step", "elms", 0, 30, True),
    ("fopdt_noisy", "elms", 0, 20, False),
    ("fopdt_noisy", "eiv", 0, 20, False),
    ("sopdt_noisy", "elms", 0, 20, False),
    ("sopdt_noisy", "eiv", 0, 20, False),
)


def cases():
    recs = {r["name"]: r for r in records()}
    out = []
    for rec_name, method, dmin, dmax, whole in CASES:
        r = recs[rec_name]
        order = 1 if r["truth"][0] == "fopdt" else 2
        costs, best = ref.scan(r["u"], r["y"], r["Ts"], order, method, dmin, dmax, whole)
        out.append(dict(rec=r, method=method, order=order, dmin=dmin, dmax=dmax, whole=whole,
                        costs=costs, best=best))
    return out


def _params(order, model):
    if order == 1:
        return [model["K"], model["tau"], 0.0]
    return [model["k"], model["a"], model["b"]]


def generate():
    recs = records()
    body = [
        "typedef struct ls_vec_record {\n"
        "    const char *name;\n"
        "    size_t n;\n"
        "    double Ts;\n"
        "    const double *u;\n"
        "    const double *y;\n"
        "    int noisy;          /* 1: noise added (and quantised) */\n"
        "    size_t true_delay;  /* samples */\n"
        "    double truth[3];    /* FOPDT K, tau, 0; SOPDT k, a, b (form 2) */\n"
        "} ls_vec_record_t;\n\n"
        "typedef struct ls_vec_case {\n"
        "    int record;         /* index into ls_vec_records */\n"
        "    int order;          /* 1 FOPDT, 2 SOPDT */\n"
        "    int eiv;            /* 0 ELMS, 1 EIV */\n"
        "    int whole_record;\n"
        "    size_t delay_min, delay_max;\n"
        "    const double *costs; /* delay_max - delay_min + 1; -1: skipped */\n"
        "    size_t delay;       /* chosen */\n"
        "    double cost, u0, y0;\n"
        "    double model[3];    /* as truth */\n"
        "    double a[2], b[2];  /* A = 1 + a[0] q + a[1] q^2, B = b[0] q + b[1] q^2 */\n"
        "} ls_vec_case_t;\n",
    ]
    index = {}
    for i, r in enumerate(recs):
        index[r["name"]] = i
        body.append(_emit.array("double", f"ls_vec_{r['name']}_u", r["u"]))
        body.append(_emit.array("double", f"ls_vec_{r['name']}_y", r["y"]))
    rec_rows = []
    for r in recs:
        tr = list(r["truth"][1:]) + ([0.0] if r["truth"][0] == "fopdt" else [])
        rec_rows.append(
            f"    {{\"{r['name']}\", {len(r['u'])}u, {_emit.num(r['Ts'])}, ls_vec_{r['name']}_u, "
            f"ls_vec_{r['name']}_y, {int(r['noisy'])}, {r['delay']}u, "
            f"{{{', '.join(_emit.num(v) for v in tr)}}}}},")
    body.append("static const ls_vec_record_t ls_vec_records[] = {\n" + "\n".join(rec_rows)
                + "\n};\n")
    case_rows = []
    for i, c in enumerate(cases()):
        best = c["best"]
        costs = [v if np.isfinite(v) else -1.0 for v in c["costs"]]
        body.append(_emit.array("double", f"ls_vec_costs_{i}", costs))
        a = list(best["a"][1:]) + [0.0] * (3 - len(best["a"]))
        b = list(best["b"]) + [0.0] * (2 - len(best["b"]))
        case_rows.append(
            f"    {{{index[c['rec']['name']]}, {c['order']}, {int(c['method'] == 'eiv')}, "
            f"{int(c['whole'])}, {c['dmin']}u, {c['dmax']}u, ls_vec_costs_{i}, "
            f"{best['delay']}u, {_emit.num(best['cost'])}, {_emit.num(best['u0'])}, "
            f"{_emit.num(best['y0'])}, "
            f"{{{', '.join(_emit.num(v) for v in _params(c['order'], best['model']))}}}, "
            f"{{{_emit.num(a[0])}, {_emit.num(a[1])}}}, {{{_emit.num(b[0])}, {_emit.num(b[1])}}}}},")
    body.append("static const ls_vec_case_t ls_vec_cases[] = {\n" + "\n".join(case_rows)
                + "\n};\n")
    return {FILE: _emit.header(FILE, "\n".join(body), "tools/vectorgen/ls.py")}
