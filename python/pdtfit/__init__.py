"""pdtfit from Python: FOPDT/SOPDT identification, PI/PID tuning and model
reduction, computed by the pdtfit C library (the float or double build it
was compiled with) and returned with the field names of the pdtfit command
line's JSON. Every option of `pdtfit identify`, `pdtfit tune` and
`pdtfit reduce` is a keyword argument of the function of the same name.

    import pdtfit
    rec = pdtfit.read_csv("step.csv")
    r = pdtfit.identify(rec.u, rec.y, Ts=rec.Ts, model="auto", seed=1)
    print(r.model, r.K, r.Td, r.fit, r.std)
    print(pdtfit.tune(r, rule="simc", form="pi").Kc)

Functions (help(pdtfit.identify) etc. for each):
    identify(u, y, fs=None, model="fopdt", ...)  a model from one record
    tune(model_or_result, rule="simc", form="pi", ...)  PI/PID gains
    reduce(gain, lags, zeros=(), delay=0.0, ...)  a FOPDT/SOPDT from a
                                                  detailed model
    model(kind, K, Td, ...)   a model from its parameters
    read_csv(path, ...)       a record, with the command line's reader
Results: IdentResult, Model, TuneResult (attributes = the JSON's keys,
.as_dict() = the JSON object), Record. Refusals raise PdtError (.status
the pdt_status_t name), bad arguments ValueError naming the argument or
the sample. __version__ is the library's (pdt_common.h). docs/python.md
in the source distribution has the same text with examples.
"""
import ctypes
import json
import math

import numpy as np

from . import _lib
from ._lib import lib

__all__ = ["PdtError", "Model", "IdentResult", "TuneResult", "Record", "identify", "tune",
           "reduce", "model", "read_csv", "identify_many", "STATUS_NAMES", "REAL_BYTES", "__version__"]

__version__ = _lib.VERSION
"""The library's version, PDT_VERSION_* of pdt_common.h (the one place it
is kept)."""

STATUS_NAMES = dict(_lib.STATUS_NAMES)
"""{code: name} of every pdt_status_t in pdt_status.h, the name the
library's pdt_status_name gives ("PDT_ERR_NO_EXCITATION"), as the command
line's JSON prints it."""

REAL_BYTES = lib.pdtpy_real_size()
"""4 in the float build of the library, 8 in the double build."""

_JSON_LEN = 16384


class PdtError(Exception):
    """The library refused. .status is the status's name as pdt_status_name
    and the command line's JSON give it ("PDT_ERR_NO_EXCITATION",
    "PDT_ERR_MS_LIMIT", ...), .code its value, .reason the one-line reason
    (the library's description, pdt_status_str, or the figure that
    decided a refusal, as the command line words it); str(e) says which
    call refused and why."""

    def __init__(self, code, what, detail="", reason=None):
        self.code = int(code)
        self.status = lib.pdtpy_status_name(self.code).decode()
        text = lib.pdtpy_status_str(self.code).decode()
        self.reason = reason or f"{text}{detail}"
        super().__init__(f"{what}: {self.reason} ({self.status})")


def _check(code, what, detail="", reason=None):
    if code == _lib.NOMEM:
        raise MemoryError(f"{what}: out of memory")
    if code != 0:
        raise PdtError(code, what, detail, reason)


def _parse(buf):
    return json.loads(buf.value.decode())


def _choice(table, value, what):
    key = str(value).lower()
    if key not in table:
        raise ValueError(f"unknown {what} {value!r} ({', '.join(sorted(table))})")
    return table[key]


def _darray(x, name="u and y", missing=False):
    """x as a contiguous float64 array and its C pointer; a ValueError names
    the argument, or the first sample that is not finite (missing: that is
    infinite, a NaN being a missing sample)."""
    try:
        a = np.ascontiguousarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name} must be a sequence of numbers ({e})") from None
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    bad = np.flatnonzero(np.isinf(a) if missing else ~np.isfinite(a))
    if len(bad):
        k = int(bad[0])
        raise ValueError(f"{name}[{k}] is {a[k]}: every sample must be finite "
                         f"({len(bad)} sample{'s' if len(bad) > 1 else ''} not)")
    return a, a.ctypes.data_as(_lib.D)


def _real(name, v, test=None, what=None):
    """v as a float, NaN for None; a ValueError names the argument when v is
    not a finite number or fails test (what: what it must be)."""
    if v is None:
        return math.nan
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {v!r}") from None
    if not math.isfinite(f) or (test is not None and not test(f)):
        raise ValueError(f"{name} must be {what or 'finite'}, got {v!r}")
    return f


def _whole(name, v, lo, hi, what):
    """v as an int in [lo, hi], 0 for None; a ValueError names the argument."""
    if v is None:
        return 0
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
        raise ValueError(f"{name} must be {what}, got {v!r}")
    return int(v)


def _num(d, key):
    v = d.get(key)
    return math.nan if v is None else float(v)


