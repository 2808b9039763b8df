"""Test vectors of the cost module's gain/offset profile, whole-record
scoring and simulation in engineering units (pdt_cost_profile,
pdt_cost_config_t.whole_record, pdt_cost_simulate) from pdtref.cost.

The records are those of vectorgen.cost (exact continuous-time simulation,
LCG noise, values quantised to 2^-12 so exact in float), each with its own
list of model shapes: FOPDT, overdamped and underdamped SOPDT, integrating
SOPDT, shapes whose gain has the wrong sign for the data (the best
multiplier is negative), shapes with unit gain. Every shape is profiled
under every configuration of CONFIGS: each cost kind, both time kinds in
COMBINED with unequal weights, with and without the offset fit, both delay
modes, whole_record on and off, and gain bounds that are absent, inactive,
active at the top, negative-only, or straddling zero. Bounds are placed
around the unbounded optimum of the same configuration and rounded to
multiples of 2^-10 (exact in float).

Also per shape: the discrete models (fractional and integer dead time, from
vectorgen.cost.zoh) and their four whole-record time costs; per record: two
simulations in engineering units, one with a delay beyond delay_max.
"""
import numpy as np

from pdtref import cost as ref

from . import _emit
from . import cost as base

FILE = "cost_profile_vectors.h"
BOUND_QUANTUM = 1.0 / 1024.0

KINDS = {"prediction": 0, "simulation": 1, "frequency": 2, "combined": 3}
WEIGHTS = {"uniform": 0, "band": 1}
MODES = {"frac": 0, "int": 1}

# name, kind, time_kind, delay mode, whole_record, estimate_offset,
# phi_t, phi_f, weight, bounds
CONFIGS = (
    ("sim_ofs", "simulation", "simulation", "frac", False, True, 1.0, 1.0, "uniform", "none"),
    ("sim_int_whole", "simulation", "simulation", "int", True, False, 1.0, 1.0, "uniform", "none"),
    ("pred_ofs_inact", "prediction", "simulation", "frac", False, True, 1.0, 1.0, "uniform",
     "inactive"),
    ("pred_int_whole", "prediction", "simulation", "int", True, False, 1.0, 1.0, "uniform",
     "none"),
    ("sim_whole_hi", "simulation", "simulation", "frac", True, True, 1.0, 1.0, "uniform", "high"),
    ("sim_neg", "simulation", "simulation", "frac", False, False, 1.0, 1.0, "uniform",
     "negative"),
    ("freq", "frequency", "simulation", "frac", False, True, 1.0, 1.0, "uniform", "none"),
    ("freq_band_neg", "frequency", "simulation", "frac", False, True, 1.0, 1.0, "band",
     "negative"),
    ("comb_sim", "combined", "simulation", "frac", False, True, 1.0, 0.5, "uniform", "none"),
    ("comb_pred_whole", "combined", "prediction", "int", True, False, 2.0, 1.0, "uniform",
     "none"),
    ("comb_sim_hi", "combined", "simulation", "int", False, True, 0.3, 3.0, "uniform", "high"),
    ("comb_pred_neg", "combined", "prediction", "frac", True, True, 1.0, 4.0, "band",
     "negative"),
    ("comb_sim_straddle", "combined", "simulation", "frac", True, True, 0.5, 2.0, "uniform",
     "straddle"),
)

F, S = base.Fopdt, base.Sopdt

# Extra shapes per record (by name), beside the first candidates of
# vectorgen.cost.
SHAPES = {
    "fopdt_step": [F(1.0, 3.0, 1.23), F(2.2, 2.4, 1.53),
                   S(1.6, 2.4, 0.8, 1.0),          # (2.5 s + 1)(0.5 s + 1), K 2
                   S(0.8, 0.6, 0.4, 0.87),         # underdamped
                   F(-1.0, 1.0, 3.02)],            # wrong sign
    "sopdt_chirp": [S(2.16, 0.72, 1.44, 0.81),     # the truth
                    S(1.0, 1.0, 1.3, 0.66), F(1.5, 1.1, 0.97),
                    S(1.0, 3.0, 1.44, 0.5)],       # overdamped, unit k
    "integ": [S(0.2, 0.5, 0.0, 0.5),               # the truth, integrating
              S(1.0, 0.4, 0.0, 0.73),              # integrating, unit k
              S(0.2, 0.5, 0.01, 0.5),              # nearly integrating
              F(8.0, 20.0, 1.04)],
    "reverse": [F(-0.8, 5.0, 2.0), F(1.0, 6.0, 2.3),  # the truth; wrong sign
                S(-0.2, 0.3, 0.25, 1.6),
                S(0.25, 1.25, 0.25, 2.2)],         # (4 s + 1)(s + 1), positive
}


def _q(x):
    return float(np.round(x / BOUND_QUANTUM) * BOUND_QUANTUM)


