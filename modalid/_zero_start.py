"""A driving point's fitted impulse response that starts against the force, held at 0.

``h(0) = sum 2 Re r_k + sum c_j`` is the receptance's impulse response at ``t = 0+``,
the mobility's limit at high frequency ``Re Y(i oo)``. For any structure it is 0 (a
displacement does not jump under an impulse); the passivity bounds of a driving point's
fit (``Im r <= 0``; ``c_j, u, d >= 0``) do not see it, and a pseudo-mode's real residue,
fitted to the band's background, can make it negative: a response that starts against
the force, which the impact solvers refuse ("not driving points"). Such a fit is refined
again, once its poles are found, holding ``h(0) = 0`` (``refine_varpro(zero_start=True)``);
held from the start, the equality couples the candidate modes' residues and the search
loses modes (three all but undamped modes seen at three points: none found). A positive
``h(0)`` (an instantaneous give, as a dashpot's) is passive and left alone, as is a
negative one within :data:`TRIGGER` of the size of its terms (``sum |Re r_k| +
sum |c_j| / 2``: the rounding of their sum). Measured against the residues themselves that is
no margin: a cantilever's fit at 1 % noise with ``h(0) = -4.9e-5 sum |r_k|`` is held too.
"""

from __future__ import annotations

from ._lsfd import _bounds

__all__ = ["TRIGGER", "hold_at_zero", "hold_single"]

#: ``h(0)`` below minus this share of ``sum |Re r_k| + sum |c_j| / 2`` is refitted
TRIGGER = 1e-4


def hold_at_zero(est, x, n_modes, terms, refit, notes, *, what="the impulse response"):
    """``refit()`` with ``est``'s fits holding ``h(0) = 0`` from here on, where the
    driving point's unknowns ``x`` start against the force; else None.

    ``est``: the :class:`modalid.ModalFit` being fitted (its fits read ``_zero_start``,
    cleared when a fit starts and when its identification ends); ``refit``: a function
    of no argument that fits again from the poles found and returns what the caller
    needs; appends a note to ``notes``."""
    equality = _bounds(n_modes, terms, False, zero_start=True)[2]   # h(0) = equality @ x
    jump = float(equality @ x)
    if jump >= -TRIGGER * 0.5 * float(equality @ abs(x)):
        return None
    est.__dict__["_zero_start"] = True
    out = refit()
    notes.append(f"{what} held at 0 at t = 0, as a driving point's (the fit had a 1/s term "
                 f"of {jump:.3g} m/(N s): a jump at the impact)")
    return out


def hold_single(est, omega, h, w, poles, kinds, x, info, terms, segment_std, notes):
    """:func:`hold_at_zero` in the fit of one FRF (``est``: the :class:`modalid.ModalFit`
    being fitted): refined again from its poles (held, with their standard deviations, for
    segment fits and ``refine=False``); a pseudo-mode then left with a real residue only
    (zero modal mass) is dropped. Returns ``(poles, kinds, x, info)``."""
    def refit():
        if segment_std is None and est.refine:
            p, x_new, new = est._refine(omega, h, w, poles, kinds, terms)
            return est._drop_idle(omega, h, w, p, kinds, x_new, new, terms)
        p, x_new, new = est._linear_fit(omega, h, w, poles, terms)
        return p, kinds, x_new, {**info, "cost": new["cost"]}

    out = hold_at_zero(est, x, poles.size, terms, refit, notes)
    return (poles, kinds, x, info) if out is None else out
