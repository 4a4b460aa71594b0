"""Stabilization diagram and automatic selection of physical poles.

A pole of order ``n`` is *stable* when a pole of order ``n - 1`` lies within ``freq_tol``
(relative) in natural frequency and ``damp_tol`` (relative) in damping ratio. Physical
poles are stable over many orders; noise poles wander. Selection clusters the frequency-stable poles in (log frequency, damping)
with scikit-learn's DBSCAN and keeps clusters that persist over a good share of the
orders; no hand picking. (Damping estimates scatter more than frequencies under noise,
so damping enters the clustering as a coarse feature rather than as a hard criterion.)
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.cluster import DBSCAN

__all__ = ["stabilization_table", "select_poles", "plot_stabilization"]


def stabilization_table(poles_by_order, freq_band_hz, *, freq_tol=0.01, damp_tol=0.05,
                        max_damping=0.3) -> pd.DataFrame:
    """One row per candidate pole (Im p > 0, in band, 0 < damping < max_damping).

    Columns: ``order``, ``pole``, ``frequency_hz``, ``omega_n``, ``damping_ratio``,
    ``stable_freq``, ``stable_damp``, ``stable``.
    """
    rows = []
    prev = None
    fmin, fmax = freq_band_hz
    for order, poles in enumerate(poles_by_order, start=1):
        p = poles[np.isfinite(poles) & (poles.imag > 0)]
        wn = np.abs(p)
        zeta = -p.real / wn
        keep = ((wn / (2 * np.pi) >= fmin) & (wn / (2 * np.pi) <= fmax)
                & (zeta > 0) & (zeta < max_damping))
        p, wn, zeta = p[keep], wn[keep], zeta[keep]
        if prev is not None and prev[0].size and p.size:
            dw = np.abs(wn[:, None] - prev[0][None, :]) / wn[:, None]
            nearest = np.argmin(dw, axis=1)
            stable_f = dw[np.arange(p.size), nearest] <= freq_tol
            dz = np.abs(zeta - prev[1][nearest]) / np.maximum(zeta, 1e-12)
            stable_d = stable_f & (dz <= damp_tol)
        else:
            stable_f = np.zeros(p.size, bool)
            stable_d = np.zeros(p.size, bool)
        for i in range(p.size):
            rows.append((order, p[i], wn[i] / (2 * np.pi), wn[i], zeta[i], bool(stable_f[i]),
                         bool(stable_d[i])))
        prev = (wn, zeta)
    table = pd.DataFrame(rows, columns=["order", "pole", "frequency_hz", "omega_n",
                                        "damping_ratio", "stable_freq", "stable_damp"])
    table["stable"] = table["stable_freq"] & table["stable_damp"]
    return table


def select_poles(table: pd.DataFrame, *, n_modes=None, frequencies_hz=None, freq_tol=0.01,
                 min_share=0.3):
    """Physical poles (Im p > 0) chosen from a stabilization table.

    Parameters
    ----------
    n_modes : int, optional
        Keep the ``n_modes`` most persistent clusters.
    frequencies_hz : sequence of float, optional
        Keep, for each frequency, the cluster nearest to it.
    min_share : float
        Without overrides, a cluster must hold stable poles from at least this share of
        the orders in which poles near its frequency could appear.

    Returns
    -------
    poles : ndarray of complex, sorted by frequency
    clusters : DataFrame (one row per cluster: frequency_hz, damping_ratio, size, selected)
    """
    stable = table[table["stable_freq"]]
    n_orders = int(table["order"].max()) if len(table) else 0
    if stable.empty:
        return np.zeros(0, complex), pd.DataFrame(columns=["frequency_hz", "damping_ratio",
                                                           "size", "selected"])
    zeta = stable["damping_ratio"].to_numpy()
    features = np.column_stack([np.log(stable["omega_n"].to_numpy()) / freq_tol,
                                np.log(zeta) / np.log(2.0)])  # a factor 2 in damping ~ 1
    labels = DBSCAN(eps=1.0, min_samples=2).fit_predict(features)
    clusters = []
    for label in sorted(set(labels) - {-1}):
        members = stable[labels == label]
        # one pole per order: a cluster is as large as the orders it persists over
        size = members["order"].nunique()
        first_order = int(members["order"].min())
        possible = max(n_orders - first_order + 1, 1)
        wn = float(np.median(members["omega_n"]))
        zeta = float(np.median(members["damping_ratio"]))
        clusters.append({"frequency_hz": wn / (2 * np.pi), "omega_n": wn,
                         "damping_ratio": zeta, "size": size, "share": size / possible,
                         "first_order": first_order})
    clusters = pd.DataFrame(clusters)
    if clusters.empty:
        clusters["selected"] = []
        return np.zeros(0, complex), clusters
    if frequencies_hz is not None:
        chosen = set()
        for f in np.atleast_1d(frequencies_hz):
            chosen.add(int(np.argmin(np.abs(clusters["frequency_hz"] - f))))
        selected = np.zeros(len(clusters), bool)
        selected[list(chosen)] = True
    elif n_modes is not None:
        order = np.argsort(-clusters["size"].to_numpy(), kind="stable")[:n_modes]
        selected = np.zeros(len(clusters), bool)
        selected[order] = True
    else:
        selected = (clusters["share"] >= min_share).to_numpy() & (clusters["size"] >= 3)
    clusters["selected"] = selected
    picked = clusters[selected].sort_values("omega_n")
    wn, zeta = picked["omega_n"].to_numpy(), picked["damping_ratio"].to_numpy()
    poles = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    return poles, clusters.reset_index(drop=True)


def plot_stabilization(table: pd.DataFrame, *, frf=None, selected=None, ax=None):
    """Stabilization diagram (order against frequency in Hz); returns the Axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5))
    groups = [("new", ~table["stable_freq"], "o", "lightgray"),
              ("stable frequency", table["stable_freq"] & ~table["stable"], "x", "C1"),
              ("stable frequency and damping", table["stable"], "+", "C2")]
    for label, mask, marker, color in groups:
        ax.plot(table.loc[mask, "frequency_hz"], table.loc[mask, "order"], marker, ms=4,
                color=color, ls="none", label=label)
    if selected is not None:
        for p in np.atleast_1d(selected):
            ax.axvline(abs(p) / (2 * np.pi), color="C3", lw=0.8, alpha=0.6)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("model order")
    if frf is not None:
        twin = ax.twinx()
        twin.semilogy(frf.freq_hz, np.abs(frf.values), color="k", lw=0.7)
        twin.set_ylabel(f"|{frf.quantity}|")
    ax.legend(loc="lower right", fontsize=8)
    return ax
