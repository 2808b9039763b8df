"""Records as loggers and plants make them, through `pdtfit identify` and
`tune`: missing samples (empty cells, NaN, #N/A, ERR, spreadsheet errors,
declared bad values), the time unit of the header, epoch stamps read as
seconds, and flagged models kept from the tuning (docs/cli.md, "Missing
samples" and "A model that is probably wrong").

The record is test_cli's FOPDT (K = 2, tau = 5 s, Td = 1.3 s at 10 Hz)."""
import json

import numpy as np
import pytest

from pdtsupport.cli import assert_usage_error, run
from pdtsupport.plant import simulate
from pdtsupport.records import N, TS, U0, Y0, multistep_input, noise
from pdtsupport.rng import SplitMix64

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py

MODEL = ["identify", "--model", "fopdt"]
STRICT = ["--bad-rows", "refuse"]


@pytest.fixture(scope="module")
def rec():
    u = multistep_input(N, U0, 5.0, 25, 60, 20, seed=7)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.3, u - U0, TS) + noise(N, 0.02, 11)
    return np.arange(N) * TS, u, y


def rows(t, u, y, tfmt="%.10g"):
    return [[tfmt % a, "%.10g" % b, "%.10g" % c] for a, b, c in zip(t, u, y)]


def write(path, header, body):
    path.write_text("\n".join([header] + [",".join(r) for r in body]) + "\n")
    return path


def check_fopdt(out, K, tau, Td):
    """The record's FOPDT, whatever keys the JSON has beside it."""
    assert out["model"] == "fopdt"
    assert out["K"] == pytest.approx(K, rel=0.02)
    assert out["tau"] == pytest.approx(tau, rel=0.02)
    assert out["Td"] == pytest.approx(Td, abs=0.05)
    assert out["y0"] == pytest.approx(Y0, abs=0.05) and out["u0"] == pytest.approx(U0)


def model_of(res, warn=None):
    """The JSON of a run that printed a model; stderr empty, or one warning
    holding every fragment of `warn`."""
    assert res.returncode == 0, res.stderr
    if warn is None:
        assert res.stderr == ""
    else:
        lines = res.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("pdtfit: warning: "), res.stderr
        for frag in warn:
            assert frag in lines[0], (frag, lines[0])
    return json.loads(res.stdout)


# ------------------------------------------------------ missing samples

MARKERS = ["", "  ", "NaN", "nan", "-nan", "#N/A", "N/A", "n/a", "NA", "ERR", "Error", "#VALUE!",
           "#DIV/0!", "#NAME?", "#REF!", "Bad Input", "I/O Timeout", "inf", "1e999"]


@pytest.mark.parametrize("marker", MARKERS)
def test_marker_in_y_refused_in_the_strict_reading(tmp_path, rec, marker):
    body = rows(*rec)
    body[149][2] = marker
    path = write(tmp_path / "m.csv", "t,u,y", body)
    assert_usage_error(run([*MODEL, *STRICT, path]), "m.csv:151:", "column y")


@pytest.mark.parametrize("text", ["-9999", "-9999.0", "-9.999e3"])
def test_declared_bad_value_refused_in_the_strict_reading(tmp_path, rec, text):
    body = rows(*rec)
    body[300][2] = text
    path = write(tmp_path / "b.csv", "t,u,y", body)
    assert_usage_error(run([*MODEL, *STRICT, "--bad-value", "-9999", path]), "b.csv:302:",
                       "column y", "declared bad value")
    # Undeclared it is a number like any other: the library's to judge.
    assert run([*MODEL, *STRICT, path]).returncode != 2


def test_text_that_is_no_marker_is_refused_in_either_reading(tmp_path, rec):
    body = rows(*rec)
    body[40][2] = "12.3x"
    path = write(tmp_path / "x.csv", "t,u,y", body)
    for extra in ([], STRICT):
        assert_usage_error(run([*MODEL, *extra, path]), "x.csv:42:", "column y",
                           "is not a number")


