"""`pdtfit reduce` and `pdtfit identify --method elms|eiv` (tools/cli/).

The binary is found as in test_cli.py ($PDTFIT_BIN, else the newest
build/*/tools/pdtfit); without one the tests are skipped (failed in CI).
The reductions are checked on the paper's system (17) against its published
values; the least-squares scans on noise-free records with a whole-sample dead time,
which they must recover to the real type's rounding.
"""
import json

import numpy as np
import pytest

from pdtsupport.cli import LS_FOPDT_KEYS, LS_SOPDT_KEYS, assert_usage_error, parse_output, run, \
    write_csv
from pdtsupport import plant, records

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py

LAGS17 = "2,1,0.4,0.2,0.05,0.05,0.05"
ZEROS17 = "-0.3,0.08"
REDUCE_FOPDT_KEYS = ["model", "K", "tau", "Td"]
REDUCE_SOPDT_KEYS = ["model", "K", "wn", "zeta", "Td", "tau1", "tau2", "a", "b"]


def reduce17(method, model, *extra):
    return parse_output(run(["reduce", "--method", method, "--model", model, "--gain", "1",
                             "--lags", LAGS17, "--zeros", ZEROS17, *extra]))


# ----------------------------------------------------------------- reduce

def test_half_rule_fopdt_17():
    out = reduce17("skogestad", "fopdt")
    assert list(out) == REDUCE_FOPDT_KEYS and out["model"] == "fopdt"
    assert out["K"] == pytest.approx(1.0, rel=1e-6)
    assert out["tau"] == pytest.approx(2.5, rel=1e-5)
    assert out["Td"] == pytest.approx(1.47, rel=1e-5)


def test_half_rule_sopdt_17():
    out = reduce17("skogestad", "sopdt")
    assert list(out) == REDUCE_SOPDT_KEYS and out["model"] == "sopdt"
    assert out["K"] == pytest.approx(1.0, rel=1e-5)
    assert out["tau1"] == pytest.approx(2.0, rel=1e-4)
    assert out["tau2"] == pytest.approx(1.2, rel=1e-4)
    assert out["Td"] == pytest.approx(0.77, rel=1e-5)
    assert out["b"] == pytest.approx(1.0 / (2.0 * 1.2), rel=1e-4)


def test_half_rule_controller_period_and_delay():
    """h / 2 and the model's own delay both add to the dead time; = syntax."""
    out = reduce17("skogestad", "fopdt", "--h=0.2", "--delay", "0.5")
    assert out["Td"] == pytest.approx(1.47 + 0.1 + 0.5, rel=1e-5)
    assert out["tau"] == pytest.approx(2.5, rel=1e-5)


def test_sung_fopdt_17():
    out = reduce17("sung", "fopdt")
    assert list(out) == REDUCE_FOPDT_KEYS
    assert out["K"] == pytest.approx(1.0, rel=1e-6)
    assert round(out["tau"], 2) == 2.86
    assert round(out["Td"], 2) == 1.57


def test_sung_sopdt_17():
    out = reduce17("sung", "sopdt")
    assert out["model"] in ("sopdt", "fopdt")
    if out["model"] == "sopdt":
        assert list(out) == REDUCE_SOPDT_KEYS
        assert out["K"] == pytest.approx(1.0, rel=1e-5)
        assert 0.0 < out["Td"] < 1.5


def test_reduce_gain_and_plain_lags():
    """A sign and a gain pass through; without zeros, two lags to FOPDT."""
    out = parse_output(run(["reduce", "--method", "skogestad", "--model", "fopdt", "--gain",
                            "-2.5", "--lags", "3,1"]))
    assert out["K"] == pytest.approx(-2.5, rel=1e-6)
    assert out["tau"] == pytest.approx(3.5, rel=1e-6)
    assert out["Td"] == pytest.approx(0.5, rel=1e-6)


REDUCE_BASE = ["reduce", "--method", "skogestad", "--model", "fopdt", "--gain", "1",
               "--lags", "2,1"]


