"""Test vectors of the model validation (lib/src/pdt_validate.c) from
pdtref.validate.

Three records of n samples at Ts (inputs and outputs rounded to float32, so
both C builds see the numbers the reference used): a FOPDT and a SOPDT
plant under a random binary input with noise, each validated with a model
near the truth, and a lead-lag plant validated with a FOPDT (the residual
then depends on the input). Per case the header stores the model
(``val_vec_kind``, ``val_vec_par``: K, tau, Td, 0 or k, a, b, Td), y0,
the record (``val_vec_u``, ``val_vec_y``), the gains of the robust bound
(SIMC PI of the model) and the reference's answers (``val_vec_out``):
sigma, aic, bic, white_stat, inflation, cross_stat, fir_lag, the FIR's
taps, the std of each parameter (0 past the count), the robust bound.
"""
import numpy as np

from pdtref import discrete as D
from pdtref import models as M
from pdtref import tune as T
from pdtref import validate as V

from . import _emit
from pdtsupport.rng import SplitMix64 as Rng

FILE = "validate_vectors.h"
N = 300
TS = 0.5
NOUT = 7 + V.FIR + 5 + 1


def f32(x):
    return np.asarray(x, dtype=np.float32).astype(float)


def record(seed, plants, noise):
    r = Rng.keyed(seed)
    u = np.concatenate([np.zeros(10), r.signs(N - 10, 8)])
    u = f32(10.0 + u)
    du = u - u[0]
    y = 5.0 + sum(D.simulate(D.zoh(p, TS), du) for p in plants) + r.noise(noise, N)
    return u, f32(y)


def cases():
    fo = M.Fopdt(2.0, 5.0, 1.5)
    so = M.sopdt_from_tc(1.5, 4.0, 2.0, 0.7)
    lead_a = M.Fopdt(2.0 / 3.0, 4.0, 0.5)
    lead_b = M.Fopdt(1.0 / 3.0, 1.0, 0.5)
    out = []
    u, y = record(11, [fo], 0.1)
    out.append((M.Fopdt(*f32([2.02, 5.1, 1.45])), u, y))
    u, y = record(12, [so], 0.05)
    out.append((M.Sopdt(*f32(list(so))), u, y))
    u, y = record(13, [lead_a, lead_b], 0.02)
    out.append((M.Fopdt(*f32([1.0, 3.0, 0.6])), u, y))
    return out


def generate():
    kind, par, us, ys, gains, outs = [], [], [], [], [], []
    for m, u, y in cases():
        y0 = 5.0
        res = V.validate(m, u, y, TS, y0)
        st, tr = T.compute(m, T.SIMC, T.PI)
        assert st == 0
        g = f32([tr["ideal"]["Kc"], tr["ideal"]["tauI"], 0.0, 0.0])
        ms = V.margin(res, list(g))
        kind.append(1 if isinstance(m, M.Fopdt) else 2)
        p = list(m) + ([0.0] if isinstance(m, M.Fopdt) else [])
        par.extend(p + [y0])
        us.extend(u)
        ys.extend(y)
        gains.extend(g)
        std = list(res["std"]) + [0.0] * (5 - len(res["std"]))
        outs.extend([res["sigma"], res["aic"], res["bic"], res["white_stat"],
                     res["inflation"], res["cross_stat"], float(res["fir_lag"])]
                    + list(res["fir"]) + std + [ms])
    body = (f"#define VAL_VEC_COUNT {len(kind)}\n#define VAL_VEC_N {N}\n"
            f"#define VAL_VEC_TS {TS!r}\n#define VAL_VEC_NOUT {NOUT}\n\n"
            + _emit.int_array("int", "val_vec_kind", kind)
            + _emit.array("double", "val_vec_par", par, per_line=5)
            + _emit.array("double", "val_vec_gains", gains)
            + _emit.array("double", "val_vec_out", outs)
            + _emit.array("double", "val_vec_u", us, per_line=6)
            + _emit.array("double", "val_vec_y", ys, per_line=6))
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/validate.py")}
