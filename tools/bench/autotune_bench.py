#!/usr/bin/env python3
"""Autotune benchmark of pdtfit on the Astrom-Hagglund test batch.

Usage (from the repository root):

    python3 tools/bench/autotune_bench.py [--jobs N] [--out FILE] [--no-plots]

Builds the float library and tools/bench/autotune_driver.c into
build/autotune-bench, then for each plant of the batch:

1. runs the library's autotune (pdt_autotune_scan, one call per scan) on an
   exact simulation of the true plant with measurement noise, by a fixed
   experiment rule from the plant's time scale;
2. runs a relay test on the true plant (pdt_excite, RELAY) and takes the
   Ziegler-Nichols gains from its Ku and Pu (pdt_tune_ziegler_nichols);
3. takes SIMC gains of the best low-order model of the true plant:
   Skogestad's half rule (pdt_reduce_half_rule) where it applies, the exact
   model for the integrating family, a least-squares fit to the true step
   response otherwise;
4. applies every gain set to the TRUE plant: set-point and load step IAE
   from a fine-step closed-loop simulation written here (numpy), and the
   true Ms and closed-loop stability from the true frequency response.

Writes docs/reports/autotune-benchmark.md and docs/img/autotune-*.png. Everything is
seeded; the same versions give the same document. Its prose is the templates
autotune_bench.md.in (the document) and autotune_evidence.md.in (the evidence
section) beside this file.
"""
from __future__ import annotations

import argparse
import math
import multiprocessing as mp
import pathlib
import string
import subprocess

import numpy as np
import scipy.optimize as so

from pdtsupport import plant, provenance
from pdtsupport.status import NAMES, STATUS as CODES

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "autotune-bench"
DRIVER = BUILD / "tools" / "bench" / "pdt_autotune_driver"
OUT = ROOT / "docs" / "reports" / "autotune-benchmark.md"
IMG = ROOT / "docs" / "img"

# The experiment rule (a function of the plant's time scale only).
SAMPLES_PER_SCALE = 25     # identification samples per time scale
DECIMATION = 5             # scans per identification sample
SETTLE = 20                # identification samples at rest first
PULSE_ON = 4.0             # stable plants: pulse width, time scales
PULSE_OFF = 4.0            #   and time back at u0 recorded after it
PULSE_ON_INT = 2.0         # integrating plants: pulse width
PULSE_OFF_INT = 6.0        #   and the rest of the record
AMP = 1.0                  # input change of the experiments
NOISE = 0.01               # noise std, fraction of the output swing
RELAY_EPS = 4.0            # relay hysteresis, noise standard deviations
DFILT = 10.0               # derivative filter N (Tf = tauD / N)

# The closed-loop evaluation.
SIM_STEPS = 400            # simulation steps per time scale
SIM_SPAN = 40.0            # simulated time, time scales

# Status labels from the C header (pdtsupport.status), in words.
STATUS = {code: name.lower().replace("_", " ") for code, name in NAMES.items()}
PHASE = {0: "-", 1: "settle", 2: "excite", 3: "identify", 4: "tune", 5: "done",
         6: "failed"}


# ------------------------------------------------------------------ plants

class Plant:
    """num(s) / den(s) e^{-L s}, with what the reference rule needs."""

    def __init__(self, fam, label, num, den, L, half=None, integ=False, note=""):
        self.fam, self.label = fam, label
        self.num = np.atleast_1d(np.asarray(num, float))
        self.den = np.atleast_1d(np.asarray(den, float))
        self.L, self.half, self.integ, self.note = float(L), half, integ, note

    @property
    def name(self):
        return f"{self.fam} {self.label}"

    def resp(self, w):
        s = 1j * np.asarray(w, float)
        return np.polyval(self.num, s) / np.polyval(self.den, s) * np.exp(-s * self.L)

    def gain(self):
        """DC gain (stable), or integrating gain (integrating)."""
        if self.integ:
            return float(self.num[-1] / self.den[-2])
        return float(self.num[-1] / self.den[-1])


def lagpoly(taus):
    p = np.array([1.0])
    for t in taus:
        p = np.polymul(p, [t, 1.0])
    return p


def batch():
    P = []
    for T in (0.1, 1.0, 10.0):
        P.append(Plant("P1", f"T={T:g}", [1.0], lagpoly([T]), 1.0,
                       half=(1.0, [T], [], 1.0)))
    for T in (0.1, 1.0, 10.0):
        P.append(Plant("P2", f"T={T:g}", [1.0], lagpoly([T, T]), 1.0,
                       half=(1.0, [T, T], [], 1.0)))
    for T in (0.1, 0.5, 2.0):
        P.append(Plant("P3", f"T={T:g}", [1.0], lagpoly([1.0, T, T]), 0.0,
                       half=(1.0, [1.0, T, T], [], 0.0)))
    for n in (3, 5, 8):
        P.append(Plant("P4", f"n={n}", [1.0], lagpoly([1.0] * n), 0.0,
                       half=(1.0, [1.0] * n, [], 0.0)))
    for a in (0.2, 0.5, 0.9):
        lags = [1.0, a, a * a, a ** 3]
        P.append(Plant("P5", f"alpha={a:g}", [1.0], lagpoly(lags), 0.0,
                       half=(1.0, lags, [], 0.0)))
    for L in (0.1, 0.5, 1.0):
        T = 1.0 - L
        den = np.polymul([1.0, 0.0], lagpoly([T])) if T > 0 else np.array([1.0, 0.0])
        P.append(Plant("P6", f"L={L:g}", [1.0], den, L, integ=True))
    for T in (1.0, 5.0, 10.0):
        T1 = L = 0.5
        P.append(Plant("P7", f"T={T:g}", [T], lagpoly([T, T1]), L,
                       half=(T, [T, T1], [], L)))
    for a in (0.1, 0.5, 1.1):
        P.append(Plant("P8", f"alpha={a:g}", [-a, 1.0], lagpoly([1.0] * 3), 0.0,
                       half=(1.0, [1.0] * 3, [-a], 0.0)))
    for T in (0.1, 0.5, 1.0):
        den = np.polymul([1.0, 1.0], [T * T, 1.4 * T, 1.0])
        P.append(Plant("P9", f"T={T:g}", [1.0], den, 0.0))
    return P


# ------------------------------------------------------------------ simulation

def zoh_delay(p, Ts):
    """x[k+1] = Phi x[k] + Gb u[k-l] + Ga u[k-l-1] for the dead time (l+f) Ts."""
    return plant.fractional(p.num, p.den, p.L, Ts)


