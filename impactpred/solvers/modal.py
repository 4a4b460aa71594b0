"""Time stepping with the exact discretisation of every mode.

Each complex mode (``z' = p z + u``, contribution ``Re(w z)`` to the displacement, ``w =
2 r``) and real pole advances exactly for a force ``u`` that is linear over the step
``[t_n, t_n + dt]`` (first-order hold, the default):

    z_{n+1} = exp(p dt) z_n + A u_n + C (u_{n+1} - u_n)/dt,
    A = (exp(p dt) - 1)/p,   C = (exp(p dt) - 1 - p dt)/p^2,

the rigid body as ``d += v dt + (u_n/3 + u_{n+1}/6) dt^2/M``, ``v += (u_n + u_{n+1}) dt/(2M)``,
the residual flexibility as ``D u``. The contact force ``f_{n+1}`` at each step's end is
the one for which the contact law holds there (collocation): the gap at the step's end
is affine in it, ``g_{n+1} = G + K f_{n+1}``, so rigid contact gives ``f = max(0, -G/K)``,
a spring-dashpot ``f = k d + c d'`` (exact ``d'``) one linear equation, Hertz contact a
scalar Newton solve. Contact events are located inside the step: a contact starts at
the root of the exact force-free gap in the step (found by regula falsi on the closed
form, to rounding), the force then rising linearly from 0 over the rest of the step; a
contact ends where the force, linear between ``f_n`` and the law's unclipped end value
(for Hertz contact: the gap, between its values at the step's ends), crosses 0 (for a
spring-dashpot: falls to the rounding of its ``c d'``, ``dashpot_floor``), the step
then splitting into the exact motion under a ramp down to 0 and the free motion.

Accuracy: exact for any force that is piecewise linear with these knots (the modes'
truncation is the model's, not the solver's); for the true force, smooth between events,
second order in ``dt``, contact start and end times and restitution included (on the
benchmark's 50-mode rod, errors ~300 dt^2 s in the event times: the contact dynamics'
dispersion, not the event location). First-order exceptions: a dashpot's force jump at
contact start is spread over the rest of that step, and a load is held linear between
its samples at the grid times (a jump in the load costs O(dt)). The work of the forces
on each body is integrated exactly over every (sub)step, so the energy balance of the
stepped solution holds to rounding. ``force`` holds the force at the grid times (linear
in between, except in steps with an event). Cost: O(steps x modes) in a compiled (numba)
kernel (~0.2 us a step for 50 modes), O(modes) exponentials per event, and a one-time
compilation (~10 s, cached on disk).

Stability of the first-order hold: in contact, the force at a step's end answers the
one at its start with the ratio ``-K_a/(K + c_law)`` (``K_a``: the end gap's coefficient
of ``f_n``, ``c_law`` the contact's compliance); with rigid contact and no flexibility
(``D = 0``: a Dirac-force problem) ``K_a = 2 K`` and the hold oscillates. At a ratio
near 1 the oscillation hardly decays: a mass on a model whose mobility has an
instantaneous part (a fast real pole, no flexibility: a dashpot at the contact) gave a
force alternating 0, 16 700, 200, 16 800 N about the true 8 400 N, and a work 13 % above
the energy the mass lost, at every ``dt`` (ratio 0.997). The solver uses the first-order
hold when ``K_a <= MAX_HOLD_RATIO (K + c_law)`` (0.5: the oscillation at least halves
every step; a flexibility or a compliant contact gives ratios near 4e-6 at the
automatic step), else the zero-order hold.

Zero-order hold (``hold="constant"``: unstable first-order hold, output points, or a
contact law other than ``Rigid``, ``LinearSpring``, ``Hertz``): the force is constant on
every step, the same modal maps with ``C = 0`` and ``d += v dt + u dt^2/(2M)``; the
force of each step solves the same scalar complementarity problem as the convolution
solver (:class:`._step_force.StepForce`: a plastic start where the bodies are masses at
the contact), so the two agree to rounding on the same model. First order in ``dt`` at
contact events; a Python loop, O(steps x modes).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..contact import Hertz, LinearSpring, Rigid
from ..parallel import progress_bar
from ..result import BodyEnergy, ImpactResult
from ._outputs import ModalOutputs, _require_multi
from ._step_force import StepForce, backward_gap, kernel_ratio, rounding_gap
from ._stepping import (Grid, assemble_result, energy_before, free_displacements,
                        micro_separation_tolerance, step_kernel)

__all__ = ["solve_modal", "first_order_hold_applies"]

HOLDS = ("auto", "linear", "constant")
#: steps between the zero-order hold loop's progress-bar updates
_BAR_STRIDE = 1024


class _ModalStepper:
    """Exact one-step maps of one body's modal model, stacked as complex vectors."""

    def __init__(self, model, dt):
        p = np.concatenate([model.poles, model.real_poles.astype(complex)])
        weight = np.concatenate([2.0 * model.residues, model.real_residues.astype(complex)])
        self.p = p
        self.E = np.exp(p * dt)
        self.G = np.expm1(p * dt) / p
        self.weight = weight
        self.inverse_mass = model.inverse_mass
        self.flexibility = model.flexibility
        self.dt = dt

    def output(self, z, d):
        return float(np.dot(self.weight, z).real) + d


