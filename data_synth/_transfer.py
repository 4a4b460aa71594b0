"""Responses away from the driving point: shared validation, mode shapes, multi-output models.

Positions along a :class:`~data_synth.Rod` or a :class:`~data_synth.CantileverBeam` are
dimensionless: ``xi`` is the distance from the driving point (the struck end of the rod,
the tip of the cantilever) as a fraction of the length, ``0 <= xi <= 1`` (``xi = 1`` is
the rod's far end, the cantilever's clamp). A transfer receptance ``H(xi, s)`` (m/N) is
the displacement at ``xi`` (same axis and sign as the driving-point displacement) per
unit force at ``xi = 0``.

This module holds what the two models share: the check of ``xi``, the mixin
:class:`_TransferMixin` (public :meth:`~_TransferMixin.mode_shapes` and
:meth:`~_TransferMixin.multi_output_model`, built from two private hooks of each model)
and the rod's closed forms (exponential sums and reflected waves).
"""

from __future__ import annotations

import math

import numpy as np

from modalid import MultiOutputModalModel
from modalid.validation import as_real_array

from ._base import _as_damping_ratio, _as_flag

__all__ = []


# ------------------------------------------------------------------ validation
def _check_xi(xi) -> np.ndarray:
    """Validate positions ``xi``: finite reals in ``[0, 1]``, a scalar or 1-D.

    A scalar is treated as shape (1,). Raises ``TypeError``/``ValueError`` naming ``xi``
    and the offending value.
    """
    arr = as_real_array("xi", xi)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"xi must be a scalar or 1-D (n_points,), got shape {arr.shape}")
    bad = (arr < 0.0) | (arr > 1.0)
    if np.any(bad):
        raise ValueError(f"xi must lie in [0, 1] (a fraction of the length from the driving "
                         f"point), got {float(arr[bad][0])!r} among its values")
    return arr


def _safe_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """``num / den`` for complex arrays: ``inf + 0j`` where ``den == 0`` or the quotient
    overflows, 0 where ``num == 0``; never ``nan`` (``inf + 0j`` times a number would give a
    ``nan`` imaginary part, so the scale factors go into ``num`` before the division)."""
    zero = den == 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        q = num / np.where(zero, 1.0, den)
    bad = zero | ~np.isfinite(q)
    return np.where(num == 0, 0.0 + 0j, np.where(bad, np.inf + 0j, q))


def _accurate_sum(terms: np.ndarray) -> np.ndarray:
    """Row sums of a 2-D float array, each correctly rounded (``math.fsum``)."""
    return np.array([math.fsum(row) for row in terms], dtype=float)


