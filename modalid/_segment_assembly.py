"""The whole band's model from segment fits' poles (:mod:`modalid._segments`), held: what
their linear assembly over the band (:func:`assemble`) leaves to mend. ``est``: the
:class:`modalid.ModalFit` being fitted."""

from __future__ import annotations

import numpy as np

from ._lsfd import (design_matrix, refine_varpro, release_gain, removal_cost,
                    split_coefficients)

__all__ = ["assemble", "band_model", "drop_idle_modes", "pseudo_modes_apart",
           "refine_pseudo_modes", "resume_probe"]

#: the upper pseudo-modes refined over the band decay at least at this share of the
#: band's top (rad/s): nearer 0 one is a ringing that never decays beside the band, no
#: stand-in for the modes above it
_PSEUDO_DECAY = 0.01
#: a released far pseudo-mode is kept only this share of their frequency or more from
#: the other pseudo-modes (two of them cancelling each other)
_PSEUDO_APART = 0.1
#: steps of each refinement (a step costs one linear solve of the band)
_PSEUDO_STEPS = 6


def band_model(est, frf, w, poles, cut, segment_std, notes, max_order):
    """The whole band's model from its segments' poles (``segment_std``: their standard
    deviations): the pseudo-modes placed (``est._start``), the band assembled
    (:func:`assemble`), idle modes dropped (:func:`drop_idle_modes`, appending to
    ``notes``), the pseudo-modes refined (:func:`refine_pseudo_modes`). A quick
    unconstrained probe keeps what it assembled (``_probe_assembly``): the full
    unconstrained fit is the same with its pseudo-modes refined, and
    :func:`resume_probe` makes it from there (a second fit from the start cost pyfrf's
    hammer FRF, 12 800 lines, 0.2 s more). Returns ``(poles, kinds, x, info, terms,
    segment_std)``."""
    omega, h = frf.omega, frf.values
    poles, kinds, terms = est._start(omega, h, w, poles, cut)
    est._iterations, est._buffers = 0, {}
    poles, x, info = assemble(est, omega, h, w, poles, kinds, terms, segment_std)
    poles, kinds, x, info, segment_std = drop_idle_modes(
        est, omega, h, w, poles, kinds, x, info, terms, segment_std, notes)
    if est.__dict__.get("_probe"):
        est.__dict__["_probe_assembly"] = (frf, w, poles, kinds, x, dict(info), terms,
                                           segment_std, list(notes), max_order)
    poles, kinds, x, info = refine_pseudo_modes(est, omega, h, w, poles, kinds, x, info, terms)
    return poles, kinds, x, info, terms, segment_std


def resume_probe(est):
    """The full unconstrained fit of a segmented band from what its quick probe
    assembled (:func:`band_model`): its pseudo-modes refined, then stored as
    ``est._identify`` would (the same model as a second fit from the start)."""
    frf, w, poles, kinds, x, info, terms, segment_std, notes, max_order = \
        est.__dict__.pop("_probe_assembly")
    est._iterations, est._buffers, est._final_weights = 0, {}, w
    poles, kinds, x, info = refine_pseudo_modes(est, frf.omega, frf.values, w, poles, kinds,
                                                x, info, terms)
    return est._finish_identify(frf, w, poles, kinds, x, info, terms, segment_std, notes,
                                max_order, None)


def assemble(est, omega, h, w, poles, kinds, terms, mode_std):
    """The whole band's linear unknowns for held poles (segment fits' poles, the
    pseudo-modes where :meth:`FRFPipeline._start` placed them): one weighted linear least-squares
    solve (passive when the constraint is on). The physical poles' standard deviations
    are their segments' (``mode_std``, rows in the order of the physical poles);
    the pseudo-modes' and the extra terms' are NaN."""
    poles, x, info = est._linear_fit(omega, h, w, poles, terms)
    est._final_weights = w
    rows = np.full((poles.size, 4), np.nan)
    rows[kinds == "mode"] = mode_std
    n_extra = design_matrix(1j * omega[:1], np.zeros(0), terms).shape[1]
    info.update(converged=True, std={"modes": rows, "extra": np.full(n_extra, np.nan)},
                message=f"poles from {est._segment_count} segment fits, held; residues "
                        "and residual terms by linear least squares over the band")
    return poles, x, info