def _initial_states(bodies, models):
    """Initial complex modal states of the vibration, in each model's own mode order."""
    z = []
    for body, model in zip(bodies, models):
        zi = np.zeros(model.n_modes + model.real_poles.size, dtype=complex)
        states = body.initial_modal_states()
        if states is not None:
            order = np.argsort(np.abs(model.poles), kind="stable")[:body.vibration.shape[0]]
            zi[order] = states[2]
        z.append(zi)
    return z


def _law_code(contact):
    """(code, k, c, exponent) of the laws the compiled kernel knows, else None."""
    from ._modal_kernel import HERTZ, RIGID, SPRING

    kind = type(contact)
    if kind is Rigid:
        return RIGID, 0.0, 0.0, 1.0
    if kind is LinearSpring:
        return SPRING, contact.stiffness, contact.damping, 1.0
    if kind is Hertz:
        return HERTZ, contact.stiffness, 0.0, contact.exponent
    return None


#: the note of a first-order-hold run (its force samples are the law's at the grid times:
#: :func:`impactpred._energy_terms.dashpot_dissipation` reads them so)
FIRST_ORDER_NOTE = ("modal: first-order hold, contact events located inside the steps "
                    "(second order in dt where the force is continuous, first order where it "
                    "jumps, as a dashpot's at a contact's start); force samples are its "
                    "values at the grid times")
#: the first-order hold is used up to this force ratio (see the module docstring)
MAX_HOLD_RATIO = 0.5


def _hold_ratio(steppers, contact, bodies, dt):
    """``K_a / (K + c_law)``: the first-order hold's force ratio in contact (see module doc)."""
    from ._modal_kernel import hold_coefficients

    h = dt
    k_a = k_b = inv_eff = 0.0
    for s in steppers:
        e, a, c, q = (np.empty(s.p.size, complex) for _ in range(4))
        hold_coefficients(s.p, h, e, a, c, q)      # the kernel's own A and C
        k_a += float(np.sum(s.weight * (a - c / h)).real) + s.inverse_mass * h * h / 3.0
        k_b += (float(np.sum(s.weight * c / h).real) + s.inverse_mass * h * h / 6.0
                + s.flexibility)
        inv_eff += float(np.sum(s.weight * s.p).real) + s.inverse_mass
    if not k_b > 0.0:
        raise ValueError(f"the bodies' response at a step's end to a unit force ramp is "
                         f"{k_b!r} m/N, not positive: not driving points")
    if isinstance(contact, LinearSpring):
        compliance = 1.0 / contact.stiffness
    elif isinstance(contact, Hertz):
        # tangent stiffness at the peak of an impact at the approach speed
        v = abs(bodies[0].velocity - bodies[1].velocity) or 1.0
        n, k = contact.exponent, contact.stiffness
        m_eff = 1.0 / inv_eff if inv_eff > 0 else np.inf
        depth = ((n + 1) * m_eff * v**2 / (2 * k)) ** (1 / (n + 1)) if np.isfinite(m_eff) \
            else 1.0
        compliance = 1.0 / (k * n * depth ** (n - 1))
    else:
        compliance = 0.0
    return k_a / (k_b + compliance)


