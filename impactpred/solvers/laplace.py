"""Exact, event-driven solver for rational receptances (the paper's Laplace method).

Each body is a real state-space realisation of its pole-residue receptance
(``ModalModel.to_statespace``). With ``X`` the stacked states of both bodies and the
contact force ``f`` acting as ``-f`` on body 1 and ``+f`` on body 2:

    X' = A X + Bf f,       g = g0 + Cg X + Dg f   (gap),  Dg = D1 + D2.

* Free flight: ``f = 0``, ``X(t) = expm(A t) X0``: closed form.
* Rigid contact: ``g = 0`` held. The force is a linear feedback ``f = Kf X + k0`` found
  from the first derivative of ``g`` in which ``f`` appears (relative degree 0: a
  flexibility term; 1; or 2: mass-like ``H ~ 1/s^2``). The stuck system
  ``X' = (A + Bf Kf) X`` has as poles the zeros of ``H1 + H2`` (paper eq. 5): its force
  is the inverse Laplace transform of ``(Y10 - Y20)/(H1 + H2)``. Where ``H1 + H2 ~ 1/s^2``
  and the bodies approach, the force has a Dirac impulse ``P = -g'/(Cg A Bf)`` at the
  contact's start, returned as such.
* Linear-spring contact (no damping): ``f = -k g`` while ``g < 0``: again linear.

Events (separation where ``f`` crosses 0, contact where ``g`` crosses 0) are located on a
grid of exact propagators ``expm(M dt)`` and refined to rounding on the Taylor series of
the event function (entire in ``t``). No time-step error anywhere; the grid step only
sets the output sampling and the event search, which can miss an event whose sign change
lasts less than a grid step (the step resolves the fastest pole: ``pi/(8 |lambda|max)``).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy.optimize import brentq

from modalid._statespace import pole_residue_to_statespace

from ..contact import LinearSpring, Rigid
from ..result import BodyEnergy, ImpactResult

__all__ = ["solve_laplace", "CoupledSystem"]


class CoupledSystem:
    """The two bodies' stacked real state space and the bookkeeping of its states."""

    def __init__(self, bodies):
        blocks = []
        for body in bodies:
            m = body.modal_model()
            a, b, c, d = pole_residue_to_statespace(m.poles, m.residues, m.real_poles,
                                                    m.real_residues, m.inverse_mass,
                                                    m.flexibility)
            blocks.append((m, a, b, c, d))
        (m1, a1, b1, c1, d1), (m2, a2, b2, c2, d2) = blocks
        n1, n2 = a1.shape[0], a2.shape[0]
        self.n1, self.n = n1, n1 + n2
        self.models = (m1, m2)
        self.A = scipy.linalg.block_diag(a1, a2) if self.n else np.zeros((0, 0))
        self.Bf = np.concatenate([-b1, b2])
        self.C1 = np.concatenate([c1, np.zeros(n2)])
        self.C2 = np.concatenate([np.zeros(n1), c2])
        self.Cg = self.C2 - self.C1
        self.D = (d1, d2)
        self.Dg = d1 + d2
        self.X0 = np.concatenate([_initial_state(bodies[0], m1, n1),
                                  _initial_state(bodies[1], m2, n2)])

    def rigid_velocity(self, X, i):
        """Rigid-body velocity (m/s) of body ``i`` in state ``X`` (0 if grounded)."""
        m = self.models[i]
        if not m.inverse_mass:
            return 0.0
        end = self.n1 if i == 0 else self.n
        return float(X[end - 1])

    def energies(self, X, f):
        """(rigid, vibration) energy (J) of each body in state ``X`` with force ``f``."""
        out = []
        for i, m in enumerate(self.models):
            offset = 0 if i == 0 else self.n1
            z = X[offset:offset + 2 * m.n_modes:2] + 1j * X[offset + 1:offset + 2 * m.n_modes:2]
            modal_mass = -1.0 / (2.0 * m.poles.imag * m.residues.imag)
            vib = float(np.sum(np.abs(z) ** 2 / (2.0 * modal_mass))) + 0.5 * self.D[i] * f**2
            u = self.rigid_velocity(X, i)
            rigid = 0.5 * u**2 / m.inverse_mass if m.inverse_mass else 0.0
            out.append((rigid, vib))
        return out


