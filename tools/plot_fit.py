#!/usr/bin/env python3
"""Draws a record against its identified model: `pdtfit identify --plot`.

    python3 tools/plot_fit.py SIM.csv OUT.png [--title TEXT]

SIM.csv is what `pdtfit identify --out-sim` writes (t,u,y,ysim,residual).
Upper axes: measured y and the model's simulated output; middle: the
residual y - ysim; lower: the input u. Exit status 4 when matplotlib is
missing (pdtfit then says so), 2 on a bad file.
"""
import argparse
import csv
import sys


def read(path):
    cols = {"t": [], "u": [], "y": [], "ysim": [], "residual": []}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            for k in cols:
                v = row[k]
                cols[k].append(float(v) if v not in ("", "nan") else float("nan"))
    return cols


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sim_csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    args = ap.parse_args(argv)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 4
    try:
        c = read(args.sim_csv)
    except (OSError, KeyError, ValueError) as e:
        print(f"plot_fit.py: cannot read {args.sim_csv}: {e}", file=sys.stderr)
        return 2
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(8, 6),
                           gridspec_kw={"height_ratios": [3, 1, 1]})
    ax[0].plot(c["t"], c["y"], ".", ms=2, label="y (data)")
    ax[0].plot(c["t"], c["ysim"], "-", lw=1.2, label="model")
    ax[0].legend(loc="best")
    ax[0].set_ylabel("y")
    ax[1].plot(c["t"], c["residual"], "-", lw=0.8, color="tab:red")
    ax[1].axhline(0.0, color="k", lw=0.5)
    ax[1].set_ylabel("y - model")
    ax[2].step(c["t"], c["u"], where="post", lw=1.0, color="tab:green")
    ax[2].set_ylabel("u")
    ax[2].set_xlabel("t, s (from the first row)")
    fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main())
