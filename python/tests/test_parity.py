"""Python = command line: every option of `pdtfit identify`, `tune` and
`reduce` is a keyword argument (found in the program's own option tables,
so that a new option fails here until the binding has it), the results
equal the program's JSON field by field, errors name the argument or the
sample, help() needs no file, and __version__ is the library's."""
import inspect
import json
import pathlib
import re
import tomllib
import warnings

import numpy as np
import pytest

import pdtfit
from pdtsupport import cli

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = ROOT / "tools" / "cli"
cli_test = pytest.mark.cli

# Where each option of the program is in the binding: function, keyword.
# Options whose job Python does otherwise say how (None as the keyword).
WHERE = {
    "identify": {
        "--model": "model", "--method": "method", "--td-max": "td_max", "--cost": "cost",
        "--weight": "weight", "--band": "band", "--offset": "offset", "--phi-t": "phi_t",
        "--uncertainty": "uncertainty", "--bootstrap": "bootstrap",
        "--phi-f": "phi_f", "--seed": "seed", "--evaluations": "evaluations",
        "--population": "population", "--coarse": "coarse", "--fs": "fs",
        "--integer-delay": "integer_delay", "--tune": "tune", "--tau-c": "tau_c",
        "--lambda": "lambda_", "--ms-max": "ms_max", "--deriv-filter": "deriv_filter",
        "--u-span": "u_span", "--y-span": "y_span", "--fit-min": "fit_min",
        # the reader's options are read_csv's
        "--t": ("read_csv", "t"), "--u": ("read_csv", "u"), "--y": ("read_csv", "y"),
        "--sep": ("read_csv", "sep"), "--decimal": ("read_csv", "decimal"),
        "--skip": ("read_csv", "skip"), "--time-unit": ("read_csv", "time_unit"),
        "--resample": ("read_csv", "resample"),
        "--units-row": ("read_csv", "units_row"),
        "--time-format": ("read_csv", "time_format"),
        "--bad-value": ("read_csv", "bad_value"), "--bad-rows": ("read_csv", "bad_rows"),
        "--u-before": "u_before", "--initial": "initial", "--drift": "drift",
        # Python tunes a flagged model: the flags are in the result it is given
        "--force": None,
        # outputs beside the JSON: result.simulate(), result.plot()
        "--out-sim": None, "--plot": None, "--plot-script": None,
    },
    "tune": {
        "--rule": "rule", "--form": "form", "--tau-c": "tau_c", "--lambda": "lambda_",
        "--ms-max": "ms_max", "--deriv-filter": "deriv_filter", "--u-span": "u_span",
        "--y-span": "y_span", "--fit-min": "fit_min", "--Ku": "Ku", "--Pu": "Pu",
        # the model: a Model (pdtfit.model), an IdentResult or a dict
        "--model": ("model", "kind"), "--from": "model_or_result", "--K": ("model", "K"),
        "--tau": ("model", "tau"), "--Td": ("model", "Td"), "--wn": ("model", "wn"),
        "--zeta": ("model", "zeta"), "--tau1": ("model", "tau1"), "--tau2": ("model", "tau2"),
        # Python tunes a flagged model: the flags are in the result it is given
        "--force": None,
    },
    "reduce": {
        "--method": "method", "--model": "model", "--gain": "gain", "--lags": "lags",
        "--zeros": "zeros", "--delay": "delay", "--h": "h",
    },
}
SOURCES = {"identify": ["cmd_identify.c", "tune_opts.c"], "tune": ["cmd_tune.c", "tune_opts.c"],
           "reduce": ["cmd_reduce.c"]}


def cli_options(cmd):
    """The option names of the program's tables for cmd (cmd_tune.c's model
    parameters are the pname list)."""
    names = set()
    for f in SOURCES[cmd]:
        text = (CLI / f).read_text()
        names |= set(re.findall(r'\{\s*"(--[A-Za-z0-9-]+)",\s*OPT_', text))
        m = re.search(r"pname\[P_COUNT\] = \{(.*?)\};", text, re.S)
        if m:
            names |= set(re.findall(r'"(--\w+)"', m.group(1)))
    if cmd == "identify":  # tune_opts.c's --rule and --form are identify's --tune
        names -= {"--rule", "--form"}
    return names


