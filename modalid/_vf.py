"""Relaxed vector fitting (Gustavsen and Semlyen 1999; Gustavsen 2006): pole relocation.

Starting poles ``a_n`` (complex pairs spread over the band, logarithmically when it spans
decades, damping 1 %), each iteration
solves the linear problem

    sigma(s) H(s) ~ sum c_n/(s - a_n) + d,     sigma(s) = sum c~_n/(s - a_n) + d~,

with the relaxation ``Re sum_k (sum c~_n/(s_k - a_n) + d~) = n_lines`` that keeps the
trivial solution out, and takes the zeros of ``sigma`` (the eigenvalues of
``A - b c~^T / d~`` in real block form) as the new poles. Unstable poles are flipped
into the left half-plane. Only the poles are used: residues come from the common
bounded LSFD step.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve_triangular

__all__ = ["vector_fit_poles"]


def _real_blocks(poles):
    """Real (A, b) of ``sum 1/(s - a_n)`` over conjugate pairs, and the complex columns."""
    n = 2 * len(poles)
    a = np.zeros((n, n))
    b = np.zeros(n)
    for k, p in enumerate(poles):
        i = 2 * k
        a[i:i + 2, i:i + 2] = [[p.real, p.imag], [-p.imag, p.real]]
        b[i:i + 2] = [2.0, 0.0]
    return a, b


def _columns(s, poles):
    cols = []
    for p in poles:
        a = 1.0 / (s - p)
        b = 1.0 / (s - np.conj(p))
        cols += [a + b, 1j * (a - b)]
    return np.stack(cols, axis=1)


def vector_fit_poles(omega, values, weights, n_pairs, *, start=None, rigid=False, n_iter=20,
                     tol=1e-10):
    """Relocated complex poles (Im p > 0), ``n_pairs`` of them, and the iterations used.

    ``start`` (rad/s, optional) are frequencies to start from, e.g. the resonance peaks;
    the remaining poles are spread over the band (logarithmically when it spans decades).
    ``rigid`` adds a mass line ``e/s^2`` to the fitted numerator (a free body, or the
    modes below the band): without it the poles bend to imitate one.
    """
    s = 1j * omega
    low = omega[0] if omega[0] > 0 else omega[1]
    start = np.zeros(0) if start is None else np.sort(np.asarray(start, float))[:n_pairs]
    n_fill = n_pairs - start.size
    spread = np.geomspace if omega[-1] > 10 * low else np.linspace
    beta = np.sort(np.concatenate([start, spread(low, omega[-1], n_fill + 2)[1:-1]
                                   if n_fill else []]))
    poles = -0.01 * beta + 1j * beta
    w = weights
    n_lines = s.size
    for iteration in range(1, n_iter + 1):
        phi = _columns(s, poles)                       # (lines, 2 n)
        known = np.ones((n_lines, 2 if rigid else 1), dtype=complex)
        if rigid:
            known[:, 1] = 1.0 / s**2
        # unknowns: [c (2n), d (, e), c~ (2n), d~]
        left = np.hstack([phi, known, -values[:, None] * phi, -values[:, None]]) * w[:, None]
        rows = np.concatenate([left.real, left.imag])
        rhs = np.zeros(rows.shape[0])
        # relaxation row: Re sum over lines of sigma = n_lines (scaled by the line count)
        relax = np.concatenate([np.zeros(phi.shape[1] + known.shape[1]),
                                np.sum(phi, axis=0).real, [n_lines]]) / n_lines
        rows = np.vstack([rows, relax * np.sqrt(np.sum(np.abs(values * w) ** 2))])
        rhs = np.append(rhs, np.sqrt(np.sum(np.abs(values * w) ** 2)))
        scale = np.linalg.norm(rows, axis=0)
        scale[scale == 0] = 1.0
        x = None
        if rows.shape[0] >= rows.shape[1]:         # else a few-line band: minimum norm
            q, r = np.linalg.qr(rows / scale)
            try:
                x = solve_triangular(r, q.T @ rhs) / scale
            except np.linalg.LinAlgError:
                pass                               # singular: the minimum-norm solution
        if x is None:
            x = np.linalg.lstsq(rows / scale, rhs, rcond=None)[0] / scale
        m, k = phi.shape[1], known.shape[1]
        c_tilde, d_tilde = x[m + k:2 * m + k], x[2 * m + k]
        if abs(d_tilde) < 1e-8:
            d_tilde = 1e-8 if d_tilde >= 0 else -1e-8
        a_mat, b_vec = _real_blocks(poles)
        # sigma's real block form: c~ on the blocks' states matches the columns (a+b, i(a-b))
        c_real = np.zeros(2 * len(poles))
        c_real[0::2] = c_tilde[0::2]
        c_real[1::2] = c_tilde[1::2]
        zeros = np.linalg.eigvals(a_mat - np.outer(b_vec, c_real) / d_tilde)
        zeros = np.where(zeros.real > 0, -zeros.real + 1j * zeros.imag, zeros)  # flip
        new = np.sort_complex(zeros[zeros.imag > 0])
        if new.size != len(poles):  # a pair turned real: keep the old poles for it
            new = np.concatenate([new, poles[new.size:]])[:len(poles)]
        change = np.max(np.abs(new - poles) / np.abs(poles))
        poles = new
        if change < tol:
            return poles, iteration
    return poles, n_iter
