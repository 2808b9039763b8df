"""Test vectors of the simulation cost's extra columns: the model's free
response from the first sample (pdt_cost_config_t.estimate_state) and a
linear drift (pdt_cost_config_t.drift), from pdtref.cost.profile_state.

Records cut mid-transient: the truth simulated exactly (vectorgen.cost's
step-response sum) over CUT samples of input before the record and the
record after, so that the record starts while the output still settles;
one record has a ramp added. Values quantised to 2^-12 (exact in float).
Every shape (unit gain) is profiled under every configuration of CONFIGS
(the paper's window, scored from l_u + order on, with first-order shapes
only).
"""
import numpy as np

from pdtref import cost as ref

from . import _emit
from . import cost as base

FILE = "cost_state_vectors.h"
CUT = 60

F, S = base.Fopdt, base.Sopdt

# name, truth, Ts, n, u0, y0, noise, seed, ramp per second, shapes (unit gain)
RECORDS = (
    ("fopdt_cut", F(1.5, 8.0, 1.3), 0.5, 240, 2.0, 10.0, 0.01, 11, 0.0,
     [F(1.0, 8.0, 1.3), F(1.0, 5.0, 0.9)]),
    ("sopdt_cut", S(2.16, 0.72, 1.44, 0.81), 0.25, 260, 0.0, 3.0, 0.01, 12, 0.0,
     [S(1.44, 0.72, 1.44, 0.81), S(1.0, 3.0, 1.44, 0.5)]),
    ("fopdt_ramp", F(-0.8, 5.0, 2.0), 0.5, 240, 1.0, -4.0, 0.01, 13, 0.01,
     [F(1.0, 5.0, 2.0), S(0.25, 1.25, 0.25, 2.2)]),
)

# name, estimate_offset, estimate_state, drift, whole_record
CONFIGS = (
    ("state", True, True, False, True),
    ("state_drift", True, True, True, True),
    ("drift", True, False, True, True),
    ("state_no_offset", False, True, False, True),
    ("state_window", True, True, False, False),
)
DELAY_MAX = 20


def _input(n, u0, seed):
    rng = base.Rng.keyed(seed)
    u = np.full(n, u0)
    k = 0
    while k < n:
        hold = rng.integers(6, 25)
        u[k:k + hold] = u0 + rng.uniform(lo=-1.0, hi=1.0)
        k += hold
    return base.quantise(u)


def record(entry):
    name, truth, Ts, n, u0, y0, noise, seed, ramp, shapes = entry
    u_all = _input(CUT + n, u0, seed)
    u_all[:5] = u0
    y_all = base.simulate_exact(truth, u_all, u0, Ts)
    rng = base.Rng.keyed(seed)
    t = np.arange(n) * Ts
    y = base.quantise(y0 + y_all[CUT:] + ramp * t + rng.noise(noise, n))
    return dict(name=name, Ts=Ts, n=n, u0=float(u_all[CUT]), y0=y0, u=u_all[CUT:], y=y,
                shapes=shapes)


def _kind(m):
    return 0 if isinstance(m, F) else 1


def _params(m):
    return [m.K, m.tau, m.Td, 0.0] if isinstance(m, F) else [m.k, m.a, m.b, m.Td]


def generate():
    recs = [record(e) for e in RECORDS]
    body = ["#define COST_STATE_DELAY_MAX %du\n\n" % DELAY_MAX]
    body.append(
        "/* One case: record, shape (kind 0 FOPDT K tau Td 0, 1 SOPDT k a b Td; unit\n"
        " * gain), configuration (estimate_offset, estimate_state, drift,\n"
        " * whole_record) and the reference: cost, gain, offset, x0, x1 (per s),\n"
        " * drift (per s). */\n"
        "typedef struct cost_state_case {\n"
        "    size_t rec;\n    int kind;\n    double p[4];\n    int flags[4];\n"
        "    double want[6];\n} cost_state_case_t;\n\n")
    cases = []
    for ri, rec in enumerate(recs):
        body.append(_emit.array("double", "cs_u_%d" % ri, rec["u"]))
        body.append(_emit.array("double", "cs_y_%d" % ri, rec["y"]))
        for m in rec["shapes"]:
            dm = base.zoh(m, rec["Ts"])
            for cfg in CONFIGS:
                _, ofs, st, dr, whole = cfg
                if not whole and not isinstance(m, F):
                    # Scored from l_u + 2 on, a SOPDT's fast mode has died
                    # out and its two sequences are one there: the C code
                    # holds one at 0 (PIVOT_MIN), numpy's minimum norm
                    # keeps both.
                    continue
                r = ref.profile_state(rec["u"], rec["y"], dm, rec["Ts"], rec["u0"], rec["y0"],
                                      DELAY_MAX, ofs, st, dr, whole)
                want = [r["cost"], r["gain"], r["offset"], r["x0"], r["x1"], r["drift"]]
                cases.append((ri, _kind(m), _params(m), [int(ofs), int(st), int(dr), int(whole)],
                               want))
    body.append("static const double *const cs_u[] = {%s};\n" %
                ", ".join("cs_u_%d" % i for i in range(len(recs))))
    body.append("static const double *const cs_y[] = {%s};\n" %
                ", ".join("cs_y_%d" % i for i in range(len(recs))))
    body.append(_emit.int_array("size_t", "cs_n", [r["n"] for r in recs]))
    body.append(_emit.array("double", "cs_Ts", [r["Ts"] for r in recs]))
    body.append(_emit.array("double", "cs_u0", [r["u0"] for r in recs]))
    body.append(_emit.array("double", "cs_y0", [r["y0"] for r in recs]))
    lines = []
    for ri, kind, p, fl, want in cases:
        lines.append("    {%du, %d, {%s}, {%s}, {%s}}," % (
            ri, kind, ", ".join(_emit.num(x) for x in p), ", ".join(str(f) for f in fl),
            ", ".join(_emit.num(x) for x in want)))
    body.append("static const cost_state_case_t cs_cases[%d] = {\n%s\n};\n"
                % (len(cases), "\n".join(lines)))
    return {FILE: _emit.header(FILE, "".join(body), "tools/vectorgen/cost_state.py")}
