"""Output points: each solver's way to the motion of a body's other points.

Every output is the displacement of its point along the body's contact axis ``y`` (method.md),
so the force on body 1 is ``-f`` and on body 2 ``+f`` (plus any load).

* Laplace (exact): the output rows ``C X + d f`` of the multi-output model, rewritten on the
  driving row's states, are added to each phase's output rows; their first and second
  derivatives are the rows times the phase matrix ``M`` (``Xa' = M Xa`` in every phase),
  so velocities and accelerations come from the same closed forms, exact to rounding.
* Modal stepping: the complex modal states are shared by all outputs: O(outputs x modes)
  per step, exact for the piecewise-constant force.
* Convolution: displacement = the force (load included) convolved with the transfer
  step-response increments; velocity = with the transfer impulse-response increments
  (exact for a piecewise-constant force: the velocity step response is ``h``); acceleration
  = backward differences of the velocity samples.
"""

from __future__ import annotations

import numpy as np

from modalid import MultiOutputModalModel

from ..points import PointResponse
from ._stepping import causal_convolve

__all__ = ["LaplaceOutputs", "ModalOutputs", "convolution_points", "free_point_motion",
           "has_outputs"]

#: left limits of impulse responses at grid times are sampled this fraction of a step early
_LEFT = 1e-7
#: tolerance (relative to T/m) of a beam's impulse-response series for the velocities: its
#: default (1e-6) needs 4e5 modes, 15 ms per sample; 1e-4 needs 4053 modes
_BEAM_IMPULSE_RTOL = 1e-4


def has_outputs(bodies) -> bool:
    """True when a body asks for output points."""
    return any(b.outputs is not None for b in bodies)


def _sign(index):
    return -1.0 if index == 0 else 1.0


def _rigid_ratio(body) -> np.ndarray:
    """Rigid displacement of each output per unit rigid displacement of the driving point."""
    inv_d = body.inverse_mass
    if isinstance(body.outputs, MultiOutputModalModel):
        inv = body.outputs.inverse_mass
        return inv / inv_d if inv_d else np.zeros_like(inv)
    return np.full(len(body.outputs), 1.0 if inv_d else 0.0)  # a rod translates as a whole


def _statespace_rows(body, model):
    """``(C, d)`` of the outputs on the states of the driving row's state space.

    The driving row's rigid states are the displacement (m) and velocity (m/s) (``b = [0,
    1/M]``); the multi-output rigid states are per unit ``1/M``: output ``i``'s rigid row on
    the driving states is ``[inverse_mass_i / inverse_mass, 0]``.
    """
    _, _, C, d = body.outputs.statespace_matrices()
    C = np.array(C, dtype=float)
    if model.inverse_mass:
        C[:, -2] = _rigid_ratio(body)
        C[:, -1] = 0.0
    if C.shape[1] != model.order:
        raise ValueError(f"the multi-output model's states ({C.shape[1]}) do not match its "
                         f"driving row's ({model.order})")
    return C, np.asarray(d, dtype=float)


def _require_multi(bodies, solver):
    for i, body in enumerate(bodies):
        if body.outputs is not None and not isinstance(body.outputs, MultiOutputModalModel):
            raise ValueError(f"body{i + 1}'s output positions need its exact transfer responses: "
                             f"use method='convolution' (the {solver} solver takes output "
                             "points from a MultiOutputModalModel)")


