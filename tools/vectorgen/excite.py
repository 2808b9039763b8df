"""Test vectors of the excitation generators and the recorder
(lib/src/pdt_excite.c, lib/src/pdt_record.c) from pdtref.excite.

excite_vectors.h, EXC_CASES generator cases, each a parameter row
``exc_par[EXC_NPAR * i + EXC_P_<field>]`` (the config fields; kind and enum
values as numbers), run for ``exc_len[i]`` calls from ``exc_off[i]`` in the
concatenated ``exc_pv`` (the process value given to each call; 0 for the
open-loop kinds) and ``exc_u`` (the output wanted), ``exc_first_ok[i]`` (the
first call that returns PDT_OK, -1 if none) and ``exc_length[i]`` (what
pdt_excite_length returns). The relay cases also have ``exc_relay`` rows
(Ku, Pu, a, d, cycles) as measured after their last call. Cases: steps
(one clamped), a pulse train, the paper's chirp (0 to 0.5 Hz at 20 Hz) and a
clamped chirp, PRBS of 5, 9 (clamped) and 31 bits, two relays (reverse
acting with hysteresis; direct acting with bias and a clamped level) on
process values from splitmix64 integers on a 1/64 grid so that every switching
comparison is exact in float and double.

excite_record_vectors.h, REC_CASES recorder cases: ``rec_par`` rows, scan
streams ``rec_su``, ``rec_spv`` from ``rec_soff[i]`` for ``rec_slen[i]``
scans, and what the recorder holds after the whole stream: ``rec_out``
rows (status, n, settled, u0, y0, u_safe, scans, last push index that did
not return RUNNING or -1) and the stored samples ``rec_u``, ``rec_y`` from
``rec_off[i]``. Cases: decimation with a full record, a settle window that
restarts on drift, each abort (pv, output, time, set-point), a set-point on
the right side, an abort on the first scan and one before the first sample.
"""
import math

import numpy as np

from pdtref import excite as E
from pdtsupport import plant
from pdtsupport.rng import SplitMix64 as Rng

from . import _emit

EXC_FILE = "excite_vectors.h"
REC_FILE = "excite_record_vectors.h"

EXC_FIELDS = ["kind", "Ts", "u0", "u_min", "u_max", "clamp", "pre", "amplitude", "duration",
              "t_on", "t_off", "count", "f0", "f1", "prbs_bits", "prbs_hold", "prbs_seed",
              "periods", "setpoint", "d", "bias", "eps", "action", "relay_skip",
              "relay_cycles"]
REC_FIELDS = ["decimation", "settle", "settle_band", "u_min", "u_max", "pv_min", "pv_max",
              "max_scans", "move", "setpoint", "capacity"]
BIG = 1e30  # stands for "no limit" in the vectors (finite, fits a float)


def draws(seed, count):
    """`count` integers in [0, 255]: the top byte of splitmix64."""
    return Rng.keyed(seed).bits(8, count)


def grid(x):
    """Round to the 1/64 grid (exact in float and double)."""
    return np.round(np.asarray(x, dtype=float) * 64.0) / 64.0


