"""The loop-performance monitor's statistics over a whole record
(docs/monitor.md), written from their definitions with weighted sums over
arrays: the exponential forgetting is a weight lambda^(N-1-k) on sample k.
The AR model solves the Yule-Walker equations directly (not by
Levinson-Durbin), the impulse response and the autocorrelation's
continuation follow from the AR polynomial.

monitor(sp, pv, u, Ts, model=None, horizon=0, u_lim=None) -> dict of the
figures pdt_monitor_result gives (decimation 1)."""
import math

import numpy as np

from . import discrete, pid, tune

ORDER = 24
COARSE = 8            # samples per coarse sample of the error
ACF_LAGS = 16 * ORDER
BAND = 0.7            # hysteresis of the zero crossings, a fraction of std(e)
ALPHA, GAMMA = 0.5, 0.75


def _weights(n, horizon):
    lam = math.exp(-1.0 / horizon) if horizon else 1.0
    return lam ** np.arange(n - 1, -1, -1), lam


def _autocov(e, w):
    """c(j) = sum_{k>=j} w_k e_k e_{k-j} / sum w - mean^2, j = 0..ORDER."""
    W = w.sum()
    m = (w @ e) / W
    c = np.array([(w[j:] * e[j:]) @ e[:len(e) - j] / W for j in range(ORDER + 1)])
    return c - m * m, m


def ar_model(c):
    """AR coefficients a[1..p] of the Yule-Walker equations and the
    innovation variance."""
    R = np.array([[c[abs(i - j)] for j in range(ORDER)] for i in range(ORDER)])
    a = np.linalg.solve(R, c[1:ORDER + 1])
    return a, float(c[0] - a @ c[1:ORDER + 1])


def harris(c, d):
    """Minimum variance over the dead time d (samples) over the variance."""
    a, err = ar_model(c)
    psi = np.zeros(d)
    for i in range(d):
        psi[i] = (1.0 if i == 0 else 0.0) + sum(a[j - 1] * psi[i - j]
                                               for j in range(1, min(i, ORDER) + 1))
    return min(1.0, err * float(psi @ psi) / c[0])


def acf_figures(c):
    """(first minimum, the maximum after it, period in samples or 0) of the
    autocovariances c[0..ORDER], continued by their AR model."""
    a, _ = ar_model(c)
    rho = list(c / c[0])
    while len(rho) < ACF_LAGS:
        rho.append(float(np.dot(a, rho[-1:-ORDER - 1:-1])))
    rho = np.array(rho)
    sign = rho > 0
    cross = [j - 1 + rho[j - 1] / (rho[j - 1] - rho[j]) for j in range(1, ACF_LAGS)
             if sign[j] != sign[j - 1]][:3]
    idx = [j for j in range(1, ACF_LAGS) if sign[j] != sign[j - 1]][:3]
    lo = rho[idx[0]:idx[1]].min() if len(idx) >= 2 else (rho[idx[0]:].min() if idx else 0.0)
    hi = rho[idx[1]:idx[2]].max() if len(idx) >= 3 else (rho[idx[1]:].max() if len(idx) == 2
                                                        else 0.0)
    return min(lo, 0.0), max(hi, 0.0), (cross[2] - cross[0]) if len(cross) == 3 else 0.0


def half_periods(e, w_all, sp):
    """The zero-crossing statistics (Forsman and Stattin), band moving with
    the running mean and std of e: (regularity, weighted half-periods,
    mean length of two half-periods, mean amplitude)."""
    n = len(e)
    lam = w_all[-2] if n > 1 else 1.0
    W = se = see = 0.0
    sign, seen, iae, length = 0, 0, 0.0, 0
    prev = []                      # (iae, length), newest last
    n_reg = n_hp = s_len = s_amp = moves = 0.0
    for k in range(n):
        W, se, see = lam * W + 1, lam * se + e[k], lam * see + e[k] ** 2
        mean = se / W
        var = see / W - mean * mean
        band = BAND * math.sqrt(var) if var > 0 else 0.0
        ec = e[k] - mean
        moves = lam * moves + (k > 0 and abs(sp[k] - sp[k - 1]) > 0.5 * math.sqrt(max(var, 0.0)))
        n_reg, n_hp, s_len, s_amp = lam * n_reg, lam * n_hp, lam * s_len, lam * s_amp
        if sign == 0:
            sign = 1 if ec > band else (-1 if ec < -band else 0)
            continue
        if ((sign > 0 and ec < -band) or (sign < 0 and ec > band)) and length > 0:
            if seen >= 1:
                n_hp += 1
                s_len += 2 * length
                s_amp += math.pi * iae / (2 * length)
            if seen >= 3:
                ra, rl = iae / prev[-2][0], length / prev[-2][1]
                n_reg += (ALPHA < ra < 1 / ALPHA) and (GAMMA < rl < 1 / GAMMA)
            prev.append((iae, length))
            seen, iae, length, sign = min(seen + 1, 4), 0.0, 0, -sign
        iae += abs(ec)
        length += 1
    return (n_reg / n_hp if n_hp else 0.0), n_hp, (s_len / n_hp if n_hp else 0.0), \
        (s_amp / n_hp if n_hp else 0.0), moves


def _wmean(w, x):
    return (w @ x) / w.sum()


def _wcov(w, x, y):
    return _wmean(w, x * y) - _wmean(w, x) * _wmean(w, y)


