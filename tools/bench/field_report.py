"""Records as loggers make them: writes docs/reports/field.md from
tools/bench/field_report.md.in by running `pdtfit identify` on records of
known plants with injected faults, on records whose output is unrelated
noise, and on clean records (docs/field-data.md)."""
from __future__ import annotations

import argparse
import itertools
import os
import pathlib
import platform
import subprocess

import numpy as np
from scipy.signal import lfilter

from pdtbench import benchlib as B

ROOT = pathlib.Path(__file__).resolve().parents[2]
TRUTHS = [B.fopdt_truth("fopdt 1.5/(10s+1) e^-3s", 1.5, 10.0, 3.0),
          B.sopdt_truth("sopdt wn 0.2 zeta 0.5 Td 4", 1.0, 0.2, 0.5, 4.0),
          B.fopdt_truth("fopdt -2/(40s+1) e^-12s", -2.0, 40.0, 12.0)]
MORE = [B.sopdt_truth("sopdt wn 0.05 zeta 1.2", 2.0, 0.05, 1.2, 10.0),
        B.integ_truth("integrator 0.05/(s(8s+1)) e^-3s", 0.05, 8.0, 3.0)]
MARKERS = (-9999.0, 9999.0, 32767.0, -32768.0, 65535.0, 1e6)


def scales(j):
    return j["K"], (j["tau"] if j["model"] == "fopdt" else j["wn"])


def faults(n, seed):
    out = [(f"marker {v:g}", [(150, v), (420, v)]) for v in MARKERS]
    out += [("dropout to 0", [(p + i, 0.0) for i in range(10)]) for p in (60, 250, 480)]
    picks = B.Rng.keyed(seed).choice(n, n // 100)
    out.append(("1 % at -9999", [(int(p), -9999.0) for p in picks]))
    return out


def verdict(j, K0, T0):
    if "error" in j:
        return "refused"
    K, T = scales(j)
    if abs(K / K0 - 1) < 0.02 and abs(T / T0 - 1) < 0.05:
        return "within noise"
    return "flagged" if j["flags"] else "wrong, no flag"


def fault_rows(binary, seeds):
    counts = {}
    for t, exc, snr, seed in itertools.product(TRUTHS, ("step", "prbs"), (40, 25), seeds):
        u, y, _ = B.make_record(t, exc, 600, 1.0, snr, False, seed)
        model = "fopdt" if t.kind == "fopdt" else "sopdt"
        K0, T0 = scales(B.run_pdtfit(binary, u, y, 1.0, model))
        for name, f in faults(600, seed):
            yy = y.copy()
            for p, v in f:
                yy[p] = v
            key = (model, name.split(" ")[0] if name.startswith("marker") else name)
            c = counts.setdefault(key, {})
            v = verdict(B.run_pdtfit(binary, u, yy, 1.0, model), K0, T0)
            c[v] = c.get(v, 0) + 1
    cols = ("within noise", "flagged", "refused", "wrong, no flag")
    rows = ["| model | fault | records | " + " | ".join(cols) + " |",
            "|---|---|---:|" + "---:|" * len(cols)]
    for (model, name), c in sorted(counts.items()):
        rows.append(f"| {model} | {name} | {sum(c.values())} | "
                    + " | ".join(str(c.get(k, 0)) for k in cols) + " |")
    return "\n".join(rows)


def null_rows(binary, seeds):
    rows = ["| output | records | flagged no_relation | largest evidence |", "|---|---:|---:|---:|"]
    for noise, pole in (("white", 0.0), ("AR(1), pole 0.9", 0.9), ("AR(1), pole 0.99", 0.99)):
        flagged = total = 0
        top = 0.0
        for n, model, seed in itertools.product((100, 400, 1500), ("fopdt", "sopdt"), seeds):
            rng = B.Rng.keyed(seed, n)
            u = 40.0 + 5.0 * rng.signs(n, 5)
            y = 20 + lfilter([1.0], [1.0, -pole], rng.normal(n))
            j = B.run_pdtfit(binary, u, y, 1.0, model, seed=seed)
            total += 1
            flagged += "error" not in j and "no_relation" in j["flags"]
            top = max(top, j.get("evidence", 0.0))
        rows.append(f"| {noise} | {total} | {flagged} | {top:.1f} |")
    return "\n".join(rows)


def clean_rows(binary):
    """Two rows: the fits whose structure can represent the truth, and the
    FOPDT fits of the integrator, which cannot (a lag fitted to an
    integrator's record from rest is what the mid_transient flag's second
    test flags, docs/field-data.md)."""
    rows = {}
    for t, exc, snr in itertools.product(TRUTHS + MORE, ("step", "pulse", "prbs", "chirp", "relay"),
                                         (60, 40, 25, 10, 5)):
        u, y, _ = B.make_record(t, exc, 600, 1.0, snr, False, 1)
        for model in ("fopdt", "sopdt"):
            j = B.run_pdtfit(binary, u, y, 1.0, model)
            key = ("FOPDT of the integrator" if t.kind == "integ" and model == "fopdt"
                   else "a structure that can fit the plant")
            r = rows.setdefault(key, [0, 0, 0, 0, float("inf")])
            r[0] += 1
            r[1] += j["excluded"]["count"] > 0
            r[2] += "no_relation" in j["flags"]
            r[3] += "mid_transient" in j["flags"]
            r[4] = min(r[4], j["evidence"])
    lines = ["| fits | records | with samples left out | flagged no_relation "
             "| flagged mid_transient | least evidence |",
             "|---|---:|---:|---:|---:|---:|"]
    for key in ("a structure that can fit the plant", "FOPDT of the integrator"):
        n, left, nr, mid, least = rows[key]
        lines.append(f"| {key} | {n} | {left} | {nr} | {mid} | {least:.1f} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--binary", default=os.environ.get("PDTFIT_BIN",
                                                       str(ROOT / "build/dev/tools/pdtfit")))
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "docs" / "reports" / "field.md"))
    a = ap.parse_args()
    seeds = range(1, a.seeds + 1)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    text = (ROOT / "tools" / "bench" / "field_report.md.in").read_text().format(
        commit=commit, machine=f"{platform.machine()}, {platform.python_version()}",
        faults_table=fault_rows(a.binary, seeds), null_seeds=4 * a.seeds,
        null_table=null_rows(a.binary, range(1, 4 * a.seeds + 1)), clean_table=clean_rows(a.binary))
    pathlib.Path(a.out).write_text(text)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