class _Json:
    """Fields of a JSON object as attributes (null -> None)."""

    def __init__(self, d):
        object.__setattr__(self, "_d", d)

    def __getattr__(self, name):
        d = object.__getattribute__(self, "_d")
        key = "lambda" if name == "lambda_" else name
        if key in d:
            return d[key]
        raise AttributeError(name)

    def __setattr__(self, name, value):
        raise AttributeError("pdtfit results are read-only")

    def as_dict(self):
        """The object the command line prints, key for key."""
        return json.loads(json.dumps(self._d))

    def __repr__(self):
        return f"{type(self).__name__}({json.dumps(self._d)})"


class Model(_Json):
    """A FOPDT or SOPDT model with the fields `pdtfit reduce` prints:
    model ("fopdt"/"sopdt"), K, tau, Td (fopdt) or K, wn, zeta, Td, tau1,
    tau2, a, b (sopdt; Ki for an integrator)."""

    def __init__(self, d, native):
        super().__init__(d)
        object.__setattr__(self, "_native", tuple(native))


class IdentResult(Model):
    """The result of identify: the model's fields plus y0, u0, cost, fit,
    evaluations (and f_band with the control weighting), as `pdtfit
    identify` prints them; also .u, .y, .Ts of the record."""

    def __init__(self, d, native, u, y, Ts):
        super().__init__(d, native)
        object.__setattr__(self, "u", u)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "Ts", Ts)

    def simulate(self):
        """The model's output on the record's input (from rest at u0, y0),
        as the fit is computed: an array like y."""
        u, pu = _darray(self.u)
        y, py = _darray(self.y, missing=True)
        out = np.empty(len(u))
        _check(lib.pdtpy_simulate(_lib.darray(self._native), self.Ts, pu, py, len(u),
                                  float(self.u0), float(self.y0), out.ctypes.data_as(_lib.D)),
               "simulate")
        return out

    def plot(self):
        """A matplotlib figure: the record against the model, and the
        residual, with the parameters in the title. Needs matplotlib."""
        try:
            import matplotlib.figure
        except ImportError as e:
            raise ImportError("result.plot() needs matplotlib (pip install matplotlib)") from e
        ysim = self.simulate()
        t = np.arange(len(self.y)) * self.Ts
        fig = matplotlib.figure.Figure(figsize=(8, 5))
        ax, ax_r = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1]})
        ax.plot(t, self.y, label="y (data)", lw=1)
        ax.plot(t, ysim, label="model", lw=1.5)
        ax.set_ylabel("y")
        ax.legend(loc="best")
        ax_r.plot(t, np.asarray(self.y) - ysim, lw=1)
        ax_r.set_ylabel("residual")
        ax_r.set_xlabel("t, s")
        keys = ("K", "tau", "Td") if self.model == "fopdt" else ("K", "wn", "zeta", "Td")
        pars = ", ".join(f"{k} {self._d[k]:.4g}" for k in keys if self._d.get(k) is not None)
        fig.suptitle(f"{self.model.upper()}: {pars}, fit {self.fit:.1f} %")
        return fig


class TuneResult(_Json):
    """Gains and robustness with the fields `pdtfit tune` prints: rule,
    form, Kc, tauI, tauD, Tf (ideal form), Ms, gain_margin,
    phase_margin_deg, w_ms, w_pc, w_gc, series (a dict or None),
    stated_in, and tau_c (simc) or lambda (imc; attribute lambda_)."""


class Record:
    """One record read by read_csv: u, y (numpy arrays), Ts (s), fs (Hz), n,
    and what the reader did: jitter_warn (time stamps off the grid within
    its tolerance), filled (samples filled by resampling), units_row (the
    line of a units row found under the header and skipped, else 0)."""

    def __init__(self, u, y, Ts, jitter_warn=0, filled=0, units_row=0):
        self.u, self.y, self.Ts = u, y, Ts
        self.jitter_warn, self.filled, self.units_row = jitter_warn, filled, units_row

    @property
    def fs(self):
        return 1.0 / self.Ts

    @property
    def n(self):
        return len(self.u)

    def __repr__(self):
        return f"Record(n={self.n}, Ts={self.Ts!r})"


def _opt(v):
    return math.nan if v is None else float(v)


_GA_ONLY = ("cost", "seed", "evaluations", "population", "weight", "band", "phi_t", "phi_f",
            "integer_delay", "coarse", "offset", "u_before", "initial", "drift")
_TUNE_KEYS = ("tau_c", "lambda_", "ms_max", "deriv_filter", "u_span", "y_span", "fit_min")


