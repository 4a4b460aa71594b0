"""A damping ratio the lines cannot resolve, taken off the refinement's lower bound.

A resonance narrower than the line spacing (an analyzer's sharp peak: half-power
bandwidth ``2 zeta f`` well under one line) shows its frequency in the shape of the
lines around it, but not its width: every damping small enough fits those lines about
alike, and the refinement may then drift to its bound (``zeta`` of about 1e-9), a value
no structure has and a prediction would ring with for ever. Such a mode keeps its
frequency and gets the largest of a few small damping ratios that fits the band as well
(:func:`damping_off_bound`); the modes table says its damping is not resolved
(:func:`modalid._verdict.damping_resolved`). Where the data do prefer the bound, the
mode stays there and the verdict says so. :func:`lift_single` applies it to the fit of
one FRF (the common-pole fit's counterpart lives in :mod:`modalid._global`).
"""

from __future__ import annotations

import numpy as np

from ._lsfd import refine_varpro
from ._verdict import MIN_DAMPING

__all__ = ["damping_off_bound", "lift_single", "BANDWIDTH_SHARES", "FLOOR"]

# the damping ratios tried, largest first: half-power bandwidths of these shares of a line
BANDWIDTH_SHARES = (0.25, 0.025, 0.0025)
#: no candidate below this many times the verdict's bound (a mode far above its lines'
#: spacing, f / df over 1250, would otherwise be moved from one sub-bound value to another)
FLOOR = 2.0


def damping_off_bound(n_data, n_params, line_spacing_hz, poles, kinds, cost, refit):
    """Move each physical pole whose damping ratio sits at or below the verdict's bound
    (``MIN_DAMPING``, 1e-6) to the largest of :data:`BANDWIDTH_SHARES` (half-power
    bandwidth ``2 zeta f`` as a share of the line spacing; at least :data:`FLOOR` times the
    bound) that the data cannot tell from where it was.

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
        carries ``"cost"``, ``"converged"`` and ``"n_iter"``).

    Returns
    -------
    fit : tuple or None
        ``(poles, x, info)`` of the refit with the moved poles held, or None when no pole
        sits at the bound or the data prefer it for every candidate.
    notes : list of str
        What was moved (or kept) and the cost it took, in residual variances.
    n_iter : int
        The refinement steps every trial took.

    Notes
    -----
    A candidate is taken when its refit converged and holding the pole there raises the
    cost, from the fit before this pole was moved, by less than ``ln(n_data)`` residual
    variances (the information criterion's price of the one parameter, the damping,
    that the data would otherwise set). The frequency is the bound fit's: the lines'
    shape fixed it.
    """
    zeta = -poles.real / np.abs(poles)
    low = np.flatnonzero((kinds == "mode") & (zeta <= MIN_DAMPING))
    if low.size == 0:
        return None, [], 0
    sigma2 = cost / max(n_data - n_params, 1)
    allowed = np.log(n_data)
    held = np.zeros(poles.size, bool)
    best, notes, n_iter = None, [], 0
    for k in low:
        wn = abs(poles[k])
        f_hz = wn / (2 * np.pi)
        ratios = dict.fromkeys(max(share * line_spacing_hz / (2 * f_hz), FLOOR * MIN_DAMPING)
                               for share in BANDWIDTH_SHARES)
        for z in ratios:
            trial = poles.copy()
            trial[k] = wn * complex(-z, np.sqrt(1 - z * z))
            fit = refit(trial, held | (np.arange(poles.size) == k))
            n_iter += fit[2]["n_iter"]
            rise = (fit[2]["cost"] - cost) / sigma2
            if fit[2]["converged"] and rise < allowed:
                poles, best, cost = fit[0], fit, fit[2]["cost"]
                held[k] = True
                width = 2 * z * f_hz / line_spacing_hz
                notes.append(f"mode at {f_hz:.6g} Hz: its damping ratio came out at "
                             f"{zeta[k]:.2g}, at the refinement's bound or below 1e-6; the "
                             f"lines, {line_spacing_hz:.3g} Hz apart, do not resolve it: set "
                             f"to {z:.2g} (half-power bandwidth {width:.2g} of a line), "
                             f"which fits them as well (cost {rise:+.2g} residual variances)")
                break
        else:
            notes.append(f"mode at {f_hz:.6g} Hz: its damping ratio stays at {zeta[k]:.2g}: "
                         "the lines prefer it to a half-power bandwidth of "
                         f"{BANDWIDTH_SHARES[-1]:g} of a line")
    return best, notes, n_iter


def lift_single(est, frf, poles, kinds, x, info, terms, notes):
    """:func:`damping_off_bound` in the fit of one FRF (``est``: the
    :class:`modalid.ModalFit` being fitted, its final weights and bounds; ``frf``: the
    receptance fitted). Returns ``(poles, x, info)``, moved or as they were; appends to
    ``notes`` and counts the steps in ``est._iterations``."""
    omega, h = frf.omega, frf.values
    lo, hi = est._imag_bounds(kinds, omega, poles)
    kw = dict(imag_lo=lo, imag_hi=hi, passive=est._passive_on, zero_start=est._zero_start,
              buffers=est._buffers,
              max_iter=max(50, 4 * poles.size))
    if est.max_real is not None:
        kw["max_real"] = est.max_real

    def refit(trial, hold):
        return refine_varpro(omega, h, est._final_weights, trial, terms,
                             hold=hold | (kinds == "far"), **kw)

    spacing = float(np.median(np.diff(frf.freq_hz)))
    fit, said, n_iter = damping_off_bound(2 * omega.size, x.size + 2 * poles.size, spacing,
                                          poles, kinds, info["cost"], refit)
    notes += said
    est._iterations += n_iter
    return (poles, x, info) if fit is None else fit
