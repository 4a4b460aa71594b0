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

import warnings

import numpy as np
from scipy.signal import fftconvolve

from ..result import BodyEnergy, ImpactResult

__all__ = ["Grid", "step_kernel", "free_displacements", "assemble_result", "causal_convolve",
           "energy_before"]


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
                         f"step is {kernel[0]!r} m/N, not positive: not a driving point")
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


#: ``dS[1]/dS[0]`` of the pair's summed kernel above which a step sees the bodies as
#: masses at the contact: a pure mass gives 3 (``S = t^2/2m``), a wave impedance
#: (``h(0+) > 0``, a rod) 1, a beam's ``h ~ sqrt(t)`` 1.83, a flexibility term about 0
MASS_LIKE_RATIO = 2.5


class StepForce:
    """The contact force of each step of the zero-order-hold solvers.

    ``force(G, g_prev, g_before)`` gives ``f_n`` (N) from the gap ``G`` (m) the step
    would end with at no force, the gap ``g_prev`` at its start and ``g_before`` one step
    earlier; the law's own :meth:`~impactpred.contact.ContactLaw.step_force` does it,
    except for ``Rigid`` contact between bodies that are masses at the contact at this
    step (``dS[1] > MASS_LIKE_RATIO dS[0]``: ``h1(0+) + h2(0+) = 0``, two lumped masses,
    a truncated modal model resolved by the step).

    There the exact force starts with a plastic Dirac impulse (method.md, sections 1 and
    5: undamped bodies lose energy at the Dirac parts only), and the law's
    ``f = -G/K0``, which closes the gap within the step, sends the bodies apart at about
    the speed they met (a constant force that stops a mass within a step sends it back):
    a rebound of restitution up to 1. The step of such a contact's start takes the
    plastic impulse instead, the force that zeroes the relative velocity at the step's
    end: ``f = -v/S'(dt)``, with ``v`` the force-free end velocity from the last three
    gaps, ``(3 G - 4 g_prev + g_before)/(2 dt)`` (exact under a constant acceleration),
    and ``S'(dt) = (5 dS[0] + dS[1])/(4 dt)`` the velocity a unit force gives over the
    step (exact for ``S = a t^2 + b t^3``; ``2 dS[0]/dt`` for masses). The gap it ends
    with, about half a step's travel inside, is held while the contact presses
    (``f = (g_held - G)/K0``, the law's rule about the held gap: the bodies stick where
    they met); they part when holding them would pull, and touch again where they parted
    (a short separation's return is timed by the relative motion, not by the offset,
    which each contact moves by less than half a step's travel, either way). A contact
    that starts at rest gets the law's force (the two rules agree there). First order in
    ``dt``, like the zero-order hold at every event.

    Parameters
    ----------
    contact : ContactLaw
    k0, k1 : float
        ``dS[0]``, ``dS[1]`` of the pair's summed kernel (m/N).
    dt : float
        Step (s).
    gap_tolerance : float, keyword-only
        Gap (m) below which a plastic contact's press or approach is rounding (the
        history sums' error in the difference of two displacements): after a plastic
        impact of two free masses the force needed is 0, and rounding must not keep them
        "in contact" or start another impact (:func:`rounding_gap`).
    """

    def __init__(self, contact, k0: float, k1: float, dt: float, *, gap_tolerance=0.0):
        from ..contact import Rigid

        self.k0, self.dt, self._law = float(k0), float(dt), contact
        self.plastic = type(contact) is Rigid and k1 > MASS_LIKE_RATIO * k0
        # the velocity per unit force over a step, as a gap change: S'(dt) dt/2 (m/N)
        self._k_velocity = (5.0 * k0 + k1) / 8.0
        self.gap_tolerance = float(gap_tolerance)
        self._held: float | None = None    # the gap held while a plastic contact presses
        self._touch = 0.0              # the gap at which the bodies touch: where they parted
        self.impacts = 0               # plastic starts (re-touches within a contact too)

    def force(self, G: float, g_prev: float, g_before: float) -> float:
        """``f_n`` (N) of the next step; see the class docstring."""
        if not self.plastic:
            return self._law.step_force(G, self.k0, g_prev, self.dt)
        tol = self.gap_tolerance
        if self._held is not None:
            press = self._held - G
            if press > tol:
                return press / self.k0
            self._touch, self._held = self._held, None    # holding would pull: they part
            return 0.0
        if G >= self._touch:
            return 0.0
        # -v dt/2 with v the force-free end velocity: what the impulse must take away
        approach = -(3.0 * G - 4.0 * g_prev + g_before) / 4.0
        if approach <= tol:             # inside, but not closing at the step's end
            return 0.0
        f = approach / self._k_velocity
        self._held = G + self.k0 * f
        self.impacts += 1
        return f

    def unresolved_notes(self, n_contacts: int) -> tuple:
        """``(message,)`` when the plastic holds parted and touched again on rounding
        (also warned, ``RuntimeWarning``), else ``()``.

        A hold resolves a force only to ``gap_tolerance / K0`` (N): ``K0`` falls like
        ``dt^2`` for masses, the gaps' rounding does not. Below that the bodies part and
        touch again within what the result reports as one contact (its openings stay
        within rounding of the held gap); more than ``2 n_contacts + 10`` plastic starts
        for ``n_contacts`` contacts says so (a mass pressed by a 1 N spring over 10^5
        steps of 0.2 us: the convolution solver's sums resolve 0.3 N, 565 starts).
        """
        if not self.plastic or self.impacts <= 2 * n_contacts + 10:
            return ()
        said = (f"dt={self.dt:.3g} s is too fine for a rigid contact between masses: the "
                f"step resolves the contact force to {self.gap_tolerance / self.k0:.3g} N "
                f"only (the gaps' rounding over the step's {self.k0:.3g} m/N; the bodies "
                f"touched {self.impacts} times in {n_contacts} contacts): use a coarser "
                "dt (dt=None picks one) or method='laplace'")
        warnings.warn(said, RuntimeWarning, stacklevel=4)
        return (said,)


