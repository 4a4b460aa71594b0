"""The two-sided (impact-damper) event loop for rigid and instantaneous contacts, compiled.

:func:`rigid_loop` is the ``Rigid`` / ``InstantaneousImpact`` part of
:func:`.cycle_run.run` as one compiled call: per phase, the closed form's coordinates
(:meth:`.phase.PhaseKind.start`), the event rows' coefficients, the certified
event search (:func:`.search.first_event`), the output samples with the exact
input-work integrals, the contact impulse, the state at the event, and the event itself
(the damper mass pinned on the stop, the plastic or restitution impulse, the Zeno rule
:func:`zeno_closes` shared with the Python loop, the stick-or-separate decision), with a
cap on impacts per forcing period (status ``RUNAWAY``) and a pause every ``max_phases``
phases (status ``PAUSED``: the driver redraws the progress bar). Same rules, same order
of decisions as the Python loop; only the rounding differs (loops instead of BLAS
products, the search's own sums): chattering runs, which amplify rounding, agree with the
Python loop for tens of contacts and then in their statistics only (see
``tests/test_impactpred_damper_kernels``).

A kind of phase is passed as the tuple built by :func:`.cycle_compiled.kind_arrays`:
``(lam, abs_lam, abs_lam4, order, V, Vinv, in0, S0P, X, ev_rv, ev_rp, ev_rx, out_rv,
out_rp, out_rx)`` (see :class:`.phase.PhaseKind`). Units: the engine's
(:class:`impactpred.damper._engine.Engine`, a dimensionless form; "s", "m", "N s" below
stand for its units of time, length and impulse); the input work's two integrals, see
:func:`.cycle_run._work`. Every tolerance is relative (to the forcing period, to a row's
size over it: :func:`row_sizes`), so a run is the same whatever those units.

Cost: a phase is O(terms x (states + rows x points searched)); on the benchmark's 20-mode
beam ~27 us a phase on average, ~18 us of it the event search; no Python per phase.
Compiled on first use (``cache=True``; ~40 s in a fresh environment, then loaded from
numba's cache). numba's cache does not follow calls across modules: after editing
:mod:`.search` alone, touch this module (or clear ``__pycache__``) so that
:func:`rigid_loop` is recompiled.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .search import cabs, first_event

__all__ = ["rigid_loop"]

#: phases in a row without time advancing (``tau == 0``) before the loop reports a stall
STALL = 50
#: the loop's status codes: finished the chunk; events repeat at one time (grazing); more
#: than ``max_impacts`` impacts within one forcing period (an accumulation that does not
#: close); paused after ``max_phases`` phases (the driver redraws the progress bar, then
#: calls again: a pause falls between two phases, so it does not change the run)
OK, STALLED, RUNAWAY, PAUSED = 0, 1, 2, 3
#: the Zeno rule's velocity resolution: a rebound slower than this fraction of the run's
#: velocity scale (see :func:`zeno_closes`) is taken as the end of the sequence
ZENO_VELOCITY_RTOL = 1e-6
#: the event search's zero tolerance, relative to a row's size (:func:`row_sizes`)
ZERO_RTOL = 1e-12
#: the impacts' columns: time, side, impulse, duration, relative velocity, phase
N_IMPACT_COLS = 6


@njit(cache=True)
def _cexpm1(z):  # pragma: no cover - compiled
    """``e^z - 1`` for complex ``z`` without cancellation near 0."""
    x, y = z.real, z.imag
    s = math.sin(0.5 * y)
    return complex(math.expm1(x) * math.cos(y) - 2.0 * s * s, math.exp(x) * math.sin(y))


@njit(cache=True, inline="always")
def _expm1_from(e, em1):  # pragma: no cover - compiled
    """``e^z - 1`` from ``e = e^z`` (as computed) and ``em1 = expm1(Re z)``, without
    cancellation: with ``e = e^x (c + i s)``, ``Re(e^z - 1) = expm1(x) c - s^2 / (1 + c)``
    (two terms of one sign where ``c > 0``; else, or where ``e^x < 1/2``, ``Re e - 1`` has
    no cancellation). The rounding of ``e`` (a few eps relative) passes to the result
    relatively; no transcendental call.
    """
    ex = 1.0 + em1
    if ex > 0.5:            # else |e| <= 0.5: no cancellation in Re e - 1
        c = e.real / ex
        if c > 0.0:
            sn = e.imag / ex
            return complex(em1 * c - sn * sn / (1.0 + c), e.imag)
    return complex(e.real - 1.0, e.imag)


@njit(cache=True)
def _start(kd, x, t0, omega):  # pragma: no cover - compiled
    """Coordinates ``(c1, c0, rot)`` of the state ``x`` at ``t0`` (``PhaseKind.start``)."""
    Vinv, in0, X = kd[5], kd[6], kd[8]
    n = x.size
    rot = complex(math.cos(omega * t0), math.sin(omega * t0))
    dev = np.empty(n)
    for q in range(n):
        dev[q] = x[q] - (X[q] * rot).real
    c1 = np.zeros(Vinv.shape[0], np.complex128)
    for j in range(Vinv.shape[0]):
        acc = 0j
        for q in range(n):
            acc += Vinv[j, q] * dev[q]
        c1[j] = acc
    c0 = np.zeros(in0.shape[0])
    for j in range(in0.shape[0]):
        acc_r = 0.0
        for q in range(n):
            acc_r += in0[j, q] * dev[q]
        c0[j] = acc_r
    return c1, c0, rot


@njit(cache=True)
def _coefficients(rv, rp, rx, c1, c0, rot, r_lo, r_hi):  # pragma: no cover - compiled
    """``(b, poly)`` of the rows ``r_lo:r_hi`` of ``(rv, rp, rx)`` for the coordinates."""
    R = r_hi - r_lo
    m1 = c1.size
    k = c0.size
    b = np.empty((R, m1 + 1), np.complex128)
    poly = np.zeros((R, k))
    for r in range(R):
        for j in range(m1):
            b[r, j] = rv[r_lo + r, j] * c1[j]
        b[r, m1] = rx[r_lo + r] * rot
        for j in range(k):
            acc = 0.0
            for q in range(k):
                acc += rp[r_lo + r, j, q] * c0[q]
            poly[r, j] = acc
    return b, poly


@njit(cache=True)
def _state(kd, c1, c0, rot, tau, omega):  # pragma: no cover - compiled
    """The state at ``tau`` (s) after the phase's start (``PhaseKind.state``)."""
    lam, V, S0P, X = kd[0], kd[4], kd[7], kd[8]
    n = V.shape[0]
    m1 = c1.size
    ec = np.empty(m1, np.complex128)
    for j in range(m1):
        ec[j] = np.exp(lam[j] * tau) * c1[j]
    x = np.zeros(n)
    for q in range(n):
        acc = 0.0
        for j in range(m1):
            acc += (V[q, j] * ec[j]).real
        x[q] = acc
    power = 1.0
    for j in range(c0.size):
        for q in range(n):
            acc = 0.0
            for p in range(c0.size):
                acc += S0P[j, q, p] * c0[p]
            x[q] += power * acc
        power *= tau
    rt = rot * complex(math.cos(omega * tau), math.sin(omega * tau))
    for q in range(n):
        x[q] += (X[q] * rt).real
    return x


