"""Fixtures of the binding's tests: the `pdtfit` program they compare with
(pdtsupport.cli, from pip install -e tools) and the test records."""
import numpy as np
import pytest

from pdtsupport import cli
from pdtsupport.rng import Lcg64


def pytest_configure(config):
    config.addinivalue_line("markers", "cli: runs the pdtfit program (skipped without one, "
                            "failed when CI=true or PDTFIT_REQUIRE_BIN=1)")


def pytest_runtest_setup(item):
    cli.setup_cli_test(item)


def multistep(n, u0, amp, seed, rest=20):
    """Steps of random length and level around u0, after `rest` samples at u0."""
    rng = Lcg64(seed)
    u = np.full(n, float(u0))
    k, sign = rest, 1.0
    while k < n:
        hold = 20 + int(rng.uniform() * 40)
        u[k:k + hold] = u0 + sign * amp * (0.4 + 0.6 * rng.uniform())
        sign = -sign
        k += hold
    return u


def sopdt_response(u, u0, y0, K, T1, T2, delay, noise, seed):
    """Two first-order lags in series (exact ZOH per lag, Ts = 1 per sample
    of T1, T2 in samples) and a whole-sample delay, plus noise."""
    a1, a2 = np.exp(-1.0 / T1), (np.exp(-1.0 / T2) if T2 else 0.0)
    x1 = x2 = 0.0
    y = np.empty(len(u))
    rng = Lcg64(seed + 1)
    for k in range(len(u)):
        y[k] = y0 + x2 + noise * rng.gauss()
        uk = u[k - delay] - u0 if k >= delay else 0.0
        x1 = a1 * x1 + K * (1.0 - a1) * uk
        x2 = a2 * x2 + (1.0 - a2) * x1
    return y


@pytest.fixture(scope="session")
def records():
    """{name: (u, y, fs)}: a FOPDT-like and a SOPDT-like process with noise."""
    out = {}
    u = multistep(500, 40.0, 5.0, seed=3)
    out["fopdt"] = (u, sopdt_response(u, 40.0, 300.0, 1.8, 30.0, 0.0, 12, 0.05, 3), 10.0)
    u = multistep(700, 10.0, 2.0, seed=5)
    out["sopdt"] = (u, sopdt_response(u, 10.0, 3.0, -0.7, 25.0, 9.0, 7, 0.01, 5), 2.0)
    return out


@pytest.fixture
def write_csv(tmp_path):
    """Writes columns (name -> values) with repr(), which round-trips doubles,
    so the program reads exactly the numbers the binding gets."""
    def write(name, cols):
        path = tmp_path / name
        names = list(cols)
        rows = [",".join(names)]
        rows += [",".join(repr(float(v)) for v in row) for row in zip(*cols.values())]
        path.write_text("\n".join(rows) + "\n")
        return path
    return write