@pytest.mark.parametrize("cmd", sorted(WHERE))
def test_every_option_is_a_keyword(cmd):
    found = cli_options(cmd)
    assert len(found) >= 7
    missing = sorted(found - set(WHERE[cmd]))
    assert not missing, f"pdtfit {cmd} options without a place in Python: {missing}"
    for opt, where in WHERE[cmd].items():
        if where is None:
            continue
        fn, kw = where if isinstance(where, tuple) else (cmd, where)
        assert kw in inspect.signature(getattr(pdtfit, fn)).parameters, \
            f"{opt}: pdtfit.{fn} has no {kw}="


@pytest.mark.parametrize("fn", ["identify", "tune", "reduce", "model", "read_csv"])
def test_help_documents_every_argument(fn):
    f = getattr(pdtfit, fn)
    doc = inspect.getdoc(f)
    for name in inspect.signature(f).parameters:
        assert re.search(r"\b%s\b" % re.escape(name), doc), f"{fn}: {name} not in its docstring"


def test_module_help_needs_no_file():
    doc = pdtfit.__doc__
    for fn in ("identify", "tune", "reduce", "read_csv", "PdtError", "__version__"):
        assert fn in doc


def test_version_is_the_headers():
    text = (ROOT / "lib/include/pdt/pdt_common.h").read_text()
    assert f'"{pdtfit.__version__}"' in text
    assert re.fullmatch(r"\d+\.\d+\.\d+", pdtfit.__version__)


@cli_test
def test_version_is_the_programs():
    assert pdtfit.__version__ in cli.run(["--version"]).stdout


def test_python_md_goes_into_the_sdist():
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert cfg["project"]["readme"] == "docs/python.md"
    assert "docs/python.md" in cfg["tool"]["scikit-build"]["sdist"]["include"]


@pytest.mark.parametrize("kwargs, frag", [
    (dict(Ts=-0.5), "Ts must be > 0"),
    (dict(fs=0), "fs must be > 0"),
    (dict(Ts=1, td_max=-1), "td_max must be a dead time > 0 s"),
    (dict(Ts=1, population=5), "population must be an even number"),
    (dict(Ts=1, evaluations=0), "evaluations must be a whole number >= 1"),
    (dict(Ts=1, seed=-1), "seed must be a whole number >= 0"),
    (dict(Ts=1, phi_t=-1, cost="combined"), "phi_t must be a weight >= 0"),
    (dict(Ts=1, model="third"), "unknown model 'third'"),
    (dict(Ts=1, offset="mean"), "unknown offset 'mean'"),
    (dict(Ts=1, ms_max=3), "go with tune="),
    (dict(Ts=1, tune="pid"), "tune must be 'RULE[:FORM]'"),
    (dict(Ts=1, model="auto", method="elms"), "model='auto' needs method='ga'"),
])
def test_identify_errors_name_the_argument(records, kwargs, frag):
    u, y, _ = records["fopdt"]
    with pytest.raises(ValueError, match=re.escape(frag)):
        pdtfit.identify(u, y, **kwargs)


@pytest.mark.parametrize("bad, where", [(np.inf, "y[17] is inf"), (-np.inf, "y[17] is -inf")])
def test_identify_errors_name_the_sample(records, bad, where):
    """An infinite y and a u that is not finite are refused naming the
    sample (a NaN in y is a missing sample: test_binding)."""
    u, y, fs = records["fopdt"]
    y = np.array(y)
    y[17] = bad
    y[40] = bad
    with pytest.raises(ValueError, match=re.escape(where) + r".*2 samples not"):
        pdtfit.identify(u, y, fs)
    with pytest.raises(ValueError, match=r"u\[3\] is nan"):
        pdtfit.identify(np.r_[u[:3], np.nan, u[4:]], np.asarray(records["fopdt"][1]), fs)


def test_outlier_names_the_sample(records):
    """A gross outlier of u is refused naming it (one of y is left out of
    the fit by the screen)."""
    u, y, fs = records["fopdt"]
    u = np.array(u)
    u[123] = -3e38
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.identify(u, y, fs)
    assert e.value.status == "PDT_ERR_OUTLIER" and "u[123] = -3e+38" in str(e.value)


