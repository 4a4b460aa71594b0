"""Re-identification on a cut band: what a body's identified model misses at its band top.

The uncertainty band (:mod:`impactpred.uncertainty`) re-fits each measured body on a share
of its band (:func:`refit_on_cut_band`) and reads the error the truncation leaves in each
figure from the change (:func:`truncation_error`); :func:`check_band_bodies` and
:func:`check_refittable` refuse the bodies it cannot re-identify (saved fits, common-pole
fits of several FRFs).
"""

from __future__ import annotations

import warnings

from modalid import MultiOutputModalModel, SavedFit

from .truncation import FIGURES

__all__ = ["check_band_bodies", "check_refittable", "refit_on_cut_band", "truncation_error"]


def check_band_bodies(labels, fits) -> None:
    """Refuse an uncertainty band ``predict`` cannot make for these bodies.

    Parameters
    ----------
    labels : sequence of str
        How each body is named in messages (its file or spec).
    fits : sequence of (ModalFit, SavedFit or None)
        Each body's fit; None for an exact or saved model.

    Raises
    ------
    ValueError
        A body is a saved fit (no data to re-identify) or a common-pole fit of several
        FRFs, or none is identified from a file.
    """
    for i, (label, fit) in enumerate(zip(labels, fits), start=1):
        if isinstance(fit, SavedFit):
            raise ValueError(f"body {i} ({label}) is a saved fit: the uncertainty band "
                             "re-identifies each measured body on cut bands of its data, "
                             "which a saved fit does not hold; predict from its FRF file (or "
                             "the fitted ModalFit) for the band")
        if _is_set_fit(fit):
            raise ValueError(f"body {i} ({label}) is {_SET_FIT}")
    if all(fit is None for fit in fits):
        raise ValueError(f"the uncertainty band bounds the error of bodies identified from "
                         f"FRF files, and neither body is one ({' and '.join(labels)}): an "
                         "exact model has no identification error, a saved model no data to "
                         "re-identify")


#: why a common-pole fit of several FRFs gets no band (both refusals say it)
_SET_FIT = ("a common-pole fit of several FRFs: the uncertainty band draws one FRF's "
            "parameters; give the driving point's FRF alone for the band")


def _is_set_fit(fit) -> bool:
    """Whether ``fit`` is a common-pole fit of several FRFs (its model has several rows)."""
    return isinstance(getattr(fit, "model_", None), MultiOutputModalModel)


def check_refittable(fit) -> None:
    """Refuse a fit that holds no data to re-identify (a :class:`modalid.SavedFit`) or whose
    parameters the draws cannot move (a common-pole fit of several FRFs)."""
    if isinstance(fit, SavedFit):
        where = f" ({fit.source})" if fit.source else ""
        raise ValueError(f"a SavedFit{where} holds no data to re-identify on a cut band: the "
                         "uncertainty band needs the fitted ModalFit (or its FRF file)")
    if _is_set_fit(fit):
        raise ValueError(_SET_FIT)


def refit_on_cut_band(fit, fraction: float):
    """A new ``ModalFit`` like ``fit``, on the lines up to ``fraction`` of its band top.

    Parameters
    ----------
    fit : ModalFit
        A fitted estimator (its ``data_`` and options are reused).
    fraction : float
        Share of the band top to keep, in (0, 1].

    Returns
    -------
    ModalFit
        The new, fitted estimator.
    """
    check_refittable(fit)
    low, top = fit.report_["band_hz"]
    params = fit.get_params()
    params["freq_range"] = (low, fraction * top)
    params["n_modes"] = None
    params["weights"] = None        # the setting's are per line of the data first given
    estimator = type(fit)(**params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the data as measured (a windowed fit's terms depend on what was recorded)
        estimator.fit(getattr(fit, "data_", fit.frf_),
                      weights=getattr(fit, "weights_", None))
    return estimator


def truncation_error(nominal: dict, cut: dict, fraction: float) -> dict:
    """The error left in each figure at the full band, from a re-identification on
    ``fraction`` of it.

    A figure that converges like ``F(f) = F_inf + a/f`` with the band fraction ``f`` (the
    share of the omitted modes' energy, ~1/n, is what the continuation cannot make
    exact) has ``|F(1) - F_inf| = |F(1) - F(f)| f / (1 - f)``: 4 times the change from
    80 %, 1.5 times the change from 60 %. An estimate, like Richardson's, not a bound.
    A figure missing (None) on either side gives 0.

    Parameters
    ----------
    nominal : dict
        Each figure at the full band.
    cut : dict
        The same figures from the re-identification on ``fraction`` of it.
    fraction : float
        The band fraction of ``cut``, in (0, 1).

    Returns
    -------
    dict
        The estimated error of each figure (its units).
    """
    if not 0.0 < fraction < 1.0:
        raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
    return {k: (0.0 if nominal[k] is None or cut[k] is None
                else abs(nominal[k] - cut[k]) * fraction / (1.0 - fraction)) for k in FIGURES}
