"""Test vectors of expm1 and log1p (lib/src/pdt_math.c: the library's own,
for C libraries without them, PDT_MATH_FALLBACK) from numpy.

Arguments are float32 numbers (so the float and the double build see the
same x) over what the library passes: expm1 of -Ts / tau and of the
poles' -l Ts (tiny to -100, and up to 80 below float's overflow), log1p of
the least squares' pole estimates (just above -1 to large). Near 0 they
run over powers of two from 2^-60, where expm1 and log1p are x to
rounding, and both signs.

The header stores ``MATH_EXPM1_COUNT`` arguments ``math_expm1_x`` with
``math_expm1_y`` = numpy.expm1 (double), and likewise ``math_log1p_x``,
``math_log1p_y``.
"""
import numpy as np

from . import _emit

FILE = "math_vectors.h"


def f32(values):
    return sorted(set(float(np.float32(v)) for v in values))


def expm1_args():
    tiny = [s * 2.0 ** -k for k in range(1, 61, 3) for s in (1.0, -1.0)]
    grid = list(np.linspace(-100.0, 80.0, 181)) + list(np.linspace(-1.0, 1.0, 41))
    odd = [-1e-7, 3e-7, -0.3465, 0.3465, -0.6931, 0.6931, -17.5, -88.7, 60.0]
    return f32(tiny + grid + odd)


def log1p_args():
    tiny = [s * 2.0 ** -k for k in range(1, 61, 3) for s in (1.0, -1.0)]
    near_m1 = [-1.0 + 2.0 ** -k for k in range(2, 24, 3)]
    grid = list(np.linspace(-0.99, 10.0, 111))
    large = [10.0 ** e for e in range(2, 31, 4)]
    return f32(tiny + near_m1 + grid + large)


def generate():
    ex = expm1_args()
    lx = log1p_args()
    body = (
        f"#define MATH_EXPM1_COUNT {len(ex)}u\n"
        f"#define MATH_LOG1P_COUNT {len(lx)}u\n\n"
        + _emit.array("double", "math_expm1_x", ex)
        + _emit.array("double", "math_expm1_y", [float(np.expm1(x)) for x in ex])
        + _emit.array("double", "math_log1p_x", lx)
        + _emit.array("double", "math_log1p_y", [float(np.log1p(x)) for x in lx])
    )
    return {FILE: _emit.header(FILE, body, "numpy (expm1, log1p)")}
