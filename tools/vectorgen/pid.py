"""Test vectors of the PID controller (lib/src/pdt_pid.c) from pdtref.pid.

Two sets (numbers rounded to float32 first, so both C builds see the
numbers the reference used):

Scenarios (``pid_sc_*``, PID_SC_COUNT of them): a configuration and a start
output, then PID_SC_STEPS operations, each an update (op 0: sp, pv), a
track (op 1: sp, pv, the applied output) or a bumpless change to the
scenario's second configuration (op 2, then an update with sp, pv). Stored:
``pid_sc_cfg[PID_CFG_N i ..]`` (two configurations per scenario: Ts, form,
Kc, Ti, Td, Tf, N, b, c, u_min, u_max, rate_max, antiwindup, Tt),
``pid_sc_u0[i]``, ``pid_sc_op``, ``pid_sc_in`` (sp, pv, u per step) and
``pid_sc_out``: the output after every step (the tracked output for op 1).

Closed loops (``pid_cl_*``, PID_CL_COUNT cases): SIMC gains on the paper's
half-rule FOPDT and SOPDT of (17), a set-point step (r = 1) or a load step
at the plant's input (d = 1), scan periods 0.01 s and 0.1 s. Stored per
case: the PID configuration, the plant sampled exactly at Ts (l, Phi, G0,
G1, C, order 1 or 2: x(k+1) = Phi x(k) + G0 w(k-l) + G1 w(k-l-1),
y = C x, w = u + d), r and d, and on the grid t = 0, 0.1, ..., PID_CL_T s:
the discrete loop's y (pdtref.pid.discrete_loop), the continuous loop's y
(pdtref.pid.continuous_loop), and the continuous loop's y with the dead
time lengthened by Ts / 2.
"""
import numpy as np

from pdtref import models as M
from pdtref import pid as P
from pdtref import tune as T

from . import _emit
from pdtsupport.rng import SplitMix64 as Rng

FILE = "pid_vectors.h"
STEPS = 80
CFG_KEYS = ("Ts", "form", "Kc", "Ti", "Td", "Tf", "N", "b", "c", "u_min", "u_max",
            "rate_max", "antiwindup", "Tt")
T_END = 25.0
GRID = 0.1


def f32(x):
    return float(np.float32(x))


def cfg32(**kw):
    c = P.config(**kw)
    return {k: f32(v) if isinstance(v, float) else v for k, v in c.items()}


