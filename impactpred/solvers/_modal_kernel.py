"""Compiled (numba) kernel of the modal solver's first-order-hold stepping.

See :mod:`impactpred.solvers.modal` for the scheme. Everything here is a plain function
of arrays and scalars; nothing is compiled or computed at import time (``cache=True``
keeps the machine code on disk after the first call).

Notation per body: complex modal states ``z`` (``z' = p z + u``), weights ``w`` (the
displacement is ``Re(sum w z) + d + D u``), rigid displacement ``d`` and velocity ``v``
(``d'' = u/M``, ``inv = 1/M``), flexibility ``D``; ``u`` is the total force on the body
(N, along ``+y``), linear in time on every (sub)step: ``u(tau) = u0 + sig tau``.
"""

from __future__ import annotations

import numpy as np
from numba import njit


#: contact-law codes of the kernel
RIGID, SPRING, HERTZ = 0, 1, 2

_SERIES = 0.5    # |p s| below which the hold coefficients come from their Taylor series


@njit(cache=True)
def hold_coefficients(p, s, E, A, C, Q):
    """Fill ``E = e^{ps}``, ``A = int_0^s e^{p(s-t)} dt``, ``C = int_0^s e^{p(s-t)} t dt``
    and ``Q = (C - s^2/2)/p`` (the time integral of a mode's ramp response), per pole."""
    for k in range(p.size):
        pk = p[k]
        x = pk * s
        if abs(x) < _SERIES:
            # A = s sum x^j/(j+1)!, C = s^2 sum x^j/(j+2)!, Q = s^3 sum x^j/(j+3)!
            t1 = 1.0 + 0.0j
            t2 = 0.5 + 0.0j
            t3 = 1.0 / 6.0 + 0.0j
            a = t1
            c = t2
            q = t3
            for j in range(1, 22):
                t1 = t1 * (x * (1.0 / (j + 1)))
                t2 = t2 * (x * (1.0 / (j + 2)))
                t3 = t3 * (x * (1.0 / (j + 3)))
                a += t1
                c += t2
                q += t3
                if abs(t1.real) + abs(t1.imag) < 1e-17:
                    break
            E[k] = 1.0 + x * a
            A[k] = s * a
            C[k] = s * s * c
            Q[k] = s * s * s * q
        else:
            e = np.exp(x)
            E[k] = e
            em1 = e - 1.0
            A[k] = em1 / pk
            C[k] = (em1 - x) / (pk * pk)
            Q[k] = (em1 - x - 0.5 * x * x) / (pk * pk * pk)


@njit(cache=True)
def advance(z, d, v, p, w, inv, D, s, u0, sig, E, A, C, Q, zout):
    """One body over ``[0, s]`` under ``u = u0 + sig t``: exact.

    Fills ``zout`` (may not alias ``z``); returns ``(d, v, y, int_0^s y dt)`` at ``s``.
    """
    hold_coefficients(p, s, E, A, C, Q)
    yre = 0.0
    yint = 0.0
    for k in range(p.size):
        zk = z[k]
        zn = E[k] * zk + A[k] * u0 + C[k] * sig
        zout[k] = zn
        yre += (w[k] * zn).real
        yint += (w[k] * (A[k] * zk + C[k] * u0 + Q[k] * sig)).real
    s2 = s * s
    d1 = d + v * s + inv * (0.5 * u0 * s2 + sig * s2 * s / 6.0)
    v1 = v + inv * (u0 * s + 0.5 * sig * s2)
    y1 = yre + d1 + D * (u0 + sig * s)
    yint += (d * s + 0.5 * v * s2 + inv * (u0 * s2 * s / 6.0 + sig * s2 * s2 / 24.0)
             + D * (u0 * s + 0.5 * sig * s2))
    return d1, v1, y1, yint


@njit(cache=True)
def velocity(z, v, p, w, D, u, sig):
    """``y'`` of a body with states ``z``, rigid velocity ``v``, force ``u`` rising at ``sig``."""
    acc = 0.0
    for k in range(p.size):
        acc += (w[k] * (p[k] * z[k] + u)).real
    return acc + v + D * sig


