"""The exact engine's certified event search, compiled (numba).

The phase ends at the first ``tau`` where one of its event rows turns negative. The
search (:func:`first_event`) is certified, multilevel: the terms are nested by
``|lambda|``; a level resolves the slow ones on steps ``pi / (8 Lambda)`` and bounds the
others by the sum of their moduli (``|e^{lambda tau}| <= 1`` since ``Re lambda <= 0``); a
step is cleared when the cubic Hermite interpolant's minimum, less its error bound
``h^4/384 sum |b| |lambda|^4``, less that sum, stays above the rounding level. Only the
steps not cleared are searched at the next level (``_RATIO`` times finer), so the fast
modes cost work only right at an event. At the last level (every term) a sign change
brackets the root and a dip (slope from negative to positive) has its minimum located;
a last-level span is evaluated in pieces, stopping at the first piece with an event; a
phase that starts on an event is first searched on a geometric grid of its first fine
step. A decaying transient that alone would set the coarsest level's step (a stiff real
eigenvalue) is searched apart, and the rows restarted exactly where it has died out
(:func:`first_event`). Its Python twin, the oracle it is tested against, is
``tests/oracle_event_search.py``. Rows are

    r_i(tau) = Re(sum_j b_ij e^{lambda_j tau}) + sum_c poly_ic tau^c      (tau in s)

given by their coefficients: ``b`` (K, m) complex, ``poly`` (K, k); values are in the rows'
own units (m for the gaps, N for the contact force). The uniform grids are evaluated as
by :func:`impactpred.engine.exp_kernels.sample_rows` (recurrence ``e^{lambda h}``,
recomputed exactly every 32 points and at the first one; here with the terms
kept fastest first, so that a level's terms are a contiguous tail, and no per-call
copies), grids of fewer than ``_MIN_KERNEL`` points by direct exponentials, the
geometric grid at a phase's start by Taylor sums (:func:`_taylor_rows`); roots are
polished by safeguarded Newton steps on the closed form. Only rounding differs from the
Python oracle (the order of the sums, the recurrence on the grids): all its decisions
compare values with a zero tolerance ``1e-12`` of the rows' terms, far above it.

Cost: per phase O(K m) per grid point searched; no Python, no allocation beyond the grids.
Compiled on first use (``cache=True``: loaded from numba's cache afterwards).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .exp_kernels import _polish, _value_slope, grid_rows, row_value
from .step_kernels import (QUIET_MIN_STEPS, crossing_steps, cubic_min, quiet_from,
                           uncertified_steps)

__all__ = ["cabs", "first_event"]

# the search's constants, shared with the Python oracle (tests/oracle_event_search.py):
# defined here, beside the compiled code that freezes them, so that numba's cache (which
# tracks this file only) sees a change
#: fraction of a row's scale the fast terms may carry (bounded, not sampled)
_ETA = 0.05
#: search steps per radian of the fastest resolved term: step = pi / (8 |lambda|)
_STEP = math.pi / 8.0
#: ratio of the resolved rates of two successive levels of the search
_RATIO = 64.0
#: geometric grid (fractions of the fine step) searched at a phase that starts on an event
_GEO = np.geomspace(1e-9, 1.0, 16)
#: max of the Hermite basis functions u(1-u)^2 and u^2(1-u) on [0, 1]
_H1 = 4.0 / 27.0
#: uniform grids of at least this many points are evaluated by the recurrence
_MIN_KERNEL = 8
#: steps of the first piece of a last-level span (then doubling; the Python search: 64)
_PIECE = 16
#: a decaying transient is searched on its own when it ends before this share of the
#: span (:func:`_transient_end`), at most ``_MAX_SPLITS`` times a phase
_SPLIT_SHARE = 0.25
_MAX_SPLITS = 8
#: the geometric grid's rows are summed as Taylor series of this many terms where
#: ``|lambda| tau`` stays within ``_TAYLOR_RADIUS`` (see :func:`_taylor_rows`)
_TAYLOR_TERMS = 16
_TAYLOR_RADIUS = math.pi / 8.0 + 1e-12


@njit(cache=True)
def _levels(abs_lam, abs_lam4, order, amp, scale):  # pragma: no cover - compiled
    """Levels of the search (see ``tests/oracle_event_search._levels``).

    Returns ``(cuts, tails, g4s, hs)``: level ``l`` resolves the terms ``order[cuts[l]:]``
    (the slowest), bounds the others by ``tails[l]`` (per row, row units), has the
    Hermite error coefficient ``g4s[l]`` (row units / s^4) and the step ``hs[l]`` (s).
    """
    K, m = amp.shape
    cum = np.zeros((K, m))
    ok_all = True
    n_cut = -1
    for c in range(m):
        ok = True
        for r in range(K):
            prev = cum[r, c - 1] if c else 0.0
            cum[r, c] = prev + amp[r, order[c]]
            if not cum[r, c] <= _ETA * scale[r]:
                ok = False
        if not ok and ok_all:
            ok_all = False
            n_cut = c
    if ok_all:
        n_cut = m - 1
    cuts = np.empty(m + 1, np.int64)
    cuts[0] = n_cut
    n_lev = 1
    while cuts[n_lev - 1] > 0:
        ref = _RATIO * abs_lam[order[cuts[n_lev - 1]]]
        nxt = 0
        for c in range(m):
            if abs_lam[order[c]] > ref:
                nxt += 1
        cuts[n_lev] = min(nxt, cuts[n_lev - 1] - 1)
        n_lev += 1
    cuts = cuts[:n_lev]
    c4 = np.zeros((K, m + 1))               # c4[:, c]: sum over order[c:] of |b| |lam|^4
    for c in range(m - 1, -1, -1):
        for r in range(K):
            c4[r, c] = c4[r, c + 1] + amp[r, order[c]] * abs_lam4[order[c]]
    tails = np.zeros((n_lev, K))
    g4s = np.zeros((n_lev, K))
    hs = np.empty(n_lev)
    for lv in range(n_lev):
        n_c = cuts[lv]
        for r in range(K):
            tails[lv, r] = cum[r, n_c - 1] if n_c else 0.0
            g4s[lv, r] = c4[r, n_c]
        a = abs_lam[order[n_c]]
        hs[lv] = _STEP / a if a > 0 else np.inf
    return cuts, tails, g4s, hs


@njit(cache=True, inline="always")
def cabs(z):  # pragma: no cover - compiled
    """``|z|`` without ``hypot``'s overflow guard (the moduli here are far from overflow)."""
    return math.sqrt(z.real * z.real + z.imag * z.imag)


