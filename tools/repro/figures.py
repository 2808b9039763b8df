"""The figures of docs/reports/paper-reproduction.md, in the manner of the paper's
Figures 1-9: Bode magnitude and phase within the bandwidth, step-response
deviations from (17), Nyquist curves; plus the records themselves."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pdtrepro import system17 as s17  # noqa: E402

# Fixed metadata so that the PNG files are byte-for-byte repeatable.
META = {"Software": None}
W_BODE = np.logspace(-2, np.log10(2.0), 300)
W_NYQ = np.linspace(1e-3, s17.W_U, 300)
T_STEP = np.arange(0, 1501) * 0.01


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=90, metadata=META)
    plt.close(fig)


def _models(rows):
    """(label, model, style) of every row's models: ours solid, the paper's
    dashed."""
    out = []
    for i, r in enumerate(rows):
        color = f"C{i % 10}"
        if r.model is not None:
            out.append((f"{r.name}", r.model, dict(color=color, ls="-")))
        if r.paper is not None:
            out.append((f"{r.name} (paper)", r.paper, dict(color=color, ls="--")))
    return out


def bode(path, title, models):
    g17 = s17.freq17(W_BODE)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    a1.loglog(W_BODE, np.abs(g17), "k", lw=2.5, label="true (17)")
    a2.semilogx(W_BODE, np.degrees(np.unwrap(np.angle(g17))), "k", lw=2.5)
    for label, m, st in models:
        g = m.freq(W_BODE)
        a1.loglog(W_BODE, np.abs(g), lw=1, label=label, **st)
        a2.semilogx(W_BODE, np.degrees(np.unwrap(np.angle(g))), lw=1, **st)
    for a in (a1, a2):
        a.axvline(s17.W_U, color="grey", lw=0.8, ls=":")
        a.grid(True, which="both", lw=0.3)
    a1.set_ylabel("|G(jw)|")
    a2.set_ylabel("phase, degrees")
    a2.set_xlabel("w, rad/s (dotted: phase crossover of (17), 1.186 rad/s)")
    a2.set_ylim(-400, 10)
    a1.set_title(title)
    a1.legend(fontsize=7, ncol=2)
    _save(fig, path)


def step_dev(path, title, models):
    h17 = s17.step17(T_STEP)
    fig, ax = plt.subplots(figsize=(8, 6))
    for label, m, st in models:
        ax.plot(T_STEP, m.step(T_STEP) - h17, lw=1, label=label, **st)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.grid(True, lw=0.3)
    ax.set_xlabel("t, s")
    ax.set_ylabel("step response minus that of (17)")
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.12))
    _save(fig, path)


def nyquist(path, title, models):
    g17 = s17.freq17(W_NYQ)
    fig, ax = plt.subplots(figsize=(6.5, 6))
    ax.plot(g17.real, g17.imag, "k", lw=2.5, label="true (17)")
    for label, m, st in models:
        g = m.freq(W_NYQ)
        ax.plot(g.real, g.imag, lw=1, label=label, **st)
    ax.plot([-1.0], [0.0], "k+")
    ax.grid(True, lw=0.3)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Re G(jw)")
    ax.set_ylabel("Im G(jw)")
    ax.set_title(title + ", 0 < w <= 1.186 rad/s")
    ax.legend(fontsize=7)
    _save(fig, path)


def records(path, recs):
    fig, axes = plt.subplots(len(recs), 1, figsize=(8, 2.2 * len(recs)))
    for ax, (key, (t, u, y)) in zip(axes, recs.items()):
        ax.plot(t, y, lw=0.6, color="C0", label="y")
        ax.plot(t, u + (s17.Y0 - s17.U0), lw=0.8, color="C1", label="u + 15")
        ax.set_ylabel(key)
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("t, s")
    _save(fig, path)


def make_all(img, recs, t1, t2, t3, boot):
    """Writes every figure; returns [(file name, caption)]."""
    figs = []

    def add(name, caption, fn, *args):
        fn(img / name, *args)
        figs.append((name, caption))

    add("repro-records.png", "The four records (input shifted by y0 - u0 for the plot).",
        records, recs)
    m1 = _models(t1)
    add("repro-fopdt-bode.png", "Table 1 FOPDT models against (17): Bode plot.", bode,
        "FOPDT models (Table 1)", m1)
    add("repro-fopdt-step.png", "Table 1 FOPDT models: step response minus that of (17).",
        step_dev, "FOPDT models (Table 1)", m1)
    add("repro-fopdt-nyquist.png", "Table 1 FOPDT models: Nyquist curves.", nyquist,
        "FOPDT models (Table 1)", m1)
    # Table 2: the combined-cost GA models (the paper's) and the rules.
    sel = [r for r in t2 if "combined" in r.name or "model known" in r.name]
    m2 = _models(sel)
    add("repro-sopdt-bode.png", "Table 2 SOPDT models (GA combined cost, and the rules): "
        "Bode plot.", bode, "SOPDT models (Table 2)", m2)
    add("repro-sopdt-step.png", "Table 2 SOPDT models: step response minus that of (17).",
        step_dev, "SOPDT models (Table 2)", m2)
    add("repro-sopdt-nyquist.png", "Table 2 SOPDT models: Nyquist curves.", nyquist,
        "SOPDT models (Table 2)", m2)
    m3 = [("estimated high-order model", boot["model"], dict(color="k", ls=":"))] \
        + _models(t3)
    add("repro-bootstrap-bode.png", "Table 3: the high-order model estimated from the chirp "
        "and its reductions: Bode plot.", bode, "Bootstrap (Table 3)", m3)
    add("repro-bootstrap-step.png", "Table 3: step response minus that of (17).", step_dev,
        "Bootstrap (Table 3)", m3)
    add("repro-bootstrap-nyquist.png", "Table 3: Nyquist curves.", nyquist,
        "Bootstrap (Table 3)", m3)
    return figs