def _ident_opts(model, method, cost, seed, evaluations, population, td_max, weight, band,
                phi_t, phi_f, integer_delay, coarse, offset, u_before, initial, drift):
    """The checked options of identify as a pdtpy_ident_opts_t."""
    o = _lib.IdentOpts()
    o.method = _choice(_lib.METHODS, method, "method")
    if o.method != _lib.METHODS["ga"]:
        given = dict(cost=cost != "simulation", seed=seed != 1, evaluations=evaluations,
                     population=population, weight=weight, band=band, phi_t=phi_t,
                     phi_f=phi_f, integer_delay=integer_delay, coarse=coarse,
                     offset=offset != "auto", u_before=u_before, initial=initial != "auto",
                     drift=drift)
        extra = [k for k in _GA_ONLY if given[k] not in (None, False)]
        if extra:
            raise ValueError(f"{', '.join(extra)}: options of method='ga' only")
    models = dict(_lib.MODELS, auto=_lib.MODEL_AUTO)
    o.model = _choice(models, model, "model")
    if o.model == _lib.MODEL_AUTO and o.method != _lib.METHODS["ga"]:
        raise ValueError("model='auto' needs method='ga'")
    o.cost = _choice(_lib.COSTS, cost, "cost")
    o.offset = _choice(_lib.OFFSETS, offset, "offset")
    o.weight = -1 if weight is None else _choice(_lib.WEIGHTS, weight, "weight")
    if (band is not None) != (o.weight == _lib.WEIGHTS["band"]):
        raise ValueError("band=(f_lo, f_hi) goes with weight='band'")
    if band is not None:
        if len(band) != 2:
            raise ValueError(f"band must be (f_lo, f_hi) in Hz, got {band!r}")
        o.f_lo = _real("band[0]", band[0], lambda f: f >= 0, "a frequency >= 0 Hz")
        o.f_hi = _real("band[1]", band[1], lambda f: f >= o.f_lo, "a frequency >= band[0]")
    o.integer_delay = int(bool(integer_delay))
    o.seed = _whole("seed", seed, 0, 2**64 - 1, "a whole number >= 0")
    o.evaluations = _whole("evaluations", evaluations, 1, 2**32 - 1, "a whole number >= 1")
    o.population = _whole("population", population, 4, _lib.MAX_POPULATION,
                          f"an even number from 4 to {_lib.MAX_POPULATION}")
    if o.population % 2:
        raise ValueError(f"population must be an even number, got {population!r}")
    o.coarse = _whole("coarse", coarse, 0, 2**32 - 1, "a whole number >= 0")
    ga = o.method == _lib.METHODS["ga"]
    o.td_max = _real("td_max", td_max, (lambda f: f > 0) if ga else (lambda f: f >= 0),
                     "a dead time > 0 s" if ga else "a dead time >= 0 s")
    o.phi_t = _real("phi_t", phi_t, lambda f: f >= 0, "a weight >= 0")
    o.phi_f = _real("phi_f", phi_f, lambda f: f >= 0, "a weight >= 0")
    if phi_t is not None and phi_f is not None and o.phi_t == 0 and o.phi_f == 0:
        raise ValueError("phi_t and phi_f cannot both be 0")
    o.u_before = _real("u_before", u_before)
    o.initial = _choice({"auto": 0, "rest": 1, "estimate": 2}, initial, "initial")
    o.drift = int(bool(drift))
    if (o.initial == 2 or o.drift) and o.cost != _lib.COSTS["simulation"]:
        raise ValueError("initial='estimate' and drift=True need cost='simulation'")
    return o


def _outlier_detail(u, y):
    """Which sample is a gross outlier, as the command line names it."""
    n = len(u)
    ku = lib.pdtpy_outlier(u.ctypes.data_as(_lib.D), n)
    ky = lib.pdtpy_outlier(y.ctypes.data_as(_lib.D), n)
    in_y = ky < n and (ku >= n or ky <= ku)
    k = ky if in_y else ku
    if k >= n:
        return ""
    name, x = ("y", y) if in_y else ("u", u)
    return f": {name}[{k}] = {x[k]:g}, orders of magnitude off the rest of the record"