def _initial_state(body, model, n):
    x = np.zeros(n)
    states = body.initial_modal_states()
    if states is not None:
        order = np.argsort(np.abs(model.poles), kind="stable")[:body.vibration.shape[0]]
        z0 = states[2]
        x[2 * order] = z0.real
        x[2 * order + 1] = z0.imag
    if model.inverse_mass:
        x[n - 2] = body.displacement
        x[n - 1] = body.velocity
    return x


def _relative_degree(sysm: CoupledSystem):
    """(rho, coefficient) of the first derivative of the gap in which ``f`` appears."""
    scale = max(1.0, float(np.max(np.abs(np.linalg.eigvals(sysm.A))))) if sysm.n else 1.0
    c0 = sysm.Dg
    c1 = float(sysm.Cg @ sysm.Bf) if sysm.n else 0.0
    c2 = float(sysm.Cg @ sysm.A @ sysm.Bf) if sysm.n else 0.0
    ref = abs(c2) + abs(c1) * scale + abs(c0) * scale**2
    if ref == 0.0:
        raise ValueError("H1 + H2 is identically zero: the bodies have no compliance")
    if abs(c0) * scale**2 > 1e-12 * ref:
        return 0, c0
    if abs(c1) * scale > 1e-12 * ref:
        return 1, c1
    return 2, c2


class _Phase:
    """A linear autonomous phase ``Xa' = M Xa`` with ``Xa = [X, 1, J]`` (J: impulse)."""

    def __init__(self, M, force_row, event_row):
        self.M = M
        self.force_row = force_row    # f = force_row @ Xa
        self.event_row = event_row    # event when event_row @ Xa changes sign downward
        self._cache = {}

    def propagator(self, tau):
        key = round(tau, 15)
        if key not in self._cache:
            if len(self._cache) > 8:
                self._cache.clear()
            self._cache[key] = scipy.linalg.expm(self.M * tau)
        return self._cache[key]

    def event_root(self, Xa, tau_max):
        """Root in ``(0, tau_max]`` of ``event_row @ expm(M t) Xa`` by its Taylor series."""
        coeffs = []
        w = Xa.copy()
        scale = 1.0
        for j in range(80):
            coeffs.append(float(self.event_row @ w) * scale)
            w = self.M @ w
            scale *= tau_max / (j + 1)
            if j > 3 and np.max(np.abs(coeffs[-3:])) <= 1e-18 * np.max(np.abs(coeffs)):
                break
        poly = np.polynomial.Polynomial(coeffs)  # in the variable u = t / tau_max
        a, b = 0.0, 1.0
        fa, fb = poly(a), poly(b)
        if fa * fb > 0:
            # the grid saw a sign change the series does not reproduce: take the sampled one
            return tau_max
        return brentq(poly, a, b, xtol=1e-16, rtol=4 * np.finfo(float).eps) * tau_max


