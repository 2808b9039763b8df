"""Several records of one process, one model (docs/several-records.md):
pdtfit.identify_many and `pdtfit identify FILE FILE ...` against an
independent joint output-error fit (pdtbench.joint_fit: scipy's
least_squares over the shared dynamics with each record's own offset),
on FOPDT and SOPDT plants at several noise seeds, records at different
periods and operating points, and the real gas-furnace record cut into
two segments. Target: the joint optimum within 1 % in every printed
parameter (K, tau, Td; K, tau1, tau2, Td)."""
import json
import math
import pathlib

import numpy as np
import pytest

import pdtfit
from pdtbench import joint_fit
from pdtsupport import cli

cli_test = pytest.mark.cli
ROOT = pathlib.Path(__file__).resolve().parents[2]
GAS = ROOT / "tests" / "data" / "real" / "gas_furnace.csv"


PLANTS = joint_fit.PLANTS
SEEDS = (1, 2)


def relative_differences(r, kind, records, initial="rest"):
    """pdtfit's answer against the reference's: (worst, name), offsets."""
    worst, offsets, ratio = joint_fit.compare(kind, records, joint_fit.model_of(r), initial)
    # Never worse than the reference beyond rounding: it is the optimum.
    assert ratio <= 1 + 1e-4
    return worst, offsets


@pytest.mark.parametrize("name", sorted(PLANTS))
@pytest.mark.parametrize("seed", SEEDS)
def test_joint_optimum(name, seed):
    kind, records = joint_fit.plant_records(name, seed)
    r = pdtfit.identify_many(records, model=kind, seed=seed)
    assert r.records == len(records) and r.samples == sum(len(u) for u, _, _ in records)
    assert len(r.record_fit) == len(records)
    (worst, which), offsets = relative_differences(r, kind, records)
    print(f"{name} seed {seed}: worst relative difference {worst:.2e} ({which})")
    assert worst <= 0.01, (which, worst)
    for f, (u, y, fs), off in zip(r.record_fit, records, offsets):
        assert f["n"] == len(u) and math.isclose(f["Ts"], 1.0 / fs, rel_tol=1e-6)
        assert math.isclose(f["u0"], u[0], rel_tol=1e-6)
        assert math.isclose(f["y0"], off, rel_tol=1e-3, abs_tol=1e-3 * np.ptp(y))


def test_state_estimated():
    """Each record's own state at its first sample: a record cut mid-transient."""
    num, den, Td = [1.8], [30.0, 1.0], 12.0
    a = joint_fit.make_record(num, den, Td, 400, 1.0, 40.0, 300.0, 5.0, 0.05, 3)
    b = joint_fit.make_record(num, den, Td, 460, 1.0, 50.0, 310.0, 6.0, 0.05, 4)
    b = (b[0][60:], b[1][60:], b[2])
    r = pdtfit.identify_many([a, b], initial="estimate")
    (worst, which), _ = relative_differences(r, "fopdt", [a, b], "estimate")
    assert worst <= 0.01, (which, worst)
    assert r.initial == "estimate"


def gas_segments():
    data = np.loadtxt(GAS, delimiter=",", skiprows=1)
    u, y = data[:, 0], data[:, 1]
    return [(u[:150], y[:150], 1.0 / 9.0), (u[150:], y[150:], 1.0 / 9.0)]


@pytest.mark.parametrize("kind", ["fopdt", "sopdt"])
def test_real_record_in_two_segments(kind):
    segs = gas_segments()
    r = pdtfit.identify_many(segs, model=kind)
    (worst, which), _ = relative_differences(r, kind, segs)
    print(f"gas furnace {kind}, two segments: worst relative difference {worst:.2e} ({which})")
    assert worst <= 0.01, (which, worst)


@cli_test
def test_program_equals_the_binding(tmp_path):
    """The program on two CSV files gives the binding's JSON, and the
    files' names."""
    paths = []
    for i, (u, y, fs) in enumerate(gas_segments()):
        p = tmp_path / f"seg{i}.csv"
        cli.write_csv(p, {"u": u, "y": y}, fmt="%.17g")
        paths.append(p)
    res = cli.run(["identify", "--model", "fopdt", "--fs", repr(1.0 / 9.0)] + paths)
    got = cli.parse_output(res)
    want = pdtfit.identify_many(gas_segments()).as_dict()
    for f, p in zip(got["record_fit"], paths):
        assert f.pop("file") == str(p)
    assert got == want


@cli_test
@pytest.mark.parametrize("opt,fragment", [
    (["--cost", "combined"], "--cost simulation"),
    (["--initial", "auto"], "--initial auto"),
    (["--u-before", "0"], "--u-before"),
    (["--model", "auto"], "--model auto"),
    (["--out-sim", "x.csv"], "--out-sim"),
    (["--coarse", "4"], "--coarse"),
    (["--integer-delay"], "--integer-delay"),
    (["--offset", "rest"], "--offset rest"),
    (["--method", "elms"], "--method"),
])
def test_program_refusals(tmp_path, opt, fragment):
    paths = []
    for i, (u, y, fs) in enumerate(gas_segments()):
        p = tmp_path / f"seg{i}.csv"
        cli.write_csv(p, {"u": u, "y": y})
        paths.append(p)
    args = ["identify", "--fs", "0.1"] + (["--model", "fopdt"] if "--model" not in opt else [])
    res = cli.run(args + opt + paths)
    cli.assert_usage_error(res, "several records", fragment)


def test_binding_refusals():
    segs = gas_segments()
    for kw in (dict(cost="frequency"), dict(initial="auto"), dict(u_before=0.0),
               dict(model="auto"), dict(coarse=4), dict(integer_delay=True),
               dict(offset="rest"), dict(uncertainty="bootstrap"), dict(missing="exclude"),
               dict(weight="uniform")):
        with pytest.raises(ValueError, match="not with several records"):
            pdtfit.identify_many(segs, **kw)
    with pytest.raises(ValueError, match="2 .. 8"):
        pdtfit.identify_many(segs[:1])
    u, y, fs = segs[1]
    y = y.copy()
    y[7] = math.nan
    with pytest.raises(ValueError, match=r"records\[1\] y\[7\]"):
        pdtfit.identify_many([segs[0], (u, y, fs)])
    with pytest.raises(pdtfit.PdtError):
        pdtfit.identify_many([segs[0], (np.full(146, 1.0), segs[1][1], fs)])


def test_joint_json_keys():
    r = pdtfit.identify_many(gas_segments(), tune="simc:pi")
    d = r.as_dict()
    assert d["std"] is None and d["uncertainty"] is None
    assert d["records"] == 2 and d["samples"] == 296
    assert set(d["record_fit"][0]) == {"n", "Ts", "u0", "y0", "fit", "cost", "x0", "dx0",
                                       "drift"}
    assert "Kc" in d["tune"]
    json.dumps(d)
