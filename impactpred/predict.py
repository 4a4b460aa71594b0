"""``predict``: from what a user has (measured FRF files, saved models, simple specs) to
an impact prediction, with each identified body's report and a check of the band.

A body is given as

* a measured FRF file (CSV, ``.npz``, ``.mat``, UFF 58) or an :class:`modalid.FRFData`:
  identified with :class:`modalid.ModalFit`, its verdict and driving-point decision
  judged, its model continued above its band, the band checked;
* a fitted :class:`modalid.ModalFit` (an FRF's), used as if identified here;
* a saved fit (``.json`` from ``modalid fit --out`` or :meth:`modalid.SavedFit.to_json`,
  or the :class:`~modalid.SavedFit` itself): likewise, with the same figures; only the
  uncertainty band, which re-identifies the data, needs the FRF file (or the fit);
* a saved model (``.json`` from ``ModalModel.to_json``, or from
  ``MultiOutputModalModel.to_json``: the prediction then gives every point's response),
  used as it is: a bare identified model has lost its band, so it is neither continued
  nor checked (save the fit instead);
* a spec string: ``mass:M``, ``rod:mass=..,transit_time=..[,support=free|fixed]``,
  ``spring-mass:mass=..,stiffness=..[,damping_ratio=..]``,
  ``beam:mass=..,time_scale=..`` (SI units);
* or any model object ``solve_impact`` takes.

Reading them (and contact specs) is :mod:`impactpred._specs`'s job; this module judges
the identifications, continues the models and solves.
"""

from __future__ import annotations

import functools
import re
import warnings
from dataclasses import dataclass, field

import numpy as np

from modalid import ModalModel, MultiOutputModalModel, SavedFit
from modalid.validation import as_nonnegative_scalar, as_real_scalar

from ._band_checks import (BandWarning, band_reach, force_energy_above, force_energy_below,
                           resolved_force,
                           warn_unsettled)
from ._figures import band_resolution, impact_figures
from ._specs import (READ_OPTIONS, body_label, check_estimator, identify, parse_contact,
                     read_options_pair)
from .api import solve_impact
from .body import Body, check_driving_point
from .parallel import check_progress
from .result import ImpactResult
from .truncation import NoComplianceAbove, identified_model
from .uncertainty import check_band_bodies, check_refittable, uncertainty_band

__all__ = ["predict", "Prediction", "parse_body", "parse_contact", "BandWarning",
           "ContinuationWarning", "IdentificationWarning", "check_identification",
           "READ_OPTIONS", "CONTINUATION_SHARE", "RIGID_LINE_SHARE", "RIGID_LINE_SPAN",
           "force_energy_below"]


#: ``continuation="auto"`` continues an identified body when more than this share of the
#: contact force's energy lies above its band without the continuation: a free rod struck
#: by a rod, identified on 20 modes, had 1.2-1.7 % there and its restitution 0.6-1.1 % off
#: (0.01-0.07 % with the continuation)
CONTINUATION_SHARE = 1e-3


class ContinuationWarning(UserWarning):
    """A body identified from an FRF file could not be continued above its band (no
    passive mode inside the band to continue from): it is used without."""


class IdentificationWarning(UserWarning):
    """A body's identification is suspect (``ModalFit.report_["verdict"] == "suspect"``):
    the prediction goes on, on a model to be checked."""


#: what may fix a failed identification, as predict's and ModalFit's keywords (the command
#: line names the same options as flags)
_FIT_REMEDIES = ("quantity=... if the file does not state its quantity or states it wrong; "
                 "missed_modes='dense' for a band with many weak or close modes; "
                 "window_decay_rate=... and record_length=... for FRFs measured with an "
                 "exponential window whose file does not state them; a band that holds "
                 "whole resonances (freq_range=(fmin, fmax)), or identify the body "
                 "yourself (modalid.ModalFit) and give the saved fit "
                 "(modalid.SavedFit.to_json, or modalid fit --out)")


