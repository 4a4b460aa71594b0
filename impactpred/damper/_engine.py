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

The engine runs on a dimensionless form (:mod:`impactpred.solvers._units`, as the exact
solver's): time in units of a reference ``u.t``, the states ``x = unit * xi``
(:attr:`Engine.state_unit`: a modal or real-pole state's unit the impulse ``u.j``, since
``z' = p z + F``; ``y_d``'s the length ``u.l``, ``v_d``'s ``u.l / u.t``), the force in
``u.f``, and so every matrix, row, mass, clearance, contact law and excitation the
engine holds. Its tolerances are relative to the norms of the phase matrices and rows,
which on the SI states mixed units: masses x 1e-16 or times x 1e11 made a stuck phase's
modes "resonant" with the forcing, a spring contact's matrix "defective", and times x
1e-11 changed the contact history (94 impacts for 120), with no warning. The front end
(:class:`impactpred.damper.ImpactDamper`) converts a run's start to this form
(:meth:`Engine.to_engine`) and its raw output back to SI (:meth:`Engine.to_si`).
"""

from __future__ import annotations

import math

import numpy as np

from modalid.statespace import pole_residue_to_statespace

from ..contact import Hertz, InstantaneousImpact, LinearSpring, Rigid
from ..engine.contact_loop import relative_degree
from ..engine.cycle_state import EngineState
from ..engine.phase import PhaseKind
from ..solvers._units import Units, reference_units

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

    ``units``: the :class:`impactpred.solvers._units.Units` of the dimensionless form
    (module docstring); None (default): the damper's reference units, from its rates,
    masses and lengths (powers of two, so that the changes of unit are exact); a
    force, impulse, energy or speed scale double precision cannot hold is refused
    (``ValueError``, :meth:`~impactpred.solvers._units.Units.check`). ``Units(1, 1, 1)``:
    the SI states themselves. :attr:`omega_si`, :attr:`period_si`, :attr:`base_damping`
    and :attr:`base_velocity_amplitude` are in SI; every other figure is on the form.
    """

    def __init__(self, model, *, damper_mass, clearance, contact, excitation, base_spring,
                 rank_one=True, outputs=None, units=None):
        a_p, b_p, c_p, d_p = pole_residue_to_statespace(
            model.poles, model.residues, model.real_poles, model.real_residues, 0.0,
            model.flexibility)
        n_p = a_p.shape[0]
        # output points: the multi-output model's rows C_j, d_j on the same modal states
        c_o, d_o = np.zeros((0, n_p)), np.zeros(0)
        if outputs is not None:
            a_o, b_o, c_o, d_o = outputs.statespace_matrices()
            if a_o.shape != a_p.shape or not (np.allclose(a_o, a_p) and np.allclose(b_o, b_p)):
                raise ValueError("the output points' model does not share the primary's "
                                 "states (its poles differ)")
        # SI figures the result needs (rad/s, s, N s/m, m/s)
        om_si = excitation.omega
        self.omega_si, self.period_si = om_si, 2 * math.pi / om_si
        self.base_damping = 0.0 if base_spring is None else float(base_spring[1])
        self.base_velocity_amplitude = (excitation.amplitude * om_si if base_spring is not None
                                        else 0.0)
        u = units if units is not None else _reference_units(
            a_p, b_p, c_p, d_p, damper_mass, clearance, contact, excitation, base_spring)
        u.check()
        self.units = u
        # the dimensionless form (module docstring): z = u.j zeta, F = u.f phi, t = u.t tau
        # and y = u.l eta make z' = a z + b F, y = c z + d F into zeta' = (u.t a) zeta + b phi,
        # eta = (u.j / u.l) c zeta + (u.f / u.l) d phi
        a_p, c_p, d_p = u.t * a_p, c_p * (u.j / u.l), d_p * (u.f / u.l)
        self.point_c, self.point_d = c_o * (u.j / u.l), np.asarray(d_o, float) * (u.f / u.l)
        self.n_points = self.point_d.size
        damper_mass, clearance = damper_mass / u.m, clearance / u.l
        contact = _scaled_contact(contact, u)
        n = n_p + 3
        iy, iv, i1 = n_p, n_p + 1, n_p + 2
        self.n_p, self.n, self.iy, self.iv, self.i1 = n_p, n, iy, iv, i1
        #: each state's SI unit (shape (n,)): x (SI) = state_unit * xi (the engine's)
        self.state_unit = np.concatenate([np.full(n_p, u.j), [u.l, u.l / u.t, 1.0]])
        self.model, self.m_d, self.c, self.contact = model, damper_mass, clearance, contact
        self.rank_one = bool(rank_one)
        om = om_si * u.t
        self.omega, self.phi, self.period = om, excitation.phase, 2 * math.pi / om
        h = np.array([1.0, -1.0j]) * complex(math.cos(excitation.phase),
                                             math.sin(excitation.phase))
        if base_spring is None:     # force: F = F0 cos
            amp = excitation.amplitude / u.f
            fvec, exc_row = np.array([amp, 0.0]), np.array([amp, 0.0])
            bv_row = np.zeros(2)
            #: the excitation row's unit (a force, or a base displacement)
            self.excitation_unit = u.f
        else:                       # base: F = k y_b + c y_b' on the mass
            amp = excitation.amplitude / u.l
            k_b, c_b = base_spring[0] * u.l / u.f, base_spring[1] * u.l / u.j
            fvec, exc_row = amp * np.array([k_b, -c_b * om]), np.array([amp, 0.0])
            bv_row = amp * np.array([0.0, -om])      # y_b'
            self.excitation_unit = u.l
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
                         update_of=(self.free, self.Bl, lam_row) if contact else None,
                         time_unit=self.units.t)
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

    # ---------------------------------------------------------------- units
    def to_engine(self, start):
        """The run's start (an :class:`EngineState` in SI) on the engine's dimensionless
        form."""
        u = self.units
        return EngineState(start.time / u.t, np.asarray(start.state, float) / self.state_unit,
                           start.mode, start.side, _impact_record(start.open_impact, u, -1))

    def to_si(self, raw):
        """The engine's raw run ``raw`` (:func:`impactpred.engine.cycle_run.run`) back in
        SI, in place: times (s), the sampled rows (m, m/s, N; the excitation in N or m;
        the output points' m, m/s, m/s^2), the two input-work integrals (J and m^2/s),
        the impacts (s, N s, m/s) and the final state; returns ``raw``."""
        u = self.units
        v = u.l / u.t
        k = self.n_points
        rows = np.concatenate([[u.l, v, u.l, v, u.f, self.excitation_unit],
                               np.repeat([u.l, v, v / u.t], k)])
        raw["t"] = raw["t"] * u.t
        raw["values"] = raw["values"] * rows[:, None]
        raw["work"] = raw["work"] * np.array([[u.e], [u.l * v]])
        imp = raw["impacts"]
        if isinstance(imp, dict):               # the compiled loop's columns
            raw["impacts"] = _impact_record(imp, u, 1)
        else:
            raw["impacts"] = [_impact_record(r, u, 1) for r in imp]
        fs = raw["final"]
        raw["final"] = EngineState(fs.time * u.t, fs.state * self.state_unit, fs.mode,
                                   fs.side, _impact_record(fs.open_impact, u, 1))
        raw["t_start"], raw["t_end"] = raw["t_start"] * u.t, raw["t_end"] * u.t
        return raw


def _impact_record(rec, u, power):
    """An impact's record (a dict of its time, impulse, duration, relative velocity ...)
    with those in SI (``power=1``) or on the dimensionless form (``-1``); None as it is."""
    if rec is None:
        return None
    units = {"time": u.t, "duration": u.t, "impulse": u.j, "relative_velocity": u.l / u.t}
    return {key: (value * units[key] ** power if key in units else value)
            for key, value in rec.items()}


def _scaled_contact(contact, u):
    """The contact law on the dimensionless form (force in ``u.f``, length ``u.l``)."""
    if isinstance(contact, LinearSpring):
        return LinearSpring(contact.stiffness * u.l / u.f, contact.damping * u.l / u.j)
    if isinstance(contact, Hertz):
        return Hertz(contact.stiffness * u.l ** contact.exponent / u.f, contact.exponent)
    return contact                          # Rigid and InstantaneousImpact: no unit


def _reference_units(a_p, b_p, c_p, d_p, damper_mass, clearance, contact, excitation,
                     base_spring) -> Units:
    """The reference units of a damper's engine (:func:`impactpred.solvers._units.
    reference_units`), from its SI primary ``(a_p, b_p, c_p, d_p)``: the relative motion
    ``y_d - y_p`` per unit contact force is ``d_p + (c_p b_p) / s + (c_p a_p b_p +
    1/m_d) / s^2 + ...`` at high ``s``; the rates are the primary's and the forcing's (and
    a linear spring contact's); the lengths the clearance, a base excitation's amplitude
    and what the force moves."""
    c1 = float(c_p @ b_p) if c_p.size else 0.0
    c2 = (float(c_p @ a_p @ b_p) if c_p.size else 0.0) + 1.0 / damper_mass
    free_rate = float(np.max(np.abs(np.linalg.eigvals(a_p)))) if a_p.size else 0.0
    compliance = d_p + (1.0 / contact.stiffness if isinstance(contact, LinearSpring) else 0.0)
    om = excitation.omega
    if base_spring is None:
        displacement, force = clearance, excitation.amplitude
    else:
        k_b, c_b = base_spring
        displacement = clearance + excitation.amplitude
        force = excitation.amplitude * math.hypot(k_b, c_b * om)
    return reference_units((d_p, c1, c2), free_rate, compliance=compliance,
                           t_end=2 * math.pi / om, rates=[om], displacement=displacement,
                           force=force)
