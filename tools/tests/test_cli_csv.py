"""The reader of `pdtfit identify` on files shaped like real exports: PLC and
logger CSVs with other column names, semicolons and decimal commas, tabs,
units, preambles, ISO or epoch timestamps, jitter, dropped and repeated
rows, and the program's own autotune-sim trace. Each gives the right model
with the options for it, or a refusal that names the cause and the line.

The record is test_cli's FOPDT (K = 2, tau = 5 s, Td = 1.3 s at 10 Hz)."""
import datetime
import json

import numpy as np
import pytest

from pdtsupport.cli import FOPDT_KEYS, assert_usage_error, run
from pdtsupport.plant import simulate
from pdtsupport.records import N, TS, U0, Y0, check_fopdt, multistep_input, noise
from pdtsupport.rng import SplitMix64

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py

MODEL = ["identify", "--model", "fopdt"]


@pytest.fixture(scope="module")
def rec():
    u = multistep_input(N, U0, 5.0, 25, 60, 20, seed=7)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.3, u - U0, TS) + noise(N, 0.02, 11)
    return np.arange(N) * TS, u, y


def write(path, header, rows, sep=",", newline="\n"):
    path.write_text(newline.join([header] + [sep.join(r) for r in rows]) + newline)
    return path


def cells(*cols, fmt="%.10g", decimal="."):
    out = []
    for vals in zip(*cols):
        row = [v if isinstance(v, str) else fmt % v for v in vals]
        out.append([c.replace(".", decimal) for c in row] if decimal != "." else row)
    return out


def ok(res, warn=None):
    """The JSON of a run that printed a model; stderr empty, or exactly one
    warning holding `warn`."""
    assert res.returncode == 0, res.stderr
    if warn is None:
        assert res.stderr == ""
    else:
        lines = res.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("pdtfit: warning: "), res.stderr
        assert warn in lines[0], lines[0]
    return json.loads(res.stdout)


def fopdt(out, Ts=TS, scale=1.0):
    """The model of the record with its time axis stretched by `scale`."""
    assert list(out) == FOPDT_KEYS
    assert out["Ts"] == pytest.approx(Ts, rel=1e-6)
    assert out["n"] == N or out["n"] > N - 3
    assert out["K"] == pytest.approx(2.0, rel=0.02)
    assert out["tau"] == pytest.approx(5.0 * scale, rel=0.02)
    assert out["Td"] == pytest.approx(1.3 * scale, abs=0.05 * scale)
    assert out["fit"] > 95


# ---------------------------------------------------------------- columns

def test_timestamp_cv_pv(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "plc.csv", "timestamp,CV,PV", cells(t, u, y))
    res = run([*MODEL, path])
    assert_usage_error(res, "plc.csv:1:", "no column named u", "columns found",
                       '1 "timestamp"', '2 "CV"', '3 "PV"', "--u")
    fopdt(ok(run([*MODEL, "--t", "timestamp", "--u", "cv", path])))


def test_columns_by_index(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "idx.csv", "a,b,c,d", cells(y, t, np.zeros(N), u))
    fopdt(ok(run([*MODEL, "--t", "2", "--u", "4", "--y", "1", path])))
    assert_usage_error(run([*MODEL, "--t", "2", "--u", "9", "--y", "1", path]),
                       "--u 9: no such column", "columns found")
    assert_usage_error(run([*MODEL, "--t", "2", "--u", "2", "--y", "1", path]),
                       "same column")
    # A name chosen with an option takes the first match; a default one
    # that matches twice is refused.
    path = write(tmp_path / "twice.csv", "y,t,u,U [%]", cells(y, t, u, np.zeros(N)))
    fopdt(ok(run([*MODEL, "--u", "u", path])))
    assert_usage_error(run([*MODEL, path]), "column u appears twice", "--u")


def test_units_in_the_header(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "units.csv", "t [s],u [%],y [degC]", cells(t, u, y))
    fopdt(ok(run([*MODEL, path])))
    path = write(tmp_path / "units2.csv", "Time (s), Valve [%] ,TT101 [degC]", cells(t, u, y))
    fopdt(ok(run([*MODEL, "--t", "time", "--u", "valve", "--y", "tt101", path])))


# ------------------------------------------------------------- separators

def test_semicolon_decimal_comma(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "eu.csv", "t;u;y", cells(t, u, y, decimal=","), sep=";")
    fopdt(ok(run([*MODEL, path])))
    fopdt(ok(run([*MODEL, "--sep", ";", "--decimal", ",", path])))


