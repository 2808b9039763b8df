"""Accuracy vectors of the identification's evaluation (pdt_cost_profile on
the simulation criterion over the whole record, offset fitted) from
pdtref.cost, over record lengths up to 10^4 samples and data scales from
1e-30 to 1e30.

The records are not stored: each is rebuilt by the C test from a few
numbers with the same double arithmetic (no fused operations): splitmix64
(pdtsupport.rng.SplitMix64, sim_rng64 in C) draws a +-1 input held `hold`
samples, a first-order plant x(k) = a x(k-1) + b u(k-1-l) runs on it in
double, noise (sums of four uniforms) is added, and both signals are mapped to su u + uoff and
sy y + yoff and rounded to float32. The reference works on those float32
values, so what is measured is the arithmetic of the float build, not the
rounding of its data. Per record three unit-gain shapes are profiled: a
FOPDT a little off the plant, an overdamped SOPDT, and an integrator with a
lag, whose ramp makes large sums.
"""
import numpy as np

from pdtref import cost as ref

from . import _emit
from pdtsupport import plant
from pdtsupport.rng import SplitMix64
from . import cost as base

FILE = "cost_accuracy_vectors.h"
TS = 0.5
DELAY_MAX = 50
PLANT_TAU = 6.0
PLANT_L = 3
PLANT_K = 1.7

# n, seed, hold, noise amplitude, su, sy, uoff/su, yoff/sy. The seeds are
# 10^6 apart: the stream of seed s + 1 is that of s one draw on, and a
# record draws at most about 41 000.
CASES = (
    (300, 11000000, 17, 0.02, 1.0, 1.0, 3.0, -2.0),
    (2000, 12000000, 37, 0.02, 1.0, 1.0, 3.0, 5.0),
    (10000, 13000000, 53, 0.005, 1.0, 1.0, 0.5, 20.0),
    (2000, 14000000, 29, 1e-4, 1.0, 1.0, 1.0, 1.0),
    (2000, 15000000, 37, 0.02, 1e-30, 1e-30, 3.0, 5.0),
    (2000, 16000000, 37, 0.02, 1e-12, 1e-12, 3.0, 5.0),
    (2000, 17000000, 37, 0.02, 1e12, 1e12, 3.0, 5.0),
    (2000, 18000000, 37, 0.02, 1e30, 1e30, 3.0, 5.0),
    (10000, 19000000, 53, 0.005, 1e-30, 1e-30, 0.5, 20.0),
    (10000, 20000000, 53, 0.005, 1e30, 1e30, 0.5, 20.0),
    (2000, 21000000, 37, 0.02, 1e-10, 1e10, 3.0, 5.0),
    (2000, 22000000, 37, 0.02, 1e10, 1e-10, 3.0, 5.0),
)

SHAPES = (
    base.Fopdt(1.0, PLANT_TAU * 1.05, PLANT_L * TS + 0.2),
    base.Sopdt(1.0, 1.0 / 2.5 + 1.0 / 3.0, 1.0 / (2.5 * 3.0), (PLANT_L - 2) * TS + 0.3),
    base.Sopdt(1.0, 0.5, 0.0, PLANT_L * TS),
)


def record(n, seed, hold, amp, su, sy, uoff, yoff):
    """The float32 record, as the C test rebuilds it (plant values in
    double, then scaled and rounded)."""
    a = float(np.exp(-TS / PLANT_TAU))
    b = PLANT_K * (1.0 - a)
    rng = SplitMix64(seed)
    u = rng.signs(n, hold)
    noise = rng.noise(amp, n)
    y = plant.first_order(PLANT_K, a, u, PLANT_L) + noise
    us = np.float32(su * u + uoff * su).astype(np.float64)
    ys = np.float32(sy * y + yoff * sy).astype(np.float64)
    return a, b, us, ys


def generate():
    lines = ["/* Plant of every record: x(k) = a x(k-1) + b u(k-1-l). */",
             f"#define CAV_TS {_emit.num(TS)}",
             f"#define CAV_DELAY_MAX {DELAY_MAX}u",
             f"#define CAV_PLANT_L {PLANT_L}u",
             f"#define CAV_NSHAPE {len(SHAPES)}u",
             "",
             "/* Unit-gain shapes: kind (1 FOPDT, 2 SOPDT), then K, tau, Td, 0 or",
             " * k, a, b, Td. */",
             "static const int cav_shape_kind[CAV_NSHAPE] = {"
             + ", ".join("1" if isinstance(m, base.Fopdt) else "2" for m in SHAPES) + "};"]
    params = []
    for m in SHAPES:
        params += list(m) + ([0.0] if isinstance(m, base.Fopdt) else [])
    lines.append(_emit.array("double", "cav_shape_param", params))
    lines += ["typedef struct cav_case {",
              "    size_t n;",
              "    unsigned seed, hold;",
              "    double amp, su, sy, uoff, yoff, a, b;",
              "    double u0, y0;            /* the cost's operating point (float values) */",
              "    double cost[CAV_NSHAPE];  /* reference, engineering units */",
              "    double gain[CAV_NSHAPE];",
              "    double offset[CAV_NSHAPE];",
              "    double gain_scale[CAV_NSHAPE]; /* max |y - y0| / max |unit-gain shape's output| */",
              "    double yrange;            /* max |y - y0|, the scale of offsets */",
              "} cav_case_t;", "",
              f"static const cav_case_t cav_cases[{len(CASES)}] = {{"]
    for n, seed, hold, amp, su, sy, uo, yo in CASES:
        a, b, u, y = record(n, seed, hold, amp, su, sy, uo, yo)
        u0, y0 = float(u[0]), float(y[0])
        yrange = float(np.max(np.abs(y - y0)))
        res, scales = [], []
        for m in SHAPES:
            dm = base.zoh(m, TS)
            r = ref.profile(u, y, m, dm, TS, "simulation", u0=u0, y0=y0, delay_max=DELAY_MAX,
                            estimate_offset=True, whole_record=True)
            res.append(r)
            # The gain that spans the output range with this shape: a
            # gain's error is measured against it (or the gain, if larger),
            # as the offset's against the range: a shape that does not fit
            # gets a gain near 0, whose relative error means nothing.
            scales.append(yrange / float(np.max(np.abs(ref.simulation_output(u, dm, u0)))))
        num = _emit.num
        lines.append(
            f"    {{{n}u, {seed}u, {hold}u, {num(amp)}, {num(su)}, {num(sy)}, {num(uo * su)}, "
            f"{num(yo * sy)}, {num(a)}, {num(b)}, {num(u0)}, {num(y0)},\n"
            f"     {{{', '.join(num(r['cost']) for r in res)}}},\n"
            f"     {{{', '.join(num(r['gain']) for r in res)}}},\n"
            f"     {{{', '.join(num(r['offset']) for r in res)}}},\n"
            f"     {{{', '.join(num(s) for s in scales)}}}, {num(yrange)}}},")
    lines.append("};")
    body = "\n".join(lines) + "\n"
    return {FILE: _emit.header(FILE, body, "tools/vectorgen/cost_accuracy.py")}