def bounds(mode, k_free):
    """Gain bounds for a bounds mode around the unbounded optimum k_free."""
    a = abs(k_free)
    if mode == "none":
        return 0.0, 0.0
    if mode == "inactive":
        return _q(k_free - a - 1.0), _q(k_free + a + 1.0)
    if mode == "high":
        # The top bound lies a quarter of |optimum| below the optimum.
        return _q(k_free - 2.0 * a - 1.0), _q(k_free - 0.25 * a)
    if mode == "negative":
        return _q(-3.0 * a - 1.0), -0.0625
    if mode == "straddle":
        return _q(-2.0 * a - 1.0), _q(0.5 * a)
    raise ValueError(mode)


def _options(rec, cfg):
    name, kind, tkind, mode, whole, ofs, pt, pf, weight, _ = cfg
    nf = ref.fft_size(rec["n"], rec["delay_max"])
    f_lo, f_hi = base.band_edges(nf, rec["Ts"])
    return dict(u0=rec["u0"], y0=rec["y0"], delay_max=rec["delay_max"], time_kind=tkind,
                estimate_offset=ofs, whole_record=whole, phi_t=pt, phi_f=pf,
                weight=weight, f_lo=f_lo, f_hi=f_hi)


def _dmodel(m, Ts, mode):
    return base.zoh(m, Ts) if mode == "frac" else base.zoh(m, Ts, base.int_delay(m, Ts))


def profile_case(rec, m, cfg):
    """The reference result of one shape under one configuration."""
    kind, mode, bmode = cfg[1], cfg[3], cfg[9]
    dm = _dmodel(m, rec["Ts"], mode)
    opts = _options(rec, cfg)
    free = ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], kind, **opts)
    lo, hi = bounds(bmode, free["gain"])
    res = free if bmode == "none" else ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], kind,
                                                   gain_min=lo, gain_max=hi, **opts)
    # Guard against near ties between the half-lines, which the float build
    # could resolve the other way.
    assert res["sign_free"] or res["margin"] == 0.0 or res["margin"] > 1e-3, (
        rec["name"], m, cfg[0], res["margin"])
    return lo, hi, res


def records():
    recs = base.records()
    for rec in recs:
        rec["delay_max"] = ref.resolve_delay_max(rec["n"], rec["delay_max"])
        rec["shapes"] = SHAPES[rec["name"]]
    return recs


def _params(m):
    if isinstance(m, F):
        return [m.K, m.tau, m.Td, 0.0]
    return [m.k, m.a, m.b, m.Td]


def _coef(dm):
    return list(dm.a) + list(dm.b) + list(dm.d)


def whole_costs(rec, dm):
    """pred, pred_ofs, sim, sim_ofs with whole_record."""
    out = []
    for fn in (ref.prediction_cost, ref.simulation_cost):
        for ofs in (False, True):
            out.append(fn(rec["u"], rec["y"], dm, rec["u0"], rec["y0"], rec["delay_max"], ofs,
                          True))
    return out


def sim_models(rec):
    """Two discrete models simulated per record: the first shape (fractional
    dead time) and the second with its integer delay moved beyond
    delay_max."""
    Ts = rec["Ts"]
    d0 = base.zoh(rec["shapes"][0], Ts)
    m1 = rec["shapes"][1]
    d1 = base.zoh(m1, Ts, rec["delay_max"] + 5)
    return [d0, d1]


