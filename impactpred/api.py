"""``solve_impact``: the one entry point of the impact solvers."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable

import numpy as np

from modalid.validation import as_choice, as_positive_scalar, as_real_scalar

from ._caveats import SENSITIVITY_SCALE, caveats, is_sequence, many_micro_contacts
from ._time_scales import (LOAD_STEPS, SAID_ERROR, contact_time_scales, expected_error,
                           load_time_scale)
from ._energy_terms import contact_energy, dashpot_dissipation, exchangeable_energy, load_work
from ._load_impulse import at_contacts
from ._specs import parse_contact
from .body import Body, SampledResponse
from .contact import Rigid, check_contact
from .damper.excitation import HarmonicForce
from .engine import MAX_SAMPLES
from .parallel import check_progress, one_blas_thread
from .result import EnergyAudit, EnergyWarning, ImpactResult
from .solvers.closed_form import applies_closed_form, solve_closed_form
from .solvers.convolution import solve_convolution
from .solvers.laplace import solve_laplace
from .solvers.modal import first_order_hold_applies, solve_modal

__all__ = ["solve_impact", "choose_dt", "energy_audit", "METHODS", "ENERGY_TOLERANCE"]

METHODS = ("auto", "laplace", "modal", "convolution", "closed_form")

#: steps per fastest time scale that resolve duration and restitution to about 0.1 %
_STEPS_PER_SCALE = 1000
_MAX_STEPS = MAX_SAMPLES
#: a time-stepping run takes at least this many automatic steps (a measured record's
#: sample excepted)
_MIN_RUN_STEPS = 200
#: the automatic step is never coarsened more than this to fit ``_MAX_STEPS``
_COARSEST = 20
#: an automatic step whose run fails the energy audit is halved at most this many times
_AUTO_REFINEMENTS = 2
#: output samples of the exact (laplace) solver per 1/omega of the fastest time scale
_LAPLACE_SAMPLES_PER_SCALE = 8
#: relative accuracy of each solver's energy balance (of the energy an impact can
#: redistribute, :attr:`EnergyAudit.scale`); more created energy is flagged. Measured
#: over the 196 solves of the impactpred tests: at most 1.5e-13 for "laplace", 0 for
#: "closed_form", 7.4e-5 for "modal", 5e-15 for "convolution" (a compliant contact's
#: implicit steps only lose energy); the step rule targets 0.1 % on the restitution.
ENERGY_TOLERANCE = {"closed_form": 1e-6, "laplace": 1e-6, "modal": 5e-3, "convolution": 5e-3}
_EXACT = ("closed_form", "laplace")
#: output samples of the exact solver's sensitivity runs (their figures are the events'),
#: which run up to this many spans of the sequence after its last contact
_SENSITIVITY_SAMPLES = 16
_SENSITIVITY_SPANS = 3
#: a sequence of more contacts is not checked (each run costs about the main one's search)
_SENSITIVITY_CONTACTS = 1000


def solve_impact(body1: Body, body2: Body, *, gap: float = 0.0, contact=Rigid(),
                 t_end: float, dt: float | None = None, method: str = "auto",
                 progress: bool | str = "auto",
                 sensitivity_check: bool = True) -> ImpactResult:
    """Predict the impact of two bodies touching at one point each.

    Parameters
    ----------
    body1, body2 : Body
        Body 1 approaches from below (``-y`` side); ``+y`` points from body 1 to body 2.
    gap : float, keyword-only
        Initial clearance ``g0 >= 0`` (m) between the contact points.
    contact : Rigid, LinearSpring, Hertz or str, keyword-only
        Contact law; ``Rigid()`` is the paper's. A string is its spec, as
        :func:`impactpred.predict.parse_contact` reads it (``"rigid"``,
        ``"spring:stiffness=1e4"``).
    t_end : float, keyword-only
        End of the prediction (s): every contact, separation and re-contact up to it.
    dt : float or None, keyword-only
        Time step (s) of the time-stepping solvers, or the output step of the exact ones.
        ``None`` picks one from the bodies' time scales (see :func:`choose_dt`); a
        time-stepping run that then fails its energy audit (energy created) is run again
        at half the step, twice at most, and the notes say so. A step given coarser than
        that one costs accuracy in proportion: where the energies would be off by over
        1 % (over 1.6 times the automatic step for ``"convolution"``, 5 times for
        ``"modal"``'s first-order hold) a ``RuntimeWarning`` and a note give the expected
        errors.
    method : {"auto", "laplace", "modal", "convolution", "closed_form"}, keyword-only
        ``"auto"``: the closed form for two free rods of equal transit time (without
        output points), the exact Laplace solver for rational models with a linear contact
        law and no load or a ``HarmonicForce`` load, the modal solver for other rational
        cases, the convolution solver otherwise.
    progress : bool or "auto", keyword-only
        A progress bar on stderr over the steps of the time-stepping loops that run in
        Python (``"convolution"``, O(log^2 steps) a step, and the ``"modal"`` method's
        zero-order hold, O(modes) a step; up to 4e6 steps); the compiled loops (the exact
        methods, the modal first-order hold) take none. ``"auto"`` (default): only once
        the run has taken 10 s (a stiff rod on a cantilever, 4e6 convolution steps, ran
        four minutes in silence); False: never.
    sensitivity_check : bool, keyword-only
        Whether the exact solver checks a sequence of 3 to 1000 contacts for its
        sensitivity to its inputs (see Warns): two more runs of its event search, about
        2-3 times the run's time (a 70-contact run: 9 ms -> 28 ms). Off where the caller
        measures the spread itself (an uncertainty band's draws) or times the engine.

    Returns
    -------
    ImpactResult
        With ``points``: a :class:`PointResponse` per body given with outputs
        (``Body(MultiOutputModalModel)`` or ``Body(Rod/CantileverBeam, outputs=xi)``).

    Warns
    -----
    UserWarning
        When the last contact is still closed at ``t_end`` (``in_contact_at_end``): no
        restitution (None); when the bodies still approach after the last contact
        (restitution < 0: another contact follows after ``t_end``); when the bodies never
        touch before ``t_end`` (no impact: the message gives the gap, the closing speed and
        when rigid motion alone would close the gap); when a time-stepping run chatters at
        its grid's scale (many contacts of one or two steps, and the restitution or the
        impulse moves when the run is repeated at ``dt / 2``: the figures depend on ``dt``);
        when a sequence of contacts is not converged in ``dt`` (a time-stepping run at the
        automatic step, repeated at ``dt / 2``) or, from the exact solver, not robust to its
        inputs (repeated with body 1's receptance scaled by ``1 +- 1e-6``, at a coarse
        output step and up to three spans of the sequence after its last contact: a
        perturbed run's contacts later than that are not compared); when a rigid contact
        passes over a quarter of its impulse within one period of a truncated modal model's top
        mode.
        The same words go into the result's ``notes`` (:mod:`impactpred._caveats`).
    """
    for name, body in (("body1", body1), ("body2", body2)):
        if not isinstance(body, Body):
            raise TypeError(f"{name} must be an impactpred.Body, got {type(body).__name__}")
    gap = as_real_scalar("gap", gap)
    if gap < 0:
        raise ValueError(f"gap must be >= 0 (the bodies may not start overlapping), got {gap!r}")
    y1_0, y2_0 = (_start_displacement(body1), _start_displacement(body2))
    start_gap = gap + y2_0 - y1_0
    if start_gap < -1e-12 * max(abs(gap), abs(y1_0), abs(y2_0)):
        raise ValueError(f"the bodies start overlapping: gap + y2(0) - y1(0) = {start_gap!r} m "
                         f"< 0 (gap={gap!r}, contact-point displacements at t = 0 from "
                         f"displacement, vibration and a load's direct term d F(0): "
                         f"y1(0)={y1_0!r}, y2(0)={y2_0!r})")
    contact = check_contact(parse_contact(contact) if isinstance(contact, str) else contact)
    t_end = as_positive_scalar("t_end", t_end)
    if dt is not None:
        dt = as_positive_scalar("dt", dt)
        if dt > t_end:
            raise ValueError(f"dt={dt!r} s exceeds t_end={t_end!r} s: the step must fit in "
                             "the run")
    as_choice("method", method, METHODS)
    progress = check_progress(progress)
    if not isinstance(sensitivity_check, (bool, np.bool_)):
        raise TypeError(f"sensitivity_check must be True or False, got {sensitivity_check!r}")
    bodies = (body1, body2)
    chosen = _choose_method(bodies, contact, method)
    stepping = chosen in ("modal", "convolution")       # on a grid, not exact
    notes = []
    automatic = dt is None
    if dt is None:
        dt = choose_dt(bodies, contact, t_end=t_end, method=chosen)
        notes.append(f"dt chosen automatically: {dt:.6g} s")
        coarse = _samples_too_coarse(bodies, contact, t_end, dt) if stepping else None
        if coarse is not None:
            notes.append(coarse)
            warnings.warn(coarse, RuntimeWarning, stacklevel=2)
        if stepping:
            dt = _step_for_t_end(t_end, dt, chosen, notes, bodies, contact)
    elif stepping:
        recommended = choose_dt(bodies, contact, t_end=t_end, method=chosen)
        first_order = chosen == "modal" and first_order_hold_applies(bodies, contact, dt)
        expected = expected_error(first_order, dt / recommended)
        if 2 * expected > SAID_ERROR:
            hold = "first" if first_order else "zero"
            said = (f"dt={dt:.4g} s is {dt / recommended:.3g} times the step that resolves "
                    f"these bodies ({recommended:.4g} s): expect errors up to about "
                    f"{expected:.2g} % of the approach speed in the restitution and "
                    f"{2 * expected:.2g} % of the energies (the {chosen} solver's "
                    f"{hold}-order hold, first order in dt)")
            notes.append(said)
            warnings.warn(said, RuntimeWarning, stacklevel=2)
    if stepping:
        dt = _step_within_records(bodies, t_end, dt, notes)
    solvers: dict[str, Callable[..., ImpactResult]] = {
        "laplace": solve_laplace, "modal": solve_modal, "convolution": solve_convolution,
        "closed_form": solve_closed_form}
    solver = solvers[chosen]
    options = {"progress": progress} if stepping else {}

    def run(*args, **kwargs) -> ImpactResult:   # small dense algebra: one BLAS thread
        with one_blas_thread():
            return at_contacts(solver(*args, **options, **kwargs), bodies)
    if t_end / dt > _MAX_STEPS * (1 + 1e-9):       # steps, or an exact solver's samples
        raise ValueError(f"t_end={t_end:.6g} / dt={dt:.4g} = {t_end / dt:.3g} steps or samples "
                         f"exceeds {_MAX_STEPS}: increase dt or shorten t_end (at most "
                         f"t_end={_MAX_STEPS * dt:.4g} at this step)")
    result = run(bodies, gap, contact, t_end, dt, notes=tuple(notes))
    audit = energy_audit(result, bodies, contact)
    for _ in range(_AUTO_REFINEMENTS if automatic and stepping else 0):
        # the automatic step is the best-known practice, not a guarantee: where the run
        # fails its own energy audit (energy created), halve it while the steps allow
        if audit.relative <= audit.tolerance or 2 * t_end / dt > _MAX_STEPS:
            break
        said = (f"dt halved to {dt / 2:.6g} s: at {dt:.6g} s the energy audit found "
                f"{100 * audit.relative:.3g} % of the exchangeable energy created")
        dt /= 2
        notes.append(said)
        result = run(bodies, gap, contact, t_end, dt, notes=tuple(notes))
        audit = energy_audit(result, bodies, contact)
    finer = None
    micro = stepping and many_micro_contacts(result)
    if micro or stepping and automatic and is_sequence(result):
        # contacts of a step or two: the grid's chatter, or the model's Dirac re-contacts?
        # a sequence of contacts: converged in dt? the same run at half the step tells
        # (its figures move, or they do not); a sequence at the step limit is compared
        # with the run at twice the step instead (a change there bounds dt's error). The
        # sequence is checked at the automatic step, which the solver vouches for: a step
        # given is the caller's to converge (and timed as given: one run)
        other = (dt / 2 if 2 * t_end / dt <= _MAX_STEPS
                 else None if micro else _step_within_records(bodies, t_end, 2 * dt, []))
        if other is not None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                finer = run(bodies, gap, contact, t_end, other, notes=())
    perturbed = (_sensitivity_runs(run, result, bodies, gap, contact, t_end)
                 if sensitivity_check and chosen == "laplace" else ())
    sentences = caveats(result, bodies, t_end=t_end, start_gap=start_gap, finer=finer,
                        perturbed=perturbed, time_stepping=stepping, contact=contact,
                        energy_scale=audit.scale)
    for sentence in sentences:
        warnings.warn(sentence, UserWarning, stacklevel=2)
    if sentences:
        result = dataclasses.replace(result, notes=result.notes + sentences)
    if math.isinf(audit.tolerance):
        warnings.warn(f"dt={dt:.4g} s leaves under two output samples per period of a "
                      f"load: the energy audit cannot check the load's work (the automatic "
                      f"step, dt=None, can)", RuntimeWarning, stacklevel=2)
    if not audit.ok:
        warnings.warn(f"energy audit: {'; '.join(audit.reasons)}", EnergyWarning, stacklevel=2)
    return dataclasses.replace(result, energy_audit=audit)


def _sensitivity_runs(run, result, bodies, gap, contact, t_end) -> tuple | str:
    """The exact run ``run`` repeated with body 1's receptance scaled by ``1 +- 1e-6``
    where ``result`` is a sequence of contacts (:func:`impactpred._caveats.caveats`'s
    ``perturbed``): ``()`` for no sequence, a string saying why it is not checked.

    Its figures are the events': a coarse output step, and a run to a few spans of the
    sequence after its end (the search to a long ``t_end`` would triple the run's cost:
    87 s for 35 s at ``t_end = 1e7`` s); a sequence of more than
    :data:`_SENSITIVITY_CONTACTS` is not rerun.
    """
    if result.n_contacts > _SENSITIVITY_CONTACTS:
        return (f"more than {_SENSITIVITY_CONTACTS} contacts: two more runs would about "
                "triple the cost")
    if not is_sequence(result):
        return ()
    (first, _), (_, last) = result.contact_intervals[0], result.contact_intervals[-1]
    t_check = min(t_end, last + _SENSITIVITY_SPANS * (last - first))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return tuple(run(bodies, gap, contact, t_check, t_check / _SENSITIVITY_SAMPLES,
                             notes=(), receptance_scale=1.0 + sign * SENSITIVITY_SCALE)
                         for sign in (1, -1))
    except RuntimeError as exc:          # a perturbed run stalled: said, not raised
        return f"a run with body 1's receptance scaled stopped ({exc})"


def _start_displacement(body) -> float:
    """The contact point's displacement (m) at ``t = 0``: the free motion's, plus the
    direct term ``d F(0)`` of a rational model's residual flexibility under its load."""
    d, force = body.load_direct_term()
    return float(body.free_motion(0.0)) + d * force


def _step_within_records(bodies, t_end, dt, notes):
    """``dt``, or the nearest smaller step that divides ``t_end``, so that a grid of whole
    steps from 0 to ``t_end`` stays inside every sampled response's record (s).

    A grid of ``ceil(t_end/dt)`` steps passes ``t_end`` by up to a step (or by one whole
    step when ``dt`` is the samples' spacing up to rounding), past the record's last
    sample even for a ``t_end`` equal to it.
    """
    records = [b.model.duration for b in bodies if isinstance(b.model, SampledResponse)]
    ratio = t_end / dt
    n_steps = max(1, math.ceil(ratio - 1e-9))
    if not records or n_steps * dt <= min(records) * (1 + 1e-12):
        return dt
    if t_end > min(records) * (1 + 1e-12):       # too short whatever the step: the
        return dt                                # solver's error says so
    if abs(ratio - round(ratio)) <= 1e-6 * ratio:   # dt divides t_end up to rounding
        n_steps = max(1, round(ratio))
    fitted = t_end / n_steps
    if abs(fitted - dt) > 1e-9 * dt:
        notes.append(f"dt {dt:.6g} -> {fitted:.6g} s: {n_steps} whole steps end at t_end, "
                     "inside the sampled record")
    return fitted


def _step_for_t_end(t_end, dt, method, notes, bodies, contact):
    """The automatic step ``dt`` (s), or a coarser one when ``t_end`` needs more than
    ``_MAX_STEPS`` of it: up to ``_COARSEST`` times coarser with a ``RuntimeWarning`` that
    gives the numbers (up to 1e-3 coarser, the rounding of the longest ``t_end`` the
    refusal prints, with a note only), never more (``ValueError``)."""
    if t_end / dt <= _MAX_STEPS:
        return dt
    coarse = t_end / _MAX_STEPS
    ratio = coarse / dt
    longest = _MAX_STEPS * dt
    if ratio <= 1.001:                 # the longest t_end as the message below rounds it
        notes.append(f"dt coarsened to t_end/{_MAX_STEPS} = {coarse:.6g} s ({ratio:.6g} "
                     "times the step that resolves the bodies: within the refusal's "
                     "rounding, no warning)")
        return coarse
    needs = (f"t_end={t_end:.6g} needs {t_end / dt:.3g} steps of dt={dt:.4g} s, the step that "
             f"resolves these bodies' contact duration and restitution to about 0.1 %, and a "
             f"solve takes at most {_MAX_STEPS}")
    if ratio > _COARSEST:
        raise ValueError(f"{needs}: shorten it to at most {longest:.4g} s "
                         f"(t_end={longest:.4g}) for the full accuracy, or to "
                         f"{_COARSEST * longest:.4g} s for a step up to {_COARSEST} times "
                         "coarser (with a warning), or give a coarser step dt=... explicitly "
                         "(larger errors, with a warning)")
    expected = expected_error(method == "modal" and first_order_hold_applies(
        bodies, contact, coarse), ratio)
    warnings.warn(f"{needs}: dt={coarse:.4g} s ({ratio:.3g} times coarser) is used; expect "
                  f"errors up to about {expected:.2g} % of the approach speed in the "
                  f"restitution and {2 * expected:.2g} % of the energies, or shorten t_end to "
                  f"at most {longest:.4g} s for the full accuracy", RuntimeWarning, stacklevel=3)
    notes.append(f"dt coarsened to t_end/{_MAX_STEPS} = {coarse:.6g} s ({ratio:.3g} times the "
                 "step that resolves the bodies)")
    return coarse


def energy_audit(result, bodies, contact) -> EnergyAudit:
    """The energy balance of ``result`` (see :class:`EnergyAudit`), flagged where it fails.

    Flags, each with the numbers: more energy at the end than at the start plus the loads'
    work, beyond :data:`ENERGY_TOLERANCE` of the solver (of the energy the impact can
    redistribute), in the energy delivered and, where the solver knows it
    (``BodyEnergy.vibration_held``), in the energy the bodies hold at ``t_end`` (a damped
    body that holds more than it was delivered made energy); a body left with negative
    vibration energy (a non-passive model, whose
    negative energy would hide what it created); a restitution above ``1 + tolerance``
    for two bodies without pre-impact vibration or external load (impossible: no energy
    to draw it from).

    Parameters
    ----------
    result : ImpactResult
        As a solver returns it.
    bodies : pair of Body
        The bodies it was solved for.
    contact : ContactLaw
        Its contact law (for the dashpot's dissipation and the energy left in a compliant
        contact at ``t_end``).

    Returns
    -------
    EnergyAudit
        ``ok`` False with its ``reasons`` when flagged.
    """
    before = sum(e.total_before for e in result.energy_by_body)
    after = sum(e.total_after for e in result.energy_by_body)
    coarse = (result.method == "laplace" and result.t.size > 1
              and float(np.max(np.diff(result.t))) > 1.5 * choose_dt(
                  bodies, contact, t_end=float(result.t[-1]), method="laplace"))
    work, quadrature = load_work(result, bodies, coarse=coarse)
    scale = exchangeable_energy(bodies, before, work)
    audit = EnergyAudit(before=before, after=after,
                        dissipated=dashpot_dissipation(result, contact),
                        stored=contact_energy(contact, float(result.gap[-1])),
                        load_work=work, scale=scale,
                        tolerance=ENERGY_TOLERANCE[result.method]
                        + (quadrature / scale if scale > 0.0 else 0.0))
    fix = ("check the models (a model let through with check_passive=False?)"
           if result.method in _EXACT else "refine dt or check the models")
    reasons = []
    if audit.relative > audit.tolerance:
        reasons.append(f"the bodies end with {audit.created:.4g} J more than they had and "
                       f"were given ({100 * audit.relative:.3g} % of the {audit.scale:.4g} J "
                       f"the impact can redistribute), beyond the {result.method} solver's "
                       f"accuracy ({100 * audit.tolerance:.3g} %): not a physical result; {fix}")
    held = [e.vibration_held for e in result.energy_by_body]
    if all(v is not None for v in held) and audit.scale > 0.0:
        # the energy held at t_end: more than delivered is energy a body's own damping made
        made = sum(v - e.vibration_after for v, e in zip(held, result.energy_by_body))
        excess = (audit.created + made) / audit.scale
        if excess > audit.tolerance and made / audit.scale > audit.tolerance:
            reasons.append(f"the bodies hold {audit.created + made:.4g} J more at t_end than "
                           f"they had and were given ({100 * excess:.3g} % of the "
                           f"{audit.scale:.4g} J the impact can redistribute): a body's own "
                           f"damping made energy; {fix}")
    for i, e in enumerate(result.energy_by_body):
        if e.vibration_after < -audit.tolerance * audit.scale:
            reasons.append(f"body {i + 1} ends with a negative vibration energy "
                           f"({e.vibration_after:.4g} J): a non-passive model; {fix}")
    quiet = all(b.vibration is None and b.load is None for b in bodies)
    figures = {"restitution": result.restitution, "restitution_first": result.restitution_first}
    if figures["restitution_first"] == figures["restitution"]:
        del figures["restitution_first"]
    for name, e in figures.items():
        if quiet and e is not None and e > 1.0 + audit.tolerance:
            reasons.append(f"{name} = {e:.6g} > 1 for bodies without pre-impact vibration "
                           f"or load: energy from nowhere; {fix}")
    return dataclasses.replace(audit, reasons=tuple(reasons))


def _choose_method(bodies, contact, method):
    rational = all(b.is_rational for b in bodies)
    # a harmonic force the exact solver propagates in closed form; other loads are sampled
    sampled_load = any(b.load is not None and not isinstance(b.load, HarmonicForce)
                       for b in bodies)
    linear = contact.is_linear
    outputs = any(b.outputs is not None for b in bodies)
    if method == "auto":
        if applies_closed_form(bodies, contact) and not outputs:
            return "closed_form"
        if rational and linear and not sampled_load:
            return "laplace"
        return "modal" if rational else "convolution"
    if method in ("laplace", "modal") and not rational:
        names = [type(b.model).__name__ for b in bodies if not b.is_rational]
        raise ValueError(f"method={method!r} needs rational models (ModalModel, LumpedMass, "
                         f"SpringMass), got {', '.join(names)}: use method='convolution' or "
                         "a model of finitely many modes (model.modal_model(N, "
                         "residual=True), saved as a .json model file for the command line)")
    if method == "laplace" and not linear:
        raise ValueError(f"method='laplace' needs a linear contact law (Rigid or an undamped "
                         f"LinearSpring), got {contact!r}: use method='modal'")
    if method == "laplace" and sampled_load:
        raise ValueError("method='laplace' takes a HarmonicForce load or none (a sampled or "
                         "callable load needs a time-stepping solver): use method='modal'")
    if method == "closed_form" and not applies_closed_form(bodies, contact):
        raise ValueError("method='closed_form' applies to two free rods of equal transit time "
                         "with rigid contact and rigid-body motion only")
    if method == "closed_form" and outputs:
        raise ValueError("method='closed_form' gives no output points: use "
                         "method='convolution' (exact transfer responses of the rods)")
    return method


#: steps per time scale of each kind (``modalid.receptance.TIME_SCALE_KINDS``): modes
#: are discretised exactly; a continuum's response and a wave front only by the grid; a
#: sampled record gives its own step
_STEPS_BY_KIND = {"modal": 50, "continuum": _STEPS_PER_SCALE, "transit": _STEPS_PER_SCALE,
                  "sample": 1}


def _time_scales(body, *, samples=True):
    """(time scale s, steps per scale) pairs of one body's own dynamics; without a sampled
    record's step if not ``samples``."""
    scales = tuple(body.model.time_scales())
    for ts in scales:
        if ts.kind not in _STEPS_BY_KIND:
            raise ValueError(f"{type(body.model).__name__}.time_scales() gives a time scale "
                             f"of kind {ts.kind!r}: not one of {tuple(_STEPS_BY_KIND)}")
    return [(ts.seconds, _STEPS_BY_KIND[ts.kind]) for ts in scales
            if samples or ts.kind != "sample"]


def _scales_of_kind(bodies, kind):
    """The time scales (s) of the given kind of all the bodies' models."""
    return [ts.seconds for b in bodies for ts in b.model.time_scales() if ts.kind == kind]


def choose_dt(bodies, contact, *, t_end, method="convolution") -> float:
    """A step (s) that resolves contact duration and restitution to about 0.1 %.

    (The restitution to about 1e-3 of the approach speed: where a dashpot's force jumps,
    at a contact's start, the modal solver's error is first order in the step, about
    ``0.5 dt c / m_eff`` of the restitution: 0.33 % of a critically damped pair's 0.135,
    1.7 % of a damping ratio of 5's 0.0093.)

    Each time scale gets its own number of steps: 1000 per rod transit time or beam
    ``1/omega_1`` (wave fronts are resolved only by the grid), 50 per ``1/omega`` of the
    fastest mode of a modal model (modes are discretised exactly) and of a
    ``HarmonicForce`` load, 300 per period scale of a compliant contact or of a residual
    flexibility against the bodies' masses, 10 per dashpot time ``m/c`` of a
    spring-dashpot contact, 30 per crossover of a rigid contact (where a body that is a
    mass at short times meets one that is not: ``2 M / Z`` for a mass on a rod of
    impedance ``Z``; :mod:`impactpred._time_scales`), 10 per width of a load pulse
    given as samples or a callable (it only ever shortens the step), one per sample of
    a measured response. With rods, the step
    divides every transit time when it can, so that wave reflections fall on grid points.

    The step of the time-stepping solvers (``"modal"``, ``"convolution"``) does not
    grow with ``t_end``: their accuracy depends on it; it is at most ``t_end / 200`` (but
    a measured response's sample). Where ``t_end`` would take more than
    4,000,000 such steps, :func:`solve_impact` coarsens it up to 20 times with a
    ``RuntimeWarning`` giving the numbers, and refuses (``ValueError``) beyond.

    The exact solvers are exact at any step: it only places their output samples.
    ``method="laplace"``: ``_LAPLACE_SAMPLES_PER_SCALE`` (8) per ``1/omega`` of the
    fastest time scale (about 50 per period) and at least 200 over ``t_end``; the first
    contact's exact peak is added. For both the samples are at most 4,000,000.

    Parameters
    ----------
    bodies : sequence of Body
        The bodies of the impact (their models' time scales decide).
    contact : ContactLaw
        The contact law (a compliant contact adds its own time scale).
    t_end : float, keyword-only
        End of the simulation (s).
    method : str, keyword-only
        The solver the step is for (see :data:`METHODS`); ``"auto"``: the one
        :func:`solve_impact` would choose for these bodies and contact. Default
        ``"convolution"``, unlike :func:`solve_impact`'s ``"auto"``: the step that resolves
        the bodies' physics (the time-stepping solvers'), which the exact solvers do not
        need.

    Returns
    -------
    float
        The time step (s).

    Raises
    ------
    ValueError
        ``method`` not one of :data:`METHODS`, or not possible for these bodies (as in
        :func:`solve_impact`); ``t_end`` not positive.
    TypeError
        ``bodies`` not a non-empty list of :class:`Body`, ``contact`` not a contact law.
    """
    as_choice("method", method, METHODS)
    t_end, contact = as_positive_scalar("t_end", t_end), check_contact(contact)
    if not isinstance(bodies, (list, tuple)) or not bodies:
        raise TypeError(f"bodies must be a non-empty list or tuple of impactpred.Body, "
                        f"got {bodies!r:.60}")
    for k, body in enumerate(bodies):
        if not isinstance(body, Body):
            raise TypeError(f"bodies[{k}] must be an impactpred.Body, got {type(body).__name__}")
    if method == "auto":
        method = _choose_method(tuple(bodies), contact, method)
    pairs = _scale_pairs(bodies, contact, t_end)
    # a load's pulse (samples or a callable) only ever shortens the step (load_time_scale)
    pulse = min((s for b in bodies if b.load is not None
                 and not isinstance(b.load, HarmonicForce)
                 for s in [load_time_scale(b, t_end)] if s is not None), default=np.inf)
    if not pairs:
        return min(t_end / 1000, pulse / LOAD_STEPS)
    if method == "laplace":
        return max(min(min(s for s, _ in pairs) / _LAPLACE_SAMPLES_PER_SCALE, t_end / 200),
                   t_end / _MAX_STEPS)
    sampled = _scales_of_kind(bodies, "sample")
    # ... and at least _MIN_RUN_STEPS over t_end: a t_end under one step had made a grid
    # of one step past it, on which the modal solver's bodies overlapped untouched
    dt = min(sampled) if sampled else min(min(s / n for s, n in pairs), t_end / _MIN_RUN_STEPS,
                                          pulse / LOAD_STEPS)
    rods = _scales_of_kind(bodies, "transit")
    if rods and not sampled:
        dt = _aligned_step(rods, dt)
    return max(dt, t_end / _MAX_STEPS) if method == "closed_form" else dt


def _scale_pairs(bodies, contact, t_end, *, samples=True) -> list:
    """``(time scale s, steps per scale)`` of the bodies, their harmonic loads and the
    contact (:func:`choose_dt`); without the records' samples if not ``samples``."""
    pairs = [p for b in bodies for p in _time_scales(b, samples=samples)]
    # a harmonic load is resolved like a mode: its 1/omega gets the modal steps
    pairs += [(1.0 / b.load.omega, _STEPS_BY_KIND["modal"]) for b in bodies
              if isinstance(b.load, HarmonicForce)]
    pairs += contact_time_scales(bodies, contact, shortest=min((s for s, _ in pairs),
                                                               default=t_end))
    return [(s, n) for s, n in pairs if s > 0 and math.isfinite(s)]


def _samples_too_coarse(bodies, contact, t_end, dt) -> str | None:
    """What to say when ``dt``, a sampled record's step, is over 3 times the step the
    other time scales ask for (:func:`choose_dt`): the contact is not resolved by the
    record. An undamped 1 kg spring-mass known by its impulse response at 10 kHz, struck
    by 1 kg through a 1e7 N/m spring, lost 45 % of the energy (restitution 0.64 for 1),
    the energy audit passing it. None when the record resolves it."""
    if not _scales_of_kind(bodies, "sample"):
        return None
    pairs = _scale_pairs(bodies, contact, t_end, samples=False)
    need = min((s / n for s, n in pairs), default=np.inf)
    if dt <= 3.0 * need:
        return None
    return (f"the step is the sampled record's, {dt:.4g} s: {dt / need:.0f} times the step "
            f"the contact and the bodies need ({need:.4g} s; their shortest time scale "
            f"{min(s for s, _ in pairs):.4g} s): the record does not resolve the contact, "
            "whose duration, restitution and energies may be off by several per cent or "
            "more (record the response faster, or use a model of the body)")


def _aligned_step(transit_times, dt):
    """The largest step <= ``dt`` dividing every transit time, else one dividing the shortest."""
    t_min = min(transit_times)
    n0 = math.ceil(t_min / dt - 1e-9)
    for n in range(n0, 4 * n0 + 1):
        ratios = [t * n / t_min for t in transit_times]
        if all(abs(r - round(r)) <= 1e-9 * r for r in ratios):
            return t_min / n
    return t_min / n0