def first_order_hold_applies(bodies, contact, dt) -> bool:
    """Whether :func:`solve_modal` (``hold="auto"``) steps these bodies with its
    first-order hold at ``dt`` (s), as it decides (module docstring)."""
    if any(b.outputs is not None for b in bodies) or _law_code(contact) is None:
        return False
    steppers = [_ModalStepper(b.modal_model(), dt) for b in bodies]
    try:
        return bool(_hold_ratio(steppers, contact, bodies, dt) <= MAX_HOLD_RATIO)
    except ValueError:              # not driving points: solve_modal says so
        return False


def solve_modal(bodies, gap0, contact, t_end, dt, *, notes=(), hold="auto", progress=False):
    """Modal time-stepping solve of two bodies with rational (or truncated) models.

    Parameters
    ----------
    bodies : pair of Body
    gap0 : float
        Initial gap (m).
    contact : ContactLaw
    t_end, dt : float
        End time and step (s).
    notes : tuple of str
        Notes to pass on to the result.
    hold : {"auto", "linear", "constant"}
        Force interpolation over a step. ``"auto"``: the first-order hold with located
        events where it applies and is stable (see the module docstring), else the
        zero-order hold; ``"constant"``: the zero-order hold (agrees with the convolution
        solver to rounding); ``"linear"``: the first-order hold, or ``ValueError`` where it
        does not apply.
    progress : bool
        A bar on stderr over the zero-order hold's Python step loop (the first-order
        hold's loop is compiled and takes none).
    """
    if hold not in HOLDS:
        raise ValueError(f"hold must be one of {HOLDS}, got {hold!r}")
    _require_multi(bodies, "modal")
    notes = list(notes)
    if hold != "constant":
        models = [b.modal_model() for b in bodies]
        steppers = [_ModalStepper(m, dt) for m in models]
        why = None
        if any(b.outputs is not None for b in bodies):
            why = "output points"
        elif _law_code(contact) is None:
            why = f"contact law {type(contact).__name__}"
        else:
            ratio = _hold_ratio(steppers, contact, bodies, dt)
            if not ratio <= MAX_HOLD_RATIO:
                why = (f"the first-order hold's force would oscillate from step to step at "
                       f"this dt (force ratio {ratio:.3g} > {MAX_HOLD_RATIO:g}: rigid contact "
                       "without flexibility, a dashpot-like model at the contact, or dt too "
                       "coarse for the contact stiffness)")
        if why is None:
            return _solve_linear_hold(bodies, models, steppers, gap0, contact, t_end, dt,
                                      notes)
        if hold == "linear":
            raise ValueError(f"the first-order hold does not apply: {why}")
        notes.append(f"modal: zero-order hold (first order in dt) because of {why}")
    return _solve_constant_hold(bodies, gap0, contact, t_end, dt, notes=tuple(notes),
                                progress=progress)


# ------------------------------------------------------------------ first-order hold
def _solve_linear_hold(bodies, models, steppers, gap0, contact, t_end, dt, notes):
    from ._modal_kernel import foh_stepping

    grid = Grid(t_end, dt)
    loads = [b.load_samples(grid.t) for b in bodies]
    has_load = any(b.load is not None for b in bodies)
    z = _initial_states(bodies, models)
    d = [b.displacement if b.inverse_mass else 0.0 for b in bodies]
    v = [float(b.velocity) for b in bodies]
    code, k, c, n = _law_code(contact)
    s1, s2 = steppers
    out = foh_stepping(s1.p, s1.weight, float(s1.inverse_mass), float(s1.flexibility), z[0],
                       float(d[0]), v[0],
                       s2.p, s2.weight, float(s2.inverse_mass), float(s2.flexibility), z[1],
                       float(d[1]), v[1],
                       loads[0], loads[1], has_load, float(gap0), float(dt), grid.n_steps,
                       code, float(k), float(c), float(n))
    force, y1, y2, events, impulse, work1, work2 = out[:7]
    notes.append(FIRST_ORDER_NOTE)
    gap = y2 - y1 + gap0
    tol = micro_separation_tolerance(y1, y2)
    runs = _contact_runs(events, force, gap, tol, grid)
    intervals = tuple((a, b) for a, b, _, _ in runs)
    total_impulse = float(np.sum(impulse))
    first_impulse = float(np.sum(impulse[runs[0][2]:runs[0][3] + 1])) if runs else 0.0

    b1, b2 = bodies
    inv = (b1.inverse_mass, b2.inverse_mass)
    u_before = (b1.velocity, b2.velocity)
    load_impulse = [float(np.sum(load[1:] + load[:-1]) * 0.5 * dt) for load in loads]
    u_after = (u_before[0] + inv[0] * (load_impulse[0] - total_impulse),
               u_before[1] + inv[1] * (load_impulse[1] + total_impulse))
    energies = []
    for i, (body, work) in enumerate(((b1, work1), (b2, work2))):
        rigid_before = 0.5 * u_before[i] ** 2 / inv[i] if inv[i] > 0 else 0.0
        rigid_after = 0.5 * u_after[i] ** 2 / inv[i] if inv[i] > 0 else 0.0
        vib_before = energy_before(body)
        energies.append(BodyEnergy(rigid_before, vib_before, rigid_after,
                                   vib_before + work - (rigid_after - rigid_before)))
    return ImpactResult(t=grid.t, force=force, y1=y1, y2=y2, gap=gap,
                        contact_intervals=intervals, dirac_impulses=(),
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=tuple(energies), method="modal", dt=dt,
                        first_contact_impulse=first_impulse, total_impulse=total_impulse,
                        inverse_masses=inv, notes=tuple(notes), points=(None, None))