def hertz_step_force(G, K, k, n):
    """Root of ``f = k (-(G + K f))^n`` on ``[0, -G/K]`` (``G < 0``, ``K > 0``): Newton
    safeguarded by bisection, to 1e-14 relative.

    The penetration is clipped at 0 where a force at the bracket's top rounds past it
    (``d**n`` of a negative ``d`` is NaN). Plain Python: ``Hertz.step_force`` calls it, and
    this module compiles it as :func:`hertz_force` (here, so that the cache of the compiled
    callers, which numba keys on this file, sees an edit).
    """
    lo = 0.0
    hi = -G / K
    f = min(hi, k * (-G) ** n)          # the force with the bodies' compliance neglected
    for _ in range(100):
        d = max(-(G + K * f), 0.0)
        phi = f - k * d ** n
        if phi > 0.0:
            hi = f
        else:
            lo = f
        dphi = 1.0 + k * n * K * d ** (n - 1.0) if d > 0.0 else 1.0
        f_new = f - phi / dphi
        if not lo < f_new < hi:         # Newton left the bracket: bisect
            f_new = 0.5 * (lo + hi)
        if abs(f_new - f) <= 1e-14 * max(f_new, 1e-300) or hi - lo <= 1e-15 * hi:
            return f_new
        f = f_new
    return f


@njit(cache=True)
def dashpot_floor(c, yv1, yv2, steps):
    """The rounding (N) of a dashpot force ``c d'`` after ``steps`` steps in contact.

    ``d' = y2' - y1'`` is a difference of the bodies' velocities, each advanced with a
    rounding of ``eps |y'|`` a step: ``c eps (|y1'| + |y2'|)`` per step, summed over the
    contact (a bound: two 1 kg masses through ``c = 1e6`` N s/m had drifted ``1e-9`` N over
    340 steps, under a fiftieth of it). Where the exact force decays below it (a heavily
    overdamped contact, its force ``1e-13`` of the peak), the stepped force had crept
    at that drift's level and the contact lasted twice its exact duration.
    """
    return 2.220446049250313e-16 * c * (abs(yv1) + abs(yv2)) * steps


#: the Hertz law's step force, compiled (``impactpred.contact.Hertz.step_force`` calls the
#: plain function)
hertz_force = njit(cache=True)(hertz_step_force)


@njit(cache=True)
def law_force(code, k, c, n, G, K, Gv, Kv, floor):
    """End-of-step force ``f >= 0`` and the signed quantity ``q`` that crosses 0 at separation.

    The gap at the step's end is ``G + K f`` and its rate ``Gv + Kv f``. ``q`` is the
    unclipped force for rigid and spring contact (``<= 0`` when the law gives no force);
    for Hertz contact the caller uses the gap instead. A spring-dashpot's force at or
    below ``floor`` (N, the rounding of its ``c d'``: :func:`dashpot_floor`) is no force:
    ``q`` is then the force less the floor.
    """
    if code == RIGID:
        fs = -G / K
        return max(0.0, fs), fs
    if code == SPRING:
        fs = (-k * G - c * Gv) / (1.0 + k * K + c * Kv)
        if fs > floor and G + K * fs < 0.0:
            return fs, fs
        if fs <= floor:
            return 0.0, fs - floor
        return 0.0, -k * (G + K * fs)
    if G >= 0.0:
        return 0.0, 0.0
    f = hertz_force(G, K, k, n)
    return f, f


@njit(cache=True, fastmath={"reassoc", "contract"})
def _step_pass(z, pe, zf, E, A, C, w, wA, u0, sig, need_int):
    """``zf = E (z + C pe) + A u0 + C sig`` (``z + C pe``: the states with a pending ramp).

    Returns ``Re(sum w zf)`` and, if ``need_int``, ``Re(sum w A (z + C pe))``.
    """
    yr = 0.0
    yi = 0.0
    m = z.size
    if pe != 0.0 or need_int:
        for j in range(m):
            zt = z[j] + C[j] * pe
            zn = E[j] * zt + A[j] * u0 + C[j] * sig
            zf[j] = zn
            yr += (w[j] * zn).real
            yi += (wA[j] * zt).real
    elif u0 != 0.0 or sig != 0.0:
        for j in range(m):
            zn = E[j] * z[j] + A[j] * u0 + C[j] * sig
            zf[j] = zn
            yr += (w[j] * zn).real
    else:
        for j in range(m):
            zn = E[j] * z[j]
            zf[j] = zn
            yr += (w[j] * zn).real
    return yr, yi


@njit(cache=True)
def _settle(z, pe, C):
    """Apply a pending ramp: ``z += C pe``."""
    if pe != 0.0:
        for j in range(z.size):
            z[j] += C[j] * pe


