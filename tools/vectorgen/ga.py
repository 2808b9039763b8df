"""Test vectors of the GA operators (lib/src/pdt_ga.c) from tools/pdtref/ga.py.

Every real input is rounded to float32 first, so the float and the double
build start from the very numbers the reference used; the expected outputs
are the reference's float64 results. The header stores

- ``ga_pcg_*``: 64 PCG32 outputs for each (seed, stream) pair and the
  uniform numbers the float (24-bit) and double (32-bit) builds make of them;
- ``ga_below_*``: 32 bounded integers for each n, each n from a freshly
  seeded generator (seed GA_BELOW_SEED + index, stream GA_BELOW_STREAM);
- ``ga_sbx_*``: bounded SBX on a grid (bounds x parent pairs x eta x u, in
  that loop order) plus pseudo-random cases stored row-wise
  (p1, p2, lo, hi, eta, u, c1, c2);
- ``ga_mut_*``: polynomial mutation on a grid (bounds x x x eta x u) plus
  pseudo-random rows (x, lo, hi, eta, u, y);
- ``ga_share_*``: small populations, concatenated, with their parameters;
- ``ga_tour_*``: tournaments on one shared-cost array (a, b, coin, winner).
"""
import numpy as np

from pdtref import ga
from pdtsupport.rng import SplitMix64

from . import _emit

FILE = "ga_vectors.h"
PCG_COUNT = 64
PCG_PAIRS = ((42, 54), (0, 0), (0xDEADBEEFCAFEF00D, 1), (123456789, 0xFFFFFFFFFFFFFFFF))
BELOW_N = (1, 2, 3, 7, 10, 1000, 0x80000001, 0xFFFFFFFF)
BELOW_COUNT = 32
BELOW_SEED = 2024
BELOW_STREAM = 7

ETAS = (1.0, 2.0, 15.0, 100.0)
U_GRID = (0.0, 0.15, 0.5, 0.85, 0.999, 1.0 - 2.0**-24)
BOUNDS = ((0.0, 1.0), (-5.0, 5.0), (-1e-6, 1e-6), (100.0, 100.0001), (0.5, 2000.0))
SBX_PAIRS = ((0.3, 0.6), (0.6, 0.3), (0.0, 0.5), (0.5, 1.0), (0.0, 1.0), (0.4, 0.4),
             (0.2, 0.201), (0.999, 1.0), (0.0, 0.001))
MUT_X = (0.0, 0.001, 0.25, 0.5, 0.9, 1.0)
MUT_U = (0.0, 0.1, 0.25, 0.5, 0.6, 0.9, 0.999, 1.0 - 2.0**-24)
RANDOM_CASES = 64


def f32(x):
    return float(np.float32(x))


U_GRID = tuple(f32(u) for u in U_GRID)
MUT_U = tuple(f32(u) for u in MUT_U)


def inside(frac, lo, hi):
    """A float32 value at fraction frac of [lo, hi], kept inside."""
    return min(max(f32(lo + frac * (hi - lo)), lo), hi)


def hex_array(ctype, suffix, name, values, digits, per_line):
    items = [f"0x{int(v):0{digits}x}{suffix}" for v in values]
    lines = ["    " + ", ".join(items[i:i + per_line]) + ","
             for i in range(0, len(items), per_line)]
    return f"static const {ctype} {name}[{len(items)}] = {{\n" + "\n".join(lines) + "\n};\n"


def pcg_part():
    seeds, streams, outs, unif_f, unif_d = [], [], [], [], []
    for seed, stream in PCG_PAIRS:
        seeds.append(seed)
        streams.append(stream)
        xs = ga.Pcg32(seed, stream).take(PCG_COUNT)
        outs += xs
        unif_f += [ga.uniform_float(x) for x in xs]
        unif_d += [ga.uniform_double(x) for x in xs]
    below = []
    for k, n in enumerate(BELOW_N):
        rng = ga.Pcg32(BELOW_SEED + k, BELOW_STREAM)
        below += [rng.below(n) for _ in range(BELOW_COUNT)]
    return "\n".join([
        f"#define GA_PCG_PAIRS {len(PCG_PAIRS)}\n#define GA_PCG_COUNT {PCG_COUNT}\n",
        hex_array("uint64_t", "ull", "ga_pcg_seed", seeds, 16, 3),
        hex_array("uint64_t", "ull", "ga_pcg_stream", streams, 16, 3),
        hex_array("uint32_t", "u", "ga_pcg_out", outs, 8, 6),
        "/* pdt_rng_uniform of the float build: (x >> 8) 2^-24 */\n"
        + _emit.array("double", "ga_pcg_unif_f", unif_f),
        "/* pdt_rng_uniform of the double build: x 2^-32 */\n"
        + _emit.array("double", "ga_pcg_unif_d", unif_d),
        f"#define GA_BELOW_SEED {BELOW_SEED}u\n#define GA_BELOW_STREAM {BELOW_STREAM}u\n"
        f"#define GA_BELOW_CASES {len(BELOW_N)}\n#define GA_BELOW_COUNT {BELOW_COUNT}\n",
        hex_array("uint32_t", "u", "ga_below_n", BELOW_N, 8, 6),
        hex_array("uint32_t", "u", "ga_below_out", below, 8, 6),
    ])


