"""What a solved impact cannot vouch for, in words (for :func:`impactpred.solve_impact`).

Each sentence names a way the figures of an :class:`~impactpred.result.ImpactResult` are
not the impact's final or converged answer, with what would settle it:

* the last contact is still closed at ``t_end`` (no restitution);
* the bodies still approach after the last contact (restitution < 0: another contact
  follows after ``t_end``);
* the bodies never touched (no impact);
* a time-stepping run chatters at its grid's scale (contacts of one or two steps whose
  figures move when the run is repeated at half the step: the contact count and the
  figures depend on ``dt``), or its one or two contacts begin with one that short and
  moves (a light mass on an Euler-Bernoulli beam's tip, rigid contact). A model's
  instantaneous (Dirac) re-contacts also last a step, and do not move;
* a time-stepping run's sequence of re-contacts is not converged in ``dt`` (its figures
  move when the run is repeated at half the step: each contact starts from the error the
  last one left, and a sequence builds it up);
* the exact solver's sequence of re-contacts is sensitive to its inputs (its figures move
  when body 1's receptance is scaled by ``1 +- 1e-6``: a change no model or measurement
  resolves decides which later contacts happen);
* contacts shorter than a period of the models' fastest mode (a truncated modal model
  ringing under a rigid contact: chatter the structure it stands for would not show);
* a rigid contact's plastic (Dirac) impulses took a share of the energy because a
  truncated modal model is a mass at the contact: the structure it stands for, with its
  modes above the model's or their residual flexibility, is compliant there and loses
  none at the contact (a mass on a cantilever's 20 modes: 14 % lost, e -0.30; 40 modes:
  9 %; 80 modes: 6 %);
* over a quarter of a rigid contact's impulse passed within one period of a truncated
  modal model's top mode (a light mass on a rod's modes with their residual flexibility:
  the contact is decided by that flexibility and the top modes' inertia, and the
  restitution swings with the modes kept, one contact or many).

:func:`solve_impact` warns each sentence and keeps it in the result's notes.
"""

from __future__ import annotations

import numpy as np

from modalid import ModalModel

from .contact import Rigid

__all__ = ["MICRO_STEPS", "CHATTER_CHANGE", "PLASTIC_LOSS_SHARE", "SEQUENCE_CONTACTS",
           "SENSITIVITY_SCALE", "caveats", "is_sequence", "many_micro_contacts",
           "velocity_per_impulse"]

#: a contact of at most this many steps is not resolved by a time-stepping grid
MICRO_STEPS = 2
#: grid-scale chatter is suspected when at least this many contacts after the first are
#: micro contacts, and they are at least a quarter of them
_MIN_MICRO = 3
#: ... and said when, at half the step, a restitution moves by more than this (of the
#: approach speed), or the impulse by more than this share
CHATTER_CHANGE = 2e-3
#: a time-stepping run with at least this many contacts is repeated at half its step: a
#: sequence of re-contacts builds up the step's error (a 0.5 kg mass on a 10-mode
#: cantilever with its residual flexibility, rigid contact, 5 s: e 0.815 over 29 contacts at
#: the automatic step for the exact 0.694 over 25; the first contact's e to 1e-5)
SEQUENCE_CONTACTS = 3
#: an exact sequence of contacts is run again with body 1's receptance scaled by 1 +- this
#: (its mass and stiffness changed by a part in a million): figures that move by more than
#: :data:`CHATTER_CHANGE` are one outcome of a spread, not the inputs' answer (a 0.5 kg mass
#: at 1 m/s on a 10-mode cantilever with its residual flexibility, rigid contact: e 0.7006
#: over 53 contacts, 0.7064 and 0.6877 over 57 and 58; a change of 1e-9 moves it as far)
SENSITIVITY_SCALE = 1e-6
#: the share of the exchangeable energy (the audit's scale) a truncated model's plastic
#: impulses may take before it is said
PLASTIC_LOSS_SHARE = 1e-2
#: a flexibility term whose contact time is under this share of the top mode's period is
#: a stiffness the model holds, not its truncation (:func:`_unresolved_contacts`)
_STIFF_TERM = 0.2
#: a rigid contact is decided where a truncated modal model does not resolve it when more
#: than this share of the impact's impulse passes within one period of the model's top
#: mode after the first touch (:func:`_unresolved_impulse`; masses of 0.01-1 times a
#: fixed rod's on its 10-100 modes with their residual flexibility: shares of 0.10-0.19
#: left the whole sequence's restitution within 0.1-2.8 % of the rod's, 0.29 and over
#: 8-80 % off)
UNRESOLVED_SHARE = 0.25
#: a flexibility term under this share of the top mode's compliance is a stiffness the
#: model holds (a ball's table, 1 kg on 1e4 N/m through 1e-7 m/N: 1e-3), not the omitted
#: modes' static compliance (a fixed rod truncated at N modes: about N; a cantilever at 1
#: mode: 0.03, at 2: 0.19)
_HELD_STIFFNESS = 0.01
#: a restitution this close to 0 from below is round-off (two rigid masses in rigid
#: contact leave it at -6e-17: they move on together), not an approach
_ROUND_OFF = 1e-12


