"""The validation reference (tools/pdtref/validate.py) against textbook facts."""

import numpy as np
import pytest
from scipy import stats


from pdtref import discrete as D
from pdtref import models as M
from pdtref import tune as T
from pdtref import validate as V
from pdtsupport.rng import SplitMix64


def record(m, noise, seed, n=400, Ts=0.5):
    rng = SplitMix64.keyed(seed)
    u = np.zeros(n)
    level = 1.0
    for k in range(10, n):
        if (k - 10) % 8 == 0 and rng.uniform() < 0.5:
            level = -level
        u[k] = level
    y = 5.0 + D.simulate(D.zoh(m, Ts), u) + noise * rng.normal(n)
    return 10.0 + u, y


@pytest.mark.parametrize("nu", [12, 20])
def test_chi2_quantile(nu):
    assert V.chi2_99(nu) == pytest.approx(stats.chi2.ppf(0.99, nu), rel=0.01)


def test_true_model_statistics():
    m = M.Fopdt(2.0, 5.0, 1.5)
    u, y = record(m, 0.05, 1)
    r = V.validate(m, u, y, 0.5, 5.0)
    assert r["sigma"] == pytest.approx(0.05, rel=0.1)
    assert r["white_stat"] < V.chi2_99(V.LAGS)
    assert r["cross_stat"] < V.chi2_99(V.FIR)
    assert r["cov"].shape == (4, 4) and np.all(r["std"] > 0)


def test_std_is_the_least_squares_covariance():
    """For the gain and offset alone (shape fixed) the model is linear in
    them: the reported std must be the OLS std of that regression."""
    m = M.Fopdt(2.0, 5.0, 1.5)
    u, y = record(m, 0.05, 2)
    r = V.validate(m, u, y, 0.5, 5.0)
    # Over many seeds the spread of the OLS gain matches the std.
    ks = []
    for seed in range(200):
        uu, yy = record(m, 0.05, 100 + seed)
        x = D.simulate(D.zoh(m, 0.5), uu - uu[0]) / m.K
        A = np.column_stack([x, np.ones_like(x)])
        ks.append(np.linalg.lstsq(A, yy, rcond=None)[0][0])
    # The full covariance includes the shape parameters, so it is at least
    # the gain-only spread.
    assert r["std"][0] >= 0.9 * np.std(ks)


def test_margin_without_uncertainty_is_the_nominal_ms():
    m = M.Fopdt(2.0, 5.0, 1.5)
    u, y = record(m, 0.05, 3)
    r = V.validate(m, u, y, 0.5, 5.0)
    r["cov"] = np.zeros_like(r["cov"])
    st, tr = T.compute(m, T.SIMC, T.PI)
    g = [tr["ideal"][k] for k in ("Kc", "tauI", "tauD", "Tf")]
    assert V.margin(r, g, independent=True) == pytest.approx(tr["fig"]["Ms"], rel=0.02)