def drop_idle_modes(est, omega, h, w, poles, kinds, x, info, terms, mode_std, notes):
    """Segment fits' poles the passive fit of the whole band holds at zero modal mass
    (``Im r`` at its bound 0): resonances of the other sign or noise the unconstrained
    segment fits kept, which carry nothing in this FRF (reported as modes of infinite
    modal mass, the verdict "failed"); and poles whose damping is not resolved (a
    half-power bandwidth under a line, or a standard deviation from their segment over
    half of it) that are not significant over the band (their removal, the rest refitted
    linearly, raises the cost by less than ``4 ln(n)`` residual variances, the
    information criterion's penalty: :func:`modalid._lsfd.removal_cost`). Dropped,
    and the band assembled again without them (twice at most). Returns ``(poles,
    kinds, x, info, mode_std)``."""
    spacing = float(np.median(np.diff(omega)))
    for _ in range(2):
        mode = kinds == "mode"
        idle = mode & (split_coefficients(x, poles.size, terms)[0].imag >= 0
                       if est._passive_on else False)
        # its damping unresolved (narrower than a line, or its segment's standard
        # deviation over half of it) and its removal, the rest refitted, raising the
        # band's cost by less than the information criterion's penalty: a noise line's
        # fit (a 0.05 Hz hammer FRF under a noise floor: 835.6 Hz, zeta 7e-6, 9300 kg,
        # and 829.9 Hz, zeta 1.7e-4, 1600 kg, beside an 848 Hz mode of 0.5 kg); a sharp
        # mode on a broader one's skirt, 55 times the noise at its line, stays
        unresolved = -2.0 * poles.real < spacing
        unresolved[mode] |= mode_std[:, 0] > -0.5 * poles.real[mode]   # NaN: passes
        sharp = mode & unresolved & ~idle
        if sharp.any():
            gain = removal_cost(omega, h, est._model_weights(omega, poles, x, terms, w),
                                poles, terms, np.flatnonzero(sharp),
                                passive=est._passive_on, buffers=est._buffers)
            sharp[sharp] = gain < 4.0 * np.log(2 * omega.size)
        why = np.where(idle, "no positive modal mass over the band",
                       "its damping unresolved, no more than noise to the band")
        idle |= sharp
        if not idle.any():
            break
        notes += [f"dropped the pole at {abs(p) / (2 * np.pi):.6g} Hz: a segment's, {reason}"
                  for p, reason in zip(poles[idle], why[idle])]
        mode_std = mode_std[~idle[mode]]
        poles, kinds = poles[~idle], kinds[~idle]
        poles, x, info = assemble(est, omega, h, w, poles, kinds, terms, mode_std)
    return poles, kinds, x, info, mode_std