def exc_cases():
    C = E.config
    cs = [
        (C(kind=E.STEP, Ts=0.5, u0=10.0, amplitude=5.0, pre=2.0, duration=10.0,
           u_min=0.0, u_max=100.0), 30, None),
        (C(kind=E.STEP, Ts=0.5, u0=10.0, amplitude=-15.0, u_min=0.0, u_max=100.0, clamp=True),
         20, None),
        (C(kind=E.PULSE, Ts=0.1, u0=-2.0, amplitude=3.0, pre=0.3, t_on=0.5, t_off=0.7, count=3),
         45, None),
        (C(kind=E.CHIRP, Ts=0.05, u0=0.5, amplitude=1.0, duration=40.0, f0=0.0, f1=0.5), 820,
         None),
        (C(kind=E.CHIRP, Ts=0.01, u0=1.0, amplitude=2.0, pre=0.1, duration=1.5, f0=2.0, f1=10.0,
           u_min=0.0, u_max=2.5, clamp=True), 170, None),
        (C(kind=E.PRBS, Ts=0.1, u0=1.0, amplitude=0.25, pre=0.2, prbs_bits=5, prbs_hold=3,
           periods=2), 195, None),
        (C(kind=E.PRBS, Ts=1.0, u0=4.0, amplitude=2.0, prbs_bits=9, prbs_seed=0x1A5,
           u_min=-10.0, u_max=5.0, clamp=True), 520, None),
        (C(kind=E.PRBS, Ts=0.01, u0=0.0, amplitude=1.0, prbs_bits=31, prbs_seed=0x12345678,
           prbs_hold=2, periods=0), 300, None),
    ]
    # reverse-acting relay: pv oscillates around 20 with period 37 samples
    n = 400
    k = np.arange(n)
    noise = (np.array(draws(0x5E1A0001, n)) - 127.5) / 128.0
    pv = grid(20.0 + 1.5 * np.sin(2 * math.pi * k / 37.0 + 0.3) + 0.1 * noise)
    cs.append((C(kind=E.RELAY, Ts=0.25, u0=50.0, d=10.0, eps=0.25, setpoint=20.0, pre=1.0,
                 u_min=0.0, u_max=100.0), n, pv))
    # direct-acting relay with bias, the high level clamped: a triangle wave
    n = 300
    k = np.arange(n)
    tri = 2.0 * np.abs(((k + 5) % 29) / 29.0 - 0.5) - 0.5
    noise = (np.array(draws(0x5E1A0002, n)) - 127.5) / 128.0
    pv = grid(-3.0 + 4.0 * tri + 0.05 * noise)
    cs.append((C(kind=E.RELAY, Ts=2.0, u0=50.0, bias=5.0, d=30.0, eps=0.125, setpoint=-3.0,
                 action=E.DIRECT, u_min=0.0, u_max=80.0, clamp=True, relay_skip=0,
                 relay_cycles=8), n, pv))
    return cs


def exc_row(c):
    row = []
    for f in EXC_FIELDS:
        v = c[f]
        if isinstance(v, bool):
            v = 1.0 if v else 0.0
        if v == math.inf:
            v = BIG
        if v == -math.inf:
            v = -BIG
        row.append(float(v))
    return row


def rec_cases():
    R = E.rec_config
    out = []

    def stream_step(m, D, u0, u1, y0, gain, k_step, seed, noise=0.02):
        """Scans of a first-order response to a step of u at scan k_step."""
        u = np.where(np.arange(m) >= k_step, u1, u0)
        y = y0 + plant.first_order(gain, math.exp(-1.0 / 15.0), u - u0)
        nz = (np.array(draws(seed, m)) - 127.5) / 128.0
        return u, grid(y + noise * nz)

    # 0: decimation 4, settle 5, full record of 30 samples; stream goes on
    u, y = stream_step(160, 4, 40.0, 45.0, 7.0, 2.0, 24, 0x5EC00000)
    u[61] = 47.0  # a change inside an interval: the first scan's value is kept
    out.append((R(decimation=4, settle=5, u_min=0.0, u_max=100.0, pv_min=0.0, pv_max=50.0),
                30, u, y))
    # 1: settle window restarts while pv drifts, then steadies
    m = 80
    drift = np.concatenate([np.linspace(5.0, 6.0, 20), np.full(m - 20, 6.0)])
    nz = (np.array(draws(0x5EC00001, m)) - 127.5) / 128.0
    y = grid(drift + 0.02 * nz)
    u = np.full(m, 12.0)
    u[50:] = 14.0
    out.append((R(decimation=2, settle=6, settle_band=0.1), 20, u, y))
    # 2: pv limit broken in the middle of an interval
    u, y = stream_step(120, 3, 10.0, 30.0, 20.0, 1.5, 30, 0x5EC00002)
    out.append((R(decimation=3, settle=8, pv_min=15.0, pv_max=40.0), 100, u, y))
    # 3: output limit
    u, y = stream_step(90, 2, 10.0, 30.0, 20.0, 1.5, 30, 0x5EC00003)
    u[57:] = 120.0
    out.append((R(decimation=2, settle=8, u_min=0.0, u_max=100.0), 100, u, y))
    # 4: time limit before the record is full
    u, y = stream_step(70, 1, 1.0, 2.0, 0.0, 1.0, 12, 0x5EC00004)
    out.append((R(decimation=1, settle=10, max_scans=50), 100, u, y))
    # 5: set-point below the process value for an upward experiment
    u, y = stream_step(40, 2, 1.0, 2.0, 5.0, 1.0, 100, 0x5EC00005)
    out.append((R(decimation=2, settle=10, move=E.MOVE_UP, setpoint=4.5), 50, u, y))
    # 6: set-point on the right side (below, moving down): runs to full
    u, y = stream_step(64, 2, 1.0, 0.0, 5.0, 1.0, 30, 0x5EC00006)
    out.append((R(decimation=2, settle=10, move=E.MOVE_DOWN, setpoint=4.5), 30, u, y))
    # 7: the first scan's output is beyond the limit
    u = np.array([130.0, 50.0, 50.0])
    y = np.array([1.0, 1.0, 1.0])
    out.append((R(decimation=1, settle=2, u_min=0.0, u_max=100.0), 10, u, y))
    # 8: pv limit before the first sample is complete
    u = np.array([33.0, 34.0, 35.0, 36.0])
    y = np.array([1.0, 1.0, 9.0, 1.0])
    out.append((R(decimation=4, settle=2, pv_max=5.0), 10, u, y))
    return out


