"""The fitted model and report of one FRF fit stored on its estimator (step 4 of
:mod:`modalid.fit`'s pipeline; :meth:`modalid._frf_pipeline.FRFPipeline._identify` calls
it)."""

from __future__ import annotations

import numpy as np

from ._lsfd import evaluate
from ._noise import noise_level
from ._report import (fit_report, local_misfit_inflation, misfit_notes, mode_std_columns,
                      residual_correlation_inflation)
from ._verdict import error_lines, missed_low_end, missed_resonances
from ._window import nonnegative_mass_line, structure_model, windowed_receptance
from .model import ModalModel
from .quantities import receptance_to

__all__ = ["store_fit"]

_MASS_LINE_POLE = 0.3  # a lower pseudo-mode under this share of the band's start is a mass line


def store_fit(est, frf, poles, kinds, residues, u, d, info, notes, max_order, vf_iterations,
              terms):
    """Store the fitted model on ``est`` (:class:`modalid.ModalFit`): ``model_`` (the
    structure's, a window undone), ``poles_``, the physical poles' standard deviations
    (widened for correlated residuals and local misfit) and ``report_``
    (:func:`modalid._report.fit_report`), its errors in the data's own quantity."""
    omega, h = frf.omega, frf.values
    # the model of the data fitted (windowed), then the structure's (modalid._window);
    # a transfer FRF (unconstrained fit) keeps a negative mass line (a rigid rotation,
    # or the modes below the band, measured away from the hit point)
    # its sign speaks of driving point or not, and so does a lower pseudo-mode's well
    # below the band: above its pole it adds 2 Re(r (p + sigma)) / (s + sigma)^2, a
    # mass line of that 1/M (exact for a mode of modal mass m: 1/m); a free body's
    # transfer FRF fitted from 5 Hz carried its negative rigid term (-0.2 1/kg) in one
    # of -5 kg at 0.4 Hz, and passed for a driving point. One near the band's start
    # is no mass line (a windowed fixed rod's at 0.93 of it, fitting the leakage there)
    lower = (kinds == "lower") & (np.abs(poles) < _MASS_LINE_POLE * omega[0])
    est._raw_inverse_mass = float(u) + float(
        np.sum(2.0 * np.real(residues[lower] * (poles[lower] + est._shift))))
    u = float(u) if not est._passive_on else max(float(u), 0.0)
    fitted_model = ModalModel(poles=poles, residues=residues, inverse_mass=u, flexibility=d)
    fitted = evaluate(omega, poles, residues, (), (), u, d, est._shift)
    band = est._data_band
    own = receptance_to(band.quantity, fitted, band.omega) - band.values
    window = {}
    fit_poles = poles                    # where the residual's lines are (windowed)
    if est._windowed:
        fitted_model, window = structure_model(
            fitted_model, kinds, decay_rate=est._shift, record_length=est._record,
            quantity=band.quantity, data=band, removed=est.__dict__.get("_end_removed"))
        poles, residues = fitted_model.poles, fitted_model.residues
        if est._passive_on:           # the record end's A_2 taken out of it
            fitted_model, said = nonnegative_mass_line(fitted_model)
            notes = notes + said
        if window["window_clipped"]:   # a pole moved: judged as delivered
            own = receptance_to(band.quantity, windowed_receptance(
                fitted_model, band.omega, est._shift, est._record,
                quantity=band.quantity, cut=window["record_cut"]),
                band.omega) - band.values - window["record_end_gone"]
    est.model_, est._record_cut = fitted_model, window.get("record_cut")
    physical = kinds == "mode"
    est.poles_ = poles[physical][np.argsort(np.abs(poles[physical]))]
    modes = ModalModel(poles=poles[physical], residues=residues[physical]).modes
    std = info.get("std")
    est._mode_std_raw = None          # per physical pole, by frequency (segments)
    if std is not None:
        order = np.argsort(np.abs(poles[physical]), kind="stable")
        est._mode_std_raw = std["modes"][physical][order]
    # the formula assumes independent lines; correlated residuals (model error, the
    # estimator's smoothing) carry fewer independent ones: widen by Bartlett's factor;
    # and its variance is the band's: a mode whose own lines the model misses by more
    # than that is widened by the misfit there
    weighted = est._final_weights * (fitted - h)
    inflation = residual_correlation_inflation(weighted)
    if std is not None:
        std = {k: v * inflation for k, v in std.items()}
        local = local_misfit_inflation(omega, weighted, fit_poles, correlation=inflation)
        std["modes"] = std["modes"] * local[:, None]
        notes = notes + misfit_notes(poles[physical], local[physical])
    if std is None:
        modes = mode_std_columns(modes)
    else:
        order = np.argsort(np.abs(poles[physical]), kind="stable")
        scale = window.get("truncation_factors", np.ones(poles.size))[physical][order]
        modes = mode_std_columns(modes, std["modes"][physical][order],
                                 poles[physical][order], scale)
    # marginal stds of the rigid and constant terms; not where a pseudo-mode next to
    # them trades against them (a lower one against the mass line, an upper one
    # against the constant): their marginal std is then no measure of either
    inverse_mass_std = flexibility_std = np.nan
    if std is not None:
        extra = std["extra"][len(terms.real_poles):]
        if terms.rigid and u != 0 and not np.any(kinds == "lower"):
            inverse_mass_std = float(extra[0]) / window.get("rigid_factor", 1.0)
        if terms.upper and not np.any((kinds == "upper") | (kinds == "far")):
            flexibility_std = float(extra[int(terms.rigid)])
    nrmse = float(np.linalg.norm(own) / np.linalg.norm(band.values))
    scatter = noise_level(band.values)               # the data's own, per line
    # the lines the median error counts: all, or with per-line weights those that carry
    # them (at least 1 % of the largest): a fit is judged where it was told to look
    counted = np.ones(band.values.size, bool)
    if est._band_weights is not None:
        carried = est._band_weights * np.abs(band.values)
        counted = carried >= 0.01 * carried.max()
    est.report_ = fit_report(
        est.model_, kinds, info, notes, method=est.method, max_order=max_order,
        frf_nrmse=nrmse, frf_nrmse_data=nrmse,
        frf_nrmse_receptance=float(np.linalg.norm(fitted - h) / np.linalg.norm(h)),
        noise_estimate_data=float(np.linalg.norm(scatter) / np.linalg.norm(band.values)),
        frf_median_relative_error=float(np.median(np.abs(own / band.values)[counted])),
        noise_median_relative=float(np.median((scatter / np.abs(band.values))[counted])),
        frf_error_where=error_lines(band.freq_hz, own, fit_poles[physical]),
        data_quantity=band.quantity, missed_resonances_hz=missed_resonances(
            band.freq_hz, band.values, band.values + own).tolist(),
        missed_low_end_hz=missed_low_end(band.freq_hz, band.values, band.values + own),
        band_hz=(float(frf.freq_hz[0]), float(frf.freq_hz[-1])), segments=est._segment_count,
        vf_iterations=vf_iterations, modes=modes, inverse_mass_std=inverse_mass_std,
        flexibility_std=flexibility_std, std_inflation=inflation,
        **{k: v for k, v in window.items() if k not in ("truncation_factors", "rigid_factor",
                                                         "record_cut", "record_end_gone")})