def _contact_runs(events, force, gap, tol, grid):
    """Contact intervals ``(start, end, first step, last step)`` from the kernel's events.

    Like the zero-order-hold runs: a contact whose force never exceeds ``1e-10`` of the
    peak is rounding, not contact, and two contacts separated by an opening whose gap at
    the grid times never exceeds ``tol`` are one.
    """
    raw = []
    start = None
    for time, kind, step in events:
        if kind > 0:
            start = (float(time), int(step))
        elif start is not None:
            raw.append([start[0], float(time), start[1], int(step)])
            start = None
    if start is not None:
        raw.append([start[0], float(grid.t[-1]), start[1], grid.n_steps - 1])
    if not raw:
        return []
    peak = float(np.max(force))
    t = grid.t
    runs = np.array([r[:2] for r in raw])
    first = np.searchsorted(t, runs[:, 0], "right")       # grid times inside each run
    last = np.searchsorted(t, runs[:, 1], "left")
    padded = np.append(force, 0.0)
    bounds = np.minimum(np.column_stack([first, last]).ravel(), force.size)
    top = np.where(last > first, np.maximum.reduceat(padded, bounds)[::2], 0.0)
    kept = [run for run, m in zip(raw, top) if m > 1e-10 * peak]
    merged = []
    for run in kept:
        if merged:
            prev = merged[-1]
            i0, i1 = np.searchsorted(t, prev[1], "right"), np.searchsorted(t, run[0], "left")
            if i1 <= i0 or np.all(gap[i0:i1] <= tol):
                prev[1], prev[3] = run[1], run[3]
                continue
        merged.append(run)
    return [tuple(r) for r in merged]


