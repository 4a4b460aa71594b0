"""Time scales of an impact beyond each body's own, for :func:`impactpred.choose_dt`: what
the contact law and the bodies make of each other, and the loads given as samples or
callables (:func:`load_time_scale`).

* A compliant contact: ``sqrt(m_eff / k)`` of its stiffness (a spring's; Hertz's at its
  peak) and a dashpot's ``m_eff / c``, ``m_eff`` from the bodies' high-frequency inverse
  masses.
* A rigid contact: ``sqrt(m_eff f)`` of the bodies' residual flexibility ``f``, and the
  **crossover** of the two bodies' step responses (:func:`rigid_crossover`): where a body
  that acts as a mass at short times (step response ``t^2 / 2m``) meets one that does not
  (a rod's ``t / Z``: a dashpot of its impedance ``Z``), the contact force changes regime
  at the time the two are equal, ``2 m / Z`` for a mass on a rod, however short the
  bodies' own scales are. A 5 g pellet at 3 m/s on a 1 m steel rod (``Z`` = 40 kN s/m,
  crossover 0.25 us) was stepped at the rod's 1000 steps per transit (0.2 us): restitution
  0.985 for the exact 0.7358 (Saint-Venant), silently; at 30 steps per crossover 0.7363.
  Not for a beam (slope 1.5 between a mass's 2 and a rod's 1, :data:`_SLOPE_CHANGE`): a
  light mass on ``CantileverBeam`` is stepped at the beam's own scale, and its figures
  depend on the step (a 0.1 kg mass on a 4.76 kg cantilever: a first contact of one step
  and restitution_first -0.45 / -0.69 / -0.38 at 0.75, 0.18 and 0.044 ms): the force is
  singular there (``t^-1/2``), no step resolves it, and :mod:`impactpred._caveats` says
  so where the figures move at half the step.
"""

from __future__ import annotations

import math

import numpy as np

from .body import SampledResponse
from .contact import Hertz, LinearSpring

__all__ = ["contact_time_scales", "rigid_crossover", "load_time_scale", "expected_error",
           "CROSSOVER_STEPS", "DASHPOT_STEPS", "LOAD_STEPS", "SAID_ERROR"]

#: steps per dashpot time ``m_eff / c`` of a spring-dashpot contact: a step longer than
#: it lets the clipped dashpot act a whole step at once (two masses, ``c = 10 sqrt(k m)``:
#: restitution 0.33 / 0.67 (modal / convolution) for the exact 5e-7 at 10 such times a
#: step, 0.1 / 0.2 at 3); at a tenth of it the modal solver is within 3e-4 of it
DASHPOT_STEPS = 10
#: steps per crossover time of a rigid contact (:func:`rigid_crossover`): the pellet on
#: the rod (module docstring) within 0.07 % of its exact restitution at 15 and 30, 1 % at
#: 8, 0.014 % at 60
CROSSOVER_STEPS = 30
#: the step responses are compared over this many decades below the shortest own scale
_CROSSOVER_DECADES = 6
#: a crossing counts where the two step responses' log-log slopes differ by this much (a
#: change of regime: 2 for a mass, 1 for a rod, 0 for a flexibility), not where two
#: responses of one kind differ by a little (two flexibilities: a crossing anywhere). A
#: beam's 1.5 stands exactly 0.5 from a mass's and a rod's: at a threshold of 0.5 rounding
#: decided (a 1 g mass on a cantilever: none, 10 g: found, 100 g: none); at 0.75 beams
#: are left to their own scales, as before the rule (a light mass on a beam: see the
#: module docstring)
_SLOPE_CHANGE = 0.75


def effective_inverse_mass(body) -> float:
    """High-frequency ``1/m`` seen at the contact point (1/kg); 0 for a pure compliance."""
    model = body.model
    try:
        modal = model.modal_form(20)
    except ValueError:      # no pole-residue form (a sampled record): no modes to read
        return 0.0
    inverse_masses = -2.0 * modal.poles.imag * modal.residues.imag   # 1/modal_mass
    return modal.inverse_mass + float(np.sum(inverse_masses[inverse_masses > 0]))


def rigid_crossover(bodies, shortest: float):
    """The time (s) at which the two bodies' step responses cross where their regimes
    differ (log-log slopes :data:`_SLOPE_CHANGE` or more apart), searched over
    :data:`_CROSSOVER_DECADES` decades up to ``shortest`` (s); None where they do not, or
    for a sampled record (its step is its sampling's).

    Under a rigid contact the force follows the more compliant body first: a mass on a
    rod starts at ``Z v`` (the rod's impedance) and falls off as the mass's compliance
    ``t^2 / 2m`` overtakes the rod's ``t / Z``, at ``t = 2 m / Z``.
    """
    if len(bodies) != 2 or any(isinstance(b.model, SampledResponse) for b in bodies):
        return None
    t = np.geomspace(10.0 ** -_CROSSOVER_DECADES * shortest, shortest, 12 * _CROSSOVER_DECADES
                     + 1)
    s1, s2 = (np.asarray(b.model.step_response(t), float) for b in bodies)
    usable = (s1 > 0) & (s2 > 0) & np.isfinite(s1) & np.isfinite(s2)
    if usable.sum() < 3:
        return None
    t, s1, s2 = t[usable], s1[usable], s2[usable]
    d = np.log(s1) - np.log(s2)
    slope = np.gradient(d, np.log(t))           # difference of the two log-log slopes
    cross = np.flatnonzero((np.sign(d[:-1]) * np.sign(d[1:]) < 0)
                           & (np.abs(slope[:-1] + slope[1:]) >= 2 * _SLOPE_CHANGE))
    if not cross.size:
        return None
    k = int(cross[0])
    # log-linear interpolation of the crossing between the two samples
    share = d[k] / (d[k] - d[k + 1])
    return float(np.exp(np.log(t[k]) + share * (np.log(t[k + 1]) - np.log(t[k]))))


