"""Stabilization diagram and automatic selection of physical poles.

A pole of order ``n`` is *stable* when a pole of the previous order computed lies within
``freq_tol`` (relative) in natural frequency and ``damp_tol`` (relative) in damping ratio;
given the data's line spacing, the frequency tolerance is also at most eight lines (the
distance that joins two poles in a cluster) and the two poles must be each other's
nearest. Physical poles are stable over many orders; noise poles wander. The table may
merge several (sub-)bands, each with its own orders (column ``band``).

Selection clusters the frequency-stable poles of all bands in (log frequency, log
damping) with scikit-learn's DBSCAN (damping estimates scatter more than frequencies
under noise, so damping is a coarse feature, not a hard criterion); a cluster's *share*
is the fraction of its best band's orders it appears in. :func:`select_by_information`
(:mod:`modalid._information`, re-exported here) then decides, by the Bayesian
information criterion on linear least-squares fits of the residues, how many of the
clusters ranked by share are physical (or, greedily, which of unranked candidates); no
hand picking.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.cluster import DBSCAN

from ._information import prefix_information, select_by_information
from .frf import _wrapped_phase

_JOIN_LINES = 8.0
"""With the data's line spacing: poles at most this many lines apart are a match between
orders and join in a cluster (besides ``freq_tol``)."""

__all__ = ["stabilization_table", "cluster_poles", "select_poles", "select_by_information",
           "prefix_information", "plot_stabilization", "plot_fit"]


def stabilization_table(poles_by_order, freq_band_hz, *, freq_tol=0.01, damp_tol=0.05,
                        max_damping=0.3, band=0, spacing_hz=None) -> pd.DataFrame:
    """One row per candidate pole (Im p > 0, in band, 0 < damping < max_damping).

    Orders without poles (not computed) are skipped: a pole is compared with the last
    order that has poles. Columns: ``band`` (index of the sub-band), ``order``, ``pole``,
    ``frequency_hz``, ``omega_n``, ``damping_ratio``, ``stable_freq``, ``stable_damp``,
    ``stable``. ``poles_by_order`` may also be a list of such lists with a matching list
    of bands (``freq_band_hz``): one table for all of them, ``band`` their index.

    Parameters
    ----------
    poles_by_order : list of (int, ndarray)
        ``(order, poles)`` pairs (rad/s), or a list of such lists, one per band.
    freq_band_hz : tuple of float or list of tuple
        The band (Hz), or one per list of ``poles_by_order``.
    freq_tol, damp_tol : float, keyword-only
        Relative changes of frequency and damping under which a pole is stable.
    max_damping : float, keyword-only
        Candidates of larger damping ratio are left out.
    band : int, keyword-only
        The ``band`` column's value for a single band.
    spacing_hz : float, optional, keyword-only
        The data's line spacing (Hz). Given, a pole is frequency-stable only within
        ``min(freq_tol f, 8 spacing_hz)`` of its match (as :func:`cluster_poles` joins
        poles), and only when each is the other's nearest: at high frequency ``freq_tol``
        spans many lines, and at high orders a band holds poles closer than that, so that
        almost every pole would find *some* pole of the previous order within it (93 % of
        a 12 800-line hammer FRF's, its stabilization chart solid blocks of "stable"
        poles).

    Returns
    -------
    pandas.DataFrame
    """
    if poles_by_order and isinstance(poles_by_order[0], list):
        parts = [_stability(p, b, freq_tol, damp_tol, max_damping, k, spacing_hz)
                 for k, (p, b) in enumerate(zip(poles_by_order, freq_band_hz))]
    else:
        parts = [_stability(poles_by_order, freq_band_hz, freq_tol, damp_tol, max_damping,
                            band, spacing_hz)]
    cols = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    table = pd.DataFrame({"band": cols["band"].astype(int), "order": cols["order"].astype(int),
                          "pole": cols["pole"].astype(complex),
                          "frequency_hz": cols["omega_n"] / (2 * np.pi),
                          "omega_n": cols["omega_n"], "damping_ratio": cols["damping_ratio"],
                          "stable_freq": cols["stable_freq"].astype(bool),
                          "stable_damp": cols["stable_damp"].astype(bool)})
    table["stable"] = table["stable_freq"] & table["stable_damp"]
    return table


def _stability(poles_by_order, freq_band_hz, freq_tol, damp_tol, max_damping, band,
               spacing_hz):
    """Columns (arrays) of :func:`stabilization_table` for one band."""
    max_step = np.inf if spacing_hz is None else _JOIN_LINES * 2 * np.pi * float(spacing_hz)
    cols = {k: [np.zeros(0)] for k in ("band", "order", "pole", "omega_n", "damping_ratio",
                                        "stable_freq", "stable_damp")}
    prev = None
    fmin, fmax = freq_band_hz
    for order, poles in enumerate(poles_by_order, start=1):
        if len(poles) == 0:
            continue
        p = poles[np.isfinite(poles) & (poles.imag > 0)]
        wn = np.abs(p)
        zeta = -p.real / wn
        keep = ((wn >= 2 * np.pi * fmin) & (wn <= 2 * np.pi * fmax)
                & (zeta > 0) & (zeta < max_damping))
        p, wn, zeta = p[keep], wn[keep], zeta[keep]
        if prev is not None and prev[0].size and p.size:
            dw = np.abs(wn[:, None] - prev[0][None, :])
            nearest = np.argmin(dw, axis=1)
            stable_f = dw[np.arange(p.size), nearest] <= np.minimum(freq_tol * wn, max_step)
            if spacing_hz is not None:                     # each the other's nearest
                stable_f &= np.argmin(dw, axis=0)[nearest] == np.arange(p.size)
            dz = np.abs(zeta - prev[1][nearest]) / np.maximum(zeta, 1e-12)
            stable_d = stable_f & (dz <= damp_tol)
        else:
            stable_f = np.zeros(p.size, bool)
            stable_d = np.zeros(p.size, bool)
        for key, value in (("band", np.full(p.size, band)), ("order", np.full(p.size, order)),
                           ("pole", p), ("omega_n", wn), ("damping_ratio", zeta),
                           ("stable_freq", stable_f), ("stable_damp", stable_d)):
            cols[key].append(value)
        prev = (wn, zeta)
    return {k: np.concatenate(v) for k, v in cols.items()}


def _frequency_feature(omega_n, freq_tol, spacing_hz):
    """Frequency coordinate in which a distance of 1 joins two poles: ``log(omega) /
    freq_tol`` up to the frequency where ``freq_tol`` of it is eight lines, in units of
    eight lines above it (continuous at the join)."""
    log_feature = np.log(omega_n) / freq_tol
    if spacing_hz is None:
        return log_feature
    step = _JOIN_LINES * 2 * np.pi * float(spacing_hz)       # rad/s
    join = step / freq_tol
    return np.where(omega_n <= join, log_feature,
                    np.log(join) / freq_tol + (omega_n - join) / step)


def cluster_poles(table: pd.DataFrame, *, freq_tol=0.01, representative="median",
                  spacing_hz=None) -> pd.DataFrame:
    """Clusters of frequency-stable poles, most persistent first.

    DBSCAN in (log frequency / ``freq_tol``, log2 damping) over the stable poles of every
    band together. With ``spacing_hz`` (the data's line spacing), the frequency distance
    that joins two poles is ``freq_tol`` of their frequency or eight lines, whichever is
    less: close modes (two lightly damped resonances 0.5 % apart on a 1 Hz grid at 4 kHz)
    stay two clusters instead of merging into one at their mean, while the poles of a
    peak sharper than a line, which scatter by a line or two over the orders, stay one.
    Per cluster: ``frequency_hz``, ``omega_n``, ``damping_ratio`` (medians
    over the members of its best band, or with ``representative="last"`` its member of the
    highest order: exact data), ``size`` (orders it appears in, over all bands),
    ``share`` (in its best band, the fraction of that band's orders it appears in),
    ``first_order``, ``band`` (its best band) and ``pole``.

    Parameters
    ----------
    table : pandas.DataFrame
        A :func:`stabilization_table`.
    freq_tol : float, keyword-only
        Relative frequency distance that joins two poles.
    representative : {"median", "last"}, keyword-only
        Each cluster's pole: the members' median, or the highest order's.
    spacing_hz : float, optional, keyword-only
        The data's line spacing (Hz).

    Returns
    -------
    pandas.DataFrame
        One row per cluster: its pole, frequency (Hz), damping ratio and persistence.
    """
    columns = ["frequency_hz", "omega_n", "damping_ratio", "size", "share", "first_order",
               "band", "pole"]
    stable = table[table["stable_freq"]]
    if stable.empty:
        return pd.DataFrame(columns=columns)
    zeta = stable["damping_ratio"].to_numpy()
    features = np.column_stack([_frequency_feature(stable["omega_n"].to_numpy(), freq_tol,
                                                   spacing_hz),
                                np.log(zeta) / np.log(2.0)])  # a factor 2 in damping ~ 1
    labels = DBSCAN(eps=1.0, min_samples=2).fit_predict(features)
    bands_all = table["band"].to_numpy()
    orders_all = table["order"].to_numpy()
    n_orders = {b: np.unique(orders_all[bands_all == b]).size for b in np.unique(bands_all)}
    band = stable["band"].to_numpy()
    order = stable["order"].to_numpy()
    wn_all = stable["omega_n"].to_numpy()
    rows = []
    for label in np.unique(labels[labels >= 0]):
        members = labels == label
        shares = {b: np.unique(order[members & (band == b)]).size / n_orders[b]
                  for b in np.unique(band[members])}
        best = max(shares, key=shares.get)  # type: ignore[arg-type]
        own = members & (band == best)
        if representative == "last":
            k = np.flatnonzero(own)[np.argmax(order[own])]
            wn, z = float(wn_all[k]), float(zeta[k])
        else:
            wn, z = float(np.median(wn_all[own])), float(np.median(zeta[own]))
        size = sum(np.unique(order[members & (band == b)]).size for b in shares)
        rows.append({"frequency_hz": wn / (2 * np.pi), "omega_n": wn, "damping_ratio": z,
                     "size": int(size), "share": float(shares[best]),
                     "first_order": int(order[own].min()), "band": int(best),
                     "pole": complex(-z * wn, wn * np.sqrt(1 - z**2))})
    clusters = pd.DataFrame(rows, columns=columns)
    clusters = clusters.sort_values(["share", "size"], ascending=False, kind="stable")
    return clusters.reset_index(drop=True)


def select_poles(clusters: pd.DataFrame, *, n_modes=None, frequencies_hz=None,
                 min_share=0.3):
    """Physical poles (Im p > 0) chosen among ``clusters`` (from :func:`cluster_poles`).

    Parameters
    ----------
    n_modes : int, optional
        Keep the ``n_modes`` most persistent clusters.
    frequencies_hz : sequence of float, optional
        Keep, for each frequency, the cluster nearest to it (within 5 % and nearer than
        half-way to the next requested frequency); a frequency with no cluster near it
        gets a pole of 1 % damping there. One pole per frequency, in the same order.
    min_share : float
        Without overrides: the clusters present in at least this share of their band's
        orders.

    Returns
    -------
    poles : ndarray of complex, sorted by frequency
    selected : ndarray of bool, one per cluster
    """
    selected = np.zeros(len(clusters), bool)
    extra = []
    if frequencies_hz is not None:
        freqs = clusters["frequency_hz"].to_numpy()
        req = np.sort(np.atleast_1d(np.asarray(frequencies_hz, float)))
        gap = np.diff(req)
        half = 0.5 * np.minimum(np.append(gap, np.inf), np.insert(gap, 0, np.inf))
        for f, hw in zip(req, half):
            k = int(np.argmin(np.abs(freqs - f))) if freqs.size else -1
            wn, zeta = 2 * np.pi * float(f), 0.01
            if k >= 0 and abs(freqs[k] - f) <= min(0.05 * f, hw) and not selected[k]:
                selected[k] = True
                if abs(freqs[k] - f) <= 1e-3 * f:
                    continue
                # the cluster is off the resonance: its damping, at the given frequency
                zeta = float(np.clip(clusters["damping_ratio"].iloc[k], 1e-4, 0.01))
            extra.append(complex(-zeta * wn, wn * np.sqrt(1 - zeta**2)))
    elif n_modes is not None:
        selected[:min(n_modes, len(clusters))] = True
    else:
        selected = (clusters["share"] >= min_share).to_numpy()
    use = selected.copy()
    if frequencies_hz is not None:
        near = np.abs(clusters["frequency_hz"].to_numpy()[:, None] - req) <= 1e-3 * req
        use &= near.any(axis=1)
    poles = np.concatenate([clusters["pole"].to_numpy(complex)[use],
                            np.asarray(extra, complex)])
    return poles[np.argsort(np.abs(poles))], selected


_UNITS = {"receptance": "m/N", "mobility": "m/s/N", "accelerance": "m/s²/N"}


def _frequency_scale(freq_hz):
    """``"log"`` when half the poles ``freq_hz`` lie in the bottom tenth of the band (a
    wide band whose low modes a linear axis would crowd), ``"linear"`` otherwise."""
    freq_hz = np.asarray(freq_hz, float)
    freq_hz = freq_hz[freq_hz > 0]
    if freq_hz.size < 2:
        return "linear"
    return "log" if np.median(freq_hz) < 0.1 * freq_hz.max() else "linear"


def _draw_frf_behind(ax, frf, xscale):
    """The magnitude of ``frf`` (FRFData; the mean over the rows of an FRFSet) on a twin
    axis drawn behind ``ax``'s poles; returns the line."""
    freq = np.asarray(frf.freq_hz, float)
    magnitude = np.abs(np.asarray(frf.values))
    label = f"|{frf.quantity}|"
    if magnitude.ndim == 2:
        magnitude, label = magnitude.mean(axis=0), f"mean |{frf.quantity}|"
    keep = (freq > 0) & (magnitude > 0) if xscale == "log" else magnitude > 0
    twin = ax.twinx()
    (line,) = twin.semilogy(freq[keep], magnitude[keep], color="0.35", lw=0.9, zorder=1,
                            label=f"{label} (measured)")
    twin.set_ylabel(f"{label} ({_UNITS.get(frf.quantity, 'SI')})")
    ax.set_zorder(twin.get_zorder() + 1)              # the poles over the curve
    ax.patch.set_visible(False)
    return line


def plot_stabilization(table: pd.DataFrame, *, frf=None, selected=None, ax=None,
                       xscale="auto"):
    """Stabilization diagram (model order against frequency in Hz); returns the Axes.

    Drawn to stay readable on noisy data, as modal analysis tools draw it: poles stable in
    frequency and damping as filled blue circles, poles stable in frequency only as open
    orange circles, the other (new, unstable) poles as small pale dots behind them; the
    selected poles as red dashed lines with a red marker above the chart; the measured
    FRF's magnitude, in its own quantity and units, on a twin log axis behind the poles;
    the legend above the chart, off the data.

    With ``selected``, the diagram is *cleared* (as automated modal analysis draws it): a
    stable pole keeps its strong marker when it supports a selected pole (within 1 % of
    its frequency or eight lines of ``frf``, whichever is less, and within a factor 2 of
    its damping: how :func:`cluster_poles` joins poles), and is drawn faint otherwise. At
    high orders on noisy data the estimator's noise poles are stable too, and would
    otherwise fill whole segments of the chart.

    Parameters
    ----------
    table : pandas.DataFrame
        A :func:`stabilization_table`.
    frf : FRFData or FRFSet, optional, keyword-only
        Data whose magnitude is drawn behind the poles (an FRFSet: the mean magnitude of
        its rows).
    selected : array_like of complex, optional, keyword-only
        The selected poles (rad/s), marked; the stable poles that support none of them
        are drawn faint.
    ax : matplotlib.axes.Axes, optional, keyword-only
        Where to draw (a new figure when None).
    xscale : {"auto", "linear", "log"}, keyword-only
        The frequency axis; ``"auto"``: logarithmic when half the stable poles lie in the
        bottom tenth of the band, linear otherwise.

    Returns
    -------
    matplotlib.axes.Axes
        The Axes of the poles (the FRF's twin is ``ax.figure.axes`` after it).

    Raises
    ------
    ValueError
        ``xscale`` not one of the three.
    """
    import matplotlib.pyplot as plt
    from matplotlib.transforms import blended_transform_factory

    if xscale not in ("auto", "linear", "log"):
        raise ValueError(f"xscale must be 'auto', 'linear' or 'log', got {xscale!r}")
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5.5))
    freq = table["frequency_hz"].to_numpy(float)
    order = table["order"].to_numpy(float)
    stable = table["stable"].to_numpy(bool)
    freq_only = table["stable_freq"].to_numpy(bool) & ~stable
    new = ~table["stable_freq"].to_numpy(bool)
    if xscale == "auto":
        xscale = _frequency_scale(freq[stable] if stable.sum() >= 2 else freq)
    picked = (np.zeros(0, complex) if selected is None
              else np.atleast_1d(np.asarray(selected, complex)))
    supports = _supports(table, picked, frf) if picked.size else np.ones(freq.size, bool)
    handles = []
    if frf is not None:
        handles.append(_draw_frf_behind(ax, frf, xscale))
    handles += ax.plot(freq[new], order[new], ".", ms=2.5, color="0.72", alpha=0.6,
                       ls="none", zorder=2, label="new (not stable)")
    faint = (stable | freq_only) & ~supports
    if faint.any():
        handles += ax.plot(freq[faint], order[faint], "o", ms=2.5, mfc="none", mec="C0",
                           mew=0.5, alpha=0.3, ls="none", zorder=2,
                           label="stable, no selected pole")
    freq_only = freq_only & supports
    stable = stable & supports
    handles += ax.plot(freq[freq_only], order[freq_only], "o", ms=3.2, mfc="none",
                       mec="C1", mew=0.7, alpha=0.6, ls="none", zorder=3,
                       label="stable frequency")
    handles += ax.plot(freq[stable], order[stable], "o", ms=3.5, color="C0", mec="C0",
                       ls="none", zorder=4, label="stable frequency and damping")
    if picked.size:
        chosen = np.sort(np.abs(picked)) / (2 * np.pi)
        top = blended_transform_factory(ax.transData, ax.transAxes)
        for f in chosen:
            ax.axvline(f, color="C3", lw=0.9, ls="--", alpha=0.7, zorder=1)
        handles += ax.plot(chosen, np.full(chosen.size, 1.0), "v", ms=7, color="C3",
                           transform=top, clip_on=False, ls="none", zorder=5,
                           label=f"selected ({chosen.size})")
    ax.set_xscale(xscale)
    low = freq[freq > 0].min() if np.any(freq > 0) else None
    if frf is not None:
        lines = np.asarray(frf.freq_hz, float)
        lines = lines[lines > 0] if xscale == "log" else lines
        if lines.size:
            ax.set_xlim(lines.min(), lines.max())
    elif low is not None and xscale == "log":
        ax.set_xlim(low / 1.1, freq.max() * 1.1)
    ax.set_ylim(0, max(order.max() if order.size else 1.0, 1.0) * 1.04)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("model order")
    ax.legend(handles=handles, loc="lower left", bbox_to_anchor=(0.0, 1.05), ncol=3,
              fontsize=8, frameon=False, borderaxespad=0.0, handletextpad=0.3,
              columnspacing=1.2)
    return ax


