"""The uncertainty band of an impact predicted from identified models.

:func:`uncertainty_band` re-identifies each measured body on its band cut to 60 % and
80 %, draws the fits' parameters (residues, rigid mass, residual flexibility) from their
reported standard deviations, and reports the spread of the impact figures, widened by
two error estimates added together: the truncation error the cut bands imply at the full
band (:func:`truncation_error`: a figure converging like ``1/band``, four times its change
from 80 % to 100 % of the band) and the error of the continuation's finite extent (its
synthesized modes run half as far: the change, as for an error ~ ``1/extend``; a
heuristic that errs wide). It spans
the identification's scatter, the band's truncation and the tail's extent; it does not
see a bias of the fit.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from modalid import ModalModel

from .truncation import FIGURES, band_resolution, identified_model, impact_figures

__all__ = ["UncertaintyBand", "perturb_residues", "refit_on_cut_band", "truncation_error",
           "uncertainty_band"]


@dataclass(frozen=True)
class UncertaintyBand:
    """Spread of the impact figures over re-identified and perturbed models.

    Attributes
    ----------
    nominal : dict
        Figures of the nominal prediction (see :func:`impact_figures`).
    low, high : dict
        Bounds of each figure in :data:`FIGURES`: the smallest and largest value over the
        nominal prediction and every variant, widened to ``nominal -+ (truncation +
        tail)``.
    variants : tuple of (str, dict)
        Each variant's label (``"body2 band 60%"``, ``"draw 1"``) and figures.
    truncation : dict or None
        The truncation error left at the full band, per figure, estimated from the cut
        bands (:func:`truncation_error`; 0 where no cut band gave one); None when the
        band was built without it.
    tail : dict or None
        The error of the continuation's finite extent, per figure: the change when its
        synthesized modes run half as far (taken as the error left, as for an error
        ``~ 1/extend``: a heuristic estimate that errs wide); 0 without continuation.
        ``low`` and ``high`` reach ``nominal -+ (truncation + tail)``.
    """

    nominal: dict
    low: dict
    high: dict
    variants: tuple
    truncation: dict | None = None
    tail: dict | None = None

    def contains(self, name: str, value: float, *, rel: float = 0.0) -> bool:
        """Whether ``value`` lies in ``[low, high]`` of figure ``name`` (widened by ``rel``)."""
        lo, hi = self.low[name], self.high[name]
        return lo * (1 - rel) <= value <= hi * (1 + rel) if lo >= 0 else lo <= value <= hi

    def table(self) -> str:
        """A short text table: figure, nominal, low, high."""
        lines = [f"{'figure':<18}{'nominal':>14}{'low':>14}{'high':>14}"]
        for name in FIGURES:
            lines.append(f"{name:<18}{self.nominal[name]:>14.6g}{self.low[name]:>14.6g}"
                         f"{self.high[name]:>14.6g}")
        return "\n".join(lines)


def refit_on_cut_band(fit, fraction: float):
    """A new ``ModalFit`` like ``fit``, on the lines up to ``fraction`` of its band top."""
    low, top = fit.report_["band_hz"]
    params = fit.get_params()
    params["freq_range"] = (low, fraction * top)
    params["n_modes"] = None
    estimator = type(fit)(**params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the data as measured (a windowed fit's terms depend on what was recorded)
        estimator.fit(getattr(fit, "data_", fit.frf_))
    return estimator


def perturb_residues(fit, rng) -> ModalModel:
    """``fit.model_`` with its identified parameters moved by a draw of their std.

    Each physical mode's residue moves by a complex Gaussian of its reported standard
    deviation; the rigid body's inverse mass and the residual flexibility (the constant
    term) by a real one of theirs (``report_["inverse_mass_std"]``,
    ``report_["flexibility_std"]``), kept >= 0.

    For a driving point (``report_["driving_point"]`` not False) each mode of positive
    modal mass keeps it positive: a draw whose residue's imaginary part crosses zero is
    reflected back (``Im r -> -Im r``), so that the draw stays a passive driving point
    (a modal mass of the wrong sign would be refused by the passivity check) and the
    draw sequence stays the same.
    """
    model = fit.model_
    modes = fit.report_["modes"]
    std = modes["residue_std"].to_numpy()
    residues = model.residues.copy()
    driving = fit.report_.get("driving_point") is not False
    for pole, s in zip(fit.poles_, std):
        if not np.isfinite(s):
            continue
        k = int(np.argmin(np.abs(model.poles - pole)))
        nominal = residues[k]
        drawn = nominal + s / math.sqrt(2.0) * complex(rng.standard_normal(),
                                                       rng.standard_normal())
        # modal mass -1/(2 Im p Im r) > 0  <=>  Im r has the sign of -Im p
        if driving and nominal.imag * model.poles[k].imag < 0 \
                and drawn.imag * nominal.imag <= 0:
            drawn = complex(drawn.real, -drawn.imag if drawn.imag else nominal.imag)
        residues[k] = drawn
    scalars = {}
    for name in ("inverse_mass", "flexibility"):
        value, s = getattr(model, name), fit.report_.get(f"{name}_std", math.nan)
        draw = rng.standard_normal()        # drawn always: the sequence stays reproducible
        scalars[name] = max(value + s * draw, 0.0) if value and np.isfinite(s) else value
    return ModalModel(poles=model.poles, residues=residues, real_poles=model.real_poles,
                      real_residues=model.real_residues, **scalars)


def truncation_error(nominal: dict, cut: dict, fraction: float) -> dict:
    """The error left in each figure at the full band, from a re-identification on
    ``fraction`` of it.

    A figure that converges like ``F(f) = F_inf + a/f`` with the band fraction ``f`` (the
    share of the omitted modes' energy, ~1/n, is what the continuation cannot make
    exact) has ``|F(1) - F_inf| = |F(1) - F(f)| f / (1 - f)``: 4 times the change from
    80 %, 1.5 times the change from 60 %. An estimate, like Richardson's, not a bound.
    A figure missing (None) on either side gives 0.
    """
    if not 0.0 < fraction < 1.0:
        raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
    return {k: (0.0 if nominal[k] is None or cut[k] is None
                else abs(nominal[k] - cut[k]) * fraction / (1.0 - fraction)) for k in FIGURES}


def uncertainty_band(models, fits, solve, *, fractions=(0.6, 0.8), n_draws: int = 4,
                     seed: int = 0, continuation: bool = True, n_top: int = 3,
                     extend: float = 16.0, nominal=None) -> UncertaintyBand:
    """Spread of duration, peak, impulse and restitution over plausible models.

    Parameters
    ----------
    models : sequence of 2 models
        The nominal model of each body (as used for the nominal prediction).
    fits : sequence of 2 (ModalFit or None)
        The fit of each body identified from an FRF; only these are varied.
    solve : callable
        ``solve(model1, model2) -> ImpactResult``.
    fractions : sequence of float
        Each identified body is re-identified on its band cut to these fractions of the
        band top (one body at a time, the other nominal) and continued above the cut.
    n_draws : int
        Draws (fixed ``seed``) of every identified body's parameters from their reported
        standard deviations (:func:`perturb_residues`).
    nominal : ImpactResult, optional
        The nominal result, if already solved.
    """
    if not (isinstance(extend, (int, float)) and math.isfinite(extend) and extend > 0):
        raise ValueError(f"extend must be a positive finite number, got {extend!r}")
    if isinstance(n_draws, bool) or not isinstance(n_draws, (int, np.integer)) or n_draws < 0:
        raise ValueError(f"n_draws must be an integer >= 0, got {n_draws!r}")
    if isinstance(n_top, bool) or not isinstance(n_top, (int, np.integer)) or n_top < 1:
        raise ValueError(f"n_top must be an integer >= 1, got {n_top!r}")
    for fraction in fractions:
        if not (isinstance(fraction, (int, float)) and 0.0 < fraction < 1.0):
            raise ValueError(f"fractions must lie in (0, 1), got {fraction!r}")
    models = list(models)
    if nominal is None:
        nominal = solve(*models)
    variants, cuts = [], []
    resolution = band_resolution(fits)
    for i, fit in enumerate(fits):
        if fit is None:
            continue
        for fraction in fractions:
            refit = refit_on_cut_band(fit, fraction)
            trial = list(models)
            try:
                trial[i] = identified_model(refit, continuation=continuation, n_top=n_top,
                                            extend=extend)
            except ValueError:
                continue
            cut_fits = [refit if j == i else f for j, f in enumerate(fits)]
            try:
                res = solve(*trial)
            except (ValueError, MemoryError, np.linalg.LinAlgError):
                continue                 # a degenerate re-identification: no figure
            cut_resolution = band_resolution(cut_fits)
            figs = impact_figures(res, resolution=cut_resolution)
            variants.append((f"body{i + 1} band {100 * fraction:.0f}%", figs))
            # compared with the nominal at the same resolution (the same merging)
            cuts.append((fraction, figs, impact_figures(nominal, resolution=cut_resolution)))
    rng = np.random.default_rng(seed)
    if any(f is not None for f in fits):
        for d in range(n_draws):
            trial = list(models)
            for i, fit in enumerate(fits):
                if fit is not None:
                    trial[i] = identified_model(fit, continuation=continuation, n_top=n_top,
                                                extend=extend, model=perturb_residues(fit, rng))
            variants.append((f"draw {d + 1}",
                             impact_figures(solve(*trial), resolution=resolution)))
    base = impact_figures(nominal, resolution=resolution)
    tail = {k: 0.0 for k in FIGURES}
    if continuation and extend > 1.0 and any(f is not None for f in fits):
        # the tail's own extent: synthesized modes to half as far; the change, taken as the
        # error left (as for an error ~ 1/extend), is a heuristic that errs wide: a peak's
        # change from 8x to 16x exceeded its change from 16x to 32x by 2x on a rod
        try:
            trial = [m if f is None else identified_model(f, n_top=n_top, extend=0.5 * extend)
                     for f, m in zip(fits, models)]
            half = impact_figures(solve(*trial), resolution=resolution)
        except (ValueError, MemoryError, np.linalg.LinAlgError):
            half = None
        if half is not None:
            variants.append((f"tail to {0.5 * extend:g}x the band top", half))
            tail = truncation_error(base, half, 0.5)
    everything = [base] + [v for _, v in variants]
    trunc = {k: 0.0 for k in FIGURES}
    for fraction, figs, same in cuts:
        for k, r in truncation_error(same, figs, fraction).items():
            trunc[k] = max(trunc[k], r)
    low, high = {}, {}
    for k in FIGURES:
        values = [f[k] for f in everything if f[k] is not None]
        if base[k] is not None:
            error = trunc[k] + tail[k]
            values += [base[k] - error, base[k] + error]
        low[k], high[k] = (min(values), max(values)) if values else (None, None)
    return UncertaintyBand(nominal=base, low=low, high=high, variants=tuple(variants),
                           truncation=trunc, tail=tail)
