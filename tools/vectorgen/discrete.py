"""Test vectors of the discretisation (lib/src/pdt_discrete.c) from
pdtref.discrete.

ZOH coefficients for the model sweep of vectorgen.model, each at several
sampling periods (Ts / time scale from about 0.004 to 1) and dead times
(l + f) Ts with f = 0, a tiny f, f = 0.375, 0.5 and f near 1, including
Td < Ts. Ts is a power of two and l + f a short binary fraction, so Td / Ts
is exact in float and double and both sides split the delay alike.

The header stores, per case i (DISC_VEC_COUNT of them):
- ``disc_model[i]``: index into model_vectors.h; ``disc_par[3 i ..]``: Ts,
  Td (replacing the model's), and f; ``disc_delay[i]``: l;
- ``disc_a[2 i ..]``, ``disc_b[3 i ..]``, ``disc_d[2 i ..]``: a, b and the delta
  form d (pdt_discrete.h) of the reference;
- ``disc_int_b[3 i ..]``: b of the integer-delay model with delay l
  (pdt_discrete_init_int), whose a and d equal the above.

And for simulation and prediction, DISC_SIM_CASES cases (``disc_sim_case``
indexes the cases above) over DISC_SIM_N samples: ``disc_u`` (pseudo-random
steps from splitmix64 integers, in units of 1/64), ``disc_ymeas`` (the simulated
output plus integer noise, rounded to float32), ``disc_ysim`` (simulate) and
``disc_yhat`` (predict from disc_u, disc_ymeas), all computed by the
reference from the reference coefficients rounded to float32 (the C test
uses the same rounded coefficients, so it checks simulate/predict alone).
"""
import numpy as np

from pdtref import discrete as D
from pdtref import models as M
from pdtsupport.rng import SplitMix64 as Rng

from . import _emit
from .model import sweep

FILE = "discrete_vectors.h"
SIM_N = 256
FRACS = (0.0, 2.0 ** -12, 0.375, 0.5, 1.0 - 2.0 ** -10)
WHOLE = (0, 3, 1, 7, 2)


def f32(x):
    return float(np.float32(x))


def draws(seed, count):
    """`count` integers in [-64, 63]: the top 7 bits of splitmix64, less 64."""
    return Rng.keyed(seed).bits(7, count, 64)


def with_td(m, Td):
    return m._replace(Td=Td)


def pow2_near(x):
    return 2.0 ** round(np.log2(x))


def cases():
    out = []
    j = 0
    for idx, (m, scale) in enumerate(sweep()):
        base = pow2_near(scale)
        for rel in (2.0 ** -8, 2.0 ** -6, 2.0 ** -4, 2.0 ** -2, 1.0):
            Ts = base * rel
            for _ in range(2):
                f = FRACS[j % len(FRACS)]
                l = WHOLE[(j // len(FRACS)) % len(WHOLE)]
                j += 1
                out.append((idx, with_td(m, (l + f) * Ts), Ts, l, f))
    return out


def generate():
    cs = cases()
    midx, par, delay, aa, bb, dd, bi = [], [], [], [], [], [], []
    discs = []
    for idx, m, Ts, l, f in cs:
        d = D.zoh(m, Ts)
        assert d.delay == l, (m, Ts, d.delay, l)
        di = D.zoh_int(m, Ts, l)
        midx.append(idx)
        par += [Ts, m.Td, f]
        delay.append(l)
        aa += list(d.a)
        bb += list(d.b)
        dd += list(D.delta(m, Ts))
        bi += list(di.b)
        discs.append(d)

    # simulation / prediction on a few cases: FOPDT, SOPDT overdamped fine
    # sampling, underdamped, integrating, critically damped
    pick = []
    for want in (0, 5, 13, 19, 9):
        pick.append(next(i for i, c in enumerate(cs) if c[0] == want and c[3] >= 1))
    sim_case, us, yms, ysims, yhats = [], [], [], [], []
    for n_case, ci in enumerate(pick):
        d = discs[ci]
        d32 = D.Discrete(d.delay, d.order, tuple(f32(v) for v in d.a),
                         tuple(f32(v) for v in d.b))
        u = np.array(draws(0xD15C0000 + n_case, SIM_N), dtype=float) / 64.0
        # hold each value for 8 samples so the output moves
        u = np.repeat(u[::8], 8)[:SIM_N]
        ysim = D.simulate(d32, u)
        noise = np.array(draws(0xA0153000 + n_case, SIM_N), dtype=float) / 64.0
        scale = max(np.max(np.abs(ysim)), 1e-3)
        ymeas = np.array([f32(v) for v in ysim + 0.01 * scale * noise])
        yhat = D.predict(d32, u, ymeas)
        sim_case.append(ci)
        us += list(u)
        yms += list(ymeas)
        ysims += list(ysim)
        yhats += list(yhat)

    body = (
        f"#define DISC_VEC_COUNT {len(cs)}\n#define DISC_SIM_CASES {len(pick)}\n"
        f"#define DISC_SIM_N {SIM_N}\n\n"
        + _emit.int_array("int", "disc_model", midx)
        + _emit.array("double", "disc_par", par)
        + _emit.int_array("int", "disc_delay", delay)
        + _emit.array("double", "disc_a", aa)
        + _emit.array("double", "disc_b", bb)
        + _emit.array("double", "disc_d", dd)
        + _emit.array("double", "disc_int_b", bi)
        + _emit.int_array("int", "disc_sim_case", sim_case)
        + _emit.array("double", "disc_u", us)
        + _emit.array("double", "disc_ymeas", yms)
        + _emit.array("double", "disc_ysim", ysims)
        + _emit.array("double", "disc_yhat", yhats)
    )
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/discrete.py (pdtref.discrete)")}