def generate():
    body = []
    body.append("#define CPV_NCFG %d\n" % len(CONFIGS))
    body.append(
        "\n/* One configuration of pdt_cost_profile. kind, time_kind: pdt_cost_kind_t;\n"
        " * mode: pdt_delay_mode_t; weight: pdt_weight_kind_t. */\n"
        "typedef struct cpv_config {\n    const char *name;\n"
        "    int kind, time_kind, mode, whole_record, estimate_offset;\n"
        "    double phi_t, phi_f;\n    int weight;\n} cpv_config_t;\n\n")
    body.append("static const cpv_config_t cpv_configs[CPV_NCFG] = {\n")
    for c in CONFIGS:
        name, kind, tkind, mode, whole, ofs, pt, pf, weight, _ = c
        body.append("    {\"%s\", %d, %d, %d, %d, %d, %s, %s, %d},\n"
                    % (name, KINDS[kind], KINDS[tkind], MODES[mode], int(whole), int(ofs),
                       _emit.num(pt), _emit.num(pf), WEIGHTS[weight]))
    body.append("};\n\n")
    body.append(
        "/* Result of one shape under one configuration: bounds (0, 0 =\n"
        " * unbounded), then cost, gain, offset, ct, cf. sign_free: the cost\n"
        " * does not depend on the sign of the gain and -gain is allowed too. */\n"
        "typedef struct cpv_result {\n    double gain_min, gain_max;\n"
        "    double cost, gain, offset, ct, cf;\n    int sign_free;\n} cpv_result_t;\n\n"
        "/* One record. param: FOPDT K, tau, Td, 0 or SOPDT k, a, b, Td per shape.\n"
        " * coef_frac, coef_int: a0 a1 b0 b1 b2 d0 d1 of the shape's discrete\n"
        " * model (fractional / integer dead time). whole: pred, pred_ofs, sim,\n"
        " * sim_ofs of the fractional then the integer model, whole_record on.\n"
        " * result: shape-major, CPV_NCFG per shape. sim_*: two discrete models\n"
        " * and their pdt_cost_simulate output (n values each). */\n"
        "typedef struct cpv_set {\n    const char *name;\n    size_t n;\n"
        "    double Ts, u0, y0;\n    size_t delay_min, delay_max;\n    int delay_max_auto;\n"
        "    double f_lo, f_hi;\n    const double *u, *y;\n    size_t nshape;\n"
        "    const int *kind;\n    const double *param;\n"
        "    const int *delay_frac;\n    const double *coef_frac;\n"
        "    const int *delay_int;\n    const double *coef_int;\n"
        "    const double *whole;\n    const cpv_result_t *result;\n"
        "    const int *sim_order;\n    const int *sim_delay;\n    const double *sim_coef;\n"
        "    const double *ysim;\n} cpv_set_t;\n\n")
    table = []
    auto = {r["name"]: r["delay_max"] is None for r in base.records()}
    for rec in records():
        name, n, Ts = rec["name"], rec["n"], rec["Ts"]
        shapes = rec["shapes"]
        nf = ref.fft_size(n, rec["delay_max"])
        f_lo, f_hi = base.band_edges(nf, Ts)
        p = "cpv_%s_" % name
        body.append(_emit.array("double", p + "u", rec["u"]))
        body.append(_emit.array("double", p + "y", rec["y"]))
        body.append(_emit.int_array("int", p + "kind",
                                    [1 if isinstance(m, F) else 2 for m in shapes]))
        body.append(_emit.array("double", p + "param", sum((_params(m) for m in shapes), [])))
        frac = [base.zoh(m, Ts) for m in shapes]
        intd = [base.zoh(m, Ts, base.int_delay(m, Ts)) for m in shapes]
        for dm in frac + intd:
            assert rec["delay_min"] <= dm.delay <= rec["delay_max"], (name, dm.delay)
        body.append(_emit.int_array("int", p + "delay_frac", [dm.delay for dm in frac]))
        body.append(_emit.array("double", p + "coef_frac", sum((_coef(dm) for dm in frac), [])))
        body.append(_emit.int_array("int", p + "delay_int", [dm.delay for dm in intd]))
        body.append(_emit.array("double", p + "coef_int", sum((_coef(dm) for dm in intd), [])))
        body.append(_emit.array("double", p + "whole",
                                sum((whole_costs(rec, dm) for dm in frac + intd), [])))
        rows = []
        for m in shapes:
            for cfg in CONFIGS:
                lo, hi, r = profile_case(rec, m, cfg)
                rows.append("    {%s, %s, %s, %s, %s, %s, %s, %d},\n"
                            % (_emit.num(lo), _emit.num(hi), _emit.num(r["cost"]),
                               _emit.num(r["gain"]), _emit.num(r["offset"]),
                               _emit.num(r["ct"]), _emit.num(r["cf"]), int(r["sign_free"])))
        body.append("static const cpv_result_t %sresult[%d] = {\n%s};\n"
                    % (p, len(rows), "".join(rows)))
        sims = sim_models(rec)
        body.append(_emit.int_array("int", p + "sim_order", [dm.order for dm in sims]))
        body.append(_emit.int_array("int", p + "sim_delay", [dm.delay for dm in sims]))
        body.append(_emit.array("double", p + "sim_coef", sum((_coef(dm) for dm in sims), [])))
        body.append(_emit.array("double", p + "ysim",
                                np.concatenate([ref.simulate(rec["u"], dm, rec["u0"], rec["y0"])
                                                for dm in sims])))
        body.append("\n")
        table.append(
            "    {\"%s\", %d, %s, %s, %s, %d, %d, %d, %s, %s,\n"
            "     %su, %sy, %d, %skind, %sparam,\n"
            "     %sdelay_frac, %scoef_frac, %sdelay_int, %scoef_int, %swhole, %sresult,\n"
            "     %ssim_order, %ssim_delay, %ssim_coef, %sysim},\n"
            % (name, n, _emit.num(Ts), _emit.num(rec["u0"]), _emit.num(rec["y0"]),
               rec["delay_min"], rec["delay_max"], int(auto[name]), _emit.num(f_lo),
               _emit.num(f_hi), p, p, len(shapes), p, p, p, p, p, p, p, p, p, p, p, p))
    body.append("static const cpv_set_t cpv_sets[%d] = {\n" % len(table))
    body.append("".join(table))
    body.append("};\n")
    return {FILE: _emit.header(FILE, "".join(body), "tools/pdtref/cost.py")}