# ------------------------------------------------------------------- the mixin
class _TransferMixin:
    """Mode shapes and multi-output modal models of a continuum with a driving point.

    The host class (an :class:`~data_synth.ExactModel`) provides ``_modes``,
    ``_tail_flexibility``, ``modal_model``, ``inverse_mass`` and the hooks
    :meth:`_shape_ratios` and :meth:`_elastic_static_transfer`.
    """

    __slots__ = ()

    def _shape_ratios(self, xi: np.ndarray, n: int) -> np.ndarray:  # pragma: no cover
        """``phi_k(xi) / phi_k(0)`` for the first ``n`` elastic modes, shape (n_points, n)."""
        raise NotImplementedError

    def _elastic_static_transfer(self, xi: np.ndarray) -> np.ndarray:  # pragma: no cover
        """``sum_k phi_k(xi) phi_k(0) / w_k^2`` over all elastic modes (m/N), shape (n_points,)."""
        raise NotImplementedError

    def mode_shapes(self, xi, n_modes) -> np.ndarray:
        """Mass-normalised shapes of the first ``n_modes`` elastic modes at positions ``xi``.

        Parameters
        ----------
        xi : float or array_like of float, shape (n_points,)
            Positions as fractions of the length from the driving point, in ``[0, 1]``
            (a scalar is treated as shape (1,)).
        n_modes : int
            Number of elastic modes, >= 0 (rigid-body motion excluded).

        Returns
        -------
        ndarray of float, shape (n_points, n_modes)
            ``phi_k(xi)`` (1/sqrt(kg)), normalised so that ``integral_0^1 m phi_j phi_k dxi
            = delta_jk`` (``m`` the total mass) and signed so that ``phi_k(0) > 0``;
            ``phi_k(0)^2 = 1/m_k`` with ``m_k`` the driving-point modal mass, so the
            driving-point receptance is ``sum_k phi_k(0)^2/(s^2 + w_k^2)`` (plus ``1/(m s^2)``
            for a free body) and the transfer receptance ``sum_k phi_k(xi) phi_k(0)/(s^2 +
            w_k^2)``.
        """
        xi = _check_xi(xi)
        n = self._checked_mode_count("n_modes", n_modes)
        modal_mass = self._modes(n)[1]
        return self._shape_ratios(xi, n) / np.sqrt(modal_mass)

    def static_transfer_flexibility(self, xi) -> np.ndarray:
        """Static (elastic) transfer flexibility (m/N) at positions ``xi``.

        ``sum_k phi_k(xi) phi_k(0) / w_k^2`` over all elastic modes: for a grounded model
        ``transfer_receptance(0, xi)``, for a free one the limit of ``H(xi, s) - 1/(m s^2)``
        as ``s -> 0``. Equals :attr:`static_flexibility` at ``xi = 0``.

        Parameters
        ----------
        xi : float or array_like of float, shape (n_points,)
            Positions in ``[0, 1]``.

        Returns
        -------
        ndarray of float, shape (n_points,)
        """
        return self._elastic_static_transfer(_check_xi(xi))

    def _transfer_tail(self, xi: np.ndarray, n: int) -> np.ndarray:
        """``sum_{k > n} phi_k(xi) phi_k(0) / w_k^2`` (m/N), shape (n_points,).

        At ``xi = 0`` the model's closed-form driving-point tail; elsewhere the exact static
        transfer flexibility minus the kept modes' part, summed with correct rounding
        (``math.fsum``): the absolute error is a few ulps of the static flexibility.
        """
        out = self._elastic_static_transfer(xi)
        if n:
            omega, modal_mass = self._modes(n)
            head = self._shape_ratios(xi, n) / (modal_mass * omega**2)
            total = out[:, None]
            out = _accurate_sum(np.concatenate([total, -head], axis=1))
        return np.where(xi == 0.0, float(self._tail_flexibility(n)), out)

    def multi_output_model(self, xi, n_modes, *, damping_ratio=None, residual=False):
        """Truncated modal model of the receptances from the driving point to positions ``xi``.

        Parameters
        ----------
        xi : array_like of float, shape (n_points,)
            Distinct positions in ``[0, 1]`` (fractions of the length from the driving
            point); must contain ``0.0``, the driving point, whose index becomes the model's
            ``driving_point``.
        n_modes : int
            Number of elastic modes kept, >= 0.
        damping_ratio : float or None, optional
            As in :meth:`modal_model`: ``None`` keeps the model's own (zero) damping, a
            float in ``[0, 1)`` gives every kept mode that viscous damping ratio.
        residual : bool, optional
            If True, each output gets the omitted modes' static transfer flexibility
            ``sum_{k > n_modes} phi_k(xi) phi_k(0) / w_k^2`` as its ``flexibility``: at the
            driving point the closed form of :meth:`modal_model`, elsewhere the exact static
            transfer flexibility (:meth:`static_transfer_flexibility`) minus the kept
            modes' part, correctly rounded (a few ulps of the static flexibility).

        Returns
        -------
        modalid.MultiOutputModalModel
            Poles shared by all outputs (those of :meth:`modal_model`), residues ``r_ik =
            phi_k(xi_i) phi_k(0) / (2 i w_dk)``, ``inverse_mass = 1/m`` at every output of a
            free body (0 if grounded), outputs labelled ``f"xi={v:g}"``. Its driving row
            equals ``self.modal_model(n_modes, damping_ratio=..., residual=...)`` exactly.

        Raises
        ------
        ValueError
            If ``xi`` lacks ``0.0``, has repeated values, or lies outside ``[0, 1]``.
        """
        xi = _check_xi(xi)
        driving = np.flatnonzero(xi == 0.0)
        if driving.size == 0:
            raise ValueError(f"xi must contain 0.0 (the driving point), got {xi.tolist()!r}")
        if np.unique(xi).size != xi.size:
            values, counts = np.unique(xi, return_counts=True)
            raise ValueError(f"xi values must be distinct, got {float(values[counts > 1][0])!r} "
                             f"{counts[counts > 1][0]} times")
        n = self._checked_mode_count("n_modes", n_modes)
        if damping_ratio is not None:
            _as_damping_ratio("damping_ratio", damping_ratio)
        residual = _as_flag("residual", residual)
        row = self.modal_model(n, damping_ratio=damping_ratio, residual=residual)
        ratios = self._shape_ratios(xi, n)
        ratios[driving[0]] = 1.0  # exact: the driving row is the modal model's own
        residues = ratios * row.residues[None, :]
        flexibility = self._transfer_tail(xi, n) if residual else np.zeros(xi.size)
        flexibility[driving[0]] = row.flexibility
        labels = [f"xi={v:g}" for v in xi]
        if len(set(labels)) != xi.size:
            labels = [f"xi={v!r}" for v in xi.tolist()]
        return MultiOutputModalModel(poles=row.poles, residues=residues,
                                     inverse_mass=np.full(xi.size, row.inverse_mass),
                                     flexibility=flexibility, driving_point=int(driving[0]),
                                     outputs=tuple(labels))