@pytest.mark.parametrize("call, frag", [
    (lambda m: pdtfit.tune(m, "simc", tau_c=-1), "tau_c must be a time >= 0 s"),
    (lambda m: pdtfit.tune(m, "imc", tau_c=1), "tau_c is the knob of rule='simc' only"),
    (lambda m: pdtfit.tune(m, ms_max=1), "ms_max must be a limit > 1"),
    (lambda m: pdtfit.tune(m, u_span=10), "u_span and y_span go together"),
    (lambda m: pdtfit.tune(m, "simc", Ku=2, Pu=3), "Ku and Pu are inputs of rule='zn' only"),
    (lambda m: pdtfit.reduce(1.0, [2.0, -1.0]), "lags[1] must be a time constant > 0 s"),
    (lambda m: pdtfit.reduce(1.0, [2.0], delay=-1), "delay must be a dead time >= 0 s"),
    (lambda m: pdtfit.read_csv("x.csv", fs=-1), "fs must be a sampling frequency > 0 Hz"),
])
def test_tune_reduce_errors_name_the_argument(call, frag):
    m = pdtfit.model("fopdt", 2.0, 1.0, tau=5.0)
    with pytest.raises(ValueError, match=re.escape(frag)):
        call(m)


def cli_json(*args, status=0):
    res = cli.run([str(a) for a in args])
    assert res.returncode == status, res.stderr
    return json.loads(res.stdout)


def same(py, want):
    assert py == want and list(py) == list(want)


@cli_test
@pytest.mark.parametrize("name, args, kwargs", [
    ("sopdt", ["--model", "auto"], dict(model="auto")),
    ("fopdt", ["--model", "auto", "--seed", "5"], dict(model="auto", seed=5)),
    ("fopdt", ["--model", "fopdt", "--offset", "estimate"], dict(offset="estimate")),
    ("fopdt", ["--model", "fopdt", "--offset", "rest"], dict(offset="rest")),
    ("fopdt", ["--model", "fopdt", "--uncertainty", "bootstrap", "--bootstrap", "8"],
     dict(uncertainty="bootstrap", bootstrap=8)),
    ("sopdt", ["--model", "sopdt", "--bootstrap", "6"], dict(model="sopdt", bootstrap=6)),
    ("sopdt", ["--model", "sopdt", "--uncertainty", "fisher"],
     dict(model="sopdt", uncertainty="fisher")),
    ("fopdt", ["--model", "fopdt", "--weight", "band", "--band", "0:0.05", "--td-max", "20",
               "--population", "20", "--evaluations", "3000", "--integer-delay"],
     dict(weight="band", band=(0, 0.05), td_max=20, population=20, evaluations=3000,
          integer_delay=True)),
    ("fopdt", ["--model", "fopdt", "--tune", "simc:pid", "--tau-c", "2", "--u-span", "100",
               "--y-span", "50", "--deriv-filter", "10"],
     dict(tune="simc:pid", tau_c=2, u_span=100, y_span=50, deriv_filter=10)),
    ("sopdt", ["--model", "sopdt", "--tune", "imc:pid", "--lambda", "8"],
     dict(model="sopdt", tune="imc:pid", lambda_=8)),
])
def test_identify_equals_the_program_field_by_field(records, write_csv, name, args, kwargs):
    u, y, fs = records[name]
    path = write_csv("uy.csv", {"u": u, "y": y})
    want = cli_json("identify", *args, "--fs", fs, path)
    same(pdtfit.identify(u, y, fs, **kwargs).as_dict(), want)


@cli_test
@pytest.mark.parametrize("args, kwargs", [
    (["--tune", "zn:pid"], dict(tune="zn:pid")),
    (["--tune", "simc", "--fit-min", "99.9"], dict(tune="simc", fit_min=99.9)),
])
def test_identify_tune_refused_equals_the_program(records, write_csv, args, kwargs):
    u, y, fs = records["fopdt"]
    path = write_csv("uy.csv", {"u": u, "y": y})
    want = cli_json("identify", "--model", "fopdt", *args, "--fs", fs, path, status=4)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        got = pdtfit.identify(u, y, fs, **kwargs).as_dict()
    same(got, want)
    assert got["tune"]["status"] in ("PDT_ERR_MS_LIMIT", "PDT_ERR_POOR_FIT")
    assert any("tuning refused" in str(x.message) for x in w)