def identify(u, y, fs=None, model="fopdt", cost="simulation", seed=1, *, Ts=None,
             method="ga", evaluations=None, population=None, td_max=None, weight=None,
             band=None, phi_t=None, phi_f=None, integer_delay=False, coarse=None,
             offset="auto", uncertainty="auto", bootstrap=None, tune=None, tau_c=None,
             lambda_=None, ms_max=None, deriv_filter=None, u_span=None, y_span=None,
             fit_min=None, u_before=None, missing="exclude", initial="auto", drift=False):
    """Identifies a FOPDT or SOPDT model from one record, as
    `pdtfit identify` does with the same options (docs/cli.md).

    u, y        the input and output, sequences of equal length (engineering
                units, finite; a NaN in y is a missing sample, see missing);
                the record should start at rest.
    fs or Ts    the sampling frequency (Hz) or period (s): exactly one.
    model       "fopdt", "sopdt", or "auto": both, and the order the
                evidence supports (the JSON's "order" says why).
    method      "ga" (default: pdt_identify's searches), "elms" or "eiv"
                (the least-squares delay scans; they take model and td_max
                only, another option with them is a ValueError).
    cost        "simulation" (default, the output error), "prediction",
                "frequency" or "combined" (weights phi_t, phi_f >= 0).
    seed        the searches' seed (whole number >= 0); the same seed, data
                and build give the same result.
    evaluations the search budget (>= 1; None: the library's, 9000);
    population  the population (even, 4 .. the library's maximum).
    td_max      the largest dead time searched, s (> 0; None: a third of
                the record).
    weight      "auto", "control", "uniform", or "band" with
                band=(f_lo, f_hi) in Hz: the frequency weighting.
    integer_delay  the dead time in whole samples.
    coarse      the searches' coarse record: None automatic, 1 the whole
                record, D a record D times coarser.
    offset      "auto" (default), "estimate" (y0 fitted with the model) or
                "rest" (y0 the output's mean over the record's rest window).
    u_before    the input before the first sample (`--u-before`; None: the
                first sample's).
    missing     a NaN in y is a missing sample: "exclude" (default) leaves
                it out of the fit and counts it (the result's "excluded"),
                "refuse" refuses the record (PDT_ERR_NONFINITE).
    initial     "auto" (default) tests whether the record starts at rest
                and, where it does not, identifies it again with its state
                estimated (flag mid_transient where that does not explain
                its start); "rest" does not test; "estimate" fits the
                model's free response from the first sample with the gain
                and offset (the result's "initial" and "x0", a SOPDT's
                "dx0"). With cost="simulation".
    drift       also fit a linear drift of the output (the result's
                "drift", units of y per second; y0 is then the level at the
                record's middle). With cost="simulation".
    uncertainty how "std", "cov" and "ci95" are found: "auto" (default:
                the Fisher information for a FOPDT, the bootstrap for a
                SOPDT), "fisher", or "bootstrap" (a parametric bootstrap:
                records simulated from the model with the residual's noise,
                identified again; docs/uncertainty.md).
    bootstrap   the bootstrap's runs (2 .. 100000; None: 50).
    tune        "RULE[:FORM]" (e.g. "simc:pid"): also tune the model as
                `identify --tune` does, with tau_c, lambda_, ms_max,
                deriv_filter, u_span, y_span, fit_min as for tune(). The
                result's "tune" is the TuneResult's object, or, when the
                gains are refused, {"status", "reason", "rule", "form"}
                with the model kept (a RuntimeWarning says why).

    Returns an IdentResult: the JSON's keys as attributes (model, K, tau,
    Td or K, wn, zeta, tau1, tau2, a, b, Ki; y0, u0, cost, fit,
    evaluations, searches, coarse, runner_up, flags, excluded, evidence;
    std and cov (every printed parameter, by its name), ci95 and
    bootstrap_runs with the bootstrap, uncertainty; Ts, n; order with
    model="auto"). Raises ValueError for a bad argument (naming it, or the
    first sample of u that is not finite, of y that is infinite) and
    PdtError when the library refuses the data or the options
    (PDT_ERR_OUTLIER names the sample).
    """
    if (fs is None) == (Ts is None):
        raise ValueError("give the sampling rate as fs (Hz) or Ts (s), one of them")
    if Ts is not None:
        Ts = _real("Ts", Ts, lambda f: f > 0, "> 0 (a sampling period in s)")
    else:
        Ts = 1.0 / _real("fs", fs, lambda f: f > 0, "> 0 (a sampling frequency in Hz)")
    u, pu = _darray(u, "u")
    y, py = _darray(y, "y", missing=True)
    if len(u) != len(y):
        raise ValueError(f"u has {len(u)} samples, y {len(y)}")
    if str(method).lower() != "ga" and (uncertainty != "auto" or bootstrap is not None):
        raise ValueError("uncertainty, bootstrap: options of method='ga' only")
    o = _ident_opts(model, method, cost, seed, evaluations, population, td_max, weight, band,
                    phi_t, phi_f, integer_delay, coarse, offset, u_before, initial, drift)
    o.refuse_missing = _choice({"exclude": 0, "refuse": 1}, missing, "missing")
    o.uncertainty = _choice({"auto": 0, "fisher": 1, "bootstrap": 2}, uncertainty,
                            "uncertainty")
    o.boot_runs = _whole("bootstrap", bootstrap, 2, 100000, "a run count 2 .. 100000")
    if bootstrap is not None and o.uncertainty == 1:
        raise ValueError("bootstrap goes with uncertainty='auto' or 'bootstrap'")
    topts = dict(tau_c=tau_c, lambda_=lambda_, ms_max=ms_max, deriv_filter=deriv_filter,
                 u_span=u_span, y_span=y_span, fit_min=fit_min)
    if tune is None and any(v is not None for v in topts.values()):
        raise ValueError("the tuning options (" + ", ".join(k for k, v in topts.items()
                                                             if v is not None)
                         + ") go with tune='RULE[:FORM]'")
    rule_form = _rule_form(tune) if tune is not None else None
    native = (ctypes.c_double * 5)()
    buf = ctypes.create_string_buffer(_JSON_LEN)
    code = lib.pdtpy_identify(pu, py, len(u), Ts, ctypes.byref(o), native, buf, _JSON_LEN)
    _check(code, "identify", _outlier_detail(u, y) if code == _lib.STATUS_CODE["OUTLIER"]
           else "")
    d = _parse(buf)
    if rule_form is not None:
        d["tune"] = _tune_of_ident(d, native, rule_form, topts)
    return IdentResult(d, native, u, y, Ts)


