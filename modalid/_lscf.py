"""Least-squares complex-frequency (LSCF) pole estimation: pure array kernels.

The FRF is modelled as a common-denominator rational function in the z-domain basis
``z^j = exp(i omega dt j)`` with ``dt = pi / omega_max`` (Guillaume et al., 2003):

    H(omega) ~ sum_j b_j z^j / sum_j a_j z^j,

linearised as ``W (N - H D) ~ 0``. The numerator is eliminated through the reduced normal
equations ``M = 2 (T - S^T R^-1 S)``, and with ``a_n = 1`` each model order ``n`` costs one
small linear solve. Poles are ``s = log(z_k) / dt`` for the roots of the denominator. The
basis is unit-modulus on the whole band, so the problem is equally conditioned whatever
the frequency units.
"""

from __future__ import annotations

import numpy as np

__all__ = ["lscf_poles_all_orders", "lscf_basis_step"]


def lscf_basis_step(omega: np.ndarray) -> float:
    """The z-domain sampling time ``dt = pi / omega_max`` (s)."""
    return float(np.pi / np.max(omega))


def lscf_poles_all_orders(omega, values, weights, max_order, *, outputs_axis=None):
    """Poles of every order ``1..max_order`` (continuous time, rad/s).

    Parameters
    ----------
    omega : ndarray, shape (n_lines,)
        Angular frequencies (rad/s).
    values : ndarray, shape (n_lines,) or (n_outputs, n_lines)
        FRF values (any quantity: poles do not depend on it).
    weights : ndarray, same shape as ``values``
        Real weights per line (e.g. ``1/|H|``).
    max_order : int
        Largest denominator order.

    Returns
    -------
    list of ndarray
        ``poles[n - 1]``: the ``n`` poles of order ``n`` (complex, both halves of each
        conjugate pair, and real ones).
    """
    values = np.atleast_2d(values)
    weights = np.atleast_2d(weights)
    dt = lscf_basis_step(omega)
    basis = np.exp(1j * np.outer(omega, np.arange(max_order + 1)) * dt)  # (lines, n+1)
    n1 = max_order + 1
    m_total = np.zeros((n1, n1))
    for h, w in zip(values, weights):
        x = w[:, None] * basis                      # numerator columns
        y = -(w * h)[:, None] * basis               # denominator columns
        r = (x.conj().T @ x).real
        s = (x.conj().T @ y).real
        t = (y.conj().T @ y).real
        m_total += t - s.T @ np.linalg.solve(r, s)
    poles = []
    for n in range(1, max_order + 1):
        m = m_total[:n + 1, :n + 1]
        try:
            a = np.linalg.solve(m[:n, :n], -m[:n, n])
        except np.linalg.LinAlgError:
            a = np.linalg.lstsq(m[:n, :n], -m[:n, n], rcond=None)[0]
        coeffs = np.concatenate([a, [1.0]])          # a_0 .. a_n
        z = np.roots(coeffs[::-1])
        with np.errstate(divide="ignore"):
            poles.append(np.log(z) / dt)
    return poles
