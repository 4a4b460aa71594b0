"""Compiled kernels (numba) for sums of exponentials: sampling, values, root polishing.

A phase of the exact solver gives every output as

    r(tau) = Re(sum_j b_j e^{lambda_j tau}) + sum_j p_j tau^j        (tau >= 0, s)

(:class:`.spectral.SpectralPhase`). These kernels evaluate such rows on uniform grids
and at single points, with a loop body of O(terms) and no Python per grid point (the
event search built on them is :mod:`.search`). Nothing is approximated: on a uniform
grid the exponentials advance by the exact factor ``e^{lambda h}`` and are recomputed
from ``e^{lambda tau}`` every ``_ANCHOR`` points, so the values carry rounding of order
``_ANCHOR * eps`` relative to ``sum |b_j|``; every root is polished on the closed form
itself (``e^{lambda tau}`` evaluated directly) by safeguarded Newton steps, to rounding.

Cost: one call per phase; a grid point costs ~8 flops per term. Compiled on first use
(``cache=True``: once per installation, then loaded from numba's cache).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["grid_rows", "sample_rows", "row_value", "hermite_min"]

#: exponentials recomputed exactly every this many grid points
_ANCHOR = 32


@njit(cache=True)
def row_value(lam, b, poly, tau, d):
    """``d``-th time derivative of ``Re(sum b_j e^{lambda_j tau}) + sum p_j tau^j``."""
    s = 0.0
    for j in range(lam.size):
        c = b[j] * np.exp(lam[j] * tau)
        for _ in range(d):
            c = c * lam[j]
        s += c.real
    for j in range(d, poly.size):
        coef = poly[j]
        for q in range(d):
            coef *= j - q
        s += coef * tau ** (j - d)
    return s


@njit(cache=True, fastmath=True, inline="always")
def advance_exponentials(lam, tau, exact, zr, zi, wr, wi):
    """``z = e^{lambda tau}`` (as ``zr + i zi``, in place): directly if ``exact``, else one
    step of the recurrence ``z <- z w`` with ``w = wr + i wi = e^{lambda h}``."""
    if exact:
        for j in range(lam.size):
            z = np.exp(lam[j] * tau)
            zr[j], zi[j] = z.real, z.imag
    else:
        for j in range(lam.size):
            a = zr[j] * wr[j] - zi[j] * wi[j]
            zi[j] = zr[j] * wi[j] + zi[j] * wr[j]
            zr[j] = a


@njit(cache=True, fastmath=True)
def grid_rows(G, P, c0, taus, h, rec, i_base, exact_last):
    """Rows ``Re(B e^{lambda tau}) + P tau^j`` at ``taus`` (R x len(taus)), terms ``c0:``.

    ``G = (lam, Br, Bi, zr, zi, wr, wi)``: the exponents (m,), the rows' coefficients'
    real and imaginary parts (R, m) and work space (m,) each. ``rec``: ``taus`` advances by
    ``h`` (s) but where it does not; the exponentials then advance by ``e^{lambda h}``
    and are evaluated directly every ``_ANCHOR`` points, at the first point, off the step
    and (``exact_last``) at the last point: an absolute error of order
    ``_ANCHOR eps sum |B|``. Else they are evaluated directly everywhere. ``i_base > 0``:
    ``taus`` continues the previous call's grid from its last point, at index ``i_base``
    of it (the exponentials there and ``e^{lambda h}`` are reused). Real and imaginary
    parts are kept in separate arrays so the term loops vectorise. Both event loops'
    grids are evaluated here (the search's and the samples').
    """
    lam, Br, Bi, zr, zi, wr, wi = G
    R, m = Br.shape
    n = taus.size
    out = np.empty((R, n))
    if rec and i_base == 0:
        for j in range(c0, m):
            w = np.exp(lam[j] * h)
            wr[j], wi[j] = w.real, w.imag
    for i in range(n):
        tau = taus[i]
        if not (i == 0 and i_base > 0):     # else: the previous call's last point
            exact = (not rec or i == 0 or (i_base + i) % _ANCHOR == 0
                     or abs(taus[i] - taus[i - 1] - h) > 1e-9 * h
                     or (exact_last and i == n - 1))
            advance_exponentials(lam[c0:m], tau, exact, zr[c0:m], zi[c0:m], wr[c0:m],
                                 wi[c0:m])
        for r in range(R):
            acc = 0.0
            for j in range(c0, m):
                acc += Br[r, j] * zr[j] - Bi[r, j] * zi[j]
            p = 0.0
            for q in range(P.shape[1] - 1, -1, -1):
                p = p * tau + P[r, q]
            out[r, i] = acc + p
    return out


@njit(cache=True)
def sample_rows(lam, B, P, taus, h):
    """Rows ``Re(B e^{lambda tau}) + P tau^j`` at ``taus`` (R x len(taus)).

    Where ``taus`` advances by ``h`` (s) the exponentials advance by ``e^{lambda h}``;
    every ``_ANCHOR`` points, where it does not (a phase's first point) and at the last
    point they are evaluated directly (:func:`grid_rows`).
    """
    m = lam.size
    G = (np.ascontiguousarray(lam), np.ascontiguousarray(B.real),
         np.ascontiguousarray(B.imag), np.empty(m), np.empty(m), np.empty(m), np.empty(m))
    return grid_rows(G, P, 0, taus, h, True, 0, True)


@njit(cache=True)
def hermite_min(fa, fb, da, db, h):
    """Minimum over a step ``h`` (s) of the cubic Hermite interpolant of values ``fa, fb``
    and slopes ``da, db`` at its ends: the ends, the roots of its derivative in the step
    and the stationary point of its quadratic part (exact up to rounding)."""
    delta = fb - fa
    dah = da * h
    c2 = 3.0 * delta - (2.0 * dah + db * h)
    c3 = (dah + db * h) - 2.0 * delta
    out = min(fa, fb)
    sq = np.sqrt(max(c2 * c2 - 3.0 * c3 * dah, 0.0))
    if c3 != 0.0:
        d3 = 3.0 * c3
        for u in ((-c2 + sq) / d3, (-c2 - sq) / d3):
            u = min(max(u, 0.0), 1.0)
            out = min(out, fa + u * (dah + u * (c2 + u * c3)))
    if c2 != 0.0:
        u = min(max(-dah / (2.0 * c2), 0.0), 1.0)
        out = min(out, fa + u * (dah + u * (c2 + u * c3)))
    return out


@njit(cache=True)
def _value_slope(lam, b, poly, tau, d):
    """Derivatives ``d`` and ``d + 1`` of the row at ``tau``, sharing the exponentials."""
    v, s = 0.0, 0.0
    for j in range(lam.size):
        c = b[j] * np.exp(lam[j] * tau)
        for _ in range(d):
            c = c * lam[j]
        v += c.real
        s += (c * lam[j]).real
    for j in range(d, poly.size):
        coef = poly[j]
        for q in range(d):
            coef *= j - q
        v += coef * tau ** (j - d)
        if j > d:
            s += coef * (j - d) * tau ** (j - d - 1)
    return v, s


@njit(cache=True)
def _polish(lam, b, poly, d, lo, hi, f_lo, f_hi):
    """Root of the ``d``-th derivative of the row in ``[lo, hi]`` (sign change), to rounding.

    ``f_lo``, ``f_hi``: its values at the ends. Newton steps on the closed form from the
    secant point, safeguarded by bisection of the bracket; stops when a step moves by
    less than rounding or the bracket is ``1e-15 hi`` wide.
    """
    x_tol = 1e-15 * max(hi, 1e-300)
    sign_lo = 1.0 if f_lo > 0 else -1.0
    x = lo + (hi - lo) * f_lo / (f_lo - f_hi) if f_lo != f_hi else 0.5 * (lo + hi)
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    for _ in range(100):
        fx, dx = _value_slope(lam, b, poly, x, d)
        if fx == 0.0:
            return x
        if fx * sign_lo > 0:
            lo = x
        else:
            hi = x
        x_new = x - fx / dx if dx != 0.0 else 0.5 * (lo + hi)
        if not lo < x_new < hi:
            x_new = 0.5 * (lo + hi)
        if abs(x_new - x) <= 4.5e-16 * max(abs(x), 1e-300) or hi - lo <= x_tol:
            return x_new
        x = x_new
    return x
