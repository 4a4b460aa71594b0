"""``predict``: from what a user has (measured FRF files, saved models, simple specs) to
an impact prediction, with each identified body's report and a check of the band.

A body is given as

* a measured FRF file (CSV, ``.npz``, ``.mat``, UFF 58): identified with
  :class:`modalid.ModalFit`;
* a saved model (``.json`` from ``ModalModel.to_json``, or from
  ``MultiOutputModalModel.to_json``: the prediction then gives every point's response);
* a spec string: ``mass:M``, ``rod:mass=..,transit_time=..[,support=free|fixed]``,
  ``spring-mass:mass=..,stiffness=..[,damping_ratio=..]``,
  ``beam:mass=..,time_scale=..`` (SI units);
* or any model object ``solve_impact`` takes.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from data_synth import CantileverBeam, ExactModel, LumpedMass, Rod, SpringMass
from modalid import ModalFit, ModalModel, MultiOutputModalModel
from modalid.io import read_frf

from .api import solve_impact
from .body import Body, SampledResponse, check_driving_point
from .contact import ContactLaw, Hertz, LinearSpring, Rigid
from .result import ImpactResult
from .truncation import band_resolution, identified_model, impact_figures
from .uncertainty import uncertainty_band

__all__ = ["predict", "Prediction", "parse_body", "parse_contact", "BandWarning",
           "IdentificationWarning", "check_identification"]


class BandWarning(UserWarning):
    """The predicted force has a good part of its spectrum above a body's measured band."""


class IdentificationWarning(UserWarning):
    """A body's identification is suspect (``ModalFit.report_["verdict"] == "suspect"``):
    the prediction goes on, on a model to be checked."""


#: what may fix a failed identification, as predict's and ModalFit's keywords (the command
#: line names the same options as flags)
_FIT_REMEDIES = ("quantity=... if the file does not state its quantity or states it wrong; "
                 "missed_modes='dense' for a band with many weak or close modes; "
                 "window_decay_rate=... and record_length=... for FRFs measured with an "
                 "exponential window; a band that holds whole resonances, or identify the "
                 "body yourself (modalid.ModalFit) and give the saved model (.json)")


