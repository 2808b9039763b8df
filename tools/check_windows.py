"""The Windows build of the pdtfit program against the Linux one.

Runs a representative set of commands (identify FOPDT, SOPDT and the order
by evidence with the GA, the least-squares methods, reduce, tune from the
command line and from identify's JSON, autotune-sim with two plants, and a
usage error and a refused record) with both programs on the same records
and seeds, and compares their JSON: every string and key equal; every
number of a model, of the gains and of the loop's figures within --rtol
(default 1e-4) relative or 1e-4 absolute (an offset near zero; the
records' outputs swing by 2 to 10); the exit status and a refusal's stderr
line the same. The two C libraries' expf/logf differ in their last bits,
so the searches take other paths to the same answer: the search's trace
(evaluations, scans, the standard errors, the cost and the evidence) is
held to 5 %, and the frequencies of Ms and of the crossovers, maxima of
flat curves, to 1e-3.

    python3 tools/check_windows.py --linux build/test-float/tools/pdtfit \\
        --windows build/test-mingw/tools/pdtfit.exe

The Windows program runs under Wine (--wine, default `wine`); the
environment's WINEPREFIX and WINEDEBUG apply (tools/test.sh keeps the
prefix under build/ and Wine quiet). Exits 1 if any command differs.
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

from pdtsupport.cli import write_csv
from pdtsupport.plant import simulate
from pdtsupport.records import multistep_input, noise

# Keys of the search's trace and of flat maxima, and their tolerances.
TRACE = {"evaluations", "scans", "identify", "std", "cov", "ci95", "cost", "bic", "evidence",
         "searches", "coarse", "runner_up"}
FLAT = {"w_ms", "w_pc", "w_gc"}
FOPDT_PLANT = ["--plant-gain", "2", "--plant-lags", "5", "--plant-delay", "1.3"]
SOPDT_PLANT = ["--plant-gain", "1.5", "--plant-lags", "8,3", "--plant-delay", "2"]


def make_records(d):
    """A FOPDT and a SOPDT record (0.1 s, 600 samples, noisy) as CSV files."""
    n, ts = 600, 0.1
    t = np.arange(n) * ts
    u = multistep_input(n, 50.0, 5.0, 25, 60, 20, seed=7)
    y1 = 20.0 + simulate([2.0], [5.0, 1.0], 1.3, u - 50.0, ts) + noise(n, 0.02, 11)
    y2 = 20.0 + simulate([1.5], [24.0, 11.0, 1.0], 2.0, u - 50.0, ts) + noise(n, 0.02, 13)
    return (write_csv(d / "fopdt.csv", {"t": t, "u": u, "y": y1}),
            write_csv(d / "sopdt.csv", {"t": t, "u": u, "y": y2}))


def cases(fopdt, sopdt, model_json):
    """(name, argv, stdin) of every command compared."""
    tune_fopdt = ["--model", "fopdt", "--K", "2", "--tau", "5", "--Td", "1.3"]
    return [
        ("identify FOPDT", ["identify", "--model", "fopdt", "--seed", "3", fopdt], None),
        ("identify SOPDT", ["identify", "--model", "sopdt", "--seed", "3", sopdt], None),
        ("identify auto", ["identify", "--model", "auto", sopdt], None),
        ("identify elms", ["identify", "--model", "fopdt", "--method", "elms", fopdt], None),
        ("identify combined cost", ["identify", "--model", "fopdt", "--cost", "combined",
                                    "--seed", "5", fopdt], None),
        ("reduce skogestad", ["reduce", "--method", "skogestad", "--model", "sopdt", "--gain",
                              "1", "--lags", "3,2,1,0.5", "--zeros", "0.2"], None),
        ("reduce sung", ["reduce", "--method", "sung", "--model", "fopdt", "--gain", "1",
                         "--lags", "3,2,1", "--delay", "0.3"], None),
        ("tune simc pi", ["tune", "--rule", "simc", *tune_fopdt], None),
        ("tune amigo pid", ["tune", "--rule", "amigo", "--form", "pid", *tune_fopdt], None),
        ("tune from identify", ["tune", "--rule", "imc", "--from", "-"], model_json),
        ("autotune-sim FOPDT", ["autotune-sim", *FOPDT_PLANT, "--model", "fopdt", "--noise",
                                "0.01", "--seed", "7"], None),
        ("autotune-sim SOPDT", ["autotune-sim", *SOPDT_PLANT, "--experiment", "step",
                                "--amplitude", "2", "--seed", "2"], None),
        ("usage error", ["identify", "--model", "fopdt", "--seed", "x", fopdt], None),
        ("refused record", ["identify", "--model", "fopdt", str(fopdt) + ".missing"], None),
    ]


def run(cmd, argv, stdin):
    res = subprocess.run(cmd + [str(a) for a in argv], input=stdin, capture_output=True,
                         text=True, timeout=600)
    # The Windows program writes CRLF on its text-mode streams.
    return res.returncode, res.stdout.replace("\r\n", "\n"), res.stderr.replace("\r\n", "\n")


def differences(a, b, rtol, path="$"):
    """Where the JSON values a and b differ beyond their tolerance (rtol, or
    the trace's and the flat maxima's under those keys), as strings."""
    if isinstance(a, dict) and isinstance(b, dict):
        if list(a) != list(b):
            return [f"{path}: keys {list(a)} != {list(b)}"]
        return [d for k in a for d in differences(
            a[k], b[k], 0.05 if k in TRACE else (1e-3 if k in FLAT else rtol), f"{path}.{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: {len(a)} != {len(b)} items"]
        return [d for i, (x, y) in enumerate(zip(a, b))
                for d in differences(x, y, rtol, f"{path}[{i}]")]
    num = (int, float)
    if isinstance(a, num) and isinstance(b, num) and not isinstance(a, bool):
        if math.isclose(a, b, rel_tol=rtol, abs_tol=1e-4):
            return []
        return [f"{path}: {a!r} != {b!r}"]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def compare(name, lin, win, rtol):
    """The differences of one command's two runs (status, stdout, stderr)."""
    (ls, lo, le), (ws, wo, we) = lin, win
    if ls != ws:
        return [f"exit status {ls} != {ws} ({we.strip()})"]
    if ls != 0:
        # The reason names the file as each program sees it: compare the
        # line up to the first path.
        return [] if le.split("/")[0] == we.split("/")[0] else [f"stderr {le!r} != {we!r}"]
    if le or we:
        return [f"stderr {le!r} / {we!r}"]
    return differences(json.loads(lo), json.loads(wo), rtol)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--linux", required=True, type=pathlib.Path)
    ap.add_argument("--windows", required=True, type=pathlib.Path)
    ap.add_argument("--wine", default="wine")
    ap.add_argument("--rtol", type=float, default=1e-4)
    a = ap.parse_args()
    lin_cmd, win_cmd = [str(a.linux)], [a.wine, str(a.windows)]
    # Wine's first start makes its prefix and says so on stderr.
    run(win_cmd, ["--version"], None)
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        fopdt, sopdt = make_records(pathlib.Path(tmp))
        _, model_json, _ = run(lin_cmd, ["identify", "--model", "fopdt", fopdt], None)
        for name, argv, stdin in cases(fopdt, sopdt, model_json):
            diffs = compare(name, run(lin_cmd, argv, stdin), run(win_cmd, argv, stdin), a.rtol)
            print(("FAIL " if diffs else "ok   ") + name)
            for d in diffs[:10]:
                print("     " + d)
            failed += bool(diffs)
    total = len(cases(fopdt, sopdt, model_json))
    print(f"{total - failed} of {total} commands give the Linux program's output "
          f"within {a.rtol:g} relative")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