@njit(cache=True)
def _augmented(x, t, omega, phi):  # pragma: no cover - compiled
    xa = np.empty(x.size + 2)
    xa[:x.size] = x
    ph = omega * t + phi
    xa[x.size], xa[x.size + 1] = math.cos(ph), math.sin(ph)
    return xa


@njit(cache=True)
def _integral(lam, b, poly, tau):  # pragma: no cover - compiled
    """``int_0^tau Re(sum b e^{lam s}) + poly(s) ds`` of one row (row units x s)."""
    out = 0.0
    for j in range(lam.size):
        e = tau if lam[j] == 0 else _cexpm1(lam[j] * tau) / lam[j]
        out += (b[j] * e).real
    for j in range(poly.size):
        out += poly[j] * tau ** (j + 1) / (j + 1)
    return out


@njit(cache=True)
def _decide(lam, b, poly, rtol, first):  # pragma: no cover - compiled
    """Stick (True) or separate: :func:`.cycle_run.decide` (four Taylor orders, from
    order ``first``: 1 where ``f(0) = 0`` by construction, relative degree 0)."""
    fact = 1.0
    lam_k = np.ones(lam.size, np.complex128)
    for k in range(4):
        if k:
            for j in range(lam.size):
                lam_k[j] = lam_k[j] * lam[j]
            fact *= k
        d, mag = 0.0, 0.0
        for j in range(lam.size):
            d += (b[j] * lam_k[j]).real
            mag += cabs(b[j]) * cabs(lam_k[j])
        if k < poly.size:
            d += fact * poly[k]
            mag += fact * abs(poly[k])
        if k >= first and abs(d) > rtol * mag:
            return d > 0.0
    return True