MODEL = ["--model", "fopdt", "--K", "2", "--tau", "10", "--Td", "2"]


@cli_test
@pytest.mark.parametrize("args, kwargs", [
    (["--rule", "amigo", "--form", "pid"], dict(rule="amigo", form="pid")),
    (["--rule", "zn", "--form", "pid", "--ms-max", "0"], dict(rule="zn", form="pid", ms_max=0)),
    (["--rule", "zn", "--Ku", "3", "--Pu", "7"], dict(rule="zn", Ku=3, Pu=7)),
    (["--rule", "imc", "--u-span", "50", "--y-span", "200", "--lambda", "3"],
     dict(rule="imc", u_span=50, y_span=200, lambda_=3)),
])
def test_tune_equals_the_program(args, kwargs):
    want = cli_json("tune", *args, *MODEL)
    same(pdtfit.tune(pdtfit.model("fopdt", 2.0, 2.0, tau=10.0), **kwargs).as_dict(), want)


@cli_test
def test_tune_relay_without_model_equals_the_program():
    want = cli_json("tune", "--rule", "zn", "--form", "pid", "--Ku", "3", "--Pu", "7")
    same(pdtfit.tune(None, "zn", "pid", Ku=3, Pu=7).as_dict(), want)


@cli_test
def test_tune_refusal_reason_is_the_programs():
    res = cli.run(["tune", "--rule", "zn", "--form", "pid", *MODEL])
    assert res.returncode == 1
    with pytest.raises(pdtfit.PdtError) as e:
        pdtfit.tune(pdtfit.model("fopdt", 2.0, 2.0, tau=10.0), "zn", "pid")
    assert e.value.status == "PDT_ERR_MS_LIMIT"
    assert res.stderr.strip() == f"pdtfit: tune: {e.value.reason}"


@cli_test
@pytest.mark.parametrize("args, kwargs", [
    (["--gain", "2", "--lags", "10,3,1", "--zeros", "-0.5", "--delay", "1", "--method",
      "skogestad", "--model", "fopdt"],
     dict(gain=2, lags=[10, 3, 1], zeros=[-0.5], delay=1)),
    (["--gain", "2", "--lags", "10,3,1", "--model", "sopdt", "--method", "sung"],
     dict(gain=2, lags=[10, 3, 1], model="sopdt", method="sung")),
    (["--gain", "1", "--lags", "5,2", "--h", "0.5", "--method", "skogestad", "--model",
      "fopdt"],
     dict(gain=1, lags=[5, 2], h=0.5)),
])
def test_reduce_equals_the_program(args, kwargs):
    same(pdtfit.reduce(**kwargs).as_dict(), cli_json("reduce", *args))


@cli_test
def test_read_csv_units_row_and_date_form_equal_the_program(tmp_path):
    rows = ["Zeit;CV [%];PV [degC]", "s;%;degC"]
    for k in range(80):
        y = 20 + (0.6 * (1 - np.exp(-(k - 12) / 5)) if k > 12 else 0.0)
        rows.append(f"01.03.2024 08:00:{k // 2:02d},{5 * (k % 2)}00;{5 if k > 10 else 0};"
                    + f"{y:.6f}".replace(".", ","))
    path = tmp_path / "plc.csv"
    path.write_text("\n".join(rows) + "\n")
    res = cli.run(["identify", "--model", "fopdt", "--t", "zeit", "--u", "CV [%]", "--y", "pv",
                   path])
    assert res.returncode == 0 and "units under the header" in res.stderr
    rec = pdtfit.read_csv(path, t="zeit", u="cv", y="PV [degC]")
    assert rec.units_row == 2 and rec.n == 80 and rec.Ts == pytest.approx(0.5)
    same(pdtfit.identify(rec.u, rec.y, Ts=rec.Ts).as_dict(), json.loads(res.stdout))
    assert pdtfit.read_csv(path, t="zeit", u="cv", y="pv", units_row=True).units_row == 0
