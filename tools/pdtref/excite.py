"""Reference of the excitation generators and the experiment recorder
(lib/src/pdt_excite.c, lib/src/pdt_record.c), from their definitions in
docs/experiments.md.

The C generators run one sample per call with a state machine; here each
open-loop signal is a whole-sequence formula of the sample index (the chirp
from its phase in seconds, the PRBS from the linear recurrence of its
m-sequence held by np.repeat), the relay's Ku and Pu are found after the
fact from the switching sequence, and the recorder decimates with a reshape.
numpy only.
"""
import math

import numpy as np

from pdtsupport.status import STATUS

# pdt_status_t values, read from the C header
RUNNING, OK = STATUS["RUNNING"], STATUS["OK"]
ERR_NONFINITE, ERR_PV_LIMIT, ERR_OUTPUT_LIMIT, ERR_TIMEOUT, ERR_SETPOINT = (
    STATUS[name] for name in ("NONFINITE", "PV_LIMIT", "OUTPUT_LIMIT", "TIMEOUT", "SETPOINT"))

STEP, PULSE, CHIRP, PRBS, RELAY = 1, 2, 3, 4, 5
REVERSE, DIRECT = 0, 1
MOVE_ANY, MOVE_UP, MOVE_DOWN = 0, 1, 2

# Exponents t of x^t in the primitive feedback polynomial x^n + ... + 1 of
# each register length n (the constant term left out): a(k) = XOR_t a(k - t).
PRBS_TAPS = {
    2: (2, 1), 3: (3, 2), 4: (4, 3), 5: (5, 3), 6: (6, 5), 7: (7, 6), 8: (8, 6, 5, 4),
    9: (9, 5), 10: (10, 7), 11: (11, 9), 12: (12, 6, 4, 1), 13: (13, 4, 3, 1),
    14: (14, 5, 3, 1), 15: (15, 14), 16: (16, 15, 13, 4), 17: (17, 14), 18: (18, 11),
    19: (19, 6, 2, 1), 20: (20, 17), 21: (21, 19), 22: (22, 21), 23: (23, 18),
    24: (24, 23, 22, 17), 25: (25, 22), 26: (26, 6, 2, 1), 27: (27, 5, 2, 1), 28: (28, 25),
    29: (29, 27), 30: (30, 6, 4, 1), 31: (31, 28),
}

DEFAULTS = dict(kind=STEP, Ts=0.0, u0=0.0, u_min=-math.inf, u_max=math.inf, clamp=False,
                pre=0.0, amplitude=1.0, duration=0.0, t_on=1.0, t_off=1.0, count=1,
                f0=0.0, f1=0.0, prbs_bits=7, prbs_hold=1, prbs_seed=1, periods=1,
                setpoint=0.0, d=1.0, bias=0.0, eps=0.0, action=REVERSE, relay_skip=1,
                relay_cycles=3)


def config(**kw):
    c = dict(DEFAULTS)
    for key in kw:
        if key not in c:
            raise KeyError(key)
    c.update(kw)
    return c


def samples(t, Ts):
    """Whole samples nearest to t seconds (halves round up)."""
    return int(math.floor(t / Ts + 0.5))


def poly_mask(n):
    """The feedback polynomial as an integer, bit t for x^t."""
    p = 1
    for t in PRBS_TAPS[n]:
        p |= 1 << t
    return p


def msequence(n, seed, count):
    """`count` chips a(0), a(1), ... of the m-sequence: a(i) = bit i of the
    seed for i < n, then a(k) = XOR over the taps t of a(k - t)."""
    a = [(seed >> i) & 1 for i in range(n)]
    taps = PRBS_TAPS[n]
    while len(a) < count:
        k = len(a)
        bit = 0
        for t in taps:
            bit ^= a[k - t]
        a.append(bit)
    return np.array(a[:count], dtype=int)


def levels(c):
    """(high, low) wanted levels before clamping."""
    if c["kind"] in (STEP, PULSE):
        return c["u0"] + c["amplitude"], c["u0"]
    if c["kind"] in (CHIRP, PRBS):
        return c["u0"] + c["amplitude"], c["u0"] - c["amplitude"]
    return c["u0"] + c["bias"] + c["d"], c["u0"] + c["bias"] - c["d"]


def length(c):
    """Whole length in samples, pre included; 0 for no fixed length."""
    Ts = c["Ts"]
    pre = samples(c["pre"], Ts)
    k = c["kind"]
    if k == STEP:
        body = samples(c["duration"], Ts)
        if c["duration"] > 0 and body == 0:
            body = 1
    elif k == PULSE:
        body = c["count"] * (samples(c["t_on"], Ts) + samples(c["t_off"], Ts))
    elif k == CHIRP:
        body = samples(c["duration"], Ts)
    elif k == PRBS:
        body = c["periods"] * (2 ** c["prbs_bits"] - 1) * c["prbs_hold"]
    else:
        body = 0
    return 0 if body == 0 else pre + body


