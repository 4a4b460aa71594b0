"""Contact laws between the two contact points.

The gap is ``g = y2 - y1 + g0`` (m); the compressive contact force ``f >= 0`` (N).
Every law is unilateral: no tension, and no force while the gap is open.

Each law says, once, how the solvers may treat it:

* :attr:`ContactLaw.is_linear`: the force is a linear function of the state while the
  contact is closed (``Rigid``, an undamped ``LinearSpring``), so the contact phase is a
  closed-form linear phase of the exact engine (:mod:`impactpred.engine`) and
  ``solve_impact`` may use its exact Laplace solver;
* :attr:`ContactLaw.is_impulsive`: the law acts in zero time (``InstantaneousImpact``),
  a velocity jump applied by the engine at the contact instant; it has no force history,
  so the time-stepping solvers cannot take it.

The time-stepping solvers hold the force constant over a step ``[t_n, t_n+1)``; the gap
at the end of the step is then affine in that force, ``g_{n+1} = G + K0 f_n`` (``G``: the
gap the step would end with at zero force, ``K0 > 0``: both bodies' step-response
increment over one step). :meth:`step_force` of each law solves that scalar problem.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalid.validation import as_nonnegative_scalar, as_positive_scalar, as_real_scalar

# one function with the modal kernel's, defined in its file: numba's cache of the kernel's
# compiled callers follows that file only (defined here, an edit left them stale)
from .solvers._modal_kernel import hertz_step_force

__all__ = ["Rigid", "LinearSpring", "Hertz", "InstantaneousImpact", "ContactLaw"]


class ContactLaw:
    """Base class of the contact laws (for ``isinstance`` checks)."""

    #: True when the force is linear in the state while the contact is closed, so the
    #: exact engine's closed-form contact phase (and the Laplace solver) applies.
    is_linear: bool = True
    #: True when the law acts in zero time (a velocity jump, no force history).
    is_impulsive: bool = False

    def step_force(self, G: float, K0: float, g_prev: float, dt: float) -> float:
        """Force (N) over one step such that the law holds at the step's end.

        Parameters
        ----------
        G : float
            The gap (m) at the step's end with no force over the step.
        K0 : float
            The gap's change (m/N) per unit force over the step (> 0).
        g_prev : float
            The gap (m) at the step's start.
        dt : float
            The step (s).
        """
        raise NotImplementedError


@dataclass(frozen=True)
class Rigid(ContactLaw):
    """Rigid (impenetrable) contact: ``f >= 0, g >= 0, f g = 0`` (the paper's law)."""

    def step_force(self, G, K0, g_prev, dt) -> float:
        """Linear complementarity: ``f = max(0, -G/K0)``, which makes ``g_{n+1} = max(G, 0)``.

        Parameters
        ----------
        G : float
            The gap (m) at the step's end with no force over the step.
        K0 : float
            The gap's change (m/N) per unit force over the step (> 0).
        g_prev : float
            The gap (m) at the step's start.
        dt : float
            The step (s).

        Returns
        -------
        float
            The contact force (N), >= 0.
        """
        return -G / K0 if G < 0.0 else 0.0


@dataclass(frozen=True)
class LinearSpring(ContactLaw):
    """Linear spring-dashpot contact: ``f = max(0, k d + c d')`` while the penetration
    ``d = -g > 0``.

    Parameters
    ----------
    stiffness : float
        ``k`` in N/m, > 0.
    damping : float, optional
        ``c`` in N s/m, >= 0. The dashpot never pulls: the force is clipped at 0.
    """

    stiffness: float
    damping: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "stiffness", as_positive_scalar("stiffness", self.stiffness))
        object.__setattr__(self, "damping", as_nonnegative_scalar("damping", self.damping))

    @property
    def is_linear(self) -> bool:  # type: ignore[override]
        """Undamped only: with a dashpot the force is clipped where it would pull."""
        return self.damping == 0.0

    def step_force(self, G, K0, g_prev, dt) -> float:
        """Implicit: ``f = k d_{n+1} + c (d_{n+1} - d_n)/dt`` with ``d = -g``, clipped at 0.

        Parameters
        ----------
        G : float
            The gap (m) at the step's end with no force over the step.
        K0 : float
            The gap's change (m/N) per unit force over the step (> 0).
        g_prev : float
            The gap (m) at the step's start.
        dt : float
            The step (s).

        Returns
        -------
        float
            The contact force (N), >= 0.
        """
        k, c = self.stiffness, self.damping
        f = (-k * G - c * (G - g_prev) / dt) / (1.0 + K0 * (k + c / dt))
        return f if (f > 0.0 and G + K0 * f < 0.0) else 0.0