# ========================================================================== rod
def _expm1c(z: np.ndarray) -> np.ndarray:
    """``exp(z) - 1`` for complex ``z`` without cancellation for small ``|z|``.

    ``expm1(x) cos y - 2 sin^2(y/2) + i exp(x) sin y``, ``z = x + iy``.
    """
    x, y = z.real, z.imag
    with np.errstate(over="ignore", under="ignore"):
        return (np.expm1(x) * np.cos(y) - 2.0 * np.sin(0.5 * y) ** 2) + 1j * np.exp(x) * np.sin(y)


def _sinhc(w: np.ndarray) -> np.ndarray:
    """``sinh(w)/w`` (1 at 0) for complex ``w`` with ``|Re w| <= 1``."""
    tiny = np.abs(w) < 1e-4
    safe = np.where(tiny, 1.0, w)
    return np.where(tiny, 1.0 + w * w / 6.0, np.sinh(safe) / safe)


def _rod_transfer(eps: np.ndarray, xi: np.ndarray, support: str, flex: float) -> np.ndarray:
    """``H(xi, s)`` of a rod as a function of ``eps = sT`` (complex array, any shape), with
    ``flex = 1/K`` (m/N).

    Free: ``cosh(eps (1-xi)) / (eps sinh eps)``; fixed: ``sinh(eps (1-xi)) / (eps cosh eps)``;
    both even in ``eps``, so ``Re eps >= 0`` is taken. Returns shape ``xi.shape + eps.shape``.

    ``Re eps <= 1``: the hyperbolic functions directly (no overflow; ``sinh(w)/w`` kept
    accurate near 0). ``Re eps > 1``: bounded exponentials, ``|exp(-2 eps)| < e^-2``::

        free:  [exp(-eps xi) + exp(-eps (2 - xi))] / (eps (1 - exp(-2 eps)))
        fixed: -exp(-eps xi) expm1(-2 eps (1 - xi)) / (eps (1 + exp(-2 eps)))

    (the ``expm1`` keeps the relative accuracy near the fixed end). ``inf`` at an exact
    pole (and at ``eps = 0`` for the free rod), never ``nan``.
    """
    e = np.where(eps.real < 0.0, -eps, eps)[None, ...]
    x = xi.reshape(xi.shape + (1,) * eps.ndim)
    u = 1.0 - x
    near = e.real <= 1.0
    en = np.where(near, e, 0.5)   # placeholders keep both branches finite
    ef = np.where(near, 2.0, e)
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        if support == "free":
            num_near = flex * np.cosh(en * u)
            den_near = en * np.sinh(en)
            num_far = np.exp(-ef * x) + np.exp(-ef * (1.0 + u))
            scale_far = flex / ef / -_expm1c(-2.0 * ef)
        else:
            num_near = flex * u * _sinhc(en * u)
            den_near = np.cosh(en)
            num_far = -np.exp(-ef * x) * _expm1c(-2.0 * ef * u)
            scale_far = flex / ef / (1.0 + np.exp(-2.0 * ef))
        far_value = num_far * scale_far  # finite: |1 -+ exp(-2 eps)| > 1 - e^-2
    return np.where(near, _safe_ratio(num_near, den_near), far_value)


