"""Loading of the shared library built beside this package and the ctypes
mirror of python/src/pdtpy.h (change both together)."""
import ctypes
import os
import pathlib

from . import _cheader

HERE = pathlib.Path(__file__).resolve().parent
INCLUDE = HERE / "include" / "pdt"


def _load():
    # PDTFIT_LIBRARY: a library built elsewhere, e.g. by hand with
    # cmake -DPDT_BUILD_PYTHON=ON, for working on the C side.
    path = os.environ.get("PDTFIT_LIBRARY")
    if not path:
        found = sorted(HERE.glob("lib_pdtfit.*")) + sorted(HERE.glob("_pdtfit.*"))
        if not found:
            raise ImportError(f"pdtfit: no compiled library in {HERE}; install the package "
                              "with pip install . from the repository")
        path = str(found[0])
    return ctypes.CDLL(path)


class IdentOpts(ctypes.Structure):
    _fields_ = [("method", ctypes.c_int), ("model", ctypes.c_int), ("cost", ctypes.c_int),
                ("weight", ctypes.c_int),
                ("integer_delay", ctypes.c_int), ("seed", ctypes.c_uint64),
                ("evaluations", ctypes.c_uint32), ("population", ctypes.c_uint32),
                ("td_max", ctypes.c_double), ("f_lo", ctypes.c_double),
                ("f_hi", ctypes.c_double), ("phi_t", ctypes.c_double),
                ("phi_f", ctypes.c_double), ("coarse", ctypes.c_uint32),
                ("u_before", ctypes.c_double), ("refuse_missing", ctypes.c_int),
                ("initial", ctypes.c_int),
                ("offset", ctypes.c_int), ("uncertainty", ctypes.c_int),
                ("boot_runs", ctypes.c_uint32), ("drift", ctypes.c_int)]


class TuneOpts(ctypes.Structure):
    _fields_ = [("rule", ctypes.c_int), ("form", ctypes.c_int), ("tau_c", ctypes.c_double),
                ("lambda_", ctypes.c_double), ("ms_max", ctypes.c_double),
                ("deriv_filter", ctypes.c_double), ("fit", ctypes.c_double),
                ("fit_min", ctypes.c_double), ("span", ctypes.c_double),
                ("Ku", ctypes.c_double), ("Pu", ctypes.c_double)]


class CsvOpts(ctypes.Structure):
    _fields_ = [("t_col", ctypes.c_char_p), ("u_col", ctypes.c_char_p),
                ("y_col", ctypes.c_char_p), ("sep", ctypes.c_char), ("decimal", ctypes.c_char),
                ("skip", ctypes.c_uint), ("time_unit", ctypes.c_int),
                ("resample", ctypes.c_int), ("fs", ctypes.c_double),
                ("units_row", ctypes.c_int), ("time_format", ctypes.c_char_p),
                ("bad_values", ctypes.POINTER(ctypes.c_double)),
                ("n_bad_values", ctypes.c_size_t), ("bad_rows", ctypes.c_int)]


class Series(ctypes.Structure):
    _fields_ = [("u", ctypes.POINTER(ctypes.c_double)), ("y", ctypes.POINTER(ctypes.c_double)),
                ("n", ctypes.c_size_t), ("Ts", ctypes.c_double),
                ("jitter_warn", ctypes.c_uint), ("filled", ctypes.c_uint),
                ("units_row", ctypes.c_size_t)]


NOMEM = -1000  # PDTPY_ERR_NOMEM
SOPDT_NATURAL, SOPDT_TC, SOPDT_INTEG = 0, 1, 2  # PDTPY_SOPDT_*
METHODS = {"ga": 0, "elms": 1, "eiv": 2}  # PDTPY_METHOD_*
MODEL_AUTO = 3  # PDTPY_MODEL_AUTO

