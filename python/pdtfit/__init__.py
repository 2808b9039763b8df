"""pdtfit from Python: FOPDT/SOPDT identification, PI/PID tuning and model
reduction, computed by the pdtfit C library (the float or double build it
was compiled with) and returned with the field names of the pdtfit command
line's JSON.

    import pdtfit
    rec = pdtfit.read_csv("step.csv")
    r = pdtfit.identify(rec.u, rec.y, Ts=rec.Ts, model="fopdt", seed=1)
    print(r.K, r.tau, r.Td, r.fit)
    print(pdtfit.tune(r, rule="simc", form="pi").Kc)

The whole API is in docs/python.md.
"""
import ctypes
import json
import math

import numpy as np

from . import _lib
from ._lib import lib

__all__ = ["PdtError", "Model", "IdentResult", "TuneResult", "Record", "identify", "tune",
           "reduce", "model", "read_csv", "STATUS_NAMES", "REAL_BYTES"]

STATUS_NAMES = dict(_lib.STATUS_NAMES)
"""{code: name} of every pdt_status_t in pdt_status.h, the name the
library's pdt_status_name gives ("PDT_ERR_NO_EXCITATION"), as the command
line's JSON prints it."""

REAL_BYTES = lib.pdtpy_real_size()
"""4 in the float build of the library, 8 in the double build."""

_JSON_LEN = 2048


class PdtError(Exception):
    """The library refused: .status is the status's name as pdt_status_name
    and the command line's JSON give it ("PDT_ERR_NO_EXCITATION",
    "PDT_ERR_POOR_FIT", ...), .code its value, and the message the
    library's description (pdt_status_str)."""

    def __init__(self, code, what, detail=""):
        self.code = int(code)
        self.status = lib.pdtpy_status_name(self.code).decode()
        text = lib.pdtpy_status_str(self.code).decode()
        super().__init__(f"{what}: {text} ({self.status}){detail}")


def _check(code, what, detail=""):
    if code == _lib.NOMEM:
        raise MemoryError(f"{what}: out of memory")
    if code != 0:
        raise PdtError(code, what, detail)


def _parse(buf):
    return json.loads(buf.value.decode())


def _choice(table, value, what):
    key = str(value).lower()
    if key not in table:
        raise ValueError(f"unknown {what} {value!r} ({', '.join(sorted(table))})")
    return table[key]


