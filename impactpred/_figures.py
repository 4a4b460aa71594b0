"""The figures of an impact prediction: duration and peak of the first contact, total
impulse and restitution, read off an :class:`~impactpred.ImpactResult` with the contacts
a band-limited model cannot resolve merged (:func:`impact_figures`,
:func:`band_resolution`). Exported by :mod:`impactpred.truncation`; their uncertainty band
is :mod:`impactpred.uncertainty`.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import trapezoid

__all__ = ["FIGURES", "band_resolution", "impact_figures"]

#: the figures the uncertainty band covers (``ImpactResult`` attributes)
FIGURES = ("contact_duration", "peak_force", "impulse", "restitution")


def impact_figures(result, *, resolution: float = 0.0, ringing_share: float = 0.01) -> dict:
    """Duration and peak of the first contact, total impulse and restitution.

    ``resolution`` (s): contact intervals separated by less than this are merged into one
    contact. A model identified up to ``f_top`` cannot resolve features shorter than
    about ``1/(2 f_top)``: its force rings there (Gibbs) and may touch zero for a moment
    where the true force stays positive (the first pitfall of method.md). ``0`` keeps the
    solver's intervals as they are.

    The same ringing lifts the force above zero for a moment just after a separation: an
    interval that starts within ``resolution`` of the interval before it and carries less
    than ``ringing_share`` of the contact's impulse is ringing, not contact: it extends
    the contact only when a larger interval follows within ``resolution`` and within
    ``2 resolution`` (one period of the band top) of the contact's end (a dip of the
    contact's force), and never counts as a contact of its own (its impulse stays in the
    total; a true re-contact that close carries a share of the order of the contact's).
    An interval farther from the contact's end is a contact of its own.
    ``n_contacts_raw`` counts every interval of the solver.

    Parameters
    ----------
    result : ImpactResult
        A solved impact.
    resolution : float, keyword-only
        Merge contact intervals closer than this (s).
    ringing_share : float, keyword-only
        Share of the peak force under which ringing between merged intervals is ignored.

    Returns
    -------
    dict
        ``contact_duration`` (s), ``peak_force`` (N), ``impulse`` (N s), ``restitution`` and the
        contact counts.
    """
    intervals = list(result.contact_intervals)
    if not intervals:
        return {"contact_duration": 0.0, "peak_force": 0.0, "impulse": result.impulse,
                "restitution": result.restitution, "n_contacts": 0, "n_contacts_raw": 0}
    t, force = np.asarray(result.t), np.asarray(result.force)

    def impulse(start, end):
        inside = (t >= start) & (t <= end)
        return float(trapezoid(force[inside], t[inside])) if inside.sum() > 1 else 0.0

    merged = [[*intervals[0], impulse(*intervals[0])]]    # [start, end, impulse]
    last_end, pending = intervals[0][1], 0.0     # ringing since the contact's end
    for s, e in intervals[1:]:
        j = impulse(s, e)
        if s - last_end >= resolution:                    # a contact of its own
            merged.append([s, e, j])
            pending = 0.0
        elif j < ringing_share * merged[-1][2]:           # ringing, unless contact follows
            pending += j
        elif s - merged[-1][1] < 2.0 * resolution:        # the contact goes on (ringing
            merged[-1][1:] = [e, merged[-1][2] + pending + j]   # bridges a dip for one
            pending = 0.0                                 # period of the band top at most)
        else:                                             # too far after its end
            merged.append([s, e, j])
            pending = 0.0
        last_end = e
    start, end = merged[0][:2]
    inside = (t >= start) & (t <= end)
    peak = float(np.max(force[inside], initial=0.0))
    return {"contact_duration": end - start, "peak_force": peak, "impulse": result.impulse,
            "restitution": result.restitution, "n_contacts": len(merged),
            "n_contacts_raw": len(intervals)}


def band_resolution(fits) -> float:
    """``1/(2 f_top)`` of the narrowest band among the fits (0 when there is none).

    Parameters
    ----------
    fits : sequence of ModalFit or None
        The bodies' fits (None for a body that was not identified).

    Returns
    -------
    float
        The resolution (s).
    """
    tops = [fit.report_["band_hz"][1] for fit in fits if fit is not None]
    return 0.5 / min(tops) if tops else 0.0