def caveats(result, bodies, *, t_end: float, start_gap: float, time_stepping: bool,
            finer=None, perturbed=(), contact=None,
            energy_scale: float = 0.0) -> tuple[str, ...]:
    """The sentences that apply to ``result`` (in the order above; empty if none).

    Parameters
    ----------
    result : ImpactResult
        The solved impact.
    bodies : pair of Body
        Its bodies (their velocities, loads and vibration, for the no-contact sentence).
    t_end : float
        End of the run (s).
    start_gap : float
        The contact points' distance (m) at ``t = 0``.
    time_stepping : bool
        Whether the solver steps on a grid (``"modal"``, ``"convolution"``), whose
        contacts may chatter at the grid's scale.
    finer : ImpactResult, optional
        The same run at half the step, made where :func:`many_micro_contacts` or
        :func:`is_sequence` holds: its figures tell chatter (they move) from Dirac
        re-contacts (they do not), and a sequence of contacts converged in ``dt`` from
        one that is not (a sequence whose
        half step exceeds the step limit: the run at twice the step; made at the
        automatic step only). Without it, many micro contacts are said as unverified and
        a sequence is not checked.
    perturbed : tuple of ImpactResult or str, optional
        An exact solver's sequence (:func:`is_sequence`) run again with body 1's
        receptance scaled by ``1 + SENSITIVITY_SCALE`` and ``1 - SENSITIVITY_SCALE``:
        figures that move are said (:func:`_sensitive_sequence`). Empty: not checked; a
        string: why it could not be (said).
    contact : ContactLaw, optional
        The contact law (the plastic-loss sentence is for ``Rigid`` contact only).
    energy_scale : float, optional
        The energy (J) the impact can redistribute (:attr:`EnergyAudit.scale`); 0: the
        plastic-loss sentence is not checked.

    Returns
    -------
    tuple of str
    """
    said = []
    if result.in_contact_at_end:
        said.append(f"the contact that began at {result.contact_intervals[-1][0]:.6g} s is "
                    f"still closed at t_end = {t_end:.6g} s: no restitution (None), and the "
                    "figures after it describe the bodies pressed together; a longer t_end "
                    "shows whether they separate")
    elif result.restitution is not None and (closing := _closing_at_end(result)):
        said.append(f"the bodies still approach after the last contact (ended at "
                    f"{result.contact_intervals[-1][1]:.6g} s): their rigid motion closes "
                    f"the gap at {closing:.6g} m/s at t_end (restitution "
                    f"{result.restitution:.4g}), so another contact follows after t_end = "
                    f"{t_end:.6g} s and the figures after the impact are not final; a "
                    "longer t_end reaches its end")
    if not result.touched:
        said.append(_no_contact(bodies, t_end, start_gap))
    if time_stepping and many_micro_contacts(result):
        chatter = _grid_chatter(result, finer)
        if chatter:
            said.append(chatter)
    elif time_stepping and is_sequence(result) and finer is not None:
        sequence = _sequence_moves(result, finer)
        if sequence:
            said.append(sequence)
    if isinstance(perturbed, str):
        said.append(f"the sequence of {result.n_contacts} contacts is not checked for its "
                    f"sensitivity to its inputs: {perturbed}")
    elif perturbed:
        sensitive = _sensitive_sequence(result, perturbed)
        if sensitive:
            said.append(sensitive)
    above = _restitution_above_one(result, bodies) if time_stepping else None
    if above:
        said.append(above)
    peaks = _sampled_later_peaks(result)
    if peaks:
        said.append(peaks)
    plastic = _plastic_truncation(result, bodies, contact, energy_scale)
    if plastic:
        said.append(plastic)
    unresolved = None if plastic else _unresolved_impulse(result, bodies, contact)
    if unresolved:
        said.append(unresolved)
    # (the plastic and the unresolved-impulse sentences speak of the truncation already;
    # the ringing one would point to the whole sequence's figures, which the latter denies)
    ringing = None if plastic or unresolved else _unresolved_contacts(result, bodies, contact)
    if ringing:
        said.append(ringing)
    return tuple(said)