@njit(cache=True)
def _free_gap(s, z1, d1, v1, p1, w1, inv1, D1, z2, d2, v2, p2, w2, inv2, D2, gap0,
              u10, s1g, u20, s2g, E1, A1, C1, Q1, E2, A2, C2, Q2, zs1, zs2):
    """Gap and its rate at ``s`` into a step with no contact force (loads only)."""
    _, vv1, y1, _ = advance(z1, d1, v1, p1, w1, inv1, D1, s, u10, s1g, E1, A1, C1, Q1, zs1)
    _, vv2, y2, _ = advance(z2, d2, v2, p2, w2, inv2, D2, s, u20, s2g, E2, A2, C2, Q2, zs2)
    rate = (velocity(zs2, vv2, p2, w2, D2, u20 + s2g * s, s2g)
            - velocity(zs1, vv1, p1, w1, D1, u10 + s1g * s, s1g))
    return y2 - y1 + gap0, rate


@njit(cache=True)
def _ramp_response(inv, D, h, w, p, C, Q):
    """One body's displacement ``Rb``, velocity ``Kv`` and displacement integral ``Qb`` at
    a step's end per unit end-of-step force of a ramp from 0 (rigid body, flexibility and
    modes with weights ``w``, poles ``p`` and hold coefficients ``C``, ``Q``)."""
    h2 = h * h
    Rb = inv * h2 / 6.0 + D
    Kv = inv * h / 2.0 + D / h
    Qb = inv * h2 * h / 24.0 + D * h / 2.0
    for j in range(p.size):
        Rb += (w[j] * C[j]).real / h
        Kv += (w[j] * (p[j] * C[j] / h + 1.0)).real
        Qb += (w[j] * Q[j]).real / h
    return Rb, Kv, Qb


