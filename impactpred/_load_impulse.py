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
from scipy.integrate import quad

from .damper.excitation import HarmonicForce

__all__ = ["at_contacts", "load_impulse"]


def load_impulse(load, a, b) -> float:
    """``int_a^b load(t) dt`` (N s) for ``0 <= a <= b`` (s).

    A :class:`HarmonicForce` in closed form; any other load (a vectorised callable, or
    the interpolant of samples) by adaptive quadrature (``scipy.integrate.quad``, to
    1e-10 relative), which resolves a sampled load's kinks by subdivision.
    """
    if b <= a or load is None:
        return 0.0
    if isinstance(load, HarmonicForce):
        w, phi = load.omega, load.phase
        if w == 0.0:
            return load.amplitude * math.cos(phi) * (b - a)
        return load.amplitude / w * (math.sin(w * b + phi) - math.sin(w * a + phi))

    def f(t):
        return float(np.asarray(load(np.array([t])), dtype=float).reshape(-1)[0])

    value, _ = quad(f, a, b, limit=500, epsabs=0.0, epsrel=1e-10)
    return float(value)


def at_contacts(result, bodies):
    """``result`` with its loaded free bodies' velocities read at the impact's ends.

    ``velocities_before``: at the first contact's start; ``velocities_after``: at the last
    contact's end (the load's impulse after it taken back from the final velocity);
    ``first_contact_load_impulse``: each load's impulse (N s) during the first contact.
    Unchanged where no free body carries a load, or the bodies never touched.
    """
    inv = result.inverse_masses
    loaded = [b.load is not None and m != 0.0 for b, m in zip(bodies, inv)]
    if not any(loaded) or not result.contact_intervals:
        return result
    t_start, t_first_end = result.contact_intervals[0]
    t_last_end = result.contact_intervals[-1][1]
    t_final = float(result.t[-1])
    loads = [b.load if on else None for b, on in zip(bodies, loaded)]
    before = tuple(u + m * load_impulse(f, 0.0, t_start)
                   for u, m, f in zip(result.velocities_before, inv, loads))
    after = tuple(u - m * load_impulse(f, t_last_end, t_final)
                  for u, m, f in zip(result.velocities_after, inv, loads))
    during = tuple(load_impulse(f, t_start, t_first_end) for f in loads)
    return dataclasses.replace(result, velocities_before=before, velocities_after=after,
                               first_contact_load_impulse=during)
