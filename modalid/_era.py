"""Poles from impulse responses by python-control's eigensystem realization (ERA).

For each order the discrete-time realization's eigenvalues ``z`` become continuous poles
``s = log(z) / dt``. Residues then follow from a bounded linear least-squares fit of the
samples ``h(t_k) = sum 2 Re(r e^{p t}) + sum c e^{sigma t} + u t`` (time-domain LSFD).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear

__all__ = ["era_poles_all_orders", "fit_residues_time"]


def era_poles_all_orders(h, dt, max_order, *, hankel_size=None):
    """Poles (rad/s) of the ERA realizations of orders 2, 4, ..., ``max_order``.

    Returns a list indexed like the LSCF one (entry ``k`` holds the poles of order
    ``k + 1``; odd orders are empty).
    """
    import control

    h = np.asarray(h, dtype=float)
    size = hankel_size or int(min(h.size // 2 - 1, max(4 * max_order, 200)))
    markov = h * dt  # impulse of unit area -> discrete Markov parameters
    out = []
    for order in range(1, max_order + 1):
        if order % 2:
            out.append(np.zeros(0, complex))
            continue
        sysd, _ = control.eigensys_realization(markov, order, m=size, n=size, dt=dt)
        z = np.linalg.eigvals(np.asarray(sysd.A))
        with np.errstate(divide="ignore"):
            out.append(np.log(z.astype(complex)) / dt)
    return out


def fit_residues_time(t, h, poles, real_poles, *, rigid, passive=True):
    """Residues of fixed poles from impulse-response samples (bounded least squares).

    Returns ``(residues, real_residues, inverse_mass)``.
    """
    cols = []
    for p in poles:
        e = np.exp(p * t)
        cols += [2 * e.real, -2 * e.imag]   # 2 Re(r e) = 2 (Re r Re e - Im r Im e)
    for sig in real_poles:
        cols.append(np.exp(sig * t))
    if rigid:
        cols.append(t)
    a = np.stack(cols, axis=1)
    scale = np.linalg.norm(a, axis=0)
    scale[scale == 0] = 1.0
    n_c = len(poles)
    lo, hi = np.full(a.shape[1], -np.inf), np.full(a.shape[1], np.inf)
    if passive:
        hi[1:2 * n_c:2] = 0.0
        lo[2 * n_c:] = 0.0
    x = lsq_linear(a / scale, h, bounds=(lo, hi), method="bvls").x / scale
    r = x[0:2 * n_c:2] + 1j * x[1:2 * n_c:2]
    c = x[2 * n_c:2 * n_c + len(real_poles)]
    u = x[-1] if rigid else 0.0
    return r, c, u
