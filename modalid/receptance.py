"""The receptance interface: what a body's model offers the impact solvers.

Four kinds of model describe a driving-point receptance ``H(s)`` (m/N, ``s`` in rad/s):
:class:`modalid.ModalModel` (pole-residue, identified or built), the exact models of
``data_synth`` (``Rod``, ``CantileverBeam``, ``LumpedMass``, ``SpringMass``: subclasses
of ``data_synth.ExactModel``), ``impactpred.SampledResponse`` (an impulse response known
by samples) and, through its driving-point row, :class:`modalid.MultiOutputModalModel`.
Each implements :class:`Receptance`, so that a solver asks the model what it needs
instead of asking which class it is:

==========================  ============================================================
member                      meaning
==========================  ============================================================
``inverse_mass``            rigid-body term ``1/M`` of ``H`` (1/kg; 0 when grounded)
``is_rational``             ``H`` has finitely many poles: :meth:`modal_form` is exact
``step_response(t)``        ``S(t) = int_0^t h`` (m/N) at times ``t`` (s), 0 before 0
``elastic_flexibility()``   ``lim_{s->0} H(s) - inverse_mass/s^2`` (m/N): the static
                            flexibility of the elastic part
``time_scales()``           the model's own time scales (:class:`TimeScale`)
``modal_form(n_modes)``     the pole-residue form (``ModalModel``): exact when
                            ``is_rational`` (``n_modes`` ignored), else ``n_modes``
                            modes plus the omitted modes' static flexibility;
                            ``ValueError`` for a model without modes
==========================  ============================================================

The names already used by some kinds stay as they are (``ModalModel.static_flexibility()``
is a method, ``data_synth``'s ``static_flexibility`` a property; both equal
``elastic_flexibility()``).
"""

from __future__ import annotations

from typing import NamedTuple, Protocol, runtime_checkable

import numpy as np

__all__ = ["Receptance", "TimeScale", "TIME_SCALE_KINDS"]

#: what a :class:`TimeScale` resolves, and so how a time-stepping solver must resolve it:
#: ``"modal"``: ``1/omega`` of the fastest mode of a rational model (its modes are
#: discretised exactly, a few dozen steps suffice); ``"continuum"``: ``1/omega_1`` of a
#: continuum whose response is resolved only by the grid; ``"transit"``: a wave's transit
#: time (a grid that divides it puts the reflections on grid points); ``"sample"``: the
#: step of a sampled record (one step per sample)
TIME_SCALE_KINDS = ("modal", "continuum", "transit", "sample")


class TimeScale(NamedTuple):
    """One time scale of a model's own dynamics.

    Attributes
    ----------
    seconds : float
        The scale (s), > 0.
    kind : str
        One of :data:`TIME_SCALE_KINDS`.
    """

    seconds: float
    kind: str


@runtime_checkable
class Receptance(Protocol):
    """A driving-point receptance as the impact solvers use it (see the module docstring).

    ``isinstance(model, Receptance)`` tells whether ``model`` offers every member (it does
    not check their values).
    """

    @property
    def inverse_mass(self) -> float:
        """Rigid-body term ``1/M`` (1/kg); 0 for a grounded body."""

    @property
    def is_rational(self) -> bool:
        """True when ``H(s)`` has finitely many poles (:meth:`modal_form` is exact)."""

    def step_response(self, t) -> np.ndarray:
        """Step response (m/N) at times ``t`` (s, any shape), 0 for ``t < 0``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.
        """

    def elastic_flexibility(self) -> float:
        """Static flexibility of the elastic part (m/N): ``lim_{s->0} H(s) - 1/(M s^2)``."""

    def time_scales(self) -> tuple:
        """The model's own time scales, a tuple of :class:`TimeScale` (may be empty)."""

    def modal_form(self, n_modes=None):
        """The model as a ``modalid.ModalModel`` (exact when :attr:`is_rational`).

        Parameters
        ----------
        n_modes : int or None
            Modes kept by a model with infinitely many (plus the omitted modes' static
            flexibility); ignored by a rational model.

        Raises
        ------
        ValueError
            When the model has no pole-residue form (a sampled response), or it is not
            rational and ``n_modes`` is None.
        """


def modal_time_scales(poles, real_poles) -> tuple:
    """``(TimeScale(1/|p|max, "modal"),)`` of a pole set (rad/s), or ``()`` without poles."""
    rates = np.concatenate([np.abs(np.asarray(poles)), np.abs(np.asarray(real_poles))])
    return (TimeScale(1.0 / float(np.max(rates)), "modal"),) if rates.size else ()
