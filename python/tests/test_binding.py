"""The Python binding against the `pdtfit` program: the same record, options
and seed must give the same JSON to the last printed digit (the binding and
the program run the same C code in the same real type), and the binding's
own surface (errors, read_csv, simulate, plot) must hold."""
import json
import math

import numpy as np
import pytest

import pdtfit
from pdtsupport import cli, plant, status
from pdtsupport.rng import SplitMix64

cli_test = pytest.mark.cli


def cli_json(*args):
    """The program's JSON; a warning on stderr (such as SIMC's PID on a
    FOPDT having no derivative action) is the program's, not the JSON's."""
    res = cli.run([str(a) for a in args])
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def test_float_build():
    # The comparisons below are of the default (float) build, as .ci/run builds it.
    assert pdtfit.REAL_BYTES == 4


def test_status_names_are_the_librarys():
    """Every status of the header, named by pdt_status_name: the enum's own
    identifiers, which the command line's JSON prints too."""
    members = status.cheader.enums(status.HEADER)["pdt_status_t"]
    assert pdtfit.STATUS_NAMES == {value: name for name, value in members.items()}
    assert pdtfit.STATUS_NAMES[0] == "PDT_OK"
    assert set(pdtfit.STATUS_NAMES) == set(status.NAMES)


@cli_test
@pytest.mark.parametrize("name,model,cost,seed", [
    ("fopdt", "fopdt", "simulation", 1),
    ("fopdt", "fopdt", "prediction", 7),
    ("fopdt", "sopdt", "simulation", 2),
    ("sopdt", "sopdt", "simulation", 1),
    ("sopdt", "fopdt", "simulation", 99),
])
def test_identify_equals_the_program(records, write_csv, name, model, cost, seed):
    u, y, fs = records[name]
    path = write_csv("uy.csv", {"u": u, "y": y})
    want = cli_json("identify", "--model", model, "--cost", cost, "--seed", seed, "--fs", fs,
                    path)
    r = pdtfit.identify(u, y, fs, model=model, cost=cost, seed=seed)
    assert r.as_dict() == want and list(r.as_dict()) == list(want)
    for key, value in want.items():
        assert getattr(r, key) == value


@cli_test
def test_options_reach_the_library_as_on_the_command_line(records, write_csv):
    u, y, fs = records["fopdt"]
    path = write_csv("uy.csv", {"u": u, "y": y})
    want = cli_json("identify", "--model", "fopdt", "--fs", fs, "--evaluations", 600,
                    "--population", 20, "--td-max", 5, "--integer-delay", "--seed", 3, path)
    r = pdtfit.identify(u, y, fs, evaluations=600, population=20, td_max=5.0,
                        integer_delay=True, seed=3)
    assert r.as_dict() == want and r.evaluations <= 600


@cli_test
@pytest.mark.parametrize("coarse", [1, 3])
def test_coarse_reaches_the_library_as_on_the_command_line(records, write_csv, coarse):
    u, y, fs = records["fopdt"]
    path = write_csv("uy.csv", {"u": u, "y": y})
    want = cli_json("identify", "--model", "fopdt", "--fs", fs, "--coarse", coarse, path)
    r = pdtfit.identify(u, y, fs, coarse=coarse)
    assert r.as_dict() == want and r.coarse == coarse


@cli_test
@pytest.mark.parametrize("method,model,td_max", [("elms", "fopdt", None), ("eiv", "fopdt", 4.0),
                                                 ("elms", "sopdt", None), ("eiv", "sopdt", None)])
def test_least_squares_equals_the_program(records, write_csv, method, model, td_max):
    u, y, fs = records[model]
    path = write_csv("uy.csv", {"u": u, "y": y})
    extra = ["--td-max", td_max] if td_max is not None else []
    want = cli_json("identify", "--model", model, "--method", method, "--fs", fs, *extra, path)
    r = pdtfit.identify(u, y, fs, model=model, method=method, td_max=td_max)
    got = r.as_dict()
    assert list(got) == list(want)
    # The binding's fit is the library's (pdt_cost_fit, the one pdt_identify
    # reports); the program sums its own in double for these methods
    # (tools/cli/fit_out.c), which the float build can round otherwise.
    assert got.pop("fit") == pytest.approx(want.pop("fit"), rel=1e-6)
    assert got == want
    with pytest.raises(ValueError, match="seed"):
        pdtfit.identify(u, y, fs, method=method, seed=2)