def sim_step(h, p, n_steps):
    """Open-loop unit step response at t = k h (exact ZOH, L a whole number of steps)."""
    return plant.step_response(p.num, p.den, p.L, h, n_steps)


def time_scale(p):
    """T63 of the step response (stable), or L + T (integrating)."""
    if p.integ:
        return 1.0   # L + T = 1 over the family
    K = p.gain()
    h = 0.002
    n = 40000
    while True:
        y = sim_step(h, p, n) * math.copysign(1.0, K)
        idx = np.nonzero(y >= 0.632 * abs(K))[0]
        if len(idx):
            return float(idx[0] * h)
        h *= 4.0


def sim_grid(p, scale):
    """Fine step h with the dead time a whole number of steps."""
    h = scale / SIM_STEPS
    if p.L > 0:
        h = p.L / math.ceil(p.L / h)
    return h


def closed_loop(p, g, scale, load):
    """IAE of a unit set-point step (load False) or unit input load step.

    Ideal-form PID sampled every h (fine): P and I on the error, the
    filtered derivative on the measurement (for the load step, where the
    set-point stays 0, the same as on the error). Returns IAE and the
    error left at the end (to flag loops that have not settled)."""
    Kc, tI, tD, Tf = g
    h = sim_grid(p, scale)
    sim = plant.Fine(p.num, p.den, h, int(round(p.L / h)))
    n_steps = int(round(SIM_SPAN * scale / h))
    r = 0.0 if load else 1.0
    d = 1.0 if load else 0.0
    I = 0.0
    xf = 0.0
    af = math.exp(-h / Tf) if Tf > 0 else 0.0
    iae = 0.0
    e = 0.0
    for _ in range(n_steps):
        y = sim.output()
        e = r - y
        if not math.isfinite(y) or abs(y) > 1e6:
            return float("inf"), float("inf")
        ud = 0.0
        if tD > 0:
            if Tf > 0:
                ud = -tD * (y - xf) / Tf
                xf += (1.0 - af) * (y - xf)
            else:
                ud = -tD * (y - xf) / h
                xf = y
        u = Kc * (e + I + ud)
        I += h * e / tI
        iae += abs(e) * h
        sim.advance(u + d)             # moved by the input of L before
    return iae, abs(e)


def ctrl_resp(g, w):
    Kc, tI, tD, Tf = g
    s = 1j * w
    return Kc * (1.0 + 1.0 / (tI * s) + tD * s / (Tf * s + 1.0))


def robustness(p, g, scale):
    """True Ms, and stability by the Nyquist criterion on the true loop.

    L has no right-half-plane pole; its poles at s = 0 are the controller's
    integrator and the plant's (P6). The loop is stable when the phase of
    1 + L, followed continuously from low to high frequency, rises by
    n0 pi / 2 (n0 poles at the origin) and |L| < 1 at the top."""
    w = np.logspace(-4, 4, 40001) / scale
    Lw = p.resp(w) * ctrl_resp(g, w)
    F = 1.0 + Lw
    ph = np.unwrap(np.angle(F))
    n0 = 1 + (1 if p.integ else 0)
    stable = abs((ph[-1] - ph[0]) - n0 * math.pi / 2) < 0.5 and abs(Lw[-1]) < 1
    S = 1.0 / np.abs(F)
    i = int(np.argmax(S))
    lo, hi = w[max(i - 1, 0)], w[min(i + 1, len(w) - 1)]
    res = so.minimize_scalar(
        lambda lw: -1.0 / abs(1.0 + p.resp(np.exp(lw)) * ctrl_resp(g, np.exp(lw))),
        bounds=(math.log(lo), math.log(hi)), method="bounded",
        options={"xatol": 1e-10})
    Ms = max(float(S[i]), -float(res.fun))
    return Ms, bool(stable)


# ------------------------------------------------------------------ the driver

def build():
    subprocess.run(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-G", "Ninja",
                    "-DCMAKE_BUILD_TYPE=Release", "-DPDT_BUILD_TESTS=OFF",
                    "-DPDT_REAL_DOUBLE=OFF"], check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(BUILD), "--target", "pdt_autotune_driver"],
                   check=True, stdout=subprocess.DEVNULL)


def drive(text):
    r = subprocess.run([str(DRIVER)], input=text, capture_output=True, text=True,
                       check=True)
    out = {}
    for line in r.stdout.splitlines():
        k, v = line.split()
        out[k] = float(v)
    return out


def fmt_plant(p, Ts):
    Phi, Gb, Ga, C, l = zoh_delay(p, Ts)
    n = len(C)
    vals = [f"{Ts:.17g}", str(n), str(l)]
    vals += [f"{v:.17g}" for v in Phi.ravel()]
    vals += [f"{v:.17g}" for v in Gb]
    vals += [f"{v:.17g}" for v in Ga]
    vals += [f"{v:.17g}" for v in C]
    return " ".join(vals)


def gains_of(out, tag):
    if out.get(f"{tag}_status", -99) != 0 and f"{tag}_Kc" not in out:
        return None
    return (out[f"{tag}_Kc"], out[f"{tag}_tauI"], out[f"{tag}_tauD"], out[f"{tag}_Tf"])


def experiment(p, scale):
    """The experiment rule: the user knows the time scale, nothing else."""
    Ts_id = scale / SAMPLES_PER_SCALE
    Ts = Ts_id / DECIMATION
    on, off = (PULSE_ON_INT, PULSE_OFF_INT) if p.integ else (PULSE_ON, PULSE_OFF)
    capacity = SETTLE + int(round((on + off) * SAMPLES_PER_SCALE))
    swing = abs(p.gain()) * AMP * (on * scale if p.integ else 1.0)
    return dict(Ts=Ts, Ts_id=Ts_id, on=on * scale, off=off * scale, capacity=capacity,
                swing=swing, std=NOISE * swing)


def autotune(p, scale, seed, model, form):
    e = experiment(p, scale)
    max_scans = int(2 * e["capacity"] * DECIMATION)
    lim = 5.0 * e["swing"]
    text = " ".join([
        "autotune", fmt_plant(p, e["Ts"]),
        f"{e['std']:.17g}", str(seed), str(max_scans),
        str(DECIMATION), str(e["capacity"]), str(SETTLE), f"{AMP:.17g}",
        f"{e['on']:.17g}", f"{e['off']:.17g}", "-2", "2",
        f"{-lim:.17g}", f"{lim:.17g}", str(model), "1", str(form)])
    out = drive(text)
    out["Ts"] = e["Ts"]
    return out


