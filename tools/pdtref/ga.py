"""Reference of the genetic-algorithm operators (lib/src/pdt_ga.c).

Written from the published definitions:

- PCG32, O'Neill (2014): 64-bit LCG state, "XSH RR" 32-bit output, seeded as
  the reference ``pcg32_srandom_r``. Python integers, masked to 64 bits.
- Uniform numbers: the top 24 bits times 2^-24 (the float build) or all 32
  bits times 2^-32 (the double build); bounded integers by Lemire's
  multiply-and-reject (2019).
- Bounded SBX (Deb and Agrawal 1995; Deb 2000) and bounded polynomial
  mutation (Deb and Goyal 1996), here derived as inverse-CDF sampling of the
  spread-factor / perturbation distributions restricted to the feasible part,
  in log/exp form, rather than the closed formulas of the NSGA-II code.
- Fitness sharing (Goldberg and Richardson 1987) with a numpy pairwise
  distance matrix.

numpy only.
"""
import numpy as np

MASK64 = (1 << 64) - 1
MASK32 = (1 << 32) - 1
PCG_MULT = 6364136223846793005

#: Parents closer than this fraction of the range are copied, not crossed.
SBX_MIN_GAP = 1e-14


class Pcg32:
    """PCG32 generator with O'Neill's seeding (initstate, initseq)."""

    def __init__(self, seed, stream):
        self.state = 0
        self.inc = ((stream << 1) | 1) & MASK64
        self.next_u32()
        self.state = (self.state + seed) & MASK64
        self.next_u32()

    def next_u32(self):
        old = self.state
        self.state = (old * PCG_MULT + self.inc) & MASK64
        xorshifted = (((old >> 18) ^ old) >> 27) & MASK32
        rot = old >> 59
        return ((xorshifted >> rot) | (xorshifted << ((32 - rot) & 31))) & MASK32

    def take(self, count):
        return [self.next_u32() for _ in range(count)]

    def below(self, n):
        """Uniform integer in [0, n), Lemire's unbiased method."""
        if n < 1:
            raise ValueError("n must be at least 1")
        # Accept the draw unless its low word falls among the 2^32 mod n
        # values that would over-represent some results.
        reject_under = (1 << 32) % n
        while True:
            m = self.next_u32() * n
            if (m & MASK32) >= reject_under:
                return m >> 32


def uniform_float(x):
    """The float build's uniform number from one 32-bit draw."""
    return (int(x) >> 8) / float(1 << 24)


def uniform_double(x):
    """The double build's uniform number from one 32-bit draw."""
    return int(x) / float(1 << 32)


def _as_arrays(*args):
    return np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in args))


def _sbx_spread(room, gap, eta, u):
    """Spread factor of one bounded-SBX child by inverse-CDF sampling.

    Unbounded SBX draws the spread factor b with CDF F(b) = b^(eta+1)/2 for
    b <= 1 and 1 - b^-(eta+1)/2 beyond. The child would leave the bound for
    b > bmax = 1 + 2 room / gap, so b is drawn from F restricted to
    [0, bmax]: F(b) = u F(bmax). The right branch is solved through the
    complementary mass 1 - u F(bmax) = (1 - u) + u (1 - F(bmax)), which stays
    accurate as u approaches 1.
    """
    e1 = eta + 1.0
    bmax = 1.0 + 2.0 * room / gap
    tail = np.exp(-e1 * np.log(bmax))  # 2 (1 - F(bmax))
    target = u * (1.0 - 0.5 * tail)  # u F(bmax)
    left = target <= 0.5
    with np.errstate(divide="ignore"):
        b_left = np.exp(np.log(2.0 * target) / e1)
    comp = (1.0 - u) + u * 0.5 * tail  # 1 - u F(bmax), > 0
    b_right = np.exp(-np.log(2.0 * comp) / e1)
    return np.where(left, b_left, b_right)


