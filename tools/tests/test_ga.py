"""Checks of the GA reference (tools/pdtref/ga.py) and its vectors.

PCG32 against O'Neill's published demo output; SBX and polynomial mutation
against the closed formulas of Deb's NSGA-II code (a different derivation
from the reference's inverse-CDF form), against numerical integration of
the densities with scipy, and by their statistical properties; sharing and
tournament by their defining properties.
"""
import pathlib

import numpy as np
import pytest
from scipy import integrate

TOOLS = pathlib.Path(__file__).resolve().parents[1]
ROOT = TOOLS.parent

from pdtref import ga
from vectorgen import ga as ga_vectors
from vectorgen._emit import vectors_differ


# --- PCG32 ---------------------------------------------------------------

def test_pcg32_published_demo_values():
    # pcg32-demo output, seed 42 stream 54 (pcg-random.org, pcg-c-basic).
    rng = ga.Pcg32(42, 54)
    assert rng.take(6) == [0xa15c02b7, 0x7b47f409, 0xba1d3330,
                           0x83d2f293, 0xbfa4784b, 0xcbed606e]


def test_uniform_scaling_exact_and_below_one():
    for x in (0, 1, 255, 256, 0x7FFFFFFF, 0xFFFFFFFF):
        f = ga.uniform_float(x)
        d = ga.uniform_double(x)
        assert 0.0 <= f < 1.0 and 0.0 <= d < 1.0
        assert np.float32(f) == f  # representable in float
        assert d * 2**32 == x
    assert ga.uniform_float(0xFFFFFFFF) == 1.0 - 2.0**-24
    assert ga.uniform_double(0xFFFFFFFF) == 1.0 - 2.0**-32


def test_below_range_and_uniformity():
    rng = ga.Pcg32(7, 3)
    for n in (1, 2, 3, 10, 1000, 0x80000001, 0xFFFFFFFF):
        assert all(0 <= rng.below(n) < n for _ in range(200))
    counts = np.bincount([rng.below(6) for _ in range(60000)], minlength=6)
    assert np.all(np.abs(counts - 10000) < 500)


