"""Rational exact models: a free lumped mass and a grounded spring-mass(-damper).

Both receptances are rational, so every response is a closed form, exact to rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from modalid.validation import as_positive_scalar

from ._base import ExactModel, _as_damping_ratio, _check_s, _check_times, _reciprocal

__all__ = ["LumpedMass", "SpringMass"]


@dataclass(frozen=True)
class LumpedMass(ExactModel):
    """A free rigid mass: ``H(s) = 1/(m s^2)``, ``h(t) = t/m``, ``S(t) = t^2/(2m)``.

    Parameters
    ----------
    mass : float
        Mass ``m`` (kg), > 0.

    Notes
    -----
    It has no elastic mode: :meth:`natural_frequencies` accepts only ``n = 0``, and
    :meth:`modal_model` only ``n_modes = 0`` (the exact model ``inverse_mass = 1/m``).
    :attr:`time_scale` is ``None``: a rigid mass has no intrinsic time. Every result is
    exact to rounding.
    """

    mass: float

    def __post_init__(self):
        mass = as_positive_scalar("mass", self.mass)
        if not np.isfinite(1.0 / mass):     # a subnormal mass: its inverse overflows
            raise ValueError(f"mass must be at least {np.finfo(float).tiny:.3g} kg (its "
                             f"inverse, 1/m, must be finite), got {self.mass!r}")
        object.__setattr__(self, "mass", mass)

    # ------------------------------------------------------------------ responses
    def receptance(self, s) -> np.ndarray:
        """Exact ``H(s) = 1/(m s^2)`` (m/N), shape of ``s``; ``inf`` at ``s = 0`` (and where
        it overflows), never ``nan``.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        s = _check_s(s)
        big = np.abs(s) >= 1.0
        with np.errstate(under="ignore"):
            r = 1.0 / np.where(big, s, 1.0)
            small = np.where(big, 0.0, s)
            return np.where(big, r * r / self.mass, _reciprocal(self.mass * small * small))

    def elastic_receptance(self, s) -> np.ndarray:
        """Elastic part of the receptance: identically 0 (m/N). Shape of ``s``.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        return np.zeros(_check_s(s).shape, dtype=complex)

    def impulse_response(self, t) -> np.ndarray:
        """Exact ``h(t) = t/m`` (m/(N s)) for ``t >= 0``, 0 before. Shape of ``t``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = _check_times(t)
        return np.where(t >= 0.0, t / self.mass, 0.0)

    def step_response(self, t) -> np.ndarray:
        """Exact ``S(t) = t^2/(2m)`` (m/N) for ``t >= 0``, 0 before. Shape of ``t``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = _check_times(t)
        with np.errstate(over="ignore"):
            return np.where(t >= 0.0, 0.5 * t * t / self.mass, 0.0)

    # ----------------------------------------------------------------- properties
    @property
    def is_grounded(self) -> bool:
        """False: the mass is free."""
        return False

    @property
    def is_rational(self) -> bool:
        """True."""
        return True

    @property
    def static_flexibility(self) -> float:
        """0.0 m/N: a rigid body has no elastic part."""
        return 0.0

    @property
    def time_scale(self) -> None:
        """``None``: a rigid mass has no characteristic time."""
        return None

    # ----------------------------------------------------------------------- modes
    def _mode_count(self) -> int:
        return 0

    def _modes(self, n):
        return np.empty(0), np.empty(0)

    def _tail_flexibility(self, n) -> float:
        return 0.0


@dataclass(frozen=True)
class SpringMass(ExactModel):
    """A grounded single-degree-of-freedom oscillator struck on its mass.

    ``H(s) = 1/(m s^2 + c s + k)`` with ``c = 2 zeta sqrt(k m)``.

    Parameters
    ----------
    mass : float
        Mass ``m`` (kg), > 0.
    stiffness : float
        Spring stiffness ``k`` (N/m), > 0.
    damping_ratio : float, keyword-only, optional
        Viscous damping ratio ``0 <= zeta < 1`` (default 0: undamped).

    Notes
    -----
    With ``w_n = sqrt(k/m)``, ``w_d = w_n sqrt(1 - zeta^2)``:
    ``h(t) = exp(-zeta w_n t) sin(w_d t)/(m w_d)`` and
    ``S(t) = (1/k) [1 - exp(-zeta w_n t)(cos w_d t + zeta/sqrt(1 - zeta^2) sin w_d t)]``,
    evaluated without cancellation (a Taylor series for ``w_n t < 1``). Every result is
    exact to rounding. ``modal_model(1)`` is exact: with the default
    ``damping_ratio=None`` it keeps the model's own damping ratio.
    """

    mass: float
    stiffness: float
    damping_ratio: float = field(default=0.0, kw_only=True)

    def __post_init__(self):
        object.__setattr__(self, "mass", as_positive_scalar("mass", self.mass))
        object.__setattr__(self, "stiffness", as_positive_scalar("stiffness", self.stiffness))
        object.__setattr__(self, "damping_ratio",
                           _as_damping_ratio("damping_ratio", self.damping_ratio))

    # ------------------------------------------------------------------ derived
    @property
    def natural_frequency(self) -> float:
        """Undamped natural frequency ``w_n = sqrt(k/m)`` (rad/s)."""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def damped_frequency(self) -> float:
        """Damped natural frequency ``w_d = w_n sqrt(1 - zeta^2)`` (rad/s)."""
        return self.natural_frequency * math.sqrt(1.0 - self.damping_ratio**2)

    # ------------------------------------------------------------------ responses
    def receptance(self, s) -> np.ndarray:
        """Exact ``H(s)`` (m/N) at complex ``s`` (rad/s), any shape; no overflow.

        Evaluated as ``1/(k (u^2 + 2 zeta u + 1))``, ``u = s/w_n``, or for ``|u| > 1`` as
        ``v^2/(k (1 + 2 zeta v + v^2))``, ``v = 1/u``. ``inf`` at an exact pole.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        s = _check_s(s)
        u = s / self.natural_frequency
        zeta, k = self.damping_ratio, self.stiffness
        big = np.abs(u) > 1.0
        with np.errstate(under="ignore"):
            v = 1.0 / np.where(big, u, 1.0)
            w = np.where(big, 0.0, u)
            low = _reciprocal(k * (w * w + 2.0 * zeta * w + 1.0))
            high = v * v * _reciprocal(k * (1.0 + 2.0 * zeta * v + v * v))
        return np.where(big, high, low)

    def impulse_response(self, t) -> np.ndarray:
        """Exact ``h(t) = exp(-zeta w_n t) sin(w_d t)/(m w_d)`` (m/(N s)), 0 for ``t < 0``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = _check_times(t)
        tp = np.maximum(t, 0.0)
        wn, wd = self.natural_frequency, self.damped_frequency
        with np.errstate(under="ignore"):
            out = np.exp(-self.damping_ratio * wn * tp) * np.sin(wd * tp) / (self.mass * wd)
        return np.where(t >= 0.0, out, 0.0)

    def step_response(self, t) -> np.ndarray:
        """Exact step response ``S(t)`` (m/N), 0 for ``t < 0``; see the class notes.

        With ``x = w_n t``: for ``x < 1`` the Taylor series of
        ``f = k S`` (``f'' + 2 zeta f' + f = 1``, ``f(0) = f'(0) = 0``) summed to below
        rounding; for ``x >= 1`` ``f = -expm1(-a) cos b + 2 sin^2(b/2) - e^{-a} zeta/d sin b``
        with ``a = zeta x``, ``b = d x``, ``d = sqrt(1 - zeta^2)``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = _check_times(t)
        x = np.maximum(t, 0.0) * self.natural_frequency
        zeta = self.damping_ratio
        d = math.sqrt(1.0 - zeta * zeta)
        # Taylor coefficients: a_2 = 1/2, a_{j+2} = -(2 zeta (j+1) a_{j+1} + a_j)/((j+2)(j+1)).
        coef = [0.0, 0.0, 0.5]
        for j in range(1, 26):
            coef.append(-(2.0 * zeta * (j + 1) * coef[j + 1] + coef[j]) / ((j + 2) * (j + 1)))
        xs = np.minimum(x, 1.0)
        series = np.zeros_like(xs)
        for c in reversed(coef):
            series = series * xs + c
        a, b = zeta * x, d * x
        with np.errstate(under="ignore"):
            closed = (-np.expm1(-a) * np.cos(b) + 2.0 * np.sin(0.5 * b) ** 2
                      - np.exp(-a) * (zeta / d) * np.sin(b))
        f = np.where(x < 1.0, series, closed)
        return np.where(t >= 0.0, f / self.stiffness, 0.0)

    # ----------------------------------------------------------------- properties
    @property
    def is_grounded(self) -> bool:
        """True: the spring is attached to the ground."""
        return True

    @property
    def is_rational(self) -> bool:
        """True."""
        return True

    @property
    def static_flexibility(self) -> float:
        """``H(0) = 1/k`` (m/N)."""
        return 1.0 / self.stiffness

    @property
    def time_scale(self) -> float:
        """``1/w_n`` (s)."""
        return 1.0 / self.natural_frequency

    # ----------------------------------------------------------------------- modes
    def _mode_count(self) -> int:
        return 1

    def _modes(self, n):
        return (np.full(n, self.natural_frequency), np.full(n, self.mass))

    def _tail_flexibility(self, n) -> float:
        return 1.0 / self.stiffness if n == 0 else 0.0

    def _own_damping_ratio(self) -> float:
        return self.damping_ratio
