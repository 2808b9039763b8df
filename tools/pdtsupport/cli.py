"""The `pdtfit` program for tests: where it is, how to run it, and the
checks of its output every command-line test makes.

The binary comes from $PDTFIT_BIN, else from the newest
build/*/tools/pdtfit of the checkout. Without one the command-line tests
are skipped, except when $CI is "true" or $PDTFIT_REQUIRE_BIN is "1": then
they fail (tools/tests/conftest.py), so a CI run that built no program
cannot pass silently.
"""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def find_binary():
    env = os.environ.get("PDTFIT_BIN")
    if env:
        return pathlib.Path(env)
    # The most recently built one, so a stale tree does not shadow a fresh one.
    found = [p for p in (ROOT / "build").glob("*/tools/pdtfit")
             if p.is_file() and os.access(p, os.X_OK)]
    return max(found, key=lambda p: p.stat().st_mtime) if found else None


def binary_required():
    return (os.environ.get("CI", "").lower() == "true"
            or os.environ.get("PDTFIT_REQUIRE_BIN") == "1")


BIN = find_binary()
MISSING = None if BIN is not None and BIN.is_file() else (
    "pdtfit binary not found: set PDTFIT_BIN or build into build/<dir>/ "
    "(cmake -S . -B build/x && cmake --build build/x)")

# The keys of identify's JSON: the model, then (GA only) how sure the search
# is, then the record's Ts and n.
# The uncertainty: the Fisher information's (a FOPDT, and the scans), the
# bootstrap's (a SOPDT of the GA, by default).
FISHER_KEYS = ["std", "cov", "uncertainty"]
BOOT_KEYS = ["std", "cov", "ci95", "uncertainty", "bootstrap_runs"]
LS_FOPDT_KEYS = ["model", "K", "tau", "Td", "y0", "u0", "cost", "fit", "evaluations",
                 *FISHER_KEYS, "Ts", "n"]
LS_SOPDT_KEYS = ["model", "K", "wn", "zeta", "Td", "y0", "u0", "tau1", "tau2", "a", "b",
                 "cost", "fit", "evaluations", *FISHER_KEYS, "Ts", "n"]
CERTAINTY_KEYS = ["searches", "coarse", "runner_up", "flags", "evidence", "excluded"]
TAIL = len(FISHER_KEYS) + 2
FOPDT_KEYS = LS_FOPDT_KEYS[:-TAIL] + CERTAINTY_KEYS + LS_FOPDT_KEYS[-TAIL:]
SOPDT_KEYS = LS_SOPDT_KEYS[:-TAIL] + CERTAINTY_KEYS + BOOT_KEYS + ["Ts", "n"]
# The keys of `pdtfit tune`'s JSON.
TUNE_KEYS = ["rule", "form", "Kc", "tauI", "tauD", "Tf", "Ms", "gain_margin",
             "phase_margin_deg", "w_ms", "w_pc", "w_gc", "series", "pid", "parallel", "stated_in"]
# The keys of a model inside autotune-sim's JSON: no std, Ts, n.
MODEL_KEYS = {"fopdt": FOPDT_KEYS[:-TAIL], "sopdt": SOPDT_KEYS[:-len(BOOT_KEYS) - 2]}


def run(args, stdin=None):
    return subprocess.run([str(BIN)] + [str(a) for a in args], input=stdin,
                          capture_output=True, text=True, timeout=60)


def assert_usage_error(res, *fragments, status=2):
    """Exit status, nothing on stdout, exactly one 'pdtfit: ' line on stderr."""
    assert res.returncode == status, (res.returncode, res.stderr)
    assert res.stdout == ""
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and res.stderr.endswith("\n"), res.stderr
    assert lines[0].startswith("pdtfit: "), lines[0]
    for frag in fragments:
        assert frag in lines[0], (frag, lines[0])


def parse_output(res):
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    assert res.stdout.endswith("\n") and res.stdout.count("\n") == 1
    # Strict JSON: no NaN/Infinity literals.
    return json.loads(res.stdout, parse_constant=lambda c: pytest.fail("non-JSON " + c))


def write_csv(path, cols, fmt="%.10g", header=None, newline="\n"):
    names = list(cols)
    rows = [newline.join([",".join(header or names)])]
    data = np.column_stack([cols[c] for c in names])
    for r in data:
        rows.append(",".join(fmt % v for v in r))
    path.write_text(newline.join(rows) + newline)
    return path


def setup_cli_test(item):
    """For conftest.py's pytest_runtest_setup: a test marked `cli` without
    a binary is skipped, or failed when the binary is required."""
    if MISSING and item.get_closest_marker("cli"):
        if binary_required():
            pytest.fail(MISSING + " (required: CI=true or PDTFIT_REQUIRE_BIN=1)",
                        pytrace=False)
        pytest.skip(MISSING)