def relay(p, scale, seed):
    e = experiment(p, scale)
    max_scans = int(200 * scale / e["Ts"])
    text = " ".join(["relay", fmt_plant(p, e["Ts"]), f"{e['std']:.17g}", str(seed),
                     str(max_scans), f"{AMP:.17g}", f"{RELAY_EPS * e['std']:.17g}",
                     str(RELAY_NEW[0]), str(RELAY_NEW[1]), str(RELAY_NEW[2])])
    out = drive(text)
    out["Ts"] = e["Ts"]
    return out


def fit_step(p, scale, order):
    """Least-squares FOPDT (order 1) or real-pole SOPDT (2) of the true
    step response over 0 .. 8 time scales."""
    h = scale / 200.0
    n = int(8 * 200)
    t = np.arange(n) * h
    y = sim_step(h, p, n)
    K = p.gain()

    def model(x):
        if order == 1:
            k, tau, th = x
            tt = np.maximum(t - th, 0.0)
            return k * (1.0 - np.exp(-tt / tau))
        k, t1, t2, th = x
        tt = np.maximum(t - th, 0.0)
        if abs(t1 - t2) < 1e-6 * max(t1, t2):
            t2 = t1 * (1 - 1e-6)
        return k * (1.0 - (t1 * np.exp(-tt / t1) - t2 * np.exp(-tt / t2)) / (t1 - t2))

    if order == 1:
        x0 = [K, 0.7 * scale, 0.3 * scale]
        lb, ub = [0.5 * K, 1e-3, 0.0], [2 * K, 10 * scale, 5 * scale]
    else:
        x0 = [K, 0.5 * scale, 0.2 * scale, 0.1 * scale]
        lb, ub = [0.5 * K, 1e-3, 1e-3, 0.0], [2 * K, 10 * scale, 10 * scale, 5 * scale]
    r = so.least_squares(lambda x: model(x) - y, x0, bounds=(lb, ub), xtol=1e-12,
                         ftol=1e-12)
    return r.x


def reference(p, scale):
    """SIMC PI and PID of the best low-order model of the true plant."""
    if p.half is not None:
        k, lags, zeros, th0 = p.half
        text = " ".join(["halfrule", repr(k), str(len(lags))] + [repr(v) for v in lags]
                        + [str(len(zeros))] + [repr(v) for v in zeros] + [repr(th0)])
        out = drive(text)
        fo = (out["fopdt_K"], out["fopdt_tau"], out["fopdt_Td"])
        src = "half rule"
        if "sopdt_k" in out:
            sod = (out["sopdt_k"], out["sopdt_a"], out["sopdt_b"], out["sopdt_Td"])
            mdesc = (f"FOPDT K={fo[0]:.3g} tau={fo[1]:.3g} Td={fo[2]:.3g}; "
                     f"SOPDT T1,T2 from a={sod[1]:.3g} b={sod[2]:.3g}, Td={sod[3]:.3g}")
        else:
            mdesc = f"FOPDT K={fo[0]:.3g} tau={fo[1]:.3g} Td={fo[2]:.3g} (PID = PI)"
        return gains_of(out, "pi"), gains_of(out, "pid"), src, mdesc
    if p.integ:
        T = max(1.0 - p.L, 1e-3)
        a = 1.0 / T
        out = drive(f"model 2 {a!r} {a!r} 0 {p.L!r}")
        mdesc = f"exact: integrator, lag {T:.3g}, Td={p.L:.3g}"
        return gains_of(out, "pi"), gains_of(out, "pid"), "exact model", mdesc
    k, tau, th = (float(v) for v in fit_step(p, scale, 1))
    o1 = drive(f"model 1 {k!r} {tau!r} {th!r}")
    k2, t1, t2, th2 = (float(v) for v in fit_step(p, scale, 2))
    o2 = drive(f"model 2 {k2 / (t1 * t2)!r} {(t1 + t2) / (t1 * t2)!r} "
               f"{1.0 / (t1 * t2)!r} {th2!r}")
    mdesc = (f"FOPDT K={k:.3g} tau={tau:.3g} Td={th:.3g}; "
             f"SOPDT K={k2:.3g} T1={max(t1, t2):.3g} T2={min(t1, t2):.3g} Td={th2:.3g}")
    return gains_of(o1, "pi"), gains_of(o2, "pid"), "step-response fit", mdesc


def with_filter(g):
    """ZN gains come unfiltered: give them the same filter as SIMC's."""
    if g is None:
        return None
    Kc, tI, tD, Tf = g
    if tD > 0 and Tf == 0:
        Tf = tD / DFILT
    return (Kc, tI, tD, Tf)


def evaluate(p, g, scale):
    if g is None:
        return None
    Ms, stable = robustness(p, g, scale)
    sp, sp_end = closed_loop(p, g, scale, False)
    ld, ld_end = closed_loop(p, g, scale, True)
    Ks = abs(p.gain()) * (scale if p.integ else 1.0)
    return dict(g=g, Ms=Ms, stable=stable, sp=sp / scale, ld=ld / (Ks * scale),
                settled=sp_end < 0.02 and ld_end < 0.02 * Ks)


def run_one(args):
    i, p = args
    scale = time_scale(p)
    seed = 1000 + i
    # The model order is the library's default (0): the data choose.
    at = autotune(p, scale, seed, 0, 1)
    at1 = autotune(p, scale, seed, 0, 0)
    rl = relay(p, scale, seed)
    ref_pi, ref_pid, src, mdesc = reference(p, scale)
    ctrl = {
        "at_pi": gains_of(at1, "pi") if at1.get("pi_status") == 0 else None,
        "at_pid": gains_of(at, "pid") if at.get("pid_status") == 0 else None,
        "ref_pi": ref_pi, "ref_pid": ref_pid,
        "zn_pi": gains_of(rl, "pi"), "zn_pid": with_filter(gains_of(rl, "pid")),
    }
    ev = {k: evaluate(p, g, scale) for k, g in ctrl.items()}
    return dict(p=p, scale=scale, at=at, at1=at1, rl=rl, src=src, mdesc=mdesc, ev=ev)


# ------------------------------------------------------------------ report