def test_tab_separated(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "tab.tsv", "t\tu\ty", cells(t, u, y), sep="\t")
    fopdt(ok(run([*MODEL, path])))
    fopdt(ok(run([*MODEL, "--sep", "tab", path])))


def test_comma_separator_with_decimal_comma_refused_cleanly(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "bad.csv", "t,u,y", cells(t, u, y, decimal=","))
    res = run([*MODEL, path])
    assert_usage_error(res, "bad.csv:2:", "fields, but the header has 3")


# ------------------------------------------------------ preamble, comments

def test_hash_preamble_and_comments(tmp_path, rec):
    t, u, y = rec
    rows = cells(t, u, y)
    rows.insert(300, ["# operator note: valve checked"])
    path = write(tmp_path / "pre.csv", "# logged by XY-100 on 2024-03-01\n# site 4\nt,u,y", rows)
    fopdt(ok(run([*MODEL, path])))


def test_text_preamble_with_skip(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "pre2.csv", "Logger XY-100\nExport 2024-03-01\nt,u,y", cells(t, u, y))
    assert_usage_error(run([*MODEL, path]), "pre2.csv:1:", "no column named u",
                       "Logger XY-100")
    fopdt(ok(run([*MODEL, "--skip", "2", path])))


# ------------------------------------------------------------------- time

def iso(t, start=datetime.datetime(2024, 3, 1, 8, 0, 0), sep="T", suffix=""):
    return [(start + datetime.timedelta(seconds=float(v))).isoformat(sep, "milliseconds")
            + suffix for v in t]


def test_iso_timestamps(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "iso.csv", "time,u,y", cells(iso(t), u, y))
    fopdt(ok(run([*MODEL, "--t", "time", path])))
    path = write(tmp_path / "iso2.csv", "t,u,y", cells(iso(t, sep=" ", suffix="+01:00"), u, y))
    fopdt(ok(run([*MODEL, path])))
    bad = cells(iso(t), u, y)
    bad[7][0] = "2024-03-01T08:00:0x.700"
    path = write(tmp_path / "iso3.csv", "t,u,y", bad)
    assert_usage_error(run([*MODEL, path]), "iso3.csv:9:", "column t", "ISO 8601")


def test_epoch_milliseconds(tmp_path, rec):
    t, u, y = rec
    ms = 1.7e12 + np.round(t * 1000.0)
    path = write(tmp_path / "epoch.csv", "t,u,y", cells(ms, u, y, fmt="%.15g"))
    # Taken as seconds the record would be 1000 times slower: refused.
    assert_usage_error(run([*MODEL, path]), "epoch milliseconds", "--time-unit ms")
    out = ok(run([*MODEL, "--time-unit", "s", path]))
    assert out["Ts"] == pytest.approx(100.0)
    fopdt(ok(run([*MODEL, "--time-unit", "ms", path])))
    us = 1.7e15 + np.round(t * 1e6)
    path = write(tmp_path / "epoch_us.csv", "t,u,y", cells(us, u, y, fmt="%.17g"))
    fopdt(ok(run([*MODEL, "--time-unit", "US", path])))


def test_jitter_30ms_at_1s(tmp_path, rec):
    _, u, y = rec
    t = np.arange(N) * 1.0 + SplitMix64.keyed(5).uniform(N, lo=-0.03, hi=0.03)
    path = write(tmp_path / "jit.csv", "t,u,y", cells(t, u, y))
    out = ok(run([*MODEL, path]), warn="median")
    fopdt(out, Ts=out["Ts"], scale=1.0 / TS)
    assert out["Ts"] == pytest.approx(1.0, abs=0.01)
    out = ok(run([*MODEL, "--fs", "1", path]), warn="median")
    fopdt(out, Ts=1.0, scale=1.0 / TS)


def test_jitter_beyond_tolerance_refused(tmp_path, rec):
    t, u, y = rec
    t = t.copy()
    t[100] += 0.04  # 40 % of Ts
    path = write(tmp_path / "jit2.csv", "t,u,y", cells(t, u, y))
    assert_usage_error(run([*MODEL, path]), "jit2.csv:102:", "not uniformly sampled",
                       "tolerance 25%")


# ------------------------------------------------ gaps, duplicates, steps

def test_dropped_row(tmp_path, rec):
    t, u, y = rec
    keep = np.arange(N) != 200
    path = write(tmp_path / "drop.csv", "t,u,y", cells(t[keep], u[keep], y[keep]))
    # Row 200 (t = 20.0) is missing: the row after it (t = 20.1) is on
    # line 202, after the header and rows 0 .. 199.
    assert_usage_error(run([*MODEL, path]), "drop.csv:202:", "gap of 0.2 s",
                       "after line 201", "1 row missing", "--resample")
    out = ok(run([*MODEL, "--resample", path]), warn="filled 1 row")
    assert out["n"] == N
    fopdt(out)