def sbx(p1, p2, lo, hi, eta, u):
    """Bounded SBX of one variable: returns (c1, c2), c1 from the lower
    parent's side, both clamped to [lo, hi]. Broadcasts over arrays."""
    p1, p2, lo, hi, eta, u = _as_arrays(p1, p2, lo, hi, eta, u)
    y1 = np.minimum(p1, p2)
    y2 = np.maximum(p1, p2)
    gap = y2 - y1
    cross = gap >= SBX_MIN_GAP * (hi - lo)
    safe_gap = np.where(cross, gap, 1.0)
    room_lo = np.maximum(y1 - lo, 0.0)
    room_hi = np.maximum(hi - y2, 0.0)
    mid = 0.5 * (y1 + y2)
    half = 0.5 * safe_gap
    c1 = mid - _sbx_spread(room_lo, safe_gap, eta, u) * half
    c2 = mid + _sbx_spread(room_hi, safe_gap, eta, u) * half
    c1 = np.where(cross, np.clip(c1, lo, hi), y1)
    c2 = np.where(cross, np.clip(c2, lo, hi), y2)
    return c1, c2


def mutate(x, lo, hi, eta, u):
    """Bounded polynomial mutation of one variable. Broadcasts.

    The perturbation d (in units of the range) has density
    (eta+1)/2 (1 - |d|)^eta on [-1, 1], CDF G(d) = (1 + d)^(eta+1)/2 for
    d <= 0. Feasible d lie in [-d1, d2] (d1, d2 the distances to the bounds
    over the range). u in [0, 1/2] maps linearly onto G over [-d1, 0] and
    u in (1/2, 1) onto G over [0, d2]; d is G's inverse there.
    """
    x, lo, hi, eta, u = _as_arrays(x, lo, hi, eta, u)
    e1 = eta + 1.0
    rng = hi - lo
    d1 = np.clip((x - lo) / rng, 0.0, 1.0)
    d2 = np.clip((hi - x) / rng, 0.0, 1.0)
    with np.errstate(divide="ignore"):
        # left half: 2 G(d) = (1-2u) (1-d1)^(eta+1) + 2u, d = (2G)^(1/e1) - 1
        g_lo = np.exp(e1 * np.log1p(-d1))  # 2 G(-d1)
        two_g = g_lo + 2.0 * u * (1.0 - g_lo)
        d_left = np.expm1(np.log(two_g) / e1)
        # right half by symmetry, with v = 1 - u mapped the other way
        g_hi = np.exp(e1 * np.log1p(-d2))
        two_h = g_hi + 2.0 * (1.0 - u) * (1.0 - g_hi)
        d_right = -np.expm1(np.log(two_h) / e1)
    d = np.where(u <= 0.5, d_left, d_right)
    return np.clip(x + d * rng, lo, hi)


def niche_counts(genes, lo, hi, sigma, alpha):
    """m_i = sum_j sh(d_ij) over all j (i included)."""
    genes = np.atleast_2d(np.asarray(genes, dtype=np.float64))
    z = genes / (np.asarray(hi, dtype=np.float64) - np.asarray(lo, dtype=np.float64))
    diff = z[:, None, :] - z[None, :, :]
    d = np.sqrt(np.sum(diff * diff, axis=2))
    ratio = d / sigma
    sh = np.where(ratio < 1.0, 1.0 - np.power(np.minimum(ratio, 1.0), alpha), 0.0)
    return np.sum(sh, axis=1)


def share(genes, lo, hi, cost, sigma, alpha):
    """Shared costs cost_i m_i."""
    return np.asarray(cost, dtype=np.float64) * niche_counts(genes, lo, hi, sigma, alpha)


def tournament(shared, a, b, coin):
    """Index of the winner: the smaller shared cost; NaN loses to a number;
    a tie (NaN against NaN included) goes to a for coin 0, else to b."""
    fa, fb = float(shared[a]), float(shared[b])
    if np.isnan(fa) != np.isnan(fb):
        return b if np.isnan(fa) else a
    if fa < fb:
        return a
    if fb < fa:
        return b
    return a if coin == 0 else b