def check_identification(fit, source, *, body: int) -> None:
    """Stop a prediction on a failed or non-driving-point identification; warn on a suspect one.

    Parameters
    ----------
    fit : modalid.ModalFit or modalid.SavedFit
        Fitted on the FRF file ``source`` (or saved); reads ``report_["verdict"]`` (``"ok"``,
        ``"suspect"`` or ``"failed"``, ``"ok"`` when absent), ``report_["verdict_reasons"]``
        and ``report_["driving_point"]`` (True, False or None: not decided; a set's
        ``report_["driving_row_is_driving_point"]``).
    source : str or Path
        The FRF file, named in the messages.
    body : int, keyword-only
        1 or 2, named in the messages.

    Raises
    ------
    ValueError
        The verdict is ``"failed"`` (with its reasons and options that may fix it), or
        the FRF is not a driving point (a transfer FRF cannot be an impact body).

    Warns
    -----
    IdentificationWarning
        The verdict is ``"suspect"``.
    """
    report = fit.report_
    verdict = report.get("verdict", "ok")
    reasons = "; ".join(report.get("verdict_reasons", ())) or "no reason given"
    # a saved fit is not refitted here: its remedies apply to the FRF it was made from
    saved = isinstance(fit, SavedFit)
    refit = (f" (fit {fit.source or 'its FRF file'} again with them and save it)" if saved
             else "")
    if (report.get("driving_point") is False
            or report.get("driving_row_is_driving_point") is False):   # a set's row
        why = report.get("driving_point_reason") or reasons
        fix = (" (or, if it is the driving point with its sign reversed, read it with "
               "read_options={'negate': True}; with its quantity stated wrong, with "
               "quantity=...)" if "sign reversed" in why else
               " (or, if its quantity is given or stated wrong, read it with the right "
               "quantity=...)")
        again = (f"; a saved fit keeps how it was made: fit {fit.source or 'its FRF file'} "
                 "again with these options and save it" if saved else "")
        failed = (f"; the fit this decision rests on failed ({reasons}), so it may be "
                  "wrong" if verdict == "failed" else "")
        # an exponential window the file does not state shifts the poles and the mass
        # line: a windowed driving point read as it is looks like a transfer FRF
        unstated = (getattr(fit, "window_decay_rate", 0.0) is None and getattr(
            getattr(fit, "data_", None), "window_decay_rate", 0.0) is None)
        window = ("; if it was measured with an exponential window that the file does not "
                  "state, give window_decay_rate=... (and record_length=...)"
                  if unstated else "")
        raise ValueError(f"body {body}: {source} is not a driving-point FRF ({why}{failed}): "
                         "a transfer FRF cannot be an impact body, a body needs its "
                         "driving-point receptance (force and response at the contact "
                         f"point); give the FRF measured there{fix}; if it is the one, "
                         f"fit it with passive=True{window}{again}")
    if verdict == "failed":
        raise ValueError(f"body {body}: the identification of {source} failed ({reasons}); "
                         f"options that may fix it{refit}: {_FIT_REMEDIES}")
    if verdict == "suspect":
        warnings.warn(f"body {body}: the identification of {source} is suspect ({reasons}); "
                      "the prediction relies on it", IdentificationWarning, stacklevel=4)


#: the share of each band's top the band check re-identifies on
BAND_CHECK_FRACTION = 0.8


def _cuttable(fit) -> bool:
    """Whether the band check can identify ``fit`` again on :data:`BAND_CHECK_FRACTION`
    of its band: a fit that keeps its data (not a saved fit nor a common-pole set) whose
    band's bottom lies below that share of its top."""
    if fit is None:
        return False
    try:
        check_refittable(fit)
    except (TypeError, ValueError):
        return False
    low, top = fit.report_["band_hz"]
    return low < BAND_CHECK_FRACTION * top


def _continued(fit, *, label=""):
    """``(model, note)``: ``fit``'s model for an impact continued above its band, or, where
    its band holds no mode to continue from, as identified (with a
    :class:`ContinuationWarning`); the note says which. A fit of several points (a saved
    FRF-set fit) is not continued: the continuation is built for one driving point."""
    if isinstance(fit.model_, MultiOutputModalModel):
        warnings.warn(f"{label}not continued above its band (a model of several points: the "
                      "continuation is built for one driving point): the prediction relies "
                      "on its residual terms there", ContinuationWarning, stacklevel=3)
        return (identified_model(fit, continuation=False),
                "not possible (a model of several points)")
    try:
        model = identified_model(fit, continuation=True)
    except NoComplianceAbove as exc:
        warnings.warn(f"{label}not continued above its band ({exc}): its upper residual "
                      "terms dropped", ContinuationWarning, stacklevel=3)
        return (identified_model(fit, continuation=False),      # drops them: "auto"
                f"not possible ({exc}; upper residual terms dropped)")
    except ValueError as exc:
        warnings.warn(f"{label}not continued above its band ({exc}): the prediction relies "
                      "on the model's residual terms there", ContinuationWarning, stacklevel=3)
        return identified_model(fit, continuation=False), f"not possible ({exc})"
    return model, f"on, above {fit.report_['band_hz'][1]:.4g} Hz"