def test_gap_of_several_rows(tmp_path, rec):
    t, u, y = rec
    keep = (np.arange(N) < 300) | (np.arange(N) > 304)
    path = write(tmp_path / "gap.csv", "t,u,y", cells(t[keep], u[keep], y[keep]))
    assert_usage_error(run([*MODEL, path]), "gap.csv:302:", "5 rows missing")
    out = ok(run([*MODEL, "--resample", path]), warn="filled 5 rows")
    assert out["n"] == N


def test_duplicate_row(tmp_path, rec):
    t, u, y = rec
    rows = cells(t, u, y)
    rows.insert(151, rows[150])
    path = write(tmp_path / "dup.csv", "t,u,y", rows)
    assert_usage_error(run([*MODEL, path]), "dup.csv:153:", "does not increase",
                       "duplicate", "line 152")
    fopdt(ok(run([*MODEL, "--resample", path])))


def test_step_back(tmp_path, rec):
    t, u, y = rec
    rows = cells(t, u, y)
    rows[400], rows[401] = rows[401], rows[400]
    path = write(tmp_path / "back.csv", "t,u,y", rows)
    assert_usage_error(run([*MODEL, path]), "back.csv:403:", "steps back", "line 402")
    assert_usage_error(run([*MODEL, "--resample", path]), "back.csv:403:", "steps back")


# ------------------------------------------------------ the program's own

def test_reads_autotune_trace(tmp_path):
    trace = tmp_path / "trace.csv"
    res = run(["autotune-sim", "--plant-gain", "2", "--plant-lags", "5", "--plant-delay", "1.3",
               "--trace", trace])
    assert res.returncode == 0, res.stderr
    out = ok(run([*MODEL, trace]))
    assert out["K"] == pytest.approx(2.0, rel=0.02)
    assert out["tau"] == pytest.approx(5.0, rel=0.03)
    assert out["Td"] == pytest.approx(1.3, abs=0.1)
    assert out["Ts"] == pytest.approx(json.loads(res.stdout)["scan_period"], rel=1e-6)


def test_check_fopdt_shape(tmp_path, rec):
    """The JSON of a plain file keeps identify's keys and values."""
    t, u, y = rec
    path = write(tmp_path / "plain.csv", "t,u,y", cells(t, u, y))
    check_fopdt(ok(run([*MODEL, path])), 2.0, 5.0, 1.3)


# ------------------------------------------- names, units rows, date forms

@pytest.mark.parametrize("header, args", [
    ("t,CV [%],PV [degC]", ["--u", "CV [%]", "--y", "PV [degC]"]),
    ("t,CV [%],PV [degC]", ["--u", "cv", "--y", "pv"]),
    ("t,CV,PV", ["--u", "CV [%]", "--y", "PV (degC)"]),
    ("t,CV / %,PV/degC", ["--u", "cv[%]", "--y", "PV"]),
    ('t,"CV  (%)",PV {degC}', ["--u", "CV", "--y", "pv [degC]"]),
])
def test_names_with_or_without_units(tmp_path, rec, header, args):
    t, u, y = rec
    path = write(tmp_path / "names.csv", header, cells(t, u, y))
    fopdt(ok(run([*MODEL, *args, path])))


def test_unit_decides_between_two_columns(tmp_path, rec):
    t, u, y = rec
    path = write(tmp_path / "two.csv", "time,u,Temp [degC],Temp [K]",
                 cells(t, u, y - 273.15, y))
    out = ok(run([*MODEL, "--t", "time", "--y", "temp [K]", path]))
    assert out["y0"] == pytest.approx(Y0, abs=0.1)
    assert_usage_error(run([*MODEL, "--t", "time", "--y", "Temp", path]), "appears twice")


def test_units_row(tmp_path, rec):
    t, u, y = rec
    rows = [["s", "%", "degC"]] + cells(t, u, y, decimal=",")
    path = write(tmp_path / "units.tsv", "Time\tCV\tPV", rows, sep="\t")
    fopdt(ok(run([*MODEL, "--t", "time", "--u", "cv", "--units-row", path])))
    fopdt(ok(run([*MODEL, "--t", "time", "--u", "cv", path]),
             warn="units.tsv:2: a row of units under the header, skipped"))
    # Asked for, the row is skipped whatever it holds.
    rows[0] = ["0", "0", "0"]
    path = write(tmp_path / "units2.tsv", "Time\tCV\tPV", rows, sep="\t")
    fopdt(ok(run([*MODEL, "--t", "time", "--u", "cv", "--units-row", path])))