def float_bounds():
    return [(f32(lo), f32(hi)) for lo, hi in BOUNDS]


def uniforms24(seed):
    """An endless iterator of uniform floats in [0, 1) from the top 24 bits
    of splitmix64: exact in float32, so a rounded draw never reaches 1."""
    rng = SplitMix64.keyed(seed)
    return iter(lambda: rng.bits(24) / float(1 << 24), None)


def sbx_part():
    bounds = float_bounds()
    p1s, p2s, grid = [], [], []
    for lo, hi in bounds:
        for a, b in SBX_PAIRS:
            p1, p2 = inside(a, lo, hi), inside(b, lo, hi)
            p1s.append(p1)
            p2s.append(p2)
            for eta in ETAS:
                c1, c2 = ga.sbx(p1, p2, lo, hi, eta, np.array(U_GRID))
                for x1, x2 in zip(c1, c2):
                    grid += [x1, x2]
    rand = uniforms24(0x5B7)
    rows = []
    for _ in range(RANDOM_CASES):
        lo = f32(-10 + 10 * next(rand))
        hi = f32(lo + 1e-3 + 20 * next(rand) ** 3)
        p1, p2 = inside(next(rand), lo, hi), inside(next(rand), lo, hi)
        eta = f32(1 + 99 * next(rand))
        u = f32(next(rand))
        c1, c2 = ga.sbx(p1, p2, lo, hi, eta, u)
        rows += [p1, p2, lo, hi, eta, u, float(c1), float(c2)]
    return "\n".join([
        f"#define GA_NBOUNDS {len(bounds)}\n#define GA_SBX_NPAIRS {len(SBX_PAIRS)}\n"
        f"#define GA_NETA {len(ETAS)}\n#define GA_SBX_NU {len(U_GRID)}\n"
        f"#define GA_SBX_NRAND {RANDOM_CASES}\n",
        _emit.array("double", "ga_lo", [b[0] for b in bounds]),
        _emit.array("double", "ga_hi", [b[1] for b in bounds]),
        _emit.array("double", "ga_eta", ETAS),
        _emit.array("double", "ga_sbx_u", U_GRID),
        _emit.array("double", "ga_sbx_p1", p1s),
        _emit.array("double", "ga_sbx_p2", p2s),
        "/* c1, c2 per (bounds, pair, eta, u), u varying fastest */\n"
        + _emit.array("double", "ga_sbx_c", grid),
        "/* p1, p2, lo, hi, eta, u, c1, c2 */\n"
        + _emit.array("double", "ga_sbx_rand", rows, per_line=8),
    ])


def mutation_part():
    bounds = float_bounds()
    xs, grid = [], []
    for lo, hi in bounds:
        for frac in MUT_X:
            x = inside(frac, lo, hi)
            xs.append(x)
            for eta in ETAS:
                grid += [float(v) for v in ga.mutate(x, lo, hi, eta, np.array(MUT_U))]
    rand = uniforms24(0xA11CE)
    rows = []
    for _ in range(RANDOM_CASES):
        lo = f32(-10 + 10 * next(rand))
        hi = f32(lo + 1e-3 + 20 * next(rand) ** 3)
        x = inside(next(rand), lo, hi)
        eta = f32(1 + 99 * next(rand))
        u = f32(next(rand))
        rows += [x, lo, hi, eta, u, float(ga.mutate(x, lo, hi, eta, u))]
    return "\n".join([
        f"#define GA_MUT_NX {len(MUT_X)}\n#define GA_MUT_NU {len(MUT_U)}\n"
        f"#define GA_MUT_NRAND {RANDOM_CASES}\n",
        _emit.array("double", "ga_mut_x", xs),
        _emit.array("double", "ga_mut_u", MUT_U),
        "/* y per (bounds, x, eta, u), u varying fastest */\n"
        + _emit.array("double", "ga_mut_y", grid),
        "/* x, lo, hi, eta, u, y */\n" + _emit.array("double", "ga_mut_rand", rows, per_line=6),
    ])