def parse_body(spec, *, quantity=None, estimator=None, continuation=True,
               read_options=None):
    """The model of a body spec and, for a measured FRF, its fitted ``ModalFit``.

    Parameters
    ----------
    spec : str, Path, model, FRFData or fitted ModalFit
        See the module docstring.
    quantity : str, optional, keyword-only
        Quantity of an FRF file that does not state it (an FRFData states its own: a
        different one is refused).
    estimator : modalid.ModalFit, optional, keyword-only
        The estimator an FRF file or FRFData is identified with, cloned
        (``sklearn.base.clone``: its settings, not its state); default ``ModalFit()``.
    continuation : bool, default True, keyword-only
        A model identified from an FRF file carries the high-frequency continuation of
        :func:`impactpred.truncation.continue_above_band` (with a
        :class:`ContinuationWarning` and none where the band holds no mode to continue).
        ``"auto"`` is :func:`predict`'s alone: it decides from a first solve's force, which
        one body does not have (the defaults of the options several entry points share:
        the API reference's first section).
    read_options : dict, optional, keyword-only
        :func:`modalid.read_frf` options of an FRF file (:data:`READ_OPTIONS`), e.g.
        ``{"format": "complex-lines", "freq_hz": ...}`` or ``{"conjugate": True}``
        (refused for an FRFData or a fitted ModalFit).

    Returns
    -------
    (model, fit_or_None)
        ``fit_or_None``: the ``ModalFit`` of an FRF file, the ``SavedFit`` of a saved fit.

    Raises
    ------
    ValueError
        A spec, file or model that cannot be read, naming it; an FRF stored with the
        other sign convention or a driving point with its sign reversed (see
        :func:`modalid.io.check_sign`; the message names the reading option that fixes
        it); ``continuation`` not True or False.
    TypeError
        ``estimator`` is not a ``ModalFit``.
    """
    if not isinstance(continuation, (bool, np.bool_)):
        raise ValueError(f"continuation must be True or False for one body, got "
                         f"{continuation!r} ('auto' needs the impact's force: predict)")
    model, fit = identify(spec, quantity=quantity, estimator=check_estimator(estimator),
                           read_options=read_options)
    if fit is None:
        return model, None
    if not continuation:
        return identified_model(fit, continuation=False), fit
    return _continued(fit)[0], fit


@dataclass(frozen=True)
class Prediction:
    """An impact prediction and where its models came from.

    Attributes
    ----------
    result : ImpactResult
    fits : tuple
        The ``ModalFit`` of each body identified from measured data, or its
        :class:`~modalid.SavedFit` when given as a saved fit (None otherwise).
    band_reach : tuple
        Per identified body: the share of the contact force's energy above the top of
        the band its model was identified on (None for the others).
    figures : dict
        ``contact_duration``, ``peak_force``, ``impulse``, ``restitution`` (and contact
        counts) from :func:`impactpred.truncation.impact_figures`, with contacts closer
        than the narrowest band's resolution ``1/(2 f_top)`` merged (none merged without
        an identified body: it was None then, and ``pred.figures["restitution"]`` raised).
    uncertainty : UncertaintyBand or None
        With ``predict(..., uncertainty=True)``: an interval for each of those figures,
        meant to hold the four together with probability 0.9 (``uncertainty.level``):
        the nominal figure -+ the draws' spread (the fits' parameters), the truncation
        error a re-identification on 80 % of each band implies and the tail's
        (``uncertainty.low``, ``uncertainty.high``, ``uncertainty.table()``; see
        :func:`impactpred.uncertainty.uncertainty_band`).
    continuation : tuple of str
        Per identified body, whether its model was continued above its band: ``"on,
        above <top> Hz"``, ``"off"``, ``"not possible (<why>)"``, with the share of the
        force's energy above the band that decided it under ``continuation="auto"``;
        None for the other bodies.
    band_reach_below : tuple
        Per identified body: the share of the contact force's energy below the bottom of
        its band (None for the others); a :class:`BandWarning` when the model has a term
        standing for what lies there and the share exceeds what that term is trusted
        with: ``band_tolerance`` for a lower residual pseudo-mode or a rigid-body line the
        band shows over less than a decade below its first mode, the larger of it and
        :data:`RIGID_LINE_SHARE` (10 %) for one it shows over a decade
        (:data:`RIGID_LINE_SPAN`; a fixed rod fitted
        from above its first mode took that mode for a rigid body, and a mass striking it
        rebounded with 0.46 for the exact 0.70).
    """

    result: ImpactResult
    fits: tuple
    band_reach: tuple
    figures: dict | None = None
    uncertainty: object = field(default=None)
    continuation: tuple = (None, None)
    band_reach_below: tuple = (None, None)


