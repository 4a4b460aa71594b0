"""Least-squares complex-frequency (LSCF) pole estimation: pure array kernels.

The FRF is modelled as a common-denominator rational function in the z-domain basis
``z^j = exp(i omega dt j)`` with ``dt = pi / omega_max`` (Guillaume et al., 2003):

    H(omega) ~ sum_j b_j z^j / sum_j a_j z^j,

linearised as ``W (N - H D) ~ 0``. The numerator is eliminated through the reduced normal
equations ``M = 2 (T - S^T R^-1 S)``, and with ``a_n = 1`` each model order ``n`` costs one
small linear solve. Poles are ``s = log(z_k) / dt`` for the roots of the denominator. The
basis is unit-modulus on the whole band, so the problem is equally conditioned whatever
the frequency units.

Because ``|z| = 1`` on the band, ``R``, ``S`` and ``T`` are Toeplitz matrices: entry
``(j, k)`` depends on ``k - j`` only. Their generating vectors (length ``2 n + 1``) are one
sum over the lines each, so the normal equations cost ``O(n_lines n)``, not
``O(n_lines n^2)``.

A basis scaled to the whole band resolves poles at a small fraction of ``omega_max``
poorly (their ``z`` crowd near 1). :func:`lscf_subbands` therefore also runs LSCF on
nested low sub-bands ``[omega_0, omega_max / 4^k]``, each with its own ``dt``.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import toeplitz

__all__ = ["lscf_poles_all_orders", "lscf_basis_step", "lscf_normal_matrix", "lscf_subbands"]


def lscf_basis_step(omega: np.ndarray) -> float:
    """The z-domain sampling time ``dt = pi / omega_max`` (s)."""
    return float(np.pi / np.max(omega))


def lscf_normal_matrix(omega, values, weights, max_order, dt=None):
    """Reduced normal matrix ``T - S^T R^-1 S`` (shape ``(n + 1, n + 1)``) of one FRF.

    Built from the Toeplitz generating vectors
    ``sum_l w_l^2 {1, h_l, |h_l|^2} z_l^m`` for ``m = 0 .. n`` (negative ``m`` are their
    conjugates, ``|z| = 1``).
    """
    dt = lscf_basis_step(omega) if dt is None else dt
    n1 = max_order + 1
    # z^m by repeated multiplication (rounding grows like m eps: harmless for m < 1000)
    powers = np.empty((n1, omega.size), complex)
    powers[0] = 1.0
    if n1 > 1:
        powers[1:] = np.exp(1j * dt * omega)
        np.cumprod(powers[1:], axis=0, out=powers[1:])
    w2 = weights**2
    g = powers @ np.stack([w2, w2 * values, w2 * np.conj(values), w2 * np.abs(values) ** 2],
                          axis=1).astype(complex)
    # R_jk = Re sum w^2 z^(k-j), T_jk likewise with |h|^2: symmetric Toeplitz
    r = toeplitz(g[:, 0].real)
    t = toeplitz(g[:, 3].real)
    # S_jk = -Re sum w^2 conj(z^j) h z^k = -Re sum w^2 h z^(k-j)
    pos = g[:, 1]                       # m = k - j >= 0: sum w^2 h z^m
    neg = np.conj(g[:, 2])              # m <= 0: sum w^2 h z^-|m| = conj(sum w^2 conj(h) z^|m|)
    s = -toeplitz(neg.real, pos.real)   # first column m = -j, first row m = k
    try:
        return t - s.T @ np.linalg.solve(r, s)
    except np.linalg.LinAlgError:       # fewer independent lines than the order needs
        return t - s.T @ np.linalg.lstsq(r, s, rcond=None)[0]


def lscf_poles_all_orders(omega, values, weights, max_order, *, orders=None, dt=None,
                          origin=0.0):
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
    orders : iterable of int, optional
        The orders to solve (default ``1..max_order``); the others get no poles.
    dt : float, optional
        Basis step (default ``pi / (omega_max - origin)``).
    origin : float, optional
        The angular frequency (rad/s) mapped to ``z = 1``: the basis is
        ``exp(i (omega - origin) dt)``. A band far from 0 rad/s then spans the whole upper
        half of the unit circle instead of an arc near ``z = -1``, where high powers of
        ``z`` are nearly dependent and the normal equations lose the weaker modes. The
        poles are returned in the original frame (``origin`` added to their imaginary
        part); the mirror images of the real-coefficient polynomial lie below ``origin``.

    Returns
    -------
    list of ndarray
        ``poles[n - 1]``: the ``n`` poles of order ``n`` (complex, both halves of each
        conjugate pair, and real ones); finite only (a root at ``z = 0`` is dropped).
    """
    values = np.atleast_2d(values)
    weights = np.atleast_2d(weights)
    omega = np.asarray(omega, dtype=float) - origin
    dt = lscf_basis_step(omega) if dt is None else dt
    m_total = sum(lscf_normal_matrix(omega, h, w, max_order, dt)
                  for h, w in zip(values, weights))
    wanted = set(range(1, max_order + 1) if orders is None else orders)
    poles = []
    for n in range(1, max_order + 1):
        if n not in wanted:
            poles.append(np.zeros(0, complex))
            continue
        m = m_total[:n + 1, :n + 1]
        try:
            a = np.linalg.solve(m[:n, :n], -m[:n, n])
        except np.linalg.LinAlgError:
            a = np.linalg.lstsq(m[:n, :n], -m[:n, n], rcond=None)[0]
        # roots of a_0 + a_1 z + ... + z^n: eigenvalues of the companion matrix
        comp = np.zeros((n, n))
        comp[0, :] = -a[::-1]
        comp[np.arange(1, n), np.arange(n - 1)] = 1.0
        z = np.linalg.eigvals(comp)
        z = z[np.abs(z) > 1e-300]
        poles.append(np.log(z.astype(complex)) / dt + 1j * origin)
    return poles


