"""Checks of the benchmark's own instruments (tools/bench/): the fast
reference fit's exact discretisation against pdtref, its fit on a clean
record, the certainty driver's plant simulation against pdtref, and the
battery's verdict.

The driver comes from $PDT_CERTAINTY_BIN, else from the newest
build/*/tools/bench/pdt_certainty of the checkout; without either its tests
are skipped.
"""
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

BENCH = pathlib.Path(__file__).resolve().parents[1]

from pdtbench import benchlib as bl
from pdtbench import certainty
from pdtbench import fastref
from pdtbench.benchlib import models


def driver():
    env = os.environ.get("PDT_CERTAINTY_BIN")
    if env:
        return pathlib.Path(env)
    found = sorted(BENCH.parents[1].glob("build/*/tools/bench/pdt_certainty"),
                   key=lambda p: p.stat().st_mtime)
    if not found:
        pytest.skip("no pdt_certainty built")
    return found[-1]


def input_signal():
    return np.concatenate([np.zeros(20), bl.Rng.keyed(3).signs(450, 3)])


@pytest.mark.parametrize("tau", [0.03, 0.5, 3.0, 200.0])
@pytest.mark.parametrize("Td", [0.0, 0.1, 0.234, 1.0, 2.999999999])
def test_fopdt_filter_is_exact(tau, Td):
    du, Ts = input_signal(), 0.1
    y = fastref.shifted_filter(*fastref.fopdt_filter(tau, Td, Ts), du)
    ref = bl.simulate(models.Fopdt(1.0, tau, Td), Ts, du)
    assert np.max(np.abs(y - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.mark.parametrize("a", [0.02, 0.5, 3.0, 60.0])
@pytest.mark.parametrize("rz", [0.0, 1e-5, 0.3, 0.999999, 1.0, 1.000001, 2.0, 5.0])
@pytest.mark.parametrize("Td", [0.0, 0.234, 1.05])
def test_sopdt_filter_is_exact(a, rz, Td):
    """Over-, critically and underdamped pairs and the integrator (rz = 0)."""
    du, Ts = input_signal(), 0.1
    b = (0.5 * a * rz) ** 2
    y = fastref.shifted_filter(*fastref.sopdt_filter(a, rz, Td, Ts), du)
    ref = bl.simulate(models.Sopdt(1.0, a, b, Td), Ts, du)
    assert np.max(np.abs(y - ref)) <= 1e-8 * np.max(np.abs(ref))


@pytest.mark.parametrize("kind", ["fopdt", "sopdt"])
def test_fit_recovers_a_clean_record(kind):
    Ts = 0.1
    du = input_signal()
    m = models.Fopdt(2.0, 3.0, 1.23) if kind == "fopdt" else \
        models.sopdt_from_natural(-1.5, 0.8, 0.6, 1.23)
    u = 40.0 + 10.0 * du
    y = 350.0 + bl.simulate(m, Ts, 10.0 * du)
    ref = fastref.FastRef(u, y, Ts, kind)
    c, x = ref.fit()
    got, off = ref.model_of(x)
    assert c < 1e-10 * np.var(y)
    assert abs(off - 350.0) < 1e-4
    assert abs(got.Td - 1.23) < 1e-4
    if kind == "fopdt":
        assert got.K == pytest.approx(2.0, rel=1e-5)
        assert got.tau == pytest.approx(3.0, rel=1e-5)
    else:
        nat = models.to_natural(got)
        assert (nat.K, nat.wn, nat.zeta) == pytest.approx((-1.5, 0.8, 0.6), rel=1e-5)
    cg, _ = ref.grid_fit()
    assert cg < 1e-10 * np.var(y)


def test_driver_simulates_the_plants_exactly(tmp_path):
    """The noise-free output the driver recorded equals pdtref's simulation
    of the truth driven by the recorded input, for every case."""
    exe = driver()
    cases = [json.loads(x) for x in subprocess.run(
        [str(exe), "cases"], capture_output=True, text=True, check=True).stdout.splitlines()]
    assert len(cases) >= 8
    for c in cases:
        dump = tmp_path / f"case{c['index']}.bin"
        out = subprocess.run([str(exe), "run", str(c["index"]), "7", "1", str(dump)],
                             capture_output=True, text=True, check=True).stdout
        line = json.loads(out)
        assert line["seed"] == 7
        u, y, yc = np.fromfile(dump).reshape(3, c["n"])
        assert u[0] == 40.0 and np.all(u[:16] == 40.0)
        ref = bl.simulate(certainty.truth_model(c), c["Ts"], u - u[0])
        assert np.max(np.abs(yc - ref)) <= 1e-9 * np.max(np.abs(ref)), c["name"]
        noise = y - 350.0 - yc
        snr = 20 * math.log10(np.std(yc) / np.std(noise))
        assert 22.0 < snr < 28.0, c["name"]
        assert np.ptp(u) > 0.0


def test_verdict_tells_a_wrong_basin():
    Ts = 0.1
    du = input_signal()
    truth = models.Fopdt(2.0, 3.0, 1.23)
    u = 40.0 + 10.0 * du
    y = 350.0 + bl.simulate(truth, Ts, 10.0 * du) + 0.05 * bl.Rng.keyed(1).normal(du.size)
    right = {"seed": 1, "status": 0, "flags": 0, "model": "fopdt", "K": 2.0, "tau": 3.0,
             "Td": 1.23, "fit": 99.0, "evaluations": 1000}
    wrong = dict(right, tau=30.0, Td=0.2)
    refused = {"seed": 1, "status": -14, "status_name": "poor fit"}
    assert certainty.judge(u, y, Ts, "fopdt", truth, right)["verdict"] == "right"
    assert certainty.judge(u, y, Ts, "fopdt", truth, wrong)["verdict"] == "wrong"
    assert certainty.judge(u, y, Ts, "fopdt", truth, dict(wrong, flags=4))["verdict"] == \
        "flagged-wrong"
    assert certainty.judge(u, y, Ts, "fopdt", truth, refused)["verdict"] == "refused"


def test_reference_of_a_previous_run():
    """--reference: a previous run's reference optimum of the same record
    can only make a verdict stricter."""
    Ts = 0.1
    du = input_signal()
    truth = models.Fopdt(2.0, 3.0, 1.23)
    u = 40.0 + 10.0 * du
    y = 350.0 + bl.simulate(truth, Ts, 10.0 * du) + 0.05 * bl.Rng.keyed(1).normal(du.size)
    right = {"seed": 1, "status": 0, "flags": 0, "model": "fopdt", "K": 2.0, "tau": 3.0,
             "Td": 1.23, "fit": 99.0, "evaluations": 1000}
    key = ("bench", 0, 1)
    full = certainty.judge(u, y, Ts, "fopdt", truth, right, key)
    try:
        certainty.CACHE[key] = {"ref": 2.0 * full["ref"], "ref9_missed": False,
                                "search_missed": False}
        kept = certainty.judge(u, y, Ts, "fopdt", truth, right, key)
        assert kept["verdict"] == "right" and kept["ref"] <= full["ref"] * (1 + 1e-9)
        certainty.CACHE[key] = {"ref": 0.5 * full["ref"], "ref9_missed": False,
                                "search_missed": False}
        assert certainty.judge(u, y, Ts, "fopdt", truth, right, key)["verdict"] == "wrong"
    finally:
        certainty.CACHE.clear()


@pytest.mark.parametrize("case", certainty.NOISY)
def test_noisy_truth_is_the_records_plant(case):
    """The noisy cases' truth in pdtref's form is the plant coarse_bench
    simulates."""
    from pdtbench import coarse_bench as cb
    u, y = cb.record(case[0], case[1], case[2], 300, 1)
    ref = bl.simulate(certainty.noisy_truth(case), cb.TS, u - u[0])
    assert np.max(np.abs(y - 350.0 - ref)) <= 1e-6 * np.max(np.abs(ref))


def test_reference_cache(tmp_path, monkeypatch):
    """Reference.fit read back from the cache gives the fit it stored, its
    evaluation count included; another record is fitted anew."""
    monkeypatch.setenv("PDT_REFERENCE_CACHE", str(tmp_path))
    Ts = 0.1
    du = input_signal()
    truth = models.Fopdt(2.0, 3.0, 1.23)
    u = 40.0 + 10.0 * du
    y = 350.0 + bl.simulate(truth, Ts, 10.0 * du) + 0.05 * bl.Rng.keyed(1).normal(du.size)
    first = bl.Reference(u, y, Ts, "fopdt")
    fitted = first.fit()
    assert len(list(tmp_path.glob("*/*.json"))) == 1
    again = bl.Reference(u, y, Ts, "fopdt")
    assert again.fit() == fitted and again.nfev == first.nfev > 0
    other = bl.Reference(u, y + 0.01, Ts, "fopdt")
    other.fit()
    assert len(list(tmp_path.glob("*/*.json"))) == 2
    monkeypatch.setenv("PDT_REFERENCE_CACHE", "off")
    off = bl.Reference(u, y, Ts, "fopdt")
    assert off.fit() == fitted and off.nfev == first.nfev


def test_compare_answers(tmp_path, capsys):
    """--compare: equal answers pass, a changed flag or a missing record
    fails and is listed; the report counts each kind of record."""
    rec = {"kind": "closed", "case": 0, "seed": 1, "status": 0, "flags": 0,
           "evaluations": 2100, "model": "fopdt", "K": 1.5, "tau": 3.0, "Td": 0.5}
    other = dict(rec, seed=2)
    old, new, out = tmp_path / "old.json", tmp_path / "new.json", tmp_path / "cmp.md"
    old.write_text(json.dumps(rec) + "\n" + json.dumps(other) + "\n")
    new.write_text(json.dumps(rec) + "\n" + json.dumps(other) + "\n"
                   + json.dumps({"kind": "meta", "seeds": 2}) + "\n")
    assert certainty.compare_answers(str(old), str(new), out=str(out), names=["a", "b"]) == 0
    text = out.read_text()
    assert "**2 of 2 records give the same answer bit for bit**" in text
    assert "| closed-loop cases | 2 | 2 |" in text
    new.write_text(json.dumps(dict(rec, flags=16)) + "\n")
    assert certainty.compare_answers(str(old), str(new)) == 1
    printed = capsys.readouterr().out
    assert "0 of 1 records of both runs give the same answer; 1 records are in one run only" \
        in printed
    assert "'flags': 16" in printed
