"""The paper's time-domain form, for any kernel: exact continua, modal models, samples.

While the force is piecewise constant, the gap at the end of step ``n`` is

    g_{n+1} = g_free(t_{n+1}) + sum_{j<n} f_j K[n-j] + K[0] f_n,   K = dS1 + dS2,

so each step is one scalar complementarity problem (:meth:`ContactLaw.step_force`; a
``Rigid`` contact between bodies that are masses at the contact takes a plastic impulse
at its start, :class:`._step_force.StepForce`).
The history sum is computed online by divide and conquer: once the forces of the first
half of a block are known, their effect on the second half is one FFT convolution. The
cost is O(N log^2 N) for N steps, with a Python loop over steps whose body is O(block).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.signal import fftconvolve

from ..parallel import progress_bar
from ._outputs import convolution_points
from ._step_force import StepForce, backward_gap, kernel_ratio, rounding_gap
from ._stepping import Grid, assemble_result, free_displacements, step_kernel

__all__ = ["solve_convolution", "online_complementarity"]

_BLOCK = 32


def online_complementarity(kernel, free_gap, law, dt, gap_start, *, gap_tolerance=0.0,
                           bar=None):
    """Forces ``f_n`` (N), ``n = 0..N-1``, of the discrete contact problem.

    Parameters
    ----------
    kernel : ndarray, shape (N,)
        ``K[k]`` (m/N), ``K[0] > 0``.
    free_gap : ndarray, shape (N,)
        Gap (m) at ``t_{n+1}`` without any contact force.
    law : ContactLaw or StepForce
        The contact law, or the :class:`._step_force.StepForce` built for it (its
        ``force`` gives ``f_n``). Made here from ``kernel`` and ``gap_tolerance`` when a
        law is given, which checks the kernel's ratio at the step only: the bodies'
        small-time ratio (:func:`._step_force.kernel_ratio`) needs their step responses,
        as :func:`solve_convolution` passes them.
    dt : float
        Step (s).
    gap_start : float
        Gap at ``t_0`` (m).
    gap_tolerance : float, keyword-only
        Rounding level of the gaps (m) of the ``StepForce`` made here (a given one keeps
        its own).
    bar : tqdm.tqdm or None, keyword-only
        Advanced by the steps solved (``impactpred.parallel.progress_bar``).
    """
    n_total = free_gap.size
    force = np.zeros(n_total)
    history = np.zeros(n_total)
    k0 = float(kernel[0])
    reversed_kernel = kernel[::-1].copy()
    if not isinstance(law, StepForce):
        law = StepForce(law, k0, float(kernel[1]) if n_total > 1 else 0.0, dt,
                        gap_tolerance=gap_tolerance)
    step_force = law.force
    g_prev = gap_start
    g_before = backward_gap(gap_start, free_gap[0], free_gap[1] if n_total > 1 else None)

    def solve_block(lo, hi):
        nonlocal g_prev, g_before
        for n in range(lo, hi):
            inner = 0.0
            if n > lo:
                # sum_{j=lo}^{n-1} f_j K[n-j]
                inner = float(np.dot(force[lo:n], reversed_kernel[n_total - (n - lo) - 1:
                                                                  n_total - 1]))
            g_free = free_gap[n] + history[n] + inner
            f = step_force(g_free, g_prev, g_before)
            force[n] = f
            g_before, g_prev = g_prev, g_free + k0 * f
        if bar is not None:
            bar.update(hi - lo)

    def recurse(lo, hi):
        if hi - lo <= _BLOCK:
            solve_block(lo, hi)
            return
        mid = (lo + hi) // 2
        recurse(lo, mid)
        part = force[lo:mid]
        if np.any(part):
            size = hi - lo
            conv = (fftconvolve(part, kernel[:size]) if size > 256
                    else np.convolve(part, kernel[:size]))
            history[mid:hi] += conv[mid - lo:hi - lo]
        recurse(mid, hi)

    recurse(0, n_total)
    return force


def solve_convolution(bodies, gap0, contact, t_end, dt, *, notes=(), progress=False):
    """Time-stepping solve with exact step-response kernels; see the module docstring
    (``progress``: a bar on stderr over the steps)."""
    grid = Grid(t_end, dt)
    kernels = tuple(step_kernel(b, grid) for b in bodies)
    y_free = tuple(free_displacements(b, grid, k) for b, k in zip(bodies, kernels))
    free_gap = y_free[1] - y_free[0] + gap0
    kernel = kernels[0] + kernels[1]
    _, small_time = kernel_ratio([b.step_response for b in bodies], dt)
    rule = StepForce(contact, kernel[0], kernel[1] if kernel.size > 1 else 0.0, dt,
                     small_time_ratio=small_time, gap_tolerance=rounding_gap(*y_free))
    with progress_bar(free_gap.size - 1, enabled=progress, desc="convolution",
                      unit="step") as bar:
        force = online_complementarity(kernel, free_gap[1:], rule, dt, float(free_gap[0]),
                                       bar=bar)
    result = assemble_result(bodies, gap0, grid, force, kernels, y_free,
                             method="convolution", notes=notes,
                             points=convolution_points(bodies, grid, force),
                             holding=rule.holding if rule.plastic else None,
                             plastic_starts=rule.starts)
    said = rule.unresolved_notes(result.n_contacts, stacklevel=3)
    return dataclasses.replace(result, notes=result.notes + said) if said else result
