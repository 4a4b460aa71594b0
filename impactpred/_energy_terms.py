"""The terms of :func:`impactpred.api.energy_audit`'s balance: the work of the bodies'
loads, what a dashpot contact dissipated, what a compliant contact still stores at
``t_end``, and the energy an impact can redistribute (the audit's scale)."""

from __future__ import annotations

import math

import numpy as np

from .contact import Hertz, LinearSpring
from .damper.excitation import HarmonicForce
from .solvers.modal import FIRST_ORDER_NOTE

__all__ = ["load_work", "dashpot_dissipation", "contact_energy", "exchangeable_energy"]


#: Gauss-Legendre nodes on [0, 1] and weights for the load work's Hermite quadrature
_GAUSS_X, _GAUSS_WX = np.polynomial.legendre.leggauss(4)
_GAUSS_S, _GAUSS_W = 0.5 * (_GAUSS_X + 1.0), 0.5 * _GAUSS_WX


def load_work(result, bodies, *, coarse=False) -> tuple[float, float]:
    """Work (J) of the bodies' external loads along their contact points' motion, and an
    estimate of its quadrature error (J).

    With the contact points' velocities (the exact solver's ``v1``, ``v2``): the
    displacement as the cubic Hermite interpolant of each sample interval, its rate times
    the load integrated by 4-point Gauss-Legendre (error O(dt^4); a velocity jump at an
    event is sampled on both sides, its zero-length interval adds nothing); its error
    bounded by the change when the same sum runs over every other sample (events kept),
    ``|W(dt) - W(2 dt)|`` (Richardson's ``/15`` holds only once the step resolves the
    load and the modes: at 9 samples per load period the error was 6 times that), and,
    with ``coarse`` (an output step coarser than the exact method's automatic one) or no
    sample to leave out, by the change from the midpoint rule if larger; infinite (no
    check) where a coarse step leaves under two samples per period of the load. The exact
    solver is exact at any output step, its work integral is not: the bound widens the
    audit's tolerance instead of flagging a coarse step's quadrature as energy created.
    Otherwise the load at the interval's midpoint times the displacement step (O(dt^2),
    within the time-stepping solvers' own error; no estimate).
    """
    work = error = 0.0
    t = result.t
    for body, y, v in zip(bodies, (result.y1, result.y2), (result.v1, result.v2)):
        if body.load is None:
            continue
        if v is None:
            work += _midpoint_work(body, t, y)
            continue
        fine = _hermite_work(body, t, y, v)
        work += fine
        if coarse and isinstance(body.load, HarmonicForce) and (
                float(np.max(np.diff(t))) * body.load.omega > np.pi):
            error = math.inf                             # under two samples a period
            continue
        # every other sample, both sides of each event (a zero-length interval) kept
        event = np.zeros(t.size, bool)
        event[:-1] |= t[1:] == t[:-1]
        event[1:] |= t[1:] == t[:-1]
        keep = event | (np.arange(t.size) % 2 == 0)
        keep[[0, -1]] = True
        half = abs(fine - _hermite_work(body, t[keep], y[keep], v[keep]))
        # no sample to leave out, or a step coarser than the exact method's own: the
        # midpoint rule's difference too (the step-halving one can be several times short)
        error += (max(half, abs(fine - _midpoint_work(body, t, y)))
                  if coarse or keep.all() else half)
    return work, error


def _midpoint_work(body, t, y) -> float:
    """``integral load dy`` (J): the load at each sample interval's midpoint times the
    displacement step (O(dt^2))."""
    return float(np.dot(body.load_samples(0.5 * (t[1:] + t[:-1])), np.diff(y)))


def _hermite_work(body, t, y, v) -> float:
    """``integral load(t) y'(t) dt`` (J) with ``y`` the cubic Hermite interpolant of the
    samples ``(t, y, v)``, by 4-point Gauss-Legendre on each interval."""
    h = np.diff(t)
    s = _GAUSS_S[None, :]
    # d/dt of the interpolant, times h, at the Gauss nodes
    rate_h = ((6 * s**2 - 6 * s) * (y[:-1] - y[1:])[:, None]
              + (3 * s**2 - 4 * s + 1) * (v[:-1] * h)[:, None]
              + (3 * s**2 - 2 * s) * (v[1:] * h)[:, None])
    load = body.load_samples(t[:-1, None] + s * h[:, None])
    return float(np.sum(load * rate_h * _GAUSS_W[None, :]))


