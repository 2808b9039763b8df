"""`pdtfit monitor` (tools/cli/cmd_monitor.c over lib/src/pdt_monitor.c).

Records come from pdtsupport.loop, a closed-loop simulator written apart
from the library (scipy's exact sampling of the plant, its own PI). The
figures of the C monitor are checked against the numpy reference
pdtref.monitor on the same records (the Harris index, the autocorrelation's
oscillation figures, the zero-crossing regularity, the reference loop's IAE
ratio, the mismatch regression), and one record of each kind must get its
verdict: the fast part of docs/reports/monitor.md's battery. A few seconds.
"""
import json

import numpy as np
import pytest

from pdtref import models, monitor
from pdtsupport import loop
from pdtsupport.cli import assert_usage_error, parse_output, run

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py

FIGURES = ("acf_scale", "forced", "std_e", "acf_min", "acf_max", "period", "oscillation", "regularity",
           "half_periods", "half_period_mean", "amplitude", "corr_ue", "harris", "iae_ratio",
           "corr_ve", "gain_ratio", "mismatch_t", "saturation")


def ref_model(plant):
    m = plant.model()
    if m["model"] == "fopdt":
        return models.Fopdt(m["K"], m["tau"], m["Td"])
    return models.Sopdt(m["K"] * m["b"], m["a"], m["b"], m["Td"])


def record(tmp_path, kind, plant_index, seed, n=2000):
    plant = loop.PLANTS[plant_index]
    rec = loop.simulate(plant, loop.scenario(kind, plant, seed, n=n), seed)
    csv = tmp_path / f"{kind}.csv"
    loop.write_csv(csv, rec)
    model = tmp_path / "model.json"
    model.write_text(json.dumps(plant.model()))
    return plant, rec, csv, model


@pytest.mark.parametrize("kind,plant_index,horizon,limits", [
    ("aggressive", 0, 0, None),
    ("stiction", 1, 0, None),
    ("saturated", 2, 0, (-1.0, 50.0 + 1.5 / 0.5)),
    ("gain_changed", 3, 800, None),
])
def test_figures_match_reference(tmp_path, kind, plant_index, horizon, limits):
    plant, rec, csv, model = record(tmp_path, kind, plant_index, 3)
    args = ["monitor", "--model", model, "--horizon", horizon, "--decimation", 1]
    if limits:
        args += ["--u-min", limits[0], "--u-max", limits[1]]
    out = parse_output(run(args + [csv]))
    ref = monitor.monitor(rec["sp"], rec["pv"], rec["u"], plant.Ts, ref_model(plant),
                          horizon=horizon, u_lim=limits)
    for key in FIGURES:
        if key not in ref:
            continue
        if key in ("acf_scale", "forced"):
            assert out[key] == ref[key], key
            continue
        if ref[key] is None:
            assert out[key] is None, key
            continue
        assert out[key] == pytest.approx(ref[key], rel=2e-3, abs=2e-3), key


@pytest.mark.parametrize("kind", loop.KINDS)
def test_verdict_of_each_kind(tmp_path, kind):
    """One record per kind on the two-lag plant, 4000 samples, seed 0."""
    _, _, csv, model = record(tmp_path, kind, 1, 0, n=4000)
    out = parse_output(run(["monitor", "--model", model, csv]))
    assert out["verdict"] == loop.EXPECTED[kind], out
    if kind == "stiction":
        assert out["cause"] == "stiction"
    if kind == "aggressive":
        assert out["cause"] == "tuning"


def test_without_model_identifies_one(tmp_path):
    _, _, csv, _ = record(tmp_path, "aggressive", 1, 0, n=4000)
    out = parse_output(run(["monitor", csv]))
    assert out["model"] == "identified" and out["verdict"] == "oscillating"
    assert out["process"]["model"] == "fopdt" and out["harris"] is not None


def test_short_record_is_not_enough_data(tmp_path):
    _, _, csv, model = record(tmp_path, "well", 0, 0, n=200)
    out = parse_output(run(["monitor", "--model", model, csv]))
    assert out["verdict"] == "not_enough_data"


def test_usage_errors(tmp_path):
    _, rec, csv, model = record(tmp_path, "well", 0, 0, n=100)
    assert_usage_error(run(["monitor", "--u-min", 0, csv]), "--u-min and --u-max go together")
    assert_usage_error(run(["monitor", "--u-min", 2, "--u-max", 1, csv]), "below --u-max")
    assert_usage_error(run(["monitor"]), "missing FILE")
    assert_usage_error(run(["monitor", "--model", tmp_path / "none.json", csv]), "cannot read")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,sp,pv\n" + "\n".join(f"{k},1,2" for k in range(50)) + "\n")
    assert_usage_error(run(["monitor", bad]), "u")
    lines = csv.read_text().splitlines()
    lines[30] = ",".join(lines[30].split(",")[:2] + ["nan"] + lines[30].split(",")[3:])
    nan = tmp_path / "nan.csv"
    nan.write_text("\n".join(lines) + "\n")
    res = run(["monitor", "--model", model, nan])
    assert res.returncode == 2 and res.stdout == ""
    assert np.isfinite(rec["pv"]).all()
