"""Building blocks of the identification benchmark (tools/bench/run_ident_bench.py).

- deterministic random numbers (splitmix64 + Box-Muller, independent of the
  numpy version);
- test signals: step, pulse, PRBS, chirp, and a relay with hysteresis closed
  around the simulated plant;
- exact simulation of FOPDT/SOPDT truths (pdtref's ZOH model with the
  fractional dead time, run by scipy.signal.lfilter) and of high-order
  plants with a dead time (exact ZOH of the state-space model);
- the reference fit: output-error least squares with scipy.optimize,
  multi-started over the dead time;
- figures of merit: parameter errors, step-response IAE, frequency-response
  error;
- running `pdtfit identify` on a record.
"""
from __future__ import annotations

import json
import math
import os
import pathlib
import subprocess
import tempfile

import numpy as np
import scipy.linalg as sla
import scipy.optimize as so
import scipy.signal as ss

from pdtref import discrete, models
from pdtsupport.rng import SplitMix64 as Rng  # noqa: F401 (pdtbench.benchlib.Rng)

ROOT = pathlib.Path(__file__).resolve().parents[2]

U0, Y0 = 40.0, 350.0   # operating point: 40 % valve, 350 degC
AMP = 10.0             # input excursion, % (the relay's upper level)


# Random numbers: Rng is pdtsupport.rng.SplitMix64 (imported above).


# ------------------------------------------------------------ plants

class Truth:
    """A FOPDT or SOPDT truth with its time scale (s) for the error of Td.

    kind: 'fopdt' (K, tau), 'sopdt' (K, wn, zeta; over- or underdamped),
    'integ' (Ki, T): params holds those, Td is the dead time.
    """

    def __init__(self, name, kind, params, Td, scale, settle):
        self.name, self.kind, self.params, self.Td = name, kind, params, Td
        self.scale = scale      # time constant used to normalise Td errors
        self.settle = settle    # time to settle after a step (incl. Td), s

    def model(self):
        p = self.params
        if self.kind == "fopdt":
            return models.Fopdt(p["K"], p["tau"], self.Td)
        if self.kind == "sopdt":
            return models.sopdt_from_natural(p["K"], p["wn"], p["zeta"], self.Td)
        return models.sopdt_from_integ(p["Ki"], p["T"], self.Td)

    def gain(self):
        """Output change per input unit that sizes the relay set-point."""
        return self.params.get("K", self.params.get("Ki", 1.0) * self.settle)


def fopdt_truth(name, K, tau, Td):
    return Truth(name, "fopdt", {"K": K, "tau": tau}, Td, tau, Td + 5.0 * tau)


def sopdt_truth(name, K, wn, zeta, Td):
    if zeta >= 1.0:
        settle = Td + 5.0 * 2.0 * zeta / wn        # tau1 + tau2 = 2 zeta / wn
    else:
        settle = Td + 5.0 / (zeta * wn)            # envelope e^{-zeta wn t}
    return Truth(name, "sopdt", {"K": K, "wn": wn, "zeta": zeta}, Td, 1.0 / wn, settle)


def integ_truth(name, Ki, T, Td):
    return Truth(name, "integ", {"Ki": Ki, "T": T}, Td, T, Td + 5.0 * T)


def lfilter_coeffs(d):
    """(num, den) for scipy.signal.lfilter from a pdtref Discrete model."""
    num = np.concatenate([np.zeros(d.delay + 1), np.asarray(d.b, float)])
    den = np.concatenate([[1.0], np.asarray(d.a, float)[:d.order]])
    return num, den


def simulate(m, Ts, du):
    """Output deviation of pdtref model m for input deviation du, from rest."""
    num, den = lfilter_coeffs(discrete.zoh(m, Ts))
    return ss.lfilter(num, den, du)