@njit(cache=True)
def _taylor_rows(lam, b, poly, taus):  # pragma: no cover - compiled
    """Values and slopes (2K x len(taus)) of the rows from their Taylor series at 0.

    For ``|lambda| tau <= _TAYLOR_RADIUS`` (``pi / 8``, the geometric grid of a phase
    starting on an event) the ``_TAYLOR_TERMS``-term series is exact to ``~1e-17`` of
    ``sum |b|`` (truncation ``0.39^16 / 16!``, the terms' moduli summing to at most
    ``e^0.39 sum |b|``): the same values as the direct exponentials to rounding, for
    ``~m N`` multiplications per row instead of ``m`` complex exponentials per point.
    """
    K, m = b.shape
    N = _TAYLOR_TERMS
    coef = np.zeros((K, N + 1))            # value coefficients tau^q, q = 0 .. N
    pr, pi = np.empty(m), np.empty(m)       # b lam^q / q!
    lr, li = lam.real.copy(), lam.imag.copy()
    for r in range(K):
        for j in range(m):
            pr[j], pi[j] = b[r, j].real, b[r, j].imag
        for q in range(N + 1):
            inv = 1.0 / (q + 1)
            acc = 0.0
            for j in range(m):
                acc += pr[j]
                a = (pr[j] * lr[j] - pi[j] * li[j]) * inv
                pi[j] = (pr[j] * li[j] + pi[j] * lr[j]) * inv
                pr[j] = a
            coef[r, q] = acc
        for c in range(min(poly.shape[1], N + 1)):
            coef[r, c] += poly[r, c]
    out = np.empty((2 * K, taus.size))
    for i in range(taus.size):
        tau = taus[i]
        for r in range(K):
            v = coef[r, N]
            d = N * coef[r, N]
            for q in range(N - 1, -1, -1):
                v = v * tau + coef[r, q]
                if q:
                    d = d * tau + q * coef[r, q]
            out[r, i] = v
            out[K + r, i] = d
    return out


