#!/usr/bin/env python3
"""Bit-for-bit comparison of what `pdtfit identify` alone does not reach:
tuning, reduction, least squares, order selection and the autotune.

    python3 tools/bench/result_compare.py run --pdtfit BIN --out FILE
    python3 tools/bench/result_compare.py diff FILE_A FILE_B

`run` calls `pdtfit tune` on a set of FOPDT and SOPDT models with every
rule, form and a few options (`pdt_tune_robustness`), `pdtfit reduce`
with both methods on plants with lags, zeros and delays
(`pdt_reduce_half_rule`, `pdt_reduce_sung`), `pdtfit identify` on the
records of ident_compare.py with `--tune` (tuning of identified models,
integrators included), `--model auto` (`pdt_validate_model`) and
`--method elms|eiv` (`pdt_ls`), and `pdtfit autotune-sim` with every
experiment (`pdt_excite_init`, `pdt_validate_margin`). Each call's exit
code, standard output and standard error is one JSON line, as in
ident_compare.py, whose `diff` compares two such files.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from pdtbench import ident_compare as ic

FOPDT = ((1.0, 2.5, 1.47), (2.0, 5.0, 0.3), (-0.5, 10.0, 4.0), (3.0, 0.2, 2.0))
SOPDT_TC = ((1.0, 2.0, 1.2, 0.77), (2.0, 8.0, 0.5, 1.0), (0.7, 3.0, 3.0, 0.1))
SOPDT_NAT = ((1.0, 0.8, 0.3, 1.0), (1.5, 2.0, 1.5, 0.4))
RULES = ("simc", "imc", "amigo", "zn")
FORMS = ("pi", "pid")
TUNE_OPTS = ((), ("--ms-max", "0"), ("--deriv-filter", "10", "--ms-max", "0"),
             ("--u-span", "100", "--y-span", "200"))
KNOBS = {"simc": ("--tau-c", "0.5"), "imc": ("--lambda", "3")}
PLANTS = (("1", "5,1,0.5", "", "0.2"), ("2", "10,4,2,1,0.5", "", "1"),
          ("1", "3,2", "0.5", "0"), ("1.5", "6,2,1", "-1", "0.5"),
          ("1", "8,3,1", "4,0.7", "0.3"), ("0.5", "2", "", "1.5"), ("1", "1,1,1,1,1,1", "", "0"))
ID_TUNE = ("simc:pi", "imc:pid", "amigo:pid", "zn:pid")
AUTOTUNE = (("2", "5", ""), ("1", "10,2,1", ""), ("1.5", "3,1", "0.5"))
EXPERIMENTS = ("step", "pulse", "chirp", "prbs", "relay")


def call(binary, args):
    """One call's (exit code, stdout, stderr)."""
    res = subprocess.run([str(binary)] + list(args), capture_output=True, text=True,
                         timeout=600)
    return res.returncode, res.stdout, res.stderr


def model_args():
    """The tune command's model arguments, one tuple per model."""
    out = [("--model", "fopdt", "--K", str(k), "--tau", str(t), "--Td", str(d))
           for k, t, d in FOPDT]
    out += [("--model", "sopdt", "--K", str(k), "--tau1", str(a), "--tau2", str(b), "--Td",
             str(d)) for k, a, b, d in SOPDT_TC]
    out += [("--model", "sopdt", "--K", str(k), "--wn", str(w), "--zeta", str(z), "--Td",
             str(d)) for k, w, z, d in SOPDT_NAT]
    return out


def tune_calls():
    for m in model_args():
        for rule in RULES:
            for form in FORMS:
                base = ["tune", "--rule", rule, "--form", form] + list(m)
                for opts in TUNE_OPTS:
                    yield base + list(opts)
                if rule in KNOBS:
                    yield base + list(KNOBS[rule]) + ["--ms-max", "0"]
    yield ["tune", "--rule", "zn", "--Ku", "2.5", "--Pu", "7"]
    yield ["tune", "--rule", "zn", "--form", "pid", "--Ku", "2.5", "--Pu", "7", "--ms-max", "0"]


def reduce_calls():
    for k, lags, zeros, delay in PLANTS:
        for method in ("skogestad", "sung"):
            for model in ("fopdt", "sopdt"):
                for h in ("0", "0.1") if method == "skogestad" else ("",):
                    args = ["reduce", "--method", method, "--model", model, "--gain", k,
                            "--lags", lags, "--delay", delay]
                    args += ["--h", h] if h else []
                    args += ["--zeros", zeros] if zeros else []
                    yield args


def autotune_calls():
    for k, lags, delay in AUTOTUNE:
        for exp in EXPERIMENTS:
            args = ["autotune-sim", "--plant-gain", k, "--plant-lags", lags,
                    "--experiment", exp]
            if delay:
                args += ["--plant-delay", delay]
            yield args
            yield args + ["--noise", "0.05", "--seed", "3", "--rule", "amigo", "--form", "pid"]


def identify_calls():
    """(name, u, y, Ts, extra arguments) of the identifications."""
    for name, u, y, Ts in ic.synthetic() + ic.real_records():
        for i, tune in enumerate(ID_TUNE):
            model = "fopdt" if i % 2 == 0 else "sopdt"
            yield name, u, y, Ts, ["--seed", "1", "--model", model, "--tune", tune, "--ms-max",
                                   "0", "--force"]
        yield name, u, y, Ts, ["--seed", "1", "--model", "auto", "--tune", "simc:pi", "--ms-max",
                               "0", "--force"]
        for method in ("elms", "eiv"):
            for model in ("fopdt", "sopdt"):
                yield name, u, y, Ts, ["--method", method, "--model", model, "--tune", "simc:pi",
                                       "--force"]


def identify(binary, u, y, Ts, extra):
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("u,y\n")
        f.write("\n".join(f"{a:.12g},{b:.12g}" for a, b in zip(u, y)))
        f.write("\n")
        path = f.name
    try:
        rc, out, err = call(binary, ["identify", "--fs",
                                     f"{1.0 / float(Ts):.17g}"] + extra + [path])
    finally:
        os.unlink(path)
    return rc, out, err.replace(path, "FILE")


def run(args):
    with open(args.out, "w") as f:
        def put(key, res):
            rc, out, err = res
            f.write(json.dumps({"key": key, "rc": rc, "out": out, "err": err}) + "\n")
            f.flush()
        for a in list(tune_calls()) + list(reduce_calls()) + list(autotune_calls()):
            put(" ".join(a), call(args.pdtfit, a))
        for name, u, y, Ts, extra in identify_calls():
            put(f"identify {name} " + " ".join(extra), identify(args.pdtfit, u, y, Ts, extra))
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--pdtfit", required=True)
    r.add_argument("--out", required=True)
    d = sub.add_parser("diff")
    d.add_argument("a")
    d.add_argument("b")
    args = p.parse_args()
    return run(args) if args.cmd == "run" else ic.diff(args)


if __name__ == "__main__":
    sys.exit(main())
