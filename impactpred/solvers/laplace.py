"""The exact solver's front end (the paper's Laplace method) over :mod:`impactpred.engine`.

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

This module builds those two phases (:class:`impactpred.engine.impact_run.Phase`: the
contact phase as the free flight plus the rank-one feedback ``Bf Kf``, split by
:mod:`impactpred.engine.rank_one`) and shapes the result; the engine
(:func:`impactpred.engine.impact_run.run_contact`) finds the events on the closed form
and applies the contact rules. No time-step error anywhere: the output step only sets
where the result is sampled.

The engine runs on a dimensionless form of the phases (:mod:`._units`): time in units of a
reference time (the inverse of the bodies' and the contact's fastest rate), the states
by a diagonal similarity (a modal state in units of a reference impulse, a rigid body's
displacement and velocity in a reference length and speed), each row in units of its own
(force, length, speed); the result is converted back to SI. The engine's tolerances on
the phase matrices (zero eigenvalues at ``sqrt(eps |M|)``, eigenvector conditioning) are
relative to their norm, which on the SI states mixed units: a mass scale of 1e15 or a
time scale of 1e-11 s gave wrong answers with no warning. In the dimensionless form the
solution is the same at every scale of mass, length and time; a scale whose SI results
double precision cannot hold is refused (:meth:`._units.Units.check`).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from modalid.statespace import pole_residue_to_statespace

from ..contact import LinearSpring, Rigid
from ..damper.excitation import HarmonicForce
from ..engine.contact_loop import relative_degree
from ..engine.impact_run import (ContactRules, Phase, grazing_error, insert_exact_peak,
                                 run_contact, search_step)
from ..result import BodyEnergy, ImpactResult
from ._outputs import LaplaceOutputs
from ._units import Units, reference_units

__all__ = ["solve_laplace", "CoupledSystem"]

#: a spring contact's fastest rate (rad/s) times t_end the closed form's times resolve: a
#: time scale under 1e-15 of t_end is a few units of rounding of t (a 1e300 N/m spring
#: hung the event search)
_RESOLVED_RATE = 1e15


class CoupledSystem:
    """The two bodies' stacked real state space and the bookkeeping of its states
    (``scale``: body 1's receptance multiplied by it, its mass and stiffness divided)."""

    def __init__(self, bodies, scale=1.0):
        blocks = []
        for body, factor in zip(bodies, (scale, 1.0)):
            m = body.modal_model()
            if factor != 1.0:       # body 1's receptance scaled: the sensitivity check
                m = m.replace(residues=factor * m.residues,
                              real_residues=factor * m.real_residues,
                              inverse_mass=factor * m.inverse_mass,
                              flexibility=factor * m.flexibility)
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
        x1 = _initial_state(bodies[0], m1, n1)
        x1[:2 * m1.n_modes] /= scale        # the same physical vibration (y = c z, c scaled)
        self.X0 = np.concatenate([x1, _initial_state(bodies[1], m2, n2)])

    def state_units(self, units):
        """The SI size of each state's unit in the dimensionless form (shape (n,)): a
        modal or real-pole state's ``units.j`` (N s: ``z' = p z + F``), a rigid body's
        displacement ``units.l`` and velocity ``units.l / units.t`` (:class:`._units.Units`)."""
        parts = []
        for m, size in zip(self.models, (self.n1, self.n - self.n1)):
            unit = np.full(size, units.j)
            if m.inverse_mass:
                unit[-2:] = (units.l, units.l / units.t)
            parts.append(unit)
        return np.concatenate(parts) if parts else np.zeros(0)

    def rigid_velocity(self, X, i):
        """Rigid-body velocity (m/s) of body ``i`` in state ``X`` (0 if grounded)."""
        m = self.models[i]
        if not m.inverse_mass:
            return 0.0
        end = self.n1 if i == 0 else self.n
        return float(X[end - 1])

    def energies(self, X, forces):
        """(rigid, vibration) energy (J) of each body in state ``X`` with ``forces`` (N)
        on them (the residual flexibility's strain energy ``d F^2 / 2`` included).

        A normal mode's (residue ``r`` imaginary) energy is ``m_k (qdot^2 + |p_k|^2 q^2)
        / 2`` with its displacement ``q = 2 Re(r z)`` and velocity ``qdot = 2 Re(r p z)``
        from its complex coordinate ``z`` (``z' = p z + F``), as
        :meth:`impactpred.Body.vibration_energy` counts it (``|z|^2 / (2 m_k)`` equals it
        only undamped: a damped one's differed by the cross term ``2 zeta omega m q
        qdot``). A complex mode (non-proportional damping) has no energy of its own at
        the contact point; it keeps ``|z|^2 / (2 m_k)``, which the energy audit's check of
        the energy held stays clear of (the other form overstated a passive 2-DOF body's
        energy by 40 %)."""
        out = []
        for i, m in enumerate(self.models):
            offset = 0 if i == 0 else self.n1
            z = X[offset:offset + 2 * m.n_modes:2] + 1j * X[offset + 1:offset + 2 * m.n_modes:2]
            r, p = m.residues, m.poles
            live = r.imag != 0.0                 # a zero residue: no energy in that mode
            modal_mass = -1.0 / (2.0 * p.imag[live] * r.imag[live])
            r, p, z = r[live], p[live], z[live]
            normal = np.abs(r.real) <= 1e-9 * np.abs(r)
            q = 2.0 * (r * z).real
            qdot = 2.0 * (r * p * z).real
            each = np.where(normal, 0.5 * modal_mass * (qdot**2 + np.abs(p) ** 2 * q**2),
                            np.abs(z) ** 2 / (2.0 * modal_mass))
            vib = float(np.sum(each)) + 0.5 * self.D[i] * forces[i]**2
            u = self.rigid_velocity(X, i)
            rigid = 0.5 * u**2 / m.inverse_mass if m.inverse_mass else 0.0
            out.append((rigid, vib))
        return out


def _work_on_bodies(raw, xa0, free, force_in, load_rows, jdx, *, energy_unit=1.0):
    """Work (J) of the contact force and the loads on each body over the run ``raw``
    (:class:`impactpred.engine.impact_run.RawRun`), exactly.

    Over a phase, ``int f_i v_i dt`` (``f_i``: ``-f`` on body 1, ``+f`` on body 2, plus its
    load; ``v_i`` its contact point's velocity), in closed form
    (``form.product_integrals``: contact phases, and free flight under a load). At a
    phase's start a Dirac impulse ``P`` (the jump of the impulse integral ``J`` over the
    free flight before: a Dirac comes only at a contact's start, after free flight, and
    may be followed by a contact phase or, released at once, by free flight again; one at
    ``t_end`` itself shows in the final state) does ``-+P (v_i- + v_i+) / 2``,
    with ``v- = v+ - P (v rows @ force_in)``: a Dirac occurs only where neither body feeds
    the force straight through to its velocity, so free flight's velocity rows give both
    one-sided limits. Cost: O(rates^2) per contact or loaded phase kind, then O(rates x
    (36 + fast rates)) per run (:mod:`impactpred.engine.product_integrals`).

    Parameters
    ----------
    raw : RawRun
        The engine's run (its phases and their starting states).
    xa0 : numpy.ndarray
        The augmented state at ``t = 0`` before any Dirac impulse.
    free : Phase
        The free flight (its rows 4 and 5: the contact points' velocities).
    force_in : numpy.ndarray
        The contact force's input to the augmented state (an impulse ``P`` adds
        ``P force_in``).
    load_rows : pair of numpy.ndarray
        Each body's load (N, along +y) as a row on the augmented state (zeros without one).
    jdx : int
        Index of ``J`` in the augmented state.
    energy_unit : float, keyword-only
        The energy (J) of a unit of work of the rows on the state (the run's
        dimensionless form: :class:`._units.Units`).

    Returns
    -------
    numpy.ndarray
        Shape (2,): the work on body 1 and body 2.
    """
    sign = np.array([-1.0, 1.0])
    velocity_rows = free.rows[4:6]
    work = np.zeros(2)

    def dirac_work(j_before, x_after):
        """The work of the Dirac impulse (if any) that took ``J`` from ``j_before`` to its
        value in ``x_after``."""
        jump = x_after[jdx] - j_before if j_before is not None else 0.0
        if jump == 0.0:
            return 0.0
        v_plus = velocity_rows @ x_after
        v_minus = v_plus - jump * (velocity_rows @ force_in)
        return sign * jump * 0.5 * (v_minus + v_plus)

    loaded = any(np.any(r) for r in load_rows)
    runs = {}                  # per phase kind: (the phase, its runs (x0, h)) to integrate
    j_before = xa0[jdx]         # J where the last free flight began (it holds J constant)
    for phase, t0, t1, x0 in raw.phases:
        # a Dirac impulse starts a contact only after free flight (or at t = 0)
        work += dirac_work(j_before, x0)
        if t1 > t0 and (phase.contact or loaded):
            runs.setdefault(id(phase), (phase, []))[1].append((x0, t1 - t0))
        j_before = None if phase.contact else x0[jdx]
    work += dirac_work(j_before, raw.x_end)              # a Dirac at t_end itself
    # rows: force (0 in free flight), v1, v2, and each body's load if any
    pairs = ((0, 1), (0, 2), (3, 1), (4, 2)) if loaded else ((0, 1), (0, 2))
    for phase, phase_runs in runs.values():
        rows = [phase.rows[0], phase.rows[4], phase.rows[5]] + (list(load_rows) if loaded
                                                                else [])
        ints = phase.form.product_integrals(phase.form.project(np.vstack(rows)),
                                            phase_runs, pairs)
        work += sign * ints[:2] + (ints[2:] if loaded else 0.0)
    return energy_unit * work


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


def _markov(sysm: CoupledSystem):
    """``(c0, c1, c2)``: the force's coefficients in the gap and its first two derivatives
    (``Dg``, ``Cg Bf``, ``Cg A Bf``: ``H1 + H2 ~ c0 + c1 / s + c2 / s^2`` at high ``s``)."""
    c1 = float(sysm.Cg @ sysm.Bf) if sysm.n else 0.0
    c2 = float(sysm.Cg @ sysm.A @ sysm.Bf) if sysm.n else 0.0
    return sysm.Dg, c1, c2


def _free_rate(sysm: CoupledSystem) -> float:
    """The fastest rate (rad/s) of the free bodies: their poles' largest modulus, 0 for
    none."""
    rates = [np.abs(np.concatenate([m.poles, m.real_poles])) for m in sysm.models]
    return max([0.0] + [float(r.max()) for r in rates if r.size])


def _relative_degree(sysm: CoupledSystem, t_end=None):
    """(rho, coefficient) of the first derivative of the gap in which ``f`` appears,
    judged at the free bodies' fastest rate (``1 / t_end`` without poles; 1 rad/s
    without ``t_end`` either)."""
    c0, c1, c2 = _markov(sysm)
    scale = _free_rate(sysm) or (1.0 / t_end if t_end else 1.0)
    if abs(c2) + abs(c1) * scale + abs(c0) * scale**2 == 0.0:
        raise ValueError("H1 + H2 is identically zero: the bodies have no compliance")
    rho = relative_degree(c0, c1, c2, scale)
    return rho, (c0, c1, c2)[rho]


def _units(sysm: CoupledSystem, contact, loads, t_end, displacement) -> Units:
    """The reference units of the engine's dimensionless form (:mod:`._units`);
    ``displacement``: those in play (:func:`_displacements`)."""
    compliance = sysm.Dg + (1.0 / contact.stiffness if isinstance(contact, LinearSpring)
                            else 0.0)
    return reference_units(_markov(sysm), _free_rate(sysm), compliance=compliance,
                           t_end=t_end, rates=[load.omega for _, load in loads],
                           displacement=displacement,
                           force=sum(load.amplitude for _, load in loads))


def _displacements(bodies, sysm: CoupledSystem, gap0, t_end) -> tuple[float, float]:
    """The displacements (m) at ``t = 0``, the gap and the contact points' vibration
    (:func:`_vibration_scale`), and those in play over the run: with the approach."""
    now = abs(gap0) + _vibration_scale(sysm)
    return now, now + max(abs(b.velocity) for b in bodies) * t_end


def _vibration_scale(sysm: CoupledSystem) -> float:
    """The contact points' displacements (m) at ``t = 0``, term by term: ``|C| @ |X0|``."""
    if not sysm.n:
        return 0.0
    return float((np.abs(sysm.C1) + np.abs(sysm.C2)) @ np.abs(sysm.X0))


def harmonic_loads(bodies):
    """``(body index, HarmonicForce)`` of each body's load; ``ValueError`` for any other
    load (the exact solver propagates a harmonic force in closed form, not samples)."""
    loads = []
    for i, body in enumerate(bodies):
        if body.load is None:
            continue
        if not isinstance(body.load, HarmonicForce):
            raise ValueError(f"the laplace solver takes a HarmonicForce load or none, got "
                             f"{type(body.load).__name__} on body {i + 1}: use method='modal'")
        loads.append((i, body.load))
    return loads


def solve_laplace(bodies, gap0, contact, t_end, dt, *, notes=(), receptance_scale=1.0):
    """Exact event-driven solve of two rational bodies; see the module docstring.
    ``receptance_scale``: body 1's receptance multiplied by it (the sensitivity check of
    :func:`impactpred.solve_impact` runs at ``1 +- 1e-6``)."""
    loads = harmonic_loads(bodies)
    sysm = CoupledSystem(bodies, receptance_scale)
    points = LaplaceOutputs(bodies, sysm)
    n = sysm.n
    A, Bf, Cg = sysm.A, sysm.Bf, sysm.Cg
    D1, D2 = sysm.D
    # [X, 1, J, then cos and sin of each harmonic load's phase]
    n_aug = n + 2 + 2 * len(loads)
    one, jdx = n, n + 1

    def aug(row_x, const=0.0):
        row = np.zeros(n_aug)
        row[:n] = row_x
        row[one] = const
        return row

    gap_row = aug(Cg, gap0)
    y1_row, y2_row = aug(sysm.C1), aug(sysm.C2)

    # free flight: X' = A X + the loads' inputs; each load's (cos, sin) pair rotates
    M_free = np.zeros((n_aug, n_aug))
    M_free[:n, :n] = A
    Xa = np.concatenate([sysm.X0, [1.0, 0.0], np.zeros(2 * len(loads))])
    load_rows = [np.zeros(n_aug), np.zeros(n_aug)]   # each body's load (N) on the state
    for k, (i, load) in enumerate(loads):
        ic = n + 2 + 2 * k
        load_rows[i][ic] += load.amplitude
        body_rows = slice(0, sysm.n1) if i == 0 else slice(sysm.n1, n)
        b_i = (-Bf if i == 0 else Bf)[body_rows]           # the body's own input, +y
        M_free[body_rows, ic] = load.amplitude * b_i
        M_free[ic, ic + 1], M_free[ic + 1, ic] = -load.omega, load.omega
        Xa[ic], Xa[ic + 1] = np.cos(load.phase), np.sin(load.phase)
        # the load's direct term d_i F_i in the body's displacement and in the gap
        y_row = y1_row if i == 0 else y2_row
        y_row[ic] += sysm.D[i] * load.amplitude
        gap_row[ic] += (-1.0 if i == 0 else 1.0) * sysm.D[i] * load.amplitude
    # the dimensionless form the engine runs on (:mod:`._units`): x = unit * xi,
    # t = u.t * tau, each row in units of its own (row_unit); rows are built in SI here
    displacement_0, displacement = _displacements(bodies, sysm, gap0, t_end)
    u = _units(sysm, contact, loads, t_end, displacement)
    unit = np.concatenate([sysm.state_units(u), [1.0, u.j], np.ones(2 * len(loads))])
    row_unit = np.concatenate([[u.f, u.l, u.l, u.l, u.l / u.t, u.l / u.t],
                               points.row_units(u.l, u.t)])
    M_free_s = u.matrix(M_free, unit)
    gap_s = unit * gap_row / u.l
    # output rows: force, y1, y2, gap, the contact points' velocities, the output points
    free = Phase(M_free_s, unit * np.vstack([np.zeros(n_aug), y1_row, y2_row, gap_row,
                                             y1_row @ M_free, y2_row @ M_free,
                                             points.rows(M_free, loads=loads)])
                 / row_unit[:, None], gap_s, False)

    # contact: f = Kf X + k0, X' = (A + Bf Kf) X + Bf k0, J' = f
    if not contact.is_linear:
        raise ValueError(f"the laplace solver takes Rigid() or an undamped LinearSpring, got "
                         f"{contact!r}: use method='modal' or 'convolution'")
    if isinstance(contact, Rigid):
        # the gap's rho-th derivative without the force, held at 0 by it
        rho, coef = _relative_degree(sysm, t_end)
        held = gap_row
        for _ in range(rho):
            held = held @ M_free
        force_row = -held / coef
        # coef on the dimensionless rows: the gap (rho = 0), its rate (1) per unit force,
        # or its rate's jump per unit impulse (rho = 2)
        coef = coef * (u.f / u.l if rho == 0 else u.m if rho == 2 else u.f * u.t / u.l)
    else:           # an undamped LinearSpring
        rho, coef = -1, (1.0 / contact.stiffness + sysm.Dg) * u.f / u.l
        force_row = -contact.stiffness * gap_row / (1 + contact.stiffness * sysm.Dg)
    # the force enters the states through Bf and its integral J: a rank-one update
    force_in = np.concatenate([Bf, [0.0, 1.0], np.zeros(2 * len(loads))])
    M_con = M_free + np.outer(force_in, force_row)
    force_in_s, force_s = force_in / unit * u.j, force_row * unit / u.f
    M_con_s = M_free_s + np.outer(force_in_s, force_s)
    y1_con, y2_con = y1_row - D1 * force_row, y2_row + D2 * force_row
    stuck = Phase(M_con_s, unit * np.vstack([force_row, y1_con, y2_con,
                                             gap_row + sysm.Dg * force_row,
                                             y1_con @ M_con, y2_con @ M_con,
                                             points.rows(M_con, force_row, loads=loads)])
                  / row_unit[:, None], force_s, True,
                  update_of=(free.form, force_in_s, force_s))

    rate = stuck.form.max_rate / u.t
    if isinstance(contact, LinearSpring) and not rate * t_end <= _RESOLVED_RATE:
        raise ValueError(f"the spring contact's fastest rate, {rate:.3g} rad/s, over t_end = "
                         f"{t_end:.6g} s is beyond what double-precision times resolve (a "
                         f"time scale of {1 / rate:.3g} s, {1 / (rate * t_end):.2g} of t_end):"
                         f" a stiffness of {contact.stiffness:.3g} N/m is rigid at this "
                         "scale: use Rigid(), or a shorter t_end")
    u.check()           # after the spring's own refusal: the clearer one where both apply
    t_end_s = t_end / u.t
    step = search_step(max(free.form.max_rate, stuck.form.max_rate), t_end_s)
    out_step = dt if dt is not None else t_end / 4000

    # the gap's rounding level (in u.l): 1e-12 of the displacements in play
    tol_g = 1e-12 * max(displacement / u.l, 1e-300)
    # the contact rules (Dirac impulse, hold or release): the gap's first three
    # derivatives in free flight, rows on the augmented state
    cg_powers = np.zeros((3, n_aug))
    cg_powers[0] = gap_s @ M_free_s
    cg_powers[1] = cg_powers[0] @ M_free_s
    cg_powers[2] = cg_powers[1] @ M_free_s
    rules = ContactRules(rho, coef, force_in_s[:n], jdx, force_s, force_s @ M_con_s,
                         cg_powers, tol_g)
    # touching at t = 0 and not separating: the contact rules decide at once whether a
    # contact starts (a Dirac where they approach; held where they press) (the gap at
    # t = 0 is gap0 plus what the bodies' initial displacements and loads open or close)
    # (a relative velocity within the rounding of its terms is zero)
    Xa_s = Xa / unit
    v_rel = float(cg_powers[0] @ Xa_s)
    still = abs(v_rel) <= 1e-12 * float(np.abs(cg_powers[0]) @ np.abs(Xa_s))
    # (touching now is judged at the scale of the displacements now, the gap and the
    # vibration: the approach over a long run, in tol_g, had made a gap of 1e-6 m touch at
    # t = 0 for t_end = 1e6 s, a phantom first contact of restitution -1)
    tol_0 = 1e-12 * displacement_0 / u.l
    in_contact = bool(n) and float(gap_s @ Xa_s) <= tol_0 and (v_rel < 0.0 or still)
    raw = run_contact(free, stuck, Xa_s, in_contact=in_contact, rules=rules, t_end=t_end_s,
                      step=step, out_step=out_step / u.t, gap0=gap0 / u.l)
    if in_contact and still and raw.diracs and raw.diracs[0][0] == 0.0:
        # a Dirac at t = 0 of a relative velocity within rounding is rounding (1e-21 N s):
        # not reported, nor the touch it alone would make
        raw.diracs = raw.diracs[1:]
        if raw.intervals and raw.intervals[0] == (0.0, 0.0):
            raw.intervals = raw.intervals[1:]
    # an undamped body's energy at t_end is the energy delivered: the work is integrated
    # only where a body's own damping takes some
    damped = [bool(np.any(m.poles.real) or m.real_poles.size) for m in sysm.models]
    work = (_work_on_bodies(raw, Xa_s, free, force_in_s, [unit * r / u.f for r in load_rows],
                            jdx, energy_unit=u.e) if any(damped) else None)
    if work is not None and not np.all(np.isfinite(work)):
        notes = tuple(notes) + ("the work on the bodies overflowed (a pole growing over a "
                                "phase): the vibration energy reported is what they hold "
                                "at t_end",)
        work = None
    # back to SI: times, samples, the state, impulses (the exact peak found on the form)
    T, V = insert_exact_peak(raw.T, raw.V, raw.intervals, raw.first_phase)
    raw.T, raw.V = u.t * T, row_unit[:, None] * V
    raw.intervals = [(u.t * a, u.t * b) for a, b in raw.intervals]
    raw.diracs = [(u.t * t, u.j * p) for t, p in raw.diracs]
    raw.x_end, raw.first_impulse = unit * raw.x_end, u.j * raw.first_impulse
    return _result(bodies, sysm, points, raw, force_row, jdx, t_end, out_step, u.t * step,
                   notes, work=work)


_grazing = grazing_error     # the name the CLI's tests raise


def _result(bodies, sysm, points, raw, force_row, jdx, t_end, out_step, step, notes, *,
            work):
    """The :class:`ImpactResult` of the engine's run ``raw`` (either propagation; in SI,
    the exact force peak inserted).

    A body's ``vibration_after`` is the vibration energy delivered to it: its vibration
    energy before, plus the ``work`` (J, per body) of the contact force and its load, less
    its rigid-body energy's gain; what it holds at ``t_end`` plus what its own damping
    took by then, as the time-stepping solvers obtain it by their energy balance (the
    energy a damped body holds at ``t_end`` alone depends on ``t_end``). ``work`` None:
    no body is damped, and each holds at ``t_end`` what it was delivered."""
    n = sysm.n
    intervals, diracs, X_end, kind = raw.intervals, raw.diracs, raw.x_end, raw.kind
    T, V = raw.T, raw.V
    F = np.maximum(V[0], 0.0)
    in_contact_end = bool(intervals) and intervals[-1][1] == t_end and intervals[-1][0] < t_end
    f_end = float(force_row @ X_end) if in_contact_end else 0.0
    u_before = (bodies[0].velocity, bodies[1].velocity)
    u_after = (sysm.rigid_velocity(X_end[:n], 0), sysm.rigid_velocity(X_end[:n], 1))
    before = sysm.energies(sysm.X0, _body_forces(bodies, 0.0, 0.0))
    after = sysm.energies(X_end[:n], _body_forces(bodies, f_end, t_end))
    # the energy held is the energy delivered where no body is damped (work None) and for
    # a body of neither modes nor real poles (its flexibility's strain energy alone)
    energy = []
    for i, (b, a, model) in enumerate(zip(before, after, sysm.models)):
        delivered = a[1]
        if work is not None and (model.n_modes or model.real_poles.size):
            delivered = b[1] + work[i] - (a[0] - b[0])
        energy.append(BodyEnergy(b[0], b[1], a[0], delivered, vibration_held=a[1]))
    inv = (bodies[0].inverse_mass, bodies[1].inverse_mass)
    note = (f"exact (Laplace/state-space, {kind}) solution; output step {out_step:.4g} s, "
            f"event search step {step:.4g} s",)
    return ImpactResult(t=T, force=F, y1=V[1], y2=V[2], gap=V[3], v1=V[4], v2=V[5],
                        contact_intervals=tuple(intervals), dirac_impulses=tuple(diracs),
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=tuple(energy), method="laplace", dt=out_step,
                        first_contact_impulse=raw.first_impulse,
                        total_impulse=float(X_end[jdx]), inverse_masses=inv,
                        notes=tuple(notes) + note,
                        points=points.responses(bodies, T, V[6:]))


def _body_forces(bodies, f, t):
    """The force (N, along +y) on each body at time ``t`` (s) with contact force ``f``:
    ``-f`` on body 1, ``+f`` on body 2, plus each body's load."""
    loads = [float(b.load_samples(t)) for b in bodies]
    return (loads[0] - f, loads[1] + f)