def check_identification(fit, source, *, body: int) -> None:
    """Stop a prediction on a failed or non-driving-point identification; warn on a suspect one.

    Parameters
    ----------
    fit : modalid.ModalFit
        Fitted on the FRF file ``source``; reads ``report_["verdict"]`` (``"ok"``,
        ``"suspect"`` or ``"failed"``, ``"ok"`` when absent), ``report_["verdict_reasons"]``
        and ``report_["driving_point"]`` (True, False or None: not decided).
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
    if report.get("driving_point") is False:
        why = report.get("driving_point_reason") or reasons
        raise ValueError(f"body {body}: {source} is not a driving-point FRF ({why}): a "
                         "transfer FRF cannot be an impact body, a body needs its "
                         "driving-point receptance (force and response at the contact "
                         "point); give the FRF measured there")
    if verdict == "failed":
        raise ValueError(f"body {body}: the identification of {source} failed ({reasons}); "
                         f"options that may fix it: {_FIT_REMEDIES}")
    if verdict == "suspect":
        warnings.warn(f"body {body}: the identification of {source} is suspect ({reasons}); "
                      "the prediction relies on it", IdentificationWarning, stacklevel=3)


_SPECS = {
    "mass": (LumpedMass, ("mass",)),
    "rod": (Rod, ("mass", "transit_time", "support")),
    "spring-mass": (SpringMass, ("mass", "stiffness", "damping_ratio")),
    "beam": (CantileverBeam, ("mass", "time_scale")),
}


def _parse_fields(kind, text, names):
    values, positional = {}, []
    for item in filter(None, (part.strip() for part in text.split(","))):
        if "=" in item:
            key, value = (x.strip() for x in item.split("=", 1))
            if key not in names:
                raise ValueError(f"{kind} spec: unknown field {key!r}; fields are {names}")
            values[key] = value
        else:
            positional.append(item)
    for name, value in zip(names, positional):
        values.setdefault(name, value)
    out = {}
    for key, value in values.items():
        if key == "support":
            out[key] = value
            continue
        try:
            out[key] = float(value)
        except ValueError as exc:
            raise ValueError(f"{kind} spec: {key}={value!r} is not a number") from exc
    return out


def parse_body(spec, *, quantity=None, fit=None, continuation=False):
    """The model of a body spec and, for a measured FRF, its fitted ``ModalFit``.

    Returns ``(model, fit_or_None)``. With ``continuation=True`` a model identified from
    an FRF file carries the high-frequency continuation of
    :func:`impactpred.truncation.continue_above_band`.
    """
    if isinstance(spec, (ModalModel, MultiOutputModalModel, ExactModel, SampledResponse)):
        return spec, None
    if not isinstance(spec, (str, Path)):
        raise TypeError(f"a body must be a file, a spec string or a model, got "
                        f"{type(spec).__name__}")
    text = str(spec)
    kind, sep, rest = text.partition(":")
    if sep and kind in _SPECS and not Path(text).exists():
        cls, names = _SPECS[kind]
        try:
            return cls(**_parse_fields(kind, rest, names)), None
        except TypeError as exc:
            raise ValueError(f"{kind} spec {text!r}: {exc}") from exc
    path = Path(text)
    if not path.exists():
        raise ValueError(f"body {text!r} is neither an existing file nor a spec "
                         f"({', '.join(k + ':...' for k in _SPECS)})")
    if path.suffix.lower() == ".json":
        text = path.read_text()
        if '"modalid.MultiOutputModalModel"' in text:   # several points: their responses too
            return MultiOutputModalModel.from_json(text), None
        return ModalModel.from_json(text), None
    data = read_frf(path, quantity=quantity)
    estimator = fit if fit is not None else ModalFit()
    estimator.fit(data)
    return identified_model(estimator, continuation=continuation), estimator


def parse_contact(spec) -> ContactLaw:
    """``rigid``, ``spring:stiffness=..[,damping=..]``, ``hertz:stiffness=..[,exponent=..]``
    or ``hertz-sphere:radius1=..,youngs_modulus1=..,poisson1=..,youngs_modulus2=..,
    poisson2=..[,radius2=..]``; a ``ContactLaw`` passes through."""
    if isinstance(spec, ContactLaw):
        return spec
    if not isinstance(spec, str):
        raise TypeError(f"contact must be a ContactLaw or a spec string, got {spec!r}")
    kind, _, rest = spec.partition(":")
    laws = {"spring": (LinearSpring, ("stiffness", "damping")),
            "hertz": (Hertz, ("stiffness", "exponent")),
            "hertz-sphere": (Hertz.from_materials, ("radius1", "youngs_modulus1", "poisson1",
                                                    "youngs_modulus2", "poisson2", "radius2"))}
    if kind == "rigid":
        return Rigid()
    if kind not in laws:
        raise ValueError(f"contact {spec!r}: use rigid, spring:..., hertz:... or "
                         "hertz-sphere:...")
    factory, names = laws[kind]
    return factory(**_parse_fields(kind, rest, names))


@dataclass(frozen=True)
class Prediction:
    """An impact prediction and where its models came from.

    Attributes
    ----------
    result : ImpactResult
    fits : tuple
        The ``ModalFit`` of each body identified from measured data (None otherwise).
    band_reach : tuple
        Per identified body: the share of the contact force's energy above the top of
        the band its model was identified on (None for the others).
    figures : dict or None
        ``contact_duration``, ``peak_force``, ``impulse``, ``restitution`` (and contact
        counts) from :func:`impactpred.truncation.impact_figures`, with contacts closer
        than the narrowest band's resolution ``1/(2 f_top)`` merged; None without an
        identified body (use ``result``'s own figures then).
    uncertainty : UncertaintyBand or None
        With ``predict(..., uncertainty=True)``: the spread of those figures over the
        bodies re-identified on 60 % and 80 % of their band and over draws of the fits'
        parameters, widened by the truncation error the cut bands imply and the tail's
        (``uncertainty.low``, ``uncertainty.high``, ``uncertainty.table()``).
    """

    result: ImpactResult
    fits: tuple
    band_reach: tuple
    figures: dict | None = None
    uncertainty: object = field(default=None)


def force_energy_above(result: ImpactResult, freq_hz: float) -> float:
    """Share (0-1) of the contact force's spectral energy above ``freq_hz``.

    Computed from the force history resampled on a uniform grid (FFT); Dirac parts
    count as white (all frequencies alike) over the grid's band.
    """
    t, f = result.t, result.force
    n = max(4096, int(2 ** np.ceil(np.log2(t.size))))
    grid = np.linspace(t[0], t[-1], n)
    dt = grid[1] - grid[0]
    signal = np.interp(grid, t, f)
    for time, impulse in result.dirac_impulses:
        signal[min(int(round(time / dt)), n - 1)] += impulse / dt
    spectrum = np.abs(np.fft.rfft(signal)) ** 2
    freq = np.fft.rfftfreq(n, dt)
    total = float(np.sum(spectrum[1:]))
    return float(np.sum(spectrum[freq > freq_hz]) / total) if total > 0 else 0.0


def predict(body1, body2, *, velocity1=0.0, velocity2=0.0, gap=0.0, contact="rigid",
            t_end, dt=None, method="auto", quantity=None, band_tolerance=0.01,
            continuation=False, uncertainty=False, uncertainty_draws=4,
            seed=0, fit_options=None, check_passive=True) -> Prediction:
    """Predict the impact of two bodies given as files, specs or models.

    Parameters
    ----------
    body1, body2 : str, Path or model
        See the module docstring. ``+y`` points from body 1 to body 2.
    velocity1, velocity2 : float
        Rigid-body velocities before impact (m/s).
    gap, t_end, dt, method
        As in :func:`solve_impact`.
    contact : str or ContactLaw
        See :func:`parse_contact`.
    quantity : str, optional
        Quantity of FRF files that do not state it.
    band_tolerance : float
        A :class:`BandWarning` is issued when more than this share of the force's energy
        lies above an identified body's band: the model is extrapolated there.
    continuation : bool
        Continue each model identified from an FRF file above its band (the
        structure's high-frequency impedance from its top modes; see
        :func:`impactpred.truncation.continue_above_band`). Without it rigid contact
        against a finite modal sum chatters.
    uncertainty : bool
        Attach an :class:`~impactpred.uncertainty.UncertaintyBand` (re-identification on
        60 % and 80 % of each band, ``uncertainty_draws`` parameter draws with ``seed``,
        the truncation error the cut bands imply and the continuation's).
    fit_options : dict, optional
        Keyword options of the :class:`modalid.ModalFit` each FRF file is identified with,
        e.g. ``HammerFRF.fit_options()`` (``window_decay_rate``, ``record_length``) for FRFs
        measured with an exponential window, which the fit then models exactly.
    check_passive : bool
        Refuse models that are not stable, passive driving points (see :class:`Body`).

    Raises
    ------
    ValueError
        A body's identification failed or its FRF is not a driving point (see
        :func:`check_identification`; a suspect one warns with
        :class:`IdentificationWarning`), a model is not a passive driving point, or the
        solve's input is refused (see :func:`solve_impact`).
    """
    if fit_options is not None and not isinstance(fit_options, dict):
        raise TypeError(f"fit_options must be a dict of ModalFit options, got "
                        f"{type(fit_options).__name__}")
    models, fits = [], []
    for i, spec in enumerate((body1, body2), start=1):
        estimator = ModalFit(**fit_options) if fit_options else None
        model, fit = parse_body(spec, quantity=quantity, fit=estimator,
                                continuation=continuation)
        if fit is not None:
            check_identification(fit, spec, body=i)
        if check_passive and isinstance(model, (ModalModel, MultiOutputModalModel)):
            label = spec if isinstance(spec, (str, Path)) else f"a {type(spec).__name__}"
            check_driving_point(model, name=f"body {i} ({label})",
                                opt_out="to use it anyway, check_passive=False")
        models.append(model)
        fits.append(fit)
    law = parse_contact(contact)

    def solve(model1, model2):
        return solve_impact(Body(model1, velocity=velocity1, check_passive=check_passive),
                            Body(model2, velocity=velocity2, check_passive=check_passive),
                            gap=gap, contact=law, t_end=t_end, dt=dt, method=method)

    result = solve(*models)
    identified = any(f is not None for f in fits)
    figures = (impact_figures(result, resolution=band_resolution(fits)) if identified
               else None)
    band = None
    if uncertainty and identified:
        band = uncertainty_band(models, fits, solve, n_draws=uncertainty_draws, seed=seed,
                                continuation=continuation, nominal=result)
    reach = []
    for i, fit in enumerate(fits):
        if fit is None:
            reach.append(None)
            continue
        top = fit.report_["band_hz"][1]
        share = force_energy_above(result, top)
        reach.append(share)
        if share > band_tolerance:
            warnings.warn(f"body {i + 1}: {100 * share:.1f} % of the contact force's energy "
                          f"lies above its measured band ({top:.4g} Hz); the prediction "
                          "relies on the model's residual terms there", BandWarning,
                          stacklevel=2)
    return Prediction(result=result, fits=tuple(fits), band_reach=tuple(reach),
                      figures=figures, uncertainty=band)
