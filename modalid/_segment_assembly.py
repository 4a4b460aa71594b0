"""The whole band's model from segment fits' poles (:mod:`modalid._segments`), held: what
their linear assembly over the band (:func:`assemble`) leaves to mend. ``est``: the
:class:`modalid.ModalFit` being fitted."""

from __future__ import annotations

import numpy as np

from ._lsfd import design_matrix, removal_cost, split_coefficients

__all__ = ["assemble", "drop_idle_modes"]


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
