"""The loop-performance monitor on simulated closed-loop records:
writes docs/reports/monitor.md from monitor_report.md.in.

Records come from pdtsupport.loop (a PI loop around a continuous plant,
simulated by scipy, sharing no code with the library): every kind of loop
(well tuned, aggressive, timid, process gain changed since the model,
sticky valve, saturated) on four plants and several disturbance seeds, and
a battery of well-tuned loops for the false-alarm rate. Each record is
judged by `pdtfit monitor` with and without the model.

    python3 tools/bench/monitor_report.py [--seeds 10] [--false 60] [--jobs 2]
"""
import argparse
import collections
import json
import multiprocessing
import pathlib
import platform
import string
import subprocess
import sys
import tempfile

import numpy as np

from pdtsupport import loop

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEMPLATE = pathlib.Path(__file__).with_name("monitor_report.md.in")
FIGURES = ("oscillation", "regularity", "corr_ve", "iae_ratio", "harris", "gain_ratio",
           "mismatch_t", "saturation", "idle_index")


def pdtfit():
    for build in ("release", "dev"):
        p = ROOT / "build" / build / "tools" / "pdtfit"
        if p.exists():
            return str(p)
    sys.exit("build pdtfit first (tools/demo.sh or cmake --build build/dev)")


def judge(job):
    """One record: (plant index, kind, seed, tmp dir, program) -> result."""
    pi, kind, seed, tmp, prog = job
    plant = loop.PLANTS[pi]
    rec = loop.simulate(plant, loop.scenario(kind, plant, seed), seed)
    csv = pathlib.Path(tmp) / f"{plant.name}-{kind}-{seed}.csv"
    model = pathlib.Path(tmp) / f"{plant.name}.json"
    loop.write_csv(csv, rec)
    out = {}
    for tag, extra in (("model", ["--model", str(model)]), ("none", [])):
        run = subprocess.run([prog, "monitor", *extra, str(csv)], capture_output=True,
                             text=True, check=True)
        out[tag] = json.loads(run.stdout)
    csv.unlink()
    return {"plant": plant.name, "kind": kind, "seed": seed, **out}


def run_all(seeds, false_seeds, jobs):
    prog = pdtfit()
    with tempfile.TemporaryDirectory() as tmp:
        for p in loop.PLANTS:
            (pathlib.Path(tmp) / f"{p.name}.json").write_text(json.dumps(p.model()))
        work = [(pi, k, s, tmp, prog) for pi in range(len(loop.PLANTS))
                for k in loop.KINDS for s in range(seeds)]
        work += [(pi, "well", 1000 + s, tmp, prog) for pi in range(len(loop.PLANTS))
                 for s in range(false_seeds)]
        with multiprocessing.Pool(jobs) as pool:
            return pool.map(judge, work, chunksize=4)


def kinds_table(res, tag):
    """Rows: kind; columns: each plant's count of right verdicts."""
    names = [p.name for p in loop.PLANTS]
    rows = ["| record | expected | " + " | ".join(names) + " | all |",
            "|---|---|" + "---|" * (len(names) + 1)]
    for kind in loop.KINDS:
        cells, right, total = [], 0, 0
        for name in names:
            rs = [r for r in res if r["kind"] == kind and r["plant"] == name and r["seed"] < 1000]
            ok = sum(r[tag]["verdict"] == loop.EXPECTED[kind] for r in rs)
            cells.append(f"{ok}/{len(rs)}")
            right, total = right + ok, total + len(rs)
        rows.append(f"| {kind} | `{loop.EXPECTED[kind]}` | " + " | ".join(cells)
                    + f" | {right}/{total} |")
    return "\n".join(rows)


def wrong_list(res, tag):
    """What the wrong verdicts were, counted."""
    c = collections.Counter((r["kind"], r[tag]["verdict"]) for r in res
                            if r["seed"] < 1000 and r[tag]["verdict"] != loop.EXPECTED[r["kind"]])
    if not c:
        return "none"
    return ", ".join(f"{kind} → `{v}` ({n})" for (kind, v), n in sorted(c.items()))


def causes(res):
    c = collections.Counter((r["kind"], r["model"]["cause"]) for r in res
                            if r["seed"] < 1000 and r["model"]["verdict"] == "oscillating")
    return ", ".join(f"{kind}: `{cause}` {n}" for (kind, cause), n in sorted(c.items()))


