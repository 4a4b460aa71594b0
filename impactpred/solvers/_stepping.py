"""What the time-stepping solvers share: the grid, the discrete kernels, the free motion,
and turning a piecewise-constant force history into an :class:`ImpactResult`.

Discretisation (paper's time-domain form): the force is constant, ``f_n``, on each step
``[t_n, t_n+1)``, ``t_n = n dt``. A body's displacement at ``t_n`` is then exactly

    y(t_n) = y_free(t_n) -/+ sum_{j<n} f_j dS[n-1-j],
    dS[0] = S(dt),  dS[k] = S((k+1) dt) - S(k dt)

with ``S`` the exact step response (left limit ``S(0-) = 0``, so a flexibility term is
in ``dS[0]``). ``dS[0] > 0`` for any driving point: no division by ``h(0) = 0``.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import fftconvolve

from ..result import BodyEnergy, ImpactResult

__all__ = ["Grid", "step_kernel", "free_displacements", "assemble_result", "causal_convolve",
           "energy_before", "split_diracs"]


class Grid:
    """Uniform time grid ``t_n = n dt``, ``n = 0..n_steps`` (s)."""

    def __init__(self, t_end: float, dt: float):
        self.n_steps = max(1, int(np.ceil(t_end / dt - 1e-9)))
        self.dt = dt
        self.t = dt * np.arange(self.n_steps + 1)

    @property
    def midpoints(self) -> np.ndarray:
        return self.t[:-1] + 0.5 * self.dt


def step_kernel(body, grid: Grid) -> np.ndarray:
    """``dS[k]``, ``k = 0..n_steps-1`` (m/N): step-response increments of ``body``."""
    s = body.step_response(grid.t[1:])
    kernel = np.diff(s, prepend=0.0)
    if not kernel[0] > 0:
        raise ValueError(f"the step response of {type(body.model).__name__} over the first "
                         f"step (dt = {grid.dt:.6g} s) is {float(kernel[0])!r} m/N, not "
                         "positive: not a driving point, or a step far too long for it (a "
                         "rod's step response returns to 0 at its period; choose_dt gives "
                         "the step that resolves it)")
    return kernel


def causal_convolve(force: np.ndarray, kernel: np.ndarray) -> np.ndarray:
    """``out[n] = sum_{j<n} force[j] kernel[n-1-j]`` for ``n = 0..len(force)`` (out[0] = 0)."""
    n = force.size
    conv = fftconvolve(force, kernel[:n])[:n] if n > 64 else np.convolve(force, kernel[:n])[:n]
    return np.concatenate([[0.0], conv])


def free_displacements(body, grid: Grid, kernel: np.ndarray) -> np.ndarray:
    """Displacement (m) on the grid with no contact: rigid motion, vibration, load response.

    The load is held at its step-midpoint value on each step (second-order accurate).
    """
    y = body.free_motion(grid.t)
    if body.load is not None:
        y = y + causal_convolve(body.load_samples(grid.midpoints), kernel)
    return y


def energy_before(body) -> float:
    """A body's vibration energy (J) at ``t = 0``: its modes', and the strain energy
    ``D F(0)^2 / 2`` its load holds there in a flexibility term ``D`` (the exact method's
    count, :meth:`impactpred.solvers.laplace.CoupledSystem.energies`; the bodies do not
    touch before ``t = 0``; :meth:`impactpred.Body.load_direct_term`)."""
    d, force = body.load_direct_term()
    return body.vibration_energy() + 0.5 * d * force ** 2


def micro_separation_tolerance(y1, y2) -> float:
    """Gap (m) below which an opening is rounding, not a separation."""
    return 1e-10 * max(float(np.max(np.abs(y1))), float(np.max(np.abs(y2))), 1e-300)


def contact_runs(force: np.ndarray, gap_end: np.ndarray, tol: float, *, holding=None):
    """Index ranges ``[start, stop)`` of steps in contact, merging rounding-level openings.

    A step belongs to a contact when its force exceeds ``1e-10`` of the peak (the rest
    is rounding in the history sums: touching without pressing is not contact), or, with
    ``holding`` (bool per step, :class:`._step_force.StepForce`'s plastic rule), when the
    rule held it. Two runs separated by steps whose end-of-step gap never exceeds ``tol``
    are one contact: such an "opening" is rounding, not a separation (method.md, section
    5); with ``holding`` it is measured from the gap the last contact held, not from 0.
    """
    if holding is None:
        active = force > 1e-10 * float(np.max(force, initial=0.0))
    else:
        active = np.asarray(holding, dtype=bool)
    if not np.any(active):
        return []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], active.astype(np.int8), [0]])))
    runs = list(zip(edges[::2], edges[1::2]))
    merged = [list(runs[0])]
    for start, stop in runs[1:]:
        prev_stop = merged[-1][1]
        touch = gap_end[prev_stop - 1] if holding is not None else 0.0
        if np.all(gap_end[prev_stop:start] - touch <= tol):
            merged[-1][1] = stop
        else:
            merged.append([start, stop])
    return [tuple(r) for r in merged]


def split_diracs(force, grid: Grid, starts, holding):
    """The steps that took a plastic impulse as Dirac impulses, and the regular force.

    A step ``n`` in ``starts`` (:class:`._step_force.StepForce`'s plastic starts) carries
    the impulse ``f_n dt`` that stops the bodies' relative motion within it: reported as
    a force ``f_n`` it grows like ``1/dt`` (the exact force has a Dirac there, method.md,
    section 5). Its regular part is the next step's force while the contact holds (the
    press the Dirac leaves, to first order in ``dt``), else 0; the rest is a Dirac impulse
    at ``t_n`` (none where nothing is left: a step too fine to resolve the hold). The
    force's integral is unchanged.

    Returns
    -------
    regular : ndarray, shape (n_steps,)
        The force (N) without the Dirac parts.
    diracs : tuple of (float, float)
        (time s, impulse N s) of each Dirac part.
    """
    regular = np.array(force, dtype=float)
    diracs = []
    for n in starts:
        held = n + 1 < regular.size and holding is not None and holding[n + 1]
        part = min(max(float(force[n + 1]), 0.0), float(force[n])) if held else 0.0
        if part < force[n]:          # a start at a step too fine to resolve may take none
            regular[n] = part
            diracs.append((float(grid.t[n]), (float(force[n]) - part) * grid.dt))
    return regular, tuple(diracs)


def assemble_result(bodies, gap0, grid: Grid, force, kernels, y_free, *, method, notes=(),
                    y=None, points=(None, None), holding=None, plastic_starts=()):
    """Build the :class:`ImpactResult` of a piecewise-constant force history.

    Parameters
    ----------
    force : ndarray, shape (n_steps,)
        ``f_n`` (N) on each step.
    kernels, y_free : pairs of ndarray
        Step kernels and free displacements of the two bodies.
    y : pair of ndarray, optional
        Displacements on the grid if the solver already has them.
    points : pair of (PointResponse or None), optional
        Output points, if the solver computed them.
    holding : sequence of bool or None, keyword-only
        Per step, whether :class:`._step_force.StepForce`'s plastic rule held a contact
        (:func:`contact_runs`); None: the contact law's own steps.
    plastic_starts : sequence of int, keyword-only
        The steps that took a plastic impulse (:func:`split_diracs`): reported in
        ``dirac_impulses``, not in ``force``.
    """
    b1, b2 = bodies
    if y is None:
        y1 = y_free[0] - causal_convolve(force, kernels[0])
        y2 = y_free[1] + causal_convolve(force, kernels[1])
    else:
        y1, y2 = y
    gap = y2 - y1 + gap0
    runs = contact_runs(force, gap[1:], micro_separation_tolerance(y1, y2), holding=holding)
    dt = grid.dt
    regular, diracs = split_diracs(force, grid, plastic_starts, holding)
    # a contact that is its plastic start alone is a pure Dirac: start == end, as exact
    # (not one on the last step, which may go on after t_end: in contact at the end)
    alone = {a for a, b in runs
             if b == a + 1 < force.size and regular[a] == 0.0} & set(plastic_starts)
    intervals = tuple((float(grid.t[a]), float(grid.t[a if a in alone else b]))
                      for a, b in runs)
    total_impulse = float(np.sum(force) * dt)
    first_impulse = float(np.sum(force[runs[0][0]:runs[0][1]]) * dt) if runs else 0.0

    inv = (b1.inverse_mass, b2.inverse_mass)
    u_before = (b1.velocity, b2.velocity)
    loads = [b.load_samples(grid.midpoints) for b in bodies]  # zeros without a load
    load_impulse = [float(np.sum(load) * dt) for load in loads]
    u_after = (u_before[0] + inv[0] * (load_impulse[0] - total_impulse),
               u_before[1] + inv[1] * (load_impulse[1] + total_impulse))
    energies = []
    for i, (body, yi, sign) in enumerate(((b1, y1, -1.0), (b2, y2, 1.0))):
        dy = np.diff(yi)
        work = sign * float(np.dot(force, dy)) + float(np.dot(loads[i], dy))
        rigid_before = 0.5 * u_before[i] ** 2 / inv[i] if inv[i] > 0 else 0.0
        rigid_after = 0.5 * u_after[i] ** 2 / inv[i] if inv[i] > 0 else 0.0
        vib_before = energy_before(body)
        energies.append(BodyEnergy(rigid_before, vib_before, rigid_after,
                                   vib_before + work - (rigid_after - rigid_before)))
    force_out = np.append(regular, regular[-1])
    return ImpactResult(t=grid.t, force=force_out, y1=y1, y2=y2, gap=gap,
                        contact_intervals=intervals, dirac_impulses=diracs,
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=tuple(energies), method=method, dt=dt,
                        first_contact_impulse=first_impulse, total_impulse=total_impulse,
                        inverse_masses=inv, notes=tuple(notes), points=tuple(points))
