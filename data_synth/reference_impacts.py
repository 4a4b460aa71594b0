"""Exact reference solutions of three impact problems (``method.md`` sections 2 and 3).

Conventions (``method.md`` section 1): ``y`` points from body 1 towards body 2; the
compressive contact force ``f >= 0`` pushes body 2 in ``+y`` and body 1 in ``-y``; the
gap is ``g = y2 - y1`` (the bodies touch at ``t = 0``); the coefficient of restitution is
``e = (u2' - u1') / (u1 - u2)`` with ``u`` the rigid-body (centre-of-mass) velocities.

Functions
---------
mass_on_fixed_rod
    A rigid mass strikes the free end of a fixed-free elastic rod at rest
    (Saint-Venant's problem, ``method.md`` 3(c)). Solved exactly by the method of
    characteristics, over the first contact and, by default, over every re-contact
    with the rod still vibrating after a separation.
two_free_rods_equal_transit
    Two free-free rods with equal wave transit times (``method.md`` 3(a)).
two_rigid_masses
    Two rigid masses, rigid (perfectly plastic) contact: a Dirac impulse.

Derivation of :func:`mass_on_fixed_rod` (units: s, m, kg, N)
------------------------------------------------------------
Rod of mass ``m``, one-way transit time ``T``, impedance ``Z = m/T`` (``= rho c``), fixed
at the far end, struck end at ``y2``. Particle velocity (in ``+y``, into the rod) at the
struck end is the sum of the wave leaving the end, ``a(t)``, and the wave arriving back
from the fixed end, ``b(t)``; the compressive force there is ``f = Z (a - b)``. The fixed
end imposes zero velocity, so the velocity wave reflects with a sign change and the
stress wave with the same sign: ``b(t) = -a(t - 2T)``.

* In contact the end moves with the mass, ``v = a - a(t - 2T)``, and
  ``M v' = -f = -Z (a + a(t - 2T))``. Hence the neutral delay equation
  ``M a'(t) + Z a(t) = M a'(t - 2T) - Z a(t - 2T)``, ``a = 0`` for ``t < 0``.
* The mass velocity is continuous, so ``a`` jumps wherever ``a(t - 2T)`` jumps, by the
  same amount (it jumps by ``v0`` at ``t = 0``, so by ``v0`` at every ``2kT`` of the first
  contact and the force jumps up by ``2 Z v0`` there).
* On a piece where ``a(t - 2T) = exp(-beta r) H(r)`` with ``r = (t - t0)/T`` and
  ``beta = Z T / M = m / M``, the solution is ``a = exp(-beta r) Q(r)`` with the
  polynomial recursion ``Q' = H' - 2 beta H``, i.e.
  ``Q(r) = H(r) - 2 beta int_0^r H + v(t0)``. The force is
  ``f = Z exp(-beta r) (Q + H)`` and the mass velocity ``v = exp(-beta r) (Q - H)``.
  For ``t < 2T``: ``Q = v0``, ``f = Z v0 exp(-Z t / M)``.
* Separation: the first point where ``Q + H`` changes sign from positive to negative
  (found from the critical points of the polynomial and polished with Brent's method).
  A jump up at ``2kT`` is not a separation.
* Free flight: ``f = 0`` gives ``a(t) = b(t) = -a(t - 2T)``; the end velocity is
  ``2 b(t)``; the mass flies at constant speed. The gap is ``y2 - y1``; a re-contact is
  its first sign change (the closed form is sampled densely, local minima are refined,
  the root polished by Brent's method). After a separation with the mass moving back
  (``v <= 0``), the end motion is ``4T``-periodic, so a re-contact, if any, happens
  within ``4T``; none within ``4T`` means none ever.
* Rod energy: ``E(t) = Z int_{t-2T}^{t} a(tau)^2 dtau`` (the two waves in the rod, energy
  density ``rho (a^2 + b^2)``).

Every integral of ``exp(-gamma r) r^n`` is evaluated in closed form (series or the
regularised incomplete gamma function), so the result is exact to rounding.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalid.validation import as_choice, as_positive_scalar, as_real_array, as_real_scalar

from ._characteristics import _energy_after, _FixedRodSolution

__all__ = [
    "MassOnFixedRodResult",
    "TwoFreeRodsResult",
    "TwoRigidMassesResult",
    "mass_on_fixed_rod",
    "two_free_rods_equal_transit",
    "two_rigid_masses",
]



def _frozen(a) -> np.ndarray:
    a = np.array(a, dtype=float, copy=True)
    a.setflags(write=False)
    return a


def _as_times(t) -> np.ndarray:
    arr = as_real_array("t", t)
    if arr.ndim > 1:
        raise ValueError(f"t must be a scalar or 1-D array of times (s), got shape {arr.shape}")
    return arr


# --------------------------------------------------------------------------------------
# exp-polynomial calculus
# --------------------------------------------------------------------------------------

@dataclass(frozen=True)
class MassOnFixedRodResult:
    """Exact solution of a rigid mass striking a fixed-free rod at rest.

    Body 1 is the mass, body 2 the rod (grounded, rigid-body velocity 0). All arrays
    are read-only and have the shape of the input ``t``.

    Attributes
    ----------
    t : ndarray
        Times (s) at which the histories are given (a copy of the input).
    force : ndarray
        Contact force (N), compressive positive; right-continuous at its jumps;
        0 outside the contacts.
    mass_velocity : ndarray
        Velocity of the mass (m/s) in ``+y`` (towards the rod).
    y1, y2 : ndarray
        Displacement (m) of the mass and of the rod's struck end in ``+y`` (both 0 at
        ``t = 0``; ``y1 = v0 t`` for ``t < 0``).
    gap : ndarray
        ``y2 - y1`` (m). With ``contacts="first"`` it turns negative where the ignored
        re-contacts would be.
    rod_energy : ndarray
        Elastic + kinetic energy in the rod (J), from the waves:
        ``Z int_{t-2T}^t a^2``.
    separation_time : float
        End of the first contact (s).
    velocity_after_first_contact : float
        Velocity of the mass (m/s) right after the first separation.
    restitution_first_contact : float
        ``-velocity_after_first_contact / v0`` (the rod is grounded).
    rod_energy_after_first_contact : float
        Energy left in the rod (J) at the first separation.
    impulse_first_contact : float
        ``int f dt`` over the first contact (N s), from the closed form.
    contact_intervals : tuple of (float, float)
        Every contact (start, end) in s. One interval with ``contacts="first"``.
    velocity_after : float
        Velocity of the mass (m/s) after the last contact.
    restitution : float
        ``-velocity_after / v0``.
    rod_energy_after : float
        Energy left in the rod (J) after the last contact.
    total_impulse : float
        ``int f dt`` over all contacts (N s), from the closed form.
    impedance : float
        ``Z = m / T`` (kg/s).
    force_jump_times : tuple of float
        Times (s) inside the contacts where the force may jump (returns of waves).
    contacts : str
        ``"all"`` or ``"first"``.
    """

    t: np.ndarray
    force: np.ndarray
    mass_velocity: np.ndarray
    y1: np.ndarray
    y2: np.ndarray
    gap: np.ndarray
    rod_energy: np.ndarray
    separation_time: float
    velocity_after_first_contact: float
    restitution_first_contact: float
    rod_energy_after_first_contact: float
    impulse_first_contact: float
    contact_intervals: tuple
    velocity_after: float
    restitution: float
    rod_energy_after: float
    total_impulse: float
    impedance: float
    force_jump_times: tuple
    contacts: str


def mass_on_fixed_rod(mass, rod_mass, transit_time, velocity, t, *,
                      contacts="all") -> MassOnFixedRodResult:
    """Rigid mass striking the free end of a fixed-free elastic rod at rest (exact).

    Saint-Venant's solution by the method of characteristics: the force is
    ``Z v0 exp(-Z t / M)`` for ``t < 2T`` and, on each later piece between wave
    returns, ``exp(-a u)`` times a polynomial in the local time ``u`` (``a = Z/M``),
    the polynomials following from the exact recursion given in the module docstring.
    Separation times are roots of the closed form; re-contacts with the still vibrating
    rod are found from the closed-form gap.

    Parameters
    ----------
    mass : float
        Mass of the striker ``M`` (kg), > 0.
    rod_mass : float
        Mass of the rod ``m`` (kg), > 0.
    transit_time : float
        One-way wave transit time of the rod ``T = l/c`` (s), > 0.
    velocity : float
        Approach velocity ``v0`` of the mass (m/s), > 0.
    t : float or array_like, 1-D
        Times (s) at which to evaluate the histories. Contact begins at ``t = 0``.
    contacts : {"all", "first"}, optional
        ``"all"`` (default) follows every re-contact until the mass leaves for good;
        ``"first"`` stops at the first separation (the paper's single-contact analysis:
        afterwards the mass flies freely and the rod vibrates freely, the gap may turn
        negative).

    Returns
    -------
    MassOnFixedRodResult

    Raises
    ------
    TypeError, ValueError
        For a non-numeric, non-finite or non-positive parameter, a bad ``t`` or an
        unknown ``contacts``; the message names the value.
    """
    M = as_positive_scalar("mass", mass)
    m = as_positive_scalar("rod_mass", rod_mass)
    T = as_positive_scalar("transit_time", transit_time)
    v0 = as_positive_scalar("velocity", velocity)
    tt = _as_times(t)
    mode = as_choice("contacts", contacts, ("all", "first"))

    sol = _FixedRodSolution(M, m, T, v0, first_only=(mode == "first"))
    flat = np.atleast_1d(tt).astype(float)
    force, vel, y1, y2, energy = sol.evaluate(flat)
    shape = tt.shape

    t_s, v_s = sol.first_separation
    jumps = []
    for (c0, c1) in sol.intervals:
        for s in sol.starts:
            if c0 < s < c1:
                jumps.append(float(s))
    return MassOnFixedRodResult(
        t=_frozen(tt),
        force=_frozen(force.reshape(shape)),
        mass_velocity=_frozen(vel.reshape(shape)),
        y1=_frozen(y1.reshape(shape)),
        y2=_frozen(y2.reshape(shape)),
        gap=_frozen((y2 - y1).reshape(shape)),
        rod_energy=_frozen(energy.reshape(shape)),
        separation_time=float(t_s),
        velocity_after_first_contact=float(v_s),
        restitution_first_contact=float(-v_s / v0),
        rod_energy_after_first_contact=sol.rod_energy_at(t_s),
        impulse_first_contact=sol.impulse(0.0, t_s),
        contact_intervals=tuple((float(a), float(b)) for a, b in sol.intervals),
        velocity_after=float(sol.v_end),
        restitution=float(-sol.v_end / v0),
        rod_energy_after=_energy_after(sol),
        total_impulse=sol.impulse(0.0, sol.t_end),
        impedance=sol.Z,
        force_jump_times=tuple(sorted(set(jumps))),
        contacts=mode,
    )


@dataclass(frozen=True)
class TwoFreeRodsResult:
    """Exact impact of two free-free rods with equal transit time ``T`` (method.md 3(a)).

    Attributes
    ----------
    t : ndarray
        Times (s), a copy of the input.
    force : ndarray
        Contact force (N): ``v12 m1 m2 / ((m1 + m2) T)`` on ``[0, 2T)``, else 0.
    y1, y2 : ndarray
        Contact-end displacements (m) in ``+y`` (``v10 t``, ``v20 t`` for ``t < 0``).
    v1, v2 : ndarray
        Contact-end velocities (m/s).
    gap : ndarray
        ``y2 - y1`` (m).
    force_height : float
        Height of the rectangular pulse (N).
    contact_duration : float
        ``2T`` (s).
    impulse : float
        ``force_height * 2T`` (N s).
    velocities_before, velocities_after : tuple of float
        Rigid-body velocities (m/s) of rods 1 and 2.
    restitution : float
        1 (no vibration is left in either rod).
    kinetic_energy_before, kinetic_energy_after : float
        Rigid-body kinetic energies (J).
    vibration_energy_after : float
        0 (J).
    """

    t: np.ndarray
    force: np.ndarray
    y1: np.ndarray
    y2: np.ndarray
    v1: np.ndarray
    v2: np.ndarray
    gap: np.ndarray
    force_height: float
    contact_duration: float
    impulse: float
    velocities_before: tuple
    velocities_after: tuple
    restitution: float
    kinetic_energy_before: float
    kinetic_energy_after: float
    vibration_energy_after: float


def _check_approach(v10: float, v20: float) -> float:
    v12 = v10 - v20
    if not v12 > 0.0:
        raise ValueError(f"the bodies must approach: v10 - v20 must be positive, got "
                         f"v10 = {v10!r}, v20 = {v20!r} (v10 - v20 = {v12!r})")
    return v12


def two_free_rods_equal_transit(m1, m2, transit_time, v10, v20, t) -> TwoFreeRodsResult:
    """Two free-free rods with equal transit times colliding end to end (exact).

    Paper eqs. 19-22 as corrected in ``method.md`` 3(a). With ``M = m1 + m2``,
    ``p = m1 v10 + m2 v20`` and ``v12 = v10 - v20``::

        f  = v12 m1 m2 / (M T)                  on 0 <= t < 2T
        y1 = y2 = p t / M                       on 0 <= t < 2T
        y1 = (p t - v12 m2 (t - 2T)) / M        for t >= 2T
        y2 = (p t + v12 m1 (t - 2T)) / M        for t >= 2T

    Parameters
    ----------
    m1, m2 : float
        Rod masses (kg), > 0.
    transit_time : float
        Common one-way transit time ``T`` (s), > 0.
    v10, v20 : float
        Rigid velocities before impact (m/s) in ``+y``; ``v10 > v20`` (approaching).
    t : float or array_like, 1-D
        Times (s); contact begins at ``t = 0``.

    Returns
    -------
    TwoFreeRodsResult

    Raises
    ------
    TypeError, ValueError
        For bad parameters (named in the message) or bodies not approaching.
    """
    m1 = as_positive_scalar("m1", m1)
    m2 = as_positive_scalar("m2", m2)
    T = as_positive_scalar("transit_time", transit_time)
    v10 = as_real_scalar("v10", v10)
    v20 = as_real_scalar("v20", v20)
    v12 = _check_approach(v10, v20)
    tt = _as_times(t)

    Mt = m1 + m2
    p = m1 * v10 + m2 * v20
    height = v12 * m1 * m2 / (Mt * T)
    u1 = (p - v12 * m2) / Mt
    u2 = (p + v12 * m1) / Mt
    before = tt < 0.0
    during = (tt >= 0.0) & (tt < 2.0 * T)
    force = np.where(during, height, 0.0)
    y1 = np.where(before, v10 * tt, np.where(during, p * tt / Mt,
                                              (p * tt - v12 * m2 * (tt - 2 * T)) / Mt))
    y2 = np.where(before, v20 * tt, np.where(during, p * tt / Mt,
                                              (p * tt + v12 * m1 * (tt - 2 * T)) / Mt))
    v1 = np.where(before, v10, np.where(during, p / Mt, u1))
    v2 = np.where(before, v20, np.where(during, p / Mt, u2))
    ke0 = 0.5 * m1 * v10**2 + 0.5 * m2 * v20**2
    ke1 = 0.5 * m1 * u1**2 + 0.5 * m2 * u2**2
    return TwoFreeRodsResult(
        t=_frozen(tt), force=_frozen(force), y1=_frozen(y1), y2=_frozen(y2),
        v1=_frozen(v1), v2=_frozen(v2), gap=_frozen(y2 - y1),
        force_height=float(height), contact_duration=2.0 * T, impulse=float(2.0 * T * height),
        velocities_before=(v10, v20), velocities_after=(float(u1), float(u2)),
        restitution=float((u2 - u1) / v12),
        kinetic_energy_before=float(ke0), kinetic_energy_after=float(ke1),
        vibration_energy_after=0.0,
    )


# --------------------------------------------------------------------------------------
# two rigid masses, rigid contact
# --------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TwoRigidMassesResult:
    """Rigid contact of two rigid masses: perfectly plastic, a Dirac impulse at ``t = 0``.

    Attributes
    ----------
    impulse : float
        Size of the Dirac impulse ``m1 m2 v12 / (m1 + m2)`` (N s) at ``t = 0``.
    dirac_impulses : tuple of (float, float)
        ``((0.0, impulse),)``: (time s, impulse N s).
    common_velocity : float
        Velocity of both masses after the impact (m/s).
    velocities_before, velocities_after : tuple of float
        (m/s).
    restitution : float
        0.
    kinetic_energy_before, kinetic_energy_after : float
        (J).
    energy_lost : float
        ``m1 m2 v12^2 / (2 (m1 + m2))`` (J), dissipated by the Dirac impulse.
    """

    impulse: float
    dirac_impulses: tuple
    common_velocity: float
    velocities_before: tuple
    velocities_after: tuple
    restitution: float
    kinetic_energy_before: float
    kinetic_energy_after: float
    energy_lost: float

    def displacements(self, t):
        """Displacements ``(y1, y2)`` (m) of the two masses at times ``t`` (s).

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        tuple of numpy.ndarray
            ``(y1, y2)``, each the shape of ``t``.
        """
        tt = _as_times(t)
        v10, v20 = self.velocities_before
        u = self.common_velocity
        y1 = np.where(tt < 0.0, v10 * tt, u * tt)
        y2 = np.where(tt < 0.0, v20 * tt, u * tt)
        return _frozen(y1), _frozen(y2)


def two_rigid_masses(m1, m2, v10, v20) -> TwoRigidMassesResult:
    """Two rigid masses in rigid contact (exact): a perfectly plastic impact.

    The force is the Dirac impulse ``J delta(t)``, ``J = m1 m2 v12 / (m1 + m2)``,
    ``v12 = v10 - v20``; afterwards both move at ``(m1 v10 + m2 v20) / (m1 + m2)``;
    ``e = 0``.

    Parameters
    ----------
    m1, m2 : float
        Masses (kg), > 0.
    v10, v20 : float
        Velocities before impact (m/s) in ``+y``; ``v10 > v20`` (approaching).

    Returns
    -------
    TwoRigidMassesResult

    Raises
    ------
    TypeError, ValueError
        For bad parameters (named in the message) or bodies not approaching.
    """
    m1 = as_positive_scalar("m1", m1)
    m2 = as_positive_scalar("m2", m2)
    v10 = as_real_scalar("v10", v10)
    v20 = as_real_scalar("v20", v20)
    v12 = _check_approach(v10, v20)
    Mt = m1 + m2
    J = m1 * m2 * v12 / Mt
    u = (m1 * v10 + m2 * v20) / Mt
    ke0 = 0.5 * m1 * v10**2 + 0.5 * m2 * v20**2
    ke1 = 0.5 * Mt * u**2
    return TwoRigidMassesResult(
        impulse=float(J), dirac_impulses=((0.0, float(J)),), common_velocity=float(u),
        velocities_before=(v10, v20), velocities_after=(float(u), float(u)),
        restitution=0.0, kinetic_energy_before=float(ke0), kinetic_energy_after=float(ke1),
        energy_lost=float(0.5 * m1 * m2 * v12**2 / Mt),
    )
