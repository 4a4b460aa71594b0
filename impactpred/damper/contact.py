"""The classical instantaneous impact law of impact-damper theory.

The other laws (``Rigid``, ``LinearSpring``, ``Hertz``) are the project's own
(:mod:`impactpred.contact`); this one exists only for the damper, as the textbook
baseline of Masri and Caughey.
"""

from __future__ import annotations

from dataclasses import dataclass

from modalid._checks import as_real_scalar

__all__ = ["InstantaneousImpact"]


@dataclass(frozen=True)
class InstantaneousImpact:
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
    is not resolved (``impactpred.damper._loop_kernels.zeno_closes``):

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

    def __post_init__(self):
        e = as_real_scalar("restitution", self.restitution)
        if not 0.0 <= e <= 1.0:
            raise ValueError(f"restitution must lie in [0, 1], got {e!r}")
        object.__setattr__(self, "restitution", e)
