"""A loaded body's rigid-body velocities at the impact's ends, not at ``t = 0`` and ``t_end``.

A load moves a free body's rigid-body velocity all the time (by ``1/M`` times its
impulse), before, during and after the contacts: the velocities the restitution compares
are read where the impact starts (the first contact's start) and ends (the last
contact's end), and the first contact's restitution counts the load's impulse during
that contact with the contact's own. :func:`at_contacts` does this for every solver's
result; without a load on a free body it returns the result unchanged.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .damper.excitation import HarmonicForce

__all__ = ["at_contacts", "load_impulse"]

#: least points of the trapezoid rule over an interval of a callable load
_MIN_POINTS = 33


def load_impulse(load, a, b, grid) -> float:
    """``int_a^b load(t) dt`` (N s) for ``a <= b`` (s).

    A :class:`HarmonicForce` in closed form; samples (``Body(load=(t, f))``) exactly, as
    the piecewise-linear load they are; any other callable by the trapezoid rule on the
    solver's own time ``grid`` (s) inside ``[a, b]`` (at least ``_MIN_POINTS`` points),
    the grid the time-stepping solvers apply the load on (one vectorised call).
    """
    if b <= a or load is None:
        return 0.0
    if isinstance(load, HarmonicForce):
        w, phi = load.omega, load.phase
        return load.amplitude / w * (math.sin(w * b + phi) - math.sin(w * a + phi))
    if hasattr(load, "impulse"):
        return float(load.impulse(a, b))
    inside = grid[(grid > a) & (grid < b)]
    if inside.size < _MIN_POINTS:
        inside = np.linspace(a, b, _MIN_POINTS)[1:-1]
    knots = np.concatenate([[a], inside, [b]])
    return float(np.trapezoid(np.asarray(load(knots), dtype=float).reshape(-1), knots))


def at_contacts(result, bodies):
    """``result`` with its loaded free bodies' velocities read at the impact's ends.

    ``velocities_before``: at the first contact's start; ``velocities_after``: at the last
    contact's end (the load's impulse after it taken back from the final velocity),
    ``velocities_at_end``: the final ones; ``first_contact_load_impulse``: each load's
    impulse (N s) during the first contact. Unchanged where no free body carries a load,
    or the bodies never touched.
    """
    inv = result.inverse_masses
    loaded = [b.load is not None and m != 0.0 for b, m in zip(bodies, inv)]
    if not any(loaded) or not result.contact_intervals:
        return result
    t_start, t_first_end = result.contact_intervals[0]
    t_last_end = result.contact_intervals[-1][1]
    grid = np.asarray(result.t, dtype=float)
    t_final = float(grid[-1])
    loads = [b.load if on else None for b, on in zip(bodies, loaded)]
    before = tuple(u + m * load_impulse(f, 0.0, t_start, grid)
                   for u, m, f in zip(result.velocities_before, inv, loads))
    after = tuple(u - m * load_impulse(f, t_last_end, t_final, grid)
                  for u, m, f in zip(result.velocities_after, inv, loads))
    during = tuple(load_impulse(f, t_start, t_first_end, grid) for f in loads)
    return dataclasses.replace(result, velocities_before=before, velocities_after=after,
                               velocities_at_end=result.velocities_after,
                               first_contact_load_impulse=during)
