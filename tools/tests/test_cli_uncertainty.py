"""The uncertainty `pdtfit identify` prints: "std" and "cov" of every
printed parameter under its name, the covariance carried from the model's
own parameters by the delta method (checked here with numpy's own
derivatives), and the bootstrap's "ci95" (docs/uncertainty.md)."""
import json
import math

import numpy as np
import pytest

from pdtsupport.cli import run, write_csv
from pdtsupport.plant import simulate
from pdtsupport.records import TS, U0, Y0, multistep_input, noise

pytestmark = pytest.mark.cli

N = 800


@pytest.fixture(scope="module")
def sopdt_csv(tmp_path_factory):
    u = np.where(np.arange(N) >= 80, U0 + 5.0, U0)
    y = Y0 + simulate([1.5], np.polymul([4.0, 1.0], [1.5, 1.0]), 0.83, u - U0, TS) \
        + noise(N, 0.2, 5)
    return write_csv(tmp_path_factory.mktemp("u") / "s.csv",
                     {"t": np.arange(N) * TS, "u": u, "y": y})


@pytest.fixture(scope="module")
def fopdt_csv(tmp_path_factory):
    u = multistep_input(N, U0, 5.0, 25, 60, 20, seed=7)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.33, u - U0, TS) + noise(N, 0.05, 11)
    return write_csv(tmp_path_factory.mktemp("u") / "f.csv",
                     {"t": np.arange(N) * TS, "u": u, "y": y})


def identify(path, *extra):
    res = run(["identify", *extra, path])
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def printed(k, a, b):
    """K, wn, zeta, tau1, tau2 of k / (s^2 + a s + b), by numpy."""
    r = np.sort(np.roots([1.0, a, b]).real)  # two real poles, the slow one last
    return np.array([k / b, math.sqrt(b), a / (2 * math.sqrt(b)), -1 / r[1], -1 / r[0]])


def test_sopdt_delta_method_against_numpy(sopdt_csv):
    out = identify(sopdt_csv, "--model", "sopdt", "--uncertainty", "fisher")
    assert out["uncertainty"] == "fisher" and "ci95" not in out
    names = ["K", "wn", "zeta", "Td", "y0", "tau1", "tau2", "a", "b"]
    assert list(out["std"]) == names and list(out["cov"]) == names
    # The model's own parameters (k, a, b) from the printed K, a, b and their
    # covariance: k = K b.
    K, a, b = out["K"], out["a"], out["b"]
    P = np.array([[out["cov"][i][j] for j in ("K", "a", "b")] for i in ("K", "a", "b")])
    G = np.array([[b, 0, K], [0, 1, 0], [0, 0, 1]])  # d(k, a, b) / d(K, a, b)
    C = G @ P @ G.T
    x0 = np.array([K * b, a, b])
    J = np.zeros((5, 3))
    for j in range(3):
        h = 1e-4 * abs(x0[j])
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        J[:, j] = (printed(*xp) - printed(*xm)) / (2 * h)
    want = np.sqrt(np.diag(J @ C @ J.T))
    for name, w in zip(["K", "wn", "zeta", "tau1", "tau2"], want):
        assert out["std"][name] == pytest.approx(w, rel=2e-3), name
    for name in names:
        assert out["cov"][name][name] == pytest.approx(out["std"][name] ** 2, rel=1e-5)


def test_sopdt_bootstrap_by_default(sopdt_csv):
    out = identify(sopdt_csv, "--model", "sopdt", "--bootstrap", "20")
    assert out["uncertainty"] == "bootstrap" and out["bootstrap_runs"] == 20
    assert list(out["ci95"]) == list(out["std"])
    for name, (lo, hi) in out["ci95"].items():
        assert lo <= hi and out["std"][name] > 0, name
    # The truth lies in the intervals of this record.
    for name, true in (("K", 1.5), ("Td", 0.83), ("tau1", 4.0)):
        lo, hi = out["ci95"][name]
        assert lo - 2 * out["std"][name] <= true <= hi + 2 * out["std"][name], name
    again = run(["identify", "--model", "sopdt", "--bootstrap", "20", sopdt_csv])
    assert json.loads(again.stdout) == out


def test_fopdt_fisher_by_default_bootstrap_asked(fopdt_csv):
    fisher = identify(fopdt_csv, "--model", "fopdt")
    boot = identify(fopdt_csv, "--model", "fopdt", "--uncertainty", "bootstrap",
                    "--bootstrap", "40")
    assert fisher["uncertainty"] == "fisher" and boot["uncertainty"] == "bootstrap"
    assert fisher["K"] == boot["K"]
    # A well-determined FOPDT: the two agree within the bootstrap's own error.
    for name in ("K", "tau", "Td"):
        assert boot["std"][name] == pytest.approx(fisher["std"][name], rel=0.5), name


def test_uncertainty_usage(fopdt_csv):
    res = run(["identify", "--model", "fopdt", "--uncertainty", "fisher", "--bootstrap", "5",
               fopdt_csv])
    assert res.returncode == 2 and "--bootstrap goes with" in res.stderr
    res = run(["identify", "--model", "fopdt", "--method", "elms", "--uncertainty", "bootstrap",
               fopdt_csv])
    assert res.returncode == 2 and "--method ga only" in res.stderr


def test_report_script_smoke():
    """tools/bench/uncertainty.py on a few seeds of the FOPDT: it runs and
    prints its tables (a trial run writes no file)."""
    import subprocess
    import sys

    from pdtsupport.cli import ROOT, find_binary
    res = subprocess.run([sys.executable, str(ROOT / "tools/bench/uncertainty.py"), "--seeds",
                          "4", "--plants", "fopdt", "--bin", str(find_binary())],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "| FOPDT, step, white noise | fisher |" in res.stdout
    assert "| Td | 1.33 |" in res.stdout