@njit(cache=True)
def foh_stepping(p1, w1, inv1, D1, z1_0, d1_0, v1_0,
                 p2, w2, inv2, D2, z2_0, d2_0, v2_0,
                 load1, load2, has_load, gap0, h, n_steps, code, k, c, n):
    """First-order-hold stepping with contact events located inside the steps.

    Returns ``force`` (node values, N), ``y1``, ``y2`` (m) on the grid, ``events`` (rows:
    time s, +1 start / -1 end, step index), the number of events, the contact impulse of
    every step (N s), the work done on each body (J), and the final ``z1, d1, v1, z2, d2,
    v2``.
    """
    m1 = p1.size
    m2 = p2.size
    # full-step coefficients
    E1 = np.empty(m1, np.complex128)
    A1 = np.empty(m1, np.complex128)
    C1 = np.empty(m1, np.complex128)
    Q1 = np.empty(m1, np.complex128)
    E2 = np.empty(m2, np.complex128)
    A2 = np.empty(m2, np.complex128)
    C2 = np.empty(m2, np.complex128)
    Q2 = np.empty(m2, np.complex128)
    hold_coefficients(p1, h, E1, A1, C1, Q1)
    hold_coefficients(p2, h, E2, A2, C2, Q2)
    # scratch for sub-steps
    e1 = np.empty(m1, np.complex128)
    a1 = np.empty(m1, np.complex128)
    c1 = np.empty(m1, np.complex128)
    q1 = np.empty(m1, np.complex128)
    e2 = np.empty(m2, np.complex128)
    a2 = np.empty(m2, np.complex128)
    c2 = np.empty(m2, np.complex128)
    q2 = np.empty(m2, np.complex128)
    zs1 = np.empty(m1, np.complex128)
    zs2 = np.empty(m2, np.complex128)
    zt1 = np.empty(m1, np.complex128)
    zt2 = np.empty(m2, np.complex128)
    # coefficients of the end-of-step force f in y (Rb), y' (Kv) and int y (Qb)
    h2 = h * h
    Rb1, Kv1, Qb1 = _ramp_response(inv1, D1, h, w1, p1, C1, Q1)
    Rb2, Kv2, Qb2 = _ramp_response(inv2, D2, h, w2, p2, C2, Q2)
    K = Rb1 + Rb2
    Kv = Kv1 + Kv2
    wA1 = w1 * A1
    wA2 = w2 * A2
    RwC1 = 0.0
    RwQ1 = 0.0
    for j in range(m1):
        RwC1 += (w1[j] * C1[j]).real
        RwQ1 += (w1[j] * Q1[j]).real
    RwC2 = 0.0
    RwQ2 = 0.0
    for j in range(m2):
        RwC2 += (w2[j] * C2[j]).real
        RwQ2 += (w2[j] * Q2[j]).real
    pe1 = 0.0      # pending ramp of each body's states: true z = z + C pe
    pe2 = 0.0

    z1 = z1_0.copy()
    z2 = z2_0.copy()
    zf1 = np.empty(m1, np.complex128)
    zf2 = np.empty(m2, np.complex128)
    d1 = d1_0
    v1 = v1_0
    d2 = d2_0
    v2 = v2_0
    force = np.zeros(n_steps + 1)
    y1 = np.empty(n_steps + 1)
    y2 = np.empty(n_steps + 1)
    impulse = np.zeros(n_steps)
    events = np.empty((n_steps + 2, 3))
    n_ev = 0
    work1 = 0.0
    work2 = 0.0
    acc = 0.0
    for j in range(m1):
        acc += (w1[j] * z1[j]).real
    y1[0] = acc + d1 + D1 * load1[0]
    acc = 0.0
    for j in range(m2):
        acc += (w2[j] * z2[j]).real
    y2[0] = acc + d2 + D2 * load2[0]
    f_n = 0.0
    damped = code == SPRING and c > 0.0
    in_contact = 0             # whole steps of the current contact (dashpot_floor)

    for step in range(n_steps):
        L1a = load1[step]
        L1b = load1[step + 1]
        L2a = load2[step]
        L2b = load2[step + 1]
        u10 = L1a - f_n
        u20 = L2a + f_n
        # the end-of-step state with zero force at the end (force f_n -> 0, loads linear)
        sg1 = (L1b - u10) / h
        sg2 = (L2b - u20) / h
        need_int = f_n > 0.0 or has_load
        yv1 = 0.0
        yr1, ya1 = _step_pass(z1, pe1, zf1, E1, A1, C1, w1, wA1, u10, sg1, need_int)
        yr2, ya2 = _step_pass(z2, pe2, zf2, E2, A2, C2, w2, wA2, u20, sg2, need_int)
        d1f = d1 + v1 * h + inv1 * (0.5 * u10 * h2 + sg1 * h2 * h / 6.0)
        v1f = v1 + inv1 * (u10 * h + 0.5 * sg1 * h2)
        d2f = d2 + v2 * h + inv2 * (0.5 * u20 * h2 + sg2 * h2 * h / 6.0)
        v2f = v2 + inv2 * (u20 * h + 0.5 * sg2 * h2)
        y1f = yr1 + d1f + D1 * L1b
        y2f = yr2 + d2f + D2 * L2b
        G = y2f - y1f + gap0
        Gv = 0.0
        floor = 0.0
        if damped:
            yv1 = velocity(zf1, v1f, p1, w1, D1, L1b, sg1)
            yv2 = velocity(zf2, v2f, p2, w2, D2, L2b, sg2)
            Gv = yv2 - yv1
            if f_n > 0.0:
                in_contact += 1
                floor = dashpot_floor(c, yv1, yv2, in_contact)
        f, q = law_force(code, k, c, n, G, K, Gv, Kv, floor)

        if (f_n > 0.0 and f == 0.0) or (f_n == 0.0 and f > 0.0):
            _settle(z1, pe1, C1)
            _settle(z2, pe2, C2)
            pe1 = 0.0
            pe2 = 0.0
        if f_n > 0.0 and f == 0.0:
            # ---- contact ends inside the step: the force falls linearly f_n -> 0 on [0, s]
            if code == HERTZ:
                g_n = y2[step] - y1[step] + gap0
                s = h * (-g_n) / (G - g_n) if (g_n < 0.0 and G > g_n) else 0.0
            else:
                s = h * f_n / (f_n - q) if f_n - q > 0.0 else h
            s = min(max(s, 0.0), h)
            r = h - s
            sl = (L1b - L1a) / h
            sl2 = (L2b - L2a) / h
            rate = f_n / s if s > 0.0 else 0.0
            y1_0 = y1[step]
            y2_0 = y2[step]
            dd1, vv1, ya1, yi1 = advance(z1, d1, v1, p1, w1, inv1, D1, s, u10, sl + rate,
                                         e1, a1, c1, q1, zs1)
            dd2, vv2, ya2, yi2 = advance(z2, d2, v2, p2, w2, inv2, D2, s, u20, sl2 - rate,
                                         e2, a2, c2, q2, zs2)
            work1 += (L1a + sl * s) * ya1 - u10 * y1_0 - (sl + rate) * yi1
            work2 += (L2a + sl2 * s) * ya2 - u20 * y2_0 - (sl2 - rate) * yi2
            u1s = L1a + sl * s
            u2s = L2a + sl2 * s
            d1, v1, yb1, yi1 = advance(zs1, dd1, vv1, p1, w1, inv1, D1, r, u1s, sl,
                                       e1, a1, c1, q1, z1)
            d2, v2, yb2, yi2 = advance(zs2, dd2, vv2, p2, w2, inv2, D2, r, u2s, sl2,
                                       e2, a2, c2, q2, z2)
            if has_load:
                work1 += L1b * yb1 - u1s * ya1 - sl * yi1
                work2 += L2b * yb2 - u2s * ya2 - sl2 * yi2
            y1[step + 1] = yb1
            y2[step + 1] = yb2
            impulse[step] = 0.5 * f_n * s
            events[n_ev, 0] = step * h + s
            events[n_ev, 1] = -1.0
            events[n_ev, 2] = step
            n_ev += 1
            f_n = 0.0
            force[step + 1] = 0.0
            continue

        if f_n == 0.0 and f > 0.0:
            # ---- contact starts inside the step: root of the free gap, then ramp 0 -> f
            g_n = y2[step] - y1[step] + gap0
            sl = (L1b - L1a) / h
            sl2 = (L2b - L2a) / h
            s = 0.0
            if g_n > 0.0:
                # safeguarded Newton on the exact free gap, from the secant guess
                lo = 0.0
                hi = h
                s = h * g_n / (g_n - G)
                for _ in range(50):
                    gs, gr = _free_gap(s, z1, d1, v1, p1, w1, inv1, D1, z2, d2, v2, p2, w2,
                                       inv2, D2, gap0, L1a, sl, L2a, sl2,
                                       e1, a1, c1, q1, e2, a2, c2, q2, zs1, zs2)
                    if gs > 0.0:
                        lo = s
                    elif gs < 0.0:
                        hi = s
                    else:
                        break
                    s_new = s - gs / gr if gr != 0.0 else 0.5 * (lo + hi)
                    if not lo < s_new < hi:
                        s_new = 0.5 * (lo + hi)
                    done = abs(s_new - s) <= 1e-13 * h or hi - lo <= 1e-13 * h
                    s = s_new
                    if done:
                        break
            r = h - s
            # free motion over [0, s]
            dd1, vv1, ya1, yi1 = advance(z1, d1, v1, p1, w1, inv1, D1, s, L1a, sl,
                                         e1, a1, c1, q1, zs1)
            dd2, vv2, ya2, yi2 = advance(z2, d2, v2, p2, w2, inv2, D2, s, L2a, sl2,
                                         e2, a2, c2, q2, zs2)
            if has_load:
                work1 += (L1a + sl * s) * ya1 - L1a * y1[step] - sl * yi1
                work2 += (L2a + sl2 * s) * ya2 - L2a * y2[step] - sl2 * yi2
            u1s = L1a + sl * s
            u2s = L2a + sl2 * s
            # the rest [s, h], free; the contact force rising 0 -> f over it adds
            # -/+ (C(r)/r) f to the states: end gap Gr + Kr f
            dz1, vz1, yz1, yiz1 = advance(zs1, dd1, vv1, p1, w1, inv1, D1, r, u1s, sl,
                                          e1, a1, c1, q1, zt1)
            dz2, vz2, yz2, yiz2 = advance(zs2, dd2, vv2, p2, w2, inv2, D2, r, u2s, sl2,
                                          e2, a2, c2, q2, zt2)
            # e*, a*, c*, q* now hold the coefficients of the sub-step r
            Rr1 = D1
            Rr2 = D2
            Vr1 = D1 / r if r > 0.0 else 0.0
            Vr2 = D2 / r if r > 0.0 else 0.0
            Ir1 = D1 * r / 2.0
            Ir2 = D2 * r / 2.0
            if r > 0.0:
                Rr1 += inv1 * r * r / 6.0
                Rr2 += inv2 * r * r / 6.0
                Vr1 += inv1 * r / 2.0
                Vr2 += inv2 * r / 2.0
                Ir1 += inv1 * r * r * r / 24.0
                Ir2 += inv2 * r * r * r / 24.0
                for j in range(m1):
                    Rr1 += (w1[j] * c1[j]).real / r
                    Vr1 += (w1[j] * (p1[j] * c1[j] / r + 1.0)).real
                    Ir1 += (w1[j] * q1[j]).real / r
                for j in range(m2):
                    Rr2 += (w2[j] * c2[j]).real / r
                    Vr2 += (w2[j] * (p2[j] * c2[j] / r + 1.0)).real
                    Ir2 += (w2[j] * q2[j]).real / r
            Gr = yz2 - yz1 + gap0
            Gvr = 0.0
            if damped:
                Gvr = (velocity(zt2, vz2, p2, w2, D2, L2b, sl2)
                       - velocity(zt1, vz1, p1, w1, D1, L1b, sl))
            f, q = law_force(code, k, c, n, Gr, Rr1 + Rr2, Gvr, Vr1 + Vr2, 0.0)
            in_contact = 0
            if not (f > 0.0 and r > 0.0):
                f = 0.0
            rate = f / r if r > 0.0 else 0.0
            for j in range(m1):
                z1[j] = zt1[j] - c1[j] * rate
            for j in range(m2):
                z2[j] = zt2[j] + c2[j] * rate
            d1 = dz1 - inv1 * r * r * f / 6.0
            v1 = vz1 - inv1 * r * f / 2.0
            d2 = dz2 + inv2 * r * r * f / 6.0
            v2 = vz2 + inv2 * r * f / 2.0
            yb1 = yz1 - Rr1 * f
            yb2 = yz2 + Rr2 * f
            if f > 0.0 or has_load:
                work1 += (L1b - f) * yb1 - u1s * ya1 - (sl - rate) * (yiz1 - Ir1 * f)
                work2 += (L2b + f) * yb2 - u2s * ya2 - (sl2 + rate) * (yiz2 + Ir2 * f)
            if f > 0.0:
                impulse[step] = 0.5 * f * r
                events[n_ev, 0] = step * h + s
                events[n_ev, 1] = 1.0
                events[n_ev, 2] = step
                n_ev += 1
            f_n = f
            y1[step + 1] = yb1
            y2[step + 1] = yb2
            force[step + 1] = f_n
            continue

        # ---- a whole step with the force linear from f_n to f
        if need_int:
            yi1 = (ya1 + u10 * RwC1 + sg1 * RwQ1
                   + d1 * h + 0.5 * v1 * h2 + inv1 * (u10 * h2 * h / 6.0 + sg1 * h2 * h2 / 24.0)
                   + D1 * (u10 * h + 0.5 * sg1 * h2)) - Qb1 * f
            yi2 = (ya2 + u20 * RwC2 + sg2 * RwQ2
                   + d2 * h + 0.5 * v2 * h2 + inv2 * (u20 * h2 * h / 6.0 + sg2 * h2 * h2 / 24.0)
                   + D2 * (u20 * h + 0.5 * sg2 * h2)) + Qb2 * f
            yb1 = y1f - Rb1 * f
            yb2 = y2f + Rb2 * f
            work1 += (L1b - f) * yb1 - u10 * y1[step] - (sg1 - f / h) * yi1
            work2 += (L2b + f) * yb2 - u20 * y2[step] - (sg2 + f / h) * yi2
        z1, zf1 = zf1, z1
        z2, zf2 = zf2, z2
        if f > 0.0:
            pe1 = -f / h
            pe2 = f / h
            d1 = d1f - inv1 * h2 * f / 6.0
            v1 = v1f - inv1 * h * f / 2.0
            d2 = d2f + inv2 * h2 * f / 6.0
            v2 = v2f + inv2 * h * f / 2.0
            y1[step + 1] = y1f - Rb1 * f
            y2[step + 1] = y2f + Rb2 * f
        else:
            pe1 = 0.0
            pe2 = 0.0
            d1, v1, d2, v2 = d1f, v1f, d2f, v2f
            y1[step + 1] = y1f
            y2[step + 1] = y2f
        impulse[step] = 0.5 * (f_n + f) * h
        force[step + 1] = f
        f_n = f

    _settle(z1, pe1, C1)
    _settle(z2, pe2, C2)
    return (force, y1, y2, events[:n_ev].copy(), impulse, work1, work2,
            z1, d1, v1, z2, d2, v2)
