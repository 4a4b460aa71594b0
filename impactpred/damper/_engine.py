"""The impact damper's phases for the exact engine (:mod:`impactpred.engine`).

State (real, shape (n,), ``n = n_p + 3``): the primary's block-diagonal modal states
(``ModalModel.to_statespace`` layout, ``n_p`` of them), the damper mass's displacement
``y_d`` (m) and velocity ``v_d`` (m/s), and a constant 1 (carries the clearance). The
excitation is the harmonic pair ``xh = [cos(Omega t + phi), sin(Omega t + phi)]``,
appended as two more states when the phase matrices are built and then removed again
by the particular solution (:class:`impactpred.engine.phase.PhaseKind`).

``lam`` is the contact force on the primary along ``+y`` (N): ``lam = s f`` with
``f >= 0`` the compressive force at the stop on side ``s`` (+1: the damper mass hits
the upper stop, ``y_d - y_p = c``; -1: the lower one). The gap at side ``s`` is
``g_s = c - s (y_d - y_p)``.

Every kind of phase (free flight; stuck contact, one per damper, shared by both stops;
linear-spring contact, one per stop) is decomposed once per damper; a phase then costs
two matrix-vector products to start and a vectorised evaluation to search.
"""

from __future__ import annotations

import math

import numpy as np

from modalid.statespace import pole_residue_to_statespace

from ..contact import InstantaneousImpact, LinearSpring, Rigid
from ..engine.contact_loop import relative_degree
from ..engine.cycle_state import EngineState
from ..engine.phase import PhaseKind

__all__ = ["Engine", "EngineState"]


