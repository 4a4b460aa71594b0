"""The dimensionless form the exact solver's engine runs on.

The engine (:mod:`impactpred.engine`) judges its phase matrices by tolerances relative to
their norm (zero eigenvalues at ``sqrt(eps |M|)``, eigenvector conditioning), its event
rows by rounding levels with ``1e-300`` floors and squared magnitudes. On the bodies' SI
state space these mixed units: a rigid body's states are a displacement (m) and a
velocity (m/s), a mode's a complex coordinate in N s, the contact force's input ``1/M``
and its row ``k``. A mass scale of 1e15 (or 1e-16), or a time scale of 1e-11 s (or
1e11 s), then put a stuck phase's eigenvalues under the zero cut, or its eigenvectors
past the conditioning limit, and the answer came out wrong with no warning.

:class:`Units` holds a reference time ``t``, mass ``m`` and length ``l`` chosen from the
inputs (:func:`reference_units`: each scales with the problem, and each is a power of two,
so that the changes of unit are exact), and the derived force ``f = m l / t^2``, impulse
``j = f t`` and energy ``e = f l``. The augmented state ``[X, 1, J, cos, sin ...]`` is
``x = unit * xi``: a modal or real-pole state's unit is ``j`` (``z' = p z + F``), a rigid
body's ``l`` and ``l / t``, ``J``'s ``j``; time is ``t * tau``; every row the engine sees
gives its output in units of ``f``, ``l``, ``l / t`` or ``l / t^2``. The solution is then
the same for every scale of mass, length and time, up to rounding.
"""

from __future__ import annotations

import math


__all__ = ["Units", "reference_units", "SI_RANGE"]

#: the force, energy and impulse scales (N, J, N s) and the speed scale (m/s) a solve's
#: SI results may have: their squares and products (energies, the work integrals) must
#: stay clear of double precision's overflow and underflow
SI_RANGE = (1e-120, 1e120)


def _power_of_two(x: float, fallback: float) -> float:
    """The power of two nearest ``x`` in log scale, or ``fallback`` where ``x`` is not a
    positive finite number whose inverse is finite too."""
    if not (0.0 < x < math.inf and 1.0 / x < math.inf):
        return fallback
    return 2.0 ** round(math.log2(x))


class Units:
    """Reference time ``t`` (s), mass ``m`` (kg) and length ``l`` (m), and the force
    ``f`` (N), impulse ``j`` (N s) and energy ``e`` (J) they make."""

    __slots__ = ("t", "m", "l", "f", "j", "e")

    def __init__(self, t, m, length):
        self.t, self.m, self.l = float(t), float(m), float(length)
        self.f = self.m * self.l / (self.t * self.t)
        self.j = self.f * self.t
        self.e = self.f * self.l

    def __repr__(self) -> str:
        return f"Units(t={self.t!r} s, m={self.m!r} kg, l={self.l!r} m)"

    def check(self) -> None:
        """``ValueError`` where the problem's force, impulse, energy or speed scale is
        outside :data:`SI_RANGE`: its SI results (squares of forces and speeds in the
        energies) would overflow or underflow."""
        lo, hi = SI_RANGE
        for name, value, si in (("force", self.f, "N"), ("impulse", self.j, "N s"),
                                ("energy", self.e, "J"), ("speed", self.l / self.t, "m/s")):
            if not lo <= value <= hi:
                raise ValueError(
                    f"the impact's {name} scale, {value:.3g} {si} (from a reference mass of "
                    f"{self.m:.3g} kg, length {self.l:.3g} m and time {self.t:.3g} s), is "
                    f"outside {lo:g} to {hi:g} {si}: the exact solver's SI results would "
                    "overflow or underflow in double precision; state the problem in other "
                    "units (e.g. masses in tonnes or grams) and convert the result")

    def matrix(self, M, unit):
        """The phase matrix ``M`` (on SI states, per s) on the dimensionless states
        ``xi = x / unit``, per unit ``tau = t / self.t``."""
        return self.t * (M * unit[None, :]) / unit[:, None]


def reference_units(c, free_rate, *, compliance, t_end, rates=(), displacement=0.0,
                    force=0.0) -> Units:
    """The reference :class:`Units` of an impact.

    Parameters
    ----------
    c : (float, float, float)
        ``(c0, c1, c2)``: ``H1 + H2 ~ c0 + c1 / s + c2 / s^2`` at high ``s`` (m/N, m/(N s),
        1/kg).
    free_rate : float
        The free bodies' fastest rate (rad/s), 0 for none.
    compliance : float, keyword-only
        ``c0`` plus the contact spring's ``1/k`` (m/N; ``c0`` for a rigid contact).
    t_end : float, keyword-only
        The run's end (s): the time unit where the problem has no rate at all (rigid
        masses in rigid contact).
    rates : sequence of float, keyword-only
        Other rates of the problem (rad/s): the loads' frequencies.
    displacement : float, keyword-only
        The displacements in play (m): the gap, the approach over the run, the vibration.
    force : float, keyword-only
        The loads' amplitudes (N).

    Returns
    -------
    Units
        ``1 / t``: the fastest of ``free_rate``, ``rates`` and the contact's own rate (the
        roots of ``compliance s^2 + c1 s + c2``). ``1 / m``: the inverse mass of ``H1 +
        H2`` at that rate, ``|c2| + |c1| / t + |c0| / t^2``. ``l``: ``displacement`` plus
        what ``force`` moves the bodies over ``t`` (1 m where nothing moves).
    """
    c0, c1, c2 = c
    candidates = [free_rate, *rates]
    if compliance > 0.0:
        candidates += [math.sqrt(abs(c2) / compliance), abs(c1) / compliance]
    rate = max([r for r in candidates if math.isfinite(r)] + [0.0])
    fallback = _power_of_two(t_end, 1.0)
    t = _power_of_two(1.0 / rate, fallback) if rate > 0.0 else fallback
    inverse_mass = abs(c2) + abs(c1) / t + abs(c0) / (t * t)
    m = _power_of_two(1.0 / inverse_mass, 1.0) if inverse_mass > 0.0 else 1.0
    length = _power_of_two(displacement + force * (t * t) / m, 1.0)
    return Units(t, m, length)