class HighOrder:
    """num(s) / den(s) e^{-L s} (polynomials, highest power first)."""

    def __init__(self, name, num, den, L=0.0):
        self.name = name
        self.num = np.atleast_1d(np.asarray(num, float))
        self.den = np.atleast_1d(np.asarray(den, float))
        self.L = float(L)

    def freq(self, w):
        s = 1j * np.asarray(w, float)
        return np.polyval(self.num, s) / np.polyval(self.den, s) * np.exp(-s * self.L)

    def discrete(self, Ts):
        """Exact ZOH sampled state-space model with the fractional delay
        (Astrom and Wittenmark): x+ = Phi x + G0 u(k-l) + G1 u(k-l-1)."""
        A, B, C, D = ss.tf2ss(self.num, self.den)
        n = A.shape[0]
        l, f = discrete.split_delay(self.L, Ts)

        def exp_int(t):
            M = np.zeros((n + 1, n + 1))
            M[:n, :n] = A * t
            M[:n, n:] = B * t
            E = sla.expm(M)
            return E[:n, :n], E[:n, n:]
        Phi, _ = exp_int(Ts)
        E0, G0 = exp_int(Ts - f * Ts)
        _, I1 = exp_int(f * Ts)
        return Phi, G0, E0 @ I1, C, D, l

    def simulate(self, Ts, du):
        Phi, G0, G1, C, D, l = self.discrete(Ts)
        n = du.size
        # ud[j] = du[j - l - 1]: u(k - l) is ud[k + 1], u(k - l - 1) is ud[k]
        ud = np.concatenate([np.zeros(l + 1), du])
        # ABCD with the input pair (u(k-l), u(k-l-1)) as two channels
        sysd = ss.dlti(Phi, np.hstack([G0, G1]), C, np.zeros((1, 2)), dt=Ts)
        U = np.column_stack([ud[1:n + 1], ud[0:n]])
        _, y, _ = ss.dlsim(sysd, U)
        y = y[:, 0]
        if D.size and D[0, 0] != 0.0:
            y = y + D[0, 0] * ud[1:n + 1]   # only with l = f = 0
        return y


# ------------------------------------------------------------ signals