def _supports(table, selected, frf):
    """Per pole of ``table``: does it lie within 1 % (or eight lines of ``frf``, if less)
    of a ``selected`` pole's frequency and within a factor 2 of its damping ratio?"""
    freq = table["frequency_hz"].to_numpy(float)
    zeta = table["damping_ratio"].to_numpy(float)
    f_sel = np.abs(selected) / (2 * np.pi)
    z_sel = -selected.real / np.maximum(np.abs(selected), 1e-300)
    reach = 0.01 * f_sel
    lines = None if frf is None else np.asarray(frf.freq_hz, float)
    if lines is not None and lines.size > 1:
        reach = np.minimum(reach, _JOIN_LINES * float(np.median(np.diff(lines))))
    near = np.abs(freq[:, None] - f_sel[None, :]) <= reach
    with np.errstate(divide="ignore", invalid="ignore"):
        alike = np.abs(np.log2(zeta[:, None] / z_sel[None, :])) <= 1.0
    return np.any(near & alike, axis=1)


def plot_fit(model, *, frf=None, impulse=None, ax=None, fitted=None):
    """A model against the FRF or impulse response ``(t, h)`` it was fitted to.

    An FRF is drawn in its own quantity (what was measured, not always receptance):
    magnitude on a log axis, phase (degrees) and, where the data carry it, the coherence,
    on Axes that share the frequency axis, the model in red over the data in grey.
    ``fitted``: the model's values on ``frf``'s lines above 0 Hz, when they are not
    ``model.frf`` (a windowed fit).

    Parameters
    ----------
    model : ModalModel
        The fitted model.
    frf : FRFData, optional, keyword-only
        The data it was fitted to.
    impulse : tuple of ndarray, optional, keyword-only
        ``(t, h)`` for a fit to an impulse response.
    ax : matplotlib.axes.Axes or sequence of Axes, optional, keyword-only
        One Axes: the magnitude only (or the impulse response). A sequence: magnitude,
        phase and coherence, as many as it holds. None: a new figure with the magnitude,
        the phase and (when measured) the coherence.
    fitted : ndarray, optional, keyword-only
        The model's values on the data's lines.

    Returns
    -------
    matplotlib.axes.Axes or sequence of Axes
        ``ax`` as given; with ``ax=None`` the magnitude's Axes (the phase's and the
        coherence's are ``ax.figure.axes[1:]``).
    """
    import matplotlib.pyplot as plt

    if impulse is not None:
        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        t, h = impulse
        ax.plot(t, h, color="0.6", label="data")
        ax.plot(t, model.impulse_response(t), "C3", lw=1, label="ModalFit")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("impulse response (m/(N s))")
        ax.legend(fontsize=8, loc="best")
        return ax
    frf = frf.select(frf.freq_hz > 0)
    if fitted is None:
        fitted = model.frf(frf.omega, quantity=frf.quantity)
    created = ax is None
    if created:
        rows = 3 if frf.coherence is not None else 2
        _, ax = plt.subplots(rows, 1, figsize=(7, 2.0 * rows + 2.0), sharex=True,
                             gridspec_kw={"height_ratios": [3.0, 1.5, 1.0][:rows]})
    axes = np.ravel(np.asarray(ax, dtype=object))
    magnitude = axes[0]
    frf.plot(ax=magnitude, label="data", color="0.6")
    magnitude.semilogy(frf.freq_hz, np.abs(fitted), "C3", lw=1, label="ModalFit")
    magnitude.legend(fontsize=8, loc="best")
    if axes.size > 1:
        phase = frf.plot_phase(ax=axes[1], color="0.6", lw=1)
        phase.plot(*_wrapped_phase(frf.freq_hz, fitted), "C3", lw=1)
        phase.set_ylim(-190.0, 190.0)
        phase.set_yticks([-180, -90, 0, 90, 180])
    if axes.size > 2 and frf.coherence is not None:
        coherence = axes[2]
        coherence.plot(frf.freq_hz, frf.coherence, color="C0", lw=1)
        coherence.set_ylim(0.0, 1.05)
        coherence.set_ylabel("coherence")
    if axes.size > 1:
        for upper in axes[:-1]:
            upper.set_xlabel("")
        axes[-1].set_xlabel("frequency (Hz)")
    return axes[0] if created else ax