# (n, g, sigma, alpha, layout): "rand" pseudo-random genes in the box,
# "same" all identical, "far" corners of the box, "cluster" two tight groups.
SHARE_CASES = ((1, 2, 0.3, 1.0, "rand"), (2, 1, 0.5, 1.0, "same"), (5, 3, 0.4, 1.0, "rand"),
               (6, 2, 0.25, 2.0, "cluster"), (8, 4, 0.6, 0.5, "rand"), (4, 2, 0.5, 1.0, "far"),
               (10, 3, 1.0, 1.0, "rand"), (7, 1, 0.1, 3.0, "cluster"))


def share_part():
    rand = uniforms24(0x5A4E)
    genes, los, his, costs, shared = [], [], [], [], []
    for n, g, sigma, alpha, layout in SHARE_CASES:
        lo = np.array([f32(-3 + 3 * next(rand)) for _ in range(g)])
        hi = np.array([f32(l + 0.5 + 5 * next(rand)) for l in lo])
        if layout == "rand":
            frac = [[next(rand) for _ in range(g)] for _ in range(n)]
        elif layout == "same":
            frac = [[0.37] * g for _ in range(n)]
        elif layout == "far":
            frac = [[float((i >> k) & 1) for k in range(g)] for i in range(n)]
        else:
            frac = [[(0.2 if i % 2 else 0.7) + 0.01 * next(rand) for _ in range(g)]
                    for i in range(n)]
        x = np.array([[inside(f, lo[k], hi[k]) for k, f in enumerate(row)] for row in frac])
        cost = [f32(0.1 + 10 * next(rand)) for _ in range(n)]
        cost[0] = 0.0 if n > 3 else cost[0]
        genes += list(x.ravel())
        los += list(lo)
        his += list(hi)
        costs += cost
        shared += list(ga.share(x, lo, hi, cost, sigma, alpha))
    return "\n".join([
        f"#define GA_SHARE_CASES {len(SHARE_CASES)}\n",
        _emit.int_array("size_t", "ga_share_n", [c[0] for c in SHARE_CASES]),
        _emit.int_array("size_t", "ga_share_g", [c[1] for c in SHARE_CASES]),
        _emit.array("double", "ga_share_sigma", [c[2] for c in SHARE_CASES]),
        _emit.array("double", "ga_share_alpha", [c[3] for c in SHARE_CASES]),
        "/* concatenated per case: n g genes, g bounds, n costs and results */\n"
        + _emit.array("double", "ga_share_genes", genes),
        _emit.array("double", "ga_share_lo", los),
        _emit.array("double", "ga_share_hi", his),
        _emit.array("double", "ga_share_cost", costs),
        _emit.array("double", "ga_share_want", shared),
    ])


TOUR_SHARED = (3.0, 1.0, 1.0, 0.0, 2.5, 0.0, 7.25, 1.0)


def tournament_part():
    rows = []
    for a in range(len(TOUR_SHARED)):
        for b in range(len(TOUR_SHARED)):
            for coin in (0, 1, 0xFFFFFFFF):
                if coin == 0xFFFFFFFF and (a + b) % 3:
                    continue
                rows += [a, b, coin, ga.tournament(TOUR_SHARED, a, b, coin)]
    return "\n".join([
        _emit.array("double", "ga_tour_shared", TOUR_SHARED),
        f"#define GA_TOUR_CASES {len(rows) // 4}\n/* a, b, coin, winner */\n",
        _emit.int_array("uint32_t", "ga_tour", rows),
    ])


def generate():
    body = ["#include <stdint.h>\n", pcg_part(), sbx_part(), mutation_part(), share_part(),
            tournament_part()]
    return {FILE: _emit.header(FILE, "\n".join(body), "tools/vectorgen/ga.py (tools/pdtref/ga.py)")}
