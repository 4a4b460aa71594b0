"""A damping ratio the lines cannot resolve, taken off the refinement's lower bound.

A resonance narrower than the line spacing (an analyzer's sharp peak: half-power
bandwidth ``2 zeta f`` well under one line) shows its frequency in the shape of the
lines around it, but not its width: every damping small enough fits those lines about
alike, and the refinement may then drift to its bound (``zeta`` of about 1e-9), a value
no structure has and a prediction would ring with for ever. Such a mode keeps its
frequency and gets the largest of a few small damping ratios that fits the band as well
(:func:`damping_off_bound`); the modes table says its damping is not resolved
(:func:`modalid._verdict.damping_resolved`). Where the data do prefer the bound, the
mode stays there and the verdict says so.
"""

from __future__ import annotations

import numpy as np

from ._verdict import MIN_DAMPING

__all__ = ["damping_off_bound", "BANDWIDTH_SHARES"]

# the damping ratios tried, largest first: half-power bandwidths of these shares of a line
BANDWIDTH_SHARES = (0.25, 0.025, 0.0025)


def damping_off_bound(n_data, n_params, line_spacing_hz, poles, kinds, cost, refit):
    """Move each physical pole whose damping ratio sits at the refinement's bound to the
    largest of :data:`BANDWIDTH_SHARES` (half-power bandwidth ``2 zeta f`` as a share of
    the line spacing) that the data cannot tell from the bound.

    Parameters
    ----------
    n_data, n_params : int
        The real residuals the cost sums (twice the lines, times the rows of a set) and
        the real parameters fitted (poles, residues, extra terms).
    line_spacing_hz : float
        The lines' spacing (Hz).
    poles : ndarray of complex, shape (n,)
        The refined poles (rad/s).
    kinds : ndarray of str, shape (n,)
        ``"mode"`` for a physical pole (the others are left alone).
    cost : float
        The refined fit's weighted cost (the squared norm of its weighted residual).
    refit : callable
        ``refit(poles, hold) -> (poles, x, info)``: the refinement with the poles of the
        boolean mask ``hold`` held where they are, weighted as ``cost`` is (``info``
        carries ``"cost"``).

    Returns
    -------
    fit : tuple or None
        ``(poles, x, info)`` of the refit with the moved poles held, or None when no pole
        sits at the bound or the data prefer the bound for every candidate.
    notes : list of str
        What was moved (or kept at the bound) and the cost it took, in residual variances.

    Notes
    -----
    A candidate is taken when holding the pole there raises the cost by less than
    ``ln(n_data)`` residual variances (the information criterion's price of the one
    parameter, the damping, that the data would otherwise set). The frequency is the
    bound fit's: the lines' shape fixed it.
    """
    zeta = -poles.real / np.abs(poles)
    at_bound = np.flatnonzero((kinds == "mode") & (zeta <= MIN_DAMPING))
    if at_bound.size == 0:
        return None, []
    sigma2 = cost / max(n_data - n_params, 1)
    allowed = np.log(n_data)
    held = np.zeros(poles.size, bool)
    best, notes = None, []
    for k in at_bound:
        wn = abs(poles[k])
        f_hz = wn / (2 * np.pi)
        for share in BANDWIDTH_SHARES:
            z = share * line_spacing_hz / (2 * f_hz)
            trial = poles.copy()
            trial[k] = wn * complex(-z, np.sqrt(1 - z * z))
            fit = refit(trial, held | (np.arange(poles.size) == k))
            rise = (fit[2]["cost"] - cost) / sigma2
            if rise < allowed:
                poles, best = fit[0], fit
                held[k] = True
                notes.append(f"mode at {f_hz:.6g} Hz: its damping went to the refinement's "
                             f"bound ({zeta[k]:.2g}); the lines, {line_spacing_hz:.3g} Hz "
                             f"apart, do not resolve it: set to {z:.2g} (half-power "
                             f"bandwidth {share:g} of a line), which fits them as well "
                             f"(cost {rise:+.2g} residual variances)")
                break
        else:
            notes.append(f"mode at {f_hz:.6g} Hz: its damping stays at the refinement's "
                         "bound: the lines prefer it to a half-power bandwidth of "
                         f"{BANDWIDTH_SHARES[-1]:g} of a line")
    return best, notes
