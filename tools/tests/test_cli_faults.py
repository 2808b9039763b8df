"""autotune-sim's faults (tools/sim/loop_sim.c), each against its closed form.

Every run writes a trace with the faults' columns (t,u,pv,u_valve,load,y):
the quantiser's output is the nearest multiple of Q, the drift a ramp of
slope R on pv, the rate limit a ramp of R per second that reaches a step of
A after A / (R Ts) scans, the backlash a valve that stays until the command
has moved more than S and then follows it at S, and a load step on a FOPDT
the exact response of that plant to the valve position plus the load. The
whole file runs in about a second.
"""
import math

import numpy as np
import pytest

from pdtsupport.cli import assert_usage_error, parse_output, run

pytestmark = pytest.mark.cli

FOPDT = ["--plant-gain", "2", "--plant-lags", "5", "--plant-delay", "1.3", "--scan-period", "0.05"]


def trace_of(tmp_path, *args):
    trace = tmp_path / "trace.csv"
    res = run(["autotune-sim", *FOPDT, *args, "--trace", trace])
    assert res.returncode in (0, 1), res.stderr
    assert trace.read_text().startswith("t,u,pv,u_valve,load,y\n")
    return res, np.loadtxt(trace, delimiter=",", skiprows=1).T


def test_quantiser_rounds_to_the_nearest_step(tmp_path):
    q = 0.07
    _, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "step", "--quantise", q)
    assert np.allclose(pv / q, np.round(pv / q), atol=1e-6)
    assert np.all(np.abs(pv - y) <= q / 2 + 1e-9)
    assert np.allclose(pv, q * np.floor(y / q + 0.5), atol=1e-9)
    assert np.array_equal(u, uv) and not load.any()


def test_drift_is_a_ramp_on_pv(tmp_path):
    r = 0.013
    res, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "step", "--drift", r)
    assert np.allclose(pv - y, r * t, atol=1e-7)
    out = parse_output(res) if res.returncode == 0 else None
    if out:
        assert out["faults"]["drift"] == pytest.approx(r)


@pytest.mark.parametrize("amp,rate", [(1.0, 2.0), (-3.0, 0.7)])
def test_rate_limited_ramp(tmp_path, amp, rate):
    Ts = 0.05
    _, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "step", "--amplitude", amp,
                                          "--u-rate", rate)
    k0 = int(np.argmax(u != u[0]))          # the step's first scan
    scans = math.ceil(abs(amp) / (rate * Ts) - 1e-9)
    ramp = uv[k0:k0 + scans + 3] - u[0]
    expect = np.sign(amp) * np.minimum(rate * Ts * np.arange(1, scans + 4), abs(amp))
    assert np.allclose(ramp, expect, atol=1e-6)
    assert abs(uv[k0 + scans - 2] - u[k0]) > 1e-6 and uv[k0 + scans - 1] == pytest.approx(u[k0])
    assert np.max(np.abs(np.diff(uv))) <= rate * Ts * (1 + 1e-6)


def test_backlash_stiction(tmp_path):
    s = 0.3
    # A step larger than the band: the valve moves to the command less S.
    _, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "step", "--amplitude", "1",
                                          "--stiction", s)
    k0 = int(np.argmax(u != u[0]))
    k1 = k0 + int(np.argmax(u[k0:] != u[k0]))  # back at the operating point
    assert np.allclose(uv[:k0], u[0]) and np.allclose(uv[k0:k1], u[k0] - s)
    assert np.allclose(uv[k1:], u[0] + s)  # it stays S short on the way back
    # A PRBS of half swing below S/2 never moves the valve.
    _, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "prbs", "--amplitude", "0.14",
                                          "--stiction", s, "--capacity", "300")
    assert np.ptp(u) > 0.2 and np.ptp(uv) == 0.0 and np.ptp(y) == 0.0
    # A PRBS of swing 2 A > S: the valve follows each reversal at S.
    _, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "prbs", "--amplitude", "0.5",
                                          "--stiction", s, "--capacity", "300")
    rev = np.nonzero(np.abs(np.diff(u)) > 0.99)[0] + 1
    assert len(rev) >= 3 and np.allclose(np.abs(u - uv)[rev], s)
    assert np.all(np.abs(u - uv) <= s + 1e-9)


