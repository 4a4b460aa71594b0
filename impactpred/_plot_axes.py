"""What the result plots share: twin axes whose zeros line up, and a legend kept off the
curves (drawn in headroom made for it above the data)."""

from __future__ import annotations

import numpy as np

__all__ = ["align_zeros", "legend_above_data"]


def align_zeros(*axes) -> None:
    """Set the y-limits of ``axes`` (twins sharing the x axis) so that y = 0 is at the same
    height on all of them; every limit only widens, so nothing drawn leaves its axis.

    The common height of the zero is the one that stretches the worst-stretched axis
    least (every axis's range widened to include 0 first).

    Parameters
    ----------
    *axes : matplotlib.axes.Axes
        Linear y axes.

    Returns
    -------
    None
    """
    limits = []
    for ax in axes:
        low, high = ax.get_ylim()
        limits.append((min(low, 0.0), max(high, 0.0)))
    used = [(ax, -low, high) for ax, (low, high) in zip(axes, limits) if high > low]
    if len(used) < 2:
        return
    below = np.array([n for _, n, _ in used])
    above = np.array([p for _, _, p in used])
    if not above.any():
        zero = 1.0                                  # everything at or below zero
    elif not below.any():
        zero = 0.0
    else:
        heights = np.linspace(1e-3, 1.0 - 1e-3, 999)[:, None]
        span = np.maximum(below / heights, above / (1.0 - heights))
        zero = float(heights[np.argmin(np.max(span / (below + above), axis=1)), 0])
    for ax, n, p in used:
        if zero >= 1.0:
            ax.set_ylim(-n, 0.0)
        elif zero <= 0.0:
            ax.set_ylim(0.0, p)
        else:
            span = max(n / zero, p / (1.0 - zero))
            ax.set_ylim(-zero * span, (1.0 - zero) * span)


def legend_above_data(ax, handles, labels, *, axes=(), ncol=None, loc="upper right",
                      fontsize=8):
    """A legend inside ``ax``'s top edge, with the y-limits of ``ax`` and of ``axes`` (its
    twins) raised so that no data reach the band it covers; zeros aligned by
    :func:`align_zeros` stay aligned (every axis is stretched by the same factor).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes holding the legend.
    handles, labels : list
        The legend's entries.
    axes : sequence of matplotlib.axes.Axes, keyword-only
        Twins of ``ax`` whose data must stay clear of the legend too.
    ncol : int, optional, keyword-only
        Columns (default: up to four entries a row).
    loc : str, keyword-only
        ``"upper right"`` or ``"upper left"``.
    fontsize : float or str, keyword-only

    Returns
    -------
    matplotlib.legend.Legend
    """
    ncol = ncol or min(max(len(handles), 1), 4)
    legend = ax.legend(handles, labels, loc=loc, ncol=ncol, fontsize=fontsize,
                       framealpha=0.85, borderaxespad=0.4, columnspacing=1.2,
                       handlelength=1.8)
    # the figure's renderer, whatever the backend (matplotlib >= 3.6 finds it itself)
    box = legend.get_window_extent().transformed(ax.transAxes.inverted())
    # the band the legend covers, as a fraction of the axes' height, with a margin for a
    # later tight_layout that shrinks the axes (the legend keeps its size in points)
    band = float(np.clip(1.25 * (1.0 - box.y0) + 0.02, 0.1, 0.6))
    for each in (ax, *axes):
        low, high = each.get_ylim()
        if each.get_yscale() == "log":
            top = np.log10(high) + (np.log10(high) - np.log10(low)) * band / (1.0 - band)
            each.set_ylim(low, 10.0 ** top)
        else:
            each.set_ylim(low, low + (high - low) / (1.0 - band))
    return legend
