"""Hertz contact phases of the two-sided (impact-damper) runs: exact modal discretisation.

During a Hertz contact at the stop ``s`` the engine's augmented state
``xa = [x, xh]`` (the primary's modal states, ``y_d`` (m), ``v_d`` (m/s), the constant
1, and the harmonic pair ``xh``; see :mod:`impactpred.damper._engine`) obeys

    xa' = A xa + Bl lam(t),        lam = s f,     f = k d**n   (d > 0)

with the penetration ``d = s r0 xa - c - d_p f`` (m; ``r0 xa`` is ``y_d - y_p`` without
the contact force's own instantaneous compliance ``d_p`` (m/N), the primary's residual
flexibility) and ``f`` (N) the compressive Hertz force.

Discretisation (fixed step ``h`` per contact)
---------------------------------------------
The force is taken linear over each step, ``lam(t_j + tau) = lam_j + (lam_{j+1} - lam_j)
tau / h``. For such a force the linear part is solved EXACTLY (to rounding): the
primary's modes, the damper mass (double integrator) and the harmonic excitation
(rotation of ``xh``) all go through one Van Loan matrix exponential,

    expm([[A, Bl, 0], [0, 0, 1], [0, 0, 0]] tau) = [[Phi, G1, G2], ...],
    xa(tau) = Phi xa_j + G1 lam_j + G2 (lam_{j+1} - lam_j) / h.

The end-of-step force solves the Hertz law at the end of the step,
``f = k (P - K f)**n`` with ``P`` the penetration the step would end with at zero end
force and ``K = d_p - r0 G2 / h > 0`` (m/N) the step's own compliance to its end force;
a safeguarded scalar Newton (:meth:`impactpred.Hertz.step_force`). This is the
trapezoidal rule for the nonlinear force only: second order, global error ``O(h^2)``.
The only approximation is the force's linear interpolation. Measured on a sphere
striking a heavy primary (``tests/test_impactpred_damper_hertz.py``), at the default
step: contact duration 9e-6 relative (observed order 2.0 when halving the step),
impulse 2e-7, rebound velocity 3e-7 (pre-asymptotic: order 1.5 -> 1.9); energy
balance of a forced run (Hertz is conservative) 3e-6 of the stored energy.

The step is ``h = T_c / STEPS_PER_CONTACT`` (default 200) with ``T_c`` the closed-form
duration of a Hertz impact of the effective mass ``1 / (1/m_d + 1/M_eff)`` on a rigid
wall at the approach speed (:func:`hertz_duration`), rounded down onto a geometric
grid (ratio ``2**(1/4)``) so that the step maps are reused from impact to impact, and
never longer than a forcing period / ``MIN_STEPS_PER_PERIOD``.

Exit: the contact ends in the first step whose end force is 0 (the zero-force end
penetration ``P <= 0``). The exit time ``tau*`` in that step is the root of the
penetration with the force ramped from ``lam_j`` to 0 over ``[0, tau*]`` (so the force
is continuous and vanishes at the exit, as the law requires), found by a bracketed
Illinois iteration on the exact step solution; the returned state is on the open
side, with the gap at rounding level, so the exact free flight resumes from it.

Input work (J, rows as in :mod:`.cycle_run`: ``int F_eq v_p dt`` and
``int y_b' v_p dt``) is integrated over each step by Simpson's rule with the exact
mid-step state of the discrete trajectory (``O(h^4)`` against that trajectory).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

__all__ = ["MIN_STEPS_PER_PERIOD", "STEPS_PER_CONTACT", "hertz_contact", "hertz_duration"]

#: steps per estimated contact duration (before rounding onto the geometric grid)
STEPS_PER_CONTACT = 200
#: the step never exceeds the forcing period divided by this
MIN_STEPS_PER_PERIOD = 1000
#: geometric grid of step sizes: h = period / MIN_STEPS_PER_PERIOD * 2**(-q/_QUANT)
_QUANT = 4
_MAX_EXIT_ITER = 200


def hertz_duration(stiffness, exponent, mass, speed):
    """Closed-form duration (s) of a Hertz impact on a rigid wall, ``e = 1``.

    ``m d'' = -k d**n`` from ``d = 0, d' = v``: the maximum penetration is
    ``d_max = ((n + 1) m v^2 / (2 k))**(1/(n+1))`` and the duration
    ``2 (d_max / v) int_0^1 (1 - u**(n+1))**(-1/2) du``; for ``n = 1.5`` this is
    ``2.9432 d_max / v = 3.2185 (m^2 / (k^2 v))**(1/5)`` (Johnson, Contact Mechanics,
    11.2), for ``n = 1`` it is ``pi sqrt(m / k)``.

    Parameters
    ----------
    stiffness : float
        ``k`` (N/m**n).
    exponent : float
        ``n``.
    mass : float
        Effective mass (kg).
    speed : float
        Approach speed (m/s), > 0.
    """
    p = exponent + 1.0
    d_max = (p * mass * speed ** 2 / (2.0 * stiffness)) ** (1.0 / p)
    integral = math.gamma(1.0 / p) * math.sqrt(math.pi) / (p * math.gamma(1.0 / p + 0.5))
    return 2.0 * d_max / speed * integral


class _Maps:
    """Exact maps of one step length ``tau`` (s) for a force linear over the step."""

    __slots__ = (
        "G1",
        "G2",
        "Phi",
        "_ext",
        "_half",
        "hz",
        "r0G2",
        "r0Pa",
        "r0Phi",
        "tau",
        "vG1",
        "vG2",
        "vPhi",
    )

    def __init__(self, hz, tau):
        N = hz.N
        E = expm(hz.vanloan * tau)
        self.hz, self.tau = hz, tau
        self.Phi, self.G1, self.G2 = E[:N, :N], E[:N, N], E[:N, N + 1]
        self.r0Phi = hz.r0 @ self.Phi
        self.r0G2 = float(hz.r0 @ self.G2)
        self.r0Pa = float(hz.r0 @ self.G1) - self.r0G2 / tau
        self.vPhi = hz.vrow @ self.Phi
        self.vG1, self.vG2 = float(hz.vrow @ self.G1), float(hz.vrow @ self.G2)
        self._half = self._ext = None

    def state(self, xa, lam0, slope):
        """``xa`` after ``tau`` with the force ``lam0 + slope * t`` (N, N/s) on it."""
        return self.Phi @ xa + self.G1 * lam0 + self.G2 * slope

    def vp(self, xa, lam0, slope):
        """Primary velocity (m/s) at the end of the step, from the start state."""
        hz = self.hz
        return float(self.vPhi @ xa) + self.vG1 * lam0 + self.vG2 * slope \
            + hz.vB * (lam0 + slope * self.tau) + hz.d_p * slope

    def half(self):
        if self._half is None:
            self._half = _Maps(self.hz, 0.5 * self.tau)
        return self._half

    def ext(self):
        """One matrix for a whole step: ``[xa, lam0, slope] -> [xa(tau), v_p(tau),
        v_p(tau / 2)]`` (built once per cached step)."""
        if self._ext is None:
            hz, hf, tau = self.hz, self.half(), self.tau
            N = hz.N
            E = np.empty((N + 2, N + 2))
            E[:N, :N], E[:N, N], E[:N, N + 1] = self.Phi, self.G1, self.G2
            E[N] = np.concatenate([self.vPhi, [self.vG1 + hz.vB,
                                               self.vG2 + hz.vB * tau + hz.d_p]])
            E[N + 1] = np.concatenate([hf.vPhi, [hf.vG1 + hz.vB,
                                                 hf.vG2 + hz.vB * 0.5 * tau + hz.d_p]])
            self._ext = E
        return self._ext


class _Hertz:
    """Per-engine data of the Hertz contact phases (built once, cached on the engine)."""

    def __init__(self, eng):
        A, Bl = eng.A, eng.Bl
        N = A.shape[0]
        self.N, self.n = N, eng.n
        V = np.zeros((N + 2, N + 2))
        V[:N, :N] = A
        V[:N, N] = Bl
        V[N, N + 1] = 1.0
        self.vanloan = V
        self.r0, self.yp0, self.A = eng.r0, eng.yp0, A
        self.vrow = eng.yp0 @ A                 # v_p = vrow xa + vB lam + d_p lam'
        self.vB = float(eng.yp0 @ Bl)
        # the output points (free-flight rows, the contact force apart): within a step
        # the force is linear in time (lam' = slope, lam'' = 0), so y_j = P xa + d lam,
        # y_j' = P A xa + P Bl lam + d slope, y_j'' = P A^2 xa + P A Bl lam + P Bl slope
        P, d = eng.point_rows(np.zeros(N)), eng.point_d
        self.point_rows = np.vstack([P, P @ A, P @ A @ A])
        self.point_lam = np.concatenate([d, P @ Bl, P @ A @ Bl])
        self.point_slope = np.concatenate([np.zeros_like(d), d, P @ Bl])
        self.exc_row, self.fvec, self.bv_row = eng.rows_extra
        self.d_p = float(eng.d_p)
        self.c = float(eng.c)
        self.iy, self.iv = eng.iy, eng.iv
        self.law = eng.contact
        c2 = float(eng.c_coefs[2])
        m_d = float(eng.m_d)
        self.m_eff = min(m_d, 1.0 / c2) if c2 > 0 else m_d
        self.h_max = eng.period / MIN_STEPS_PER_PERIOD
        self.omega, self.phi = eng.omega, eng.phi
        self._cache = {}

    def maps(self, q):
        """Maps of the grid step ``h_max * 2**(-q / _QUANT)`` (cached)."""
        m = self._cache.get(q)
        if m is None:
            if len(self._cache) > 64:
                self._cache.clear()
            m = self._cache[q] = _Maps(self, self.h_max * 2.0 ** (-q / _QUANT))
        return m

    def xh(self, t):
        ph = self.omega * t + self.phi
        return math.cos(ph), math.sin(ph)

    def force(self, P, K):
        """Compressive force (N) with ``f = k (P - K f)**n``, ``K >= 0`` (m/N)."""
        if P <= 0.0:
            return 0.0
        if K > 0.0:
            return self.law.step_force(-P, K, 0.0, 1.0)
        return self.law.stiffness * P ** self.law.exponent

    def vp(self, xa, lam, slope):
        return float(self.vrow @ xa) + self.vB * lam + self.d_p * slope

    def outputs(self, xa, lam, slope):
        """Output rows y_p, v_p, y_d, v_d, lam, excitation, then the output points'
        displacements, velocities and accelerations (as the front end's
        ``impactpred.damper._engine.Engine._kind``)."""
        points = self.point_rows @ xa + self.point_lam * lam + self.point_slope * slope
        return (float(self.yp0 @ xa) + self.d_p * lam, self.vp(xa, lam, slope),
                float(xa[self.iy]), float(xa[self.iv]), lam,
                float(self.exc_row @ xa[self.n:]), *points)

    def loads(self, t):
        """(F_eq (N), y_b' (m/s)) at ``t``: the two input-work weights."""
        c, s = self.xh(t)
        return (self.fvec[0] * c + self.fvec[1] * s, self.bv_row[0] * c + self.bv_row[1] * s)

    def work(self, t, m, xa, lam, slope, v0, v1):
        """Simpson's rule of ``F_eq v_p`` and ``y_b' v_p`` over the step ``m`` from ``t``."""
        tau = m.tau
        vm = m.half().vp(xa, lam, slope)
        f0, b0 = self.loads(t)
        fm, bm = self.loads(t + 0.5 * tau)
        f1, b1 = self.loads(t + tau)
        w = tau / 6.0
        return np.array([w * (f0 * v0 + 4.0 * fm * vm + f1 * v1),
                         w * (b0 * v0 + 4.0 * bm * vm + b1 * v1)])


def _hertz_force(P, K, k, ne, guess):
    """Root ``f`` (N) of ``f = k (P - K f)**ne`` on ``[0, P / K]``, ``P > 0``, ``K > 0``.

    The same safeguarded Newton iteration as :meth:`impactpred.Hertz.step_force`,
    started from ``guess`` (the previous steps' extrapolation).
    """
    lo, hi = 0.0, P / K
    f = guess if 0.0 < guess < hi else min(hi, k * P ** ne)
    for _ in range(100):
        d = P - K * f
        kd = k * d ** (ne - 1.0) if d > 0.0 else 0.0
        phi = f - kd * d if d > 0.0 else f
        if phi > 0.0:
            hi = f
        else:
            lo = f
        f_new = f - phi / (1.0 + ne * K * kd)
        if not lo < f_new < hi:
            f_new = 0.5 * (lo + hi)
        if abs(f_new - f) <= 1e-14 * f_new or hi - lo <= 1e-15 * hi:
            return f_new
        f = f_new
    return f


def _engine_data(eng):
    hz = getattr(eng, "_hertz_data", None)
    if hz is None:
        hz = _Hertz(eng)
        eng._hertz_data = hz
    return hz


def hertz_contact(eng, x, t, side, t_end, t0_run, dt_out):
    """Advance a Hertz contact at the stop ``side`` until the penetration returns to 0.

    Parameters
    ----------
    eng : impactpred.damper._engine.Engine
        The damper's engine (``eng.contact`` is an :class:`impactpred.Hertz`).
    x : ndarray, shape (n,)
        Engine state at the contact's start (or at a run's start inside a contact).
    t : float
        Its time (s).
    side : int
        +1 upper stop, -1 lower stop.
    t_end : float
        End of the run (s): the contact is cut there if still closed.
    t0_run, dt_out : float
        Output grid ``t0_run + j dt_out`` (s).

    Returns
    -------
    t_new : float
        Exit time (s), or ``t_end`` if the contact is still closed then.
    x_new : ndarray, shape (n,)
        State at ``t_new``; at an exit the gap is 0 to rounding, on the open side.
    impulse : float
        ``int f dt`` (N s, >= 0) over ``[t, t_new]`` (exact for the piecewise-linear force).
    samples : list of (ts, vals, grid, dwork)
        Outputs: ``ts`` (s), ``vals`` (6 x len(ts): y_p, v_p, y_d, v_d, lam, excitation),
        ``grid`` (output-grid index, -1 off the grid) at the output-grid times strictly
        inside ``(t, t_new)``, at ``t_new``, and at ``t`` too when ``t == t0_run``;
        ``dwork`` (2 x len(ts)): input work (J) since ``t`` (see the module docstring).
    closed : bool
        True when the contact is still closed at ``t_new`` (cut by ``t_end``).
    """
    hz = _engine_data(eng)
    s = float(side)
    n, N = hz.n, hz.N
    xa = np.empty(N)
    xa[:n] = x
    xa[n:] = hz.xh(t)
    c, r0, law = hz.c, hz.r0, hz.law
    # force now: 0 at a contact's start; inside a contact (a continued run) the law's
    # root with the primary's instantaneous compliance d_p
    pen_rigid = s * float(r0 @ xa) - c
    f = hz.force(pen_rigid, hz.d_p)
    lam = s * f
    # step from the closed-form duration at the equivalent approach speed
    v_rel = s * float(r0 @ (hz.A @ xa))
    e_spring = law.stiffness * max(pen_rigid - hz.d_p * f, 0.0) ** (law.exponent + 1.0) \
        / (law.exponent + 1.0)
    v_eq = math.sqrt(max(v_rel, 0.0) ** 2 + 2.0 * e_spring / hz.m_eff)
    q = 0
    if v_eq > 0.0:
        h_want = hertz_duration(law.stiffness, law.exponent, hz.m_eff, v_eq) / STEPS_PER_CONTACT
        if h_want < hz.h_max:
            q = math.ceil(_QUANT * math.log2(hz.h_max / h_want) - 1e-9)
    mp = hz.maps(q)
    h = mp.tau
    K = hz.d_p - mp.r0G2 / h                # end-of-step compliance (m/N), > 0

    ts, rows, grid, works = [], [], [], []
    work = np.zeros(2)

    def record(tt, xs, lam_s, slope_s, g):
        ts.append(tt)
        rows.append(hz.outputs(xs, lam_s, slope_s))
        grid.append(g)
        works.append(work.copy())

    def grid_index(tt):
        jj = (tt - t0_run) / dt_out
        r = round(jj)
        return int(r) if abs(jj - r) < 1e-7 else -1

    def interior(m, xa, lam, slope, t, v0):
        """Output-grid samples strictly inside ``(t, t + m.tau)`` (exact maps)."""
        j_lo = math.floor((t - t0_run) / dt_out + 1e-9) + 1
        j_hi = math.ceil((t + m.tau - t0_run) / dt_out - 1e-9) - 1
        base = work.copy()
        for jj in range(j_lo, j_hi + 1):
            tg = t0_run + jj * dt_out
            d = tg - t
            if not 0.0 < d < m.tau:
                continue
            mg = _Maps(hz, d)
            xg = mg.state(xa, lam, slope)
            xg[n:] = hz.xh(tg)
            vg = mg.vp(xa, lam, slope)
            work[:] = base + hz.work(t, mg, xa, lam, slope, v0, vg)
            record(tg, xg, lam + slope * d, slope, jj)
        work[:] = base

    if t == t0_run:
        record(t, xa, lam, 0.0, 0)
    kk, ne = law.stiffness, law.exponent
    om, phi0 = hz.omega, hz.phi
    (fv0, fv1), (bv0, bv1) = hz.fvec, hz.bv_row
    l0f, l0b = hz.loads(t)
    ext = np.empty(N + 2)
    f_old = f
    # next output-grid time after t
    t_grid = t0_run + (math.floor((t - t0_run) / dt_out + 1e-9) + 1) * dt_out
    impulse = 0.0
    t_start, j = t, 0
    v_prev = hz.vp(xa, lam, 0.0)
    closed = True
    while t < t_end:
        t_next = t_start + (j + 1) * h
        if t_next >= t_end - 1e-9 * h:       # last step: up to the run's end
            m, t_next = _Maps(hz, t_end - t), t_end
            Km = hz.d_p - m.r0G2 / m.tau
        else:
            m, Km = mp, K
        tau = m.tau
        P = s * (float(m.r0Phi @ xa) + m.r0Pa * lam) - c
        if P <= 0.0:
            f1 = 0.0
        elif m is mp:
            f1 = _hertz_force(P, K, kk, ne, 2.0 * f - f_old)
        else:
            f1 = hz.force(P, Km)
        if f1 > 0.0:
            slope = (s * f1 - lam) / tau
            if m is mp:
                ext[:N], ext[N], ext[N + 1] = xa, lam, slope
                out = m.ext() @ ext
                x1, v1, vm = out[:N], out[N], out[N + 1]
            else:
                x1 = m.state(xa, lam, slope)
                v1 = m.vp(xa, lam, slope)
                vm = m.half().vp(xa, lam, slope)
            ph = om * t_next + phi0
            x1[n] = cx = math.cos(ph)
            x1[n + 1] = sx = math.sin(ph)
            if t_next > t_grid:
                interior(m, xa, lam, slope, t, v_prev)
                t_grid = t0_run + (math.floor((t_next - t0_run) / dt_out + 1e-9) + 1) * dt_out
            phm = ph - 0.5 * om * tau
            cm, sm = math.cos(phm), math.sin(phm)
            w = tau / 6.0
            l1f, l1b = fv0 * cx + fv1 * sx, bv0 * cx + bv1 * sx
            work[0] += w * (l0f * v_prev + 4.0 * (fv0 * cm + fv1 * sm) * vm + l1f * v1)
            work[1] += w * (l0b * v_prev + 4.0 * (bv0 * cm + bv1 * sm) * vm + l1b * v1)
            l0f, l0b = l1f, l1b
            impulse += 0.5 * tau * (f + f1)
            xa, lam, f_old, f, t, v_prev = x1, s * f1, f, f1, t_next, v1
            j += 1
            if t >= t_end:
                record(t, xa, lam, slope, grid_index(t))
            continue
        # the end force is 0: the penetration returns to 0 inside this step
        tau, me, x1 = _exit(hz, xa, lam, s, m)
        slope = -lam / tau
        x1[n:] = hz.xh(t + tau)
        v1 = me.vp(xa, lam, slope)
        interior(me, xa, lam, slope, t, v_prev)
        work += hz.work(t, me, xa, lam, slope, v_prev, v1)
        impulse += 0.5 * tau * f
        xa, lam, f, t = x1, 0.0, 0.0, t + tau
        closed = False
        record(t, xa, 0.0, slope, grid_index(t))
        break
    samples = [(np.array(ts), np.array(rows, dtype=float).T, np.array(grid, dtype=int),
                np.array(works).T)]
    return t, xa[:n].copy(), impulse, samples, closed


def _exit(hz, xa, lam, s, m):
    """Exit inside the step ``m`` whose end force is 0.

    ``tau* in (0, m.tau]``: the penetration with the force ramped from ``lam`` (N) to 0
    over ``[0, tau*]`` is 0 there; bracketed Illinois iteration on the exact maps.
    Returns ``(tau*, maps of tau*, state)``, the bracket end on the open side
    (penetration <= 0); the whole step when the force is 0 from its start (a graze).
    """
    c, r0 = hz.c, hz.r0

    def pen(tau, mm=None):
        mm = mm if mm is not None else _Maps(hz, tau)
        x = mm.state(xa, lam, -lam / tau)
        return s * float(r0 @ x) - c, x, mm

    lo, p_lo = 0.0, s * float(r0 @ xa) - c          # zero force from here on: no D-part
    hi = m.tau
    p_hi, x_hi, m_hi = pen(hi, m)
    if lam == 0.0 or p_hi > 0.0 or p_lo <= 0.0:
        # a graze shorter than the step (exact free flight over it), or not bracketed
        # (rounding): leave at the step's end, open
        return hi, m_hi, x_hi
    scale = abs(c) + abs(float(r0 @ xa)) + 1e-300
    f_lo, f_hi, last = p_lo, p_hi, 0
    for _ in range(_MAX_EXIT_ITER):
        if hi - lo <= 4e-16 * hi or -p_hi <= 1e-15 * scale:
            break
        tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        if not lo < tau < hi:
            tau = 0.5 * (lo + hi)
        p, x, mm = pen(tau)
        if p > 0.0:
            lo, f_lo = tau, p
            if last == 1:
                f_hi *= 0.5
            last = 1
        else:
            hi, p_hi, f_hi, x_hi, m_hi = tau, p, p, x, mm
            if last == -1:
                f_lo *= 0.5
            last = -1
    return hi, m_hi, x_hi