def model_desc(at):
    if not at.get("has_model"):
        return "-"
    if at["model_kind"] == 1:
        return f"FOPDT K={at['model_K']:.3g} tau={at['model_tau']:.3g} Td={at['model_Td']:.3g}"
    k, a, b, Td = at["model_k"], at["model_a"], at["model_b"], at["model_Td"]
    if b == 0:
        return f"integ. Ki={k / a:.3g} T={1 / a:.3g} Td={Td:.3g}"
    disc = a * a - 4 * b
    if disc >= 0:
        r1 = (a + math.sqrt(disc)) / 2
        r2 = (a - math.sqrt(disc)) / 2
        return f"SOPDT K={k / b:.3g} T1={1 / r2:.3g} T2={1 / r1:.3g} Td={Td:.3g}"
    wn = math.sqrt(b)
    return f"SOPDT K={k / b:.3g} wn={wn:.3g} zeta={a / (2 * wn):.3g} Td={Td:.3g}"


def cell(e, key):
    if e is None:
        return "refused"
    if not e["stable"]:
        return "unstable"
    v = e[key]
    s = f"{v:.2f}" if key == "Ms" else f"{v:.3g}"
    if key != "Ms" and not e["settled"]:
        s += "*"
    return s


def status_of(at, tag):
    st = int(at.get(f"{tag}_status", at.get("status", -99)))
    if not at.get("has_model"):
        return STATUS.get(int(at.get("status", -99)), str(at.get("status")))
    if st == 0:
        return "ok"
    why = STATUS.get(st, str(st))
    if st == CODES["MS_LIMIT"] and f"{tag}_refused_Ms_model" in at:
        why = f"Ms {at[f'{tag}_refused_Ms_model']:.2f} on model > 2"
    return why