@dataclass(frozen=True)
class Hertz(ContactLaw):
    """Hertzian contact ``f = k d**exponent`` for penetration ``d = -g > 0``.

    Parameters
    ----------
    stiffness : float
        ``k`` in N/m**exponent, > 0 (for a sphere of radius R on a flat:
        ``k = 4/3 E* sqrt(R)``).
    exponent : float, optional
        1.5 for Hertz's point contact.

    Nonlinear, so only the time-stepping solvers take it: a safeguarded scalar Newton
    solve per step.
    """

    stiffness: float
    exponent: float = 1.5
    is_linear = False

    def __post_init__(self):
        object.__setattr__(self, "stiffness", as_positive_scalar("stiffness", self.stiffness))
        object.__setattr__(self, "exponent", as_positive_scalar("exponent", self.exponent))

    @classmethod
    def from_materials(cls, *, radius1, youngs_modulus1, poisson1, youngs_modulus2,
                       poisson2, radius2=np.inf) -> Hertz:
        """Hertz's sphere-on-sphere (or sphere-on-flat, ``radius2=inf``) contact.

        ``k = 4/3 E* sqrt(R*)`` with ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` and
        ``1/R* = 1/R1 + 1/R2``; radii in m, moduli in Pa. A steel ball of radius 5 mm on a
        steel beam: ``Hertz.from_materials(radius1=5e-3, youngs_modulus1=210e9,
        poisson1=0.3, youngs_modulus2=210e9, poisson2=0.3)``, ``k ~ 1.1e10 N/m^1.5``.

        Parameters
        ----------
        radius1 : float, keyword-only
            Radius of body 1's sphere (m).
        youngs_modulus1, poisson1 : float, keyword-only
            Its Young's modulus (Pa) and Poisson's ratio (in (-1, 0.5]; 0.5 for an
            incompressible material such as rubber).
        youngs_modulus2, poisson2 : float, keyword-only
            Body 2's.
        radius2 : float, keyword-only
            Radius of body 2's sphere (m); ``inf`` for a flat.

        Returns
        -------
        Hertz
            Exponent 3/2, stiffness ``k`` (N/m^1.5).
        """
        r1 = as_positive_scalar("radius1", radius1)
        r2 = np.inf if radius2 == np.inf else as_positive_scalar("radius2", radius2)
        e1 = as_positive_scalar("youngs_modulus1", youngs_modulus1)
        e2 = as_positive_scalar("youngs_modulus2", youngs_modulus2)
        nu1 = as_real_scalar("poisson1", poisson1)
        nu2 = as_real_scalar("poisson2", poisson2)
        for name, nu in (("poisson1", nu1), ("poisson2", nu2)):
            if not -1.0 < nu <= 0.5:          # 0.5: incompressible (rubber), E* stays finite
                raise ValueError(f"{name} must lie in (-1, 0.5], got {nu!r}")
        e_star = 1.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)
        r_star = 1.0 / (1.0 / r1 + 1.0 / r2)
        return cls(4.0 / 3.0 * e_star * np.sqrt(r_star), 1.5)

    def step_force(self, G, K0, g_prev, dt) -> float:
        """Root of ``phi(f) = f - k (-(G + K0 f))**n`` on ``[0, -G/K0]`` (unique, phi
        increasing).

        Parameters
        ----------
        G : float
            The gap (m) at the step's end with no force over the step.
        K0 : float
            The gap's change (m/N) per unit force over the step (> 0).
        g_prev : float
            The gap (m) at the step's start.
        dt : float
            The step (s).

        Returns
        -------
        float
            The contact force (N), >= 0.
        """
        if G >= 0.0:
            return 0.0
        return hertz_step_force(float(G), float(K0), self.stiffness, self.exponent)