#: a rigid-body line is a free body's exact receptance, but a mode just below the band
#: looks the same from above it: the line is taken on trust only where the band shows it
#: over this span, its bottom at most this fraction of the lowest mode's frequency (a free
#: rod measured from 30 Hz, its first mode at 500 Hz: trusted; a fixed rod measured from
#: 300 Hz, its 250 Hz mode taken for a rigid body and its next at 750 Hz, or a cantilever
#: measured from 1.65 times its first mode, next at 3.8 times the band's bottom: not)
RIGID_LINE_SPAN = 0.1
#: the share of the contact force's energy below the band a trusted rigid-body line is
#: trusted with (a free rod struck by a mass of its weight, measured from 1, 7 and 30 Hz:
#: 0.3, 2.7 and 9 % of the force's energy below the band, its restitution right each time)
RIGID_LINE_SHARE = 0.1


def _lower_terms(fit, band_tolerance: float) -> tuple:
    """``(words, share, vouched)``: what of ``fit``'s model stands for the body below its
    band, the share of the force's energy below the band it is trusted with, and whether
    the band vouches for it (a rigid-body line seen over a decade); ``(None, inf, True)``
    without such a term (the model below the band is then its modes' own, right when no
    mode lies there). A lower residual pseudo-mode (modes below the band, lumped) is
    trusted with ``band_tolerance``; a rigid-body line the band shows over a decade below
    its lowest mode (:data:`RIGID_LINE_SPAN`) with :data:`RIGID_LINE_SHARE`, one it shows
    over less with ``band_tolerance``."""
    report = fit.report_
    if report.get("lower_residual_mode"):
        return ("a lower residual term (what lies below the band, as one pseudo-mode)",
                band_tolerance, False)
    if report.get("rigid_body"):
        low, top = report["band_hz"]
        modes = report.get("modes")
        freqs = (np.asarray(modes["frequency_hz"], float) if modes is not None
                 and "frequency_hz" in modes else np.zeros(0))
        freqs = freqs[np.isfinite(freqs)]
        lowest = float(freqs.min()) if freqs.size else top
        if low <= RIGID_LINE_SPAN * lowest:
            return ("a rigid-body line (a free body's, seen over a decade below its first "
                    "mode)", max(band_tolerance, RIGID_LINE_SHARE), True)
        seen = (f"seen up to {lowest / low:.2g} times the band's bottom" if lowest > low
                else "beside a mode at the band's bottom")
        return (f"a rigid-body line {seen} (a mode just below the band looks the same from "
                "above it)", band_tolerance, False)
    return None, np.inf, True


def _check_model(model, spec, body: int, check_passive: bool) -> None:
    """Refuse a modal model that is not a stable, passive driving point (see
    :func:`check_driving_point`), unless ``check_passive`` is False."""
    if check_passive and isinstance(model, (ModalModel, MultiOutputModalModel)):
        check_driving_point(model, name=f"body {body} ({body_label(spec)})",
                            opt_out="to use it anyway, check_passive=False")


