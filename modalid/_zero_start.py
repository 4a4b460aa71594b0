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
negative one within :data:`TRIGGER` of the residues (rounding and noise: a noise-free
cantilever's fit has -1.6e-5 of them; the two fits the impact solvers refused, -3e-3 and
-6e-3).
"""

from __future__ import annotations

from ._lsfd import Terms, _bounds

__all__ = ["TRIGGER", "initial_jump", "hold_at_zero", "hold_single"]

#: ``h(0)`` below minus this share of ``sum |r_k| + sum |c_j|`` is refitted
TRIGGER = 1e-4


def initial_jump(x, n_modes: int, terms: Terms) -> float:
    """``h(0)`` (m/(N s)) of the linear unknowns ``x`` of one row (see
    :func:`modalid._lsfd.split_coefficients`)."""
    return float(_bounds(n_modes, terms, False, zero_start=True)[2] @ x)


def hold_at_zero(est, x, n_modes, terms, refit, notes, *, what="the impulse response"):
    """``refit()`` with ``est``'s fits holding ``h(0) = 0`` from here on, where the
    driving point's unknowns ``x`` start against the force; else None.

    ``est``: the :class:`modalid.ModalFit` being fitted (its fits read ``_zero_start``,
    cleared when a fit starts and when its identification ends); ``refit``: a function
    of no argument that fits again from the poles found and returns what the caller
    needs; appends a note to ``notes``."""
    jump = initial_jump(x, n_modes, terms)
    scale = float(abs(_bounds(n_modes, terms, False, zero_start=True)[2]) @ abs(x)) / 2
    if jump >= -TRIGGER * scale:
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