def open_loop(c, n):
    """Outputs of the first n calls of an open-loop generator and the status
    each call returns (RUNNING, then OK with u0 once the length has passed)."""
    Ts, u0 = c["Ts"], c["u0"]
    k = np.arange(n)
    pre = samples(c["pre"], Ts)
    j = k - pre  # the excitation's own sample index
    on = j >= 0
    kind = c["kind"]
    if kind == STEP:
        x = np.where(on, c["amplitude"], 0.0)
    elif kind == PULSE:
        n_on, n_off = samples(c["t_on"], Ts), samples(c["t_off"], Ts)
        x = np.where(on & (np.mod(j, n_on + n_off) < n_on), c["amplitude"], 0.0)
    elif kind == CHIRP:
        N = samples(c["duration"], Ts)
        T = N * Ts
        t = j * Ts
        phase = 2.0 * math.pi * (c["f0"] * t + (c["f1"] - c["f0"]) * t * t / (2.0 * T))
        x = np.where(on, c["amplitude"] * np.sin(phase), 0.0)
    elif kind == PRBS:
        hold = c["prbs_hold"]
        nb = c["prbs_bits"]
        chips_needed = max(0, (n - pre) // hold + 1)
        chips = msequence(nb, c["prbs_seed"] & ((1 << nb) - 1), max(chips_needed, nb))
        held = np.repeat(chips, hold)
        x = np.zeros(n)
        m = max(0, n - pre)
        x[pre:] = np.where(held[:m] == 1, c["amplitude"], -c["amplitude"])
    else:
        raise ValueError("not an open-loop kind")
    u = np.clip(u0 + x, c["u_min"], c["u_max"])
    status = np.full(n, RUNNING)
    L = length(c)
    if L:
        u[L:] = u0
        status[L:] = OK
    return u, status


def relay(c, pv):
    """The relay on a process-value sequence: (u, status, result) where
    result is a dict (Ku, Pu, a, d, cycles) or None before a measured cycle.
    The switching runs as a loop (it depends on its own past); the cycles
    are measured afterwards from the switching sequence."""
    pv = np.asarray(pv, dtype=float)
    n = len(pv)
    pre = samples(c["pre"], c["Ts"])
    sign = 1.0 if c["action"] == REVERSE else -1.0
    e = sign * (c["setpoint"] - pv)
    high = np.zeros(n, dtype=bool)
    state = None
    for k in range(pre, n):
        if state is None:
            state = e[k] >= 0
        elif state and e[k] < -c["eps"]:
            state = False
        elif not state and e[k] > c["eps"]:
            state = True
        high[k] = state
    rises = [k for k in range(pre + 1, n) if high[k] and not high[k - 1]]
    # cycle i runs from rises[i] to rises[i+1]
    skip, want = c["relay_skip"], c["relay_cycles"]
    end = None
    if len(rises) > skip + want:
        end = rises[skip + want]  # the call that completes the last cycle
    hi_w, lo_w = levels(c)
    hi = min(max(hi_w, c["u_min"]), c["u_max"])
    lo = min(max(lo_w, c["u_min"]), c["u_max"])
    u = np.where(high, hi, lo)
    u[:pre] = c["u0"]
    status = np.full(n, RUNNING)
    if end is not None:
        u[end:] = c["u0"]
        status[end:] = OK
    periods, amps = [], []
    last = len(rises) - 1 if end is None else skip + want
    for i in range(skip, last):
        r0, r1 = rises[i], rises[i + 1]
        periods.append(r1 - r0)
        amps.append(0.5 * (np.max(pv[r0:r1]) - np.min(pv[r0:r1])))
    periods, amps = periods[-want:], amps[-want:]
    result = None
    if periods:
        a = float(np.mean(amps))
        d = 0.5 * (hi - lo)
        result = dict(Ku=4.0 * d / (math.pi * a), Pu=float(np.mean(periods)) * c["Ts"], a=a, d=d,
                      cycles=len(periods))
    return u, status, result


def relay_fopdt_exact(K, tau, L, d):
    """The relay limit cycle of K e^{-L s} / (tau s + 1) under an ideal
    symmetric relay +/- d (no hysteresis), in closed form: the output moves
    exponentially toward +/- K d, and each switch shows L seconds later, so
    the half period is tau ln(2 e^{L/tau} - 1) and the amplitude
    K d (1 - e^{-L/tau}). Returns (Ku = 4 d / (pi a), Pu, a)."""
    a = K * d * (1.0 - math.exp(-L / tau))
    Pu = 2.0 * tau * math.log(2.0 * math.exp(L / tau) - 1.0)
    return 4.0 * d / (math.pi * a), Pu, a


def fopdt_ultimate(K, tau, L):
    """Ultimate gain and period of a FOPDT: the frequency where its phase is
    -pi (w L + atan(w tau) = pi, by bisection) and 1 / |G| there. This is
    what the describing-function analysis of an ideal relay predicts."""
    lo, hi = 1e-9, math.pi / L
    for _ in range(200):
        w = 0.5 * (lo + hi)
        if w * L + math.atan(w * tau) < math.pi:
            lo = w
        else:
            hi = w
    w = 0.5 * (lo + hi)
    return math.sqrt(1.0 + (w * tau) ** 2) / abs(K), 2.0 * math.pi / w


REC_DEFAULTS = dict(decimation=1, settle=10, settle_band=0.0, u_min=-math.inf, u_max=math.inf,
                    pv_min=-math.inf, pv_max=math.inf, max_scans=0, move=MOVE_ANY,
                    setpoint=0.0)


def rec_config(**kw):
    c = dict(REC_DEFAULTS)
    for key in kw:
        if key not in c:
            raise KeyError(key)
    c.update(kw)
    return c


def record(c, capacity, u_scan, pv_scan):
    """The recorder fed the scans (u_scan[i], pv_scan[i]) in turn.

    Returns a dict: u, y (the stored samples), n, status, settled, u0, y0,
    u_safe, scans (accepted) and last (index of the push that first
    returned something other than RUNNING, or None)."""
    u_scan = np.asarray(u_scan, dtype=float)
    pv_scan = np.asarray(pv_scan, dtype=float)
    m = len(u_scan)
    D = c["decimation"]
    # first scan that breaks a rule, and which
    bad = np.full(m, 0)
    idx = np.arange(m)
    if c["max_scans"]:
        bad[(bad == 0) & (idx >= c["max_scans"])] = ERR_TIMEOUT
    fin = np.isfinite(u_scan) & np.isfinite(pv_scan)
    bad[(bad == 0) & ~fin] = ERR_NONFINITE
    bad[(bad == 0) & ((u_scan < c["u_min"]) | (u_scan > c["u_max"]))] = ERR_OUTPUT_LIMIT
    bad[(bad == 0) & ((pv_scan < c["pv_min"]) | (pv_scan > c["pv_max"]))] = ERR_PV_LIMIT
    hits = np.nonzero(bad)[0]
    abort = int(hits[0]) if len(hits) else None
    good = m if abort is None else abort
    ns = good // D  # complete samples before the abort
    us = u_scan[:ns * D].reshape(ns, D).mean(axis=1) if ns else np.zeros(0)
    ys = pv_scan[:ns * D].reshape(ns, D).mean(axis=1) if ns else np.zeros(0)

    # settle window start s and the sample j that completes it
    s, settle_at = 0, None
    for j in range(ns):
        if c["settle_band"] > 0 and j > s and np.ptp(ys[s:j + 1]) > c["settle_band"]:
            s = j
        if j - s + 1 == c["settle"]:
            settle_at = j
            break
    out = dict(status=RUNNING, settled=settle_at is not None, last=None)
    end_sample = ns  # samples past this one are not stored
    if settle_at is not None:
        y0 = float(np.mean(ys[s:settle_at + 1]))
        u0 = float(np.mean(us[s:settle_at + 1]))
        wrong = ((c["move"] == MOVE_UP and not c["setpoint"] > y0)
                 or (c["move"] == MOVE_DOWN and not c["setpoint"] < y0))
        if wrong:
            out["status"] = ERR_SETPOINT
            end_sample = settle_at + 1
            out["last"] = (settle_at + 1) * D - 1
    else:
        hi = ns
        u0 = float(np.mean(us[s:hi])) if hi > s else None
        y0 = float(np.mean(ys[s:hi])) if hi > s else 0.0
    n = min(end_sample - s, capacity)
    if out["status"] == RUNNING and end_sample - s >= capacity:
        out["status"] = OK
        out["last"] = (s + capacity) * D - 1
    if out["status"] == RUNNING and abort is not None:
        out["status"] = int(bad[abort])
        out["last"] = abort
    if out["last"] is not None and out["status"] in (OK, ERR_SETPOINT):
        scans = out["last"] + 1
    else:
        scans = good
    if u0 is None:
        if scans > 0:
            u_safe = float(u_scan[0])
        else:
            x = u_scan[0]
            u_safe = c["u_min"] if x != x else min(max(x, c["u_min"]), c["u_max"])
        u0_out = u_safe
    else:
        u_safe = u0_out = u0
    out.update(u=us[s:s + n], y=ys[s:s + n], n=n, u0=u0_out, y0=y0, u_safe=u_safe, scans=scans)
    return out