class LaplaceOutputs:
    """Output rows of both bodies for the exact solver's phases."""

    def __init__(self, bodies, sysm):
        _require_multi(bodies, "laplace")
        self.n = sysm.n
        self.blocks = []  # (body index, C on all states, d, sign)
        for i, body in enumerate(bodies):
            if body.outputs is None:
                continue
            C, d = _statespace_rows(body, sysm.models[i])
            full = np.zeros((C.shape[0], sysm.n))
            offset = 0 if i == 0 else sysm.n1
            full[:, offset:offset + C.shape[1]] = C
            self.blocks.append((i, full, d, _sign(i)))

    @property
    def n_rows(self) -> int:
        return sum(3 * full.shape[0] for _, full, _, _ in self.blocks)

    def row_units(self, length, time):
        """The unit of each of :meth:`rows`' rows, per body: ``length`` (m) for the
        displacements, ``length / time`` for the velocities, ``length / time^2`` for the
        accelerations (the exact solver's dimensionless form)."""
        units = [np.repeat([length, length / time, length / (time * time)], full.shape[0])
                 for _, full, _, _ in self.blocks]
        return np.concatenate(units) if units else np.zeros(0)

    def rows(self, M, force_row=None, *, loads=()):
        """Displacement, velocity and acceleration rows (per body) on the augmented state
        ``[X, 1, J, cos, sin of each load]``: ``C X + d (sign f + F_i)``, with ``loads``
        the ``(body index, HarmonicForce)`` pairs of those cosines."""
        n_aug = M.shape[0]
        out = []
        for i, full, d, sign in self.blocks:
            disp = np.zeros((full.shape[0], n_aug))
            disp[:, :self.n] = full
            if force_row is not None:
                disp += sign * d[:, None] * force_row[None, :]
            for k, (j, load) in enumerate(loads):
                if j == i:
                    disp[:, self.n + 2 + 2 * k] += d * load.amplitude
            vel = disp @ M
            out += [disp, vel, vel @ M]
        return np.vstack(out) if out else np.zeros((0, n_aug))

    def responses(self, bodies, T, V):
        """One :class:`PointResponse` (or None) per body from the extra output rows ``V``."""
        points = [None, None]
        row = 0
        note = ("exact (Laplace/state-space) closed forms; at event times both one-sided "
                "limits are sampled; Dirac parts of velocity/acceleration are not in the samples")
        for i, full, _, _ in self.blocks:
            k = full.shape[0]
            disp, vel, acc = (V[row + j * k: row + (j + 1) * k] for j in range(3))
            row += 3 * k
            points[i] = PointResponse(bodies[i].output_labels, T, disp, vel, acc, note)
        return tuple(points)


class ModalOutputs:
    """Records one body's outputs in the modal time-stepping loop (left limits at ``t_n``)."""

    def __init__(self, body, model, n_times, dt):
        multi = body.outputs
        self.dt = dt
        self.flex = np.asarray(multi.flexibility, dtype=float)
        self.u_prev = self.u_prev2 = 0.0
        p = np.concatenate([model.poles, model.real_poles.astype(complex)])
        W = np.concatenate([2.0 * multi.residues, multi.real_residues.astype(complex)], axis=1)
        k = W.shape[0]
        self.k = k
        self.stack = np.vstack([W, W * p, W * p**2])                  # (3k, modes)
        ratio = _rigid_ratio(body)
        # u terms: displacement flexibility; velocity Re sum W; acceleration Re sum W p + 1/M_i
        self.u_coef = np.concatenate([multi.flexibility, W.sum(axis=1).real,
                                      (W * p).sum(axis=1).real + multi.inverse_mass])
        self.h0 = W.sum(axis=1).real       # h(0+): its f' term in the acceleration
        self.d_coef = np.concatenate([ratio, np.zeros(2 * k)])
        self.v_coef = np.concatenate([np.zeros(k), ratio, np.zeros(k)])
        self.values = np.empty((3 * k, n_times))

    def record(self, j, z, d, v, u):
        """Sample ``j`` from the modal states ``z``, rigid ``d``, ``v`` and the force ``u``."""
        values = self.values[:, j]
        values[:] = (self.stack @ z).real + self.u_coef * u + self.d_coef * d + self.v_coef * v
        if u != self.u_prev or self.u_prev != self.u_prev2:
            k, h = self.k, self.dt
            # flexibility d f', d f'' and h(0+) f' are Diracs for a piecewise-constant
            # force; spread over the step as backward differences
            values[k:2 * k] += self.flex * ((u - self.u_prev) / h)
            values[2 * k:] += (self.flex * ((u - 2 * self.u_prev + self.u_prev2) / h**2)
                               + self.h0 * ((u - self.u_prev) / h))
        self.u_prev2, self.u_prev = self.u_prev, u

    def response(self, body, t):
        k = self.k
        note = ("modal time stepping: exact for the piecewise-constant force; left limits at "
                "t_n (the force of step n-1 acting); the terms d f' (velocity), d f'' and "
                "h(0+) f' (acceleration) use backward differences of the force (first order)")
        return PointResponse(body.output_labels, t, self.values[:k], self.values[k:2 * k],
                             self.values[2 * k:], note)