def figure_table(res):
    """Median (range) of each figure by kind, with the model."""
    rows = ["| record | " + " | ".join(FIGURES) + " |", "|---|" + "---|" * len(FIGURES)]
    for kind in loop.KINDS:
        cells = []
        for f in FIGURES:
            v = [r["model"][f] for r in res if r["kind"] == kind and r["seed"] < 1000
                 and r["model"][f] is not None]
            cells.append(f"{np.median(v):.2f} ({min(v):.2f}..{max(v):.2f})" if v else "-")
        rows.append(f"| {kind} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def false_alarms(res, tag):
    rs = [r for r in res if r["seed"] >= 1000]
    bad = [r for r in rs if r[tag]["verdict"] != "ok"]
    c = collections.Counter(r[tag]["verdict"] for r in bad)
    what = ", ".join(f"`{v}` {n}" for v, n in sorted(c.items())) or "none"
    return len(rs), len(bad), what


def margins(res):
    """The largest figure of each test among the well-tuned battery."""
    rs = [r["model"] for r in res if r["seed"] >= 1000]
    top = {f: max(r[f] for r in rs if r[f] is not None) for f in
           ("oscillation", "regularity", "iae_ratio", "mismatch_t")}
    g = [abs(np.log(r["gain_ratio"])) for r in rs if r["gain_ratio"] is not None]
    top["gain"] = float(np.exp(max(g))) if g else float("nan")
    return top


def count_work():
    """Instructions (x86-64, callgrind, inclusive) of pdt_monitor_scan per
    scan at decimation 1 and 10, of pdt_monitor_result and _init, from
    tools/bench/monitor_count.c built -O2 with the library (float)."""
    src = sorted(str(p) for p in (ROOT / "lib" / "src").glob("*.c"))
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        exe = pathlib.Path(tmp) / "mc"
        subprocess.run(["cc", "-O2", "-std=c99", f"-I{ROOT}/lib/include", f"-I{ROOT}/lib/src",
                        f"-I{ROOT}/tools/sim",
                        *src, str(pathlib.Path(__file__).with_name("monitor_count.c")), "-lm",
                        "-o", str(exe)], check=True)
        for dec in (1, 10):
            cg = pathlib.Path(tmp) / f"cg{dec}"
            subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={cg}",
                            str(exe), str(dec)], check=True, capture_output=True)
            ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100",
                                  str(cg)], check=True, capture_output=True, text=True).stdout
            for name in ("pdt_monitor_scan", "pdt_monitor_result", "pdt_monitor_init"):
                for line in ann.splitlines():
                    if line.rstrip().split(":")[-1].startswith(name + " "):
                        out[(name, dec)] = int(line.split()[0].replace(",", ""))
    return {"scan1": out[("pdt_monitor_scan", 1)] / 4000,
            "scan10": out[("pdt_monitor_scan", 10)] / 4000,
            "result": out[("pdt_monitor_result", 1)], "init": out[("pdt_monitor_init", 1)]}


def commit():
    run = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True)
    return run.stdout.strip() or "unknown"


def render(res, args):
    n_model = false_alarms(res, "model")
    n_none = false_alarms(res, "none")
    top = margins(res)
    work = count_work()
    values = {
        "scan1": f"{work['scan1']:.0f}", "scan10": f"{work['scan10']:.0f}",
        "result": f"{work['result']:,}".replace(",", " "),
        "init": f"{work['init']:,}".replace(",", " "),
        "commit": commit(), "machine": f"{platform.machine()}, {platform.system()} "
        f"{platform.release()}, Python {platform.python_version()}",
        "seeds": args.seeds, "last_seed": args.seeds - 1, "false_seeds": args.false, "plants": len(loop.PLANTS),
        "plant_list": "\n".join(f"- `{p.name}`: {p.K} / "
                                + " ".join(f"({T} s + 1)" for T in p.lags)
                                + f" e^(-{p.Td} s), Ts = {p.Ts} s; model {json.dumps(p.model())}"
                                for p in loop.PLANTS),
        "kinds_model": kinds_table(res, "model"), "kinds_none": kinds_table(res, "none"),
        "wrong_model": wrong_list(res, "model"), "wrong_none": wrong_list(res, "none"),
        "causes": causes(res), "figures": figure_table(res),
        "fa_n": n_model[0], "fa_model": n_model[1], "fa_model_what": n_model[2],
        "fa_model_pct": f"{100.0 * n_model[1] / n_model[0]:.2f}",
        "fa_none": n_none[1], "fa_none_what": n_none[2],
        "fa_none_pct": f"{100.0 * n_none[1] / n_none[0]:.2f}",
        "top_osc": f"{top['oscillation']:.3f}", "top_reg": f"{top['regularity']:.3f}",
        "top_iae": f"{top['iae_ratio']:.2f}", "top_t": f"{top['mismatch_t']:.1f}",
        "top_gain": f"{top['gain']:.3f}",
    }
    return string.Template(TEMPLATE.read_text()).substitute(values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10, help="records per plant and kind")
    ap.add_argument("--false", type=int, default=60, help="well-tuned records per plant")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "docs" / "reports" / "monitor.md"))
    ap.add_argument("--dump", help="also write every result as JSON here")
    args = ap.parse_args()
    res = run_all(args.seeds, args.false, args.jobs)
    if args.dump:
        pathlib.Path(args.dump).write_text(json.dumps(res))
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(render(res, args))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