def _bodies(specs, *, quantity, estimator, read_options, check_passive):
    """``(models, fits)`` of the two bodies, checked: an identified body's model as
    identified (no continuation), its fit (a clone of its ``estimator``, a pair) judged by
    :func:`check_identification`."""
    models, fits = [], []
    for i, (spec, options) in enumerate(zip(specs, read_options_pair(read_options, specs)),
                                        start=1):
        model, fit = identify(spec, quantity=quantity, estimator=estimator[i - 1],
                               read_options=options, check_passive=check_passive,
                               label=f"body {i}: ")
        if fit is not None:
            check_identification(fit, body_label(spec), body=i)
            model = identified_model(fit, continuation=False)
        _check_model(model, spec, i, check_passive)
        models.append(model)
        fits.append(fit)
    return models, fits


def _solve_pair(model1, model2, *, velocity1, velocity2, check_passive, gap, contact, t_end,
                dt, method, progress=False, sensitivity_check=True):
    """The impact of two models (``predict``'s solves; the band's variants without the
    exact solver's sensitivity check: their spread is the band's own)."""
    return solve_impact(_body(1, model1, velocity1, check_passive),
                        _body(2, model2, velocity2, check_passive),
                        gap=gap, contact=contact, t_end=t_end, dt=dt, method=method,
                        progress=progress, sensitivity_check=sensitivity_check)