def identify_many(records, model="fopdt", cost="simulation", seed=1, *, method="ga",
                  evaluations=None, population=None, td_max=None, weight=None, band=None,
                  phi_t=None, phi_f=None, integer_delay=False, coarse=None, offset="auto",
                  uncertainty="auto", bootstrap=None, tune=None, tau_c=None, lambda_=None,
                  ms_max=None, deriv_filter=None, u_span=None, y_span=None, fit_min=None,
                  u_before=None, missing="refuse", initial=None, drift=False):
    """Identifies one FOPDT or SOPDT model from several records of one
    process, as `pdtfit identify FILE FILE ...` does (docs/several-records.md).

    records     a sequence of 2 .. 8 tuples (u, y, fs): each record's input
                and output (sequences of equal length, finite) and its
                sampling frequency in Hz. Each record has its own sampling
                period, its own input operating point (its u[0]), its own
                output offset and, with initial="estimate", its own state
                at the first sample (with drift=True its own drift); the
                dynamics (K, tau, Td, or the SOPDT's) are shared. The
                answer is the joint output-error optimum over all records.

    The keyword options are identify()'s, with these differences, each a
    ValueError when asked for: method "ga" and cost "simulation" only; no
    weight, band, phi_t, phi_f, integer_delay, u_before; coarse None or 1
    (the searches run on the whole records); offset "auto" or "estimate"
    (both estimate each record's offset); initial None (= "rest") or
    "rest" or "estimate" ("auto"'s test and refit take one record);
    missing "refuse" (a NaN in any y is a ValueError naming the record and
    the sample); uncertainty "auto" (no bootstrap: the result's std, cov
    and uncertainty are None, docs/several-records.md). tune and its
    options tune the joint model as identify() does.

    Returns an IdentResult with the keys of identify()'s (those of the
    first record: its y0, u0, Ts, n; fit and cost over all records) plus
    record_fit (a list, one dict per record: n, Ts, u0, y0, fit, cost,
    x0, dx0, drift), records and samples; .u, .y, .Ts are the first
    record's. Raises PdtError when the library refuses a record (e.g.
    PDT_ERR_NO_EXCITATION, PDT_ERR_TOO_SHORT for the dead-time bound).
    """
    recs = list(records)
    if not 2 <= len(recs) <= _lib.MAX_RECORDS:
        raise ValueError(f"records must hold 2 .. {_lib.MAX_RECORDS} (u, y, fs) tuples, "
                         f"got {len(recs)}")
    refused = dict(method=str(method).lower() != "ga", cost=str(cost).lower() != "simulation",
                   weight=weight is not None, band=band is not None, phi_t=phi_t is not None,
                   phi_f=phi_f is not None, integer_delay=bool(integer_delay),
                   coarse=coarse not in (None, 0, 1), offset=str(offset).lower() == "rest",
                   u_before=u_before is not None, missing=str(missing).lower() != "refuse",
                   initial=initial is not None and str(initial).lower() == "auto",
                   model=str(model).lower() == "auto", uncertainty=uncertainty != "auto",
                   bootstrap=bootstrap is not None)
    bad = [k for k, v in refused.items() if v]
    if bad:
        raise ValueError(f"identify_many: {', '.join(bad)}: not with several records "
                         "(docs/several-records.md)")
    arrays, Ts = [], []
    for r, rec in enumerate(recs):
        if len(rec) != 3:
            raise ValueError(f"records[{r}] must be (u, y, fs)")
        u, _ = _darray(rec[0], f"records[{r}] u")
        y, _ = _darray(rec[1], f"records[{r}] y")
        if len(u) != len(y):
            raise ValueError(f"records[{r}]: u has {len(u)} samples, y {len(y)}")
        Ts.append(1.0 / _real(f"records[{r}] fs", rec[2], lambda f: f > 0,
                              "> 0 (a sampling frequency in Hz)"))
        arrays.append((u, y))
    o = _ident_opts(model, "ga", "simulation", seed, evaluations, population, td_max, None,
                    None, None, None, False, coarse, offset, None,
                    "rest" if initial is None else initial, drift)
    o.refuse_missing = 1
    topts = dict(tau_c=tau_c, lambda_=lambda_, ms_max=ms_max, deriv_filter=deriv_filter,
                 u_span=u_span, y_span=y_span, fit_min=fit_min)
    if tune is None and any(v is not None for v in topts.values()):
        raise ValueError("the tuning options go with tune='RULE[:FORM]'")
    rule_form = _rule_form(tune) if tune is not None else None
    count = len(recs)
    up = (_lib.D * count)(*[a[0].ctypes.data_as(_lib.D) for a in arrays])
    yp = (_lib.D * count)(*[a[1].ctypes.data_as(_lib.D) for a in arrays])
    ns = (ctypes.c_size_t * count)(*[len(a[0]) for a in arrays])
    ts = (ctypes.c_double * count)(*Ts)
    native = (ctypes.c_double * 5)()
    buf = ctypes.create_string_buffer(_JSON_LEN)
    _check(lib.pdtpy_identify_many(up, yp, ns, ts, count, ctypes.byref(o), native, buf,
                                   _JSON_LEN), "identify_many")
    d = _parse(buf)
    if rule_form is not None:
        d["tune"] = _tune_of_ident(d, native, rule_form, topts)
    return IdentResult(d, native, arrays[0][0], arrays[0][1], Ts[0])