class Engine:
    """Matrices and phase kinds of one damper, built once (see the module docstring).

    ``rank_one=True`` (default) splits the stuck phases (``Rigid``,
    ``InstantaneousImpact``) as the free flight plus the rank-one force feedback
    (:mod:`impactpred.engine.rank_one`, as ``solve_impact``'s exact method does; 1.8 ms
    instead of 12 ms on a 20-mode primary, as accurate or more against ``expm``);
    ``False``: the general eigendecomposition. The two round differently, and chattering
    runs amplify rounding into different (equally valid) contact histories: compare them
    by statistics, not sample by sample (one 100-cycle run's impacts per cycle on the
    20-mode beam ranges over 14.9-16.7 under 1-ulp changes of the force; means over six
    such changes: ``tests/test_impactpred_damper_kernels.py``). Spring-dashpot phases
    always take the general route: split by rank one, a dashpot's phase lost two orders
    of accuracy in ``tests/test_impactpred_damper.py``'s grazing check (5e-8 against
    2e-10 of the motion).
    """

    def __init__(self, model, *, damper_mass, clearance, contact, excitation, base_spring,
                 rank_one=True, outputs=None):
        a_p, b_p, c_p, d_p = pole_residue_to_statespace(
            model.poles, model.residues, model.real_poles, model.real_residues, 0.0,
            model.flexibility)
        n_p = a_p.shape[0]
        # output points: the multi-output model's rows C_j, d_j on the same modal states
        self.point_c, self.point_d = np.zeros((0, n_p)), np.zeros(0)
        if outputs is not None:
            a_o, b_o, c_o, d_o = outputs.statespace_matrices()
            if a_o.shape != a_p.shape or not (np.allclose(a_o, a_p) and np.allclose(b_o, b_p)):
                raise ValueError("the output points' model does not share the primary's "
                                 "states (its poles differ)")
            self.point_c, self.point_d = c_o, np.asarray(d_o, dtype=float)
        self.n_points = self.point_d.size
        n = n_p + 3
        iy, iv, i1 = n_p, n_p + 1, n_p + 2
        self.n_p, self.n, self.iy, self.iv, self.i1 = n_p, n, iy, iv, i1
        self.model, self.m_d, self.c, self.contact = model, damper_mass, clearance, contact
        self.rank_one = bool(rank_one)
        om = excitation.omega
        self.omega, self.phi, self.period = om, excitation.phase, 2 * math.pi / om
        h = np.array([1.0, -1.0j]) * complex(math.cos(excitation.phase),
                                             math.sin(excitation.phase))
        amp = excitation.amplitude
        if base_spring is None:     # force: F = F0 cos
            fvec, exc_row = np.array([amp, 0.0]), np.array([amp, 0.0])
            bv_row = np.zeros(2)
            self.base_damping = 0.0
        else:                       # base: F = k y_b + c y_b' on the mass
            k_b, c_b = base_spring
            fvec, exc_row = amp * np.array([k_b, -c_b * om]), np.array([amp, 0.0])
            bv_row = amp * np.array([0.0, -om])      # y_b'
            self.base_damping = c_b
        self.base_velocity_amplitude = amp * om if base_spring is not None else 0.0
        N = n + 2
        A = np.zeros((N, N))
        A[:n_p, :n_p] = a_p
        A[:n_p, n:] = np.outer(b_p, fvec)
        A[iy, iv] = 1.0
        A[n, n + 1], A[n + 1, n] = -om, om
        Bl = np.zeros(N)
        Bl[:n_p] = b_p
        Bl[iv] = -1.0 / damper_mass
        e1 = np.zeros(N)
        e1[i1] = 1.0
        yp0 = np.zeros(N)
        yp0[:n_p] = c_p
        yp0[n:] = d_p * fvec
        ey = np.zeros(N)
        ey[iy] = 1.0
        r0 = ey - yp0                   # y_d - y_p without the contact force's D-part
        self.A, self.Bl, self.e1, self.yp0, self.r0, self.d_p = A, Bl, e1, yp0, r0, d_p
        self.h = h
        self.rows_extra = (exc_row, fvec, bv_row)
        # relative degree of the gap w.r.t. the contact force
        c1 = -float(r0 @ Bl)
        c2 = -float(r0 @ A @ Bl)
        rate = max(float(np.max(np.abs(np.linalg.eigvals(a_p)))) if n_p else 0.0, om)
        self.rho = relative_degree(d_p, c1, c2, rate)
        self.c_coefs = (d_p, c1, c2)
        #: velocity jump of y_d - y_p per unit impulse: 1/m_d + 1/M_eff
        self.inv_mu = c2
        self.free = self._kind(A, np.zeros(N), [clearance * e1 - r0, clearance * e1 + r0],
                               "free-flight")
        self._stuck, self._spring, self._pen = {}, {}, {}
        self.stick_rows = {}
        if isinstance(contact, (Rigid, InstantaneousImpact)):
            for s in (1, -1):
                self.stuck(s)
        elif isinstance(contact, LinearSpring):
            if contact.damping > 0 and d_p > 0:
                raise ValueError("a LinearSpring with damping on a primary with a flexibility "
                                 f"term ({d_p!r} m/N) is not supported: use damping=0, or a "
                                 "model without residual flexibility")
            for s in (1, -1):
                self.spring(s)

    # ---------------------------------------------------------------- phase kinds
    def _kind(self, M, lam_row, event_rows, name, *, contact=False):
        """A phase kind; ``contact``: ``M`` is the free flight's plus ``outer(Bl, lam_row)``
        (the contact force fed back), split by the rank-one route through the free
        flight's form (else by the general route)."""
        n = self.n
        yp = self.yp0 + self.d_p * lam_row
        exc_row, fvec, bv_row = self.rows_extra

        def harm(v):
            row = np.zeros(n + 2)
            row[n:] = v
            return row

        ey, ev = np.zeros(n + 2), np.zeros(n + 2)
        ey[self.iy], ev[self.iv] = 1.0, 1.0
        points = self.point_rows(lam_row)      # displacements, velocities, accelerations
        out = np.vstack([yp, yp @ M, ey, ev, lam_row, harm(exc_row), harm(fvec), harm(bv_row),
                         points, points @ M, points @ M @ M])
        kind = PhaseKind(M, self.h, self.omega, np.vstack(event_rows), out, name=name,
                         update_of=(self.free, self.Bl, lam_row) if contact else None)
        kind.M_lam = lam_row
        return kind

    def stuck(self, s):
        """Stuck phase (damper mass moving with the primary) at side ``s``."""
        key = s if self.rho == 0 else 1
        if key not in self._stuck:
            d_p, c1, c2 = self.c_coefs
            A, r0 = self.A, self.r0
            if self.rho == 2:
                lam = r0 @ A @ A / c2
            elif self.rho == 1:
                lam = r0 @ A / c1
            else:
                lam = (r0 - s * self.c * self.e1) / d_p
            M = self.A + np.outer(self.Bl, lam)
            self._stuck[key] = self._kind(M, lam, [lam, -lam], "stuck-contact",
                                          contact=self.rank_one)
        return self._stuck[key]

    def spring(self, s):
        """Linear spring(-dashpot) contact phase at side ``s``: ``f = k pen + c pen'``."""
        if s not in self._spring:
            k, cd = self.contact.stiffness, self.contact.damping
            pen = s * self.r0 - self.c * self.e1
            d_p = self.d_p
            if cd > 0:     # d_p == 0: pen' = pen A X + (pen Bl) lam, lam = s f
                f = (k * pen + cd * pen @ self.A) / (1.0 - cd * s * float(pen @ self.Bl))
            else:
                f = k * pen / (1.0 + k * d_p)
            lam = s * f
            M = self.A + np.outer(self.Bl, lam)
            self._spring[s] = self._kind(M, lam, [f], f"spring-contact({s:+d})")
            self._spring[s].event_row = f
            q = k * pen + cd * pen @ self.A
            self._pen[s] = self._kind(self.A, np.zeros(self.n + 2), [-q, pen],
                                      f"penetrating-flight({s:+d})")
        return self._spring[s]

    # ---------------------------------------------------------------- helpers
    def resonance_error(self, *, stuck_sides=None, contact_sides=None) -> float:
        """The largest relative rounding error near a resonance over the phase kinds built
        (:attr:`PhaseKind.resonance_error`); of the stuck kinds, those of ``stuck_sides``
        only (the sides, +1 or -1, a run stuck on), of the spring-contact and penetrating
        ones those of ``contact_sides`` (the sides it touched); None: every one built (the
        loops build some whether a run enters them or not)."""
        keys = (None if stuck_sides is None
                else {s if self.rho == 0 else 1 for s in stuck_sides})
        stuck = [k for key, k in self._stuck.items() if keys is None or key in keys]
        touched = [k for phases in (self._spring, self._pen) for side, k in phases.items()
                   if contact_sides is None or side in contact_sides]
        kinds = [self.free, *stuck, *touched]
        return max(kind.resonance_error for kind in kinds)

    def point_rows(self, lam_row):
        """The output points' displacement rows on the augmented state (shape
        ``(n_points, n + 2)``): ``C_j x_p + d_j (F_eq + lam)``, ``lam = lam_row @ xa`` the
        contact force of the phase (zeros in free flight)."""
        _, fvec, _ = self.rows_extra
        rows = np.zeros((self.n_points, self.n + 2))
        rows[:, :self.n_p] = self.point_c
        rows[:, self.n:] = np.outer(self.point_d, fvec)
        return rows + np.outer(self.point_d, lam_row)

    def augmented(self, x, t):
        ph = self.omega * t + self.phi
        return np.concatenate([x, [math.cos(ph), math.sin(ph)]])

    def gap_rate(self, xa, s):
        """``g_s'`` in free flight (m/s)."""
        return -s * float(self.r0 @ (self.A @ xa))