#: a time-stepped restitution further above 1 than this is said (:func:`caveats`)
_ABOVE_ONE = 1e-6


def _restitution_above_one(result, bodies) -> str | None:
    """The sentence for a time-stepped restitution above 1 between bodies with no load
    and no vibration before the impact, where passive bodies give at most 1: the grid's
    error (Hertz between two free masses, exponent 0.3: 1.00014 by the modal solver,
    inside its energy tolerance, with no word)."""
    e = result.restitution
    quiet = all(b.load is None and b.vibration is None for b in bodies)
    if e is None or not quiet or e <= 1.0 + _ABOVE_ONE:
        return None
    return (f"the restitution {e:.6g} exceeds 1, which passive bodies without loads or "
            f"vibration before the impact cannot give: it is the time stepping's error at "
            f"dt = {result.dt:.4g} s (within its energy tolerance); a smaller dt brings it "
            "down")


#: a later contact of an exact run shorter than this many output steps has its force
#: peak said to be read from the samples (:func:`_sampled_later_peaks`; at 4 it was said
#: of ordinary runs, two spring-masses' rattling contacts of 3.9 samples over 0.5 s)
_PEAK_SAMPLES = 2


def _sampled_later_peaks(result) -> str | None:
    """The sentence for an exact run whose later contacts last under
    :data:`_PEAK_SAMPLES` output steps: only the first contact's force peak is found
    exactly, the others' are read from the samples (a rattling pair over 2000 s, contacts
    of 2.2e-4 s sampled every 5e-4 s: the history's largest force 27 % low, unsaid)."""
    if result.method != "laplace":
        return None
    later = [b - a for a, b in result.contact_intervals[1:] if b > a]
    if not later or min(later) >= _PEAK_SAMPLES * result.dt:
        return None
    return (f"later contacts last as little as {min(later):.3g} s, sampled every "
            f"{result.dt:.3g} s: their force peaks are read from the samples and may be "
            "understated (the largest force over the history with them); the first "
            "contact's peak is exact; a smaller dt samples them finer")


def velocity_per_impulse(model: ModalModel) -> float:
    """The contact point's velocity jump (m/s) per unit impulse (N s): ``h'(0+)``, exact.

    ``inverse_mass + sum 2 Re(r_k p_k) + sum a_j sigma_j`` (1/kg): finite where the model
    is a mass at the contact (``h(0+) = 0``, no flexibility term). A plastic impulse ``J``
    between two such bodies takes ``J^2 (c1 + c2) / 2`` (J) of energy.
    """
    c = model.inverse_mass + 2.0 * float(np.sum((model.residues * model.poles).real))
    return c + float(np.sum(model.real_residues * model.real_poles))


def _truncated(model) -> bool:
    """A modal model with modes and no residual flexibility: a mass at its driving point
    that stands for a structure compliant there."""
    return isinstance(model, ModalModel) and model.n_modes > 0 and model.flexibility == 0.0