@njit(cache=True)
def _ev(G, P, c0, taus, h, uniform, i_base=0):  # pragma: no cover - compiled
    """Values and slopes (2K x len(taus)) of the terms ``c0:`` (fastest first: those of a
    level) and the polynomial ``P`` (:func:`impactpred.engine.exp_kernels.grid_rows`; ``G``
    in the search's term order). ``uniform``: ``taus`` advances by ``h`` (s) but at its
    last point (the recurrence serves grids of ``_MIN_KERNEL`` points or more), else the
    exponentials are evaluated directly everywhere; ``i_base > 0``: ``taus`` continues
    the previous call's grid from its last point, at index ``i_base`` of it.
    """
    return grid_rows(G, P, c0, taus, h, uniform and taus.size >= _MIN_KERNEL, i_base, False)


@njit(cache=True)
def _locate(lam, bi, pi, lo, hi, zero_tol_i, total_i, opened_i):  # pragma: no cover
    """Root of a row in ``[lo, hi]`` (``>= -zero_tol`` at ``lo``, below at ``hi``), in s.

    Safeguarded Newton steps on the closed form; an open row still at rounding level at
    ``lo`` has its event where it leaves ``[-zero_tol, 0]``, or at its own root after a
    low positive lobe found on a geometric grid of ``[0, hi]`` (as the Python oracle).
    """
    shift = 0.0
    noise = 4e-16 * total_i
    f_lo = row_value(lam, bi, pi, lo, 0)
    if f_lo <= 0.0:
        if not (opened_i and f_lo >= -zero_tol_i):
            return lo
        n_g = _GEO.size
        vals = np.empty(n_g)
        first_pos = -1
        first_neg = -1
        for j in range(n_g):
            vals[j] = row_value(lam, bi, pi, hi * _GEO[j], 0)
        for j in range(n_g):
            if first_pos < 0 and vals[j] > noise:
                first_pos = j
            elif first_pos >= 0 and j > first_pos and vals[j] <= 0.0:
                first_neg = j
                break
        if first_neg >= 0:
            lo, hi = hi * _GEO[first_neg - 1], hi * _GEO[first_neg]
            f_lo = vals[first_neg - 1]
        else:
            shift = zero_tol_i
            f_lo += shift
            if f_lo <= 0.0:
                return lo
    f_hi = row_value(lam, bi, pi, hi, 0) + shift
    x = lo + (hi - lo) * f_lo / (f_lo - f_hi)
    for _ in range(100):
        fx, dx = _value_slope(lam, bi, pi, x, 0)
        fx += shift
        if abs(fx) <= noise:
            return x
        if fx > 0.0:
            lo = x
        elif fx < 0.0:
            hi = x
        else:
            return x
        x_new = x - fx / dx if dx != 0.0 else 0.5 * (lo + hi)
        if not lo < x_new < hi:
            x_new = 0.5 * (lo + hi)
        if abs(x_new - x) <= 4e-16 * max(abs(x), 1e-300) or hi - lo <= 4e-16 * hi:
            return x_new
        x = x_new
    return x