@pytest.mark.parametrize("args,frag", [
    (["reduce"], "--method"),
    (["reduce", "--model", "fopdt", "--gain", "1", "--lags", "1"], "--method"),
    (["reduce", "--method", "skogestad", "--gain", "1", "--lags", "1"], "--model"),
    (["reduce", "--method", "skogestad", "--model", "fopdt", "--lags", "1"], "--gain"),
    (["reduce", "--method", "skogestad", "--model", "fopdt", "--gain", "1"], "--lags"),
    (["reduce", "--method", "halving", "--model", "fopdt", "--gain", "1", "--lags", "1"],
     "unknown method"),
    (REDUCE_BASE[:4] + ["thirdorder"] + REDUCE_BASE[5:], "unknown model"),
    (REDUCE_BASE[:6] + ["one"] + REDUCE_BASE[7:], "--gain"),
    (REDUCE_BASE[:6] + ["inf"] + REDUCE_BASE[7:], "--gain"),
    (REDUCE_BASE[:8] + ["2,-1"], "--lags"),
    (REDUCE_BASE[:8] + ["2,0"], "--lags"),
    (REDUCE_BASE[:8] + ["2,,1"], "--lags"),
    (REDUCE_BASE[:8] + [""], "--lags"),
    (REDUCE_BASE[:8] + ["2;1"], "--lags"),
    (REDUCE_BASE[:8] + [",".join(["1"] * 65)], "--lags"),
    (REDUCE_BASE + ["--zeros", "0.5,0"], "--zeros"),
    (REDUCE_BASE + ["--zeros", "x"], "--zeros"),
    (REDUCE_BASE + ["--delay", "-1"], "--delay"),
    (REDUCE_BASE + ["--delay", "nan"], "--delay"),
    (REDUCE_BASE + ["--h", "-0.1"], "--h"),
    (REDUCE_BASE + ["--h"], "needs a value"),
    (["reduce", "--method", "sung", "--model", "fopdt", "--gain", "1", "--lags", "2,1",
      "--h", "0.1"], "--h"),
    (REDUCE_BASE + ["--cost", "simulation"], "unknown option '--cost'"),
    (REDUCE_BASE + ["model.csv"], "unexpected argument"),
    (REDUCE_BASE + ["-x"], "unexpected argument"),
])
def test_reduce_usage_errors(args, frag):
    assert_usage_error(run(args), frag)


def test_reduce_library_refusals():
    # Sung needs a phase crossover: one lag never reaches -180 degrees.
    res = run(["reduce", "--method", "sung", "--model", "fopdt", "--gain", "1", "--lags", "2"])
    assert_usage_error(res, "cannot reduce", status=1)
    # A SOPDT from one lag has no second time constant.
    res = run(["reduce", "--method", "skogestad", "--model", "sopdt", "--gain", "1",
               "--lags", "2"])
    assert_usage_error(res, "cannot reduce", status=1)
    # More lags than the half rule takes (PDT_REDUCE_MAX_LAGS = 32).
    res = run(["reduce", "--method", "skogestad", "--model", "fopdt", "--gain", "1",
               "--lags", ",".join(["0.1"] * 40)])
    assert_usage_error(res, "cannot reduce", status=1)


def test_help_mentions_the_new_commands():
    text = run(["--help"]).stdout
    for word in ["reduce", "--method", "skogestad", "sung", "--lags", "--zeros", "--delay",
                 "--h ", "elms", "eiv", "--td-max"]:
        assert word in text, word
    res = run(["reduce", "--help"])
    assert res.returncode == 0 and "reduce: " in res.stdout and "--lags" in res.stdout
    assert "--cost KIND" not in res.stdout


# ----------------------------------------------------------------- elms / eiv

TS = 0.1


def multistep(n, u0, seed):
    """Steps of 25 to 64 samples, 1.6 to 4 around u0, after 20 at rest."""
    return records.multistep_input(n, u0, 4.0, 25, 64, 20, seed)


def fopdt_record(K=2.0, tau=5.0, l=13, n=600, u0=50.0, y0=20.0):
    """Exact samples of K e^{-l Ts s}/(tau s + 1) behind a ZOH: the
    difference equation (3) is exact for it."""
    u = multistep(n, u0, 7)
    return u, y0 + plant.first_order(K, np.exp(-TS / tau), u - u0, l)


def sopdt_record(K=1.5, T1=4.0, T2=1.0, l=8, n=800, u0=10.0, y0=3.0):
    u = multistep(n, u0, 11)
    a1, a2 = np.exp(-TS / T1), np.exp(-TS / T2)
    # ZOH of K/((T1 s+1)(T2 s+1)): step response at Ts and 2 Ts gives b1, b2.
    h = lambda t: K * (1 - (T1 * np.exp(-t / T1) - T2 * np.exp(-t / T2)) / (T1 - T2))
    A1, A2 = -(a1 + a2), a1 * a2
    b1 = h(TS)
    b2 = h(2 * TS) - h(TS) + A1 * b1
    y = np.zeros(n)
    du = u - u0
    for k in range(n):
        v = 0.0
        if k >= 1:
            v -= A1 * y[k - 1]
        if k >= 2:
            v -= A2 * y[k - 2]
        if k - 1 - l >= 0:
            v += b1 * du[k - 1 - l]
        if k - 2 - l >= 0:
            v += b2 * du[k - 2 - l]
        y[k] = v
    return u, y0 + y