def _plastic_truncation(result, bodies, contact, energy_scale) -> str | None:
    """The sentence on the energy a truncated model's plastic impulses took, if more than
    :data:`PLASTIC_LOSS_SHARE` of ``energy_scale``; else None.

    Exact for the model (method.md, section 5: undamped bodies lose energy at the Dirac
    parts only, ``J^2 (c1 + c2) / 2`` each, :func:`velocity_per_impulse`), but a property
    of its truncation: the loss shrinks as modes are added (a mass of 0.1 kg at 1 m/s on a
    cantilever's tip: 33 % at 5 modes, 14 % at 20, 9 % at 40, 6 % at 80), and the
    continuum loses none at a rigid contact.
    """
    if (type(contact) is not Rigid or not result.dirac_impulses or energy_scale <= 0.0
            or not all(body.is_rational for body in bodies)):
        return None
    which = [i for i, body in enumerate(bodies, 1) if _truncated(body.model)]
    if not which:
        return None
    per_impulse = sum(velocity_per_impulse(body.modal_model()) for body in bodies)
    lost = 0.5 * per_impulse * sum(j * j for _, j in result.dirac_impulses)
    share = lost / energy_scale
    if share <= PLASTIC_LOSS_SHARE:
        return None
    names = " and ".join(f"body {i}" for i in which)
    n = len(result.dirac_impulses)
    return (f"the rigid contact's {n} plastic (Dirac) impulse{'s' if n > 1 else ''} took "
            f"{100 * share:.3g} % of the energy the impact can redistribute ({lost:.4g} J): "
            f"{names}'s modal model, with no residual flexibility, is a mass at the "
            "contact; if it stands for a continuum, which is compliant there and loses no "
            "energy at a rigid contact, the figures depend on the modes kept (more modes, "
            "a residual flexibility term or a contact law with stiffness settle them); a "
            "lumped system's plastic impacts are its own")


def _unresolved_contacts(result, bodies, contact) -> str | None:
    """The sentence on contacts shorter than a period of the models' fastest mode, if at
    least :data:`_MIN_MICRO` and a quarter of the contacts are; else None.

    A finite modal model does not resolve what happens in less than a period of its top
    mode: under a rigid contact its top modes ring and the contact chatters at their scale
    (a 0.5 kg mass at 1 m/s on a fixed rod's 10
    modes with their residual flexibility: 10 contacts, the first 52 us long with a
    restitution of -0.64, for the rod's one contact of 512 us; at 30 modes 35 contacts, at
    60, 63; a cantilever's 20 modes: 24 contacts of 0.2-0.3 periods of its top mode).
    Rational bodies with modes only (a continuum's exact model has no top mode); not
    said beside the plastic-loss sentence, which names the truncation already.
    """
    if type(contact) is not Rigid or result.n_contacts < _MIN_MICRO:
        return None
    if not all(body.is_rational for body in bodies):
        return None
    models = [body.modal_model() for body in bodies]
    tops = [float(np.max(np.abs(m.poles.imag))) for m in models if m.n_modes > 0]
    if not tops:
        return None
    period = 2.0 * np.pi / max(tops)
    # a flexibility term against the masses at the contact closes it in half a period
    # pi sqrt(d / c); where that is far below the top mode's period it is a stiffness the
    # model holds, not its truncation (a ball on a spring-mass table through 1e-7 m/N:
    # contacts of 300 us, the table's period 63 ms), and the contacts are resolved; a
    # truncated model's residual flexibility rings at its top modes' scale (a fixed rod's
    # 10 modes: 19 us against 41 us)
    flexibility = sum(m.flexibility for m in models)
    per_impulse = sum(velocity_per_impulse(m) for m in models)
    if flexibility > 0 and per_impulse > 0 and (
            np.pi * np.sqrt(flexibility / per_impulse) < _STIFF_TERM * period):
        return None
    intervals = np.asarray(result.contact_intervals, dtype=float).reshape(-1, 2)
    short = int(np.count_nonzero(intervals[:, 1] - intervals[:, 0] < period))
    if short < _MIN_MICRO or 4 * short < len(intervals):
        return None
    top = max(tops) / (2 * np.pi)
    return (f"{short} of the {len(intervals)} contacts last less than one period of the "
            f"models' fastest mode ({top:.4g} Hz, {1 / top:.3g} s), which the models do "
            "not resolve: under a rigid contact a truncated modal model's top modes ring "
            "and the contact chatters at their scale, which the structure it stands for, "
            "with its higher modes, need not do. The first contact's figures "
            "(restitution_first, contact_duration_first) then describe one of those "
            "contacts, not the impact; the whole sequence's (restitution, total_impulse) "
            "are the ones to read, and more modes, a continuation above the band "
            "(impactpred.predict continues measured models) or a contact law with "
            "stiffness settle them")