def lscf_subbands(omega, values, weights, max_order, *, factor=4.0, min_lines=64,
                  peaks=None, zoom=False):
    """LSCF poles on the whole band and on nested low sub-bands.

    Sub-band ``k`` holds the lines ``omega <= omega_max / factor^k``; it is used while it has
    at least ``min_lines`` lines and (if ``peaks`` given, resonance-peak frequencies in
    rad/s) at least one peak below 80 % of its top. Its largest order is scaled down with
    the number of peaks it holds. Even orders only: a real polynomial of odd order spends
    a root on the real axis. With ``zoom`` (a segment of a wide band), a band whose lowest
    line lies above a tenth of its top gets its basis origin one line below its lowest
    line (``origin`` of :func:`lscf_poles_all_orders`): on a segment of a wide hammer FRF
    the weaker of close modes then stabilise. Not by default: the real-coefficient
    polynomial mirrors the band about its origin, a jump the model must then bridge at the
    band's low edge, which costs the noisiest data (coherence ~0.3) their one mode.

    ``values`` and ``weights`` may hold several outputs, shape (n_outputs, n_lines): their
    normal equations are summed (global LSCF: one common denominator, common poles).

    Returns
    -------
    list of (omega_top, poles_by_order)
        One entry per band, whole band first.
    """
    out = []
    top = float(np.max(omega))
    k = 0
    while True:
        mask = omega <= top
        if k > 0:
            if np.count_nonzero(mask) < min_lines:
                break
            if peaks is not None and not np.any(np.asarray(peaks) < 0.8 * top):
                break
        order = max_order
        if k > 0 and peaks is not None:
            n_peaks = int(np.count_nonzero(np.asarray(peaks) <= top))
            order = int(min(max_order, 4 * n_peaks + 16))
        om = omega[mask]
        origin = 0.0
        if zoom and om.size > 1 and om.min() > 0.1 * top:
            origin = float(om.min() - np.min(np.diff(np.sort(om))))
        poles = lscf_poles_all_orders(om, values[..., mask], weights[..., mask],
                                      order, orders=range(2, order + 1, 2), origin=origin)
        out.append((top, poles))
        top /= factor
        k += 1
    return out
