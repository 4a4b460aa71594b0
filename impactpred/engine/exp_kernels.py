"""Compiled kernels (numba) for sums of exponentials: sampling and first-crossing search.

A phase of the exact solver gives every output as

    r(tau) = Re(sum_j b_j e^{lambda_j tau}) + sum_j p_j tau^j        (tau >= 0, s)

(:class:`.spectral.SpectralPhase`). These kernels evaluate such rows on uniform grids
and find where one first turns negative, with a loop body of O(terms) and no Python per
grid point. Nothing is approximated: on a uniform grid the exponentials advance by the
exact factor ``e^{lambda h}`` and are recomputed from ``e^{lambda tau}`` every
``_ANCHOR`` points, so the values carry rounding of order ``_ANCHOR * eps`` relative to
``sum |b_j|``; every root is polished on the closed form itself (``e^{lambda tau}``
evaluated directly) by safeguarded Newton steps, to rounding.

Cost: one call per phase; a grid point costs ~8 flops per term. Compiled on first use
(``cache=True``: once per installation, then loaded from numba's cache).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["grid_rows", "sample_rows", "first_crossing", "row_value", "phase_run",
           "hermite_min"]

#: exponentials recomputed exactly every this many grid points
_ANCHOR = 32
#: points of the geometric grid searched for a short lobe at a phase's start
_N_GEO = 256


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


@njit(cache=True, fastmath=True)
def first_crossing(lam, b, poly, e0, de0, step, t0, t_end, threshold, zero_tol, relative):
    """First event of a row in ``(0, t_end - t0]``: where it falls below ``threshold``.

    The row is sampled on ``tau_k = k * step`` (the last point exactly at ``t_end - t0``).
    A step whose end is below ``threshold`` brackets the root; a step where the slope goes
    from negative to positive (a dip between samples) that the cubic Hermite interpolant
    less its error bound ``h^4/384 sum |b_j| |lambda_j|^4`` cannot keep above
    ``threshold`` has its minimum located and, if that is below ``threshold``, brackets
    the root before it. The time returned is the
    row's own zero in that bracket (``threshold`` only detects the crossing, so a
    rounding-level dip is not an event). Values within ``zero_tol``
    of zero at the bracket's start count as an event there (``relative``: ``zero_tol``
    times the largest ``|row|`` seen so far). A phase that starts at an event (row at
    rounding level at ``tau = 0``) is searched for a short positive lobe on a geometric
    grid of the first step before the event is declared at once.

    Parameters
    ----------
    lam, b : ndarray of complex, shape (m,); poly : ndarray, shape (k,)
        The row (see the module docstring).
    e0, de0 : float
        Row value and slope at ``tau = 0`` (as computed by the caller).
    step, t0, t_end : float
        Search step (s), the phase's start time and the end of the run (s).
    threshold, zero_tol : float
        The event level and the rounding level (absolute, or relative if ``relative``).

    Returns
    -------
    float
        ``tau`` of the event, or ``-1.0`` if none before ``t_end``.
    """
    m = lam.size
    bl = b * lam
    dpoly = np.zeros(max(poly.size - 1, 0))
    for j in range(1, poly.size):
        dpoly[j - 1] = poly[j] * j
    # |4th derivative| <= g4: bounds the cubic Hermite interpolation error, h^4/384 g4
    g4 = 0.0
    for j in range(m):
        g4 += abs(b[j]) * abs(lam[j]) ** 4
    for j in range(4, poly.size):
        g4 += abs(poly[j]) * j * (j - 1) * (j - 2) * (j - 3) * max(t_end - t0, 1.0) ** (j - 4)
    w = np.exp(lam * step)
    wr, wi = w.real.copy(), w.imag.copy()
    br, bi = b.real.copy(), b.imag.copy()
    blr, bli = bl.real.copy(), bl.imag.copy()
    zr, zi = np.ones(m), np.zeros(m)
    tau_prev, e_prev, de_prev = 0.0, e0, de0
    e_max = abs(e0)
    k = 0
    while t0 + tau_prev < t_end * (1 - 1e-15):
        k += 1
        tau = k * step
        exact = k % _ANCHOR == 0
        if t0 + tau >= t_end:
            tau = t_end - t0
            exact = True
        advance_exponentials(lam, tau, exact, zr, zi, wr, wi)
        e, de = 0.0, 0.0
        for j in range(m):
            e += br[j] * zr[j] - bi[j] * zi[j]
            de += blr[j] * zr[j] - bli[j] * zi[j]
        acc, dacc = 0.0, 0.0
        for q in range(poly.size - 1, -1, -1):
            acc = acc * tau + poly[q]
        for q in range(dpoly.size - 1, -1, -1):
            dacc = dacc * tau + dpoly[q]
        e += acc
        de += dacc
        e_max = max(e_max, abs(e))
        a, b_end, e_a = tau_prev, tau, e_prev
        crossed = e < threshold
        if (not crossed and de_prev < 0 and de > 0 and e_prev >= threshold
                and hermite_min(e_prev, e, de_prev, de, tau - tau_prev)
                - (tau - tau_prev) ** 4 / 384.0 * g4 <= threshold):
            # a dip between the samples that the interpolation bound cannot clear:
            # its minimum, where the slope vanishes
            t_min = _polish(lam, b, poly, 1, tau_prev, tau, de_prev, de)
            e_min = row_value(lam, b, poly, t_min, 0)
            if e_min < threshold:
                crossed, b_end, e = True, t_min, e_min
        if crossed:
            tol = zero_tol * e_max if relative else zero_tol
            if e_a <= tol and a == 0.0:
                # the phase starts at an event: the row may open a short positive lobe
                # before it turns negative; look for it on a geometric grid
                ratio = (1e9) ** (1.0 / (_N_GEO - 1))
                x_prev, v_prev, seen_positive = 0.0, e_a, False
                for i in range(_N_GEO):
                    x = b_end * 1e-9 * ratio ** i if i < _N_GEO - 1 else b_end
                    v = row_value(lam, b, poly, x, 0)
                    if v > tol:
                        seen_positive = True
                    elif seen_positive and v < threshold:
                        a, b_end, e_a = x_prev, x, v_prev
                        break
                    x_prev, v_prev = x, v
            if e_a <= tol:
                return a
            e_b = e if b_end == tau else row_value(lam, b, poly, b_end, 0)
            return _polish(lam, b, poly, 0, a, b_end, e_a, e_b)   # the row's own root
        tau_prev, e_prev, de_prev = tau, e, de
    return -1.0


@njit(cache=True)
def phase_run(rates, modes_r, modes_i, proj_r, proj_i, in0, s0_powers, out_poly_m,
              out_expo_m, ev_poly_m, ev_expo_m, x, e0, t0, t_end, step, out_step, threshold,
              zero_tol, relative):
    """One phase of the exact solver from state ``x`` at ``t0``: its event, samples and end state.

    The phase's split form (:class:`.spectral.SpectralPhase`: ``rates`` (m,), ``modes``
    (n, m) and ``proj`` (m, n) as real and imaginary parts, ``in0`` (k, n), ``s0_powers``
    (k, n, k)) and the projections
    of its output rows (``out_poly_m`` (R, k, k), ``out_expo_m`` (R, m)) and event row
    (``ev_*``, one row) give every coefficient; the event is :func:`first_crossing`'s.

    Returns
    -------
    tau : float
        Time of the event after ``t0`` (s), or ``-1.0`` if none before ``t_end``.
    x_end : ndarray, shape (n,)
        The state at the event (or at ``t_end``).
    times : ndarray, shape (N,)
        ``t0``, the output grid ``j * out_step`` strictly inside the phase, and its end.
    values : ndarray, shape (R, N)
        The output rows at ``times``.
    """
    n = x.size
    m = rates.size
    k = in0.shape[0]
    c1 = np.zeros(m, np.complex128)
    for j in range(m):
        acc_re, acc_im = 0.0, 0.0
        for q in range(n):
            acc_re += proj_r[j, q] * x[q]
            acc_im += proj_i[j, q] * x[q]
        c1[j] = complex(acc_re, acc_im)
    c0 = np.zeros(k)
    for j in range(k):
        acc_r = 0.0
        for q in range(n):
            acc_r += in0[j, q] * x[q]
        c0[j] = acc_r
    # event row coefficients
    b_ev = ev_expo_m[0] * c1
    p_ev = np.zeros(k)
    for j in range(k):
        for q in range(k):
            p_ev[j] += ev_poly_m[0, j, q] * c0[q]
    de0 = 0.0
    for j in range(m):
        de0 += (b_ev[j] * rates[j]).real
    if k > 1:
        de0 += p_ev[1]
    tau = first_crossing(rates, b_ev, p_ev, e0, de0, step, t0, t_end, threshold, zero_tol,
                         relative)
    tau_end = tau if tau >= 0.0 else t_end - t0
    # output rows on t0, the grid inside the phase, and its end
    t_to = t0 + tau_end
    k_lo = int(np.floor(t0 / out_step + 1e-9)) + 1
    k_hi = int(np.ceil(t_to / out_step - 1e-9)) - 1
    n_grid = 0
    for kk in range(k_lo, k_hi + 1):
        tg = out_step * kk
        if t0 < tg < t_to:
            n_grid += 1
    times = np.empty(n_grid + 2)
    times[0] = t0
    i = 1
    for kk in range(k_lo, k_hi + 1):
        tg = out_step * kk
        if t0 < tg < t_to:
            times[i] = tg
            i += 1
    times[i] = t_to
    R = out_expo_m.shape[0]
    B = np.empty((R, m), np.complex128)
    for r in range(R):
        for j in range(m):
            B[r, j] = out_expo_m[r, j] * c1[j]
    P = np.zeros((R, k))
    for r in range(R):
        for j in range(k):
            for q in range(k):
                P[r, j] += out_poly_m[r, j, q] * c0[q]
    values = sample_rows(rates, B, P, times - t0, out_step)
    # the state at the end
    zr, zi = np.empty(m), np.empty(m)
    for j in range(m):
        z = np.exp(rates[j] * tau_end) * c1[j]
        zr[j], zi[j] = z.real, z.imag
    x_end = np.zeros(n)
    for q in range(n):
        acc_r = 0.0
        for j in range(m):
            acc_r += modes_r[q, j] * zr[j] - modes_i[q, j] * zi[j]
        x_end[q] = acc_r
    power = 1.0
    for j in range(k):
        for q in range(n):
            acc_r = 0.0
            for p in range(k):
                acc_r += s0_powers[j, q, p] * c0[p]
            x_end[q] += power * acc_r
        power *= tau_end
    return tau, x_end, times, values