def contact_time_scales(bodies, contact, *, shortest: float) -> list:
    """``(time scale, steps per scale)`` pairs of the contact (module docstring):
    ``sqrt(m_eff/k)`` of the stiffness that closes it (300 steps), a dashpot's
    ``m_eff/c`` (:data:`DASHPOT_STEPS`), and for a rigid contact the bodies' crossover
    (:func:`rigid_crossover` below ``shortest``, s: the shortest of the bodies' own scales
    and their harmonic loads'; :data:`CROSSOVER_STEPS`).

    The stiffness is the contact's own (spring; Hertz at its peak) or, for rigid contact,
    that of the bodies' residual flexibility; ``m_eff`` comes from the bodies'
    high-frequency inverse masses.
    """
    pairs = []
    if not isinstance(contact, (LinearSpring, Hertz)) and not contact.is_impulsive:
        crossover = rigid_crossover(bodies, shortest)
        if crossover is not None:
            pairs.append((crossover, CROSSOVER_STEPS))
    inv = sum(effective_inverse_mass(b) for b in bodies)
    if inv <= 0:
        return pairs
    m_eff = 1.0 / inv
    if isinstance(contact, LinearSpring):
        pairs = [(math.sqrt(m_eff / contact.stiffness), 300)]
        if contact.damping > 0:
            pairs.append((m_eff / contact.damping, DASHPOT_STEPS))
        return pairs
    if isinstance(contact, Hertz):
        v = abs(bodies[0].velocity - bodies[1].velocity) or 1.0
        depth = (5 * m_eff * v**2 / (4 * contact.stiffness)) ** (1 / (contact.exponent + 1))
        return [(depth / v, 300)]
    # rounding-level flexibilities (e.g. left by a continuation) are no compliance
    rational = [b.model.modal_form() for b in bodies if b.model.is_rational]
    flex = sum(m.flexibility for m in rational
               if m.flexibility > 1e-9 * abs(m.static_flexibility()))
    if flex > 0:
        pairs.append((math.sqrt(m_eff * flex), 300))
    return pairs


#: steps per time scale of a load given as samples or a callable (:func:`load_time_scale`)
LOAD_STEPS = 10
#: a callable load is read at this many points over ``t_end`` for its time scale
_LOAD_PROBE = 100_001


def load_time_scale(body, t_end) -> float | None:
    """The width (s) of a body's strongest load pulse (samples or a callable): the time
    around its largest ``|f|`` that ``|f|`` stays at half of it or more, read on the load's
    own samples, linear between them (a callable on :data:`_LOAD_PROBE` points over
    ``t_end``); None where that lasts to the record's or the run's end (a load switched
    on: a jump needs no step of its own, its impulse is off by at most half a step's) or
    is not resolved by the probe. A 1000 N tap 0.1 ms wide (a triangle, 0.05 N s) on a
    1 kg mass at rest was missed by the modal solver's step of 0.24 ms (no contact,
    "their loads did not close the gap") and taken as 0.082 N s by the convolution's;
    noise on a measured load does not shorten it (a slope would)."""
    knots = getattr(body.load, "t", None)
    t = (np.asarray(knots, float) if knots is not None
         else np.linspace(0.0, t_end, _LOAD_PROBE))
    f = np.abs(body.load_samples(t))
    k = int(np.argmax(f)) if f.size else 0
    if f.size < 2 or not f[k] > 0:
        return None
    half = 0.5 * f[k]
    below = np.flatnonzero(f < half)
    left, right = below[below < k], below[below > k]
    if not left.size or not right.size:         # on to an end: a jump, or a long load
        return None
    i, j = int(left[-1]), int(right[0])         # the last line below, either side
    if knots is None and j - i <= 2:            # within the probe's own resolution
        return None

    def crossing(a, b):                         # where |f| passes half, between a and b
        return t[a] + (half - f[a]) / (f[b] - f[a]) * (t[b] - t[a])

    return float(crossing(j, j - 1) - crossing(i, i + 1))


#: a time-stepping run's restitution error (% of the approach speed) per unit of
#: ``dt / choose_dt``, first order in the step, as measured at 1-20 units (a bound). A
#: zero-order hold (the convolution solver; the modal one where its first-order hold does
#: not apply) loses 0.24-0.32 % a unit on two masses through a linear spring, a
#: spring-dashpot or Hertz contact (exponents 0.3, 0.5, 1.5) and on a mass striking a
#: spring-mass's flexibility (rigid contact), 0.11 % on a Hertz ball on a rod, up to
#: 0.03 % a mass on a rod (rigid); the modal first-order hold at most 0.05 % (a
#: dashpot's force jump at a contact's start), under 0.003 % otherwise. The energies'
#: errors are about twice the restitution's (a share ``1 - e^2`` of them).
_ERROR_PER_STEP = {False: 0.32, True: 0.1}
#: a step given coarser than the one that resolves the bodies is warned of where the
#: energies' expected error (twice :func:`expected_error`) passes this (%); the automatic
#: step and finer never are
SAID_ERROR = 1.0


def expected_error(first_order: bool, ratio: float) -> float:
    """The restitution error (% of the approach speed) to expect at ``ratio`` times the
    step :func:`impactpred.api.choose_dt` gives, first order in the step
    (:data:`_ERROR_PER_STEP`): 0.32 % a unit for a zero-order hold (``"convolution"``),
    0.1 % for the modal solver's first-order hold (``first_order``); the energies' error
    is about twice that share of them."""
    return _ERROR_PER_STEP[bool(first_order)] * ratio