def _residual_top_period(model) -> float | None:
    """The period (s) of the top mode of a modal model whose flexibility term is its
    omitted modes' static compliance (at least :data:`_HELD_STIFFNESS` of the top mode's
    compliance ``1 / (m_k omega_k^2)``), else None."""
    if not isinstance(model, ModalModel) or model.n_modes == 0 or not model.flexibility > 0:
        return None
    omega = np.abs(model.poles)
    top = int(np.argmax(omega))
    inverse_mass = -2.0 * model.poles[top].imag * model.residues[top].imag   # 1/m_k
    if not inverse_mass > 0 or model.flexibility * omega[top] ** 2 < (
            _HELD_STIFFNESS * inverse_mass):
        return None
    return float(2.0 * np.pi / omega[top])


def _unresolved_impulse(result, bodies, contact) -> str | None:
    """The sentence on a rigid contact decided within one period of a truncated modal
    model's top mode, if more than :data:`UNRESOLVED_SHARE` of the impulse passes in that
    time after the first touch; else None.

    What happens in less than a period of its top mode the model does not resolve: there
    it is its flexibility term, the omitted modes' static compliance (which those modes,
    pushed that fast, would not answer statically), ahead of its top modes' inertia. A
    light striker is stopped or thrown back in that time (a 5 g mass at 3 m/s on a 1 m
    steel rod, fixed, as 100, 200, 400, 800 modes with their residual flexibility: one
    contact each, restitutions 0.78, 0.60, 0.35, 0.03 for the rod's 0.736: a Newton's
    cradle once the modes' summed inverse masses reach the striker's), and the figures
    are the truncation's, the whole sequence's too.
    """
    if type(contact) is not Rigid or not result.touched or not result.impulse > 0:
        return None
    if not all(body.is_rational for body in bodies):
        return None
    periods = [(i, p) for i, body in enumerate(bodies, 1)
               if (p := _residual_top_period(body.modal_model())) is not None]
    if not periods:
        return None
    starts = [a for a, _ in result.contact_intervals[:1]] + [
        t for t, _ in result.dirac_impulses[:1]]
    t0 = min(starts)
    which, period = max(periods, key=lambda pair: pair[1])
    t, force = result.t, result.force
    inside = (t > t0) & (t < t0 + period)
    times = np.concatenate([[t0], t[inside], [t0 + period]])
    values = np.interp(times, t, force)
    values[1:-1] = force[inside]
    window = float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(times)))
    window += sum(j for tj, j in result.dirac_impulses if t0 <= tj <= t0 + period)
    share = window / result.impulse
    if share <= UNRESOLVED_SHARE:
        return None
    return (f"{100 * share:.3g} % of the impact's impulse passes within {period:.3g} s of "
            f"the first touch, one period of body {which}'s fastest mode "
            f"({1 / period:.4g} Hz), which its modal model does not resolve: a rigid contact "
            "that fast is decided by the model's flexibility term (the static compliance of "
            "the modes it omits, which would not answer statically) and its top modes' "
            "inertia, not by the structure it stands for, and the restitution and every "
            "figure after the impact depend on the modes kept (a 5 g mass on a steel rod's "
            "100 to 800 modes: 0.78 to 0.03, the rod's 0.736). More modes, until the "
            "impulse takes several of their periods, or a contact law with the contact's "
            "own stiffness settle them")


def _closing_at_end(result) -> float | None:
    """The speed (m/s) at which the bodies' rigid motion closes the gap at ``t_end`` after
    the last contact (at the velocities there: a load keeps changing them after the
    contact), or None where it does not."""
    u1, u2 = result.velocities_before
    w1, w2 = result.velocities_at_end or result.velocities_after
    return w1 - w2 if w1 - w2 > _ROUND_OFF * (u1 - u2) else None


def _no_contact(bodies, t_end, start_gap) -> str:
    closing = bodies[0].velocity - bodies[1].velocity
    said = (f"no contact by t_end = {t_end:.6g} s: the contact points start "
            f"{start_gap:.6g} m apart, the bodies closing at {closing:.6g} m/s")
    if closing > 0:
        meet = start_gap / closing                          # rigid motion alone
        said += f" (rigid motion alone would close the gap at t = {meet:.6g} s)"
        return said + ("; no impact to predict before a longer t_end" if meet > t_end else
                       ", yet their loads or vibration kept them apart: no impact to predict")
    if any(b.load is not None or b.vibration is not None for b in bodies):
        return said + (" and their loads or vibration did not close the gap: no impact to "
                       "predict before a longer t_end")
    return said + ("; they do not approach (+y points from body 1 to body 2): no impact to "
                   "predict")