D = ctypes.POINTER(ctypes.c_double)
lib = _load()
lib.pdtpy_status_str.restype = ctypes.c_char_p
lib.pdtpy_status_str.argtypes = [ctypes.c_int]
lib.pdtpy_status_name.restype = ctypes.c_char_p
lib.pdtpy_status_name.argtypes = [ctypes.c_int]
lib.pdtpy_real_size.restype = ctypes.c_int
lib.pdtpy_model_make.argtypes = [ctypes.c_int, ctypes.c_int] + [ctypes.c_double] * 4 + [D]
lib.pdtpy_model_json.argtypes = [D, ctypes.c_char_p, ctypes.c_size_t]
lib.pdtpy_identify.argtypes = [D, D, ctypes.c_size_t, ctypes.c_double,
                               ctypes.POINTER(IdentOpts), D, ctypes.c_char_p, ctypes.c_size_t]
DP = ctypes.POINTER(D)
lib.pdtpy_identify_many.argtypes = [DP, DP, ctypes.POINTER(ctypes.c_size_t), D, ctypes.c_size_t,
                                    ctypes.POINTER(IdentOpts), D, ctypes.c_char_p,
                                    ctypes.c_size_t]
lib.pdtpy_simulate.argtypes = [D, ctypes.c_double, D, D, ctypes.c_size_t, ctypes.c_double,
                               ctypes.c_double, D]
lib.pdtpy_tune.argtypes = [D, ctypes.POINTER(TuneOpts), D, ctypes.c_char_p, ctypes.c_size_t]
lib.pdtpy_reduce.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_double, D, ctypes.c_size_t,
                             D, ctypes.c_size_t, ctypes.c_double, ctypes.c_double, D,
                             ctypes.c_char_p, ctypes.c_size_t]
lib.pdtpy_read_series.argtypes = [ctypes.c_char_p, ctypes.POINTER(CsvOpts),
                                  ctypes.POINTER(Series), ctypes.c_char_p, ctypes.c_size_t]
lib.pdtpy_series_free.argtypes = [ctypes.POINTER(Series)]
lib.pdtpy_series_free.restype = None
lib.pdtpy_outlier.argtypes = [D, ctypes.c_size_t]
lib.pdtpy_outlier.restype = ctypes.c_size_t

# The enums, from the headers installed with the package; a status's name
# is the library's own (pdt_status_name), as the command line prints it.
STATUS_CODES = sorted(_cheader.enums(INCLUDE / "pdt_status.h")["pdt_status_t"].values())
STATUS_NAMES = {code: lib.pdtpy_status_name(code).decode() for code in STATUS_CODES}
STATUS_CODE = {name: code for code, name in _cheader.status_names(INCLUDE / "pdt_status.h").items()}
_cost = _cheader.enums(INCLUDE / "pdt_cost.h")
_tune = _cheader.enums(INCLUDE / "pdt_tune.h")
_model = _cheader.enums(INCLUDE / "pdt_model.h")
_ident = _cheader.enums(INCLUDE / "pdt_ident.h")


def _choices(members, prefix):
    return {m[len(prefix):].lower(): v for m, v in members.items() if m.startswith(prefix)}


MODELS = _choices(_model["pdt_model_kind_t"], "PDT_MODEL_")
COSTS = _choices(_cost["pdt_cost_kind_t"], "PDT_COST_")
WEIGHTS = {k: v for k, v in _choices(_ident["pdt_ident_weight_t"], "PDT_IDENT_WEIGHT_").items()
           if k != "custom"}  # needs an array of weights: not offered
OFFSETS = _choices(_ident["pdt_ident_offset_t"], "PDT_IDENT_OFFSET_")
RULES = _choices(_tune["pdt_tune_rule_t"], "PDT_TUNE_")
FORMS = _choices(_tune["pdt_tune_form_t"], "PDT_TUNE_")
_common = _cheader.defines(INCLUDE / "pdt_common.h")
VERSION = "%d.%d.%d" % tuple(_common["PDT_VERSION_" + p] for p in ("MAJOR", "MINOR", "PATCH"))
MAX_POPULATION = _cheader.defines(INCLUDE / "pdt_ident.h")["PDT_IDENT_MAX_POPULATION"]
MAX_RECORDS = _cheader.defines(INCLUDE / "pdt_config.h")["PDT_IDENT_MAX_RECORDS"]


def darray(values):
    """A C array of doubles holding `values` (any sequence of numbers)."""
    values = [float(v) for v in values]
    return (ctypes.c_double * max(len(values), 1))(*values)
