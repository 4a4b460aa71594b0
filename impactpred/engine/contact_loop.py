"""The contact rules and the one-clearance event loop, compiled (numba).

:func:`relative_degree` (both front ends) says how a contact starts. :func:`event_loop`
alternates the two phases of a one-clearance run (:mod:`.impact_run`; each propagated in
closed form by :func:`phase_run`, its event found by the certified search
:func:`.search.first_event` that the two-stop loop uses too) and applies the contact rules
between them with :func:`contact_start`, which the matrix-exponential fallback in
:mod:`.impact_run` calls too, so both paths decide contacts identically. Cost: one
compiled call per solve; per event O(terms x search points) plus O(states^2) for the
contact decision. numba's cache does not follow calls across modules: after editing
:mod:`.search` or :mod:`.exp_kernels` alone, touch this module (and
:mod:`.cycle_loop`) so that the loops are recompiled.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .exp_kernels import row_value, sample_rows
from .search import cabs, first_event

__all__ = ["relative_degree", "contact_start", "free_lobe_height", "phase_run", "event_loop"]

#: an event loop that does not advance this many times in a row is stalled (grazing)
MAX_STALLS = 50
#: an event that advances time by at most this share of ``t_end`` does not advance it (a
#: contact and a free flight alternating 1e-14 s apart at a graze would take 1e12 events,
#: and their samples all memory, to reach ``t_end``)
MIN_ADVANCE = 1e-12
#: a phase that starts where the loop decided its event row opens takes a start below
#: zero by at most this share of the row's terms, or the worst-case rounding of their sum
#: (``terms x eps x`` its rounding scale, larger where the terms cancel), as rounding
_START_OFFSET = 1e-9


def relative_degree(c0, c1, c2, scale):
    """Relative degree (0, 1 or 2) of a gap with respect to the contact force.

    ``c0, c1, c2``: the force's coefficient in the gap, its first and its second
    derivative (``D``, ``C B``, ``C A B`` of the phase's state space); ``scale`` (rad/s):
    the fastest rate of the free flight. The first coefficient above ``1e-12`` of the
    scaled sum decides (one rule for both front ends). Degree 2 (mass-like contact):
    a contact starts with a Dirac impulse that zeroes the approach velocity.
    """
    ref = abs(c2) + abs(c1) * scale + abs(c0) * scale ** 2
    if abs(c0) * scale ** 2 > 1e-12 * ref:
        return 0
    if abs(c1) * scale > 1e-12 * ref:
        return 1
    return 2


@njit(cache=True)
def free_lobe_height(x, cg_powers):
    """Largest gap (m) a free flight from ``x`` opens before closing (cubic Taylor form).

    ``cg_powers`` (3, n): the rows of the gap's first three time derivatives in free flight
    (on the state ``x``: the augmented one, loads included). Bodies pressed together at
    rest (the gap's rate 0 within the rounding of its terms, the first derivative beyond
    rounding closing it) open no gap: 0.
    """
    g1 = np.dot(cg_powers[0], x)
    g2 = np.dot(cg_powers[1], x)
    g3 = np.dot(cg_powers[2], x)
    r1 = 1e-12 * np.dot(np.abs(cg_powers[0]), np.abs(x))
    r2 = 1e-12 * np.dot(np.abs(cg_powers[1]), np.abs(x))
    r3 = 1e-12 * np.dot(np.abs(cg_powers[2]), np.abs(x))
    if abs(g1) <= r1 and (g2 < -r2 or (abs(g2) <= r2 and g3 < -r3)):
        return 0.0
    if g3 >= 0.0:
        return np.inf            # the cubic does not close again: a real opening
    disc = g2 * g2 - 2.0 * g3 * g1   # g'(tau) = g1 + g2 tau + g3 tau^2 / 2 = 0
    if disc < 0.0:
        return 0.0
    sq = np.sqrt(disc)
    tau = max((-g2 + sq) / g3, (-g2 - sq) / g3)
    if not tau > 0.0:
        return 0.0
    return g1 * tau + 0.5 * g2 * tau * tau + g3 * tau ** 3 / 6.0


@njit(cache=True)
def contact_start(xa, rho, coef, bf, jdx, force_row, force_rate_row, cg_powers, step, tol_g):
    """Start a contact from the augmented state ``xa`` (modified in place by any impulse).

    Where ``H1 + H2 ~ 1/s^2`` (``rho == 2``) and the bodies approach, a Dirac impulse
    ``P = -g'/coef`` is applied first. The contact then holds if the force starts
    positive, or at zero (within rounding) and rising; or if releasing it would open
    the gap by less than rounding before it closes again (method.md, section 5).

    Returns
    -------
    (impulse, holds) : (float, bool)
        The Dirac impulse (N s, 0 if none) and whether the contact holds.
    """
    n = bf.size
    impulse = 0.0
    if rho == 2:
        v_rel = np.dot(cg_powers[0], xa)
        if v_rel < 0.0:
            impulse = -v_rel / coef
            for q in range(n):
                xa[q] += bf[q] * impulse
            xa[jdx] += impulse
    f0 = np.dot(force_row, xa)
    df0 = np.dot(force_rate_row, xa)
    # rounding in the located gap shows up in f0 (as -g/c where rho = 0, c = Dg, or for a
    # spring, c = 1/k + Dg): the gap's tolerance, and 1e-12 of the scale of the terms of
    # f0 = -(gap0 + y2 - y1)/c (a loaded run from rest has a tolerance of 1e-312 m)
    f_tol = 1e-9 * (abs(f0) + abs(df0) * step)
    if rho <= 0:
        f_tol += tol_g / abs(coef) + 1e-12 * np.dot(np.abs(force_row), np.abs(xa))
    holds = f0 > f_tol or (f0 > -f_tol and df0 > 0.0)
    # (releasing would open the gap by no more than rounding: a force below zero but
    # rising, or bodies pressed together at rest, the force and its rate 0)
    rate_tol = 1e-12 * np.dot(np.abs(force_rate_row), np.abs(xa))
    if not holds and df0 >= -rate_tol and free_lobe_height(xa, cg_powers) <= tol_g:
        holds = True
    return impulse, holds


@njit(cache=True)
def phase_run(rates, abs_rates, abs_rates4, order, modes_r, modes_i, proj_r, proj_i, in0,
              s0_powers, out_poly_m, out_expo_m, ev_poly_m, ev_expo_m, ev_abs, x, t0, t_end,
              out_step, zero_tol, relative, on_boundary, start_value=np.nan):
    """One phase of the exact solver from state ``x`` at ``t0``: its event, samples and end state.

    The phase's split form (:class:`.spectral.SpectralPhase`: ``rates`` (m,) with their
    moduli, fourth powers and the order fastest first, ``modes`` (n, m) and ``proj``
    (m, n) as real and imaginary parts, ``in0`` (k, n), ``s0_powers`` (k, n, k)) and the
    projections of its output rows (``out_poly_m`` (R, k, k), ``out_expo_m`` (R, m)) and
    event row (``ev_*``, one row) give every coefficient. The event is where the event
    row falls below ``-zero_tol`` (``relative``: ``zero_tol`` times the sum of the row's
    terms), raised to four times the rounding scale of its coefficients (``ev_abs`` (m,):
    ``|event row| @ |modes|``; a stiff contact's large force row projects onto the modes
    with cancellation), located at the row's own zero by :func:`.search.first_event`;
    ``on_boundary``: the phase starts where the loop has decided it (a contact start or
    end): the event row is open there, and an event only where it leaves its rounding
    level (or after a short positive lobe, at its zero). ``start_value``: the event row's
    value at the start as the loop computed it on the state (NaN: not given), where the
    split form's own value carries the rounding of its projections, far larger where the
    phase is stiff (a 1e14 N/m spring between 1 kg masses: 0.024 N off, 3e-9 of the row's
    terms): the form is set to start there (then, as without it, a start below zero by
    no more than rounding is taken as zero; a genuinely negative start stays an event).

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
    # the coordinates, and the scale of their rounding (|proj| @ |x|, |in0| @ |x|)
    c1 = np.zeros(m, np.complex128)
    c1_mag = np.zeros(m)
    for j in range(m):
        acc_re, acc_im, acc_p = 0.0, 0.0, 0.0
        for q in range(n):
            acc_re += proj_r[j, q] * x[q]
            acc_im += proj_i[j, q] * x[q]
            acc_p += (abs(proj_r[j, q]) + abs(proj_i[j, q])) * abs(x[q])
        c1[j] = complex(acc_re, acc_im)
        c1_mag[j] = acc_p
    c0 = np.zeros(k)
    c0_mag = np.zeros(k)
    for j in range(k):
        acc_r, acc_p = 0.0, 0.0
        for q in range(n):
            acc_r += in0[j, q] * x[q]
            acc_p += abs(in0[j, q]) * abs(x[q])
        c0[j] = acc_r
        c0_mag[j] = acc_p
    # the event row's coefficients, as the search takes them (one row), and the rounding
    # scale of each: of the row's projections and of the coordinates
    b_ev = np.empty((1, m), np.complex128)
    p_ev = np.zeros((1, k))
    total = 0.0
    rounding = 0.0
    for j in range(m):
        b_ev[0, j] = ev_expo_m[0, j] * c1[j]
        total += cabs(b_ev[0, j])
        rounding += ev_abs[j] * cabs(c1[j]) + cabs(ev_expo_m[0, j]) * c1_mag[j]
    for j in range(k):
        for q in range(k):
            p_ev[0, j] += ev_poly_m[0, j, q] * c0[q]
            rounding += abs(ev_poly_m[0, j, q]) * c0_mag[q]
        total += abs(p_ev[0, j])
    tol = np.empty(1)
    tol[0] = max(zero_tol * total if relative else zero_tol,
                 4.0 * np.finfo(np.float64).eps * rounding) + 1e-300
    scale = np.empty(1)
    scale[0] = total
    open_row = 0 if on_boundary else -1
    if on_boundary:
        # the loop has decided the row opens here (the gap in a free flight, the force in
        # a contact), so it is zero here: a start below zero by the previous phase's
        # rounding (a held gap's drift above this phase's own rounding level; a stiff
        # spring's force -k g at a gap located to its tolerance; a stuck phase's force at
        # a contact start, its terms cancelling from 1e6 times their sum) is not an event;
        # the search takes the row from that offset
        start = row_value(rates, b_ev[0], p_ev[0], 0.0, 0)
        if not np.isnan(start_value):
            p_ev[0, 0] += start_value - start
            start = start_value
        allowed = max(_START_OFFSET * total, (m + k) * np.finfo(np.float64).eps * rounding)
        if -allowed <= start < 0.0:
            p_ev[0, 0] -= start
    if m:
        tau, _ = first_event(rates, abs_rates, abs_rates4, order, b_ev, p_ev, t_end - t0,
                             scale, tol, on_boundary, open_row)
    else:   # a polynomial alone (rigid bodies in free flight): one null term sets the step
        slow = np.full(1, complex(-8.0 / max(t_end - t0, 1e-300), 0.0))
        tau, _ = first_event(slow, np.abs(slow), np.abs(slow) ** 4, np.zeros(1, np.int64),
                             np.zeros((1, 1), np.complex128), p_ev, t_end - t0, scale, tol,
                             on_boundary, open_row)
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