def geo(xs):
    xs = [x for x in xs if x is not None and math.isfinite(x) and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def ratios(res, a, b, key):
    out = []
    for r in res:
        ea, eb = r["ev"][a], r["ev"][b]
        if ea and eb and ea["stable"] and eb["stable"]:
            out.append(ea[key] / eb[key])
    return out


def plots(res):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = [r["p"].name for r in res]
    x = np.arange(len(res))
    fig, axs = plt.subplots(3, 1, figsize=(12, 10), sharex=True)
    for ax, key, lab in zip(axs, ("sp", "ld", "Ms"),
                            ("set-point IAE / T", "load IAE / (K T)", "true Ms")):
        for off, k, c, m in ((-0.25, "at_pid", "C0", "o"), (0.0, "ref_pid", "C1", "s"),
                             (0.25, "zn_pid", "C2", "^")):
            v = [r["ev"][k][key] if r["ev"][k] and r["ev"][k]["stable"] else np.nan
                 for r in res]
            ax.semilogy(x + off, v, m, color=c, ls="none",
                        label={"at_pid": "pdtfit autotune SIMC PID",
                               "ref_pid": "SIMC PID, best model",
                               "zn_pid": "ZN PID, relay"}[k])
        ax.set_ylabel(lab)
        ax.grid(True, which="both", alpha=0.3)
    axs[0].legend(fontsize=8)
    axs[-1].set_xticks(x)
    axs[-1].set_xticklabels(names, rotation=90, fontsize=8)
    fig.tight_layout()
    fig.savefig(IMG / "autotune-pid.png", dpi=90)
    plt.close(fig)


TEMPLATE = pathlib.Path(__file__).with_name("autotune_bench.md.in")


def constants():
    """The experiment rule's and the loop's settings, as the prose quotes them."""
    return {"noise_pct": f"{NOISE * 100:g}", "amp": f"{AMP:g}", "pulse_on": f"{PULSE_ON:g}",
            "pulse_off": f"{PULSE_OFF:g}", "pulse_on_int": f"{PULSE_ON_INT:g}",
            "pulse_off_int": f"{PULSE_OFF_INT:g}", "samples_per_scale": f"{SAMPLES_PER_SCALE}",
            "scan_div": f"{SAMPLES_PER_SCALE * DECIMATION}", "decimation": f"{DECIMATION}",
            "settle": f"{SETTLE}", "relay_eps": f"{RELAY_EPS:g}", "sim_steps": f"{SIM_STEPS}",
            "sim_span": f"{SIM_SPAN:g}"}


def runs_section(res):
    """The autotune runs' table rows and the refusals below it."""
    n = len(res)
    rows, refused, noform = [], [], []
    for r in res:
        at, at1, rl, p = r["at"], r["at1"], r["rl"], r["p"]
        T = r["scale"]
        exp_T = at.get("scans_experiment", 0) * at["Ts"] / T
        idn = int(at.get("scans", 0) - at.get("scans_experiment", 0))
        fit = f"{at['fit']:.1f}" if at.get("has_model") else "-"
        fit1 = f"{at1['fit']:.1f}" if at1.get("has_model") else "-"
        pid_s, pi_s, pis_s = status_of(at, "pid"), status_of(at1, "pi"), status_of(at, "pi")
        if pid_s != "ok":
            refused.append((p.name, "PID", pid_s))
        if pi_s != "ok":
            refused.append((p.name, "PI", pi_s))
        if pis_s != "ok":
            noform.append((p.name, pis_s))
        rel_T = rl.get("scans", 0) * rl["Ts"] / T
        ku = f"{rl['Ku']:.3g}" if "Ku" in rl else "-"
        pu = f"{rl['Pu']:.3g}" if "Pu" in rl else "-"
        rows.append(f"| {p.name} | {T:.3g} | {pid_s} | {exp_T:.1f} | {idn} | {fit} | "
                    f"{model_desc(at)} | {pi_s} | {fit1} | {model_desc(at1)} | {pis_s} | "
                    f"{rel_T:.1f} | {ku} | {pu} |")
    if all(r["at"].get("has_model") and r["at1"].get("has_model") for r in res):
        block = (f"Refused: {len(refused)} of {2 * n} autotune runs "
                 f"({sum(1 for x in refused if x[1] == 'PID')} PID, "
                 f"{sum(1 for x in refused if x[1] == 'PI')} PI); no run was aborted "
                 "by a safety limit or failed to identify.")
    else:
        block = f"Refused or failed: {len(refused)} of {2 * n} autotune runs."
    if refused:
        block += "\n\n" + "\n".join(f"- {name} {tag}: {why}" for name, tag, why in refused)
    return {"runs_rows": "\n".join(rows), "refused_block": block,
            "noform_count": str(len(noform)),
            "noform_list": (": " + ", ".join(f"{a} ({b})" for a, b in noform)) if noform else ""}


def gains_section(res, tagA, tagR, tagZ, form):
    """One controller form's results and gains on the true plant."""
    rows, gains = [], []
    for r in res:
        ev = r["ev"]
        row = [r["p"].name]
        for key in ("sp", "ld", "Ms"):
            row += [cell(ev[tagA], key), cell(ev[tagR], key), cell(ev[tagZ], key)]
        rows.append("| " + " | ".join(row) + " |")
        cells = []
        for k in (tagA, tagR, tagZ):
            e = ev[k]
            if e is None:
                cells.append("-")
            else:
                g = e["g"]
                cells.append(", ".join(f"{v:.3g}" for v in (g if form == "PID" else g[:2])))
        gains.append(f"| {r['p'].name} | " + " | ".join(cells) + " |")
    return "\n".join(rows), "\n".join(gains)


def summary_section(res):
    """The summary's two tables and the list of clearly worse runs."""
    ratio_rows, count_rows, worse = [], [], []
    for a, b, lab in (("at_pi", "ref_pi", "autotune PI / reference SIMC PI"),
                      ("at_pid", "ref_pid", "autotune PID / reference SIMC PID"),
                      ("at_pi", "zn_pi", "autotune PI / ZN PI"),
                      ("at_pid", "zn_pid", "autotune PID / ZN PID")):
        rs = ratios(res, a, b, "sp")
        ratio_rows.append(f"| {lab} | {len(rs)} | {geo(rs):.3f} | "
                          f"{geo(ratios(res, a, b, 'ld')):.3f} | "
                          f"{geo(ratios(res, a, b, 'Ms')):.3f} |")
    for k, lab in (("at_pi", "autotune PI"), ("at_pid", "autotune PID"),
                   ("ref_pi", "reference SIMC PI"), ("ref_pid", "reference SIMC PID"),
                   ("zn_pi", "ZN PI (relay)"), ("zn_pid", "ZN PID (relay)")):
        es = [r["ev"][k] for r in res if r["ev"][k] is not None]
        st = [e for e in es if e["stable"]]
        mx = max((e["Ms"] for e in st), default=float("nan"))
        count_rows.append(f"| {lab} | {len(es)} | {sum(1 for e in es if not e['stable'])} | "
                          f"{sum(1 for e in st if e['Ms'] > 2)} | {mx:.2f} | "
                          f"{sum(1 for e in st if not e['settled'])} |")
    for r in res:
        for a, b in (("at_pi", "ref_pi"), ("at_pid", "ref_pid")):
            ea, eb = r["ev"][a], r["ev"][b]
            if ea and eb and ea["stable"] and eb["stable"]:
                q = ea["ld"] / eb["ld"]
                if q > 1.25 or ea["Ms"] > eb["Ms"] * 1.15:
                    worse.append(f"{r['p'].name} {a[3:].upper()}: load IAE x{q:.2f}, "
                                 f"Ms {ea['Ms']:.2f} against {eb['Ms']:.2f}")
    return {"ratio_rows": "\n".join(ratio_rows), "count_rows": "\n".join(count_rows),
            "worse_list": "\n".join(f"- {w}" for w in worse) if worse else "- none"}


def reading_figures(res):
    """The figures the reading of the results quotes."""
    runs = [r[k] for r in res for k in ("at", "at1") if r[k].get("has_model")]
    idn = [int(a.get("scans", 0) - a.get("scans_experiment", 0)) for a in runs]
    idn_T = [(a.get("scans", 0) - a.get("scans_experiment", 0)) * a["Ts"] / r["scale"]
             for r in res for a in (r["at"], r["at1"]) if a.get("has_model")]
    return {"n_runs": str(len(runs)),
            "n_fo": str(sum(1 for a in runs if int(a["model_kind"]) == 1)),
            "n_so": str(sum(1 for a in runs if int(a["model_kind"]) == 2)),
            "idn_min": str(min(idn)), "idn_max": str(max(idn)),
            "idn_med": str(int(np.median(idn))),
            "idn_T_min": f"{min(idn_T):.1f}", "idn_T_max": f"{max(idn_T):.1f}"}


def report(res, ev_text):
    """docs/reports/autotune-benchmark.md: the template autotune_bench.md.in
    filled with the evidence section and the batch's tables."""
    values = {"evidence": ev_text, "n": str(len(res)), **constants(), **runs_section(res),
              **summary_section(res), **reading_figures(res),
              "reference_rows": "\n".join(f"| {r['p'].name} | {r['src']} | {r['mdesc']} |"
                                          for r in res)}
    values["pi_rows"], values["pi_gain_rows"] = gains_section(res, "at_pi", "ref_pi", "zn_pi",
                                                              "PI")
    values["pid_rows"], values["pid_gain_rows"] = gains_section(res, "at_pid", "ref_pid",
                                                                "zn_pid", "PID")
    values.update(provenance.fields())
    return string.Template(TEMPLATE.read_text()).substitute(values)


# ------------------------------------------------------------------ the evidence batch

def evidence_plants():
    """The batch of the evidence section: every class the autotune meets."""
    P = []
    P.append(Plant("E1", "lag-dominant FOPDT", [1.0], lagpoly([10.0]), 1.0,
                   half=(1.0, [10.0], [], 1.0)))
    P.append(Plant("E2", "lag-dominant SOPDT", [2.0], lagpoly([2.0, 1.0]), 0.3,
                   half=(2.0, [2.0, 1.0], [], 0.3)))
    P.append(Plant("E3", "delay-dominant", [1.0], lagpoly([1.0]), 5.0,
                   half=(1.0, [1.0], [], 5.0)))
    P.append(Plant("E4", "four lags", [1.0], lagpoly([1.0] * 4), 0.0,
                   half=(1.0, [1.0] * 4, [], 0.0)))
    P.append(Plant("E5", "three lags + delay", [0.7], lagpoly([3.0] * 3), 1.0,
                   half=(0.7, [3.0] * 3, [], 1.0)))
    P.append(Plant("E6", "LHP zero", [0.5, 1.0], lagpoly([2.0, 1.0, 1.0]), 0.2,
                   half=(1.0, [2.0, 1.0, 1.0], [0.5], 0.2)))
    P.append(Plant("E7", "RHP zero", [-0.5, 1.0], lagpoly([1.0] * 3), 0.0,
                   half=(1.0, [1.0] * 3, [-0.5], 0.0)))
    P.append(Plant("E8", "lead-lag", [2.0, 1.0], lagpoly([4.0, 1.0]), 0.5))
    P.append(Plant("E9", "negative gain FOPDT", [-1.5], lagpoly([6.0]), 1.5,
                   half=(-1.5, [6.0], [], 1.5)))
    P.append(Plant("E10", "negative gain SOPDT", [-1.0], lagpoly([3.0, 1.0]), 1.0,
                   half=(-1.0, [3.0, 1.0], [], 1.0)))
    P.append(Plant("E11", "integrating + lag", [1.0], np.polymul([1.0, 0.0], lagpoly([0.5])),
                   0.5, integ=True))
    P.append(Plant("E12", "pure integrator + delay", [1.0], np.array([1.0, 0.0]), 1.0,
                   integ=True))
    P.append(Plant("E13", "underdamped zeta 0.4", [1.0], [1.0, 0.8, 1.0], 0.5))
    P.append(Plant("E14", "underdamped zeta 0.6", [2.0], [4.0, 2.4, 1.0], 1.0))
    return P


EXPERIMENTS = ("relay", "PRBS", "step", "pulse")
NOISES = (0.0, 0.01, 0.03)
SEEDS = (1, 2, 3)
RELAY_NEW = (0, 3, 0.1)    # relay_skip, relay_cycles, relay_settle: the defaults
RELAY_OLD = (1, 3, 0.0)    # the relay as it was
EV_STATUS = STATUS


def ev_experiment(p, scale, exp):
    Ts_id = scale / SAMPLES_PER_SCALE
    Ts = Ts_id / DECIMATION
    tail = 0
    p1 = p2 = 0.0
    if exp == "pulse":
        on, off = (PULSE_ON_INT, PULSE_OFF_INT) if p.integ else (PULSE_ON, PULSE_OFF)
        p1, p2 = on * scale, off * scale
        capacity = SETTLE + int(round((on + off) * SAMPLES_PER_SCALE))
    elif exp == "step":
        capacity = SETTLE + 8 * SAMPLES_PER_SCALE
    elif exp == "PRBS":
        chip = 0.5 * scale
        p1 = max(1, int(round(chip / Ts)))
        p2 = 5
        body = 31 * p1 * Ts
        capacity = SETTLE + int(round((body + 3 * scale) / Ts_id))
        tail = int(3 * SAMPLES_PER_SCALE)
    else:
        capacity = SETTLE + 40 * SAMPLES_PER_SCALE
        tail = int(3 * SAMPLES_PER_SCALE)
    swing = abs(p.gain()) * AMP * (8.0 * scale if p.integ else 1.0)
    return dict(Ts=Ts, capacity=capacity, tail=tail, p1=p1, p2=p2, swing=swing)


def ev_autotune(p, scale, exp, noise, seed, old=False, order=1, form=0):
    e = ev_experiment(p, scale, exp)
    std = noise * abs(p.gain()) * AMP * (scale if p.integ else 1.0)
    lim = 5.0 * e["swing"]
    max_scans = int(3 * e["capacity"] * DECIMATION)
    kind = EXPERIMENTS.index(exp)
    skip, cyc, settle = RELAY_OLD if old else RELAY_NEW
    n_sp = int(round(30 * scale / e["Ts"]))
    if old:   # the library as it was: FOPDT, fit >= 80 %, Ms <= 2 on the model only
        order, ms_rob, fit_min, agree = 0, 0.0, 80.0, 0.0
    else:
        ms_rob, fit_min, agree = 2.0, 0.0, 2.0
    text = " ".join(str(v) for v in [
        "at", fmt_plant(p, e["Ts"]), f"{std:.17g}", seed, max_scans,
        kind, DECIMATION, e["capacity"], SETTLE, e["tail"], f"{AMP:.17g}",
        f"{e['p1']:.17g}", f"{e['p2']:.17g}", -2 * AMP, 2 * AMP, f"{-lim:.17g}",
        f"{lim:.17g}", 1000 + seed, form, order, ms_rob, fit_min, agree,
        f"{RELAY_EPS * std:.17g}", skip, cyc, n_sp, n_sp, 1 if p.gain() < 0 else 0, settle])
    out = drive(text)
    out["Ts"] = e["Ts"]
    out["n_sp"] = n_sp
    return out


def ev_loop(p, scale, g):
    Ts = scale / SAMPLES_PER_SCALE / DECIMATION
    n_sp = int(round(30 * scale / Ts))
    out = drive(" ".join(["loop", fmt_plant(p, Ts)] + [f"{v:.17g}" for v in g]
                         + [str(n_sp), str(n_sp)]))
    return out


def true_ultimate(p):
    """Ku (input per output unit) and Pu of the true plant: the first
    crossing of -180 degrees of its unwrapped phase (sign taken out)."""
    w = np.logspace(-4, 3, 200001)
    G = p.resp(w) * math.copysign(1.0, p.gain())
    ph = np.unwrap(np.angle(G))
    idx = np.nonzero(ph <= -math.pi)[0]
    if not len(idx):
        return None
    i = idx[0]
    return 1.0 / abs(G[i]), 2 * math.pi / w[i]


def ev_one(args):
    pi, p = args
    scale = time_scale(p)
    runs, pid_runs = [], []
    for exp in EXPERIMENTS:
        for noise in NOISES:
            for seed in (SEEDS if noise > 0 else (1,)):
                for old, form in ((False, 0), (True, 0), (False, 1)):
                    out = ev_autotune(p, scale, exp, noise, seed, old=old, form=form)
                    r = dict(exp=exp, noise=noise, seed=seed, old=old,
                             status=int(out.get("status", -99)), out=out)
                    if out.get("has_gains"):
                        g = (out["at_Kc"], out["at_tauI"], out["at_tauD"], out["at_Tf"])
                        Ms, stable = robustness(p, g, scale)
                        r.update(Ms=Ms, stable=stable and out.get("cl_bounded", 0) == 1,
                                 sp=out.get("cl_sp_iae", math.inf) / scale,
                                 ld=out.get("cl_load_iae", math.inf),
                                 ov=out.get("cl_overshoot", math.nan),
                                 Ms_model=out["at_Ms_model"],
                                 kind=int(out["model_kind"]),
                                 detune=out.get("detune", 1.0))
                    (pid_runs if form == 1 else runs).append(r)
    ref_pi, ref_pid, src, mdesc = reference(p, scale)
    ref = None
    if ref_pi is not None:
        Ms, stable = robustness(p, ref_pi, scale)
        lo = ev_loop(p, scale, ref_pi)
        ref = dict(g=ref_pi, Ms=Ms, stable=stable, sp=lo.get("cl_sp_iae", math.inf) / scale,
                   ld=lo.get("cl_load_iae", math.inf), src=src)
    ref_d = None
    if ref_pid is not None:
        Ms, stable = robustness(p, ref_pid, scale)
        lo = ev_loop(p, scale, ref_pid)
        ref_d = dict(g=ref_pid, Ms=Ms, stable=stable,
                     sp=lo.get("cl_sp_iae", math.inf) / scale,
                     ld=lo.get("cl_load_iae", math.inf), src=src)
    return dict(p=p, scale=scale, runs=runs, pid_runs=pid_runs, ref=ref, ref_pid=ref_d)


def relay_study(args):
    """Relay length against accuracy: (skip, cycles) variants, Ku and Pu
    against the true ultimate point."""
    pi, p = args
    scale = time_scale(p)
    tu = true_ultimate(p)
    rows = []
    if tu is None:
        return dict(p=p, rows=rows)
    e = ev_experiment(p, scale, "relay")
    for skip, cyc, settle in RELAY_VARIANTS:
        for noise in (0.0, 0.01, 0.03):
            for seed in (SEEDS if noise > 0 else (1,)):
                std = noise * abs(p.gain()) * AMP * (scale if p.integ else 1.0)
                max_scans = int(200 * scale / e["Ts"])
                sign = 1 if p.gain() > 0 else -1
                # the relay mode acts reverse; a negative plant gets -d
                text = " ".join(["relay", fmt_plant(p, e["Ts"]), f"{std:.17g}", str(seed),
                                 str(max_scans), f"{AMP:.17g}", f"{RELAY_EPS * std:.17g}",
                                 str(skip), str(cyc), str(settle)])
                if sign < 0:
                    continue
                out = drive(text)
                if int(out.get("status", -99)) != 0:
                    rows.append(dict(skip=skip, cyc=cyc, settle=settle, noise=noise, ok=False))
                    continue
                rows.append(dict(skip=skip, cyc=cyc, settle=settle, noise=noise, ok=True,
                                 t=out["scans"] * e["Ts"] / scale,
                                 eK=abs(out["Ku"]) / tu[0] - 1.0,
                                 eP=out["Pu"] / tu[1] - 1.0))
    return dict(p=p, rows=rows)


RELAY_VARIANTS = ((1, 3, 0.0), (0, 2, 0.0), (0, 1, 0.0), (0, 3, 0.1))

MC_SEEDS = 40


def mc_one(args):
    """Monte-Carlo check of the reported std: PRBS at 3 % noise, the true
    model class fixed, MC_SEEDS noise seeds."""
    name, p, order = args
    scale = time_scale(p)
    vals, stds = [], []
    for seed in range(1, MC_SEEDS + 1):
        out = ev_autotune(p, scale, "PRBS", 0.03, 100 + seed, order=order)
        if not out.get("has_model") or "std0" not in out:
            continue
        if order == 0:
            v = [out["model_K"], out["model_tau"], out["model_Td"]]
        else:
            v = [out["model_k"], out["model_a"], out["model_b"], out["model_Td"]]
        vals.append(v)
        stds.append([out[f"std{i}"] for i in range(len(v))])
    return dict(name=name, order=order, vals=np.array(vals), stds=np.array(stds))


EV_TEMPLATE = pathlib.Path(__file__).with_name("autotune_evidence.md.in")


def ev_counts(runs):
    """The completion and Ms sentence of a set of runs, and its refusals."""
    n = len(runs)
    done = [r for r in runs if r["status"] == 0]
    ms = np.array([r["Ms"] for r in done if r["stable"]])
    le = int(np.sum(ms <= 2.2)) if len(ms) else 0
    text = (f"completed {len(done)} of {n} runs ({100.0 * len(done) / n:.1f} %); "
            f"unstable loops on the true plant: {sum(1 for r in done if not r['stable'])}; "
            f"Ms on the true plant <= 2.2 in {le} of {len(done)} completed runs "
            f"({100.0 * le / max(len(done), 1):.1f} %); Ms median {np.median(ms):.2f}, "
            f"95th percentile {np.percentile(ms, 95):.2f}, largest {ms.max():.2f}")
    refused = {}
    for r in runs:
        if r["status"] != 0:
            k = EV_STATUS.get(r["status"], str(r["status"]))
            refused[k] = refused.get(k, 0) + 1
    return text, ", ".join(f"{k} {v}" for k, v in sorted(refused.items())) or "none"


def ev_plant_row(x):
    """One plant's row of the per-plant table (new | old)."""
    ref = x["ref"]
    row = [x["p"].name, f"{ref['Ms']:.2f}" if ref else "-"]
    cells = {}
    for old in (False, True):
        d = [r for r in x["runs"] if r["old"] == old and r["status"] == 0]
        mx = max((r["Ms"] if r["stable"] else math.inf) for r in d) if d else math.nan
        sp = [r["sp"] / ref["sp"] for r in d if ref and r["stable"]]
        ld = [r["ld"] / ref["ld"] for r in d if ref and r["stable"]]
        cells[old] = (len(d), mx, np.median(sp) if sp else math.nan,
                      np.median(ld) if ld else math.nan, d)
    n_new, mx_new, sp_new, ld_new, d_new = cells[False]
    n_old, mx_old, sp_old, ld_old, _ = cells[True]
    kinds = (sum(1 for r in d_new if r.get("kind") == 1),
             sum(1 for r in d_new if r.get("kind") == 2))
    det = np.median([r["detune"] for r in d_new]) if d_new else math.nan

    def fm(v):
        return "unstable" if v == math.inf else f"{v:.2f}"
    row += [str(n_new), str(n_old), fm(mx_new), fm(mx_old), f"{sp_new:.2f}", f"{ld_new:.2f}",
            f"{sp_old:.2f}", f"{ld_old:.2f}", f"{kinds[0]}/{kinds[1]}", f"{det:.2g}"]
    return "| " + " | ".join(row) + " |"


def ev_experiment_rows(res):
    """Completed runs and the largest Ms per experiment (new)."""
    rows = []
    for exp in EXPERIMENTS:
        rr = [r for x in res for r in x["runs"] if not r["old"] and r["exp"] == exp]
        d = [r for r in rr if r["status"] == 0]
        mx = max((r["Ms"] if r["stable"] else math.inf) for r in d) if d else math.nan
        over = [f"{x['p'].name} {r['noise'] * 100:g}% s{r['seed']} ({r['Ms']:.2f})"
                for x in res for r in x["runs"]
                if not r["old"] and r["exp"] == exp and r["status"] == 0 and r["Ms"] > 2.2]
        rows.append(f"| {exp} | {len(d)} of {len(rr)} | {mx:.2f} | {', '.join(over) or '-'} |")
    return "\n".join(rows)


def ev_leadlag_rows(res):
    """The lead-lag plant's Ms per run, new and old."""
    ll = [x for x in res if x["p"].fam == "E8"][0]
    pairs = {}
    for r in ll["runs"]:
        pairs.setdefault((r["exp"], r["noise"], r["seed"]), {})[r["old"]] = r

    def c(r):
        if r is None:
            return "-"
        if r["status"] != 0:
            return EV_STATUS.get(r["status"], str(r["status"]))
        return f"{r['Ms']:.2f}" if r["stable"] else "unstable"
    return "\n".join(f"| {key[0]} | {key[1] * 100:g} % | {key[2]} | {c(d.get(False))} | "
                     f"{c(d.get(True))} |" for key, d in pairs.items())


def ev_pid_rows(res):
    """The PID runs per plant against the reference SIMC PID."""
    rows = []
    for x in res:
        ref = x["ref_pid"]
        d = [r for r in x["pid_runs"] if r["status"] == 0]
        mx = max((r["Ms"] if r["stable"] else math.inf) for r in d) if d else math.nan
        sp = [r["sp"] / ref["sp"] for r in d if ref and r["stable"]]
        ld = [r["ld"] / ref["ld"] for r in d if ref and r["stable"]]
        det = np.median([r["detune"] for r in d]) if d else math.nan
        rows.append(f"| {x['p'].name} | {ref['Ms']:.2f} | {len(d)} | "
                    f"{'unstable' if mx == math.inf else f'{mx:.2f}'} | "
                    f"{np.median(sp) if sp else math.nan:.2f} | "
                    f"{np.median(ld) if ld else math.nan:.2f} | {det:.2g} |" if ref else
                    f"| {x['p'].name} | - | {len(d)} | {mx:.2f} | - | - | {det:.2g} |")
    return "\n".join(rows)


def ev_mc_rows(mc):
    """The parameters' spread over the noise seeds against the reported std."""
    rows = []
    for m in mc:
        names = ["K", "tau", "Td"] if m["order"] == 0 else ["k", "a", "b", "Td"]
        if len(m["vals"]) == 0:
            continue
        for i, nm in enumerate(names):
            sp = float(np.std(m["vals"][:, i], ddof=1))
            rep = float(np.median(m["stds"][:, i]))
            rows.append(f"| {m['name']} | {'FOPDT' if m['order'] == 0 else 'SOPDT'} | {nm} | "
                        f"{np.mean(m['vals'][:, i]):.4g} | {sp:.3g} | {rep:.3g} | "
                        f"{rep / sp if sp > 0 else math.nan:.2f} |")
    return "\n".join(rows)


def ev_relay_rows(relay):
    """The relay's length and its Ku, Pu errors per variant."""
    rows = []
    for sc in RELAY_VARIANTS:
        all_rows = [r for x in relay for r in x["rows"] if (r["skip"], r["cyc"], r["settle"]) == sc]
        ok = [r for r in all_rows if r["ok"]]
        if not ok:
            continue
        t = np.array([r["t"] for r in ok])
        eK = np.abs([r["eK"] for r in ok])
        eP = np.abs([r["eP"] for r in ok])
        rows.append(f"| {sc[0]} + {sc[1]}, {sc[2]:g} | {len(ok)} of {len(all_rows)} | "
                    f"{np.median(t):.2f} | {t.max():.2f} | {np.median(eK) * 100:.1f} % | "
                    f"{eK.max() * 100:.1f} % | {np.median(eP) * 100:.1f} % | "
                    f"{eP.max() * 100:.1f} % |")
    return "\n".join(rows)


def ev_report(res, relay, mc):
    """The evidence section: the template autotune_evidence.md.in filled
    with the batch's counts and tables."""
    new, new_ref = ev_counts([r for x in res for r in x["runs"] if not r["old"]])
    old, old_ref = ev_counts([r for x in res for r in x["runs"] if r["old"]])
    pid, pid_ref = ev_counts([r for x in res for r in x["pid_runs"]])
    fails = [(x["p"].name, r) for x in res for r in x["runs"] if not r["old"] and r["status"] != 0]
    values = {
        "n_plants": str(len(res)), "n_experiments": str(len(EXPERIMENTS)),
        "experiments": ", ".join(EXPERIMENTS), "summary_new": new + ".", "refusals_new": new_ref,
        "summary_old": old + ".", "refusals_old": old_ref,
        "refused_runs": "; ".join(f"{nm} {r['exp']} {r['noise'] * 100:g} % seed {r['seed']}: "
                                  f"{EV_STATUS.get(r['status'], str(r['status']))}"
                                  for nm, r in fails) or "none",
        "plant_rows": "\n".join(ev_plant_row(x) for x in res),
        "experiment_rows": ev_experiment_rows(res), "leadlag_rows": ev_leadlag_rows(res),
        "pid_summary": pid.replace(" runs (", " (", 1), "pid_refusals": pid_ref,
        "pid_rows": ev_pid_rows(res), "mc_seeds": str(MC_SEEDS), "mc_rows": ev_mc_rows(mc),
        "relay_rows": ev_relay_rows(relay)}
    return string.Template(EV_TEMPLATE.read_text()).substitute(values)


def evidence(jobs):
    plants = list(enumerate(evidence_plants()))
    mc_cases = [("E1 lag-dominant FOPDT", plants[0][1], 0),
                ("E2 lag-dominant SOPDT", plants[1][1], -1),
                ("E13 underdamped", plants[12][1], -1)]
    if jobs > 1:
        with mp.Pool(jobs) as pool:
            res = pool.map(ev_one, plants, chunksize=1)
            relay = pool.map(relay_study, plants, chunksize=1)
            mc = pool.map(mc_one, mc_cases, chunksize=1)
    else:
        res = [ev_one(x) for x in plants]
        relay = [relay_study(x) for x in plants]
        mc = [mc_one(x) for x in mc_cases]
    return ev_report(res, relay, mc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=pathlib.Path, default=OUT)
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--evidence-only", action="store_true",
                    help="only the evidence batch (for a quick look; not the document)")
    args = ap.parse_args()
    import time
    t0 = time.time()
    build()
    ev_text = evidence(args.jobs)
    if args.evidence_only:
        args.out.write_text(ev_text + "\n")
        print(f"wrote {args.out} in {time.time() - t0:.0f} s")
        return
    plants = list(enumerate(batch()))
    if args.jobs > 1:
        with mp.Pool(args.jobs) as pool:
            res = pool.map(run_one, plants, chunksize=1)
    else:
        res = [run_one(x) for x in plants]
    if not args.no_plots:
        IMG.mkdir(parents=True, exist_ok=True)
        plots(res)
    wall = time.time() - t0
    text = report(res, ev_text)
    args.out.write_text(text)
    print(f"wrote {args.out} in {wall:.0f} s")


if __name__ == "__main__":
    main()