@njit(cache=True)
def _crossings(lam, b, poly, total, zero_tol, opened, t_all, v, g4):  # pragma: no cover
    """First event among the steps of ``t_all`` with every term: ``(tau, row)`` or
    ``(-1.0, -1)``. ``v`` (2K x len(t_all)): values and slopes."""
    K = b.shape[0]
    steps, code = crossing_steps(t_all, v, K, g4, zero_tol)
    for idx in range(steps.size):
        j = steps[idx]
        best_t, best_i = np.inf, -1
        for i in range(K):
            c = code[i, idx]
            if c == 0:
                continue
            lo, hi = t_all[j], t_all[j + 1]
            if c == 2:
                # a dip: its interpolated minimum less the interpolation error bounds the
                # row's minimum in the step; at or above -zero_tol (rounding-level dips of
                # a row at 0) it cannot be an event, without locating the minimum
                hs = hi - lo
                if (cubic_min(v[i, j], v[i, j + 1], v[K + i, j], v[K + i, j + 1], hs)
                        - hs ** 4 / 384.0 * g4[i] >= -zero_tol[i]):
                    continue
                d_lo = row_value(lam, b[i], poly[i], lo, 1)
                d_hi = row_value(lam, b[i], poly[i], hi, 1)
                if d_lo >= 0.0:
                    t_min = lo
                elif d_hi <= 0.0:
                    t_min = hi
                else:
                    t_min = _polish(lam, b[i], poly[i], 1, lo, hi, d_lo, d_hi)
                if row_value(lam, b[i], poly[i], t_min, 0) >= -zero_tol[i]:
                    continue
                hi = t_min
            root = _locate(lam, b[i], poly[i], lo, hi, zero_tol[i], total[i], opened[i])
            if best_i < 0 or root < best_t:
                best_t, best_i = root, i
        if best_i >= 0:
            return best_t, best_i
    return -1.0, -1


@njit(cache=True)
def _before_negative(steps, v, K, tail, zero_tol):  # pragma: no cover - compiled
    """The uncertified ``steps`` up to the first one whose end is certainly below
    ``-zero_tol`` for some row (level value plus the bound ``tail`` of the terms left out):
    the first event is no later than that end, so the steps after it need no search."""
    for q in range(steps.size):
        j = steps[q]
        for r in range(K):
            if v[r, j + 1] + tail[r] < -zero_tol[r]:
                return steps[:q + 1]
    return steps


@njit(cache=True)
def _uniform(a, b_end, h):  # pragma: no cover - compiled
    """``n + 1`` points from ``a`` to ``b_end`` (s), ``n = ceil((b_end - a) / h)``; step."""
    n = max(1, int(math.ceil((b_end - a) / h - 1e-9)))
    t_all = np.empty(n + 1)
    for j in range(n + 1):
        t_all[j] = a + (b_end - a) * j / n
    t_all[n] = b_end
    return t_all, (b_end - a) / n


@njit(cache=True)
def _fine(lam, b, poly, G, PP, total, zero_tol, opened, g4_full, h_f, a,
          b_end):  # pragma: no cover - compiled
    """First event in ``[a, b_end]`` with every term, in pieces of ``_PIECE`` steps
    (doubling up to ``16 _PIECE``), stopping at the first piece with an event."""
    t_all, h = _uniform(a, b_end, h_f)
    n = t_all.size - 1
    i0, piece = 0, _PIECE
    while i0 < n:
        i1 = min(n, i0 + piece)
        tt = t_all[i0:i1 + 1]
        tau, row = _crossings(lam, b, poly, total, zero_tol, opened, tt,
                              _ev(G, PP, 0, tt, h, True, i0), g4_full)
        if row >= 0:
            return tau, row
        i0, piece = i1, min(2 * piece, 16 * _PIECE)
    return -1.0, -1