@njit(cache=True)
def row_sizes(b, poly, t_scale):  # pragma: no cover - compiled
    """The size of each event row ``Re(sum_j b_j e^{lam_j tau}) + sum_j poly_j tau^j`` over
    the time scale ``t_scale``: ``sum_j |b_j| + sum_j |poly_j| t_scale^j`` (shape (K,)),
    in the rows' units; both loops' event-search zero tolerance is :data:`ZERO_RTOL` of it.

    Each ``tau^j`` coefficient is weighted by ``t_scale^j`` (the loops pass the forcing
    period), so that the size, and every rule built on it (the zero tolerance, the Zeno
    rule's gap resolution), is the same whatever the unit of time. Summed as they stood,
    the coefficients of ``tau`` and ``tau^2`` (a damper mass's velocity, a stuck phase's
    integrators) counted in that unit: 1 s on the SI states, a reference time on a
    dimensionless form.
    """
    K, m = b.shape
    k = poly.shape[1]
    out = np.empty(K)
    for r in range(K):
        acc = 0.0
        for j in range(m):
            acc += cabs(b[r, j])
        w = 1.0
        for j in range(k):
            acc += abs(poly[r, j]) * w
            w *= t_scale
        out[r] = acc
    return out


@njit(cache=True)
def zeno_closes(e, v_rel, acc, c, gap_tol, v_scale):  # pragma: no cover - compiled
    """Whether an impact closes a Zeno sequence: replace it by a plastic impact, then
    :func:`_decide` (the ``Rigid`` law's stick-or-separate path), instead of a rebound.

    Parameters
    ----------
    e : float
        Coefficient of restitution (0 for ``Rigid``: always plastic).
    v_rel : float
        Approach velocity at the stop (m/s, > 0 approaching).
    acc : float
        Second derivative of that stop's gap in free flight at the impact (m/s^2; < 0: the
        relative acceleration pushes the damper mass back onto the stop).
    c : float
        Clearance on each side (m).
    gap_tol : float
        The event search's zero tolerance on that gap: :data:`ZERO_RTOL` of the gap row's
        size over a forcing period (:func:`row_sizes`), the gap's resolution.
    v_scale : float
        The run's velocity scale (m/s): the largest approach velocity so far, at least
        ``c Omega``.

    Returns
    -------
    bool
        True when the rebound ``u = e v_rel`` (m/s) is not resolved:

        * ``u <= ZENO_VELOCITY_RTOL * v_scale`` (the resolution of the restitution law);
        * ``e < 1`` and ``2 c <= gap_tol``: the two stops coincide to the gap's resolution,
          the rebound is at once an impact on the other stop, and the impacts
          ``v, e v, e^2 v, ...`` at one instant sum to a plastic impact (exact; at ``c = 0``
          the damper mass can never leave the primary);
        * ``acc < 0`` and ``h = u^2 / (2 |acc|) <= gap_tol``: the rebound's height is below
          the gap's resolution (the event search could not tell the next impact from a
          graze). Under the constant relative acceleration ``acc`` the remaining bounces
          (heights ``e^{2j} h``) accumulate at ``t + T_Z``, ``T_Z = 2 u / ((1 - e) |acc|)``
          (the geometric series of their flight times ``2 e^j u / |acc|``), with zero
          relative velocity: their limit is the stuck phase, which is taken at once
          instead of at ``t + T_Z``. That moves the damper mass by at most ``h`` and the
          primary by at most ``(m_d / M_eff) u T_Z = 4 (m_d / M_eff) h / (1 - e)`` (the
          sequence's momentum is exchanged within ``T_Z`` instead of at once).

        Neither scale vanishes with the clearance (``gap_tol`` is relative to the gap's
        terms, the primary's motion among them). A sequence closes after about
        ``ln(h_0 / gap_tol) / (2 ln(1/e))`` impacts (``h_0``: its first height; at most
        ~``14 / (1 - e)``).
    """
    if e <= 0.0:
        return True
    u = e * v_rel
    if u <= ZENO_VELOCITY_RTOL * v_scale:
        return True
    if e < 1.0 and 2.0 * c <= gap_tol:
        return True
    return acc < 0.0 and u * u <= -2.0 * acc * gap_tol


