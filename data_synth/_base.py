"""``ExactModel``: the interface shared by the exact driving-point models of ``data_synth``.

Every model describes one structure by its driving-point receptance ``H(s)`` (m/N, with
``s`` in rad/s) at the contact point, its unit impulse response ``h(t)`` (m/(N s)) and
its step response ``S(t) = integral_0^t h`` (m/N), all known in closed form or as series
with a stated error bound, and it can produce a truncated :class:`modalid.ModalModel`.
"""

from __future__ import annotations

import abc

import numpy as np

from modalid import ModalModel
from modalid.validation import (as_choice, as_complex_array, as_count, as_nonnegative_scalar,
                             as_real_array)
from modalid.quantities import QUANTITIES, receptance_to
from modalid.receptance import TimeScale

__all__ = ["ExactModel"]


def _as_flag(name: str, value) -> bool:
    """Return ``value`` as a bool, or raise ``TypeError`` naming ``name``."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {value!r} "
                        f"of type {type(value).__name__}")
    return bool(value)


def _as_damping_ratio(name: str, value) -> float:
    """Return a viscous damping ratio in ``[0, 1)``, or raise naming ``name``."""
    out = as_nonnegative_scalar(name, value)
    if out >= 1.0:
        raise ValueError(f"{name} must be < 1 (an underdamped mode), got {out!r}")
    return out


class ExactModel(abc.ABC):
    """Exact driving-point dynamics of one linear structure (abstract base class).

    Subclasses are frozen dataclasses, validated on construction. Conventions: SI
    units, ``s`` and ``omega`` in rad/s, receptance in m/N, time in s.

    Attributes
    ----------
    mass : float
        Total mass (kg); a field of every subclass.
    time_scale : float or None
        A characteristic time (s), for choosing time steps and windows: the rod's
        transit time ``T``, the beam's ``T = sqrt(m/K)`` (its constructor argument;
        ``1/w_1 = T/eps_1^2 = 0.284 T``), the spring-mass ``1/w_n``; ``None`` for a
        lumped mass, which has none. A field or property of every subclass.

    Notes
    -----
    Subclasses implement :meth:`receptance`, :meth:`impulse_response`,
    :meth:`step_response`, :attr:`is_grounded`, :attr:`static_flexibility`, ``time_scale``
    and the three private hooks :meth:`_mode_count`, :meth:`_modes` and
    :meth:`_tail_flexibility` from which :meth:`natural_frequencies` and
    :meth:`modal_model` are built.
    """

    __slots__ = ()

    # -------------------------------------------------------------- exact functions
    @abc.abstractmethod
    def receptance(self, s) -> np.ndarray:
        """Exact driving-point receptance ``H(s)`` (m/N) at complex ``s`` (rad/s).

        Parameters
        ----------
        s : array_like of complex, any shape
            Laplace variable (rad/s); finite values.

        Returns
        -------
        ndarray of complex, shape of ``s``
            ``H(s)``. ``inf`` at ``s = 0`` for a free body and possibly at an exact pole;
            never ``nan``.
        """

    @abc.abstractmethod
    def impulse_response(self, t) -> np.ndarray:
        """Unit impulse response ``h(t)`` (m/(N s)) at times ``t`` (s), 0 for ``t < 0``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.
        """

    @abc.abstractmethod
    def step_response(self, t) -> np.ndarray:
        """Step response ``S(t) = integral_0^t h`` (m/N) at times ``t`` (s), 0 for ``t < 0``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.
        """

    def elastic_receptance(self, s) -> np.ndarray:
        """Elastic part ``H(s) - inverse_mass / s**2`` (m/N) at complex ``s`` (rad/s).

        Finite at ``s = 0``, where it equals :attr:`static_flexibility`. For a grounded
        model it is :meth:`receptance` itself.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        return self.receptance(s)

    def frf(self, omega, *, quantity: str = "receptance") -> np.ndarray:
        """Exact FRF at angular frequencies ``omega`` (rad/s).

        Parameters
        ----------
        omega : array_like of float, any shape
            Angular frequencies (rad/s).
        quantity : {"receptance", "mobility", "accelerance"}
            Receptance (m/N), mobility (m/(N s)) or accelerance (m/(N s^2)).

        Returns
        -------
        ndarray of complex, shape of ``omega``
            The FRF at ``s = i omega``. The accelerance of a free body at ``omega = 0``
            is its finite limit ``inverse_mass`` (as :meth:`modalid.ModalModel.frf`); its
            receptance and mobility there are ``inf`` (never ``nan``).
        """
        as_choice("quantity", quantity, QUANTITIES)
        omega = as_real_array("omega", omega)
        if quantity == "receptance" or not self.inverse_mass:
            return receptance_to(quantity, self.receptance(1j * omega), omega)
        elastic = receptance_to(quantity, self.elastic_receptance(1j * omega), omega)
        if quantity == "accelerance":
            return elastic + self.inverse_mass
        # mobility of the rigid body, inverse_mass/(i omega): inf (never nan) at omega = 0
        zero = omega == 0.0
        with np.errstate(over="ignore"):
            rigid = self.inverse_mass / (1j * np.where(zero, 1.0, omega))
        return np.where(zero, np.inf + 0j, elastic + rigid)

    # ---------------------------------------------------------------- properties
    @property
    @abc.abstractmethod
    def is_grounded(self) -> bool:
        """True when the structure is attached to the ground (no rigid-body motion)."""

    @property
    def inverse_mass(self) -> float:
        """Rigid-body term ``1/mass`` (1/kg) of a free body; 0.0 for a grounded one."""
        return 0.0 if self.is_grounded else 1.0 / self.mass

    @property
    def is_rational(self) -> bool:
        """True when ``H(s)`` is a rational function (finitely many poles)."""
        return False

    @property
    @abc.abstractmethod
    def static_flexibility(self) -> float:
        """Elastic flexibility at ``s = 0`` (m/N).

        ``H(0)`` of a grounded model; ``lim_{s->0} (H(s) - inverse_mass / s**2)`` of a
        free one.
        """

    # ------------------------------------------ receptance interface (modalid.receptance)
    def elastic_flexibility(self) -> float:
        """:attr:`static_flexibility` (m/N), under the receptance interface's name.

        Returns
        -------
        float
        """
        return float(self.static_flexibility)

    def time_scales(self) -> tuple:
        """``1/omega_1`` (s) of the first elastic mode: kind ``"modal"`` for a rational
        model, ``"continuum"`` otherwise; ``()`` without elastic modes.

        Returns
        -------
        tuple of modalid.receptance.TimeScale
        """
        if self._mode_count() == 0:
            return ()
        omega_1 = float(self._modes(1)[0][0])
        return (TimeScale(1.0 / omega_1, "modal" if self.is_rational else "continuum"),)

    def modal_form(self, n_modes=None) -> ModalModel:
        """The exact :meth:`modal_model` of a rational model (every mode; ``n_modes``
        ignored), else ``modal_model(n_modes, residual=True)``; ``ValueError`` when a
        model with infinitely many modes gets ``n_modes=None``.

        Parameters
        ----------
        n_modes : int, optional
            Modes of a continuum's truncated form (ignored by rational models).

        Returns
        -------
        modalid.ModalModel
        """
        if self.is_rational:
            return self.modal_model(self._mode_count())
        if n_modes is None:
            raise ValueError(f"a {type(self).__name__} needs n_modes to become a ModalModel")
        return self.modal_model(n_modes, residual=True)

    def jump_times(self, t_end) -> np.ndarray:
        """Times ``0 < t <= t_end`` (s) where :meth:`impulse_response` is discontinuous.

        The start of the response at ``t = 0`` is not listed. The base implementation
        returns an empty array (a continuous ``h`` for ``t > 0``).

        Parameters
        ----------
        t_end : float
            End of the time window (s), >= 0.

        Returns
        -------
        ndarray of float, shape (n_jumps,)
            Increasing jump times.
        """
        as_nonnegative_scalar("t_end", t_end)
        return np.empty(0)

    # ------------------------------------------------------------------ modes
    @abc.abstractmethod
    def _mode_count(self) -> int | None:
        """Number of elastic modes, ``None`` for infinitely many."""

    @abc.abstractmethod
    def _modes(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """Undamped natural frequencies (rad/s) and driving-point modal masses (kg) of
        the first ``n`` elastic modes (``n`` already checked), each shape (n,)."""

    @abc.abstractmethod
    def _tail_flexibility(self, n: int) -> float:
        """Static flexibility (m/N) of the elastic modes ``k > n``: ``sum 1/(m_k w_k^2)``."""

    def _own_damping_ratio(self) -> float:
        """Damping ratio of the model's own modes (0 for undamped models)."""
        return 0.0

    def _checked_mode_count(self, name: str, n) -> int:
        n = as_count(name, n)
        available = self._mode_count()
        if available is not None and n > available:
            raise ValueError(f"{name} must be <= {available}: {type(self).__name__} has "
                             f"{available} elastic mode(s), got {n}")
        return n

    def natural_frequencies(self, n) -> np.ndarray:
        """First ``n`` undamped elastic natural frequencies (rad/s), increasing.

        Rigid-body motion is excluded.

        Parameters
        ----------
        n : int
            Number of frequencies, >= 0.

        Returns
        -------
        ndarray of float, shape (n,)

        Raises
        ------
        ValueError
            If the model has fewer than ``n`` elastic modes.
        """
        n = self._checked_mode_count("n", n)
        return np.array(self._modes(n)[0], dtype=float)

    def modal_model(self, n_modes, *, damping_ratio=None, residual=False) -> ModalModel:
        """Truncated modal model: rigid body plus the first ``n_modes`` elastic modes.

        Parameters
        ----------
        n_modes : int
            Number of elastic modes kept, >= 0 and at most the model's mode count.
        damping_ratio : float or None, optional
            ``None`` (default) keeps the model's own damping: zero for every model except
            :class:`~data_synth.SpringMass`, whose modal model is then exact. A float in
            ``[0, 1)`` gives every kept mode that viscous damping ratio instead (for the
            undamped models this adds modal damping).
        residual : bool, optional
            If True, the omitted modes' static flexibility ``sum_{k > n_modes}
            1/(m_k w_k^2)`` (computed in closed form, not by subtraction) is added as the
            model's ``flexibility``, so that the static flexibility of the elastic part
            equals :attr:`static_flexibility` exactly (to rounding).

        Returns
        -------
        modalid.ModalModel
            ``inverse_mass / s^2 + flexibility + sum_k 1/(m_k (s^2 + 2 zeta w_k s + w_k^2))``.
            Exact only for a rational model with all its modes kept; otherwise a
            truncation of the exact modal expansion.
        """
        n = self._checked_mode_count("n_modes", n_modes)
        if damping_ratio is None:
            zeta = self._own_damping_ratio()
        else:
            zeta = _as_damping_ratio("damping_ratio", damping_ratio)
        residual = _as_flag("residual", residual)
        flexibility = float(self._tail_flexibility(n)) if residual else 0.0
        if n == 0:
            return ModalModel(inverse_mass=self.inverse_mass, flexibility=flexibility)
        omega, modal_mass = self._modes(n)
        return ModalModel.from_modes(omega, zeta, modal_mass, inverse_mass=self.inverse_mass,
                                     flexibility=flexibility)


def _check_times(t) -> np.ndarray:
    """Validate times ``t`` (s): a finite real array of any shape."""
    return as_real_array("t", t)


def _check_s(s) -> np.ndarray:
    """Validate a Laplace variable ``s`` (rad/s): a finite complex array of any shape."""
    return as_complex_array("s", s)


def _reciprocal(d: np.ndarray) -> np.ndarray:
    """``1/d`` for a complex array; ``inf + 0j`` (never ``nan``) where ``d == 0`` or ``1/d``
    overflows (``|d| < 1/DBL_MAX``)."""
    zero = d == 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = 1.0 / np.where(zero, 1.0, d)
    return np.where(zero | ~np.isfinite(out), np.inf + 0j, out)
