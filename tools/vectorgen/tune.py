"""Test vectors of the tuning rules (lib/src/pdt_tune.c) from pdtref.tune.

Models (rounded to float32 first, so both C builds see the numbers the
reference used): FOPDT over tau/Td from 0.01 to 100 and without dead time,
real-pole, complex-pole and integrating SOPDT, negative gains, and the
half-rule models of the paper's test system (17). Every rule x form runs on
every model with the default knob, plus knob and filter variants.

The header stores, per case i (TUNE_VEC_COUNT of them):
- ``tune_vec_kind[i]`` (1 FOPDT, 2 SOPDT), ``tune_vec_par[4 i ..]`` (K, tau,
  Td, 0 or k, a, b, Td);
- ``tune_vec_rule[i]``, ``tune_vec_form[i]`` (the C enums), ``tune_vec_cfg[2 i ..]``
  (knob: tau_c or lambda, 0 for the default; deriv_filter);
- ``tune_vec_status[i]``: what pdt_tune_compute returns with fit = 100 and
  ms_max = 0;
- ``tune_vec_out[TUNE_VEC_NOUT i ..]``: ideal Kc, tauI, tauD, Tf; series Kc,
  tauI, tauD, Tf; series_exists, series_rule; knob; Ms, w_ms (0 when a
  second local maximum of |S| comes within 1 % of Ms, so that where the
  peak lies is not well defined; -1 for +infinity), gain margin (0 for none), w_pc, phase
  margin (deg), w_gc. Zeros when status != 0.

And robustness of given gains (``tune_rob_*``, TUNE_ROB_COUNT cases):
kind, model, ideal gains (Kc, tauI, tauD, Tf), status, and Ms, w_ms, gain
margin, w_pc, phase margin, w_gc.
"""
import math

import numpy as np

from pdtref import models as M
from pdtref import tune as T

from . import _emit

FILE = "tune_vectors.h"
NOUT = 17


def f32(x):
    return float(np.float32(x))


def fop(K, tau, Td):
    return M.Fopdt(f32(K), f32(tau), f32(Td))


def sop(m):
    return M.Sopdt(f32(m.k), f32(m.a), f32(m.b), f32(m.Td))


def models():
    return [
        fop(1.0, 2.5, 1.47),            # (17), Skogestad's half rule
        fop(1.0, 2.4, 1.55),            # (17), the paper's GA
        fop(2.0, 10.0, 1.0),            # lag-dominant
        fop(0.5, 1.0, 5.0),             # delay-dominant
        fop(1.0, 0.1, 10.0),            # delay-dominant: ZN PID unstable
        fop(1.0, 100.0, 1.0),           # almost integrating
        fop(-1.5, 3.0, 0.6),            # reverse acting
        fop(3.0, 0.2, 0.05),            # fast
        fop(1.0, 1.0, 0.0),             # no dead time
        sop(M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77)),     # (17), Skogestad
        sop(M.sopdt_from_tc(1.0, 2.2, 0.74, 1.0)),     # (17), GA chirp
        sop(M.sopdt_from_tc(1.0, 3.56, 1.6, 0.9)),     # Table 3
        sop(M.sopdt_from_tc(2.0, 10.0, 0.05, 0.5)),    # widely separated
        sop(M.sopdt_from_tc(-1.0, 1.0, 0.9, 0.1)),     # reverse, near critical
        sop(M.sopdt_from_natural(1.3, 2.0, 0.5, 0.4)), # underdamped
        sop(M.sopdt_from_tc(1.0, 2.9, 0.5, 0.79, complex=True)),  # Sung2
        sop(M.sopdt_from_tc(1.0, 1.0, 0.5, 0.0)),      # no dead time
        sop(M.sopdt_from_integ(0.5, 2.0, 0.33)),       # integrating
        sop(M.sopdt_from_integ(-1.2, 0.1, 0.5)),       # integrating, reverse
        sop(M.sopdt_from_integ(1.0, 1.0, 0.0)),        # integrating, no delay
    ]


def cases():
    out = []
    for m in models():
        for rule in (T.SIMC, T.IMC, T.AMIGO, T.ZN):
            for form in (T.PI, T.PID):
                out.append((m, rule, form, 0.0, 10.0))
    ms = models()
    m17, s17 = ms[0], ms[9]
    out += [
        (m17, T.SIMC, T.PI, 0.5, 10.0),     # tau_c = theta / 3: faster
        (m17, T.SIMC, T.PI, 4.0, 10.0),
        (m17, T.IMC, T.PI, 0.8, 10.0),
        (m17, T.IMC, T.PID, 1.0, 5.0),
        (ms[8], T.SIMC, T.PI, 0.5, 10.0),  # no dead time, tau_c set
        (s17, T.SIMC, T.PID, 0.0, 0.0),     # unfiltered derivative
        (s17, T.IMC, T.PID, 0.0, 0.0),
        (s17, T.SIMC, T.PID, 0.3, 20.0),
        (ms[14], T.SIMC, T.PID, 0.0, 0.0),
        (ms[17], T.SIMC, T.PID, 0.0, 0.0),
        (ms[17], T.IMC, T.PI, 5.0, 10.0),
    ]
    return out