@dataclass(frozen=True)
class InstantaneousImpact(ContactLaw):
    """Instantaneous impact with a constant coefficient of restitution ``e``.

    At contact the relative velocity ``v_rel`` (approaching, > 0) reverses times ``e`` in
    zero time, through the impulse

        P = (1 + e) v_rel / (1/m_d + 1/M_eff),

    with ``1/M_eff`` the primary driving point's velocity jump per unit impulse (for
    real normal modes the sum of the modal ``1/m_k``). The primary's flexibility term
    (``ModalModel.flexibility``) is ignored at the impulse, since an impulse through a
    pure flexibility would be a displacement jump; use ``Rigid()`` or a compliant law to
    include it.

    Parameters
    ----------
    restitution : float
        ``0 <= e <= 1``.

    Notes
    -----
    With ``e < 1`` a damper mass can come to rest against a stop through an infinite
    sequence of ever smaller impacts (a Zeno sequence). Under a relative acceleration
    ``a`` pushing it onto the stop, a rebound at ``u = e v`` (m/s) returns after
    ``2 u / a``, and the flight times ``2 e^j u / a`` sum to the accumulation point

        t_inf = t_k + 2 u / (a (1 - e)) = t_k + 2 e v_k / (a (1 - e)),

    after which the mass moves with the primary. The engine closes the sequence (the
    impact is taken as plastic, then the ``Rigid()`` law's stick-or-separate decision
    applies: the mass sticks until the contact force turns tensile) as soon as a rebound
    is not resolved (``impactpred.engine.cycle_loop.zeno_closes``):

    * ``u`` below ``1e-6`` of the largest impact velocity so far (at least
      ``clearance * Omega``);
    * its height ``u^2 / (2 a)`` below the gap's resolution, ``1e-12`` of the terms of
      the gap's closed form (the primary's motion among them, so it does not vanish with
      the clearance);
    * for ``e < 1``, the two stops closer than that resolution: a rebound is at once an
      impact on the other stop, and the impacts ``v, e v, e^2 v, ...`` at one instant
      sum to a plastic impact. At ``clearance = 0`` the damper mass therefore moves with
      the primary for good, as with ``Rigid()``.

    A sequence then takes at most about ``ln(1e12) / (2 ln(1/e))`` impacts (27 at
    ``e = 0.6``, 1,400 at ``e = 0.99``). ``e = 1`` has no such limit: an impact at a
    resolved velocity between stops that coincide to rounding makes the engine raise a
    ``RuntimeError``, as do more than 100,000 impacts within one forcing period (elastic
    bouncing between stops a tiny clearance apart).
    """

    restitution: float
    is_linear = False
    is_impulsive = True

    def __post_init__(self):
        e = as_real_scalar("restitution", self.restitution)
        if not 0.0 <= e <= 1.0:
            raise ValueError(f"restitution must lie in [0, 1], got {e!r}")
        object.__setattr__(self, "restitution", e)


def check_contact(contact) -> ContactLaw:
    """Return ``contact`` if ``solve_impact`` can take it, else raise ``TypeError`` naming
    it: a contact law with a force history (an impulsive law such as
    ``InstantaneousImpact`` is for ``ImpactDamper``)."""
    if isinstance(contact, ContactLaw) and not contact.is_impulsive:
        if type(contact) is ContactLaw:       # the base class: no law of its own
            raise TypeError("contact must be a contact law such as Rigid(), "
                            "LinearSpring(...) or Hertz(...), not the base ContactLaw()")
        return contact
    why = (": an impulsive law has no force history (ImpactDamper takes it)"
           if isinstance(contact, ContactLaw) else "")
    raise TypeError(f"contact must be Rigid(), LinearSpring(...) or Hertz(...), got "
                    f"{contact!r}{why}")
