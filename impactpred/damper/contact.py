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
    sequence of ever smaller impacts (a Zeno sequence). The engine closes it: when the
    rebound velocity falls below ``1e-6`` of the largest impact velocity seen, the mass
    sticks to the primary (the coupled system's exact solution) until the contact force
    turns tensile, as with ``Rigid()``.
    """

    restitution: float

    def __post_init__(self):
        e = as_real_scalar("restitution", self.restitution)
        if not 0.0 <= e <= 1.0:
            raise ValueError(f"restitution must lie in [0, 1], got {e!r}")
        object.__setattr__(self, "restitution", e)