def scenarios():
    """(name, cfg, cfg2, u0, ops); ops a list of (op, sp, pv, u)."""
    rng = Rng.keyed(20240611)
    out = []

    def walk(n, scale, start=0.0):
        x, v = start, []
        for _ in range(n):
            x += scale * (rng.uniform() - 0.5)
            v.append(f32(x))
        return v

    def sps(n, levels):
        per = n // len(levels)
        return [f32(levels[min(k // per, len(levels) - 1)]) for k in range(n)]

    def upd(sp, pv):
        return [(0, s, p, 0.0) for s, p in zip(sp, pv)]

    # Two-degree-of-freedom PID, ideal, N filter, no saturation.
    c = cfg32(Ts=0.1, Kc=1.7, Ti=3.0, Td=0.6, N=8.0, b=0.7, c=0.5, u_min=-1e3, u_max=1e3)
    out.append(("ideal 2dof", c, c, 5.0, upd(sps(STEPS, [1.0, 3.0, -2.0]), walk(STEPS, 0.4))))
    # Series form with its own filter time, derivative on the measurement.
    c = cfg32(Ts=0.05, form=P.SERIES, Kc=1.3, Ti=2.0, Td=1.2, Tf=0.12, u_min=-1e3, u_max=1e3)
    out.append(("series", c, c, 0.0, upd(sps(STEPS, [0.0, 2.0]), walk(STEPS, 0.3))))
    # Saturation: each anti-windup mode on the same data.
    sp = sps(STEPS, [20.0, 0.0])
    pv = walk(STEPS, 0.2)
    for aw in (P.AW_BACK_CALC, P.AW_CONDITIONAL, P.AW_BOTH, P.AW_NONE):
        c = cfg32(Ts=0.2, Kc=0.8, Ti=1.5, u_min=0.0, u_max=10.0, antiwindup=aw)
        out.append((f"windup {aw}", c, c, 2.0, upd(sp, pv)))
    # A given tracking time and a PID's default one.
    c = cfg32(Ts=0.2, Kc=0.8, Ti=1.5, Td=0.3, u_min=0.0, u_max=10.0, Tt=0.7)
    out.append(("tracking time", c, c, 2.0, upd(sp, pv)))
    # Rate limit.
    c = cfg32(Ts=0.1, Kc=2.0, Ti=4.0, u_min=-50.0, u_max=50.0, rate_max=5.0)
    out.append(("rate", c, c, 0.0, upd(sps(STEPS, [4.0, -4.0, 0.0]), walk(STEPS, 0.1))))
    # Unfiltered derivative, PD without integral action, a start outside the limits.
    c = cfg32(Ts=0.1, Kc=1.1, Ti=0.0, Td=0.4, N=0.0, b=1.0, c=1.0, u_min=-5.0, u_max=5.0)
    out.append(("pd unfiltered", c, c, 7.0, upd(sps(STEPS, [0.5, 1.5]), walk(STEPS, 0.2))))
    # Manual / automatic / gain change: update, track a ramp, update, change.
    c = cfg32(Ts=0.1, Kc=1.5, Ti=2.5, Td=0.5, N=10.0, u_min=-100.0, u_max=100.0)
    c2 = cfg32(Ts=0.1, Kc=0.9, Ti=4.0, Td=0.2, N=5.0, b=0.5, u_min=-100.0, u_max=100.0)
    sp = sps(STEPS, [1.0, 2.0, 2.0, 0.5])
    pv = walk(STEPS, 0.3)
    ops = []
    for k in range(STEPS):
        q = k // 20
        if q == 1:
            ops.append((1, sp[k], pv[k], f32(3.0 + 0.25 * (k - 20))))
        elif k == 60:
            ops.append((2, sp[k], pv[k], 0.0))
        else:
            ops.append((0, sp[k], pv[k], 0.0))
    out.append(("manual auto gains", c, c2, 1.0, ops))
    # Direct action (negative gain), SERIES PI, tracked before the first update.
    c = cfg32(Ts=0.5, form=P.SERIES, Kc=-0.6, Ti=5.0, u_min=0.0, u_max=100.0)
    ops = [(1, 10.0, 10.0, 40.0)] + upd(sps(STEPS - 1, [10.0, 12.0]), walk(STEPS - 1, 0.5, 10.0))
    out.append(("direct acting", c, c, 0.0, ops))
    return out


def run_scenario(cfg, cfg2, u0, ops):
    pid = P.Pid(cfg, u0)
    res = []
    for op, sp, pv, u in ops:
        if op == 1:
            pid.track(sp, pv, u)
            res.append(u)
            continue
        if op == 2:
            pid.set_config(cfg2)
        res.append(pid.update(sp, pv))
    return res


def loop_cases():
    """(model, pid cfg, ideal gains for the continuous loop)."""
    cases = []
    for m, form in ((M.Fopdt(1.0, 2.5, 1.47), T.PI),
                    (M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77), T.PID)):
        st, r = T.compute(m, T.SIMC, form)
        assert st == 0
        s = {k: f32(v) for k, v in r["series"].items()}
        ideal = T.series_to_ideal(s)
        cases.append((m, s, (ideal["Kc"], ideal["tauI"], ideal["tauD"], ideal["Tf"])))
    return cases


def closed_loops():
    t = np.arange(0.0, T_END + GRID / 2, GRID)
    rows = []
    for m, s, ideal in loop_cases():
        for r, d in ((1.0, 0.0), (0.0, 1.0)):
            yc = P.continuous_loop(m, ideal, t, r=r, d=d)
            for Ts in (0.01, 0.1):
                cfg = cfg32(Ts=Ts, form=P.SERIES, Kc=s["Kc"], Ti=s["tauI"], Td=s["tauD"],
                            Tf=s["Tf"], N=0.0, u_min=-100.0, u_max=100.0)
                n = int(round(T_END / Ts)) + 1
                yd, _ = P.discrete_loop(m, cfg, n, r=r, d=d)
                step = int(round(GRID / Ts))
                mh = m._replace(Td=m.Td + Ts / 2)
                yh = P.continuous_loop(mh, ideal, t, r=r, d=d)
                rows.append((m, cfg, r, d, yd[::step], yc, yh))
    return rows


def generate():
    sc = scenarios()
    cfgs, u0s, opv, ins, outs = [], [], [], [], []
    for _name, c, c2, u0, ops in sc:
        assert len(ops) == STEPS
        cfgs += [c[k] for k in CFG_KEYS] + [c2[k] for k in CFG_KEYS]
        u0s.append(u0)
        opv += [o[0] for o in ops]
        for o in ops:
            ins += [o[1], o[2], o[3]]
        outs += run_scenario(c, c2, u0, ops)
    body = [f"#define PID_SC_COUNT {len(sc)}u\n#define PID_SC_STEPS {STEPS}u\n"
            f"#define PID_CFG_N {len(CFG_KEYS)}u\n",
            _emit.array("double", "pid_sc_cfg", cfgs, 7),
            _emit.array("double", "pid_sc_u0", u0s),
            _emit.int_array("int", "pid_sc_op", opv, 20),
            _emit.array("double", "pid_sc_in", ins, 6),
            _emit.array("double", "pid_sc_out", outs)]

    rows = closed_loops()
    npts = len(rows[0][4])
    cl_cfg, cl_plant, cl_rd, yd_all, yc_all, yh_all, cl_l = [], [], [], [], [], [], []
    for m, cfg, r, d, yd, yc, yh in rows:
        cl_cfg += [cfg[k] for k in CFG_KEYS]
        l, Phi, G0, G1, C = P.plant_sampled(m, cfg["Ts"])
        n = Phi.shape[0]
        ph = np.zeros(4)
        ph[:n * n] = Phi.reshape(-1)
        g0 = np.zeros(2)
        g1 = np.zeros(2)
        cc = np.zeros(2)
        g0[:n], g1[:n], cc[:n] = G0, G1, C
        cl_plant += list(ph) + list(g0) + list(g1) + list(cc)
        cl_l += [l, n]
        cl_rd += [r, d]
        yd_all += list(yd)
        yc_all += list(yc)
        yh_all += list(yh)
    body += [f"#define PID_CL_COUNT {len(rows)}u\n#define PID_CL_POINTS {npts}u\n"
             f"#define PID_CL_GRID {GRID}\n#define PID_CL_T {T_END}\n",
             _emit.array("double", "pid_cl_cfg", cl_cfg, 7),
             _emit.array("double", "pid_cl_plant", cl_plant),
             _emit.int_array("int", "pid_cl_l", cl_l),
             _emit.array("double", "pid_cl_rd", cl_rd),
             _emit.array("double", "pid_cl_yd", yd_all),
             _emit.array("double", "pid_cl_yc", yc_all),
             _emit.array("double", "pid_cl_yh", yh_all)]
    return {FILE: _emit.header(FILE, "\n".join(body), "tools/pdtref/pid.py")}