def rec_row(c, capacity):
    row = []
    for f in REC_FIELDS:
        v = capacity if f == "capacity" else c[f]
        if v == math.inf:
            v = BIG
        if v == -math.inf:
            v = -BIG
        row.append(float(v))
    return row


def gen_excite():
    par, off, lens, pvs, us, first_ok, length, relay_rows = [], [], [], [], [], [], [], []
    relay_case = []
    for i, (c, n, pv) in enumerate(exc_cases()):
        if c["kind"] == E.RELAY:
            u, status, res = E.relay(c, pv)
            assert res is not None
            relay_case.append(i)
            relay_rows += [res["Ku"], res["Pu"], res["a"], res["d"], res["cycles"]]
        else:
            pv = np.zeros(n)
            u, status = E.open_loop(c, n)
        par += exc_row(c)
        off.append(len(us))
        lens.append(n)
        pvs += list(pv)
        us += list(u)
        oks = np.nonzero(status == E.OK)[0]
        first_ok.append(int(oks[0]) if len(oks) else -1)
        length.append(E.length(c))
    defs = "".join(f"#define EXC_P_{f.upper()} {j}\n" for j, f in enumerate(EXC_FIELDS))
    body = (
        f"#define EXC_CASES {len(lens)}\n#define EXC_NPAR {len(EXC_FIELDS)}\n"
        f"#define EXC_RELAY_CASES {len(relay_case)}\n#define EXC_BIG {BIG!r}\n" + defs + "\n"
        + _emit.array("double", "exc_par", par)
        + _emit.int_array("int", "exc_off", off)
        + _emit.int_array("int", "exc_len", lens)
        + _emit.int_array("int", "exc_first_ok", first_ok)
        + _emit.int_array("long", "exc_length", length)
        + _emit.int_array("int", "exc_relay_case", relay_case)
        + _emit.array("double", "exc_relay", relay_rows)
        + _emit.array("double", "exc_pv", pvs)
        + _emit.array("double", "exc_u", us)
    )
    return _emit.header(EXC_FILE, body, "tools/vectorgen/excite.py (pdtref.excite)")


def gen_record():
    par, soff, slen, su, spv, outs, off, ru, ry = [], [], [], [], [], [], [], [], []
    for c, capacity, u, y in rec_cases():
        r = E.record(c, capacity, u, y)
        par += rec_row(c, capacity)
        soff.append(len(su))
        slen.append(len(u))
        su += list(u)
        spv += list(y)
        outs += [r["status"], r["n"], 1.0 if r["settled"] else 0.0, r["u0"], r["y0"],
                 r["u_safe"], r["scans"], -1 if r["last"] is None else r["last"]]
        off.append(len(ru))
        ru += list(r["u"])
        ry += list(r["y"])
    defs = "".join(f"#define REC_P_{f.upper()} {j}\n" for j, f in enumerate(REC_FIELDS))
    outdefs = "".join(f"#define REC_O_{f} {j}\n" for j, f in enumerate(
        ["STATUS", "N", "SETTLED", "U0", "Y0", "U_SAFE", "SCANS", "LAST"]))
    body = (
        f"#define REC_CASES {len(slen)}\n#define REC_NPAR {len(REC_FIELDS)}\n#define REC_NOUT 8\n"
        + defs + outdefs + "\n"
        + _emit.array("double", "rec_par", par)
        + _emit.int_array("int", "rec_soff", soff)
        + _emit.int_array("int", "rec_slen", slen)
        + _emit.array("double", "rec_su", su)
        + _emit.array("double", "rec_spv", spv)
        + _emit.array("double", "rec_out", outs)
        + _emit.int_array("int", "rec_off", off)
        + _emit.array("double", "rec_u", ru)
        + _emit.array("double", "rec_y", ry)
    )
    return _emit.header(REC_FILE, body, "tools/vectorgen/excite.py (pdtref.excite)")


def generate():
    return {EXC_FILE: gen_excite(), REC_FILE: gen_record()}