def test_below_large_n_rejects_without_bias():
    # n = 2^31 + 1: nearly half the draws fall in the rejected zone, so the
    # upper half of [0, n) must still be hit as often as the lower half.
    rng = ga.Pcg32(1, 1)
    n = 0x80000001
    xs = np.array([rng.below(n) for _ in range(20000)])
    frac = np.mean(xs >= n // 2)
    assert abs(frac - 0.5) < 0.02


# --- SBX -----------------------------------------------------------------

def sbx_deb(p1, p2, lo, hi, eta, u):
    """Deb's NSGA-II closed form, scalar, plain floats."""
    y1, y2 = min(p1, p2), max(p1, p2)
    if y2 - y1 < 1e-14 * (hi - lo):
        return y1, y2
    out = []
    for beta, sign in ((1 + 2 * (y1 - lo) / (y2 - y1), -1), (1 + 2 * (hi - y2) / (y2 - y1), 1)):
        alpha = 2 - beta ** -(eta + 1)
        if u <= 1 / alpha:
            bq = (u * alpha) ** (1 / (eta + 1))
        else:
            bq = (1 / (2 - u * alpha)) ** (1 / (eta + 1))
        out.append(min(max(0.5 * ((y1 + y2) + sign * bq * (y2 - y1)), lo), hi))
    return tuple(out)


def test_sbx_matches_closed_form():
    for p1, p2, lo, hi in [(0.3, 0.7, 0, 1), (0.7, 0.3, 0, 1), (0, 1, 0, 1), (-2, 4.5, -5, 5),
                           (0.0, 0.01, 0, 1), (0.99, 1.0, 0, 1)]:
        for eta in (1, 2, 15, 100):
            for u in np.linspace(0, 0.99, 23):
                want = sbx_deb(p1, p2, lo, hi, eta, u)
                got = ga.sbx(p1, p2, lo, hi, eta, u)
                np.testing.assert_allclose([float(got[0]), float(got[1])], want,
                                           rtol=1e-12, atol=1e-13 * (hi - lo))


def test_sbx_spread_is_truncated_inverse_cdf():
    # The density of the spread factor, integrated numerically, restricted
    # to [0, bmax]: the drawn spread must sit at the fraction u of the mass.
    def dens(b, eta):
        return 0.5 * (eta + 1) * (b ** eta if b <= 1 else b ** -(eta + 2))

    for eta in (1.0, 3.0, 15.0):
        for room, gap in ((0.5, 1.0), (0.05, 1.0), (3.0, 0.2)):
            bmax = 1 + 2 * room / gap
            total = (integrate.quad(dens, 0, min(1, bmax), args=(eta,))[0]
                     + (integrate.quad(dens, 1, bmax, args=(eta,))[0] if bmax > 1 else 0))
            for u in (0.1, 0.4, 0.6, 0.95):
                b = float(ga._sbx_spread(room, gap, eta, u))
                mass = integrate.quad(dens, 0, min(b, 1), args=(eta,))[0]
                if b > 1:
                    mass += integrate.quad(dens, 1, b, args=(eta,))[0]
                assert mass / total == pytest.approx(u, rel=1e-7)


def test_sbx_children_inside_bounds_and_finite():
    u = np.linspace(0, 1 - 2**-24, 257)
    cases = [(0, 0, 0, 1), (1, 1, 0, 1), (0, 1, 0, 1), (0.5, 0.5, 0, 1), (0, 1e-9, 0, 1),
             (1 - 1e-9, 1, 0, 1), (100.0, 100.0 + 1e-5, 100.0, 100.0 + 2e-5), (-1e-30, 1e-30, -1e-30, 1e-30)]
    for p1, p2, lo, hi in cases:
        for eta in (1, 2, 5, 20, 50, 100, 1e6):
            c1, c2 = ga.sbx(p1, p2, lo, hi, eta, u)
            assert np.all(np.isfinite(c1)) and np.all(np.isfinite(c2))
            assert np.all((c1 >= lo) & (c1 <= hi) & (c2 >= lo) & (c2 <= hi))
            assert np.all(c1 <= c2)


def test_sbx_mean_preserved_away_from_bounds():
    # Far bounds: both children use the same spread, mean exactly preserved.
    u = np.linspace(0, 1, 10001, endpoint=False)
    c1, c2 = ga.sbx(0.4, 0.6, -1e6, 1e6, 2.0, u)
    np.testing.assert_allclose(0.5 * (c1 + c2), 0.5, atol=1e-12)
    # Moderate bounds, many u: the average child is the parents' mean.
    c1, c2 = ga.sbx(0.45, 0.55, 0.0, 1.0, 10.0, u)
    assert np.mean(np.concatenate([c1, c2])) == pytest.approx(0.5, abs=1e-4)


def test_sbx_spread_grows_as_eta_falls():
    u = (np.arange(4096) + 0.5) / 4096
    spreads = [np.mean(np.subtract(*ga.sbx(0.4, 0.6, 0.0, 1.0, eta, u)[::-1]))
               for eta in (100, 50, 20, 15, 5, 2, 1)]
    assert all(a < b for a, b in zip(spreads, spreads[1:]))


# --- polynomial mutation -------------------------------------------------

def mutate_deb(x, lo, hi, eta, u):
    d1, d2 = (x - lo) / (hi - lo), (hi - x) / (hi - lo)
    p = 1 / (eta + 1)
    if u <= 0.5:
        dq = (2 * u + (1 - 2 * u) * (1 - d1) ** (eta + 1)) ** p - 1
    else:
        dq = 1 - (2 * (1 - u) + 2 * (u - 0.5) * (1 - d2) ** (eta + 1)) ** p
    return min(max(x + dq * (hi - lo), lo), hi)


def test_mutate_matches_closed_form():
    for x, lo, hi in [(0.3, 0, 1), (0, 0, 1), (1, 0, 1), (-4, -5, 5), (2.5, 2, 3)]:
        for eta in (1, 5, 20, 100):
            for u in np.linspace(0, 0.999, 37):
                assert float(ga.mutate(x, lo, hi, eta, u)) == pytest.approx(
                    mutate_deb(x, lo, hi, eta, u), rel=1e-12, abs=1e-13 * (hi - lo))


def test_mutate_perturbation_is_truncated_inverse_cdf():
    eta, x, lo, hi = 4.0, 0.2, 0.0, 1.0

    def dens(d):
        return 0.5 * (eta + 1) * (1 - abs(d)) ** eta

    left = integrate.quad(dens, -(x - lo), 0)[0]
    right = integrate.quad(dens, 0, hi - x)[0]
    for u in (0.05, 0.3, 0.7, 0.95):
        d = float(ga.mutate(x, lo, hi, eta, u)) - x
        if u <= 0.5:
            frac = integrate.quad(dens, -(x - lo), d)[0] / left
            assert frac == pytest.approx(2 * u, rel=1e-7)
        else:
            frac = integrate.quad(dens, 0, d)[0] / right
            assert frac == pytest.approx(2 * u - 1, rel=1e-7)


def test_mutate_inside_bounds_finite_and_centred():
    u = np.linspace(0, 1 - 2**-24, 513)
    for x, lo, hi in [(0, 0, 1), (1, 0, 1), (0.5, 0, 1), (1e-30, 0, 1e-30), (5, 5, 5 + 1e-9)]:
        for eta in (1, 20, 100, 1e6):
            y = ga.mutate(x, lo, hi, eta, u)
            assert np.all(np.isfinite(y)) and np.all((y >= lo) & (y <= hi))
            assert float(ga.mutate(x, lo, hi, eta, 0.5)) == x


# --- sharing and tournament ----------------------------------------------

def test_share_properties():
    rng = ga.Pcg32(3, 9)
    genes = np.array([[ga.uniform_double(rng.next_u32()) for _ in range(3)] for _ in range(12)])
    lo, hi = np.zeros(3), np.ones(3)
    m = ga.niche_counts(genes, lo, hi, 0.4, 1.0)
    assert np.all(m >= 1.0) and np.all(m <= 12)
    same = np.tile([[0.2, 0.3, 0.4]], (7, 1))
    np.testing.assert_array_equal(ga.niche_counts(same, lo, hi, 0.1, 2.0), 7.0)
    far = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    np.testing.assert_array_equal(ga.niche_counts(far, lo, hi, 0.5, 1.0), 1.0)
    # brute-force double loop
    for sigma, alpha in ((0.3, 1.0), (0.6, 2.0), (0.9, 0.5)):
        want = [sum(max(0.0, 1 - (np.linalg.norm(a - b) / sigma) ** alpha)
                    if np.linalg.norm(a - b) < sigma else 0.0 for b in genes) for a in genes]
        np.testing.assert_allclose(ga.niche_counts(genes, lo, hi, sigma, alpha), want, rtol=1e-14)


def test_tournament():
    s = [3.0, 1.0, 1.0, float("nan"), float("nan")]
    assert ga.tournament(s, 0, 1, 0) == 1 and ga.tournament(s, 1, 0, 1) == 1
    assert ga.tournament(s, 1, 2, 0) == 1 and ga.tournament(s, 1, 2, 7) == 2
    assert ga.tournament(s, 3, 0, 0) == 0 and ga.tournament(s, 0, 3, 1) == 0
    assert ga.tournament(s, 3, 4, 0) == 3 and ga.tournament(s, 3, 4, 1) == 4


# --- vectors -------------------------------------------------------------

def test_vectors_regenerate_and_stay_small():
    files = ga_vectors.generate()
    for name, text in files.items():
        assert len(text) < 400_000
        assert vectors_differ((ROOT / "tests" / "vectors" / name).read_text(), text) is None
