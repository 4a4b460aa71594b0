"""Exact model of a uniform Euler-Bernoulli cantilever beam struck at its free tip.

With ``K = EI/l^3`` (N/m), ``T = sqrt(m/K)`` (s) and ``e^4 = -s^2 T^2`` (method.md
section 2):

    H(s) = (cosh e sin e - sinh e cos e) / (K e^3 (1 + cosh e cos e))
         = (1/m) sum_{k>=1} 4 / (s^2 + eps_k^4 / T^2)

where ``eps_k`` are the roots of ``1 + cosh(e) cos(e) = 0`` (:func:`cantilever_roots`).
``H`` is exact (closed form). The time responses are the modal series

    h(t) = (4T/m) sum_k sin(eps_k^2 t/T) / eps_k^2
    S(t) = (4T^2/m) sum_k 2 sin^2(eps_k^2 t/(2T)) / eps_k^4

truncated after a number of terms chosen from a stated, rigorous error bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalid.validation import as_count, as_positive_scalar

from ._base import ExactModel, _check_s, _check_times, _reciprocal
from ._beam_transfer import (
    _DEN_SERIES,
    _folded_branch,
    _horner,
    _shape_ratios,
    _transfer,
    _weighted_series,
)
from ._transfer import _check_xi, _TransferMixin
from .roots import _power_tail, _terms_for_tail, cantilever_roots

__all__ = ["CantileverBeam"]

# Taylor series in z = e^4 (entire): N(e)/e^3 = sum_j 4 (-4)^j z^j/(4j+3)!, and
# 1 + cosh e cos e (_DEN_SERIES). For |z| < 1, 9 terms reach 1e-23.
_NUM_SERIES = np.array([4.0 * (-4.0) ** j / math.factorial(4 * j + 3) for j in range(9)])

# Memory bound of the series evaluation: elements per (times x modes) block.
_BLOCK = 1 << 20

DEFAULT_IMPULSE_RTOL = 1e-6
DEFAULT_STEP_RTOL = 1e-12


def _dimensionless_receptance(x: np.ndarray) -> np.ndarray:
    """``K H`` as a function of ``x = sT`` (complex array), without overflow or cancellation.

    ``|x| < 1``: the Taylor series in ``z = e^4 = -x^2``. Otherwise the branch
    ``e = sqrt(i x)`` rotated by a power of ``i`` into ``Re e >= |Im e|`` (``H`` depends on
    ``e^4`` only), and, for ``Im e >= 0`` (the conjugate otherwise, ``H`` being real on
    the real axis), with ``P = exp(-2e)``, ``Q = exp(2ie)``, ``G = 4 exp(-(1 - i) e)``,
    all of modulus <= 4 (the factor ``exp(e - ie)/4`` is divided out of both terms)::

        K H = [i (1+P)(1-Q) - (1-P)(1+Q)] / (e^3 [G + (1+P)(1+Q)])
    """
    small = np.abs(x) < 1.0
    z = -np.where(small, x, 0.0) ** 2
    series = _horner(_NUM_SERIES, z) / _horner(_DEN_SERIES, z)

    e, lower, p, q, denominator = _folded_branch(x, small)
    with np.errstate(under="ignore", over="ignore", invalid="ignore"):
        num = 1j * (1.0 + p) * (1.0 - q) - (1.0 - p) * (1.0 + q)
        r = 1.0 / e  # |e| >= 1; r**3 underflows (to 0) where e**3 would overflow
        direct = num * r**3 * _reciprocal(denominator)
    direct = np.where(lower, direct.conj(), direct)
    return np.where(small, series, direct)


def _as_tolerance(name: str, value) -> float:
    out = as_positive_scalar(name, value)
    if out >= 1.0:
        raise ValueError(f"{name} must be < 1, got {out!r}")
    return out


@dataclass(frozen=True)
class CantileverBeam(ExactModel, _TransferMixin):
    """Uniform Euler-Bernoulli cantilever beam struck at its free tip.

    Parameters
    ----------
    mass : float
        Total mass ``m = rho A l`` (kg), > 0.
    time_scale : float
        ``T = sqrt(m/K) = l^2 sqrt(rho A / (E I))`` (s), > 0, with ``K = EI/l^3``.

    Notes
    -----
    Natural frequencies ``w_k = eps_k^2 / T``, each with driving-point modal mass
    ``m/4``; ``H(0) = 1/(3K)`` (``sum eps_k^-4 = 1/12``). :attr:`time_scale` is ``T``
    itself (the first period is ``2 pi T / eps_1^2 = 1.787 T``).

    :meth:`receptance` is exact to rounding at every complex ``s``. :meth:`impulse_response`
    and :meth:`step_response` sum the first ``N`` modes; see their error bounds
    (:meth:`impulse_error_bound`, :meth:`step_error_bound`). The impulse response is
    a Riemann-type function (``h(0+) = 0``, ``h ~ sqrt(t)`` for small ``t``, no jumps):
    its series converges slowly, the step response's fast.

    Away from the tip (``xi`` = distance from the tip as a fraction of the length,
    ``xi = 1`` the clamp): :meth:`transfer_receptance` (closed form),
    :meth:`transfer_impulse_response` and :meth:`transfer_step_response` (modal series with
    the same bounds as at the tip), :meth:`mode_shapes`, :meth:`static_transfer_flexibility`
    (``(1 - xi)^2 (2 + xi) / (6K)``) and :meth:`multi_output_model`.
    """

    mass: float
    time_scale: float

    def __post_init__(self):
        object.__setattr__(self, "mass", as_positive_scalar("mass", self.mass))
        object.__setattr__(self, "time_scale", as_positive_scalar("time_scale",
                                                                  self.time_scale))

    @classmethod
    def from_material(cls, length, youngs_modulus, second_moment, area,
                      density) -> CantileverBeam:
        """Build from geometry and material.

        Parameters
        ----------
        length : float
            Length ``l`` (m), > 0.
        youngs_modulus : float
            Young's modulus ``E`` (Pa), > 0.
        second_moment : float
            Second moment of area ``I`` (m^4), > 0.
        area : float
            Cross-section area ``A`` (m^2), > 0.
        density : float
            Density ``rho`` (kg/m^3), > 0.

        Returns
        -------
        CantileverBeam
            ``mass = rho A l``, ``time_scale = sqrt(mass / (E I / l^3))``.
        """
        length = as_positive_scalar("length", length)
        youngs_modulus = as_positive_scalar("youngs_modulus", youngs_modulus)
        second_moment = as_positive_scalar("second_moment", second_moment)
        area = as_positive_scalar("area", area)
        density = as_positive_scalar("density", density)
        mass = density * area * length
        stiffness = youngs_modulus * second_moment / length**3
        return cls(mass, math.sqrt(mass / stiffness))

    # ------------------------------------------------------------------- derived
    @property
    def stiffness(self) -> float:
        """``K = EI/l^3 = m/T^2`` (N/m); the static tip stiffness is ``3K``."""
        return self.mass / self.time_scale**2

    # ------------------------------------------------------------------ receptance
    def receptance(self, s) -> np.ndarray:
        """Exact tip receptance ``H(s)`` (m/N) at complex ``s`` (rad/s), any shape.

        No overflow for any finite ``s`` (bounded exponentials only), no cancellation near
        ``s = 0`` (Taylor series in ``e^4 = -s^2 T^2`` for ``|sT| < 1``; ``H(0) = 1/(3K)``).
        For large ``|s|`` off the imaginary axis ``H ~ sqrt(2) / (K (sT)^(3/2))``. ``inf``
        at an exact pole, never ``nan``.

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
        return _dimensionless_receptance(s * self.time_scale) / self.stiffness

    # ---------------------------------------------------------------- time series
    def impulse_error_bound(self, n_terms) -> float:
        """Bound (m/(N s)) on ``|h(t) - h_N(t)|`` for all ``t`` with ``N = n_terms`` modes.

        ``(4T/m) sum_{k > N} eps_k^-2`` (the tail of the absolutely convergent series),
        ``~ 4T/(pi^2 m N)``.

        Parameters
        ----------
        n_terms : int
            Modes summed.

        Returns
        -------
        float
        """
        n = as_count("n_terms", n_terms)
        return 4.0 * self.time_scale / self.mass * _power_tail(n, 2)

    def step_error_bound(self, n_terms) -> float:
        """Bound (m/N) on ``|S(t) - S_N(t)|`` for all ``t`` with ``N = n_terms`` modes.

        Every omitted term ``(4T^2/m) 2 sin^2(.)/eps_k^4`` lies in
        ``[0, 8 T^2/(m eps_k^4)]``, so ``0 <= S - S_N <= (8T^2/m) sum_{k > N} eps_k^-4``
        ``~ 8T^2/(3 pi^4 m N^3)``.

        Parameters
        ----------
        n_terms : int
            Modes summed.

        Returns
        -------
        float
        """
        n = as_count("n_terms", n_terms)
        return 8.0 * self.time_scale**2 / self.mass * _power_tail(n, 4)

    def _n_terms(self, response: str, rtol, n_terms) -> int:
        if n_terms is not None:
            if rtol is not None:
                raise ValueError(f"give rtol or n_terms, not both: got rtol={rtol!r} and "
                                 f"n_terms={n_terms!r}")
            return as_count("n_terms", n_terms)
        if response == "impulse":
            rtol = _as_tolerance("rtol", DEFAULT_IMPULSE_RTOL if rtol is None else rtol)
            return _terms_for_tail(2, rtol / 4.0)  # (4T/m) tail2 <= rtol T/m
        rtol = _as_tolerance("rtol", DEFAULT_STEP_RTOL if rtol is None else rtol)
        return _terms_for_tail(4, rtol / 24.0)  # (8T^2/m) tail4 <= rtol T^2/(3m)

    def _series(self, t: np.ndarray, n: int, kind: str) -> np.ndarray:
        """``sum_{k<=n} c_k f(eps_k^2 t/T)`` in blocks of at most ``_BLOCK`` elements.

        ``kind="impulse"``: ``f = sin``, ``c_k = eps_k^-2``; ``kind="step"``:
        ``f = 2 sin^2(./2)``, ``c_k = eps_k^-4``. The phases are formed in turns and
        reduced to ``[-1/2, 1/2]`` before the sine (cheap, and as accurate as the phase).
        """
        tau = np.maximum(t, 0.0).ravel() / self.time_scale
        eps = cantilever_roots(n)
        freq = eps * eps
        turns_per_tau = freq / (2.0 * np.pi)
        weight = 1.0 / freq if kind == "impulse" else 1.0 / (freq * freq)
        out = np.zeros(tau.size)
        if n == 0 or tau.size == 0:
            return out.reshape(t.shape)
        t_block = min(tau.size, _BLOCK)
        k_block = max(1, _BLOCK // t_block)
        for i in range(0, tau.size, t_block):
            ti = tau[i:i + t_block]
            acc = np.zeros(ti.size)
            # Last modes (smallest terms) first.
            for j in reversed(range(0, n, k_block)):
                u = np.multiply.outer(ti, turns_per_tau[j:j + k_block])
                u -= np.rint(u)
                if kind == "impulse":
                    acc += np.sin(2.0 * np.pi * u) @ weight[j:j + k_block]
                else:
                    acc += (2.0 * np.sin(np.pi * u) ** 2) @ weight[j:j + k_block]
            out[i:i + t_block] = acc
        return out.reshape(t.shape)

    def impulse_response(self, t, *, rtol=None, n_terms=None) -> np.ndarray:
        """Tip impulse response ``h(t)`` (m/(N s)), 0 for ``t < 0``: truncated modal series.

        ``h_N(t) = (4T/m) sum_{k<=N} sin(eps_k^2 t/T)/eps_k^2``.

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        rtol : float, keyword-only, optional
            Error tolerance relative to ``T/m``: ``N`` is the smallest number of modes
            with :meth:`impulse_error_bound` ``<= rtol * T/m`` (default ``1e-6``,
            ``N = 405285``; the bound falls as ``0.405/N``).
        n_terms : int, keyword-only, optional
            Number of modes ``N`` instead of ``rtol`` (give one of the two).

        Returns
        -------
        ndarray of float, shape of ``t``
            ``h_N(t)``, with ``|h - h_N| <= impulse_error_bound(N)`` at every ``t``.

        Notes
        -----
        The bound is uniform in ``t`` (no sharper ``t``-dependent bound is claimed: ``h``
        is a Riemann-type function, continuous but not smooth). Cost ``O(N t.size)``
        (about 15 ms per time sample at the default ``rtol``); memory bounded by blocks
        of ``2**20`` elements.
        """
        t = _check_times(t)
        n = self._n_terms("impulse", rtol, n_terms)
        out = (4.0 * self.time_scale / self.mass) * self._series(t, n, "impulse")
        return np.where(t >= 0.0, out, 0.0)

    def step_response(self, t, *, rtol=None, n_terms=None) -> np.ndarray:
        """Tip step response ``S(t)`` (m/N), 0 for ``t < 0``: truncated modal series.

        ``S_N(t) = (4T^2/m) sum_{k<=N} 2 sin^2(eps_k^2 t/(2T))/eps_k^4``
        (``S_N(0) = 0``, no cancellation at small ``t``).

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        rtol : float, keyword-only, optional
            Error tolerance relative to the static flexibility ``1/(3K) = T^2/(3m)``:
            ``N`` is the smallest number of modes with :meth:`step_error_bound`
            ``<= rtol/(3K)`` (default ``1e-12``, ``N = 4347``).
        n_terms : int, keyword-only, optional
            Number of modes ``N`` instead of ``rtol`` (give one of the two).

        Returns
        -------
        ndarray of float, shape of ``t``
            ``S_N(t)``, with ``0 <= S - S_N <= step_error_bound(N)`` at every ``t``.

        Notes
        -----
        Cost ``O(N t.size)`` (about 0.15 ms per time sample at the default ``rtol``).
        Rounding: each phase is formed with relative error ~1e-16, so the absolute error
        grows like ``1e-16 eps_1^2 t/T`` relative to ``1/(3K)``: negligible for
        ``t < 1e3 T``.
        """
        t = _check_times(t)
        n = self._n_terms("step", rtol, n_terms)
        out = (4.0 * self.time_scale**2 / self.mass) * self._series(t, n, "step")
        return np.where(t >= 0.0, out, 0.0)

    # ------------------------------------------------------------ away from the tip
    def transfer_receptance(self, s, xi) -> np.ndarray:
        """Exact transfer receptance ``H(xi, s)`` (m/N) from the tip to positions ``xi``.

        Euler-Bernoulli, in closed form (not a modal sum): with ``e^4 = -s^2 T^2`` and
        ``W(xi)`` the deflection per unit tip force in units of ``1/K`` (``W'''' = e^4 W``,
        ``W''(0) = 0``, ``W'''(0) = 1``, ``W(1) = W'(1) = 0``)::

            K H = [(ch S - sh C)(cosh e xi + cos e xi) - (1 + C ch + S sh)(sinh e xi + sin e xi)
                   + 2 (1 + ch C) sinh e xi] / (2 e^3 (1 + ch C))

        (``ch, sh, C, S`` = ``cosh e, sinh e, cos e, sin e``). Equal to ``(1/m) sum_k
        4 psi_k(xi) / (s^2 + w_k^2)`` with ``psi_k = phi_k(xi)/phi_k(0)``.

        Parameters
        ----------
        s : array_like of complex, any shape
            Laplace variable (rad/s), finite.
        xi : float or array_like of float, shape (n_points,)
            Positions as fractions of the length from the tip, in ``[0, 1]`` (a scalar is
            treated as shape (1,)).

        Returns
        -------
        ndarray of complex, shape ``(n_points,) + s.shape``
            ``H(xi, s)``; equal to :meth:`receptance` at ``xi = 0`` to rounding; 0 at the
            clamp; ``H(xi, 0) = (1 - xi)^2 (2 + xi)/(6K)``. No overflow for any finite ``s``
            (a Taylor series in ``e^4`` for ``|sT| < 1``, bounded exponentials elsewhere);
            ``inf`` at an exact pole, never ``nan``. The absolute error is a few ulps of
            ``|H(0, s)|``.
        """
        s = _check_s(s)
        xi = _check_xi(xi)
        return _transfer(s * self.time_scale, xi, 1.0 / self.stiffness)

    def _transfer_series(self, t, xi, kind, rtol, n_terms) -> np.ndarray:
        t = _check_times(t)
        xi = _check_xi(xi)
        n = self._n_terms(kind, rtol, n_terms)
        eps = cantilever_roots(n)
        freq = eps * eps
        weights = _shape_ratios(eps, xi) / (freq if kind == "impulse" else freq * freq)
        tau = np.maximum(t, 0.0).ravel() / self.time_scale
        out = _weighted_series(tau, freq, weights, kind, _BLOCK).reshape(xi.shape + t.shape)
        scale = 4.0 * self.time_scale / self.mass
        if kind == "step":
            scale *= self.time_scale
        return np.where(t >= 0.0, scale * out, 0.0)

    def transfer_impulse_response(self, t, xi, *, rtol=None, n_terms=None) -> np.ndarray:
        """Transfer impulse response ``h(xi, t)`` (m/(N s)), 0 for ``t < 0``: modal series.

        ``h_N(xi, t) = (4T/m) sum_{k<=N} psi_k(xi) sin(eps_k^2 t/T)/eps_k^2``, with
        ``psi_k(xi) = phi_k(xi)/phi_k(0)``.

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        xi : float or array_like of float, shape (n_points,)
            Positions in ``[0, 1]``.
        rtol, n_terms : keyword-only, optional
            As in :meth:`impulse_response` (same default ``N``).

        Returns
        -------
        ndarray of float, shape ``(n_points,) + t.shape``
            ``h_N``, with ``|h - h_N| <= impulse_error_bound(N)`` at every ``t`` and ``xi``:
            the driving-point bound holds because ``|psi_k(xi)| <= 1`` (the tip moves most
            in every mode: checked on a fine grid for the first 2000 modes; beyond, to
            ``O(exp(-eps_k))``, ``psi_k = (cos a - sin a + exp(-a) + (-1)^(k+1) exp(-b))/2``
            with ``a = eps_k xi``, ``b = eps_k (1 - xi)``, of modulus <= 1, reached only at
            the tip). Cost ``O(N n_points t.size)``.
        """
        return self._transfer_series(t, xi, "impulse", rtol, n_terms)

    def transfer_step_response(self, t, xi, *, rtol=None, n_terms=None) -> np.ndarray:
        """Transfer step response ``S(xi, t)`` (m/N), 0 for ``t < 0``: modal series.

        ``S_N(xi, t) = (4T^2/m) sum_{k<=N} psi_k(xi) 2 sin^2(eps_k^2 t/(2T))/eps_k^4``.

        Parameters
        ----------
        t : array_like of float, any shape
            Times (s).
        xi : float or array_like of float, shape (n_points,)
            Positions in ``[0, 1]``.
        rtol, n_terms : keyword-only, optional
            As in :meth:`step_response` (same default ``N``, error relative to ``1/(3K)``).

        Returns
        -------
        ndarray of float, shape ``(n_points,) + t.shape``
            ``S_N``, with ``|S - S_N| <= step_error_bound(N)`` at every ``t`` and ``xi``
            (``|psi_k| <= 1``, see :meth:`transfer_impulse_response`; the sign of the
            error is known only at the tip).
        """
        return self._transfer_series(t, xi, "step", rtol, n_terms)

    def _shape_ratios(self, xi, n):
        return _shape_ratios(cantilever_roots(n), xi)

    def _elastic_static_transfer(self, xi):
        # Euler-Bernoulli deflection under a tip load P: P l^3 (1 - xi)^2 (2 + xi)/(6 EI)
        u = 1.0 - xi
        return u * u * (3.0 - u) / (6.0 * self.stiffness)

    # ----------------------------------------------------------------- properties
    @property
    def is_grounded(self) -> bool:
        """True: the beam is clamped."""
        return True

    @property
    def static_flexibility(self) -> float:
        """Static tip flexibility ``H(0) = 1/(3K) = T^2/(3m)`` (m/N)."""
        return 1.0 / (3.0 * self.stiffness)

    # ----------------------------------------------------------------------- modes
    def _mode_count(self) -> None:
        return None

    def _modes(self, n):
        eps = cantilever_roots(n)
        return eps * eps / self.time_scale, np.full(n, 0.25 * self.mass)

    def _tail_flexibility(self, n) -> float:
        # sum_{k>n} 4/(m w_k^2) = (4 T^2/m) sum_{k>n} eps_k^-4
        return 4.0 * self.time_scale**2 / self.mass * _power_tail(n, 4)