@njit(cache=True)
def first_event(lam, abs_lam, abs_lam4, order, b, poly, tau_max, scale, zero_tol,
                on_boundary, open_row):  # pragma: no cover - compiled
    """First ``tau`` in ``(0, tau_max]`` (s) where a row falls below ``-zero_tol``.

    :func:`_search_span` over the phase, its decaying transients apart: while the fastest
    term the coarsest level would resolve (and every faster one) decays below its row's
    zero tolerance well before ``tau_max`` (:func:`_transient_end`), the span up to there
    is searched first and the rows are then restarted from its end, exactly
    (:func:`_shifted`), where those terms no longer set any level's step. A stiff real
    eigenvalue (``-7.8e6`` rad/s, the stuck phase of a body whose model carries a static
    flexibility) then costs about a hundred steps of its own scale, not steps of its scale
    over the whole phase (1.6e8 over 8 s). Arguments and result as :func:`_search_span`.
    """
    t0 = 0.0
    for _ in range(_MAX_SPLITS):
        cut = _transient_end(lam, order, b, poly, tau_max - t0, scale, zero_tol)
        if cut <= 0.0:
            break
        tau, row = _search_span(lam, abs_lam, abs_lam4, order, b, poly, cut, scale,
                                zero_tol, on_boundary, open_row)
        if row >= 0:
            return t0 + tau, row
        b, poly = _shifted(lam, b, poly, cut)
        t0 += cut
        on_boundary, open_row = False, -1
    tau, row = _search_span(lam, abs_lam, abs_lam4, order, b, poly, tau_max - t0, scale,
                            zero_tol, on_boundary, open_row)
    return (t0 + tau, row) if row >= 0 else (-1.0, -1)


@njit(cache=True)
def _transient_end(lam, order, b, poly, span, scale, zero_tol):  # pragma: no cover
    """Where the phase's decaying transient ends, or 0.0 (no split).

    The coarsest level resolves the terms from the first (fastest first) whose running
    sum of moduli exceeds ``_ETA`` of a row's scale (and any term as fast); those terms
    and the faster ones are the transient when each decays (``Re lambda < 0``) below the
    row's ``zero_tol`` (at least its rounding level) shared among them: the time (s) when
    the last does, if that is before ``_SPLIT_SHARE`` of ``span`` and every row is then
    above twice its ``zero_tol`` (the next span starts clear of any event: a row near
    zero there stays in one search). The transient is then gone from the rows, not
    merely bounded: the next span's levels are set by the terms that last.
    """
    K, m = b.shape
    n_fast = -1
    acc = np.zeros(K)
    for c in range(m):
        for r in range(K):
            acc[r] += cabs(b[r, order[c]])
            if acc[r] > _ETA * scale[r]:
                n_fast = c + 1
        if n_fast > 0:
            break
    if n_fast < 0:
        return 0.0                        # nothing resolved on the coarsest level
    while n_fast < m and cabs(lam[order[n_fast]]) == cabs(lam[order[n_fast - 1]]):
        n_fast += 1                       # a term as fast as the last one resolved
    cut = 0.0
    for q in range(n_fast):
        j = order[q]
        rate = -lam[j].real
        for r in range(K):
            share = max(zero_tol[r], 1e-15 * scale[r]) / n_fast
            size = cabs(b[r, j])
            if size > share:
                if rate <= 0.0:
                    return 0.0
                cut = max(cut, math.log(size / share) / rate)
    if not 0.0 < cut < _SPLIT_SHARE * span:
        return 0.0
    b_cut, p_cut = _shifted(lam, b, poly, cut)
    for r in range(K):
        value = p_cut[r, 0] if p_cut.shape[1] else 0.0
        for j in range(m):
            value += b_cut[r, j].real
        if not value > 2.0 * zero_tol[r]:
            return 0.0
    return cut


@njit(cache=True)
def _shifted(lam, b, poly, t):  # pragma: no cover - compiled
    """The rows restarted at ``tau = t`` (s): ``b e^{lambda t}`` and the polynomial's
    Taylor coefficients at ``t`` (exact to rounding)."""
    K, m = b.shape
    k = poly.shape[1]
    b_t = np.empty((K, m), np.complex128)
    for j in range(m):
        grow = np.exp(lam[j] * t)
        for r in range(K):
            b_t[r, j] = b[r, j] * grow
    p_t = np.zeros((K, k))
    for q in range(k):
        for c in range(q, k):
            coef = t ** (c - q)                      # times the binomial C(c, q)
            for i in range(q):
                coef *= (c - i) / (i + 1.0)
            for r in range(K):
                p_t[r, q] += poly[r, c] * coef
    return b_t, p_t