def _model_parts(m, Ts, sp, pv, u, u_lim):
    """The model's output from u - u0, and the reference loop (SIMC PI on
    the model, tau_c = its dead time) driven by sp and pv - G (u - u_ref):
    (v, e_ref). The reference PI has the output's limits when given."""
    d = discrete.zoh(m, Ts)
    ym = discrete.simulate(d, u - u[0])
    status, res = tune.compute(m, tune.SIMC, tune.PI, ms_max=0.0)
    if status != tune.OK:
        status, res = tune.compute(m, tune.SIMC, tune.PI, knob=Ts, ms_max=0.0)
    g = res["ideal"]
    ctrl = pid.Pid(pid.config(Ts=Ts, Kc=g["Kc"], Ti=g["tauI"], Td=0.0, Tf=0.0, N=0.0,
                              u_min=u_lim[0] if u_lim else -1e30,
                              u_max=u_lim[1] if u_lim else 1e30), 0.0)
    n = len(u)
    du = np.zeros(n + d.delay + 3)   # u_ref - u, after delay + 3 zeros of rest
    yd = np.zeros(n)                 # G (u_ref - u)
    a = list(d.a)[:d.order]
    e_ref = np.zeros(n)
    off = d.delay + 3
    for k in range(n):
        # the difference equation at k, from du[.. k - 1] (discrete.simulate's)
        acc = sum(bi * du[off + k - 1 - d.delay - i] for i, bi in enumerate(d.b))
        acc -= sum(ai * yd[k - 1 - i] for i, ai in enumerate(a) if k - 1 - i >= 0)
        yd[k] = acc
        yref = pv[k] + acc
        if k == 0:
            ctrl.track(sp[k], yref, u[k])
            uref = u[k]
        else:
            uref = ctrl.update(sp[k], yref)
        du[off + k] = uref - u[k]
        e_ref[k] = sp[k] - yref
    return (pv - pv[0]) - ym, e_ref


def mismatch(z, v, w, sp0):
    """(gain ratio, |t|) of v regressed on z, the t test's memory from the
    residual's autocorrelation at lag ORDER; (None, None) when the
    set-point (z + sp0) does not move."""
    vz, vv, cv = _wcov(w, z, z), _wcov(w, v, v), _wcov(w, z, v)
    if not (vz > 1e-6 * (_wmean(w, z) ** 2 + sp0 * sp0) and vz > 0 and vv > 0):
        return None, None
    beta = cv / vz
    r = v - beta * z
    W = w.sum()
    mr = _wmean(w, r)
    cl = (w[ORDER:] * r[ORDER:]) @ r[:-ORDER] / W - mr * mr
    vr = vv - beta * cv
    rl = cl / vr
    rho = min(math.exp(math.log(rl) / ORDER) if 0 < rl < 1 else (1.0 if rl >= 1 else 0.0),
              0.9999)
    neff = W * W / (w @ w) * (1 - rho) / (1 + rho)
    t = abs(beta) / math.sqrt(vr / (neff * vz))
    return (1 / (1 - beta) if beta < 0.9 else 10.0), t


def monitor(sp, pv, u, Ts, model=None, horizon=0, u_lim=None, sat_band=0.005):
    sp, pv, u = (np.asarray(x, dtype=float) for x in (sp, pv, u))
    n = len(sp)
    w, _ = _weights(n, horizon)
    e = sp - pv
    c, _ = _autocov(e, w)
    out = {"std_e": math.sqrt(c[0])}
    lo, hi, per = acf_figures(c)
    scale = 1
    nc = n // COARSE
    if nc > 2 * ORDER:
        # the coarse error: means of COARSE samples, weights lambda^COARSE
        cc, _ = _autocov(e[:nc * COARSE].reshape(nc, COARSE).mean(axis=1),
                         _weights(nc, horizon / COARSE if horizon else 0)[0])
        clo, chi, cper = acf_figures(cc)
        if -clo * chi > -lo * hi:
            lo, hi, per, scale = clo, chi, cper * COARSE, COARSE
    out.update(acf_min=lo, acf_max=hi, period=per * Ts if per else None,
               oscillation=math.sqrt(-lo * hi), acf_scale=scale)
    reg, nhp, slen, samp, moves = half_periods(e, w, sp)
    out["forced"] = bool(per > 0 and moves > 0 and per * moves >= w.sum())
    out.update(regularity=reg, half_periods=nhp, half_period_mean=slen * Ts / 2 if nhp else None,
               amplitude=samp if nhp else None)
    du = u - u[0]
    out["corr_ue"] = _wcov(w, du, e) / math.sqrt(_wcov(w, du, du) * c[0])
    if u_lim is not None:
        tol = sat_band * (u_lim[1] - u_lim[0])
        out["saturation"] = _wmean(w, ((u <= u_lim[0] + tol) | (u >= u_lim[1] - tol)) * 1.0)
    if model is not None:
        l, _ = discrete.split_delay(model.Td, Ts)
        out["delay_samples"] = l + 1
        out["harris"] = harris(c, l + 1)
        v, e_ref = _model_parts(model, Ts, sp, pv, u, u_lim)
        out["iae_ratio"] = (w @ np.abs(e)) / (w @ np.abs(e_ref))
        out["corr_ve"] = _wcov(w, v, e) / math.sqrt(_wcov(w, v, v) * c[0])
        out["gain_ratio"], out["mismatch_t"] = mismatch(sp - sp[0], v, w, sp[0])
    return out
