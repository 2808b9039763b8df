"""Least-squares delay scans, ELMS and E-IV-LMS (paper Part One).

Written from the prediction models (3) and (5), not from the C code: here
every delay gets the plain design matrix in engineering units,

    FOPDT: [y(k-1), u(k-l-1), 1]
    SOPDT: [y(k-1), y(k-2), u(k-l-1), u(k-l-2), 1]

solved by numpy's SVD least squares (ELMS) or by a square instrumental-
variable solve (E-IV-LMS, instruments with x^, the ELMS model simulated from
rest, in place of y). The C code uses a delta form, centring and Gaussian
elimination instead; the two agree only if both are right.

Conventions (shared with pdt_ls.h): samples k = 0 .. n-1; u0 = u[0]; the
input is at rest (u0) before sample 0; the score of a delay is the mean of
the squared one-step residual over k = k0 .. n-1 with k0 = l_u + order (or
order with whole_record); Td = l Ts.
"""
import numpy as np

INF = float("inf")


def _u_lagged(u, lag, k):
    """u(k - lag) for the sample indexes k, u[0] before sample 0."""
    idx = k - lag
    return np.where(idx >= 0, u[np.maximum(idx, 0)], u[0])


def _design(u, y, l, order, k):
    cols = [y[k - 1]]
    if order == 2:
        cols.append(y[k - 2])
    cols.append(_u_lagged(u, l + 1, k))
    if order == 2:
        cols.append(_u_lagged(u, l + 2, k))
    cols.append(np.ones(len(k)))
    return np.column_stack(cols)


def _unpack(theta, order):
    """theta of the design above -> (a, b, c): A = [1, a1(, a2)] so that
    y(k) + a1 y(k-1) + a2 y(k-2) = b1 u(k-l-1) + b2 u(k-l-2) + c."""
    if order == 1:
        return np.array([1.0, -theta[0]]), np.array([theta[1]]), theta[2]
    return np.array([1.0, -theta[0], -theta[1]]), np.array(theta[2:4]), theta[4]


def simulate_aux(a, b, u, l):
    """The discrete model A(q) x = B(q) q^(l+1) (u - u0) from rest."""
    ud = np.asarray(u, dtype=float) - u[0]
    n = len(ud)
    x = np.zeros(n)
    for k in range(n):
        acc = 0.0
        for i in range(1, len(a)):
            if k - i >= 0:
                acc -= a[i] * x[k - i]
        for j in range(len(b)):
            idx = k - l - 1 - j
            if idx >= 0:
                acc += b[j] * ud[idx]
        x[k] = acc
    return x


def to_continuous(a, b, Ts):
    """Continuous model of the discrete estimate, or None without one.

    FOPDT: dict K, tau. SOPDT: dict k, a, b of form (2) from the poles
    ln(z) / Ts, with the DC gain sum(b) / A(1)."""
    poles = np.roots(a)
    if len(a) == 2:
        alpha = -a[1]
        if not 0.0 < alpha < 1.0:
            return None
        return dict(K=b[0] / (1.0 - alpha), tau=-Ts / np.log(alpha))
    if np.all(np.abs(poles.imag) == 0.0):
        z = poles.real
        if not np.all((z > 0.0) & (z < 1.0)):
            return None
        s = np.log(z) / Ts
    else:
        if not np.abs(poles[0]) < 1.0:
            return None
        s = np.log(poles.astype(complex)) / Ts
    den_a = float(-(s[0] + s[1]).real)
    den_b = float((s[0] * s[1]).real)
    dc = float(np.sum(b) / np.sum(a))
    return dict(k=dc * den_b, a=den_a, b=den_b)


def fit_delay(u, y, l, order, method, k0):
    """Estimate at delay l: dict(a, b, c, cost) or None when the solve has
    no unique solution or (IV) the auxiliary model is unstable."""
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    k = np.arange(k0, len(y))
    phi = _design(u, y, l, order, k)
    target = y[k]
    theta, _, rank, _ = np.linalg.lstsq(phi, target, rcond=None)
    if rank < phi.shape[1]:
        return None
    if method == "eiv":
        a, b, _ = _unpack(theta, order)
        if np.max(np.abs(np.roots(a))) >= 1.0:
            return "unstable"
        x = simulate_aux(a, b, u, l)
        z = phi.copy()
        z[:, 0] = x[k - 1]
        if order == 2:
            z[:, 1] = x[k - 2]
        theta = np.linalg.solve(z.T @ phi, z.T @ target)
    r = target - phi @ theta
    a, b, c = _unpack(theta, order)
    return dict(a=a, b=b, c=c, cost=float(np.mean(r * r)))


def scan(u, y, Ts, order, method, delay_min, delay_max, whole_record=False):
    """The whole scan: costs per delay (inf when skipped) and the best fit
    (dict with delay, cost, model, y0, u0, a, b) or None."""
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    k0 = order if whole_record else delay_max + order
    costs = []
    best = None
    for l in range(delay_min, delay_max + 1):
        f = fit_delay(u, y, l, order, method, k0)
        model = None
        if isinstance(f, dict):
            model = to_continuous(f["a"], f["b"], Ts)
        if model is None:
            costs.append(INF)
            continue
        costs.append(f["cost"])
        if best is None or f["cost"] < best["cost"]:
            # Steady state at u = u0: A(1) y0 = B(1) u0 + c.
            y0 = (np.sum(f["b"]) * u[0] + f["c"]) / np.sum(f["a"])
            best = dict(delay=l, cost=f["cost"], model=model, y0=float(y0), u0=float(u[0]),
                        a=f["a"], b=f["b"], Td=l * Ts)
    return np.array(costs), best