def _rule_form(spec):
    """(rule, form) of "RULE[:FORM]"."""
    rule, _, form = str(spec).partition(":")
    if rule.lower() not in _lib.RULES or (form and form.lower() not in _lib.FORMS):
        raise ValueError(f"tune must be 'RULE[:FORM]', RULE simc, imc, amigo or zn, FORM pi "
                         f"or pid, got {spec!r}")
    return rule.lower(), (form or "pi").lower()


def _tune_of_ident(d, native, rule_form, topts):
    """identify's "tune": the gains, or the refusal with the model kept."""
    import warnings
    try:
        return tune(Model(d, native), rule_form[0], rule_form[1], fit=d["fit"],
                    **topts).as_dict()
    except PdtError as e:
        warnings.warn(f"identify: the model is kept, its tuning refused: {e}", RuntimeWarning,
                      stacklevel=3)
        return {"status": e.status, "reason": e.reason, "rule": rule_form[0],
                "form": rule_form[1]}


def model(kind, K=None, Td=0.0, *, tau=None, wn=None, zeta=None, tau1=None, tau2=None,
          Ki=None, T=None):
    """A model from its parameters, for tune() or to compare with a result.

    model("fopdt", K, Td, tau=...)          K e^(-Td s) / (tau s + 1)
    model("sopdt", K, Td, wn=..., zeta=...) K wn^2 e^(-Td s) / (s^2 + 2 zeta wn s + wn^2)
    model("sopdt", K, Td, tau1=..., tau2=...)  K e^(-Td s) / ((tau1 s + 1)(tau2 s + 1))
    model("sopdt", Td=..., Ki=..., T=...)   Ki e^(-Td s) / (s (T s + 1))

    kind is "fopdt" or "sopdt"; times in s. Returns a Model; PdtError
    when the library refuses the
    parameters (PDT_ERR_ARG: e.g. tau <= 0, Td < 0)."""
    kind_v = _choice(_lib.MODELS, kind, "model")
    out = (ctypes.c_double * 5)()
    if kind_v == _lib.MODELS["fopdt"]:
        args = (0, K, tau, 0.0)
    elif wn is not None or zeta is not None:
        args = (_lib.SOPDT_NATURAL, K, wn, zeta)
    elif tau1 is not None or tau2 is not None:
        args = (_lib.SOPDT_TC, K, tau1, tau2)
    else:
        args = (_lib.SOPDT_INTEG, Ki, T, 0.0)
    if any(a is None for a in args):
        raise ValueError(f"model({kind!r}): parameters missing")
    _check(lib.pdtpy_model_make(kind_v, args[0], float(args[1]), float(args[2]),
                                float(args[3]), float(Td), out), "model")
    return _model_of(out)


def _model_of(native):
    buf = ctypes.create_string_buffer(_JSON_LEN)
    if lib.pdtpy_model_json(native, buf, _JSON_LEN) < 0:
        raise MemoryError("model: JSON buffer too small")
    return Model(_parse(buf), native)


def _as_model(m):
    if isinstance(m, Model):
        return m
    if isinstance(m, dict):  # a model the command line printed
        if m.get("model") == "fopdt":
            return model("fopdt", m["K"], m["Td"], tau=m["tau"])
        if m.get("Ki") is not None:
            return model("sopdt", Td=m["Td"], Ki=m["Ki"], T=m["tau2"])
        return model("sopdt", m["K"], m["Td"], wn=m["wn"], zeta=m["zeta"])
    raise TypeError("tune() takes a Model, an IdentResult or a dict printed by pdtfit")