def test_missing_u_holds_the_u_before(tmp_path, rec):
    """Markers in u inside a level: the u before is held, the model is the
    clean record's, the JSON and one warning say so."""
    t, u, y = rec
    clean = model_of(run([*MODEL, write(tmp_path / "c.csv", "t,u,y", rows(t, u, y))]))
    body = rows(t, u, y)
    for k, m in ((100, "#N/A"), (101, ""), (250, "-9999"), (400, "ERR")):
        assert u[k] == u[k - 1]
        body[k][1] = m
    path = write(tmp_path / "u.csv", "t,u,y", body)
    res = run([*MODEL, "--bad-value", "-9999", path])
    out = model_of(res, warn=["u.csv: missing samples", "0 of y", "4 of u",
                              "lines 102, 103, 252, 402"])
    assert out["missing"] == {"count": 0, "first": [], "u_held": 4}
    for key in ("K", "tau", "Td", "y0", "cost"):
        assert out[key] == clean[key]
    assert list(out)[-1] == "missing"


def test_missing_u_at_the_start_takes_the_first_u(tmp_path, rec):
    t, u, y = rec
    body = rows(t, u, y)
    body[0][1] = body[1][1] = "NaN"
    out = model_of(run([*MODEL, write(tmp_path / "u0.csv", "t,u,y", body)]),
                   warn=["2 of u", "lines 2, 3"])
    check_fopdt(out, 2.0, 5.0, 1.3)


def test_missing_y_is_left_out_or_refused(tmp_path, rec):
    """A missing y is NaN to the library: left out of the fit where the
    library takes missing samples, else refused naming them."""
    t, u, y = rec
    body = rows(t, u, y)
    for k, m in ((120, "#N/A"), (121, "#N/A"), (330, ""), (331, "ERR")):
        body[k][2] = m
    path = write(tmp_path / "y.csv", "t,u,y", body)
    res = run([*MODEL, path])
    lines = res.stderr.splitlines()
    assert lines[0].startswith("pdtfit: warning: ") and "y.csv: missing samples" in lines[0]
    assert "4 of y left out of the fit, 0 of u" in lines[0]
    assert "lines 122, 123, 332, 333" in lines[0]
    if res.returncode == 0:
        out = json.loads(res.stdout)
        assert out["missing"] == {"count": 4, "first": [120, 121, 330, 331], "u_held": 0}
        assert out["excluded"]["missing"] == 4
        check_fopdt(out, 2.0, 5.0, 1.3)
    else:
        assert res.returncode == 1 and res.stdout == ""
        assert "4 missing samples of y" in lines[1] and "--bad-rows refuse" in lines[1]


def test_a_column_of_markers_is_refused(tmp_path, rec):
    t, u, y = rec
    body = [[a, b, "#N/A"] for a, b, _ in rows(t, u, y)]
    assert_usage_error(run([*MODEL, write(tmp_path / "all.csv", "t,u,y", body)]),
                       "all.csv:", "column y holds no value")


@pytest.mark.parametrize("cell", ["", "#N/A", "NaN"])
def test_missing_time_is_refused(tmp_path, rec, cell):
    body = rows(*rec)
    body[77][0] = cell
    path = write(tmp_path / "t.csv", "t,u,y", body)
    assert_usage_error(run([*MODEL, path]), "t.csv:79:", "column t")


def test_stamp_far_out_of_place_is_refused(tmp_path, rec):
    """A last stamp 10^8 s on (a wrong year, a counter's wrap): refused as a
    gap, and with --resample at once rather than filled with 10^9 rows
    (found by fuzz_csv: tests/fuzz/corpus/csv/finding-gap-rows)."""
    body = rows(*rec)
    body[-1][0] = "%.10g" % 1e8
    path = write(tmp_path / "far.csv", "t,u,y", body)
    assert_usage_error(run([*MODEL, path]), "far.csv:", "not uniformly sampled")
    assert_usage_error(run([*MODEL, "--resample", path]), "far.csv:", "rows a record may have")


def test_bad_value_usage(tmp_path, rec):
    path = write(tmp_path / "ok.csv", "t,u,y", rows(*rec))
    assert_usage_error(run([*MODEL, "--bad-value", "x", path]), "--bad-value")
    assert_usage_error(run([*MODEL, "--bad-rows", "drop", path]), "bad-rows mode")
    # Repeated and listed: the values add up.
    body = rows(*rec)
    body[10][2], body[20][2], body[30][2] = "-9999", "32767", "65535"
    path = write(tmp_path / "s.csv", "t,u,y", body)
    res = run([*MODEL, *STRICT, "--bad-value", "-9999", "--bad-value", "32767,65535", path])
    assert_usage_error(res, "s.csv:12:", "declared bad value")


# ------------------------------------------------------------ time units

