"""The text of docs/reports/paper-reproduction.md around the generated tables:
the prose is the template paper_reproduction.md.in beside this file
(str.format fields), the tables and numbers come from here."""
import pathlib

TEMPLATE = pathlib.Path(__file__).with_name("paper_reproduction.md.in")


def _num(rows, name):
    for r in rows:
        if r.name == name:
            return r
    raise KeyError(name)


def _cands(boot):
    lines = ["| order n | delay d (samples of 0.2 s) | output-error mean square | BIC | "
             "continuous form |", "|---|---|---|---|---|"]
    for c in sorted(boot["cands"], key=lambda c: (c["n"], c["d"])):
        ok = "yes" if c["cont"] is not None else "no (a pole on the negative real axis "\
            "or outside the unit circle)"
        mark = " (chosen)" if c is boot["best"] else ""
        lines.append(f"| {c['n']}{mark} | {c['d']} | {c['V']:.3g} | {c['bic']:.1f} | {ok} |")
    return "\n".join(lines)


def render(t1, t2, t3, boot, figs, table, merit_table, provenance):
    b = boot
    lags = ", ".join(f"{v:.3g}" for v in b["lags"])
    zeros = ", ".join(f"{v:.3g}" for v in b["zeros"]) or "none"
    img = "\n\n".join(f"![{cap}](../img/{name})\n*{cap}*" for name, cap in figs)
    ctx = dict(
        t1=table(t1, False), m1=merit_table(t1), t2=table(t2, True), m2=merit_table(t2),
        t3=table(t3, True),
        m3=merit_table(t3, [("estimated high-order model", b["merit"])]),
        cands=_cands(b), n=b["best"]["n"], d=b["best"]["d"], delay=b["delay"], K=b["K"],
        lags=lags, zeros=zeros, img=img,
    )
    ctx.update(EXPLAIN(t1, t2, t3, b))
    ctx.update(provenance)
    return TEMPLATE.read_text().format(**ctx)


def EXPLAIN(t1, t2, t3, b):
    g = {r.name: r for r in t1}
    el, ga = g["ELMS"], g["GA_t, simulation cost"]
    pulses = [r.merit.iae for r in t2 if r.name.startswith("GA, pulse") and r.merit]
    return dict(elms_K=el.model.K if el.model else float("nan"),
                sim_iae=ga.merit.iae, hi_iae=b["merit"].iae,
                pulse_lo=min(pulses), pulse_hi=max(pulses),
                cplx="none was complex here" if not any(
                    abs(complex(r).imag) > 1e-9 for r in list(b["model"].poles)
                    + list(b["model"].zeros)) else "this model has such a pair")