@njit(cache=True)
def _grow_rows(a, need):
    out = np.empty((a.shape[0], max(need, 2 * a.shape[1])))
    out[:, :a.shape[1]] = a
    return out


@njit(cache=True)
def _grow_pairs(a, need):
    out = np.empty((max(need, 2 * a.shape[0]), 2))
    out[:a.shape[0]] = a
    return out


@njit(cache=True)
def event_loop(free, stuck, xa0, in_contact, t_end, step, out_step, tol_g, rho, coef, bf,
               jdx, force_row, force_rate_row, cg_powers, gap0):
    """Run free flight and contact phases from ``xa0`` at ``t = 0`` to ``t_end``.

    Parameters
    ----------
    free, stuck : tuple
        Each phase as ``(rates, modes_r, modes_i, proj_r, proj_i, in0, s0_powers,
        out_poly_m, out_expo_m, ev_poly_m, ev_expo_m, ev_abs, abs_rates, abs_rates4,
        order)`` (see :func:`phase_run`).
    xa0 : ndarray, shape (n + 2,)
        Augmented initial state ``[X, 1, J]``.
    in_contact : bool
        The bodies touch and do not separate at ``t = 0``: the contact rules decide at once
        (a Dirac impulse where they approach, a contact where they press).
    t_end, step, out_step, tol_g : float
        End time, the search step of the contact decision's rounding level, the output
        step (s) and the gap's rounding level (m).
    rho, coef : int, float
        Relative degree of the gap in the force and its coefficient (``rho = -1``: a
        spring contact, no Dirac impulse).
    bf, jdx, force_row, force_rate_row, cg_powers
        Force input of the states (n,), index of ``J``, the contact force and its rate as
        rows on ``xa``, and the gap's derivative rows (see :func:`contact_start`).
    gap0 : float
        Initial gap (m): the samples' gap row is ``y2 - y1 + gap0`` (rows 1 and 2 of the
        phases' output rows are ``y1`` and ``y2``; it is inserted as row 3).

    Returns
    -------
    status : int
        0, or 1 if events repeated without time advancing (grazing).
    t_stall : float
        Where it stalled.
    times, values : ndarray, shapes (N,), (R + 1, N)
        Output samples (every phase's start, grid points and end): the phases' rows with
        the gap inserted as row 3.
    intervals, diracs : ndarray, shape (K, 2)
        Contact intervals (start, end) and Dirac impulses (time, size).
    xa_end : ndarray
        The augmented state at ``t_end``.
    first_impulse : float
        ``J`` after the first contact (or at the end if none).
    starts : ndarray, shape (P, 2)
        Every phase's start time and whether it is a contact phase (1.0) or free flight
        (0.0), in order; ``states`` (len(xa0), P) the augmented state there (a contact's
        Dirac impulse applied).
    """
    n_rows = free[8].shape[0]
    cap = int(t_end / out_step) + 64
    times = np.empty(cap)
    values = np.empty((n_rows + 1, cap))
    used = 0
    intervals = np.empty((8, 2))
    n_iv = 0
    diracs = np.empty((8, 2))
    n_d = 0
    xa = xa0.copy()
    starts = np.empty((8, 2))
    states = np.empty((xa0.size, 8))
    n_ph = 0
    first_impulse, have_first = 0.0, False
    t = 0.0
    contact_at = 0.0
    if in_contact:
        impulse, in_contact = contact_start(xa, rho, coef, bf, jdx, force_row,
                                            force_rate_row, cg_powers, step, tol_g)
        if impulse != 0.0:
            diracs[n_d, 0], diracs[n_d, 1] = 0.0, impulse
            n_d += 1
        if not in_contact and impulse != 0.0:   # a Dirac alone: over at once
            intervals[n_iv, 0], intervals[n_iv, 1] = 0.0, 0.0
            n_iv += 1
            first_impulse, have_first = xa[jdx], True
    stalled = 0
    while t < t_end * (1 - 1e-15):
        ph = stuck if in_contact else free
        if n_ph + 1 > starts.shape[0]:
            starts = _grow_pairs(starts, n_ph + 1)
            states = _grow_rows(states, n_ph + 1)
        starts[n_ph, 0], starts[n_ph, 1] = t, 1.0 if in_contact else 0.0
        for q in range(xa.size):
            states[q, n_ph] = xa[q]
        n_ph += 1
        tau, x_end, ts, vs = phase_run(ph[0], ph[12], ph[13], ph[14], ph[1], ph[2], ph[3],
                                       ph[4], ph[5], ph[6], ph[7], ph[8], ph[9], ph[10],
                                       ph[11], xa,
                                       t, t_end, out_step, 1e-12 if in_contact else tol_g,
                                       in_contact, True,
                                       np.dot(force_row, xa) if in_contact else np.nan)
        if used + ts.size > times.size:
            need = used + ts.size
            grown = np.empty(max(need, 2 * times.size))
            grown[:used] = times[:used]
            times = grown
            values = _grow_rows(values, need)
        for i in range(ts.size):        # explicit loops: numba's 2-D slice copy is slow
            times[used + i] = ts[i]
        for r in range(n_rows):         # rows 0-2, the gap, then the rest
            rr = r if r < 3 else r + 1
            for i in range(ts.size):
                values[rr, used + i] = vs[r, i]
        for i in range(ts.size):
            values[3, used + i] = vs[2, i] - vs[1, i] + gap0
        used += ts.size
        xa = x_end
        happened = tau >= 0.0
        t_ev = t + tau if happened else t_end
        stalled = stalled + 1 if t_ev - t <= MIN_ADVANCE * t_end else 0
        if stalled > MAX_STALLS:
            return (1, t, times[:used], values[:, :used], intervals[:n_iv], diracs[:n_d],
                    xa, first_impulse, starts[:n_ph], states[:, :n_ph])
        t = t_ev
        if not happened:
            break
        if n_iv + 1 > intervals.shape[0]:
            intervals = _grow_pairs(intervals, n_iv + 1)
        if in_contact:                  # separation
            intervals[n_iv, 0], intervals[n_iv, 1] = contact_at, t
            n_iv += 1
            in_contact = False
        else:                           # contact
            contact_at = t
            impulse, in_contact = contact_start(xa, rho, coef, bf, jdx, force_row,
                                                force_rate_row, cg_powers, step, tol_g)
            if impulse != 0.0:
                if n_d + 1 > diracs.shape[0]:
                    diracs = _grow_pairs(diracs, n_d + 1)
                diracs[n_d, 0], diracs[n_d, 1] = t, impulse
                n_d += 1
            if not in_contact:
                intervals[n_iv, 0], intervals[n_iv, 1] = t, t
                n_iv += 1
        if not have_first and n_iv > 0:
            first_impulse, have_first = xa[jdx], True
    if in_contact:
        if n_iv + 1 > intervals.shape[0]:
            intervals = _grow_pairs(intervals, n_iv + 1)
        intervals[n_iv, 0], intervals[n_iv, 1] = contact_at, t_end
        n_iv += 1
    if not have_first:
        first_impulse = xa[jdx]
    return (0, t, times[:used], values[:, :used], intervals[:n_iv], diracs[:n_d], xa,
            first_impulse, starts[:n_ph], states[:, :n_ph])
