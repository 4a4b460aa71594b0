"""Closed form for two free-free rods of equal transit time (method.md, section 3a).

The force is a rectangular pulse of width ``2T`` and height ``v12 m1 m2 / ((m1 + m2) T)``;
both ends move at the centre-of-mass velocity during contact; afterwards the rigid
velocities are those of a perfectly elastic collision and no vibration is left (e = 1).
"""

from __future__ import annotations

import numpy as np

from ..result import BodyEnergy, ImpactResult

__all__ = ["applies_closed_form", "solve_closed_form"]


def applies_closed_form(bodies, contact) -> bool:
    """True for two free rods with equal transit time, rigid contact, rigid motion only."""
    from data_synth import Rod

    from ..contact import Rigid

    if not isinstance(contact, Rigid):
        return False
    if not all(isinstance(b.model, Rod) and b.model.support == "free" for b in bodies):
        return False
    if any(b.vibration is not None or b.load is not None for b in bodies):
        return False
    t1, t2 = (b.model.transit_time for b in bodies)
    return abs(t1 - t2) <= 1e-12 * max(t1, t2)


def solve_closed_form(bodies, gap0, contact, t_end, dt, *, notes=()):
    """Exact solution on an output grid of step ``dt`` with the event times inserted."""
    b1, b2 = bodies
    m1, m2 = b1.model.mass, b2.model.mass
    T = b1.model.transit_time
    u1, u2 = b1.velocity, b2.velocity
    v12 = u1 - u2
    M = m1 + m2
    inv = (1.0 / m1, 1.0 / m2)
    rigid_before = (0.5 * m1 * u1**2, 0.5 * m2 * u2**2)
    if dt is None:
        dt = T / 100.0
    grid = np.arange(0.0, t_end + 0.5 * dt, dt)
    grid = grid[grid <= t_end]
    free_gap0 = gap0 + b2.displacement - b1.displacement
    t_contact = free_gap0 / v12 if v12 > 0 else np.inf
    if t_contact > t_end:
        t = grid
        y1, y2 = b1.displacement + u1 * t, b2.displacement + u2 * t
        energy = tuple(BodyEnergy(e, 0.0, e, 0.0) for e in rigid_before)
        return ImpactResult(t=t, force=np.zeros_like(t), y1=y1, y2=y2, gap=y2 - y1 + gap0,
                            contact_intervals=(), dirac_impulses=(),
                            velocities_before=(u1, u2), velocities_after=(u1, u2),
                            energy_by_body=energy, method="closed_form", dt=dt,
                            first_contact_impulse=0.0, total_impulse=0.0,
                            inverse_masses=inv, notes=tuple(notes))
    t_sep = t_contact + 2 * T
    events = [x for x in (t_contact, t_sep) if x <= t_end]
    t = np.unique(np.concatenate([grid, events]))
    height = v12 * m1 * m2 / (M * T)
    during = (t >= t_contact) & (t < t_sep)
    force = np.where(during, height, 0.0)
    p = m1 * u1 + m2 * u2
    tau = t - t_contact  # time since contact
    y_c1 = b1.displacement + u1 * t_contact  # positions at first touch
    y_c2 = b2.displacement + u2 * t_contact
    after = tau >= 2 * T
    y1 = np.where(tau < 0, b1.displacement + u1 * t,
                  y_c1 + (p * tau - np.where(after, v12 * m2 * (tau - 2 * T), 0.0)) / M)
    y2 = np.where(tau < 0, b2.displacement + u2 * t,
                  y_c2 + (p * tau + np.where(after, v12 * m1 * (tau - 2 * T), 0.0)) / M)
    impulse = height * 2 * T
    separated = t_sep <= t_end
    intervals = ((t_contact, t_sep if separated else t_end),)
    total = impulse if separated else height * (t_end - t_contact)
    ua = (u1 - total / m1, u2 + total / m2)
    # The contact end moves at the centre-of-mass velocity while the force acts, so the
    # force's work on rod 2 is F v_cm (duration) and minus that on rod 1.
    v_cm = p / M
    work = (-total * v_cm, total * v_cm)
    masses = (m1, m2)
    energy = tuple(BodyEnergy(rigid_before[i], 0.0, 0.5 * masses[i] * ua[i] ** 2,
                              rigid_before[i] + work[i] - 0.5 * masses[i] * ua[i] ** 2)
                   for i in range(2))
    return ImpactResult(t=t, force=force, y1=y1, y2=y2, gap=y2 - y1 + gap0,
                        contact_intervals=intervals, dirac_impulses=(),
                        velocities_before=(u1, u2), velocities_after=ua,
                        energy_by_body=energy, method="closed_form", dt=dt,
                        first_contact_impulse=total, total_impulse=total,
                        inverse_masses=inv, notes=tuple(notes))