@pytest.fixture(scope="module")
def fopdt_csv(tmp_path_factory):
    u, y = fopdt_record()
    return write_csv(tmp_path_factory.mktemp("ls") / "fopdt.csv",
                     {"t": np.arange(len(u)) * TS, "u": u, "y": y}, fmt="%.12g")


@pytest.fixture(scope="module")
def sopdt_csv(tmp_path_factory):
    u, y = sopdt_record()
    return write_csv(tmp_path_factory.mktemp("ls") / "sopdt.csv",
                     {"t": np.arange(len(u)) * TS, "u": u, "y": y}, fmt="%.12g")


def float_build():
    return "float" in run(["--version"]).stdout


@pytest.mark.parametrize("method", ["elms", "eiv"])
def test_ls_fopdt_exact(fopdt_csv, method):
    out = parse_output(run(["identify", "--model", "fopdt", "--method", method, fopdt_csv]))
    assert list(out) == LS_FOPDT_KEYS
    rtol = 2e-3 if float_build() else 1e-6
    assert out["K"] == pytest.approx(2.0, rel=rtol)
    assert out["tau"] == pytest.approx(5.0, rel=rtol)
    assert out["Td"] == pytest.approx(1.3, abs=1e-5)
    assert out["y0"] == pytest.approx(20.0, abs=1e-3)
    assert out["u0"] == pytest.approx(50.0)
    assert 0.0 <= out["cost"] < 1e-6
    assert out["fit"] > 99.0
    # Dead times scanned: 0 .. n / 4 by default, 0 .. 3 s with --td-max 3.
    assert out["evaluations"] == 600 // 4 + 1
    out = parse_output(run(["identify", "--model", "fopdt", "--method", method, "--td-max",
                            "3", fopdt_csv]))
    assert out["evaluations"] == 31 and out["Td"] == pytest.approx(1.3, abs=1e-5)


@pytest.mark.parametrize("method", ["elms", "eiv"])
def test_ls_sopdt_exact(sopdt_csv, method):
    out = parse_output(run(["identify", "--model", "sopdt", "--method", method, sopdt_csv]))
    assert list(out) == LS_SOPDT_KEYS
    rtol = 2e-2 if float_build() else 1e-5
    assert out["K"] == pytest.approx(1.5, rel=rtol)
    assert out["tau1"] == pytest.approx(4.0, rel=rtol)
    assert out["tau2"] == pytest.approx(1.0, rel=rtol)
    assert out["Td"] == pytest.approx(0.8, abs=1e-5)
    assert out["fit"] > 98.0


def test_ls_td_max_past_record_refused(fopdt_csv):
    """A dead-time bound that leaves too few samples is the library's
    refusal (exit 1), not a usage error."""
    res = run(["identify", "--model", "fopdt", "--method", "elms", "--td-max", "100",
               fopdt_csv])
    assert_usage_error(res, "cannot identify", status=1)


def test_ls_constant_input_refused(tmp_path):
    n = 64
    path = write_csv(tmp_path / "flat.csv", {"t": np.arange(n) * TS, "u": np.full(n, 5.0),
                                             "y": np.linspace(0, 1, n)})
    res = run(["identify", "--model", "fopdt", "--method", "eiv", path])
    assert_usage_error(res, "cannot identify", status=1)


@pytest.mark.parametrize("args,frag", [
    (["--method", "lms"], "unknown method"),
    (["--method", "elms", "--cost", "simulation"], "--cost"),
    (["--method", "eiv", "--seed", "3"], "--seed"),
    (["--method", "elms", "--evaluations", "100"], "--evaluations"),
    (["--method", "eiv", "--population", "8"], "--population"),
    (["--td-max", "-1"], "--td-max"),
    (["--td-max", "x"], "--td-max"),
    (["--td-max", "0"], "--td-max"),  # ga needs a positive bound
    (["--method"], "needs a value"),
])
def test_identify_method_usage_errors(args, frag):
    assert_usage_error(run(["identify", "--model", "fopdt", *args, "X"])
                       if args != ["--method"] else
                       run(["identify", "--model", "fopdt", "X", "--method"]), frag)


def test_ls_td_max_zero_allowed(tmp_path):
    """elms takes --td-max 0 (delay 0 only); the JSON says one delay scanned."""
    u, y = fopdt_record(l=0)
    path = write_csv(tmp_path / "nodelay.csv", {"t": np.arange(len(u)) * TS, "u": u, "y": y},
                     fmt="%.12g")
    out = parse_output(run(["identify", "--model", "fopdt", "--method", "elms", "--td-max",
                            "0", path]))
    assert out["evaluations"] == 1 and out["Td"] == 0
    assert json.dumps(out)  # plain JSON
