"""The wave front's allowance of the uncertainty band's peak force.

Under a rigid contact the exact force may jump (a wave front arriving at the contact); a
band-limited, continued model rises within the band's resolution and overshoots the jump
at its crest (Gibbs, softened by the continuation's smooth tail). That overshoot is the
one error of the prediction whose sign is known, so the peak force's interval reaches
further down by :func:`front_allowance` of the :func:`front_jump`
(:func:`impactpred.uncertainty.uncertainty_band` adds it).
"""

from __future__ import annotations

import numpy as np

from ._figures import impact_figures

__all__ = ["FRONT_OVERSHOOT", "front_allowance", "front_jump"]


#: a continued model's overshoot where the force jumps (a wave front under a rigid contact),
#: per continued body, as a share of the jump: measured on the benchmark's damped truths,
#: noise-free, their first 10, 20 and 40 modes continued as a fit's are (0.003-0.024 for the
#: mass on a fixed rod, 0.018-0.029 per rod for two free rods; two rods' overshoots add).
#: Without continuation the residual flexibility rounds the front off instead (the mass on
#: the rod: the peak 20-27 % low), an error on the other side, which the truncation
#: estimate sees
FRONT_OVERSHOOT = 0.03


def front_jump(result, resolution: float) -> float:
    """The jump of the force at the first contact's peak: its range (max - min) within
    ``resolution`` of the peak.

    A model identified up to ``f_top`` resolves no feature shorter than ``resolution =
    1/(2 f_top)``; where the exact force jumps (a wave front), the model's force rises or
    falls within that time and overshoots the jump at its crest. A smooth peak (a Hertz
    pulse, a mass on a spring) changes little within it, so the range is small there.

    Parameters
    ----------
    result : ImpactResult
        The nominal prediction.
    resolution : float
        The band's resolution (s), :func:`~impactpred.truncation.band_resolution`; 0
        gives 0.

    Returns
    -------
    float
        The jump (N), 0 without a contact.
    """
    if resolution <= 0.0:
        return 0.0
    figs = impact_figures(result, resolution=resolution)
    if figs["n_contacts"] == 0:
        return 0.0
    t, force = np.asarray(result.t), np.asarray(result.force)
    start = result.contact_intervals[0][0]
    inside = np.flatnonzero((t >= start) & (t <= start + figs["contact_duration"]))
    if inside.size == 0:
        return 0.0
    t_peak = t[inside[int(np.argmax(force[inside]))]]
    near = force[np.abs(t - t_peak) <= resolution]
    return float(near.max() - near.min())


def front_allowance(jump: float, n_bodies: int) -> float:
    """How far below the nominal peak force the exact one may lie at a wave front.

    A continued model's force overshoots a jump of the exact force (Gibbs, softened by
    the continuation's smooth tail): by up to :data:`FRONT_OVERSHOOT` of the jump per
    continued body. The overshoot is an error of a known sign (the crest is above the
    plateau), so the peak's interval is widened downwards only.

    Parameters
    ----------
    jump : float
        The force's jump at the peak (N), :func:`front_jump`.
    n_bodies : int
        The identified, continued bodies (each rings at the front).

    Returns
    -------
    float
        The allowance (N).
    """
    return FRONT_OVERSHOOT * n_bodies * max(jump, 0.0)