def rest_samples(n):
    return max(16, n // 20)


def excitation(kind, n, Ts, truth_scale, rng):
    """Input deviation (units of AMP) of an open-loop test, 0 at the start.

    step: one step after the rest; pulse: up for 40 % of the record, then
    back; prbs: random +-1 levels held a random multiple of the switching
    time (about the plant's time scale / 2) until 70 % of the record, then
    rest; chirp: a sine from 0 to 3 / (2 pi scale) Hz over the record.
    """
    k0 = rest_samples(n)
    du = np.zeros(n)
    if kind == "step":
        du[k0:] = 1.0
    elif kind == "pulse":
        du[k0:k0 + int(0.4 * n)] = 1.0
    elif kind == "prbs":
        hold = max(1, int(round(0.5 * truth_scale / Ts)))
        k, end = k0, int(0.7 * n)
        level = 1.0
        while k < end:
            run = hold * (1 + int(rng.uniform() * 4))
            du[k:min(k + run, end)] = level
            level = -level if rng.uniform() < 0.7 else level
            k += run
    elif kind == "chirp":
        t = (np.arange(n) - k0) * Ts
        t[t < 0] = 0.0
        f1 = 3.0 / (2.0 * math.pi * truth_scale)
        T = (n - k0) * Ts
        du = np.sin(2.0 * math.pi * 0.5 * f1 / T * t ** 2)
        du[:k0] = 0.0
    else:
        raise ValueError(kind)
    return du


RETURNS_TO_REST = ("pulse", "prbs")


def relay_record(truth, n, Ts, sigma, quant, rng_noise):
    """Relay with hysteresis around the plant (closed loop): u switches
    between u0 + AMP and u0 - 0.5 AMP to hold y at y0 + 0.3 K AMP (for an
    integrator, y0 + 0.3 Ki AMP settle). Returns (u, y, y_noise_free)."""
    d = discrete.zoh(truth.model(), Ts)
    num, den = lfilter_coeffs(d)
    nb, na = num.size, den.size
    k0 = rest_samples(n)
    sign = 1.0 if truth.gain() > 0 else -1.0
    sp = 0.3 * abs(truth.gain()) * AMP * sign
    h = max(3.0 * sigma, quant, 1e-3 * abs(sp))
    e = rng_noise.normal(n) * sigma
    du = np.zeros(n)
    yc = np.zeros(n)
    ym = np.zeros(n)
    level = 1.0
    for k in range(n):
        acc = 0.0
        for j in range(1, nb):
            if k - j >= 0:
                acc += num[j] * AMP * du[k - j]
        for j in range(1, na):
            if k - j >= 0:
                acc -= den[j] * yc[k - j]
        yc[k] = acc
        ym[k] = yc[k] + e[k]
        if quant > 0:
            ym[k] = quant * np.round((Y0 + ym[k]) / quant) - Y0
        if k < k0:
            continue
        err = sign * (sp - ym[k])
        if err > h:
            level = 1.0
        elif err < -h:
            level = -0.5
        du[k] = level
    return U0 + AMP * du, Y0 + ym, yc


def make_record(truth, exc, n, Ts, snr_db, quantised, seed):
    """One known-truth record: (u, y, info). Noise std from the variance of
    the noise-free output deviation: sigma^2 = var(y_clean) / 10^(snr/10)."""
    rng_sig = Rng(1000003 * seed + 17)
    rng_noise = Rng(7919 * seed + 3)
    if exc == "relay":
        # The loop's noise-free variance first, then the same loop with noise.
        _, _, yc = relay_record(truth, n, Ts, 0.0, 0.0, Rng(1))
        sigma = float(np.std(yc)) / 10.0 ** (snr_db / 20.0)
        quant = 0.005 * (np.ptp(yc) + 6 * sigma) if quantised else 0.0
        u, y, yc = relay_record(truth, n, Ts, sigma, quant, rng_noise)
        return u, y, {"sigma": sigma, "quant": quant}
    du = excitation(exc, n, Ts, truth.scale, rng_sig)
    yc = simulate(truth.model(), Ts, AMP * du)
    sigma = float(np.std(yc)) / 10.0 ** (snr_db / 20.0)
    y = Y0 + yc + sigma * rng_noise.normal(n)
    quant = 0.0
    if quantised:
        quant = 0.005 * np.ptp(y)
        y = quant * np.round(y / quant)
    return U0 + AMP * du, y, {"sigma": sigma, "quant": quant}


# ------------------------------------------------------------ pdtfit

def run_pdtfit(binary, u, y, Ts, model, cost="simulation", seed=1, extra=()):
    """Runs `pdtfit identify` on the record; returns the parsed JSON or
    {'error': text}."""
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("u,y\n")
        f.write("\n".join(f"{a:.12g},{b:.12g}" for a, b in zip(u, y)))
        f.write("\n")
        path = f.name
    try:
        args = [str(binary), "identify", "--model", model, "--cost", cost,
                "--seed", str(seed), "--fs", f"{1.0 / float(Ts):.17g}", *extra, path]
        res = subprocess.run(args, capture_output=True, text=True, timeout=120)
    finally:
        os.unlink(path)
    # 3: a model printed with a warning (negative fit, on a search bound);
    # the benchmark scores it like any other model.
    if res.returncode not in (0, 3):
        return {"error": res.stderr.strip()}
    return json.loads(res.stdout)


def model_from_json(j):
    """(pdtref model, y0) of a pdtfit result."""
    if j["model"] == "fopdt":
        return models.Fopdt(j["K"], j["tau"], j["Td"]), j["y0"]
    if j["b"] == 0 or j.get("K") is None:
        return models.Sopdt(j["Ki"] * j["a"], j["a"], 0.0, j["Td"]), j["y0"]
    return models.Sopdt(j["K"] * j["b"], j["a"], j["b"], j["Td"]), j["y0"]


# ------------------------------------------------------------ reference fit

def _sopdt_from_x(x, Trec):
    """Reference SOPDT parameters: x = (log a, 1/zeta, Td, g); the numerator
    is k = g (b + a / Trec), so g is the DC gain when the lag is short and
    Ki Trec for an integrator: one smooth scale for both."""
    a = math.exp(x[0])
    b = (a * x[1] / 2.0) ** 2
    return models.Sopdt(x[3] * (b + a / Trec), a, b, x[2])


# ------------------------------------------------------------ reference cache

# The scipy reference fit takes most of a benchmark's time and depends on
# the record alone, not on pdtfit: Reference.fit keeps its answers on disk,
# under a hash of the record, the fit's arguments and the code and
# versions that compute it (this file, pdtref, numpy, scipy), so that a
# benchmark run again after a change to pdtfit refits nothing it fitted
# before, and any change to the reference itself refits everything.
# PDT_REFERENCE_CACHE: the folder (default build/bench/reference-cache),
# or "off".
_CACHE_VERSION = None


def _cache_dir():
    env = os.environ.get("PDT_REFERENCE_CACHE")
    if env == "off":
        return None
    return pathlib.Path(env) if env else ROOT / "build" / "bench" / "reference-cache"


def _code_version():
    global _CACHE_VERSION
    if _CACHE_VERSION is None:
        import hashlib
        import scipy
        h = hashlib.sha256()
        for f in [pathlib.Path(__file__)] + sorted(pathlib.Path(models.__file__).parent.glob("*.py")):
            h.update(f.read_bytes())
        h.update(f"numpy {np.__version__} scipy {scipy.__version__}".encode())
        _CACHE_VERSION = h.hexdigest()
    return _CACHE_VERSION


def _cache_key(*parts):
    import hashlib
    h = hashlib.sha256(_code_version().encode())
    for p in parts:
        h.update(np.ascontiguousarray(p, dtype="<f8").tobytes() if isinstance(p, np.ndarray)
                 else repr(p).encode())
        h.update(b"|")
    return h.hexdigest()


def _cache_get(key):
    d = _cache_dir()
    if d is None:
        return None
    try:
        return json.loads((d / key[:2] / f"{key}.json").read_text())
    except (OSError, ValueError):
        return None


def _cache_put(key, value):
    d = _cache_dir()
    if d is None:
        return
    sub = d / key[:2]
    sub.mkdir(parents=True, exist_ok=True)
    # Written whole, then renamed: worker processes never see half a file.
    fd, tmp = tempfile.mkstemp(dir=sub, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump(value, f)
    os.replace(tmp, sub / f"{key}.json")


class Reference:
    """Output-error least squares (scipy.optimize.least_squares, TRF, bounds)
    on the simulated output of the exact ZOH model with fractional delay,
    with a free output offset. Bounds as pdtfit's defaults: time constants
    in [Ts/4, 2T], Td in [0, T/3], SOPDT damping >= 0.2 or integrating.
    Nine dead-time starts spread over the Td range; the shape starts from a
    time constant of T/20 (SOPDT: critically damped), gain and offset from a
    linear least-squares fit at that start."""

    def __init__(self, u, y, Ts, model, starts=9):
        self.u, self.y, self.Ts, self.kind = np.asarray(u), np.asarray(y), Ts, model
        self.du = self.u - self.u[0]
        self.n = self.u.size
        self.T = self.n * Ts
        self.nstarts = starts
        self.nfev = 0

    def model_of(self, x):
        if self.kind == "fopdt":
            return models.Fopdt(x[2], math.exp(x[0]), x[1])
        return _sopdt_from_x(x, self.T)

    def resid(self, x):
        self.nfev += 1
        m = self.model_of(x[:-1])
        return self.y - x[-1] - simulate(m, self.Ts, self.du)

    def _shape_start(self, Td):
        c = self.T / 20.0
        if self.kind == "fopdt":
            x = [math.log(c), Td, 1.0]
        else:
            x = [math.log(2.0 / c), 1.0, Td, 1.0]
        unit = simulate(self.model_of(x), self.Ts, self.du)
        A = np.column_stack([unit, np.ones(self.n)])
        g, off = np.linalg.lstsq(A, self.y, rcond=None)[0]
        x[-1] = g
        return np.array(x + [off])

    def fit(self, td_starts=None):
        """(model, offset, cost) of the best of the starts; kept in the
        reference cache (above), with the evaluations it counted."""
        key = _cache_key("Reference.fit", self.u, self.y, self.Ts, self.kind, self.nstarts,
                         None if td_starts is None else [float(t) for t in td_starts])
        hit = _cache_get(key)
        if hit is None:
            n0 = self.nfev
            m, off, c = self._fit(td_starts)
            hit = {"kind": "fopdt" if isinstance(m, models.Fopdt) else "sopdt",
                   "m": [float(v) for v in m], "off": float(off), "c": float(c),
                   "nfev": self.nfev - n0}
            _cache_put(key, hit)
            self.nfev = n0
        # The same plain floats whether fitted now or read back.
        self.nfev += hit["nfev"]
        cls = models.Fopdt if hit["kind"] == "fopdt" else models.Sopdt
        return cls(*hit["m"]), hit["off"], hit["c"]

    def _fit(self, td_starts):
        Ts, T = self.Ts, self.T
        inf = np.inf
        if self.kind == "fopdt":
            lo = [math.log(Ts / 4), 0.0, -inf, -inf]
            hi = [math.log(2 * T), T / 3, inf, inf]
        else:
            # a = 1/tau' with tau' = 1/a in [Ts/8, 2T] (pdtfit: from tau_min/2)
            lo = [math.log(1.0 / (2 * T)), 0.0, 0.0, -inf, -inf]
            hi = [math.log(8.0 / Ts), 5.0, T / 3, inf, inf]
        itd = 1 if self.kind == "fopdt" else 2
        if td_starts is None:
            td_starts = [(j + 0.5) / self.nstarts * T / 3 for j in range(self.nstarts)]
        best = None
        for td in td_starts:
            x0 = self._shape_start(td)
            x0 = np.clip(x0, np.array(lo) + 1e-12, np.array(hi) - 1e-12)
            x0[itd] = td
            try:
                r = so.least_squares(self.resid, x0, bounds=(lo, hi), method="trf",
                                     x_scale="jac", xtol=1e-10, ftol=1e-10, gtol=1e-10,
                                     max_nfev=400)
            except (ValueError, np.linalg.LinAlgError):
                continue
            c = float(np.mean(r.fun ** 2))
            if best is None or c < best[0]:
                best = (c, r.x)
        c, x = best
        return self.model_of(x[:-1]), float(x[-1]), c


def oe_cost(m, y0, u, y, Ts):
    """Whole-record output-error mean square of m around (u[0], y0), the
    offset re-fitted (the residual's variance): one yardstick for every fit."""
    r = np.asarray(y) - y0 - simulate(m, Ts, np.asarray(u) - u[0])
    return float(np.var(r))


# ------------------------------------------------------------ figures of merit

def _natural(m):
    n = models.to_natural(m)
    return n.K, n.wn, n.zeta


def param_errors(truth, m):
    """Relative errors of the parameters (and Td error / time scale) of an
    identified model against the truth; dict name -> error."""
    p = truth.params
    sc = truth.scale
    if truth.kind == "fopdt":
        e = {"K": abs(m.K / p["K"] - 1), "tau": abs(m.tau / p["tau"] - 1)}
    elif truth.kind == "sopdt":
        if m.b <= 0:
            return {"K": math.inf, "wn": math.inf, "zeta": math.inf, "Td": math.inf}
        K, wn, z = _natural(m)
        e = {"K": abs(K / p["K"] - 1), "wn": abs(wn / p["wn"] - 1),
             "zeta": abs(z / p["zeta"] - 1)}
    else:
        Ki = m.k / m.a                  # k/(s (s + a)) = (k/a)/(s (s/a + 1))
        e = {"Ki": abs(Ki / p["Ki"] - 1), "T": abs((1.0 / m.a) / p["T"] - 1)}
        if m.b > 0:
            # a hair inside the integrator: its ramp slope over the record
            e["Ki"] = abs((m.k / m.a) / p["Ki"] - 1)
    e["Td"] = abs(m.Td - truth.Td) / sc
    return e


def step_grid(Tend, n=2000):
    return np.linspace(0.0, Tend, n + 1)


def step_model(m, t):
    dt = t[1] - t[0]
    return simulate(m, dt, np.ones(t.size))


def niae(h, href, t):
    """IAE of h against href over t, divided by (t_end max|href|): the mean
    absolute error as a fraction of the reference's largest value."""
    dt = t[1] - t[0]
    return float(np.sum(np.abs(h - href)) * dt / (t[-1] * np.max(np.abs(href))))


def model_freq(m, w):
    mag, ph = models.freq(m, w)
    return mag * np.exp(1j * ph)
