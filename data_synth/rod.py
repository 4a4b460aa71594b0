"""Exact model of a uniform rod in axial vibration, struck at its end ``x = l``.

With ``K = EA/l`` (N/m), ``T = l/c`` (one-way wave transit time, s), ``m = K T^2`` and
``eps = s T`` (method.md section 2):

* fixed at ``x = 0``: ``H = tanh(eps)/(K eps) = (1/m) sum_{k>=1} 2/(s^2 + ((k-1/2) pi/T)^2)``;
* free at ``x = 0``:  ``H = coth(eps)/(K eps) = (1/m) [1/s^2 + sum_{k>=1} 2/(s^2 + (k pi/T)^2)]``.

The impulse responses are the square wave and the staircase produced by the wave
reflections, and the step responses their exact integrals: everything here is closed
form and exact to rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from scipy.special import polygamma

from modalid.validation import as_choice, as_nonnegative_scalar, as_positive_scalar
from modalid.receptance import TimeScale

from ._base import ExactModel, _check_s, _check_times, _reciprocal
from ._transfer import _check_xi, _rod_transfer, _rod_waves, _TransferMixin

__all__ = ["Rod"]

SUPPORTS = ("free", "fixed")


def _bernoulli_numbers(n: int) -> list[Fraction]:
    """Exact Bernoulli numbers ``B_0 .. B_n`` (``B_1 = +1/2``; Akiyama-Tanigawa).

    ``scipy.special.bernoulli`` is only accurate to about 1e-12 relative; this is exact.
    """
    a = [Fraction(0)] * (n + 1)
    out = []
    for m in range(n + 1):
        a[m] = Fraction(1, m + 1)
        for j in range(m, 0, -1):
            a[j - 1] = j * (a[j - 1] - a[j])
        out.append(a[0])
    return out


def _coth_series_coefficients(n_terms: int) -> np.ndarray:
    """Coefficients ``c_j`` of ``(z coth z - 1)/z^2 = sum_{j>=0} c_j z^(2j)``.

    ``z coth z = sum_{n>=0} 2^(2n) B_(2n) z^(2n) / (2n)!`` (Bernoulli numbers), radius pi.
    """
    b = _bernoulli_numbers(2 * n_terms)
    return np.array([float(2 ** (2 * n) * b[2 * n] / math.factorial(2 * n))
                     for n in range(1, n_terms + 1)])


# |z| < 1: terms fall at least as (1/pi)^2 per order; 18 orders reach 1e-18.
_COTH_SERIES = _coth_series_coefficients(18)


def _elastic_free(eps: np.ndarray) -> np.ndarray:
    """``(eps coth eps - 1)/eps^2`` for complex ``eps``, stable everywhere.

    A Taylor series for ``|eps| < 1`` (no cancellation near 0, value 1/3 at 0), else
    ``(coth eps - 1/eps)/eps`` (no overflow for large ``|eps|``).
    """
    small = np.abs(eps) < 1.0
    z2 = np.where(small, eps, 0.0) ** 2
    series = np.zeros_like(z2)
    for c in reversed(_COTH_SERIES):
        series = series * z2 + c
    e = np.where(small, 1.0, eps)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        coth = _reciprocal(np.tanh(e))
        direct = (coth - 1.0 / e) / e
    return np.where(small, series, direct)


def _period_index(t: np.ndarray, period: float) -> np.ndarray:
    """Integer ``n >= 0`` with ``n * period <= t < (n + 1) * period`` in floating point.

    The products ``n * period`` are exactly the values :meth:`Rod.jump_times` returns,
    so the responses jump exactly there.
    """
    n = np.floor(np.maximum(t, 0.0) / period)
    n = n + ((n + 1.0) * period <= t)  # undo rounding of the division, either way
    n = n - (n * period > t)
    return np.maximum(n, 0.0)


@dataclass(frozen=True)
class Rod(ExactModel, _TransferMixin):
    """Uniform rod in axial vibration, struck at its end ``x = l``.

    Parameters
    ----------
    mass : float
        Total mass ``m`` (kg), > 0.
    transit_time : float
        One-way wave transit time ``T = l/c`` (s), > 0, ``c = sqrt(E/rho)``.
    support : {"free", "fixed"}, keyword-only
        Boundary condition of the far end ``x = 0`` (default ``"free"``).

    Notes
    -----
    Stiffness ``K = m/T^2 = EA/l``. Impulse responses (values at a jump are the right
    limits; the jumps are at the products ``2T * j`` listed by :meth:`jump_times`):

    * fixed: square wave ``+T/m`` on ``(0, 2T)``, ``-T/m`` on ``(2T, 4T)``, period ``4T``;
      its step response is the triangle wave rising to ``2T^2/m`` at ``2T``;
    * free: staircase ``(T/m)(2n+1)`` on ``(2nT, 2(n+1)T)``; its step response is
      ``(2T^2/m) n^2 + (T/m)(2n+1)(t - 2nT)`` (equal to the rigid ``t^2/(2m)`` at ``2nT``).

    Natural frequencies: fixed ``(k - 1/2) pi/T``, free ``k pi/T`` (``k >= 1``), each
    with driving-point modal mass ``m/2``.

    Away from the driving point (``xi`` = distance from the struck end as a fraction of the
    length, ``xi = 1`` the far end): :meth:`transfer_receptance`,
    :meth:`transfer_impulse_response`, :meth:`transfer_step_response` (closed forms, exact
    to rounding), :meth:`mode_shapes` ``sqrt(2/m) cos(k' pi xi)`` (``k' = k`` free,
    ``k - 1/2`` fixed), :meth:`static_transfer_flexibility` and
    :meth:`multi_output_model`.
    """

    mass: float
    transit_time: float
    support: str = field(default="free", kw_only=True)

    def __post_init__(self):
        object.__setattr__(self, "mass", as_positive_scalar("mass", self.mass))
        object.__setattr__(self, "transit_time",
                           as_positive_scalar("transit_time", self.transit_time))
        as_choice("support", self.support, SUPPORTS)

    @classmethod
    def from_material(cls, length, area, youngs_modulus, density, *,
                      support: str = "free") -> Rod:
        """Build from geometry and material.

        Parameters
        ----------
        length : float
            Length ``l`` (m), > 0.
        area : float
            Cross-section area ``A`` (m^2), > 0.
        youngs_modulus : float
            Young's modulus ``E`` (Pa), > 0.
        density : float
            Density ``rho`` (kg/m^3), > 0.
        support : {"free", "fixed"}, keyword-only
            Far-end boundary condition.

        Returns
        -------
        Rod
            ``mass = rho A l``, ``transit_time = l / sqrt(E/rho)``.
        """
        length = as_positive_scalar("length", length)
        area = as_positive_scalar("area", area)
        youngs_modulus = as_positive_scalar("youngs_modulus", youngs_modulus)
        density = as_positive_scalar("density", density)
        return cls(density * area * length, length / math.sqrt(youngs_modulus / density),
                   support=support)

    # ------------------------------------------------------------------- derived
    @property
    def stiffness(self) -> float:
        """Static axial stiffness ``K = EA/l = m/T^2`` (N/m)."""
        return self.mass / self.transit_time**2

    # ------------------------------------------------------------------ responses
    def receptance(self, s) -> np.ndarray:
        """Exact ``H(s)`` (m/N) at complex ``s`` (rad/s), any shape.

        Fixed: ``tanh(eps)/(K eps)`` (``1/K`` at 0). Free: ``1/(K eps tanh eps)``
        (``inf`` at 0). ``eps = sT``. ``np.tanh`` saturates to ``+-1`` for large
        ``|Re eps|`` without overflow, and ``tanh(eps)/eps`` has no cancellation near 0;
        at an exact pole the result is ``inf``, never ``nan``.

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
        eps = s * self.transit_time
        zero = eps == 0
        e = np.where(zero, 1.0, eps)
        K = self.stiffness
        with np.errstate(over="ignore", under="ignore"):
            th = np.tanh(e)
            if self.support == "fixed":
                return np.where(zero, 1.0 / K + 0j, th / (K * e))
            return np.where(zero, np.inf + 0j, _reciprocal(K * e * th))

    def elastic_receptance(self, s) -> np.ndarray:
        """Elastic part (m/N): fixed ``H(s)``; free ``(eps coth eps - 1)/(K eps^2)``.

        The free form is a Taylor series for ``|eps| < 1`` (``1/(3K)`` at 0) and
        ``(coth eps - 1/eps)/(K eps)`` elsewhere.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        if self.support == "fixed":
            return self.receptance(s)
        s = _check_s(s)
        return _elastic_free(s * self.transit_time) / self.stiffness

    def impulse_response(self, t) -> np.ndarray:
        """Exact impulse response ``h(t)`` (m/(N s)), 0 for ``t < 0``; see the class notes.

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
        T, m = self.transit_time, self.mass
        n = _period_index(t, 2.0 * T)
        if self.support == "fixed":
            out = (T / m) * (1.0 - 2.0 * np.mod(n, 2.0))
        else:
            out = (T / m) * (2.0 * n + 1.0)
        return np.where(t >= 0.0, out, 0.0)

    def step_response(self, t) -> np.ndarray:
        """Exact step response ``S(t)`` (m/N), 0 for ``t < 0``; see the class notes.

        Vectorised closed forms (no loop over reflections): fixed
        ``(T/m) min(u, 4T - u)`` with ``u = t mod 4T``; free
        ``(2T^2/m) n^2 + (T/m)(2n+1)(t - 2nT)``, ``n = floor(t/2T)``.

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
        T, m = self.transit_time, self.mass
        n = _period_index(t, 2.0 * T)
        u = np.clip(t - n * (2.0 * T), 0.0, 2.0 * T)  # time since the last reflection
        if self.support == "fixed":
            odd = np.mod(n, 2.0) == 1.0
            out = (T / m) * np.where(odd, 2.0 * T - u, u)
        else:
            out = (2.0 * T * T / m) * n * n + (T / m) * (2.0 * n + 1.0) * u
        return np.where(t >= 0.0, out, 0.0)

    # ------------------------------------------------------- away from the driving point
    def transfer_receptance(self, s, xi) -> np.ndarray:
        """Exact transfer receptance ``H(xi, s)`` (m/N) from the struck end to positions ``xi``.

        With ``eps = sT``, ``Z = m/T`` (the rod's impedance ``EA/c``) and ``u = 1 - xi``:

        * free:  ``H = cosh(eps u) / (Z s sinh eps)``;
        * fixed: ``H = sinh(eps u) / (Z s cosh eps)`` (0 at the fixed end ``xi = 1``).

        Parameters
        ----------
        s : array_like of complex, any shape
            Laplace variable (rad/s), finite.
        xi : float or array_like of float, shape (n_points,)
            Positions as fractions of the length from the struck end, in ``[0, 1]``
            (a scalar is treated as shape (1,)).

        Returns
        -------
        ndarray of complex, shape ``(n_points,) + s.shape``
            ``H(xi, s)``; at ``xi = 0`` it equals :meth:`receptance` to rounding. ``inf`` at
            ``s = 0`` for the free rod (and at an exact pole), never ``nan``; no overflow for
            any finite ``s`` (bounded exponentials for ``|Re sT| > 1``).
        """
        s = _check_s(s)
        xi = _check_xi(xi)
        return _rod_transfer(s * self.transit_time, xi, self.support, 1.0 / self.stiffness)

    def transfer_impulse_response(self, t, xi) -> np.ndarray:
        """Exact transfer impulse response ``h(xi, t)`` (m/(N s)), 0 for ``t < 0``.

        A staircase of reflected waves. The force's wave reaches ``xi`` at the times
        ``a_n = (2n + xi) T`` (travelling away from the struck end) and ``b_n = (2n + 2 - xi)
        T`` (after reflection at the far end), ``n >= 0``; each arrival changes ``h`` by
        ``1/Z = T/m``: free rod ``+`` at every arrival; fixed rod ``(-1)^n`` at ``a_n`` and
        ``-(-1)^n`` at ``b_n``. So the particle velocity under a unit step force is
        ``h``: at the free far end ``2/Z`` for ``T < t < 3T``. At a jump the value is the
        right limit. Vectorised closed form (no loop over reflections).

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        xi : float or array_like of float, shape (n_points,)
            Positions in ``[0, 1]``.

        Returns
        -------
        ndarray of float, shape ``(n_points,) + t.shape``
            Equal to :meth:`impulse_response` at ``xi = 0``.
        """
        t = _check_times(t)
        xi = _check_xi(xi)
        T = self.transit_time
        return (T / self.mass) * _rod_waves(t, xi, T, self.support, "impulse")

    def transfer_step_response(self, t, xi) -> np.ndarray:
        """Exact transfer step response ``S(xi, t)`` (m/N), 0 for ``t < 0``.

        ``S(xi, t) = integral_0^t h(xi, .) = (1/Z) sum_n (+-)(t - a_n)_+ (+-)(t - b_n)_+``
        with the arrivals and signs of :meth:`transfer_impulse_response`, in closed form:
        with ``N`` arrivals of a sequence so far and ``u`` the age of the last one,
        ``sum = N u + T N (N - 1)`` (free) or ``2T floor(N/2) + u [N odd]`` (fixed,
        alternating signs).

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        xi : float or array_like of float, shape (n_points,)
            Positions in ``[0, 1]``.

        Returns
        -------
        ndarray of float, shape ``(n_points,) + t.shape``
            Continuous in ``t``; zero until the wave arrives at ``t = xi T``; equal to
            :meth:`step_response` at ``xi = 0``.
        """
        t = _check_times(t)
        xi = _check_xi(xi)
        T = self.transit_time
        return (T / self.mass) * _rod_waves(t, xi, T, self.support, "step")

    def _shape_ratios(self, xi, n):
        # phi_k(xi)/phi_k(0) = cos(k' pi xi); phi_k(0) = sqrt(2/m)
        k = np.arange(1.0, n + 1.0) - (0.5 if self.support == "fixed" else 0.0)
        return np.cos(math.pi * np.multiply.outer(xi, k))

    def _elastic_static_transfer(self, xi):
        # fixed: H(xi, 0) = (1 - xi)/K; free: lim (H - 1/(m s^2)) = (1/3 - xi + xi^2/2)/K
        if self.support == "fixed":
            return (1.0 - xi) / self.stiffness
        return (1.0 / 3.0 - xi + 0.5 * xi * xi) / self.stiffness

    # ----------------------------------------------------------------- properties
    @property
    def is_grounded(self) -> bool:
        """True for ``support="fixed"``."""
        return self.support == "fixed"

    @property
    def static_flexibility(self) -> float:
        """Fixed: ``1/K``; free: the elastic part ``1/(3K)`` (m/N)."""
        return 1.0 / self.stiffness if self.support == "fixed" else 1.0 / (3.0 * self.stiffness)

    @property
    def time_scale(self) -> float:
        """The transit time ``T`` (s)."""
        return self.transit_time

    def time_scales(self) -> tuple:
        """``(TimeScale(T, "transit"),)``: the wave transit time (s).

        Returns
        -------
        tuple of modalid.receptance.TimeScale
        """
        return (TimeScale(self.transit_time, "transit"),)

    def jump_times(self, t_end) -> np.ndarray:
        """Jump times ``2T j`` (``j >= 1``) of :meth:`impulse_response` up to ``t_end`` (s).

        The fixed rod's ``h`` jumps by ``-+2T/m``, the free rod's by ``+2T/m``, at each.

        Parameters
        ----------
        t_end : float
            The end of the times of interest (s).

        Returns
        -------
        numpy.ndarray of float
            The jump times (s), ascending.
        """
        t_end = as_nonnegative_scalar("t_end", t_end)
        period = 2.0 * self.transit_time
        j = np.arange(1.0, math.floor(t_end / period) + 2.0)
        times = j * period
        return times[times <= t_end]

    # ----------------------------------------------------------------------- modes
    def _mode_count(self) -> None:
        return None

    def _modes(self, n):
        k = np.arange(1.0, n + 1.0)
        if self.support == "fixed":
            k = k - 0.5
        return k * (math.pi / self.transit_time), np.full(n, 0.5 * self.mass)

    def _tail_flexibility(self, n) -> float:
        # sum_{k>n} 2 T^2 / (m pi^2 x_k^2), x_k = k - 1/2 (fixed) or k (free): a trigamma.
        shift = 0.5 if self.support == "fixed" else 1.0
        return float(2.0 / (self.stiffness * math.pi**2) * polygamma(1, n + shift))
