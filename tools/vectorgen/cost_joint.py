"""Test vectors of the joint profile of several records of one process
(pdt_cost_joint_profile), from pdtref.cost.profile_joint.

The records of vectorgen.cost_state (cut mid-transient, one with a ramp),
each with its own period, operating point and length, taken in pairs and
all three together; every shape (unit gain) of the first record is
profiled on them under every configuration of CONFIGS.
"""
from pdtref import cost as ref

from . import _emit
from . import cost as base
from . import cost_state

FILE = "cost_joint_vectors.h"

# Which records go together (indices into cost_state.RECORDS).
GROUPS = ((0, 1), (1, 2), (0, 1, 2))

# name, estimate_offset, estimate_state, drift
CONFIGS = (
    ("offset", True, False, False),
    ("state", True, True, False),
    ("state_drift", True, True, True),
)


def _params(m):
    return [m.K, m.tau, m.Td, 0.0] if isinstance(m, base.Fopdt) else [m.k, m.a, m.b, m.Td]


def _case(recs, group, m, cfg):
    _, ofs, st, dr = cfg
    rows = []
    for i in group:
        rec = recs[i]
        rows.append(dict(u=rec["u"], y=rec["y"], dm=base.zoh(m, rec["Ts"]), Ts=rec["Ts"],
                         u0=rec["u0"], y0=rec["y0"]))
    r = ref.profile_joint(rows, ofs, st, dr)
    return r


def generate():
    recs = [cost_state.record(e) for e in cost_state.RECORDS]
    body = [
        "/* One case: the records (count, indices into the cost_state vectors'\n"
        " * records), the shape (kind 0 FOPDT K tau Td 0, 1 SOPDT k a b Td; unit\n"
        " * gain), the configuration (estimate_offset, estimate_state, drift) and\n"
        " * the reference: cost, gain, the first record's offset. */\n"
        "typedef struct cost_joint_case {\n"
        "    size_t count;\n    size_t rec[3];\n    int kind;\n    double p[4];\n"
        "    int flags[3];\n    double want[3];\n} cost_joint_case_t;\n\n"]
    lines = []
    for group in GROUPS:
        for m in cost_state.RECORDS[group[0]][9]:
            for cfg in CONFIGS:
                r = _case(recs, group, m, cfg)
                idx = list(group) + [0] * (3 - len(group))
                lines.append("    {%du, {%s}, %d, {%s}, {%s}, {%s}}," % (
                    len(group), ", ".join("%du" % i for i in idx),
                    0 if isinstance(m, base.Fopdt) else 1,
                    ", ".join(_emit.num(x) for x in _params(m)),
                    ", ".join(str(int(f)) for f in cfg[1:]),
                    ", ".join(_emit.num(x) for x in (r["cost"], r["gain"], r["offsets"][0]))))
    body.append("static const cost_joint_case_t cj_cases[%d] = {\n%s\n};\n"
                % (len(lines), "\n".join(lines)))
    return {FILE: _emit.header(FILE, "".join(body), "tools/vectorgen/cost_joint.py")}