@njit(cache=True)
def _grow(a, need):  # pragma: no cover - compiled
    out = np.empty((a.shape[0], max(need, 2 * a.shape[1])))
    out[:, :a.shape[1]] = a
    return out


@njit(cache=True)
def _emit(lam, ob, op, t_a, tau, t0_run, dt_out, first_sample, work, times, vals, wk, grid,
          used):  # pragma: no cover - compiled
    """Samples of a phase starting at ``t_a`` (s), lasting ``tau``: the output grid strictly
    inside it, its end (and ``t_a`` itself if ``first_sample``). ``ob``, ``op``: the output
    rows' coefficients. Writes times, the sampled rows (the first six, then the output
    points' rows from row 8 on; rows 6 and 7 are the input-work weights), the input-work
    integrals (from ``work``, updated) and grid indices (-1: off the grid) from column
    ``used``; returns the arrays (grown if needed) and the new count.
    """
    j_lo = int(math.floor((t_a - t0_run) / dt_out + 1e-9)) + 1
    j_hi = int(math.ceil((t_a + tau - t0_run) / dt_out - 1e-9)) - 1
    n_in = 0
    for j in range(j_lo, j_hi + 1):
        s = t0_run + j * dt_out - t_a
        if 0.0 < s < tau:
            n_in += 1
    n_pts = n_in + 1 + (1 if first_sample else 0)
    taus = np.empty(n_pts)
    gi = np.empty(n_pts, np.int64)
    i = 0
    if first_sample:
        taus[0], gi[0] = 0.0, 0
        i = 1
    for j in range(j_lo, j_hi + 1):
        s = t0_run + j * dt_out - t_a
        if 0.0 < s < tau:
            taus[i], gi[i] = s, j
            i += 1
    end_j = (t_a + tau - t0_run) / dt_out
    taus[i] = tau
    gi[i] = int(round(end_j)) if abs(end_j - round(end_j)) < 1e-7 else -1
    if used + n_pts > times.size:
        need = used + n_pts
        t_new = np.empty(max(need, 2 * times.size))
        t_new[:used] = times[:used]
        times = t_new
        g_new = np.empty(max(need, 2 * grid.size), np.int64)
        g_new[:used] = grid[:used]
        grid = g_new
        vals = _grow(vals, need)
        wk = _grow(wk, need)
    m = lam.size
    iw = lam[m - 1]
    n_rows = vals.shape[0]          # sampled rows: ob's rows 0-5, then 8 on
    # the work integrals need Re(a_r e^{i w s}) Re(v_p(s)): the rows' excitation terms
    a0, a1 = ob[6, m - 1], ob[7, m - 1]
    for p in range(n_pts):
        s = taus[p]
        col = used + p
        times[col] = t_a + s
        grid[col] = gi[p]
        w0, w1 = 0.0, 0.0
        for r in range(n_rows):
            vals[r, col] = 0.0
        w = np.exp(iw * s)
        for j in range(m):
            z = np.exp(lam[j] * s) if j < m - 1 else w
            for r in range(n_rows):
                vals[r, col] += (ob[r if r < 6 else r + 2, j] * z).real
            # int_0^s e^{mu u} du for mu = i w + lam_j and i w + conj(lam_j), from the
            # exponentials at hand (see _expm1_from)
            vb = ob[1, j]
            em1 = math.expm1(lam[j].real * s)
            mu1 = iw + lam[j]
            mu2 = iw + np.conj(lam[j])
            e1 = complex(s) if mu1 == 0 else _expm1_from(w * z, em1) / mu1
            e2 = complex(s) if mu2 == 0 else _expm1_from(w * np.conj(z), em1) / mu2
            c1 = vb * e1
            c2 = np.conj(vb) * e2
            w0 += 0.5 * ((a0 * c1).real + (a0 * c2).real)
            w1 += 0.5 * ((a1 * c1).real + (a1 * c2).real)
        for r in range(n_rows):
            acc, pw = 0.0, 1.0
            for c in range(op.shape[1]):
                acc += op[r if r < 6 else r + 2, c] * pw
                pw *= s
            vals[r, col] += acc
        wk[0, col] = work[0] + w0
        wk[1, col] = work[1] + w1
    work[0] = wk[0, used + n_pts - 1]
    work[1] = wk[1, used + n_pts - 1]
    return times, vals, wk, grid, used + n_pts


