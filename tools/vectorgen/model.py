"""Test vectors of the models (lib/src/pdt_model.c) from pdtref.models.

A sweep of FOPDT and SOPDT models (overdamped, critically damped,
underdamped with zeta 0.1 .. 0.9, widely separated poles, integrating,
negative gains). Every parameter, time and frequency is rounded to float32
first, so both C builds see exactly the numbers the reference used.

The header stores, per model i (MODEL_VEC_COUNT of them):
- ``model_kind[i]`` (1 FOPDT, 2 SOPDT) and ``model_par[4 i ..]``: K, tau, Td, 0
  or k, a, b, Td;
- ``model_t[MODEL_VEC_NT i ..]`` and ``model_step[..]``: times and the unit-step
  response, from just before the dead time to several time constants, with
  points close after the dead time where the response is tiny;
- ``model_w[MODEL_VEC_NW i ..]``, ``model_mag``, ``model_phase``: frequency
  response (w = 0 included);
- ``model_natural[4 i ..]`` (K, wn, zeta, Td), ``model_tc[5 i ..]``
  (K, T1, T2, complex, Td), ``model_integ[3 i ..]`` (Ki, T, Td) with
  ``model_forms[i]`` a bit mask of the forms that exist (1 natural, 2 tc,
  4 integ); rows of missing forms hold zeros.
"""
import numpy as np

from pdtref import models as M

from . import _emit

FILE = "model_vectors.h"
NT = 24
NW = 12


def f32(x):
    return float(np.float32(x))


def sweep():
    """(model, time scale) pairs; the scale sets the time and frequency grids."""
    out = []

    def fop(K, tau, Td):
        out.append((M.Fopdt(f32(K), f32(tau), f32(Td)), f32(tau)))

    def sop(m, scale):
        out.append((M.Sopdt(f32(m.k), f32(m.a), f32(m.b), f32(m.Td)), scale))

    fop(1.5, 2.0, 0.33)
    fop(-0.7, 0.05, 0.0)
    fop(1.0, 2.4, 1.55)
    fop(3.0, 100.0, 12.3)
    fop(0.2, 0.5, 0.0049)
    sop(M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77), 2.0)
    sop(M.sopdt_from_tc(1.0, 2.2, 0.74, 1.0), 2.2)
    sop(M.sopdt_from_tc(2.0, 10.0, 0.05, 0.5), 10.0)
    sop(M.sopdt_from_tc(-1.0, 1.0, 0.9, 0.1), 1.0)
    sop(M.Sopdt(1.0, 2.0, 1.0, 0.3), 1.0)           # critically damped, exact
    sop(M.Sopdt(4.0, 1.0, 0.25, 0.0), 2.0)          # critically damped, tau 2
    sop(M.sopdt_from_natural(1.0, 1.0, 0.999, 0.2), 1.0)
    sop(M.sopdt_from_natural(1.0, 1.0, 1.001, 0.2), 1.0)
    for zeta in (0.1, 0.3, 0.5, 0.7, 0.9):
        sop(M.sopdt_from_natural(1.3, 2.0, zeta, 0.4), 0.5)
    sop(M.sopdt_from_tc(1.0, 2.9, 0.5, 0.79, complex=True), 2.9)
    sop(M.sopdt_from_integ(0.5, 2.0, 0.33), 2.0)
    sop(M.sopdt_from_integ(-1.2, 0.1, 0.0), 0.5)
    return out


def times(m, scale):
    Td = m.Td
    rel = [-0.5, 0.0, 1e-4, 1e-3, 4e-3, 0.01, 0.03, 0.07, 0.1, 0.2, 0.3, 0.5,
           0.7, 1.0, 1.3, 1.7, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 12.0]
    assert len(rel) == NT
    return [f32(Td + r * scale) for r in rel]


def freqs(scale):
    rel = [0.0, 1e-3, 0.01, 0.1, 0.3, 0.7, 1.0, 1.5, 2.0, 5.0, 10.0, 100.0]
    assert len(rel) == NW
    return [f32(r / scale) for r in rel]


def forms(m):
    nat = (0.0, 0.0, 0.0, 0.0)
    tc = (0.0, 0.0, 0.0, 0.0, 0.0)
    integ = (0.0, 0.0, 0.0)
    mask = 0
    if isinstance(m, M.Sopdt):
        if m.b != 0:
            n = M.to_natural(m)
            nat = (n.K, n.wn, n.zeta, n.Td)
            t = M.to_tc(m)
            tc = (t.K, t.T1, t.T2, 1.0 if t.complex else 0.0, t.Td)
            mask |= 3
        else:
            g = M.to_integ(m)
            integ = (g.Ki, g.T, g.Td)
            mask |= 4
    return mask, nat, tc, integ


def generate():
    cases = sweep()
    kind, par, ts, ys, ws, mags, phs = [], [], [], [], [], [], []
    masks, nats, tcs, integs = [], [], [], []
    for m, scale in cases:
        if isinstance(m, M.Fopdt):
            kind.append(1)
            par += [m.K, m.tau, m.Td, 0.0]
        else:
            kind.append(2)
            par += [m.k, m.a, m.b, m.Td]
        t = times(m, scale)
        ts += t
        ys += list(M.step(m, t))
        w = freqs(scale)
        mag, ph = M.freq(m, w)
        if not np.isfinite(mag[0]):
            mag = mag.copy()
            mag[0] = 0.0  # the integrator's +inf at w = 0: the test checks it apart
        ws += w
        mags += list(mag)
        phs += list(ph)
        mask, nat, tc, integ = forms(m)
        masks.append(mask)
        nats += nat
        tcs += tc
        integs += integ
    body = (
        f"#define MODEL_VEC_COUNT {len(cases)}\n#define MODEL_VEC_NT {NT}\n"
        f"#define MODEL_VEC_NW {NW}\n\n"
        + _emit.int_array("int", "model_kind", kind)
        + _emit.array("double", "model_par", par)
        + _emit.array("double", "model_t", ts)
        + _emit.array("double", "model_step", ys)
        + _emit.array("double", "model_w", ws)
        + _emit.array("double", "model_mag", mags)
        + _emit.array("double", "model_phase", phs)
        + _emit.int_array("int", "model_forms", masks)
        + _emit.array("double", "model_natural", nats)
        + _emit.array("double", "model_tc", tcs)
        + _emit.array("double", "model_integ", integs)
    )
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/model.py (pdtref.models)")}