def rob_cases():
    ms = models()
    m17, s17, under, integ = ms[0], ms[9], ms[14], ms[17]
    Ku, Pu = T.ultimate(m17)
    g = T.gains
    return [
        (m17, g(0.85, 2.5)),
        (m17, g(0.9 * Ku, 2.5)),          # stable, poorly damped
        (m17, g(1.1 * Ku, 1e3)),          # beyond the ultimate gain
        (m17, g(0.6 * Ku, Pu / 2, Pu / 8, Pu / 80)),
        (s17, g(2.0, 3.2, 0.75, 0.0)),    # unfiltered, SOPDT rolls off
        (s17, g(-2.0, 3.2, 0.75, 0.1)),   # wrong sign
        (under, g(0.3, 1.0)),             # resonance
        (under, g(1.5, 0.3)),
        (integ, g(0.4, 8.0)),
        (integ, g(0.4, 1.0)),             # too little integral time
        (integ, g(1.0, 6.0, 2.0, 0.2)),
    ]


def _fig_row(fig):
    gm = fig["gm"] if math.isfinite(fig["gm"]) else 0.0
    # a runner-up peak within 1 % makes the place of the peak ambiguous
    w_ms = fig["w_ms"]
    if fig["ms2"] > 0.99 * fig["Ms"]:
        w_ms = 0.0
    elif not math.isfinite(w_ms):
        w_ms = -1.0
    return [fig["Ms"], w_ms, gm, fig["w_pc"], fig["pm_deg"], fig["w_gc"]]


def _par(m):
    if isinstance(m, M.Fopdt):
        return 1, [m.K, m.tau, m.Td, 0.0]
    return 2, [m.k, m.a, m.b, m.Td]


def generate():
    kind, par, rule, form, cfg, status, out = [], [], [], [], [], [], []
    for m, r, f, knob, nf in cases():
        k, p = _par(m)
        kind.append(k)
        par += p
        rule.append(r)
        form.append(f)
        cfg += [knob, nf]
        st, res = T.compute(m, r, f, knob=knob, deriv_filter=nf, fit=100.0, ms_max=0.0)
        status.append(st)
        if st != T.OK:
            out += [0.0] * NOUT
            continue
        gi, gs = res["ideal"], res["series"]
        row = [gi["Kc"], gi["tauI"], gi["tauD"], gi["Tf"]]
        row += [gs["Kc"], gs["tauI"], gs["tauD"], gs["Tf"]] if gs else [0.0] * 4
        row += [1.0 if gs else 0.0, 1.0 if res["series_rule"] else 0.0, res["knob"]]
        row += _fig_row(res["fig"])
        assert len(row) == NOUT
        out += row

    rkind, rpar, rgain, rstat, rout = [], [], [], [], []
    for m, g in rob_cases():
        k, p = _par(m)
        rkind.append(k)
        rpar += p
        g = {key: f32(val) for key, val in g.items()}
        rgain += [g["Kc"], g["tauI"], g["tauD"], g["Tf"]]
        try:
            rout += _fig_row(T.robustness(m, g))
            rstat.append(T.OK)
        except T.TuneError as e:
            rstat.append(e.status)
            rout += [0.0] * 6

    body = (
        f"#define TUNE_VEC_COUNT {len(kind)}u\n#define TUNE_VEC_NOUT {NOUT}u\n"
        f"#define TUNE_ROB_COUNT {len(rkind)}u\n\n"
        + _emit.int_array("int", "tune_vec_kind", kind)
        + _emit.array("double", "tune_vec_par", par)
        + _emit.int_array("int", "tune_vec_rule", rule)
        + _emit.int_array("int", "tune_vec_form", form)
        + _emit.array("double", "tune_vec_cfg", cfg)
        + _emit.int_array("int", "tune_vec_status", status)
        + _emit.array("double", "tune_vec_out", out)
        + _emit.int_array("int", "tune_rob_kind", rkind)
        + _emit.array("double", "tune_rob_par", rpar)
        + _emit.array("double", "tune_rob_gain", rgain)
        + _emit.int_array("int", "tune_rob_status", rstat)
        + _emit.array("double", "tune_rob_out", rout)
    )
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/tune.py")}