def dashpot_dissipation(result, contact) -> float:
    """Energy (J) a spring-dashpot contact took: its dashpot's ``c`` times the integral
    of the penetration rate squared while the force acts, plus the spring energy left
    behind where the force is clipped at 0 (the dashpot would pull) with the bodies
    still overlapping. From the force and gap histories, not from the force's work.

    The rate as each solver's contact law holds it: a zero-order hold's force is constant
    over a step and meets the law with the step's mean rate, ``(d_{n+1} - d_n)/dt``, which
    gives the dashpot ``c (d_{n+1} - d_n)^2 / dt`` a step (exact for the stepped
    solution); the modal solver's first-order hold meets it at the grid times with the
    exact rate, ``d' = (f - k d)/c`` (:func:`_node_dissipation`).
    """
    if not isinstance(contact, LinearSpring) or contact.damping == 0.0:
        return 0.0
    depth = np.maximum(-result.gap, 0.0)
    if result.method == "modal" and FIRST_ORDER_NOTE in result.notes:
        return _node_dissipation(result, contact, depth)
    step = np.diff(depth)
    acting = result.force[:-1] > 0.0
    dashpot = contact.damping * float(np.sum(step[acting] ** 2 / np.diff(result.t)[acting]))
    spring = 0.5 * contact.stiffness * depth**2
    released = np.maximum(spring[:-1] - spring[1:], 0.0)
    return dashpot + float(np.sum(released[~acting]))


def _node_dissipation(result, contact, depth) -> float:
    """:func:`dashpot_dissipation` of a first-order-hold run: ``c`` times the trapezoidal
    integral of ``d'^2`` over each contact interval, ``d' = (f - k d)/c`` at its grid times
    and at its located ends (where the force is 0: at the start ``d = 0``, at the
    separation ``d' = -k d/c``), plus the spring energy ``k d^2/2`` left at each separation
    (as much of it as the overlap has released by the next contact or ``t_end``).

    Second order in the step. The grid samples alone (the rate of a step as its secant)
    had left out the dashpot's force jump at each start and the rate's curvature:
    5-9 % short for two masses through ``c = 1e3`` and ``1e6`` N s/m.
    """
    k, c = contact.stiffness, contact.damping
    t, force = result.t, result.force
    intervals = result.contact_intervals
    total = 0.0
    for n, (start, end) in enumerate(intervals):
        inside = (t > start) & (t < end)
        closed = result.in_contact_at_end and n == len(intervals) - 1
        times = np.concatenate([[start], t[inside], [end]])
        d = np.concatenate([[np.interp(start, t, depth)], depth[inside],
                            [np.interp(end, t, depth)]])
        f = np.concatenate([[0.0], force[inside], [force[-1] if closed else 0.0]])
        rate = (f - k * d) / c
        total += c * float(np.sum(0.5 * (rate[1:] ** 2 + rate[:-1] ** 2) * np.diff(times)))
        if not closed:      # released by the next start or t_end (the rest is ``stored``)
            later = np.interp(intervals[n + 1][0], t, depth) if n + 1 < len(intervals) \
                else depth[-1]
            total += 0.5 * k * max(d[-1] ** 2 - later**2, 0.0)
    return total


def contact_energy(contact, gap_end: float) -> float:
    """Elastic energy (J) of a compliant contact at penetration ``-gap_end`` (m)."""
    depth = max(-gap_end, 0.0)
    if isinstance(contact, LinearSpring):
        return 0.5 * contact.stiffness * depth**2
    if isinstance(contact, Hertz):
        return contact.stiffness * depth ** (contact.exponent + 1) / (contact.exponent + 1)
    return 0.0


def exchangeable_energy(bodies, before: float, load_work: float) -> float:
    """Energy (J) an impact can redistribute: ``before`` less the centre of mass's kinetic
    energy when both bodies are free and unloaded, plus ``|load_work|``."""
    inv = [b.inverse_mass for b in bodies]
    if all(i > 0.0 for i in inv) and all(b.load is None for b in bodies):
        mass = 1.0 / inv[0] + 1.0 / inv[1]
        momentum = bodies[0].velocity / inv[0] + bodies[1].velocity / inv[1]
        before -= 0.5 * momentum * (momentum / mass)     # no overflow at huge masses
    return max(before, 0.0) + abs(load_work)