def free_point_motion(body, t):
    """Outputs' displacement, velocity, acceleration with no force: rigid motion and vibration.

    Arrays of shape (n_points, len(t)).
    """
    t = np.asarray(t, dtype=float)
    ratio = _rigid_ratio(body)[:, None]
    disp = ratio * (body.displacement + body.velocity * t)[None, :]
    vel = ratio * np.full(t.shape, body.velocity)[None, :]
    acc = np.zeros_like(disp)
    states = body.initial_modal_states()
    if states is not None:
        p, _, z0 = states
        r = _vibration_residues(body, p)                       # (n_points, n_vib)
        e = z0[:, None] * np.exp(np.outer(p, t))              # (n_vib, n_t)
        disp = disp + 2.0 * (r @ e).real
        vel = vel + 2.0 * ((r * p) @ e).real
        acc = acc + 2.0 * ((r * p**2) @ e).real
    return disp, vel, acc


def _vibration_residues(body, poles):
    """Each output's residues at the vibration modes' ``poles`` (matched by value)."""
    multi = body.outputs
    if isinstance(multi, MultiOutputModalModel):
        residues = multi.residues
    else:                       # a Rod or CantileverBeam with positions xi
        xi = np.asarray(body.outputs)
        rows = np.arange(xi.size)
        if not np.any(xi == 0.0):  # the model wants the driving point among its outputs
            xi, rows = np.concatenate([[0.0], xi]), rows + 1
        multi = body.model.multi_output_model(xi, poles.size)
        residues = multi.residues[rows]
    distance = np.abs(multi.poles[None, :] - poles[:, None])
    index = np.argmin(distance, axis=1)
    if np.any(distance[np.arange(poles.size), index] > 1e-9 * np.abs(poles)):
        raise ValueError("the output model's poles do not match the vibration modes")
    return residues[:, index]


def _transfer_responses(body, t, dt):
    """Outputs' step responses at ``t`` and impulse responses just before ``t`` (s).

    The impulse responses of continua jump where waves arrive, often on grid times: they
    are sampled ``1e-7`` of a step early, i.e. as left limits.
    """
    if isinstance(body.outputs, MultiOutputModalModel):
        multi = body.outputs
        return multi.step_response(t), multi.impulse_response(t)
    xi = np.asarray(body.outputs)
    model = body.model
    step = np.asarray(model.transfer_step_response(t, xi), dtype=float)
    options = {"rtol": _BEAM_IMPULSE_RTOL} if hasattr(model, "impulse_error_bound") else {}
    impulse = np.asarray(model.transfer_impulse_response(t - _LEFT * dt, xi, **options),
                         dtype=float)
    return step, impulse


def convolution_points(bodies, grid, force):
    """Output points of a piecewise-constant force history (time-stepping solvers).

    Returns one :class:`PointResponse` (or None) per body, sampled on ``grid.t`` as left
    limits, like ``y1``, ``y2``.
    """
    points = [None, None]
    t = grid.t
    dt = grid.dt
    note = ("convolution of the piecewise-constant force with the exact transfer step "
            "responses (displacement) and impulse responses (velocity: exact for that force, "
            "but a flexibility term's d f' is a backward difference of the force); "
            "left limits at t_n; acceleration = backward differences of the velocity samples "
            "(the velocity jumps where the force does: expect step-size-dependent peaks)")
    for i, body in enumerate(bodies):
        if body.outputs is None:
            continue
        u = body.load_samples(grid.midpoints) + _sign(i) * force
        step, impulse = _transfer_responses(body, t[1:], dt)
        d_step = np.diff(step, axis=1, prepend=0.0)
        d_imp = np.diff(impulse, axis=1, prepend=0.0)
        disp, vel, acc = free_point_motion(body, t)
        disp = disp + np.stack([causal_convolve(u, row) for row in d_step])
        vel = vel + np.stack([causal_convolve(u, row) for row in d_imp])
        if isinstance(body.outputs, MultiOutputModalModel):
            # flexibility: d f' is a Dirac train for a piecewise-constant force; spread
            # over the step as a backward difference
            flex = np.asarray(body.outputs.flexibility, dtype=float)
            vel[:, 1:] += flex[:, None] * (np.diff(u, prepend=0.0) / dt)[None, :]
        acc = acc.copy()
        acc[:, 1:] = np.diff(vel, axis=1) / dt
        extra = ""
        if hasattr(body.model, "impulse_error_bound"):
            extra = (f"; the impulse-response series is truncated at {_BEAM_IMPULSE_RTOL:g} T/m "
                     "(uniform bound): velocity error <= that times the force's total variation")
        points[i] = PointResponse(body.output_labels, t, disp, vel, acc, note + extra)
    return tuple(points)
