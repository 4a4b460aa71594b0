"""The synthetic benchmark's report: targets (PASS/MISS) and markdown tables.

Split from :mod:`impactpred.benchmark` (which re-exports every name); the tables' columns
are those of :func:`impactpred.benchmark.run_case`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from .truncation import FIGURES

_SHORT = {"contact_duration": "duration", "peak_force": "peak", "impulse": "impulse",
          "restitution": "e"}

#: the issue's targets (#19) at 1 % noise, every case and band: |error| in %
TARGETS = {"restitution": 1.0, "impulse": 1.0, "contact_duration": 2.0, "peak_force": 10.0}
#: the same at 5 % noise
TARGETS_5 = {"restitution": 2.0, "impulse": 2.0, "contact_duration": 4.0, "peak_force": 20.0}
#: the families the first targets (10 modes, 1 %) were set for; #19 sets them for every case
TARGET_FAMILIES = ("mass-rod", "rod-rod")
#: the band must hold all four exact figures in at least this share of the cases at every
#: configuration (#19)
BAND_TARGET = 0.9


def targets_at(noise: float) -> dict:
    """The ``|error|`` targets (%) at a noise level: :data:`TARGETS` up to 1 %, else
    :data:`TARGETS_5`.

    Parameters
    ----------
    noise : float
        Noise level (a share, 0.01 for 1 %).

    Returns
    -------
    dict
        The target (%) of each figure.
    """
    return TARGETS if noise <= 0.01 + 1e-12 else TARGETS_5
def check_targets(table: pd.DataFrame) -> pd.DataFrame:
    """PASS/MISS per target and configuration (#19): at every band and noise, every case's
    four errors within :func:`targets_at` (1 %: e and impulse 1 %, duration 2 %, peak 10 %;
    5 %: 2 / 2 / 4 / 20 %); the band containing all four exact figures in at least
    :data:`BAND_TARGET` of the cases; ``e <= 1`` for every row.

    Parameters
    ----------
    table : pandas.DataFrame
        The benchmark's rows (:func:`run_benchmark`'s table).

    Returns
    -------
    pandas.DataFrame
        One row per target and configuration: ``target``, ``worst``, ``result``, ``misses``.
    """
    rows = []
    cols = [f"in_band_{_SHORT[k]}" for k in FIGURES]
    for (n, noise), sel in table.groupby(["n_modes", "noise"], sort=True):
        tol = targets_at(noise)
        ok = np.ones(len(sel), dtype=bool)
        worst = []
        for k, t in tol.items():
            err = sel[f"{_SHORT[k]}_err_%"].abs().to_numpy()
            ok &= err <= t                       # NaN (a failed row) misses
            largest = np.nanmax(err) if np.isfinite(err).any() else math.nan
            worst.append(f"{_SHORT[k]} {largest:.3g}")
        rows.append({"target": f"{n} modes, {100 * noise:g} %: every case within "
                     + "/".join(f"{t:g}" for t in tol.values()) + " % (e/J/D/P)",
                     "worst": f"{int(ok.sum())}/{len(sel)} cases pass; worst % "
                              + ", ".join(worst),
                     "result": "PASS" if ok.all() and len(sel) else "MISS",
                     "misses": ", ".join(c for c, good in zip(sel.case, ok) if not good)})
        banded = sel.dropna(subset=cols)
        if banded.empty:                         # no band at this configuration
            continue
        inside = banded[cols].astype(bool).all(axis=1)
        need = math.ceil(BAND_TARGET * len(sel) - 1e-9)
        rows.append({"target": f"{n} modes, {100 * noise:g} %: band holds all four exact "
                     f"figures in >= {need} of {len(sel)} cases",
                     "worst": f"{int(inside.sum())}/{len(sel)} cases; D/P/J/e held in "
                     + "/".join(str(int(banded[c].astype(bool).sum())) for c in cols),
                     "result": "PASS" if int(inside.sum()) >= need and len(sel) else "MISS",
                     "misses": ", ".join(r.case for r, good in zip(banded.itertuples(), inside)
                                         if not good)})
    above = table[table.e_above_1.fillna(False).astype(bool)]
    rows.append({"target": "no prediction with e > 1", "worst": f"max e = "
                 f"{table.e_pred.max():.6f}", "result": "PASS" if above.empty else "MISS",
                 "misses": ", ".join(above.case)})
    return pd.DataFrame(rows)


def markdown_table(table: pd.DataFrame) -> str:
    """The benchmark table in markdown, errors in % of the exact value, PASS/MISS marks
    against :func:`targets_at` in every cell, the band's half-widths in %.

    Parameters
    ----------
    table : pandas.DataFrame
        The benchmark's rows (:func:`run_benchmark`'s table).

    Returns
    -------
    str
        Markdown.
    """
    def mark(r, k, v):
        return f"{v:+.2f} {'PASS' if abs(v) <= targets_at(r['noise'])[k] else 'MISS'}"

    head = ("| case | modes | noise (H1 % per line) | duration % | peak % | impulse % | e % | "
            "e pred (exact) | damped truth D/P/J/e % | force err % | contacts | "
            "band contains D/P/J/e | band half-width D/P/J/e % | "
            "time hammer/ident/predict/band s |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for d in table.to_dict("records"):
        r = d
        if d.get("failure") and d["failure"].startswith("predict"):
            lines.append(f"| {d['case']} | {d['n_modes']} | {100 * d['noise']:g} % | "
                         f"failed: {d['failure']} |" + " |" * (head.count("|") - 5))
            continue
        cells = [mark(r, k, d[f"{_SHORT[k]}_err_%"]) for k in FIGURES]
        truth = "/".join(f"{d[f'{_SHORT[k]}_truth_err_%']:+.2f}" for k in FIGURES)
        inb = d["in_band_e"]
        banded = not (inb is None or (isinstance(inb, float) and math.isnan(inb)))
        contains = "/".join("y" if d[f"in_band_{_SHORT[k]}"] else "n" for k in FIGURES) \
            if banded else "-"
        widths = "/".join(
            format(0.5 * (d[f"band_hi_{_SHORT[k]}_%"] - d[f"band_lo_{_SHORT[k]}_%"]), ".2g")
            for k in FIGURES) if banded else "-"
        noise = f"{100 * d['noise']:g} %" + (f" ({d['frf_noise_%']})"
                                             if d.get("frf_noise_%") else "")
        lines.append(f"| {d['case']} | {d['n_modes']} | {noise} | "
                     + " | ".join(cells) + f" | {d['e_pred']:.4f} ({d['e_exact']:.4f}) | "
                     f"{truth} | {d['force_err_%']:.1f} | {d['contacts']} | {contains} | "
                     f"{widths} | "
                     f"{d['t_hammer_s']:.2f}/{d['t_identify_s']:.2f}/{d['t_predict_s']:.2f}/"
                     f"{d['t_band_s']:.1f} |")
    return "\n".join(lines)


def error_table(table: pd.DataFrame) -> str:
    """Markdown: per case and noise, each figure's ``|error|`` (%) at every band, side by side.

    Parameters
    ----------
    table : pandas.DataFrame
        The benchmark's rows (:func:`run_benchmark`'s table).

    Returns
    -------
    str
        Markdown.
    """
    bands = sorted(table.n_modes.unique())
    head = ("| case | noise | " + " | ".join(f"{_SHORT[k]} % at {'/'.join(map(str, bands))}"
                                             for k in FIGURES) + " |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for (case, noise), sel in table.groupby(["case", "noise"], sort=False):
        sel = sel.set_index("n_modes")
        cells = []
        for k in FIGURES:
            cells.append(" / ".join(f"{sel.loc[n, f'{_SHORT[k]}_err_%']:+.2f}" if n in sel.index
                                    else "-" for n in bands))
        lines.append(f"| {case} | {100 * noise:g} % | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _markdown(frame: pd.DataFrame) -> str:
    lines = ["| " + " | ".join(frame.columns) + " |", "|" + "---|" * len(frame.columns)]
    lines += ["| " + " | ".join(str(v) for v in r) + " |" for r in frame.itertuples(index=False)]
    return "\n".join(lines)


def _plot(out, case, ref, results):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.6))
    ax.plot(ref.t, ref.force, "k", lw=2, label="exact")
    for (n, noise), (t, force) in sorted(results.items()):
        ax.plot(t, force, lw=1, label=f"{n} modes, {100 * noise:g} % noise")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("contact force (N)")
    ax.set_title(case.key + ": " + case.description, fontsize=7)
    ax.legend(fontsize=7)
    fig.tight_layout()
    name = "".join(c if c.isalnum() else "_" for c in case.key)
    fig.savefig(Path(out) / f"force_{name}.png", dpi=100)
    plt.close(fig)