@pytest.mark.parametrize("header,scale", [
    ("t [ms]", 1e3), ("time_ms", 1e3), ("t (us)", 1e6), ("Time [s]", 1.0), ("time", 1.0),
    ("t_min", 1.0 / 60.0), ("T [msec]", 1e3), ("t_us", 1e6), ("Time (h)", 1.0 / 3600.0),
    ("t [\u00b5s]", 1e6), ("timestamp [ms]", 1e3), ("Timestamp_s", 1.0)])
def test_time_unit_from_the_header(tmp_path, rec, header, scale):
    t, u, y = rec
    path = tmp_path / "unit.csv"
    path.write_text("\n".join([f"{header},u,y"] + [",".join(r) for r in rows(
        t * scale, u, y, "%.12g")]) + "\n", encoding="utf-8")
    out = model_of(run([*MODEL, path]))
    assert out["Ts"] == pytest.approx(TS, rel=1e-6)
    check_fopdt(out, 2.0, 5.0, 1.3)


def test_time_unit_option_overrides_the_header(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "o.csv", "t [s],u,y", rows(t * 1e3, u, y))
    out = model_of(run([*MODEL, "--time-unit", "ms", path]))
    assert out["Ts"] == pytest.approx(TS, rel=1e-6)


def test_header_unit_that_is_no_time_unit(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "f.csv", "t [degC],u,y", rows(t, u, y))
    assert_usage_error(run([*MODEL, path]), "f.csv:2:", "\"degC\" is not a time unit",
                       "--time-unit")
    assert model_of(run([*MODEL, "--time-unit", "s", path]))["Ts"] == pytest.approx(TS)


@pytest.mark.parametrize("start,scale,unit", [(1.7e12, 1e3, "ms"), (1.7e15, 1e6, "us")])
def test_epoch_counts_read_as_seconds_are_refused(tmp_path, rec, start, scale, unit):
    t, u, y = rec
    path = write(tmp_path / "e.csv", "t,u,y", rows(start + np.round(t * scale), u, y, "%.17g"))
    assert_usage_error(run([*MODEL, path]), "e.csv:", f"--time-unit {unit}")
    assert model_of(run([*MODEL, "--time-unit", unit, path]))["Ts"] == pytest.approx(TS)
    # A header unit is an answer too.
    path = write(tmp_path / "h.csv", f"t [{unit}],u,y",
                 rows(start + np.round(t * scale), u, y, "%.17g"))
    assert model_of(run([*MODEL, path]))["Ts"] == pytest.approx(TS)


def test_epoch_seconds_are_seconds(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "s.csv", "t,u,y", rows(1.7e9 + t, u, y, "%.12f"))
    assert model_of(run([*MODEL, path]))["Ts"] == pytest.approx(TS, rel=1e-6)


# ------------------------------------------------- flagged models, tune

@pytest.fixture(scope="module")
def flagged(tmp_path_factory, rec):
    """identify's JSON of a model flagged at_bound (the dead time held to
    0.5 s), and its exit status."""
    path = write(tmp_path_factory.mktemp("flag") / "r.csv", "t,u,y", rows(*rec))
    res = run([*MODEL, "--td-max", "0.5", path])
    assert res.returncode == 3 and json.loads(res.stdout)["flags"] == ["at_bound"]
    return path, res.stdout


def test_tune_from_refuses_a_flagged_model(flagged):
    _, text = flagged
    res = run(["tune", "--rule", "simc", "--from", "-"], stdin=text)
    assert_usage_error(res, "tune: gains refused", "(at_bound)", "--force", status=3)
    res = run(["tune", "--rule", "simc", "--from", "-", "--force"], stdin=text)
    assert res.returncode == 3
    assert json.loads(res.stdout)["rule"] == "simc"
    assert res.stderr.count("\n") == 1 and "at_bound" in res.stderr


def test_tune_from_names_every_flag(flagged):
    _, text = flagged
    out = json.loads(text)
    out["flags"] = ["unconfirmed", "at_bound", "no_relation"]
    res = run(["tune", "--rule", "imc", "--from", "-"], stdin=json.dumps(out))
    assert_usage_error(res, "(unconfirmed, at_bound, no_relation)", status=3)
    out["flags"], out["fit"] = [], -4.5
    res = run(["tune", "--rule", "imc", "--from", "-"], stdin=json.dumps(out))
    assert_usage_error(res, "negative fit", status=3)
    out["fit"] = 80.0
    assert run(["tune", "--rule", "imc", "--from", "-"], stdin=json.dumps(out)).returncode == 0