def solve_laplace(bodies, gap0, contact, t_end, dt, *, notes=()):
    """Exact event-driven solve of two rational bodies; see the module docstring."""
    if any(b.load is not None for b in bodies):
        raise ValueError("the laplace solver takes no external load: use method='modal'")
    sysm = CoupledSystem(bodies)
    n = sysm.n
    A, Bf, Cg = sysm.A, sysm.Bf, sysm.Cg
    n_aug = n + 2  # [X, 1, J]
    one, jdx = n, n + 1

    def augment(M_x, force_row_x, force_const):
        M = np.zeros((n_aug, n_aug))
        M[:n, :n] = M_x
        force_row = np.zeros(n_aug)
        force_row[:n] = force_row_x
        force_row[one] = force_const
        return M, force_row

    # free flight
    M_free, zero_force = augment(A, np.zeros(n), 0.0)
    gap_row = np.zeros(n_aug)
    gap_row[:n] = Cg
    gap_row[one] = gap0
    free = _Phase(M_free, zero_force, gap_row)

    # contact
    if isinstance(contact, Rigid):
        rho, coef = _relative_degree(sysm)
        if rho == 0:
            kf, k0 = -Cg / coef, -gap0 / coef
        elif rho == 1:
            kf, k0 = -(Cg @ A) / coef, 0.0
        else:
            kf, k0 = -(Cg @ A @ A) / coef, 0.0
    elif isinstance(contact, LinearSpring) and contact.damping == 0.0:
        rho, coef = None, None
        k = contact.stiffness
        kf, k0 = -k * Cg / (1 + k * sysm.Dg), -k * gap0 / (1 + k * sysm.Dg)
    else:
        raise ValueError(f"the laplace solver takes Rigid() or an undamped LinearSpring, got "
                         f"{contact!r}: use method='modal' or 'convolution'")
    M_con = np.zeros((n_aug, n_aug))
    M_con[:n, :n] = A + np.outer(Bf, kf)
    M_con[:n, one] = Bf * k0
    M_con[jdx, :n] = kf
    M_con[jdx, one] = k0
    force_row = np.zeros(n_aug)
    force_row[:n], force_row[one] = kf, k0
    stuck = _Phase(M_con, force_row, force_row)

    lam = np.concatenate([np.linalg.eigvals(M_free[:n, :n]), np.linalg.eigvals(M_con[:n, :n])])
    lam_max = float(np.max(np.abs(lam))) if lam.size else 0.0
    step = np.pi / (8 * lam_max) if lam_max > 0 else t_end / 1000
    step = min(step, dt) if dt is not None else step
    step = min(step, t_end / 20)
    n_grid = int(math.ceil(t_end / step - 1e-9))
    step = t_end / n_grid

    Xa = np.concatenate([sysm.X0, [1.0, 0.0]])
    u_scale = max(abs(b.velocity) for b in bodies) + 1e-300
    y_scale = abs(gap0) + u_scale * t_end + float(np.max(np.abs(sysm.X0), initial=0.0))
    tol_g = 1e-12 * y_scale

    times, states, forces = [0.0], [Xa.copy()], []
    intervals, diracs = [], []
    first_impulse = None

    def gap_rate(X):
        return float(Cg @ (A @ X[:n])) if n else 0.0

    def start_contact(t, Xa):
        """Apply any Dirac impulse; return (Xa, holds) with holds False if f < 0 at once."""
        if rho == 2:
            v_rel = gap_rate(Xa)
            if v_rel < 0:
                p = -v_rel / coef
                Xa = Xa.copy()
                Xa[:n] += Bf * p
                Xa[jdx] += p
                diracs.append((t, p))
        f0 = float(force_row @ Xa)
        df0 = float(force_row @ (M_con @ Xa))
        # rounding in the located gap shows up in f0 (as -g/Dg where rho = 0)
        f_tol = 1e-9 * (abs(f0) + abs(df0) * step) + (tol_g / abs(coef) if rho == 0 else 0.0)
        holds = f0 > f_tol or (f0 > -f_tol and df0 > 0)
        return Xa, holds

    def run_phase(phase, t, Xa, contact_phase):
        """Propagate from (t, Xa) to the phase's first event or t_end.

        Contact phase: the event is the force turning negative. Free flight: the gap
        turning negative beyond rounding (``tol_g``); if it is not positive at the step's
        start, the contact starts there.
        """
        k = int(math.floor(t / step + 1e-9)) + 1
        t_prev, X_prev = t, Xa
        e_prev = float(phase.event_row @ Xa)
        while t_prev < t_end * (1 - 1e-15):
            t_next = min(k * step, t_end)
            tau = t_next - t_prev
            X_next = phase.propagator(tau) @ X_prev
            e_next = float(phase.event_row @ X_next)
            if (e_next < 0.0) if contact_phase else (e_next < -tol_g):
                root = 0.0 if e_prev <= 0.0 else phase.event_root(X_prev, tau)
                X_ev = phase.propagator(root) @ X_prev if root < tau else X_next
                return t_prev + root, X_ev, True
            times.append(t_next)
            states.append(X_next)
            forces.append(phase)
            t_prev, X_prev, e_prev = t_next, X_next, e_next
            k += 1
        return t_prev, X_prev, False

    t = 0.0
    # touching at t = 0 and approaching: the first contact starts at once
    in_contact = bool(n) and gap0 <= tol_g and gap_rate(Xa) < 0
    contact_start = 0.0
    initial_phase = free
    if in_contact:
        Xa, holds = start_contact(0.0, Xa)
        states[0] = Xa
        if holds:
            initial_phase = stuck
        else:
            intervals.append((0.0, 0.0))
            in_contact = False
    stalled = 0
    while t < t_end * (1 - 1e-15):
        phase = stuck if in_contact else free
        t_ev, X_ev, happened = run_phase(phase, t, Xa, in_contact)
        stalled = stalled + 1 if t_ev == t else 0
        if stalled > 50:
            raise RuntimeError(f"contact events repeat without time advancing at t = {t!r} s: "
                               "the contact state cannot be decided (grazing); use "
                               "method='modal'")
        t, Xa = t_ev, X_ev
        if not happened:
            break
        if in_contact:  # separation
            intervals.append((contact_start, t))
            times.append(t)
            states.append(Xa)
            forces.append(None)  # force 0 from here
            in_contact = False
        else:  # contact
            contact_start = t
            Xa, holds = start_contact(t, Xa)
            times.append(t)
            states.append(Xa)
            if holds:
                forces.append(stuck)
                in_contact = True
            else:
                forces.append(None)
                intervals.append((t, t))
        if first_impulse is None and intervals:
            first_impulse = float(Xa[jdx])
    if in_contact:
        intervals.append((contact_start, t_end))
    if first_impulse is None:
        first_impulse = float(Xa[jdx])

    T = np.array(times)
    X = np.array(states)
    # force at each sample: the phase that produced the sample (start sample: initial phase)
    in_stuck = np.array([ph is stuck for ph in [initial_phase] + forces])
    F = np.where(in_stuck, X @ force_row, 0.0)
    T, X, F = _insert_exact_peak(T, X, F, in_stuck, intervals, stuck)
    F = np.maximum(F, 0.0)
    D1, D2 = sysm.D
    y1 = X[:, :n] @ sysm.C1 - D1 * F
    y2 = X[:, :n] @ sysm.C2 + D2 * F
    gap = y2 - y1 + gap0
    X_end = X[-1]
    f_end = F[-1]
    u_before = (bodies[0].velocity, bodies[1].velocity)
    u_after = (sysm.rigid_velocity(X_end[:n], 0), sysm.rigid_velocity(X_end[:n], 1))
    before = sysm.energies(sysm.X0, 0.0)
    after = sysm.energies(X_end[:n], f_end)
    energy = tuple(BodyEnergy(b[0], b[1], a[0], a[1]) for b, a in zip(before, after))
    inv = (bodies[0].inverse_mass, bodies[1].inverse_mass)
    note = (f"exact (Laplace/state-space) solution; {n_grid} output/event-search steps of "
            f"{step:.4g} s",)
    return ImpactResult(t=T, force=F, y1=y1, y2=y2, gap=gap,
                        contact_intervals=tuple(intervals), dirac_impulses=tuple(diracs),
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=energy, method="laplace", dt=step,
                        first_contact_impulse=first_impulse,
                        total_impulse=float(X_end[jdx]), inverse_masses=inv,
                        notes=tuple(notes) + note)


def _insert_exact_peak(T, X, F, in_stuck, intervals, stuck):
    """Insert the exact maximum of the first contact's force (a root of ``f'``) as a sample."""
    if not intervals or intervals[0][1] <= intervals[0][0]:
        return T, X, F
    start, end = intervals[0]
    inside = np.flatnonzero(in_stuck & (T >= start) & (T <= end))
    if inside.size < 2:
        return T, X, F
    i = inside[np.argmax(F[inside])]
    rate = _Phase(stuck.M, stuck.force_row, stuck.force_row @ stuck.M)
    for lo in (i - 1, i):
        if lo < inside[0] or lo + 1 > inside[-1]:
            continue
        d_lo = float(rate.event_row @ X[lo])
        d_hi = float(rate.event_row @ X[lo + 1])
        if d_lo > 0 >= d_hi:
            tau = rate.event_root(X[lo], T[lo + 1] - T[lo])
            x_peak = scipy.linalg.expm(stuck.M * tau) @ X[lo]
            f_peak = float(stuck.force_row @ x_peak)
            k = lo + 1
            return (np.insert(T, k, T[lo] + tau), np.insert(X, k, x_peak, axis=0),
                    np.insert(F, k, f_peak))
    return T, X, F