def _arrivals(t: np.ndarray, c: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    """Count ``N`` of arrivals ``a_n = (2n + c) T <= t`` (``n >= 0``) and ``u = t - a_{N-1}``.

    ``c`` broadcasts against ``t``; ``u = 0`` where ``N = 0``. The floor of the division is
    corrected either way so that ``N`` is exact for the floating-point products ``a_n``.
    """
    t = np.maximum(t, 0.0)
    n = np.floor((t / T - c) / 2.0)  # index of the last arrival, -1 or less if none
    n = n + ((2.0 * (n + 1.0) + c) * T <= t)
    n = n - ((2.0 * n + c) * T > t)
    n = np.maximum(n, -1.0)
    count = n + 1.0
    u = np.where(count > 0, np.clip(t - (2.0 * n + c) * T, 0.0, 2.0 * T), 0.0)
    return count, u


def _rod_waves(t: np.ndarray, xi: np.ndarray, T: float, support: str, kind: str) -> np.ndarray:
    """Reflected-wave sums of the rod's transfer responses, times ``Z = m/T`` (so in s or s^2/s).

    With ``H = (1/(Z s)) sum_{n>=0} (+-1)^n [exp(-s a_n) +- exp(-s b_n)]``, ``a_n = (2n + xi) T``,
    ``b_n = (2n + 2 - xi) T`` (free: all signs +; fixed: ``(-1)^n`` and ``-`` before ``b_n``):
    ``Z h`` counts the arrivals so far, ``Z S`` sums their ages ``t - a_n``. Closed forms
    in the arrival counts (no loop over reflections). Shape ``xi.shape + t.shape``.
    """
    x = xi.reshape(xi.shape + (1,) * t.ndim)
    tt = t[None, ...]
    n1, u1 = _arrivals(tt, x, T)
    n2, u2 = _arrivals(tt, 2.0 - x, T)
    if support == "free":
        if kind == "impulse":
            out = n1 + n2
        else:  # sum_{j<N} (u + 2jT) = N u + T N (N - 1)
            out = n1 * u1 + T * n1 * (n1 - 1.0) + n2 * u2 + T * n2 * (n2 - 1.0)
    else:
        odd1, odd2 = np.mod(n1, 2.0), np.mod(n2, 2.0)
        if kind == "impulse":
            out = odd1 - odd2
        else:  # alternating sum: 2T floor(N/2) + (u if N odd); n1 - n2 is 0 or 1
            out = (2.0 * T) * (np.floor(n1 / 2.0) - np.floor(n2 / 2.0)) + odd1 * u1 - odd2 * u2
    return np.where(tt >= 0.0, out, 0.0)