@njit(cache=True)
def _search_span(lam, abs_lam, abs_lam4, order, b, poly, tau_max, scale, zero_tol,
                 on_boundary, open_row):  # pragma: no cover - compiled
    """First ``tau`` in ``(0, tau_max]`` (s) where a row falls below ``-zero_tol``.

    The search of the module docstring: ``lam`` (m,) complex,
    ``abs_lam``, ``abs_lam4`` its moduli and their fourth powers, ``order`` the terms
    fastest first (``PhaseKind.order_desc``); ``b`` (K, m), ``poly`` (K, k); ``scale``,
    ``zero_tol`` (K,) in row units; ``open_row``: the row decided to open (-1: none).

    Returns ``(tau, row)``, or ``(-1.0, -1)`` when no row crosses before ``tau_max``.
    """
    K, m = b.shape
    k = poly.shape[1]
    amp = np.empty((K, m))
    total = np.empty(K)
    for r in range(K):
        acc = 0.0
        for j in range(m):
            amp[r, j] = cabs(b[r, j])
            acc += amp[r, j]
        for c in range(k):
            acc += abs(poly[r, c])
        total[r] = acc
    opened = np.zeros(K, np.bool_)
    if open_row >= 0:
        opened[open_row] = True
    # the grids' terms, fastest first (a level's terms are then a tail ``c0:``)
    lam_o = np.empty(m, np.complex128)
    Br = np.empty((2 * K, m))
    Bi = np.empty((2 * K, m))
    for c in range(m):
        j = order[c]
        lam_o[c] = lam[j]
        for r in range(K):
            bj, blj = b[r, j], b[r, j] * lam[j]
            Br[r, c], Bi[r, c] = bj.real, bj.imag
            Br[K + r, c], Bi[K + r, c] = blj.real, blj.imag
    G = (lam_o, Br, Bi, np.empty(m), np.empty(m), np.empty(m), np.empty(m))
    PP = np.zeros((2 * K, k))
    for r in range(K):
        for c in range(k):
            PP[r, c] = poly[r, c]
            if c + 1 < k:
                PP[K + r, c] = poly[r, c + 1] * (c + 1)
    g4_full = amp @ abs_lam4
    cuts, tails, g4s, hs = _levels(abs_lam, abs_lam4, order, amp, scale)
    n_lev = cuts.size
    h_f = hs[n_lev - 1]
    tau = 0.0
    if on_boundary:     # a start lobe shorter than a fine step is seen on this grid
        g_end = min(h_f, tau_max)
        taus = np.empty(_GEO.size + 1)
        taus[0] = 0.0
        for j in range(_GEO.size):
            taus[j + 1] = g_end * _GEO[j]
        if abs_lam.max() * g_end <= _TAYLOR_RADIUS:
            e_all = _taylor_rows(lam, b, poly, taus)
        else:
            e_all = _ev(G, PP, 0, taus, 0.0, False)
        for i in range(K):
            if not (e_all[i, 0] <= zero_tol[i]) or opened[i]:
                continue
            pos = -1
            for j in range(1, taus.size):
                if e_all[i, j] > zero_tol[i]:
                    pos = j
                    break
            bad = pos < 0 or e_all[i, 0] < -zero_tol[i]
            if not bad:
                for j in range(1, pos):
                    if e_all[i, j] < -zero_tol[i]:
                        bad = True
            if bad:
                return 0.0, i          # the row does not open: the event is now
            for j in range(1, pos):
                e_all[i, j] = zero_tol[i]   # rounding-level start: not an event
        t_ev, row = _crossings(lam, b, poly, total, zero_tol, opened, taus, e_all, g4_full)
        if row >= 0:
            return t_ev, row
        if taus[-1] >= tau_max:
            return -1.0, -1
        tau = taus[-1]
    h0 = hs[0]
    if tau_max - tau > QUIET_MIN_STEPS * h0:     # a long span: its quiet tail cut off
        tau_max = quiet_from(lam, b, poly, tau, tau_max, h0, zero_tol)
        if tau_max <= tau:
            return -1.0, -1
    chunk = 16
    # spans still to search, depth first in time order: (level, start, end, piece)
    st_lv = np.empty(64, np.int64)
    st_p = np.empty(64, np.int64)
    st_a = np.empty(64)
    st_b = np.empty(64)
    while tau < tau_max:
        n_pts = 0
        for j in range(chunk + 1):
            if tau + h0 * j < tau_max:
                n_pts += 1
        if tau + h0 * chunk >= tau_max:
            grid = np.empty(n_pts + 1)
            for j in range(n_pts):
                grid[j] = tau + h0 * j
            grid[n_pts] = tau_max
        else:
            grid = np.empty(chunk + 1)
            for j in range(chunk + 1):
                grid[j] = tau + h0 * j
        v = _ev(G, PP, cuts[0], grid, h0, True)
        unc = _before_negative(uncertified_steps(grid, v, K, g4s[0], tails[0], zero_tol, _H1),
                               v, K, tails[0], zero_tol)
        q = 0
        while q < unc.size:
            q1 = q
            while q1 + 1 < unc.size and unc[q1 + 1] == unc[q1] + 1:
                q1 += 1
            a, b_end = grid[unc[q]], grid[unc[q1] + 1]
            q = q1 + 1
            if n_lev == 1:
                t_ev, row = _fine(lam, b, poly, G, PP, total, zero_tol, opened,
                                  g4_full, h_f, a, b_end)
                if row >= 0:
                    return t_ev, row
                continue
            n_st = 1
            st_lv[0], st_a[0], st_b[0], st_p[0] = 1, a, b_end, _PIECE
            while n_st:
                n_st -= 1
                lv, sa, sb, piece = st_lv[n_st], st_a[n_st], st_b[n_st], st_p[n_st]
                if lv >= n_lev - 1:
                    t_ev, row = _fine(lam, b, poly, G, PP, total, zero_tol, opened,
                                      g4_full, h_f, sa, sb)
                    if row >= 0:
                        return t_ev, row
                    continue
                # the span's grid, evaluated a piece at a time: its first ``piece`` steps
                # now, the rest (pushed below this piece's runs) only if no event is there
                t_all, h = _uniform(sa, sb, hs[lv])
                n_steps = t_all.size - 1
                tt = t_all[:min(n_steps, piece) + 1]
                v_l = _ev(G, PP, cuts[lv], tt, h, True)
                u_all = uncertified_steps(tt, v_l, K, g4s[lv], tails[lv], zero_tol, _H1)
                u_l = _before_negative(u_all, v_l, K, tails[lv], zero_tol)
                if n_st + u_l.size + 1 > st_lv.size:
                    grow = n_st + u_l.size + 1
                    st_lv = np.concatenate((st_lv, np.empty(grow, np.int64)))
                    st_p = np.concatenate((st_p, np.empty(grow, np.int64)))
                    st_a = np.concatenate((st_a, np.empty(grow)))
                    st_b = np.concatenate((st_b, np.empty(grow)))
                if tt.size < t_all.size and u_l.size == u_all.size:
                    st_lv[n_st], st_p[n_st] = lv, min(2 * piece, 16 * _PIECE)
                    st_a[n_st], st_b[n_st] = tt[-1], sb
                    n_st += 1
                # runs of consecutive steps, pushed last first (popped in time order)
                runs_end = u_l.size
                while runs_end > 0:
                    r1 = runs_end - 1
                    r0 = r1
                    while r0 > 0 and u_l[r0 - 1] == u_l[r0] - 1:
                        r0 -= 1
                    st_lv[n_st], st_p[n_st] = lv + 1, _PIECE
                    st_a[n_st], st_b[n_st] = tt[u_l[r0]], tt[u_l[r1] + 1]
                    n_st += 1
                    runs_end = r0
        tau = grid[-1]
        chunk = min(2 * chunk, 512)
    return -1.0, -1