def clock(t, fmt, start=datetime.datetime(2024, 3, 1, 8, 0, 0)):
    return [(start + datetime.timedelta(seconds=float(v))).strftime(fmt) for v in t]


def test_plc_date_with_decimal_comma(tmp_path, rec):
    t, u, y = rec
    stamps = [s[:-3] for s in clock(t, "%d.%m.%Y %H:%M:%S,%f")]  # milliseconds
    rows = [[st, *r] for st, r in zip(stamps, cells(u, y, decimal=","))]
    path = write(tmp_path / "plc.csv", "Zeit;CV;PV", rows, sep=";")
    fopdt(ok(run([*MODEL, "--t", "zeit", "--u", "cv", path])))


def test_spreadsheet_date_am_pm(tmp_path, rec):
    t, u, y = rec
    t = t * 20  # 2 s steps across noon
    stamps = [s.lstrip("0").replace("/0", "/") for s in
              clock(t, "%m/%d/%Y %I:%M:%S %p", datetime.datetime(2024, 3, 1, 11, 50, 0))]
    assert stamps[0] == "3/1/2024 11:50:00 AM" and "3/1/2024 12:00:00 PM" in stamps
    path = write(tmp_path / "xl.csv", "Time,u,y", cells(stamps, u, y))
    fopdt(ok(run([*MODEL, "--t", "time", path])), Ts=2.0, scale=20.0)


def test_time_format(tmp_path, rec):
    t, u, y = rec
    stamps = [s[:-4] for s in clock(t, "%Y%m%d-%H%M%S.%f")]  # 1/100 s
    path = write(tmp_path / "f.csv", "t,u,y", cells(stamps, u, y))
    fopdt(ok(run([*MODEL, "--time-format", "%Y%m%d-%H%M%S.%f", path])))
    assert_usage_error(run([*MODEL, "--time-format", "%d.%m.%Y %H:%M:%S", path]), "f.csv:2:",
                       "does not match the time format")


def test_slash_date_without_am_pm_asks_for_the_format(tmp_path, rec):
    t, u, y = rec
    stamps = clock(t * 10, "%d/%m/%Y %H:%M:%S", datetime.datetime(2024, 3, 13, 23, 59, 0))
    path = write(tmp_path / "dm.csv", "t,u,y", cells(stamps, u, y))
    assert_usage_error(run([*MODEL, path]), "dm.csv:2:", "--time-format")
    fopdt(ok(run([*MODEL, "--time-format", "%d/%m/%Y %H:%M:%S", path])), Ts=1.0, scale=10.0)


def test_header_unit_units_row_and_markers_together(tmp_path, rec):
    """The header's time unit (after a slash too), a units row found, a
    missing-value marker and names given without their units, in one
    file: the model, the marker left out, the unit row reported."""
    t, u, y = rec
    rows = [["ms", "%", "degC"]] + cells(t * 1000.0, u, y, decimal=",")
    rows[41][2] = "#N/A"
    path = write(tmp_path / "all.csv", "Time / ms;CV [%];PV {degC}", rows, sep=";")
    res = run([*MODEL, "--u", "cv", "--y", "PV [degC]", path])
    assert res.returncode == 0, res.stderr
    assert "all.csv:2: a row of units under the header, skipped" in res.stderr
    out = json.loads(res.stdout)
    assert out["Ts"] == pytest.approx(TS, rel=1e-6)
    assert out["missing"] == {"count": 1, "first": [40], "u_held": 0}
    assert out["K"] == pytest.approx(2.0, rel=0.02)
    # A slash in a name is no unit unless it names one: "Date/Time" is a name.
    path = write(tmp_path / "dt.csv", "Date/Time,u,y", cells(t, u, y))
    fopdt(ok(run([*MODEL, "--t", "date/time", path])))


def test_plc_dates_with_epoch_check_and_units_row(tmp_path, rec):
    """Date-times are no counts: the epoch check leaves them alone, and a
    units row under a PLC export's header is found."""
    t, u, y = rec
    stamps = [s[:-3] for s in clock(t, "%d.%m.%Y %H:%M:%S,%f")]
    rows = [["", "%", "degC"]] + [[st, *r] for st, r in zip(stamps, cells(u, y, decimal=","))]
    path = write(tmp_path / "plc.csv", "Zeit;CV;PV", rows, sep=";")
    fopdt(ok(run([*MODEL, "--t", "zeit", "--u", "cv", path]),
             warn="plc.csv:2: a row of units under the header, skipped"))