@njit(cache=True)
def _pin(x, t, s, velocity, iy, iv, c, r0, r0A, omega, phi):  # pragma: no cover
    """Put the damper mass exactly on stop ``s`` (and at zero relative velocity)."""
    xa = _augmented(x, t, omega, phi)
    out = x.copy()
    out[iy] += s * c - np.dot(r0, xa)
    if velocity:
        out[iv] -= np.dot(r0A, xa)
    return out


@njit(cache=True)
def _new_impact(imp, n_imp, t, s, v_rel, omega, phi):  # pragma: no cover - compiled
    if n_imp == imp.shape[0]:
        grown = np.empty((2 * n_imp + 16, imp.shape[1]))
        grown[:n_imp] = imp[:n_imp]
        imp = grown
    imp[n_imp, 0], imp[n_imp, 1], imp[n_imp, 2] = t, s, 0.0
    imp[n_imp, 3], imp[n_imp, 4] = 0.0, v_rel
    imp[n_imp, 5] = (omega * t + phi) % (2.0 * math.pi)
    return imp, n_imp + 1


@njit(cache=True)
def rigid_loop(free, stuck_p, stuck_m, x, t, mode, side, on_boundary, open_row,
               first_sample, stall, crawl, v_max, work, cur, imp, n_imp, t_end, t_stop,
               max_phases, max_impacts, t0_run, dt_out, period, iy, iv, c, omega, phi, r0,
               r0A, r0AA, A, bl, inv_mu, rho, restitution,
               decide_rtol):  # pragma: no cover - compiled
    """Phases from ``(x, t)`` until ``t >= t_stop`` (or ``t_end``, s) for a rigid or
    instantaneous contact: :func:`.cycle_run.run`'s loop (see the module docstring).

    Parameters
    ----------
    free, stuck_p, stuck_m : tuple
        The free-flight and stuck (upper, lower stop) kinds (:func:`kind_arrays`).
    x, t, mode, side, on_boundary, open_row, first_sample, stall, crawl, v_max
        The loop's state (``mode``: 0 free, 1 stuck; ``open_row`` -1: none; ``v_max``:
        the Zeno rule's velocity scale, m/s), carried from one call to the next so that
        chunks of a run give the run itself.
    work : ndarray, shape (2,)
        The input-work integrals so far (updated in place).
    cur, imp, n_imp
        The open impact's row (-1: none) in the impacts table ``imp`` (rows ``:n_imp``;
        columns: time (s), side, impulse (N s), duration (s), relative velocity (m/s),
        forcing phase (rad)).
    t_end, t_stop : float
        End of the run (every search looks up to it) and of this call (s).
    max_phases, max_impacts : int
        Phases after which this call pauses (status ``PAUSED``), and impacts allowed within
        one forcing period (more: status ``RUNAWAY``).
    t0_run, dt_out, period : float
        Start of the run, output step and forcing period (s).
    iy, iv, c, omega, phi, r0, r0A, r0AA, A, bl, inv_mu, rho, restitution, decide_rtol
        The phases' builder (:class:`impactpred.damper._engine.Engine`): indices of
        ``y_d``, ``v_d``, clearance (m), excitation (rad/s, rad), the relative
        displacement / velocity / acceleration rows, the free-flight matrix, the contact
        force's input ``Bl[:n]``, ``1/mu`` (1/kg), the relative degree, ``e`` (0 for
        ``Rigid``) and ``decide``'s tolerance.

    Returns
    -------
    tuple
        ``(status, t, x, mode, side, on_boundary, open_row, first_sample, stall, crawl,
        v_max, cur, imp, n_imp, times, values, work_samples, grid, done)``: ``status``
        ``OK``; ``STALLED`` when events repeat without time advancing (then ``t`` and
        ``mode`` say where); ``RUNAWAY`` after the impact that is the ``max_impacts + 1``-th
        within one period (``t``: its time); ``PAUSED`` after ``max_phases`` phases
        (continue with the state returned); the samples of this call (``values``: the
        first six output rows, then the output points' three rows each); ``done``: the
        run reached ``t_end``.
    """
    cap = max(int((min(t_stop, t_end) - t) / dt_out), 0) * 2 + 256
    times = np.empty(cap)
    vals = np.empty((free[12].shape[0] - 2, cap))   # the output rows but the work weights
    wk = np.empty((2, cap))
    grid = np.empty(cap, np.int64)
    used = 0
    done = False
    status = OK
    n_phases = 0
    while t < t_end - 1e-12 * period and t < t_stop:
        if n_phases >= max_phases:
            status = PAUSED
            break
        n_phases += 1
        if mode == 0:
            kd = free
            r_lo, r_hi = 0, 2
        elif side == 1:
            kd = stuck_p
            r_lo, r_hi = 0, 1
        else:
            kd = stuck_m
            r_lo, r_hi = 1, 2
        lam = kd[0]
        c1, c0, rot = _start(kd, x, t, omega)
        b, poly = _coefficients(kd[9], kd[10], kd[11], c1, c0, rot, r_lo, r_hi)
        K = r_hi - r_lo
        if open_row >= 0 and c0.size and (mode == 0 or rho == 0):
            # the damper mass was put exactly on the stop: the open gap row is 0 at the
            # start; remove the closed form's rounding there
            s0 = 0.0
            for j in range(lam.size):
                s0 += b[open_row, j].real
            poly[open_row, 0] -= s0 + poly[open_row, 0]
        total = row_sizes(b, poly, period)
        zero_tol = np.empty(K)
        scale = np.empty(K)
        for r in range(K):
            zero_tol[r] = ZERO_RTOL * total[r] + 1e-300
            scale[r] = c if (mode == 0 and c > 0) else total[r]
        tau, row = first_event(lam, kd[1], kd[2], kd[3], b, poly, t_end - t, scale, zero_tol,
                               on_boundary, open_row)
        open_row = -1
        happened = row >= 0
        if not happened:
            tau = t_end - t
        ob, op = _coefficients(kd[12], kd[13], kd[14], c1, c0, rot, 0, kd[12].shape[0])
        times, vals, wk, grid, used = _emit(lam, ob, op, t, tau, t0_run, dt_out, first_sample,
                                            work, times, vals, wk, grid, used)
        first_sample = False
        if mode == 1 and cur >= 0:
            imp[cur, 2] += side * _integral(lam, ob[4], op[4], tau)
        x = _state(kd, c1, c0, rot, tau, omega)
        stall = stall + 1 if tau == 0.0 else 0
        crawl = crawl + 1 if tau < 1e-9 * period else 0
        if stall > STALL or crawl > 100 * STALL:
            return (STALLED, t, x, mode, side, on_boundary, open_row, first_sample, stall,
                    crawl, v_max, cur, imp, n_imp, times[:used], vals[:, :used],
                    wk[:, :used], grid[:used], done)
        t = t + tau
        if not happened:
            done = True
            break
        on_boundary = True
        if mode == 0:
            s = 1 if row == 0 else -1
            xa = _augmented(x, t, omega, phi)
            v_rel = s * np.dot(r0, A @ xa)
            v_max = max(v_max, v_rel)
            imp, n_imp = _new_impact(imp, n_imp, t, s, v_rel, omega, phi)
            cur = n_imp - 1
            if n_imp > max_impacts and imp[n_imp - 1 - max_impacts, 0] > t - period:
                return (RUNAWAY, t, x, mode, side, on_boundary, open_row, first_sample,
                        stall, crawl, v_max, cur, imp, n_imp, times[:used], vals[:, :used],
                        wk[:, :used], grid[:used], done)
            x = _pin(x, t, s, False, iy, iv, c, r0, r0A, omega, phi)
            e = restitution
            xa = _augmented(x, t, omega, phi)
            if zeno_closes(e, v_rel, -s * np.dot(r0AA, xa), c, zero_tol[row], v_max):
                # plastic (Rigid, or the limit of a Zeno sequence): the Rigid law's path
                p = max(v_rel, 0.0) / inv_mu if rho == 2 else 0.0
                x = x + s * p * bl
                imp[cur, 2] += p
                if rho == 2:
                    x = _pin(x, t, s, True, iy, iv, c, r0, r0A, omega, phi)
                ks = stuck_p if s == 1 else stuck_m
                kc1, kc0, krot = _start(ks, x, t, omega)
                i = 0 if s == 1 else 1
                sb, sp = _coefficients(ks[9], ks[10], ks[11], kc1, kc0, krot, i, i + 1)
                stick = _decide(ks[0], sb[0], sp[0], decide_rtol, 1 if rho == 0 else 0)
            else:
                p = (1.0 + e) * v_rel / inv_mu
                x = x + s * p * bl
                imp[cur, 2] += p
                stick = False
            if stick:
                mode, side, open_row = 1, s, 0
            else:
                mode, open_row = 0, (0 if s == 1 else 1)
        else:
            if cur >= 0:
                imp[cur, 3] = t - imp[cur, 0]
            x = _pin(x, t, side, rho == 2, iy, iv, c, r0, r0A, omega, phi)
            mode, open_row = 0, (0 if side == 1 else 1)
    if not t < t_end - 1e-12 * period:
        done = True
    return (status, t, x, mode, side, on_boundary, open_row, first_sample, stall, crawl,
            v_max, cur, imp, n_imp, times[:used], vals[:, :used], wk[:, :used], grid[:used],
            done)