def test_tune_from_autotune_json_reads_the_flags_of_its_ident(flagged):
    _, text = flagged
    ident = json.loads(text)
    doc = {"status": "PDT_OK", "ident": ident, "tune": {"flags": []}}
    res = run(["tune", "--rule", "simc", "--from", "-"], stdin=json.dumps(doc))
    assert_usage_error(res, "(at_bound)", status=3)


def test_identify_tune_refuses_a_flagged_model(flagged):
    path, _ = flagged
    res = run([*MODEL, "--td-max", "0.5", "--tune", "simc", path])
    assert res.returncode == 3 and res.stdout == ""
    assert "identify: gains refused" in res.stderr.splitlines()[-1]
    assert "(at_bound)" in res.stderr.splitlines()[-1]
    res = run([*MODEL, "--td-max", "0.5", "--tune", "simc", "--force", path])
    assert res.returncode == 3 and "tune" in json.loads(res.stdout)
    assert_usage_error(run([*MODEL, "--force", path]), "--force goes with --tune")
    assert_usage_error(run(["tune", "--rule", "simc", "--force", "--model", "fopdt", "--K", "1",
                            "--tau", "1", "--Td", "1"]), "--force goes with --from")


def test_t_before_time_and_clock_times_beside_fs(tmp_path, rec):
    """t wins over time; a column "time" of clock times is left aside when
    --fs gives the rate (as before "time" was a default name)."""
    t, u, y = rec
    body = [[a, a, b, c] for a, b, c in (r for r in rows(t * 1e3, u, y))]
    for r, k in zip(body, range(len(body))):
        r[0] = "%.10g" % (k * TS)
    path = write(tmp_path / "tt.csv", "t,time,u,y", body)
    assert model_of(run([*MODEL, path]))["Ts"] == pytest.approx(TS, rel=1e-6)
    clock = [[f"08:{k // 600:02d}:{k // 10 % 60:02d}", b, c] for k, (_, b, c) in
             enumerate(rows(t, u, y))]
    path = write(tmp_path / "clock.csv", "Time,u,y", clock)
    check_fopdt(model_of(run([*MODEL, "--fs", "10", path])), 2.0, 5.0, 1.3)
    assert_usage_error(run([*MODEL, path]), "clock.csv:2:", "column t", "08:00:00")


def test_pipe_keeps_no_relation(tmp_path):
    """A PRBS input with an unrelated output: identify flags no_relation
    (exit 3), and tune --from refuses the gains naming it (exit 3)."""
    rng = SplitMix64.keyed(3)
    u = U0 + 5.0 * rng.signs(N, 10)
    y = Y0 + 0.5 * rng.normal(N)
    path = write(tmp_path / "noise.csv", "t,u,y", rows(np.arange(N) * TS, u, y))
    res = run([*MODEL, path])
    assert res.returncode == 3 and "no_relation" in json.loads(res.stdout)["flags"]
    tuned = run(["tune", "--rule", "simc", "--from", "-"], stdin=res.stdout)
    assert_usage_error(tuned, "gains refused", "no_relation", status=3)
    res = run([*MODEL, "--tune", "simc", path])
    assert res.returncode == 3 and res.stdout == ""
    assert "no_relation" in res.stderr.splitlines()[-1]


@pytest.mark.parametrize("extra", [[], ["--bad-value", "-9999"]])
def test_bootstrap_of_a_record_with_missing_samples(tmp_path, rec, extra):
    """The bootstrap's noise is the residual's over the samples the fit
    kept: a record with missing samples and a gross error has the
    bootstrap's std, close to the clean record's, not a failed bootstrap."""
    t, u, y = rec
    clean = write(tmp_path / "clean.csv", "t,u,y", rows(t, u, y))
    body = rows(t, u, y)
    body[150][2], body[151][2], body[400][2] = "#N/A", "", "-9999"
    path = write(tmp_path / "holes.csv", "t,u,y", body)
    args = ["identify", "--model", "fopdt", "--uncertainty", "bootstrap", "--bootstrap", "20"]
    ref = json.loads(run([*args, clean]).stdout)
    res = run([*args, *extra, path])
    assert res.returncode == 0, res.stderr
    assert "bootstrap failed" not in res.stderr
    out = json.loads(res.stdout)
    assert out["uncertainty"] == "bootstrap" and out["bootstrap_runs"] >= 18
    for p in ("K", "tau", "Td"):
        assert out["std"][p] == pytest.approx(ref["std"][p], rel=0.5)