def test_load_step_response_of_a_fopdt(tmp_path):
    K, T, L, Ts, d, tl = 2.0, 5.0, 1.3, 0.05, 0.4, 30.0
    res, (t, u, pv, uv, load, y) = trace_of(tmp_path, "--experiment", "step", "--load-step",
                                            f"{tl}:{d}")
    assert np.array_equal(load, np.where(t >= tl - 1e-9, d, 0.0))
    # Superposed exact responses of the held inputs (the input u_valve + load).
    w = uv + load
    yy = np.zeros_like(t)
    for k in np.nonzero(np.diff(np.concatenate(([w[0]], w))))[0]:
        dt = t - t[k] - L
        yy += K * (w[k] - w[k - 1]) * np.where(dt > 0, 1 - np.exp(-np.maximum(dt, 0) / T), 0)
    assert np.max(np.abs(y - y[0] - yy)) < 1e-6
    out = parse_output(res) if res.returncode == 0 else None
    if out:
        assert out["faults"]["load_step"] == {"t": pytest.approx(tl), "d": pytest.approx(d)}


def test_faults_combine(tmp_path):
    _, (t, u, pv, uv, load, y) = trace_of(
        tmp_path, "--experiment", "step", "--load-step", "20:0.2", "--drift", "0.01",
        "--quantise", "0.05", "--u-rate", "1", "--stiction", "0.1", "--noise", "0")
    assert np.allclose(pv, 0.05 * np.floor((y + 0.01 * t) / 0.05 + 0.5), atol=1e-9)
    assert np.max(np.abs(np.diff(uv))) <= 0.05 + 1e-9
    assert load[-1] == 0.2 and np.max(np.abs(u - uv)[-10:]) == pytest.approx(0.1)


def test_no_fault_keeps_the_three_columns(tmp_path):
    trace = tmp_path / "trace.csv"
    run(["autotune-sim", *FOPDT, "--trace", trace])
    assert trace.read_text().startswith("t,u,pv\n")


@pytest.mark.parametrize("args,frag", [
    (["--load-step", "5"], "--load-step"),
    (["--load-step", "-1:2"], "--load-step"),
    (["--load-step", "x:2"], "--load-step"),
    (["--load-step", "3:nan"], "--load-step"),
    (["--quantise", "0"], "--quantise"),
    (["--u-rate", "-1"], "--u-rate"),
    (["--stiction", "0"], "--stiction"),
    (["--drift", "inf"], "--drift"),
])
def test_fault_usage_errors(args, frag):
    assert_usage_error(run(["autotune-sim", *FOPDT, *args]), frag)


@pytest.mark.parametrize("kc", ["0.1", "0.8"])
def test_closed_loop_retune(kc):
    out = parse_output(run(["autotune-sim", *FOPDT, "--closed-loop", "--initial-gains",
                            f"{kc},5", "--experiment", "step", "--noise", "0.01"]))
    cl = out["closed_loop"]
    assert out["status"] == "PDT_OK" and cl["gains"] == "new"
    assert cl["initial"] == {"Kc": pytest.approx(float(kc)), "Ti": 5, "Td": 0}
    assert out["ident"]["K"] == pytest.approx(2.0, rel=0.05)
    assert out["loop"]["Ms_true"] < 2.0 and out["loop"]["stable"]
    # Bumpless: the hand-over moves the output less than the loop's own
    # largest move in a scan.
    assert cl["handover_du"] < 0.2 * cl["du_max"]


def test_load_step_is_repeated_or_refused():
    res = run(["autotune-sim", *FOPDT, "--experiment", "prbs", "--noise", "0.02",
               "--load-step", "150:0.3"])
    out = parse_output(res) if res.returncode == 0 else None
    if out is None:
        import json
        out = json.loads(res.stdout)
        assert out["status"] in ("PDT_ERR_DISTURBED", "PDT_ERR_UNCERTAIN")
    else:
        assert out["repeats"] == 1 and out["shift"] <= 0.08


@pytest.mark.parametrize("args,frag", [
    (["--closed-loop"], "--initial-gains"),
    (["--initial-gains", "1,2"], "--closed-loop"),
    (["--closed-loop", "--initial-gains", "1"], "--initial-gains"),
    (["--closed-loop", "--initial-gains", "1,0"], "--initial-gains"),
    (["--closed-loop", "--initial-gains", "1,2", "--experiment", "relay"], "set-point"),
])
def test_closed_loop_usage_errors(args, frag):
    assert_usage_error(run(["autotune-sim", *FOPDT, *args]), frag)


def test_actuator_position_restores_the_gain():
    base = [*FOPDT, "--experiment", "step", "--noise", "0.02", "--model", "fopdt",
            "--stiction", "0.05"]
    cmd = parse_output(run(["autotune-sim", *base]))
    pos = parse_output(run(["autotune-sim", *base, "--actuator-position"]))
    assert abs(pos["ident"]["K"] - 2.0) < 0.01 < abs(cmd["ident"]["K"] - 2.0)
    assert pos["ident"]["Td"] == pytest.approx(1.3, abs=0.03)