def backward_gap(gap0: float, free1: float, free2: float) -> float:
    """The gap one step before ``t_0`` (m) on the quadratic through the force-free gaps
    at ``t_0, t_1, t_2``: :class:`StepForce`'s ``g_before`` at the first step."""
    return 3.0 * gap0 - 3.0 * free1 + free2


def energy_before(body) -> float:
    """A body's vibration energy (J) at ``t = 0``: its modes', and the strain energy
    ``D F(0)^2 / 2`` its load holds there in a flexibility term ``D`` (the exact method's
    count, :meth:`impactpred.solvers.laplace.CoupledSystem.energies`; the bodies do not
    touch before ``t = 0``). A rational body's ``D`` only: a continuum's response has no
    instantaneous term."""
    energy = body.vibration_energy()
    if body.load is not None and body.is_rational:
        force = float(body.load_samples(np.zeros(1))[0])
        energy += 0.5 * body.modal_model().flexibility * force ** 2
    return energy


def rounding_gap(y1, y2) -> float:
    """Gap (m) within which a step's predicted gap is rounding: ``1e-12`` of the largest
    displacement (the FFT history sums of the convolution solver err by up to about
    ``1e-12`` of it after a plastic impact; a contact's own press one step after its
    impact is 1e-11 of it and more on the test cases). :class:`StepForce`'s tolerance."""
    return 1e-12 * max(float(np.max(np.abs(y1))), float(np.max(np.abs(y2))), 1e-300)


def micro_separation_tolerance(y1, y2) -> float:
    """Gap (m) below which an opening is rounding, not a separation."""
    return 1e-10 * max(float(np.max(np.abs(y1))), float(np.max(np.abs(y2))), 1e-300)


def contact_runs(force: np.ndarray, gap_end: np.ndarray, tol: float, *, held=False):
    """Index ranges ``[start, stop)`` of steps in contact, merging rounding-level openings.

    A step belongs to a contact when its force exceeds ``1e-10`` of the peak (the rest
    is rounding in the history sums: touching without pressing is not contact). Two runs
    separated by steps whose end-of-step gap never exceeds ``tol`` are one contact: such
    an "opening" is rounding, not a separation (method.md, section 5). ``held``: the
    contacts hold their gap where the bodies met (:class:`StepForce`'s plastic rule),
    and an opening is measured from the gap the last contact held, not from 0.
    """
    active = force > 1e-10 * float(np.max(force, initial=0.0))
    if not np.any(active):
        return []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], active.astype(np.int8), [0]])))
    runs = list(zip(edges[::2], edges[1::2]))
    merged = [list(runs[0])]
    for start, stop in runs[1:]:
        prev_stop = merged[-1][1]
        touch = gap_end[prev_stop - 1] if held else 0.0
        if np.all(gap_end[prev_stop:start] - touch <= tol):
            merged[-1][1] = stop
        else:
            merged.append([start, stop])
    return [tuple(r) for r in merged]


def assemble_result(bodies, gap0, grid: Grid, force, kernels, y_free, *, method, notes=(),
                    y=None, points=(None, None), plastic=False):
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
    plastic : bool, keyword-only
        The forces come from :class:`StepForce`'s plastic rule (contacts hold the gap
        where the bodies met: :func:`contact_runs`' ``held``).
    """
    b1, b2 = bodies
    if y is None:
        y1 = y_free[0] - causal_convolve(force, kernels[0])
        y2 = y_free[1] + causal_convolve(force, kernels[1])
    else:
        y1, y2 = y
    gap = y2 - y1 + gap0
    runs = contact_runs(force, gap[1:], micro_separation_tolerance(y1, y2), held=plastic)
    dt = grid.dt
    intervals = tuple((float(grid.t[a]), float(grid.t[b])) for a, b in runs)
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
    force_out = np.append(force, force[-1])
    return ImpactResult(t=grid.t, force=force_out, y1=y1, y2=y2, gap=gap,
                        contact_intervals=intervals, dirac_impulses=(),
                        velocities_before=u_before, velocities_after=u_after,
                        energy_by_body=tuple(energies), method=method, dt=dt,
                        first_contact_impulse=first_impulse, total_impulse=total_impulse,
                        inverse_masses=inv, notes=tuple(notes), points=tuple(points))