def tune(model_or_result=None, rule="simc", form="pi", *, tau_c=None, lambda_=None,
         ms_max=None, deriv_filter=None, u_span=None, y_span=None, fit_min=None, fit=None,
         Ku=None, Pu=None):
    """PI/PID gains of a model by a published rule (pdt_tune_compute) and
    the robustness of the loop they make, as `pdtfit tune` prints them.

    model_or_result  an IdentResult, a Model, or a dict printed by pdtfit
                (identify's JSON); None only with Ku and Pu.
    rule        "simc", "imc", "amigo" or "zn"; form "pi" or "pid".
    tau_c       SIMC's closed-loop time constant, s (>= 0; 0: the dead time).
    lambda_     IMC's lambda, s (>= 0; 0: the rule's default).
    ms_max      the robustness limit: gains whose maximum sensitivity Ms on
                the model exceeds it are refused (> 1, or 0 for none;
                default 2).
    deriv_filter  N of the derivative filter Tf = tauD / N (>= 1, 0 none).
    u_span, y_span  the spans of u and y (> 0, both or neither): adds the
                gains in percent of span ("percent").
    fit_min     refuse below this fit, % (>= 0; default none). The fit is
                the result's (an IdentResult or a dict with "fit"), else
                fit=, else 100.
    Ku, Pu      zn only: classic Ziegler-Nichols from a relay test's
                ultimate gain and period (s); with a model, the figures of
                those gains on it and the Ms limit.

    Returns a TuneResult (rule, form, Kc, tauI, tauD, Tf, Ms, gain_margin,
    phase_margin_deg, w_ms, w_pc, w_gc, series, pid, parallel, [percent],
    stated_in, tau_c or lambda, [Ku, Pu]). Raises PdtError when the gains
    are refused: .status "PDT_ERR_MS_LIMIT" (Ms above ms_max),
    "PDT_ERR_POOR_FIT" (fit below fit_min), "PDT_ERR_UNSTABLE",
    "PDT_ERR_NO_FORM"; .reason the line `pdtfit tune` prints. ValueError
    for a bad argument, naming it.
    """
    o = _lib.TuneOpts()
    o.rule = _choice(_lib.RULES, rule, "rule")
    o.form = _choice(_lib.FORMS, form, "form")
    if tau_c is not None and o.rule != _lib.RULES["simc"]:
        raise ValueError("tau_c is the knob of rule='simc' only")
    if lambda_ is not None and o.rule != _lib.RULES["imc"]:
        raise ValueError("lambda_ is the knob of rule='imc' only")
    if (u_span is None) != (y_span is None):
        raise ValueError("u_span and y_span go together")
    o.tau_c = _real("tau_c", tau_c, lambda f: f >= 0, "a time >= 0 s (0: the dead time)")
    o.lambda_ = _real("lambda_", lambda_, lambda f: f >= 0, "a time >= 0 s (0: the default)")
    o.ms_max = _real("ms_max", ms_max, lambda f: f == 0 or f > 1, "a limit > 1 (or 0 for none)")
    o.deriv_filter = _real("deriv_filter", deriv_filter, lambda f: f == 0 or f >= 1,
                           "N >= 1 (or 0 for none)")
    o.fit_min = _real("fit_min", fit_min, lambda f: f >= 0, "a fit in percent >= 0")
    us = _real("u_span", u_span, lambda f: f > 0, "the span of u > 0")
    ys = _real("y_span", y_span, lambda f: f > 0, "the span of y > 0")
    o.span = ys / us if u_span is not None else math.nan
    if (Ku is None) != (Pu is None):
        raise ValueError("Ku and Pu go together")
    if Ku is not None and o.rule != _lib.RULES["zn"]:
        raise ValueError("Ku and Pu are inputs of rule='zn' only")
    o.Ku = _real("Ku", Ku, lambda f: f != 0, "a gain != 0")
    o.Pu = _real("Pu", Pu, lambda f: f > 0, "a period > 0 s")
    m = None
    if model_or_result is not None:
        m = _as_model(model_or_result)
        if fit is None:
            fit = m._d.get("fit") if isinstance(m, IdentResult) else (
                model_or_result.get("fit") if isinstance(model_or_result, dict) else None)
    elif Ku is None:
        raise ValueError("tune() needs a model (or Ku and Pu with rule='zn')")
    o.fit = _real("fit", fit)
    ms = ctypes.c_double(math.nan)
    buf = ctypes.create_string_buffer(_JSON_LEN)
    code = lib.pdtpy_tune(_lib.darray(m._native) if m is not None else None, ctypes.byref(o),
                          ctypes.byref(ms), buf, _JSON_LEN)
    if code == _lib.STATUS_CODE["POOR_FIT"]:
        f = 100.0 if math.isnan(o.fit) else o.fit
        _check(code, "tune", reason=f"gains refused: fit {f:.4g}% below {o.fit_min:.4g}% "
                                    "(--fit-min)")
    if code == _lib.STATUS_CODE["MS_LIMIT"] and not math.isnan(ms.value):
        lim = 2.0 if math.isnan(o.ms_max) else o.ms_max
        _check(code, "tune", reason=f"gains refused: Ms {ms.value:.4g} exceeds the limit "
                                    f"{lim:.4g} (--ms-max; --ms-max 0 prints them)")
    _check(code, "tune")
    return TuneResult(_parse(buf))