# ------------------------------------------------------------------- zero-order hold
def _solve_constant_hold(bodies, gap0, contact, t_end, dt, *, notes=(), progress=False):
    """The zero-order-hold stepping (Python loop): agrees with the convolution solver."""
    grid = Grid(t_end, dt)
    models = [b.modal_model() for b in bodies]
    steppers = [_ModalStepper(m, dt) for m in models]
    # only the first step-response increment enters the stepping: S(dt) of each body
    first = [float(m.step_response([dt])[0]) for m in models]
    if not all(x > 0 for x in first):
        raise ValueError(f"the step responses over the first step (dt = {dt:.6g} s) are "
                         f"{first} m/N, not both positive: not driving points, or a step far "
                         "too long for them (choose_dt gives the step that resolves them)")
    k0 = first[0] + first[1]
    # the contact rule as the convolution solver builds it (the two agree to rounding);
    # its rounding scale, the free motion with the loads' response, only where it is used
    ratio, small_time = kernel_ratio([m.step_response for m in models], dt)
    rule = StepForce(contact, k0, ratio * k0, dt, small_time_ratio=small_time)
    if rule.plastic:
        rule.gap_tolerance = rounding_gap(*(free_displacements(b, grid, step_kernel(b, grid))
                                            for b in bodies))
    law = rule.force
    loads = [b.load_samples(grid.midpoints) for b in bodies]

    z = _initial_states(bodies, models)
    d = [b.displacement if b.inverse_mass else 0.0 for b in bodies]
    v = [b.velocity for b in bodies]

    force = np.zeros(grid.n_steps)
    y1 = np.empty(grid.n_steps + 1)
    y2 = np.empty(grid.n_steps + 1)
    y1[0] = steppers[0].output(z[0], d[0])
    y2[0] = steppers[1].output(z[1], d[1])
    g_prev = y2[0] - y1[0] + gap0
    s1, s2 = steppers
    E1, G1, w1, E2, G2, w2 = s1.E, s1.G, s1.weight, s2.E, s2.G, s2.weight
    h, h2 = dt, 0.5 * dt * dt
    m1, m2 = s1.inverse_mass, s2.inverse_mass
    z1, z2 = z
    rec1, rec2 = (ModalOutputs(b, m, grid.n_steps + 1, dt) if b.outputs is not None else None
                  for b, m in zip(bodies, models))
    if rec1:
        rec1.record(0, z1, d[0], v[0], 0.0)
    if rec2:
        rec2.record(0, z2, d[1], v[1], 0.0)
    def free_step(z1, z2, d, v, u1, u2):
        """The end-of-step state at zero contact force, and its gap."""
        z1f = E1 * z1 + G1 * u1
        z2f = E2 * z2 + G2 * u2
        d1f = d[0] + v[0] * h + m1 * h2 * u1
        d2f = d[1] + v[1] * h + m2 * h2 * u2
        y1f = float(np.dot(w1, z1f).real) + d1f + s1.flexibility * u1
        y2f = float(np.dot(w2, z2f).real) + d2f + s2.flexibility * u2
        return z1f, z2f, d1f, d2f, y1f, y2f, y2f - y1f + gap0

    # the gap a step before t_0 (StepForce), from the force-free gaps at t_1 and t_2
    *state1, free1 = free_step(z1, z2, d, v, loads[0][0], loads[1][0])
    free2 = None
    if grid.n_steps > 1:
        v1 = [v[0] + loads[0][0] * m1 * h, v[1] + loads[1][0] * m2 * h]
        free2 = free_step(state1[0], state1[1], state1[2:4], v1, loads[0][1],
                          loads[1][1])[-1]
    g_before = backward_gap(g_prev, free1, free2)
    with progress_bar(grid.n_steps, enabled=progress, desc="modal", unit="step") as bar:
        for n in range(grid.n_steps):
            if n and n % _BAR_STRIDE == 0:
                bar.update(_BAR_STRIDE)
            u1, u2 = loads[0][n], loads[1][n]
            z1f, z2f, d1f, d2f, y1f, y2f, G = free_step(z1, z2, d, v, u1, u2)
            f = law(G, g_prev, g_before)
            force[n] = f
            if f:
                z1 = z1f - G1 * f
                z2 = z2f + G2 * f
                d[0], d[1] = d1f - m1 * h2 * f, d2f + m2 * h2 * f
                v[0] += (u1 - f) * m1 * h
                v[1] += (u2 + f) * m2 * h
                y1[n + 1] = y1f - first[0] * f
                y2[n + 1] = y2f + first[1] * f
            else:
                z1, z2 = z1f, z2f
                d[0], d[1] = d1f, d2f
                v[0] += u1 * m1 * h
                v[1] += u2 * m2 * h
                y1[n + 1], y2[n + 1] = y1f, y2f
            g_before, g_prev = g_prev, y2[n + 1] - y1[n + 1] + gap0
            if rec1:
                rec1.record(n + 1, z1, d[0], v[0], u1 - f)
            if rec2:
                rec2.record(n + 1, z2, d[1], v[1], u2 + f)
        bar.update(grid.n_steps - bar.n)
    points = tuple(r.response(b, grid.t) if r else None for r, b in zip((rec1, rec2), bodies))
    result = assemble_result(bodies, gap0, grid, force, None, None, method="modal",
                             notes=notes, y=(y1, y2), points=points,
                             holding=rule.holding if rule.plastic else None,
                             plastic_starts=rule.starts)
    said = rule.unresolved_notes(result.n_contacts, stacklevel=4)
    return dataclasses.replace(result, notes=result.notes + said) if said else result