def _micro_count(result) -> tuple[int, int]:
    """``(micro contacts after the first, contacts)`` of ``result``."""
    intervals = np.asarray(result.contact_intervals, dtype=float).reshape(-1, 2)
    steps = (intervals[1:, 1] - intervals[1:, 0]) / result.dt
    return int(np.count_nonzero(steps <= MICRO_STEPS + 1e-9)), len(intervals)


def many_micro_contacts(result) -> bool:
    """Whether at least :data:`_MIN_MICRO` contacts after the first, and a quarter of
    them, last at most :data:`MICRO_STEPS` steps (grid-scale chatter, or a model's Dirac
    re-contacts: a run at half the step tells them apart), or the run's only contacts
    (fewer than :data:`SEQUENCE_CONTACTS`) begin with one that short (:func:`_lone_micro`)."""
    return _chattering(result) or _lone_micro(result)


def _chattering(result) -> bool:
    """Whether at least :data:`_MIN_MICRO` contacts after the first, and a quarter of
    them, last at most :data:`MICRO_STEPS` steps."""
    micro, total = _micro_count(result)
    return micro >= _MIN_MICRO and micro >= 0.25 * (total - 1)


def _lone_micro(result) -> bool:
    """Whether a run of fewer than :data:`SEQUENCE_CONTACTS` contacts (not checked as a
    sequence) begins with a contact of at most :data:`MICRO_STEPS` steps: a 1 g mass at 1
    m/s on an exact cantilever's tip (rigid contact, a force singular as ``t^-1/2``)
    touched for one step and left at e = 0.776, 0.597 and 0.329 at steps of 2.8, 0.71 and
    0.18 us, silently; a Dirac impulse on a truncated model lasts a step too, and stays."""
    intervals = np.asarray(result.contact_intervals, dtype=float).reshape(-1, 2)
    if not 0 < len(intervals) < SEQUENCE_CONTACTS:
        return False
    return bool(intervals[0, 1] - intervals[0, 0] <= (MICRO_STEPS + 1e-9) * result.dt)


def is_sequence(result) -> bool:
    """Whether ``result`` has :data:`SEQUENCE_CONTACTS` contacts or more (a time-stepping
    one is repeated at another step to check them: :func:`_sequence_moves`)."""
    return result.n_contacts >= SEQUENCE_CONTACTS


def _sequence_moves(result, finer) -> str | None:
    """The sentence on a sequence of contacts whose figures move at ``finer``'s step
    (half the automatic one, or twice it at the step limit), else None.

    The automatic step resolves one contact's figures to about 0.1 %; over a sequence
    each contact starts from the error the last one left: a 0.5 kg mass at 1 m/s on a
    10-mode cantilever with its residual flexibility (rigid contact, 5 s) gives e 0.815 over
    29 contacts (``"modal"``) and 0.824 over 30 (``"convolution"``) for the exact 0.694
    over 25, the two solvers agreeing with each other; under a 1e4 N/m spring the
    convolution method's 0.773 (exact 0.759) moves to 0.768 at half the step.
    """
    head = f"the sequence of {result.n_contacts} contacts (dt = {result.dt:.4g} s)"
    changes = _moves(result, finer)
    if changes is None:
        return None
    other = "dt / 2" if finer.dt < result.dt else "2 dt"
    return (f"{head} is not converged in dt: at {other} its figures move ({changes}, "
            f"{finer.n_contacts} contacts); each contact starts from the error the last one "
            "left, so the figures after the first contact depend on dt: refine dt until "
            "they settle, or use method='laplace' where the models are rational (exact)")