def reduce(gain, lags, zeros=(), delay=0.0, model="fopdt", method="skogestad", h=0.0):
    """A FOPDT or SOPDT from the detailed model
    gain prod (Zj s + 1) / prod (Ti s + 1) e^(-delay s), as `pdtfit reduce`
    prints it.

    gain     the steady-state gain (finite).
    lags     the lag time constants Ti, s (each > 0; at least one).
    zeros    the numerator time constants Zj, s (each != 0; negative: a
             right-half-plane zero).
    delay    the dead time, s (>= 0).
    model    "fopdt" or "sopdt".
    method   "skogestad" (the half rule, h the controller period, s, >= 0)
             or "sung" (Sung et al.'s frequency-response fit).

    Returns a Model. Raises ValueError for a bad argument (naming it) and
    PdtError when the library refuses the plant."""
    methods = {"skogestad": 0, "sung": 1}  # pdtpy_reduce's own numbering
    mth = _choice(methods, method, "method")
    kind = _choice(_lib.MODELS, model, "model")
    gain = _real("gain", gain)
    lags, zeros = list(lags), list(zeros)
    if not lags:
        raise ValueError("lags must hold at least one time constant")
    for k, v in enumerate(lags):
        _real(f"lags[{k}]", v, lambda f: f > 0, "a time constant > 0 s")
    for k, v in enumerate(zeros):
        _real(f"zeros[{k}]", v, lambda f: f != 0, "a time constant != 0 s")
    delay = _real("delay", delay, lambda f: f >= 0, "a dead time >= 0 s")
    h = _real("h", h, lambda f: f >= 0, "a controller period >= 0 s")
    native = (ctypes.c_double * 5)()
    buf = ctypes.create_string_buffer(_JSON_LEN)
    _check(lib.pdtpy_reduce(mth, kind, gain, _lib.darray(lags), len(lags),
                            _lib.darray(zeros), len(zeros), delay, h, native,
                            buf, _JSON_LEN), "reduce")
    return Model(_parse(buf), native)


def read_csv(path, t=None, u=None, y=None, *, fs=None, sep=None, decimal=None, skip=0,
             time_unit=None, resample=False, units_row=False, time_format=None,
             bad_value=(), bad_rows="missing"):
    """Reads u, y and the sampling period from a CSV file with the reader of
    `pdtfit identify` (the same options, docs/cli.md).

    path        the file (str or Path).
    t, u, y     the columns: names (matched as the command line matches
                them) or 1-based indexes; by default t, u, y.
    fs          the sampling frequency, Hz, for a file without a time
                column (or to check the time column against).
    sep         the field separator (",", ";", tab or " "; None: detected).
    decimal     the decimal mark ("." or ","; None: ".").
    skip        lines to skip before the header (>= 0).
    time_unit   "s", "ms", "us", "min" or "h": the time column's unit
                (None: the header's, "t [ms]", "time_ms", else s).
    resample    fill gaps on the median interval by zero-order hold.
    units_row   one row of units under the header, to skip (without it a
                units row is found and skipped, and Record.units_row says
                on which line).
    time_format the time column's date-time form, strftime-like: %Y %y %m
                %d %H %I %M %S %f %p %z (None: ISO 8601,
                "01.03.2024 08:00:00,500" and "3/1/2024 8:00:00 AM" forms
                are found).
    bad_value   declared bad values (a number or a sequence, -9999, 32767):
                a u or y cell equal to one is a missing sample.
    bad_rows    "missing" (default): missing samples as below; "refuse":
                each is refused with its line (ValueError).

    A missing y (an empty cell, NaN, #N/A, ERR, ...) is NaN in y, a missing
    u the u before it. Returns a Record (u, y, Ts, fs, n, jitter_warn,
    filled, units_row); raises ValueError naming the file, line and column
    of a malformed file."""
    if fs is not None:
        _real("fs", fs, lambda f: f > 0, "a sampling frequency > 0 Hz")
    _whole("skip", skip, 0, 1000000, "a line count 0 .. 1000000")
    o = _lib.CsvOpts()
    o.t_col, o.u_col, o.y_col = (None if c is None else str(c).encode() for c in (t, u, y))
    o.sep = (sep or "\0").encode()
    o.decimal = (decimal or "\0").encode()
    o.skip = int(skip)
    o.time_unit = -1 if time_unit is None else _choice(
        {"s": 0, "ms": 1, "us": 2, "min": 3, "h": 4}, time_unit, "time unit")
    o.resample = int(bool(resample))
    o.fs = float(fs or 0.0)
    o.units_row = int(bool(units_row))
    o.time_format = None if time_format is None else str(time_format).encode()
    bad = np.atleast_1d(np.asarray(bad_value, dtype=np.float64)).copy()
    if bad.ndim != 1 or not np.isfinite(bad).all():
        raise ValueError(f"bad_value must be finite numbers, got {bad_value!r}")
    o.bad_values = bad.ctypes.data_as(_lib.D) if len(bad) else None
    o.n_bad_values = len(bad)
    o.bad_rows = _choice({"missing": 0, "refuse": 1}, bad_rows, "bad_rows")
    s = _lib.Series()
    err = ctypes.create_string_buffer(512)
    if lib.pdtpy_read_series(str(path).encode(), ctypes.byref(o), ctypes.byref(s), err,
                             len(err)) != 0:
        raise ValueError(err.value.decode(errors="replace"))
    try:
        u_a = np.ctypeslib.as_array(s.u, shape=(s.n,)).copy()
        y_a = np.ctypeslib.as_array(s.y, shape=(s.n,)).copy()
        return Record(u_a, y_a, s.Ts, s.jitter_warn, s.filled, s.units_row)
    finally:
        lib.pdtpy_series_free(ctypes.byref(s))