def refine_pseudo_modes(est, omega, h, w, poles, kinds, x, info, terms):
    """The pseudo-modes refined over the whole band, the segments' poles held.

    Where :meth:`FRFPipeline._start` placed them, the residues made
    up for them: a cantilever's accelerance on 10 000 lines (2 % noise, 8 segments) had
    every modal mass 0.5 % high and its FRF 1.3 % off the truth, against 0.08 % for one
    fit of 4000 lines. First the lower and upper ones, the far one held; then the far one
    too where the data support moving it (:func:`modalid._lsfd.release_gain` over
    ``2 ln(2n)``, as :meth:`FRFPipeline._release_far`) and kept only inside its
    frequency bounds and apart from the other pseudo-modes (:data:`_PSEUDO_APART`); the
    upper ones' decay rates bounded below (:data:`_PSEUDO_DECAY`). Released freely,
    they had settled undamped, at a bound, or two had cancelled each other (a free rod's
    accelerance on 50 000 lines, then not passive). Not in the quick unconstrained
    probe, whose modes' signs decide the driving point (its error, larger for it, then
    judges the passive fit's a little more leniently). Cost: each refinement at most
    :data:`_PSEUDO_STEPS` steps of ``O(lines x columns x moving parameters)`` (the held
    poles' columns keep their Gram block). Returns ``(poles, kinds, x, info)``; the
    physical poles' standard deviations stay their segments'.
    """
    mode, far = kinds == "mode", kinds == "far"
    if mode.all() or est.__dict__.get("_probe"):
        return poles, kinds, x, info
    lo, hi = est._imag_bounds(kinds, omega, poles)
    wm = est._model_weights(omega, poles, x, terms, w)
    if wm is not w:                       # the cost to beat, under the model's weights
        poles, x, assembled = est._linear_fit(omega, h, wm, poles, terms)
        info = {**info, "cost": assembled["cost"]}
    kw = dict(imag_lo=lo, imag_hi=hi, passive=est._passive_on, zero_start=est._zero_start,
              buffers=est._buffers, with_std=False, max_iter=_PSEUDO_STEPS, held_gram=True)

    # the upper and far pseudo-modes decay at least at a hundredth of the band's top:
    # released with no floor the far one settled undamped (2649 Hz, damping 1e-9 above a
    # cantilever's 2 kHz band), an upper one at 67 kHz above a free rod's 20 kHz
    ceiling = np.where(np.isin(kinds, ("upper", "far")), -_PSEUDO_DECAY * omega[-1], -1e-300)
    if est.max_real is not None:
        ceiling = np.minimum(ceiling, est.max_real)

    def refined(hold, max_real=ceiling):
        moved, x_new, new = refine_varpro(omega, h, wm, poles, terms, hold=hold,
                                          max_real=max_real, **kw)
        est._iterations += new["n_iter"]
        return moved, x_new, new

    if not (mode | far).all():
        moved, x_new, new = refined(mode | far)
        if new["cost"] < info["cost"]:
            poles, x, info = moved, x_new, {**info, "cost": new["cost"]}
    if far.any():
        gain = release_gain(omega, h, wm, poles, terms, far, passive=est._passive_on,
                            held=mode)
        if gain >= 2 * np.log(2 * omega.size):
            moved, x_new, new = refined(mode)
            if new["cost"] < info["cost"] and pseudo_modes_apart(moved, kinds, lo, hi):
                poles, x, info = moved, x_new, {**info, "cost": new["cost"]}
                kinds = np.where(far, "upper", kinds)
    est._final_weights = wm
    info["message"] += "; the pseudo-modes refined over the band"
    return poles, kinds, x, info


def pseudo_modes_apart(poles, kinds, lo=None, hi=None) -> bool:
    """Whether the pseudo-modes (``kinds`` not ``"mode"``) stand :data:`_PSEUDO_APART` of
    their frequency or more from each other, and the far one (``kinds == "far"``)
    strictly inside its bounds on ``Im p`` (``lo``, ``hi``, if given: at a bound it is a
    stand-in pushed out of its range). Two close pseudo-modes cancel each other: a
    cantilever's accelerance at 3 % noise (one fit) had an upper one refined onto the
    held far one (0.005 % apart), then both released to a pair 0.0003 % apart, residues
    +4.2 and -4.2 - 0.001i, and its passive fit's model was not passive once one of them
    reached zero modal mass (:meth:`modalid._frf_pipeline.FRFPipeline._release_far`)."""
    f = np.abs(poles[kinds != "mode"])
    apart = np.abs(f[:, None] - f[None, :]) > _PSEUDO_APART * f[None, :]
    np.fill_diagonal(apart, True)
    if lo is None:
        return bool(apart.all())
    far = kinds == "far"
    inside = (poles[far].imag > lo[far] * (1 + 1e-6)) & (poles[far].imag < hi[far] * (1 - 1e-6))
    return bool(apart.all() and inside.all())