def _quiet_solve(solve, models, t_end):
    """``solve`` of ``models`` up to ``t_end`` at the automatic step, its warnings not
    said (the band's spectrum of a run the caller's ``t_end`` samples too coarsely:
    :func:`impactpred._band_checks.resolved_force`)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return solve(*models, t_end=t_end, dt=None)


def _body(index, model, velocity, check_passive):
    """``Body(model, velocity=...)``, its refusals naming the body and ``velocity{index}``
    (``predict``'s argument, the command line's ``--v1``/``--v2``)."""
    try:
        return Body(model, velocity=velocity, check_passive=check_passive)
    except ValueError as exc:
        message = re.sub(r"\bvelocity(?==| must\b)", f"velocity{index}", str(exc))
        raise ValueError(f"body {index}: {message}") from None


def predict(body1, body2, *, velocity1=0.0, velocity2=0.0, gap=0.0, contact="rigid",
            t_end, dt=None, method="auto", quantity=None, band_tolerance=0.01,
            continuation="auto", uncertainty=False, uncertainty_draws=4,
            seed=0, estimator=None, read_options=None, check_passive=True,
            executor=None, progress="auto", band_check=True) -> Prediction:
    """Predict the impact of two bodies given as files, specs or models.

    Parameters
    ----------
    body1, body2 : str, Path, model, FRFData or fitted ModalFit
        See the module docstring. ``+y`` points from body 1 to body 2.
    velocity1, velocity2 : float
        Rigid-body velocities before impact (m/s).
    gap, t_end, dt, method
        As in :func:`solve_impact`.
    contact : str or ContactLaw
        See :func:`parse_contact`.
    quantity : str, optional
        Quantity of FRF files that do not state it (an FRFData states its own: a
        different one is refused).
    band_tolerance : float
        A :class:`BandWarning` is issued when more than this share of the force's energy
        lies above an identified body's band (the model is extrapolated there), or below
        it where the model has a lower residual pseudo-mode or a rigid-body line standing
        for what lies there (one seen over a decade: above :data:`RIGID_LINE_SHARE`;
        ``Prediction.band_reach_below``); and, where such a term is not seen over a
        decade, when the run goes on after the first contact for more than a quarter
        period of the band's bottom (a mode below the band would turn the body back).
    continuation : {"auto", True, False}, default "auto"
        Continue the models identified from FRF files above their band (the structure's
        high-frequency impedance from its top modes; see
        :func:`impactpred.truncation.continue_above_band`), the best-known route: a
        finite modal sum makes rigid contact chatter (a free rod identified on 10 modes
        and struck by a rod of half its length: restitution 2.0 % off without, 0.06 %
        with). ``"auto"`` solves first without and continues each body whose band has
        more than :data:`CONTINUATION_SHARE` (0.1 %) of the contact force's energy above
        it, then solves again (the continuation can make a solve ten times slower, where
        it changes little); ``True`` continues every identified body, ``False`` none. A
        band holding no mode to continue from goes without (a
        :class:`ContinuationWarning`). ``Prediction.continuation`` says what was done.
    uncertainty : bool
        Attach an :class:`~impactpred.uncertainty.UncertaintyBand` (stated level 0.9 for
        the four figures together: ``uncertainty_draws`` draws of the fits' residues and
        as many of their poles with ``seed``, re-identification on 80 % of each band, the
        truncation error it implies and the continuation's).
    executor : None, concurrent.futures.Executor or dask.distributed.Client
        Where the uncertainty band's re-identifications and solves run (``None``: here,
        one after the other); the band does not depend on it.
    band_check : bool
        Without ``uncertainty``: re-identify each identified body on 80 % of its band
        and solve with it (the uncertainty band's truncation part alone), and warn
        (:class:`BandWarning`) where the restitution's, impulse's or duration's interval
        (the cut band's change times ``TRUNCATION_FACTOR f / (1 - f)``, 7 at ``f = 0.8``)
        reaches further than :data:`impactpred._band_checks.UNSETTLED`: the bands do
        not settle the answer. Costs a re-identification and a solve per identified body
        (20 random file predictions took 1.2 times as long); a body whose fit holds no
        data (a saved fit, a common-pole set) or whose band is too narrow to cut enters
        as identified, unchecked.
    estimator : modalid.ModalFit or pair of them, optional
        The estimator each FRF file or FRFData is identified with, cloned for each body
        (``sklearn.base.clone``: its settings; ``estimator`` itself is not fitted; a pair:
        body 1's, body 2's, either None for the default), e.g.
        ``ModalFit(**HammerFRF.fit_options())`` (``window_decay_rate``,
        ``record_length``) for FRFs measured with an exponential window whose file does
        not state them (``frf_from_hammer``'s FRFData and the files ``write_frf`` writes
        do, and ``ModalFit()`` models what they state). Default ``ModalFit()``.
    read_options : dict or pair of dicts, optional
        :func:`modalid.read_frf` options of the FRF files (:data:`READ_OPTIONS`; a pair:
        body 1's, body 2's), e.g. ``{"format": "complex-lines", "freq_hz": f}`` for bare
        complex lines, ``{"conjugate": True}`` for a file stored with the other sign
        convention, ``{"negate": True}`` for a driving point with its sign reversed
        (files only: one dict passes an FRFData or a fitted ModalFit by, a pair's entry
        for one is refused).
    check_passive : bool
        Refuse models that are not stable, passive driving points (see :class:`Body`),
        and FRF files or FRFData whose sign says they are not (see
        :func:`modalid.io.check_sign`).
    progress : bool or "auto"
        A progress bar on stderr for the time-stepping solves of the prediction itself
        (``solve_impact``'s ``progress``) and one counting the uncertainty band's
        re-identifications and solves: ``"auto"`` (default) once a solve or the band has
        taken 10 s (the band check's: once it has taken 10 s unless False).

    Returns
    -------
    Prediction

    Raises
    ------
    TypeError
        ``estimator`` is not a ``ModalFit`` (e.g. a dict of its options).
    ValueError
        A body's identification failed or its FRF is not a driving point (see
        :func:`check_identification`; a suspect one warns with
        :class:`IdentificationWarning`), an FRF file is stored with the other sign
        convention or its sign is reversed, a model is not a passive driving point, or
        the solve's input is refused (see :func:`solve_impact`).
    RuntimeError
        The solver cannot go on (e.g. a grazing contact the exact solver cannot decide;
        the message names the method to use instead).
    """
    if isinstance(estimator, (list, tuple)):
        if len(estimator) != 2:
            raise ValueError(f"estimator must be a ModalFit or a pair of them (body 1, body "
                             f"2), got {len(estimator)} items")
        estimator = tuple(check_estimator(e) for e in estimator)
    else:
        estimator = (check_estimator(estimator),) * 2
    if not (isinstance(continuation, (bool, np.bool_)) or continuation == "auto"):
        raise ValueError(f"continuation must be True, False or 'auto', got {continuation!r}")
    progress = check_progress(progress)
    for name, flag in (("uncertainty", uncertainty), ("band_check", band_check)):
        if not isinstance(flag, (bool, np.bool_)):
            raise TypeError(f"{name} must be True or False, got {flag!r}")
    band_tolerance = as_nonnegative_scalar("band_tolerance", band_tolerance)
    # before any identification: a wide band's fit takes seconds
    velocity1, velocity2 = as_real_scalar("velocity1", velocity1), as_real_scalar("velocity2",
                                                                                  velocity2)
    specs = (body1, body2)
    models, fits = _bodies(specs, quantity=quantity, estimator=estimator,
                           read_options=read_options, check_passive=check_passive)
    if uncertainty:
        check_band_bodies([body_label(spec) for spec in specs], fits)
    law = parse_contact(contact)

    # a partial of a module-level function: it pickles, for the band's process pools
    solve = functools.partial(_solve_pair, velocity1=velocity1, velocity2=velocity2,
                              check_passive=check_passive, gap=gap, contact=law,
                              t_end=t_end, dt=dt, method=method)

    # the run the band's spectrum is read from (resolved_force), of ``models`` as they
    # stand when called; ``record`` is the probe's while the probe is the answer
    resolve = functools.partial(_quiet_solve, solve, models)
    notes = [None if fit is None else "off" for fit in fits]
    result, probe_warnings, record = None, [], None
    if continuation == "auto":
        # the probe without continuation: its warnings are said only if its result stays
        with warnings.catch_warnings(record=True) as probe_warnings:
            warnings.simplefilter("always")
            result = solve(*models, progress=progress)
        record = resolved_force(result, resolve)
        shares = [None if fit is None else force_energy_above(record, fit.report_["band_hz"][1])
                  for fit in fits]
        wanted = [share is not None and share > CONTINUATION_SHARE for share in shares]
        notes = [None if share is None else
                 f"off (auto: {100 * share:.2f} % of the force's energy above the band)"
                 for share in shares]
    else:
        shares = [None] * 2
        wanted = [bool(continuation) and fit is not None for fit in fits]
    if any(wanted):
        for i, fit in enumerate(fits):
            if wanted[i]:
                models[i], notes[i] = _continued(fit, label=f"body {i + 1}: ")
                if shares[i] is not None:
                    notes[i] += (f" (auto: {100 * shares[i]:.2f} % of the force's "  # type: ignore[operator]
                                 "energy lay above the band without it)")
                _check_model(models[i], specs[i], i + 1, check_passive)
        result, record = solve(*models, progress=progress), None
    elif result is None:
        result = solve(*models, progress=progress)
    else:
        for caught in probe_warnings:
            warnings.warn(caught.message, caught.category, stacklevel=2)
    identified = any(f is not None for f in fits)
    variants = functools.partial(solve, sensitivity_check=False)   # the band's solves
    figures = impact_figures(result, resolution=band_resolution(fits) if identified else 0.0)
    band = None
    continued = any(n is not None and n.startswith("on") for n in notes)
    if uncertainty and identified:
        band = uncertainty_band(models, fits, variants, n_draws=uncertainty_draws, seed=seed,
                                continuation=continued, nominal=result, executor=executor,
                                contact=law, progress=progress)
    elif band_check and any(_cuttable(f) for f in fits):
        # the band's cheap half (no draws): does the answer move with the band? A body
        # whose band cannot be cut enters as identified, as an exact one does
        checked = [i + 1 for i, f in enumerate(fits) if _cuttable(f)]
        try:
            with warnings.catch_warnings():   # its outcome changes: in warn_unsettled's words
                warnings.filterwarnings("ignore", message=".*left out of the band's spread")
                check = uncertainty_band(models, [f if _cuttable(f) else None for f in fits],
                                         variants, n_draws=0, continuation=continued,
                                         nominal=result, executor=executor, contact=law,
                                         fractions=(BAND_CHECK_FRACTION,), tail_variant=False,
                                         progress="auto" if progress else False)
        except ValueError as exc:        # a re-identification the cut band refuses
            warnings.warn(f"the band check could not re-identify on {BAND_CHECK_FRACTION:.0%}"
                          f" of the band ({exc}): this prediction is not checked",
                          BandWarning, stacklevel=2)
        else:
            warn_unsettled(check, figures, checked)
    reach, reach_below = band_reach(result, fits, notes, band_tolerance,
                                    [_lower_terms(fit, band_tolerance) if fit is not None
                                     else (None, np.inf, True) for fit in fits],
                                    record=record if record is not None
                                    else resolved_force(result, resolve))
    return Prediction(result=result, fits=tuple(fits), band_reach=tuple(reach),
                      figures=figures, uncertainty=band, continuation=tuple(notes),
                      band_reach_below=tuple(reach_below))
