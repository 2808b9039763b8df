"""identify -> tune in one pipe, the fit written and drawn, and the
warnings on a model that is probably wrong (tools/cli/cmd_identify.c,
cmd_tune.c, fit_out.c, tools/plot_fit.py)."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

from pdtsupport.cli import BIN, TUNE_KEYS, assert_usage_error, parse_output, run, write_csv
from pdtsupport.plant import simulate
from pdtsupport.records import N, TS, U0, Y0, multistep_input, noise

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py


@pytest.fixture(scope="module")
def rec_csv(tmp_path_factory):
    u = multistep_input(N, U0, 5.0, 25, 60, 20, seed=7)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.3, u - U0, TS) + noise(N, 0.02, 11)
    path = tmp_path_factory.mktemp("rec") / "rec.csv"
    return write_csv(path, {"t": np.arange(N) * TS, "u": u, "y": y})


@pytest.fixture(scope="module")
def sopdt_csv(tmp_path_factory):
    u = multistep_input(N, U0, 5.0, 30, 80, 20, seed=3)
    y = Y0 + simulate([1.5], np.polymul([4.0, 1.0], [1.5, 1.0]), 0.8, u - U0, TS)
    path = tmp_path_factory.mktemp("rec") / "sopdt.csv"
    return write_csv(path, {"t": np.arange(N) * TS, "u": u, "y": y})


def same(a, b, rel=1e-7):
    """Equal JSON, numbers to about the seventh digit: a model read back
    from its 9 printed digits is not the one in memory (double build)."""
    if isinstance(a, dict):
        return list(a) == list(b) and all(same(a[k], b[k], rel) for k in a)
    if isinstance(a, float) or isinstance(b, float):
        return a == pytest.approx(b, rel=rel, abs=1e-12)
    return a == b


def pipe(first, second):
    a = run(first)
    assert a.returncode == 0, a.stderr
    return a, run(second, stdin=a.stdout)


# --------------------------------------------------------- identify | tune

def test_identify_pipe_tune(rec_csv):
    ident, res = pipe(["identify", "--model", "fopdt", rec_csv],
                      ["tune", "--rule", "simc", "--from", "-"])
    out = parse_output(res)
    m = json.loads(ident.stdout)
    assert list(out) == TUNE_KEYS + ["tau_c"]
    # SIMC PI on a FOPDT: Kc = tau / (K (tau_c + Td)), tauI = min(tau, 4 (tau_c + Td)).
    assert out["Kc"] == pytest.approx(m["tau"] / (m["K"] * 2 * m["Td"]), rel=1e-5)
    assert out["tauI"] == pytest.approx(min(m["tau"], 8 * m["Td"]), rel=1e-5)
    assert same(out, tune_known(m))


def tune_known(m, *extra):
    return parse_output(run(["tune", "--rule", "simc", *extra, "--model", "fopdt",
                             "--K", repr(m["K"]), "--tau", repr(m["tau"]), "--Td",
                             repr(m["Td"])]))


def test_tune_from_file_and_identify_tune(tmp_path, rec_csv):
    res = run(["identify", "--model", "fopdt", "--tune", "SIMC:pi", rec_csv])
    both = parse_output(res)
    tuning = both.pop("tune")
    path = tmp_path / "m.json"
    path.write_text(json.dumps(both) + "\n")
    assert same(parse_output(run(["tune", "--rule", "simc", "--from", path])), tuning)
    assert same(tuning, tune_known(both))


@pytest.mark.parametrize("args, status, frag", [
    (["--tune", "zn:pid"], "PDT_ERR_MS_LIMIT", "exceeds the limit 2"),
    (["--tune", "simc", "--fit-min", "100"], "PDT_ERR_POOR_FIT", "below 100%"),
])
def test_identify_tune_refused_keeps_the_model(rec_csv, args, status, frag):
    res = run(["identify", "--model", "fopdt", *args, rec_csv])
    assert res.returncode == 4, res.stderr
    out = json.loads(res.stdout)
    plain = parse_output(run(["identify", "--model", "fopdt", rec_csv]))
    tuning = out.pop("tune")
    assert out == plain
    assert tuning["status"] == status and frag in tuning["reason"]
    assert tuning["rule"] == args[1].split(":")[0] and "Kc" not in tuning
    assert "tuning refused" in res.stderr and frag in res.stderr
    assert "poorly" not in tuning["reason"]


def test_identify_tune_sopdt_pid(sopdt_csv):
    out = parse_output(run(["identify", "--model", "sopdt", "--tune", "simc:pid", "--u-span",
                            "100", "--y-span", "50", sopdt_csv]))
    t = out["tune"]
    assert t["form"] == "pid" and t["tauD"] > 0
    p, pc = t["parallel"], t["percent"]
    assert pc["Kp"] == pytest.approx(p["Kp"] * 50 / 100, rel=1e-6)
    assert pc["Ki"] == pytest.approx(p["Ki"] * 0.5, rel=1e-6)
    assert pc["Kd"] == pytest.approx(p["Kd"] * 0.5, rel=1e-6)


def test_tune_from_autotune_output(tmp_path):
    res = run(["autotune-sim", "--plant-gain", "2", "--plant-lags", "5", "--plant-delay", "1.3"])
    at = json.loads(res.stdout)
    path = tmp_path / "at.json"
    path.write_text(res.stdout)
    out = parse_output(run(["tune", "--rule", "simc", "--from", path]))
    assert out["Kc"] == pytest.approx(at["tune"]["Kc"], rel=1e-5)


def test_tune_from_refusals(tmp_path):
    path = tmp_path / "x.json"
    path.write_text('{"rule":"simc"}\n')
    assert_usage_error(run(["tune", "--rule", "simc", "--from", path]), "holds no model")
    path.write_text('{"model":"fopdt","K":1,"tau":-2,"Td":1}\n')
    assert_usage_error(run(["tune", "--rule", "simc", "--from", path]), "invalid")
    path.write_text('{"model":"fopdt","K":1,"tau":2,"Td":1,"fit":40}\n')
    # A fit threshold decides only when asked for (--fit-min).
    assert run(["tune", "--rule", "simc", "--from", path]).returncode == 0
    assert_usage_error(run(["tune", "--rule", "simc", "--from", path, "--fit-min", "80"]),
                       "fit 40% below 80%", status=1)


def test_percent_of_span():
    args = ["--model", "fopdt", "--K", "2", "--tau", "10", "--Td", "2"]
    out = parse_output(run(["tune", "--rule", "imc", "--form", "pid", *args, "--u-span", "50",
                            "--y-span", "200"]))
    assert list(out) == TUNE_KEYS[:-1] + ["percent", "stated_in", "lambda"]
    assert out["percent"]["Kp"] == pytest.approx(out["Kc"] * 4, rel=1e-6)


def test_simc_pid_on_fopdt_says_no_derivative():
    res = run(["tune", "--rule", "simc", "--form", "pid", "--model", "fopdt", "--K", "1",
               "--tau", "2.5", "--Td", "1.47"])
    assert res.returncode == 0 and json.loads(res.stdout)["tauD"] == 0
    assert res.stderr.startswith("pdtfit: warning: tune: simc gives this fopdt no derivative")


def test_zn_on_fopdt_without_delay_names_the_cause():
    res = run(["tune", "--rule", "zn", "--model", "fopdt", "--K", "1", "--tau", "1", "--Td", "0"])
    assert_usage_error(res, "no such form", "ultimate point", "no dead time", "--Ku", status=1)
    assert "complex" not in res.stderr


# ------------------------------------------------------------- see the fit

def test_out_sim(tmp_path, rec_csv):
    sim = tmp_path / "sim.csv"
    out = parse_output(run(["identify", "--model", "fopdt", "--out-sim", sim, rec_csv]))
    with open(sim, newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["t", "u", "y", "ysim", "residual"] and len(rows) == N
    y = np.array([float(r["y"]) for r in rows])
    ysim = np.array([float(r["ysim"]) for r in rows])
    res = np.array([float(r["residual"]) for r in rows])
    assert np.allclose(res, y - ysim, atol=1e-6)
    fit = 100 * (1 - np.linalg.norm(res) / np.linalg.norm(y - y.mean()))
    assert fit == pytest.approx(out["fit"], abs=0.05)
    assert float(rows[10]["t"]) == pytest.approx(10 * TS)


def test_plot(tmp_path, rec_csv):
    pytest.importorskip("matplotlib")
    png = tmp_path / "fit.png"
    out = parse_output(run(["identify", "--model", "fopdt", "--plot", png, rec_csv]))
    assert out["model"] == "fopdt"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert list(tmp_path.iterdir()) == [png]  # the temporary CSV is gone


def test_plot_failures(tmp_path, rec_csv):
    png = tmp_path / "fit.png"
    res = run(["identify", "--model", "fopdt", "--plot", png, "--plot-script",
               tmp_path / "none.py", rec_csv])
    assert_usage_error(res, "plot script not found")
    fake = tmp_path / "fake.py"
    fake.write_text("import sys\nsys.exit(4)\n")
    env = dict(os.environ, PDTFIT_PLOT_SCRIPT=str(fake))
    res = subprocess.run([str(BIN), "identify", "--model", "fopdt", "--plot", str(png),
                          str(rec_csv)], capture_output=True, text=True, env=env)
    assert_usage_error(res, "no matplotlib", status=1)
    env["PATH"] = str(tmp_path)  # no python3 there
    res = subprocess.run([str(BIN), "identify", "--model", "fopdt", "--plot", str(png),
                          str(rec_csv)], capture_output=True, text=True, env=env)
    assert res.returncode == 1 and "cannot run python3" in res.stderr


# ----------------------------------------------------- probably wrong

def test_ls_nonsense_on_a_step_test_warned(tmp_path):
    """A 400-row step test: the prediction-error scans land on a dead time
    near the end of the scan and a negative fit."""
    n = 400
    u = np.full(n, 50.0)
    u[20:] = 55.0
    y = 20 + simulate([2.0], [30.0, 1.0], 5.0, u - 50, 1.0) + noise(n, 1.0, 1)
    path = write_csv(tmp_path / "step.csv", {"t": np.arange(n) * 1.0, "u": u, "y": y})
    for method in ("elms", "eiv"):
        res = run(["identify", "--model", "fopdt", "--method", method, path])
        assert res.returncode == 3, res.stderr
        out = json.loads(res.stdout)
        assert out["fit"] < 0
        assert "pdtfit: warning: identify: fit" in res.stderr and "negative" in res.stderr
    res = run(["identify", "--model", "fopdt", path])
    assert res.returncode == 0 and res.stderr == ""


def test_ga_on_a_bound_warned(tmp_path, rec_csv):
    res = run(["identify", "--model", "fopdt", "--td-max", "0.5", rec_csv])
    assert res.returncode == 3
    assert "sits on its search bound" in res.stderr and "dead time at 0.5 s" in res.stderr


def test_budget_minimum(rec_csv):
    res = run(["identify", "--model", "fopdt", "--evaluations", "100", rec_csv])
    assert_usage_error(res, "--evaluations 100 is below the minimum", status=1)
    least = int(res.stderr.split("minimum ")[1].split()[0])
    assert run(["identify", "--model", "fopdt", "--evaluations", str(least),
                rec_csv]).returncode in (0, 3)
    assert run(["identify", "--model", "fopdt", "--evaluations", str(least - 1),
                rec_csv]).returncode == 1