def _sensitive_sequence(result, perturbed) -> str | None:
    """The sentence on an exact sequence of contacts whose figures move in the runs
    ``perturbed`` (body 1's receptance scaled by ``1 +- SENSITIVITY_SCALE``), else None.

    Each contact starts from the state the last one left, and where a contact is a near
    graze a change too small to measure decides whether it happens: the 53 contacts of a
    0.5 kg mass on a 10-mode cantilever with its residual flexibility (rigid, 1 m/s) end at
    e 0.7006, and at 0.7064 and 0.6877 with the mass changed by a part in a million.
    """
    changes = _figure_changes(result, perturbed)
    if not changes:
        return None
    counts = " / ".join(str(other.n_contacts) for other in perturbed)
    said = (f"the sequence of {result.n_contacts} contacts is sensitive to its inputs: with "
            f"body 1's receptance scaled by 1 +- {SENSITIVITY_SCALE:g} (its mass and "
            "stiffness changed by less than any model or measurement resolves) its figures "
            f"move ({', '.join(changes)}; {counts} contacts): each contact starts from the "
            "state the last one left, so the figures after the first contacts are one "
            "outcome of a spread at least this wide, not a converged answer")
    first = result.restitution_first
    if first is not None and not any(c.startswith("restitution_first") for c in changes):
        said += f" (the first contact's restitution, {first:.4g}, holds)"
    return said


def _figure_changes(result, others) -> list[str]:
    """The figures (restitutions, impulse) that move from ``result`` to any of ``others``
    by more than :data:`CHATTER_CHANGE`, as ``"name a -> b1 / b2"``."""
    def text(value):
        return "None" if value is None else f"{value:.4g}"

    changes = []
    for name in ("restitution", "restitution_first"):
        a, bs = getattr(result, name), [getattr(other, name) for other in others]
        if a is None and all(b is None for b in bs):
            continue
        # one in contact at its end (None) and another not is a change too
        if any(b is None or a is None or abs(a - b) > CHATTER_CHANGE for b in bs):
            changes.append(f"{name} {text(a)} -> {' / '.join(text(b) for b in bs)}")
    a, bs = result.impulse, [other.impulse for other in others]
    scale = max(abs(a), *(abs(b) for b in bs), 1e-300)
    if any(abs(a - b) > CHATTER_CHANGE * scale for b in bs):
        changes.append(f"impulse {a:.4g} -> {' / '.join(f'{b:.4g}' for b in bs)} N s")
    return changes


def _moves(result, finer) -> str | None:
    """How the figures move from ``result`` to ``finer``, if beyond
    :data:`CHATTER_CHANGE`; else None."""
    return ", ".join(_figure_changes(result, [finer])) or None


def _grid_chatter(result, finer) -> str | None:
    """The sentence on many micro contacts whose figures move at half the step (or that
    could not be checked), else None.

    Such contacts are the grid's, not the model's: a mass dropped at 2 m/s on a steel
    cantilever's tip (an Euler-Bernoulli beam, rigid contact) makes 19, 48 and 179
    contacts over 20 ms at steps of 4.8, 1 and 0.1 us, most of one or two steps, and a
    restitution of 0.45, 0.46 and 0.33: no converged answer, since the beam has no
    high-frequency limit and the contact no stiffness. A mass on a fixed rod's 20 modes
    without flexibility (rigid contact) re-contacts instantaneously too, Diracs of a step
    each, and its restitution stays within 2e-4 at half the step: nothing to say.
    """
    micro, total = _micro_count(result)
    lone = _lone_micro(result) and not _chattering(result)
    head = (f"the first contact lasts at most {MICRO_STEPS} steps" if lone else
            f"{micro} of the {total} contacts last at most {MICRO_STEPS} steps")
    head += f" (dt = {result.dt:.4g} s)"
    if finer is None:
        moved = "the run could not be repeated at dt / 2 within the step limit to check"
    else:
        changes = _moves(result, finer)
        if changes is None:
            return None
        moved = (f"at dt / 2 {'its figures move' if lone else 'they move'} ({changes}, "
                 f"{finer.n_contacts} contacts)")
    what = ("the contact is shorter than the grid resolves, so" if lone else
            "the contact chatters at the grid's scale, so the count of contacts,")
    return (f"{head}, and {moved}: {what} the restitution and the first contact's figures "
            "depend on dt; a rigid contact on a model without a high-frequency limit (an "
            "Euler-Bernoulli beam's tip) has no converged answer: give the contact a "
            "stiffness (Hertz, a spring), or refine dt")
