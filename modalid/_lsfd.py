"""Residues for given poles (LSFD) and the joint nonlinear refinement: pure array kernels.

The receptance model, ``s = i omega``:

    H(s) = sum_k [ r_k/(s - p_k) + conj(r_k)/(s - conj p_k) ]
         + sum_j c_j/(s - sigma_j) + u/s^2 + d

with real unknowns ``Re r_k, Im r_k, c_j, u, d``. Passivity of a driving point (positive
modal mass ``-1/(2 Im p Im r)``) is ``Im r_k <= 0``; with ``u, d, c_j >= 0`` it makes a
bound-constrained linear least-squares problem (``scipy.optimize.lsq_linear``). Columns
are scaled to unit norm, so the solve does not depend on the frequency units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, lsq_linear

__all__ = ["Terms", "design_matrix", "fit_residues", "refine", "evaluate"]


@dataclass(frozen=True)
class Terms:
    """Which terms the model has besides the complex modes."""

    real_poles: np.ndarray
    rigid: bool
    upper: bool


def design_matrix(s, poles, terms: Terms):
    """Complex columns (lines x unknowns) in the order Re r, Im r per mode, c_j, u, d."""
    cols = []
    for p in poles:
        a = 1.0 / (s - p)
        b = 1.0 / (s - np.conj(p))
        cols += [a + b, 1j * (a - b)]
    for sig in terms.real_poles:
        cols.append(1.0 / (s - sig))
    if terms.rigid:
        cols.append(1.0 / s**2)
    if terms.upper:
        cols.append(np.ones_like(s))
    return np.stack(cols, axis=1) if cols else np.zeros((s.size, 0), complex)


def _bounds(n_modes, terms: Terms, passive):
    n = 2 * n_modes + len(terms.real_poles) + int(terms.rigid) + int(terms.upper)
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    if passive:
        hi[1:2 * n_modes:2] = 0.0                    # Im r <= 0
        lo[2 * n_modes:] = 0.0                       # c_j, u, d >= 0
    return lo, hi


def _unpack(x, n_modes, terms: Terms):
    r = x[0:2 * n_modes:2] + 1j * x[1:2 * n_modes:2]
    k = 2 * n_modes
    c = x[k:k + len(terms.real_poles)]
    k += len(terms.real_poles)
    u = x[k] if terms.rigid else 0.0
    k += int(terms.rigid)
    d = x[k] if terms.upper else 0.0
    return r, c, u, d


def fit_residues(omega, values, weights, poles, terms: Terms, *, passive=True):
    """Linear (bounded) least squares for the residues of fixed ``poles`` (Im p > 0).

    Returns ``(residues, real_residues, inverse_mass, flexibility, covariance, sse)``; the
    covariance (of the real unknowns) comes from the weighted normal matrix and the
    residual variance, ``sse`` is the weighted sum of squared residuals.
    """
    s = 1j * omega
    a = design_matrix(s, poles, terms) * weights[:, None]
    b = values * weights
    a_real = np.concatenate([a.real, a.imag])
    b_real = np.concatenate([b.real, b.imag])
    scale = np.linalg.norm(a_real, axis=0)
    scale[scale == 0] = 1.0
    an = a_real / scale
    # compress the tall problem to its triangular factor: same minimiser, tiny solve
    q, rmat = np.linalg.qr(an)
    qb = q.T @ b_real
    lo, hi = _bounds(len(poles), terms, passive)
    res = lsq_linear(rmat, qb, bounds=(lo, hi), method="bvls")
    x = res.x / scale
    dof = max(b_real.size - x.size, 1)
    sse = float(np.sum((a_real @ x - b_real) ** 2))
    cov_scaled = np.linalg.pinv(rmat.T @ rmat) * (sse / dof)
    cov = cov_scaled / np.outer(scale, scale)
    r, c, u, d = _unpack(x, len(poles), terms)
    return r, c, u, d, cov, sse


def evaluate(omega, poles, residues, real_poles, real_residues, inverse_mass, flexibility):
    """The receptance model at ``s = i omega``."""
    s = 1j * omega
    out = np.full(s.shape, flexibility, dtype=complex)
    if len(poles):
        sk = s[:, None]
        out += np.sum(residues / (sk - poles) + np.conj(residues) / (sk - np.conj(poles)), axis=1)
    if len(real_poles):
        out += np.sum(real_residues / (s[:, None] - real_poles), axis=1)
    if inverse_mass:
        out += inverse_mass / s**2
    return out


def refine(omega, values, weights, poles, residues, real_poles, real_residues, inverse_mass,
           flexibility, *, rigid, upper, passive=True, max_nfev=200, imag_bounds=None):
    """Joint weighted nonlinear least squares of every pole and residue.

    Parameters per complex mode: ``Re p, Im p, Re r, Im r``; per real pole ``sigma, c``;
    then ``u`` and ``d`` if present. Analytic Jacobian; bounds keep poles stable and, with
    ``passive``, modal masses positive; ``imag_bounds`` (pairs per complex pole) keeps a
    pole's ``Im p`` in a range (e.g. a residual pseudo-mode outside the band). Returns the
    refined parts and the ``scipy.optimize.OptimizeResult``.
    """
    s = 1j * omega
    n_c, n_r = len(poles), len(real_poles)
    x0 = []
    for p, r in zip(poles, residues):
        x0 += [p.real, p.imag, r.real, r.imag]
    for sig, c in zip(real_poles, real_residues):
        x0 += [sig, c]
    if rigid:
        x0.append(inverse_mass)
    if upper:
        x0.append(flexibility)
    x0 = np.array(x0, dtype=float)
    lo, hi = np.full(x0.size, -np.inf), np.full(x0.size, np.inf)
    hi[0:4 * n_c:4] = 0.0                      # Re p <= 0
    lo[1:4 * n_c:4] = 0.0                      # Im p >= 0
    if imag_bounds is not None:
        lo[1:4 * n_c:4] = [b[0] for b in imag_bounds]
        hi[1:4 * n_c:4] = [b[1] for b in imag_bounds]
    hi[4 * n_c:4 * n_c + 2 * n_r:2] = 0.0      # sigma <= 0
    if passive:
        hi[3:4 * n_c:4] = 0.0                  # Im r <= 0
        lo[4 * n_c + 1:4 * n_c + 2 * n_r:2] = 0.0
        lo[4 * n_c + 2 * n_r:] = 0.0
    x0 = np.clip(x0, lo, hi)
    w = weights

    def parts(x):
        xc = x[:4 * n_c].reshape(n_c, 4)
        p = xc[:, 0] + 1j * xc[:, 1]
        r = xc[:, 2] + 1j * xc[:, 3]
        xr = x[4 * n_c:4 * n_c + 2 * n_r].reshape(n_r, 2)
        k = 4 * n_c + 2 * n_r
        u = x[k] if rigid else 0.0
        d = x[k + int(rigid)] if upper else 0.0
        return p, r, xr[:, 0], xr[:, 1], u, d

    def residual(x):
        p, r, sig, c, u, d = parts(x)
        e = (evaluate(omega, p, r, sig, c, u, d) - values) * w
        return np.concatenate([e.real, e.imag])

    def jacobian(x):
        p, r, sig, c, u, d = parts(x)
        cols = np.zeros((s.size, x.size), dtype=complex)
        if n_c:
            a = 1.0 / (s[:, None] - p)
            b = 1.0 / (s[:, None] - np.conj(p))
            ra2, rb2 = r * a**2, np.conj(r) * b**2
            cols[:, 0:4 * n_c:4] = ra2 + rb2
            cols[:, 1:4 * n_c:4] = 1j * (ra2 - rb2)
            cols[:, 2:4 * n_c:4] = a + b
            cols[:, 3:4 * n_c:4] = 1j * (a - b)
        if n_r:
            q = 1.0 / (s[:, None] - sig)
            cols[:, 4 * n_c:4 * n_c + 2 * n_r:2] = c * q**2
            cols[:, 4 * n_c + 1:4 * n_c + 2 * n_r:2] = q
        k = 4 * n_c + 2 * n_r
        if rigid:
            cols[:, k] = 1.0 / s**2
        if upper:
            cols[:, k + int(rigid)] = 1.0
        cols *= w[:, None]
        return np.concatenate([cols.real, cols.imag])

    result = least_squares(residual, x0, jac=jacobian, bounds=(lo, hi), x_scale="jac",
                           method="trf", max_nfev=max_nfev, xtol=1e-12, ftol=1e-12, gtol=1e-12)
    return parts(result.x), result
