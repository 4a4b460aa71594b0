"""Time stepping with the exact discretisation of every mode (zero-order hold).

For a force constant over the step ``[t_n, t_n + dt)``, each complex mode
(``z' = p z + u``, contribution ``2 Re(r z)``) and real pole advances exactly:

    z_{n+1} = exp(p dt) z_n + (exp(p dt) - 1)/p u_n,

the rigid body as ``d += v dt + u dt^2/(2M)``, ``v += u dt/M``. The contact force of each
step solves the same scalar complementarity problem as the convolution solver, so the
two agree to rounding on the same model; this one carries the history in O(modes)
state per step instead of an FFT convolution. Cost: O(steps x modes).
"""

from __future__ import annotations

import numpy as np

from ._outputs import ModalOutputs, _require_multi
from ._stepping import Grid, assemble_result

__all__ = ["solve_modal"]


class _ModalStepper:
    """Exact one-step maps of one body's modal model, stacked as complex vectors."""

    def __init__(self, model, dt):
        p = np.concatenate([model.poles, model.real_poles.astype(complex)])
        weight = np.concatenate([2.0 * model.residues, model.real_residues.astype(complex)])
        self.E = np.exp(p * dt)
        self.G = np.expm1(p * dt) / p
        self.weight = weight
        self.inverse_mass = model.inverse_mass
        self.flexibility = model.flexibility
        self.dt = dt

    def output(self, z, d):
        return float(np.dot(self.weight, z).real) + d


def solve_modal(bodies, gap0, contact, t_end, dt, *, notes=()):
    """Modal time-stepping solve of two bodies with rational (or truncated) models."""
    _require_multi(bodies, "modal")
    grid = Grid(t_end, dt)
    models = [b.modal_model() for b in bodies]
    steppers = [_ModalStepper(m, dt) for m in models]
    # only the first step-response increment enters the stepping: S(dt) of each body
    first = [float(m.step_response([dt])[0]) for m in models]
    if not all(x > 0 for x in first):
        raise ValueError(f"the step responses over the first step are {first} m/N, not "
                         "positive: not driving points")
    k0 = first[0] + first[1]
    loads = [b.load_samples(grid.midpoints) for b in bodies]

    # initial modal states of the vibration, in each model's own mode order
    z = []
    for body, model in zip(bodies, models):
        zi = np.zeros(model.n_modes + model.real_poles.size, dtype=complex)
        states = body.initial_modal_states()
        if states is not None:
            order = np.argsort(np.abs(model.poles), kind="stable")[:body.vibration.shape[0]]
            zi[order] = states[2]
        z.append(zi)
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
    law = contact.step_force
    z1, z2 = z
    rec1, rec2 = (ModalOutputs(b, m, grid.n_steps + 1, dt) if b.outputs is not None else None
                  for b, m in zip(bodies, models))
    if rec1:
        rec1.record(0, z1, d[0], v[0], 0.0)
    if rec2:
        rec2.record(0, z2, d[1], v[1], 0.0)
    for n in range(grid.n_steps):
        u1, u2 = loads[0][n], loads[1][n]
        # the end-of-step state at zero contact force
        z1f = E1 * z1 + G1 * u1
        z2f = E2 * z2 + G2 * u2
        d1f = d[0] + v[0] * h + m1 * h2 * u1
        d2f = d[1] + v[1] * h + m2 * h2 * u2
        y1f = float(np.dot(w1, z1f).real) + d1f + s1.flexibility * u1
        y2f = float(np.dot(w2, z2f).real) + d2f + s2.flexibility * u2
        G = y2f - y1f + gap0
        f = law(G, k0, g_prev, h)
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
        g_prev = y2[n + 1] - y1[n + 1] + gap0
        if rec1:
            rec1.record(n + 1, z1, d[0], v[0], u1 - f)
        if rec2:
            rec2.record(n + 1, z2, d[1], v[1], u2 + f)
    points = tuple(r.response(b, grid.t) if r else None for r, b in zip((rec1, rec2), bodies))
    return assemble_result(bodies, gap0, grid, force, None, None, method="modal",
                           notes=notes, y=(y1, y2), points=points)