@cli_test
def test_read_csv_with_time_column_equals_the_program(records, write_csv):
    u, y, fs = records["fopdt"]
    path = write_csv("tuy.csv", {"t": np.arange(len(u)) / fs, "u": u, "y": y})
    rec = pdtfit.read_csv(path)
    assert rec.n == len(u) and np.array_equal(rec.u, u) and np.array_equal(rec.y, y)
    assert rec.Ts == pytest.approx(1.0 / fs, rel=1e-12)
    want = cli_json("identify", "--model", "fopdt", path)
    assert pdtfit.identify(rec.u, rec.y, Ts=rec.Ts).as_dict() == want


@cli_test
def test_read_csv_errors_are_the_programs(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("t,u,y\n" + "".join(f"{k},1,2\n" for k in range(5)) + "5,1,abc\n")
    res = cli.run(["identify", "--model", "fopdt", path])
    assert res.returncode == 2
    with pytest.raises(ValueError) as e:
        pdtfit.read_csv(path)
    assert res.stderr.strip() == "pdtfit: " + str(e.value)
    assert ":7:" in str(e.value)


@cli_test
@pytest.mark.parametrize("rule,form", [("simc", "pi"), ("simc", "pid"), ("imc", "pi"),
                                       ("imc", "pid"), ("amigo", "pi"), ("zn", "pi")])
def test_tune_equals_the_program(records, rule, form):
    u, y, fs = records["fopdt"]
    r = pdtfit.identify(u, y, fs, model="fopdt")
    want = cli_json("tune", "--rule", rule, "--form", form, "--model", "fopdt",
                    "--K", repr(r.K), "--tau", repr(r.tau), "--Td", repr(r.Td), "--ms-max", 0)
    assert pdtfit.tune(r, rule=rule, form=form, ms_max=0).as_dict() == want


@cli_test
def test_tune_of_a_printed_sopdt_equals_the_program(records):
    u, y, fs = records["sopdt"]
    printed = pdtfit.identify(u, y, fs, model="sopdt").as_dict()
    want = cli_json("tune", "--rule", "imc", "--form", "pid", "--model", "sopdt",
                    "--K", printed["K"], "--wn", printed["wn"], "--zeta", printed["zeta"],
                    "--Td", printed["Td"], "--lambda", 4)
    got = pdtfit.tune(printed, rule="imc", form="pid", lambda_=4.0)
    assert got.as_dict() == want and got.lambda_ == 4.0


@cli_test
@pytest.mark.parametrize("method,model", [("skogestad", "fopdt"), ("skogestad", "sopdt"),
                                          ("sung", "fopdt"), ("sung", "sopdt")])
def test_reduce_equals_the_program(method, model):
    lags, zeros = [2, 1, 0.4, 0.2, 0.05, 0.05, 0.05], [-0.3, 0.08]
    want = cli_json("reduce", "--method", method, "--model", model, "--gain", 1,
                    "--lags", ",".join(map(str, lags)), "--zeros", ",".join(map(str, zeros)))
    assert pdtfit.reduce(1.0, lags, zeros, model=model, method=method).as_dict() == want


@cli_test
def test_refusal_is_the_programs(write_csv, records):
    u, y, fs = records["fopdt"]
    flat = np.full_like(u, u[0])
    res = cli.run(["identify", "--model", "fopdt", "--fs", fs,
                   write_csv("flat.csv", {"u": flat, "y": y})])
    assert res.returncode == 1
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.identify(flat, y, fs)
    assert e.value.status == "PDT_ERR_NO_EXCITATION"
    assert e.value.code == status.STATUS["NO_EXCITATION"]
    # The library's own words, as the program prints them.
    assert str(e.value).split(": ")[1].split(" (")[0] in res.stderr


@cli_test
def test_status_names_are_the_programs():
    """The name the program's JSON gives a refusal is the binding's."""
    res = cli.run(["autotune-sim", "--plant-gain", "2", "--plant-lags", "5", "--plant-delay",
                   "1.3", "--pv-max", "0.5"])
    assert res.returncode == 1
    got = json.loads(res.stdout)
    code = status.STATUS["PV_LIMIT"]
    assert got["status"] == pdtfit.STATUS_NAMES[code] == "PDT_ERR_PV_LIMIT"
    assert got["reason"] == pdtfit.PdtError(code, "x").args[0].split(": ")[1].split(" (")[0]


def test_tune_refused_by_ms_limit(records):
    u, y, fs = records["fopdt"]
    r = pdtfit.identify(u, y, fs)
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.tune(r, rule="zn", form="pid", ms_max=1.1)
    assert e.value.status == "PDT_ERR_MS_LIMIT" and "Ms " in str(e.value)


def test_simulate_gives_the_reported_fit(records):
    u, y, fs = records["sopdt"]
    r = pdtfit.identify(u, y, fs, model="sopdt")
    ysim = r.simulate()
    fit = 100.0 * (1.0 - np.linalg.norm(y - ysim) / np.linalg.norm(y - np.mean(y)))
    assert fit == pytest.approx(r.fit, abs=0.05)
    assert r.fit > 90.0


def test_model_constructors_agree():
    nat = pdtfit.model("sopdt", 2.0, 1.5, wn=0.5, zeta=1.25)
    tc = pdtfit.model("sopdt", 2.0, 1.5, tau1=nat.tau1, tau2=nat.tau2)
    assert tc.K == pytest.approx(2.0) and tc.zeta == pytest.approx(1.25, rel=1e-5)
    f = pdtfit.model("FOPDT", 1.0, 0.5, tau=3.0)
    assert f.as_dict() == {"model": "fopdt", "K": 1, "tau": 3, "Td": 0.5}
    integ = pdtfit.model("sopdt", Td=1.0, Ki=0.2, T=4.0)
    assert integ.K is None and integ.Ki == pytest.approx(0.2) and integ.wn == 0


def test_bad_choices_and_arguments():
    u = np.zeros(100)
    with pytest.raises(ValueError, match="unknown cost"):
        pdtfit.identify(u, u, 1.0, cost="nope")
    with pytest.raises(ValueError, match="fs"):
        pdtfit.identify(u, u)
    with pytest.raises(ValueError):
        pdtfit.identify(u, u[:50], 1.0)
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.identify(u, u, 1.0, evaluations=1)
    assert e.value.status in pdtfit.STATUS_NAMES.values()


def test_plot_returns_a_figure(records):
    pytest.importorskip("matplotlib")
    u, y, fs = records["fopdt"]
    fig = pdtfit.identify(u, y, fs).plot()
    assert type(fig).__name__ == "Figure" and len(fig.axes) == 2
    assert "FOPDT" in fig._suptitle.get_text() and math.isfinite(fig.axes[1].lines[0].get_ydata()[0])


def test_read_csv_header_unit_and_missing_samples(records, tmp_path):
    """The header's time unit and the missing samples, as the program
    reads them: t [ms] in milliseconds, #N/A in y NaN, an empty u the u
    before it; a unit given overrides the header."""
    u, y, fs = records["fopdt"]
    lines = ["t [ms],u,y"] + [f"{1000.0 * k / fs!r},{float(a)!r},{float(b)!r}" for k, (a, b) in
                               enumerate(zip(u, y))]
    lines[11] = lines[11].rsplit(",", 1)[0] + ",#N/A"
    t, _, last = lines[21].split(",")
    lines[21] = f"{t},,{last}"
    path = tmp_path / "ms.csv"
    path.write_text("\n".join(lines) + "\n")
    rec = pdtfit.read_csv(path)
    assert rec.Ts == pytest.approx(1.0 / fs, rel=1e-9)
    assert math.isnan(rec.y[10]) and np.isfinite(np.delete(rec.y, 10)).all()
    assert rec.u[20] == rec.u[19]
    assert pdtfit.read_csv(path, time_unit="s").Ts == pytest.approx(1000.0 / fs, rel=1e-9)


def test_read_csv_bad_value_and_bad_rows(records, tmp_path):
    """A declared bad value is a missing sample (--bad-value); with
    bad_rows="refuse" a missing sample is refused with its line."""
    u, y, fs = records["fopdt"]
    lines = ["t,u,y"] + [f"{k / fs!r},{float(a)!r},{float(b)!r}" for k, (a, b) in
                         enumerate(zip(u, y))]
    lines[31] = lines[31].rsplit(",", 1)[0] + ",-9999"
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    assert pdtfit.read_csv(path).y[30] == -9999
    rec = pdtfit.read_csv(path, bad_value=[-9999, 32767])
    assert math.isnan(rec.y[30]) and np.isfinite(np.delete(rec.y, 30)).all()
    with pytest.raises(ValueError, match=r"bad\.csv:32: .*declared bad value"):
        pdtfit.read_csv(path, bad_value=-9999, bad_rows="refuse")


def _fopdt_response(u, Ts, u0):
    """20 + the response of 2 e^(-1.3 s) / (5 s + 1), at rest at u0 before
    the record, to u (zero-order hold, whole-sample dead time)."""
    y = plant.first_order(2.0, math.exp(-Ts / 5.0), np.asarray(u) - u0, int(round(1.3 / Ts)) + 1)
    return 20.0 + y + 0.01 * SplitMix64.keyed(5).normal(len(u))


def test_missing_samples_and_u_before():
    """A NaN in y is left out of the fit and counted (missing="refuse":
    refused); a record that begins at the step needs u_before."""
    n, Ts = 600, 0.1
    u = 50.0 + 5.0 * SplitMix64.keyed(3).signs(n, 20)
    u[:30] = 50.0
    y = _fopdt_response(u, Ts, 50.0)
    ref = pdtfit.identify(u, y, Ts=Ts)
    assert ref.excluded == {"count": 0, "missing": 0, "first": []}
    y[100:105] = np.nan
    r = pdtfit.identify(u, y, Ts=Ts)
    assert r.excluded["missing"] == 5 and r.excluded["first"][:5] == [100, 101, 102, 103, 104]
    assert r.K == pytest.approx(ref.K, rel=0.01)
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.identify(u, y, Ts=Ts, missing="refuse")
    assert e.value.status == "PDT_ERR_NONFINITE"
    step = np.full(n, 55.0)
    y = _fopdt_response(step, Ts, 50.0)
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.identify(step, y, Ts=Ts)
    assert e.value.status == "PDT_ERR_NO_EXCITATION"
    r = pdtfit.identify(step, y, Ts=Ts, u_before=50.0)
    assert r.u0 == 50.0 and r.K == pytest.approx(2.0, rel=0.01)


def test_initial_estimate_and_drift():
    """A record cut mid-transient: initial="estimate" finds the whole
    record's gain; a ramp on the output: drift=True finds the ramp-free model and
    the slope. Both need the output error."""
    n, Ts, cut = 900, 0.1, 150
    u = 50.0 + 5.0 * SplitMix64.keyed(7).signs(n, 25)
    u[:30] = 50.0
    y = _fopdt_response(u, Ts, 50.0)
    whole = pdtfit.identify(u, y, Ts=Ts)
    r = pdtfit.identify(u[cut:], y[cut:], Ts=Ts, initial="estimate")
    assert r.K == pytest.approx(whole.K, rel=0.02)
    assert r.tau == pytest.approx(whole.tau, rel=0.05)
    assert r.initial == "estimate" and math.isfinite(r.x0)
    slope = 0.02
    r = pdtfit.identify(u, y + slope * Ts * np.arange(n), Ts=Ts, drift=True)
    assert r.K == pytest.approx(whole.K, rel=0.01)
    assert r.drift == pytest.approx(slope, rel=0.05)
    with pytest.raises(ValueError):
        pdtfit.identify(u, y, Ts=Ts, drift=True, cost="prediction")
    with pytest.raises(ValueError):
        pdtfit.identify(u, y, Ts=Ts, initial="estimate", method="elms")