def _darray(x):
    a = np.ascontiguousarray(x, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError("u and y must be one-dimensional")
    return a, a.ctypes.data_as(_lib.D)


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
        y, py = _darray(self.y)
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
    its tolerance), filled (samples filled by resampling)."""

    def __init__(self, u, y, Ts, jitter_warn=0, filled=0):
        self.u, self.y, self.Ts = u, y, Ts
        self.jitter_warn, self.filled = jitter_warn, filled

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
            "integer_delay", "coarse")


def identify(u, y, fs=None, model="fopdt", cost="simulation", seed=1, *, Ts=None,
             method="ga", evaluations=None, population=None, td_max=None, weight=None,
             band=None, phi_t=None, phi_f=None, integer_delay=False, coarse=None):
    """Identifies a FOPDT or SOPDT model from a record with the options of
    `pdtfit identify`: the genetic-algorithm search (method "ga",
    pdt_identify) or the least-squares delay scans "elms" and "eiv"
    (pdt_ls_identify, which take model and td_max only). coarse is the
    library's decimation of the searches' record (None: automatic, 1: the
    whole record; `pdtfit identify --coarse`). Give the sampling
    rate as fs (Hz) or Ts (s). Returns an IdentResult; raises PdtError when
    the library refuses the data or the options."""
    if (fs is None) == (Ts is None):
        raise ValueError("give the sampling rate as fs (Hz) or Ts (s), one of them")
    Ts = float(Ts) if Ts is not None else 1.0 / float(fs)
    u, pu = _darray(u)
    y, py = _darray(y)
    if len(u) != len(y):
        raise ValueError(f"u has {len(u)} samples, y {len(y)}")
    o = _lib.IdentOpts()
    o.method = _choice(_lib.METHODS, method, "method")
    if o.method != _lib.METHODS["ga"]:
        given = dict(cost=cost != "simulation", seed=seed != 1, evaluations=evaluations,
                     population=population, weight=weight, band=band, phi_t=phi_t,
                     phi_f=phi_f, integer_delay=integer_delay, coarse=coarse)
        extra = [k for k in _GA_ONLY if given[k] not in (None, False)]
        if extra:
            raise ValueError(f"{', '.join(extra)}: options of method='ga' only")
    o.model = _choice(_lib.MODELS, model, "model")
    o.cost = _choice(_lib.COSTS, cost, "cost")
    o.weight = -1 if weight is None else _choice(_lib.WEIGHTS, weight, "weight")
    if (band is not None) != (o.weight == _lib.WEIGHTS["band"]):
        raise ValueError("band=(f_lo, f_hi) goes with weight='band'")
    o.f_lo, o.f_hi = (float(band[0]), float(band[1])) if band is not None else (0.0, 0.0)
    o.integer_delay = int(bool(integer_delay))
    o.seed = int(seed)
    o.evaluations = int(evaluations or 0)
    o.population = int(population or 0)
    o.coarse = int(coarse or 0)
    o.td_max, o.phi_t, o.phi_f = _opt(td_max), _opt(phi_t), _opt(phi_f)
    native = (ctypes.c_double * 5)()
    buf = ctypes.create_string_buffer(_JSON_LEN)
    _check(lib.pdtpy_identify(pu, py, len(u), Ts, ctypes.byref(o), native, buf, _JSON_LEN),
           "identify")
    return IdentResult(_parse(buf), native, u, y, Ts)


def model(kind, K=None, Td=0.0, *, tau=None, wn=None, zeta=None, tau1=None, tau2=None,
          Ki=None, T=None):
    """A model from its parameters: model("fopdt", K, Td, tau=...), or a
    SOPDT from wn and zeta, tau1 and tau2, or an integrator from Ki and T
    (Ki e^(-Td s) / (s (T s + 1)))."""
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


def tune(model_or_result, rule="simc", form="pi", *, tau_c=None, lambda_=None, ms_max=None,
         deriv_filter=None):
    """PI/PID gains of a model by a published rule (pdt_tune_compute) and
    the robustness of the loop they make, as `pdtfit tune` prints them.
    Raises PdtError (e.g. PDT_ERR_MS_LIMIT when Ms exceeds ms_max, default
    2)."""
    m = _as_model(model_or_result)
    o = _lib.TuneOpts()
    o.rule = _choice(_lib.RULES, rule, "rule")
    o.form = _choice(_lib.FORMS, form, "form")
    o.tau_c, o.lambda_ = _opt(tau_c), _opt(lambda_)
    o.ms_max, o.deriv_filter = _opt(ms_max), _opt(deriv_filter)
    ms = ctypes.c_double(math.nan)
    buf = ctypes.create_string_buffer(_JSON_LEN)
    code = lib.pdtpy_tune(_lib.darray(m._native), ctypes.byref(o), ctypes.byref(ms), buf,
                          _JSON_LEN)
    _check(code, "tune", f": Ms {ms.value:.4g}" if not math.isnan(ms.value) else "")
    return TuneResult(_parse(buf))


def reduce(gain, lags, zeros=(), delay=0.0, model="fopdt", method="skogestad", h=0.0):
    """A FOPDT or SOPDT from the detailed model
    gain prod (Zj s + 1) / prod (Ti s + 1) e^(-delay s) by Skogestad's half
    rule (method "skogestad", h the controller period) or Sung et al.'s fit
    ("sung"), as `pdtfit reduce` prints it. Returns a Model."""
    methods = {"skogestad": 0, "sung": 1}  # pdtpy_reduce's own numbering
    mth = _choice(methods, method, "method")
    kind = _choice(_lib.MODELS, model, "model")
    lags, zeros = list(lags), list(zeros)
    native = (ctypes.c_double * 5)()
    buf = ctypes.create_string_buffer(_JSON_LEN)
    _check(lib.pdtpy_reduce(mth, kind, float(gain), _lib.darray(lags), len(lags),
                            _lib.darray(zeros), len(zeros), float(delay), float(h), native,
                            buf, _JSON_LEN), "reduce")
    return Model(_parse(buf), native)


def read_csv(path, t=None, u=None, y=None, *, fs=None, sep=None, decimal=None, skip=0,
             time_unit="s", resample=False):
    """Reads u, y and the sampling period from a CSV file with the reader of
    `pdtfit identify`. t, u, y: the columns (names or 1-based indexes; by
    default t, u, y). Returns a Record; raises ValueError naming the file,
    line and column of a malformed file."""
    o = _lib.CsvOpts()
    o.t_col, o.u_col, o.y_col = (None if c is None else str(c).encode() for c in (t, u, y))
    o.sep = (sep or "\0").encode()
    o.decimal = (decimal or "\0").encode()
    o.skip = int(skip)
    o.time_unit = _choice({"s": 0, "ms": 1, "us": 2}, time_unit, "time unit")
    o.resample = int(bool(resample))
    o.fs = float(fs or 0.0)
    s = _lib.Series()
    err = ctypes.create_string_buffer(512)
    if lib.pdtpy_read_series(str(path).encode(), ctypes.byref(o), ctypes.byref(s), err,
                             len(err)) != 0:
        raise ValueError(err.value.decode(errors="replace"))
    try:
        u_a = np.ctypeslib.as_array(s.u, shape=(s.n,)).copy()
        y_a = np.ctypeslib.as_array(s.y, shape=(s.n,)).copy()
        return Record(u_a, y_a, s.Ts, s.jitter_warn, s.filled)
    finally:
        lib.pdtpy_series_free(ctypes.byref(s))
