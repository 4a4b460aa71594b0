"""``DamperResult``: the histories, impacts and steady-state figures of one damper run."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from modalid.validation import as_count

from ..contact import Hertz
from ..points import PointResponse
from ..result import ReadOnlyArrays, _frozen
from ..engine.phase import _cubic_min

__all__ = ["DamperResult", "DamperState", "build_result"]

#: relative tolerance on Poincare points for "the response repeats"
STEADY_RTOL = 1e-6
#: periods tried for a periodic steady state (period-1 .. period-4 motion)
MAX_PERIOD = 4
#: a rounding error near a resonance (relative to the response) worth a note and a warning
RESONANCE_ERROR_NOTE = 1e-8
_IMPACT_COLUMNS = ["time", "side", "impulse", "duration", "relative_velocity", "phase"]


@dataclass(frozen=True, eq=False, repr=False)
class DamperState(ReadOnlyArrays):
    """Where a run ended, for ``ImpactDamper.simulate(initial=...)``.

    Attributes
    ----------
    time : float
        Time (s); the excitation's phase follows from it.
    state : ndarray, shape (n,)
        Engine state: the primary's modal states, ``y_d`` (m), ``v_d`` (m/s), 1.
    mode : str
        ``"free"``, ``"stuck"``, ``"spring"``, ``"pen"`` (spring-dashpot released while
        still overlapping) or ``"hertz"``.
    side : int
        Stop in contact (+1 upper, -1 lower; 0 in free flight).
    open_impact : dict or None
        The impact still in progress at ``time`` (so far), continued by the next run,
        which lists it whole. A ``Hertz`` contact cut so restarts its time-stepping grid
        there: the continued run departs from the unsplit one by the stepping's error
        (5e-11 m in a 3e-4 m clearance), which a chaotic response may then grow.
    clearance : float or None
        The clearance (m) of the damper the state comes from (None: not known); a run
        continued on another clearance is checked against it
        (:meth:`ImpactDamper.simulate`).
    """

    time: float
    state: np.ndarray
    mode: str
    side: int
    open_impact: Any = None
    clearance: float | None = None


@dataclass(frozen=True, eq=False, repr=False)
class DamperResult(ReadOnlyArrays):
    """One run of :meth:`ImpactDamper.simulate`; immutable (read-only arrays).

    Attributes
    ----------
    t : ndarray, shape (n_samples,)
        Times (s): ``samples_per_cycle`` per forcing period plus every event time.
    primary, damper : ndarray, shape (n_samples,)
        Displacement (m) of the primary's driving point and of the damper mass.
    primary_velocity, damper_velocity : ndarray, shape (n_samples,)
        Their velocities (m/s); at an event's time the value just before it (the sample
        closes the phase the event ends; the samples after it follow the event).
    force : ndarray, shape (n_samples,)
        Contact force on the primary along ``+y`` (N): positive at the upper stop,
        negative at the lower one. Dirac parts are only in ``impacts``.
    excitation : ndarray, shape (n_samples,)
        The force (N) or base displacement (m).
    input_work : ndarray, shape (n_samples,)
        Energy put in by the excitation since the run's start (J), exact (closed-form
        integrals of force times velocity; for a base excitation the work of its
        equivalent force ``k y_b + c y_b'`` on the primary's absolute motion, which
        balances the energy counted with the spring's ``k x^2 / 2`` of the absolute
        displacement; the base's own work through the spring and dashpot differs from it
        by boundary terms, not in the mean power).
    freq_hz, period : float
        Excitation frequency (Hz) and period (s).
    impacts : pandas.DataFrame
        One row per impact: ``time`` (s), ``side`` (+1 upper, -1 lower), ``impulse``
        (N s, its magnitude, Dirac part included: ``side`` gives its direction on the
        primary), ``duration`` (s, 0 for instantaneous),
        ``relative_velocity`` (m/s, approach speed before it), ``phase`` (rad of the
        forcing at impact, in [0, 2 pi)). A fresh copy on each access (the result stays
        as it was run). An impact is listed by the run in which it ends: one still in
        progress at the run's end is not listed (``final_state.open_impact`` holds it so
        far) and the run that continues this one lists it whole, so the tables of a run
        split anywhere concatenate to the unsplit run's.
    steady_state_cycle : int or None
        First cycle from which the Poincare points repeat (period ``steady_period``)
        to ``STEADY_RTOL``; None if they do not.
    is_steady : bool
    steady_period : int or None
        Number of forcing cycles of the periodic response (1: period-1 motion).
    primary_amplitude : float
        Half peak-to-peak displacement (m) of the primary over the steady cycles (the
        last 10 % of the cycles if not steady; see ``notes``); peaks refined by cubic
        Hermite interpolation of displacement and velocity between samples: to about
        4e-6 relative at the default 32 samples per cycle (1e-3 at 8; 1e-6 at 256, where
        the steady window's own tolerance ``STEADY_RTOL`` is the limit), while the
        histories are exact to rounding. Refined only where the samples lie within a
        period of the primary's lowest mode (beyond a radian, on an undamped primary
        whose free vibration persists, to a few per cent); where they lie further apart
        (a forcing far below it), the samples' own half peak-to-peak, and ``notes`` says
        so.
    impacts_per_cycle : float
        Impacts per forcing period over the same cycles, counted by start time: an
        impact still open at the run's end counts here (it is listed in ``impacts`` by
        the run that ends it).
    power_dissipated : float
        Mean input power (W) over the same cycles: in a steady state it equals the power
        dissipated by impacts, contact damping and the primary's damping.
    reduction : float
        ``primary_amplitude / amplitude_without_damper``; NaN without excitation (a free
        rattle: no bare amplitude to compare with).
    amplitude_without_damper : float
        Closed-form steady amplitude (m) of the primary alone.
    notes : tuple of str
    final_state : DamperState
        Pass the result (or this) as ``initial=`` to continue the run.
    damper_config : ImpactDamper
        The damper simulated.
    points : PointResponse or None
        With a ``MultiOutputModalModel`` primary: the displacement, velocity and
        acceleration of each of its output points (rows, in its ``outputs`` order) along
        the driving point's axis, on ``t``; exact like ``primary`` (where an impulse acts
        the samples hold the regular part: the state just after it). ``Hertz`` contacts
        are time-stepped (the force linear within a step), like ``primary``. None for
        other primaries.
    """

    t: np.ndarray
    primary: np.ndarray
    damper: np.ndarray
    primary_velocity: np.ndarray
    damper_velocity: np.ndarray
    force: np.ndarray
    excitation: np.ndarray
    input_work: np.ndarray
    grid_index: np.ndarray
    freq_hz: float
    period: float
    t_start: float
    n_cycles: int
    samples_per_cycle: int
    _impacts: pd.DataFrame = field(repr=False)
    steady_state_cycle: int | None
    is_steady: bool
    steady_period: int | None
    primary_amplitude: float
    impacts_per_cycle: float
    power_dissipated: float
    reduction: float
    amplitude_without_damper: float
    notes: tuple
    final_state: DamperState
    damper_config: Any
    points: PointResponse | None = None

    @property
    def impacts(self) -> pd.DataFrame:
        """The impacts table (class docstring), a fresh copy on each access."""
        return self._impacts.copy()

    def __setstate__(self, state):
        # a result pickled before the table became a property kept it as ``impacts``
        if "impacts" in state:
            state = {("_impacts" if k == "impacts" else k): v for k, v in state.items()}
        super().__setstate__(state)

    def poincare(self) -> pd.DataFrame:
        """States once per forcing period, at the run's starting phase.

        Returns
        -------
        pandas.DataFrame
            Columns ``cycle``, ``time`` (s), ``primary`` (m), ``primary_velocity`` (m/s),
            ``damper`` (m), ``damper_velocity`` (m/s); one row per cycle boundary
            (``n_cycles + 1`` rows).
        """
        idx = _poincare_index(self.grid_index, self.samples_per_cycle)
        return pd.DataFrame({
            "cycle": np.arange(idx.size), "time": self.t[idx], "primary": self.primary[idx],
            "primary_velocity": self.primary_velocity[idx], "damper": self.damper[idx],
            "damper_velocity": self.damper_velocity[idx]})

    def plot(self, ax=None, *, last_cycles=None):
        """Primary and damper-mass displacement against time, impacts marked.

        Displacements in mm on the left axis; a contact force that lasts (spring-dashpot or
        Hertz contact, not instantaneous impacts, whose impulses are in ``impacts``) in N
        on a twin axis on the right, its zero level with the displacements' zero; the
        legend in a band above the curves, clear of them.

        Parameters
        ----------
        ax : matplotlib Axes, optional
        last_cycles : int, keyword-only, optional
            Plot only the last cycles, >= 1 (default: all).

        Returns
        -------
        matplotlib.axes.Axes
            The displacements' axes (a force twin is ``ax.figure.axes`` after it).
        """
        import matplotlib.pyplot as plt

        from .._plot_axes import align_zeros, legend_above_data

        if ax is None:
            _, ax = plt.subplots(figsize=(8, 3.5))
        if last_cycles is not None:      # not an empty plot from 0, -3 or 2.5
            last_cycles = as_count("last_cycles", last_cycles, minimum=1)
        t0 = -np.inf if last_cycles is None else self.t[-1] - last_cycles * self.period
        sel = self.t >= t0
        ax.plot(self.t[sel], self.primary[sel] * 1e3, label="primary (driving point)")
        ax.plot(self.t[sel], self.damper[sel] * 1e3, label="damper mass", lw=0.8)
        imp = self.impacts[self.impacts["time"] >= t0]
        if len(imp):
            y = np.interp(imp["time"], self.t, self.damper) * 1e3
            ax.plot(imp["time"], y, "k.", ms=3, label="impacts")
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("displacement (mm)")
        versus = (f"x{self.reduction:.3g} of the bare structure"
                  if math.isfinite(self.reduction) else "no excitation")
        ax.set_title(f"{self.freq_hz:.4g} Hz: amplitude {self.primary_amplitude * 1e3:.4g} mm "
                     f"({versus})")
        handles, labels = ax.get_legend_handles_labels()
        twins = ()
        if np.any(self.force[sel] != 0):
            force = ax.twinx()
            force.plot(self.t[sel], self.force[sel], color="C3", lw=0.8,
                       label="contact force on the primary")
            force.set_ylabel("contact force (N)")
            align_zeros(ax, force)
            more = force.get_legend_handles_labels()
            handles, labels, twins = handles + more[0], labels + more[1], (force,)
        legend_above_data(ax, handles, labels, axes=twins, fontsize="small")
        return ax


def _poincare_index(grid, spc):
    on = np.flatnonzero((grid >= 0) & (grid % spc == 0))
    _, first = np.unique(grid[on], return_index=True)
    return on[first]


def _steady(points, rtol):
    """(first steady cycle, period) from Poincare points (n_points, n_comp), or (None, None)."""
    n = points.shape[0]
    scale = np.max(np.abs(points), axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    for m in range(1, MAX_PERIOD + 1):
        if n <= 3 * m:
            break
        d = np.max(np.abs(points[m:] - points[:-m]) / scale, axis=1)
        bad = np.flatnonzero(d > rtol)
        first = int(bad[-1]) + 1 if bad.size else 0
        if n - 1 - first >= 3 * m:            # at least three repeats seen
            return first, m
    return None, None


def _amplitude(t, y, v, max_step=np.inf):
    """Half peak-to-peak of ``y``, extremes refined by cubic Hermite steps between samples
    at most ``max_step`` (s) apart (a cubic through samples a radian of the primary's
    lowest mode apart errs by at most ``(omega h)^4 / 384`` of its amplitude, through
    samples 2 to 4 radians apart by 1-3 % on an undamped primary; through samples
    several of its periods apart, by any amount: 103 m for a 0.5 mm motion)."""
    if y.size < 2:
        return 0.0
    h = np.diff(t)
    ok = (h > 0) & (h <= max_step)
    ya, yb, va, vb, h = y[:-1][ok], y[1:][ok], v[:-1][ok], v[1:][ok], h[ok]
    lo = float(np.min(_cubic_min(ya, yb, va, vb, h), initial=np.min(y)))
    hi = -float(np.min(_cubic_min(-ya, -yb, -va, -vb, h), initial=-np.max(y)))
    return 0.5 * (hi - lo)


def build_result(damper, raw, *, n_cycles, samples_per_cycle):
    """Assemble a :class:`DamperResult` from the engine's raw output.

    Parameters
    ----------
    damper : ImpactDamper
        The system that was simulated.
    raw : object
        The engine's raw run (events, samples, final state), in SI
        (:meth:`impactpred.damper._engine.Engine.to_si`).
    n_cycles : int, keyword-only
        Forcing cycles simulated.
    samples_per_cycle : int, keyword-only
        Output samples per forcing period.

    Returns
    -------
    DamperResult
    """
    spc = samples_per_cycle
    t, vals, work, grid = raw["t"], raw["values"], raw["work"], raw["grid"]
    eng = damper.engine()
    T = eng.period_si
    t0 = raw["t_start"]
    notes = []
    rows = raw["impacts"]
    if isinstance(rows, dict):      # the compiled loop's columns
        imp = pd.DataFrame({k: rows[k] for k in _IMPACT_COLUMNS}, columns=_IMPACT_COLUMNS)
    else:
        imp = pd.DataFrame([{k: r[k] for k in _IMPACT_COLUMNS} for r in rows],
                           columns=_IMPACT_COLUMNS)
    imp["side"] = imp["side"].astype(int)
    # the phases the run entered: free flight, the stuck ones of the sides it held on (an
    # impact that lasted; the open impact is in the table), the contact ones it touched
    held = set(imp.loc[imp["duration"] > 0, "side"])
    touched = set(imp["side"])
    if raw["final"].mode != "free":
        held.add(raw["final"].side)
        touched.add(raw["final"].side)
    loss = eng.resonance_error(stuck_sides=held, contact_sides=touched)
    if loss > RESONANCE_ERROR_NOTE:
        note = (f"the excitation frequency lies {np.finfo(float).eps / loss:.2g} (relative) "
                "from an undamped mode of a phase: the closed form's free and forced parts "
                f"cancel there, leaving a rounding error of about {loss:.1g} of the response")
        notes.append(note)
        warnings.warn(note, UserWarning, stacklevel=3)
    pidx = _poincare_index(grid, spc)
    points = vals[:4, pidx].T
    first, period = _steady(points, STEADY_RTOL)
    if first is not None:
        n_use = ((n_cycles - first) // period) * period
        c_a = n_cycles - n_use
    else:
        c_a = n_cycles - max(1, int(round(0.1 * n_cycles)))
        notes.append(f"no steady state within {n_cycles} cycles (Poincare points do not repeat "
                     f"to {STEADY_RTOL:g} with period <= {MAX_PERIOD}): amplitude, impacts and "
                     f"power are over the last {n_cycles - c_a} cycles")
    t_a, t_b = t0 + c_a * T, raw["t_end"]
    win = (t >= t_a - 1e-12 * T) & (t <= t_b + 1e-12 * T)
    # a cubic between samples a period or more of the primary's lowest mode apart
    # represents nothing: no refinement there (closer, it errs by a few per cent at most)
    omega_low = float(np.min(np.abs(damper.model.poles), initial=np.inf))
    amp = _amplitude(t[win], vals[0, win], vals[1, win], max_step=2 * np.pi / omega_low)
    step = T / spc
    if step * omega_low > 2 * np.pi:
        need = math.ceil(T * omega_low)
        note = (f"the output samples ({spc} per cycle, {step:.4g} s apart) do not resolve the "
                f"primary's lowest mode ({omega_low / (2 * np.pi):.4g} Hz, "
                f"{step * omega_low / (2 * np.pi):.3g} of its periods between samples): "
                "primary_amplitude (and reduction) is the samples' half peak-to-peak, which "
                f"may miss extremes between them; samples_per_cycle >= {need} resolves it")
        notes.append(note)
        warnings.warn(note, UserWarning, stacklevel=3)
    ia, ib = pidx[c_a], pidx[-1]
    dt = t[ib] - t[ia]
    dw = work[:, ib] - work[:, ia]
    power = dw[0] / dt
    if eng.base_damping:
        cb, vb = eng.base_damping, eng.base_velocity_amplitude
        power = (dw[0] - 2 * cb * dw[1]) / dt + 0.5 * cb * vb ** 2
    n_imp = int(np.count_nonzero((imp["time"] >= t_a - 1e-12 * T)
                                 & (imp["time"] < t_b - 1e-12 * T)))
    fs = raw["final"]
    if fs.open_impact is not None:
        # listed by the run that ends it (the continuation lists it whole); counted
        # above among this run's impacts per cycle, which count by start time
        if not (len(imp) and imp["time"].iloc[-1] == fs.open_impact["time"]):
            raise AssertionError("the open impact is not the last row of the table")
        imp = imp.iloc[:-1]
    a0 = damper.amplitude_without_damper()
    w_in = work[0]
    if eng.base_damping:
        om, phi = eng.omega_si, eng.phi
        sin2 = 0.5 * (t - t0) - (np.sin(2 * (om * t + phi)) - math.sin(2 * (om * t0 + phi))) \
            / (4 * om)
        w_in = work[0] - 2 * eng.base_damping * work[1] \
            + eng.base_damping * eng.base_velocity_amplitude ** 2 * sin2
    final = DamperState(fs.time, fs.state, fs.mode, fs.side, fs.open_impact, damper.clearance)
    n_points = eng.n_points
    points = None
    if n_points:
        disp, vel, acc = np.split(vals[6:6 + 3 * n_points], 3)
        method = ("exact in free flight; Hertz contacts time-stepped (the force linear "
                  "within a step)" if isinstance(eng.contact, Hertz)
                  else "exact (closed form between events)")
        points = PointResponse(labels=tuple(damper.primary.outputs), t=t, displacement=disp,
                               velocity=vel, acceleration=acc, method=method)
    return DamperResult(
        t=_frozen(t), primary=_frozen(vals[0]), primary_velocity=_frozen(vals[1]),
        damper=_frozen(vals[2]), damper_velocity=_frozen(vals[3]), force=_frozen(vals[4]),
        excitation=_frozen(vals[5]), input_work=_frozen(w_in), grid_index=_frozen(grid, int),
        freq_hz=1.0 / T, period=T, t_start=t0, n_cycles=n_cycles, samples_per_cycle=spc,
        _impacts=imp, steady_state_cycle=first, is_steady=first is not None,
        steady_period=period, primary_amplitude=amp,
        impacts_per_cycle=n_imp / (n_cycles - c_a), power_dissipated=float(power),
        reduction=amp / a0 if a0 > 0 else math.nan, amplitude_without_damper=a0,
        notes=tuple(notes), final_state=final, damper_config=damper, points=points)
