"""``ImpactResult``: everything a solve predicts, immutable, with its own diagnostics."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

__all__ = ["ImpactResult", "BodyEnergy", "EnergyAudit", "EnergyWarning"]


class ReadOnlyArrays:
    """Mixin of the frozen result dataclasses: their arrays stay read-only when pickled,
    deep-copied or copied (unpickling does not run ``__post_init__``, which froze them:
    a result sent through a process pool came back writeable, and ``r.force[:] = 0``
    then made its peak force 0 beside an unchanged impulse); the repr shows an array's
    shape, not its values (a result's ran to thousands of characters)."""

    def __repr__(self) -> str:
        def shown(value):
            if isinstance(value, np.ndarray):
                return f"<array {'x'.join(map(str, value.shape)) or 'scalar'}>"
            if isinstance(value, (tuple, list)) and len(value) > 4:
                return f"<{len(value)} {type(value).__name__} items>"
            return repr(value)
        fields = getattr(self, "__dataclass_fields__", {})
        parts = (f"{name}={shown(getattr(self, name))}" for name in fields
                 if fields[name].repr)
        return f"{type(self).__name__}({', '.join(parts)})"

    def __setstate__(self, state):
        for name, value in state.items():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)     # this object's own copy (or a frozen one)
            object.__setattr__(self, name, value)


class EnergyWarning(UserWarning):
    """A prediction ends with more energy than it had: beyond the solver's accuracy, the
    result is not physical (see :class:`EnergyAudit`)."""


@dataclass(frozen=True)
class BodyEnergy:
    """Energy of one body (J) before the impact and at the end of the solve.

    ``vibration_after`` is the vibration energy delivered to the body by ``t_end``: its
    vibration energy before, plus the work of the contact force and its load on it, less
    its rigid-body energy's gain. For an undamped body that is the vibration energy it
    holds at ``t_end``; a damped body holds that less what its own damping took, and
    ``t_end`` would decide the figure: every solver reports the energy delivered (the
    exact method integrates the work on its closed form; the time-stepping ones sum it
    over their steps). It counts the strain energy ``d F^2 / 2`` of a residual
    flexibility ``d`` under the force on the body (contact force and load): a body loaded
    at ``t = 0`` starts with ``d F(0)^2 / 2`` of it.

    Parameters
    ----------
    rigid_before, vibration_before : float
        Rigid-body kinetic and vibration energy (J) before the impact.
    rigid_after, vibration_after : float
        The same at the end of the solve (J; the vibration energy delivered).
    vibration_held : float or None
        The vibration energy the body holds at ``t_end`` (J), where the solver knows its
        state (the exact method); None otherwise. For an undamped body it is
        ``vibration_after``; above it, the body's own damping made energy (a model that is
        not passive), which the energy audit flags.
    """

    rigid_before: float
    vibration_before: float
    rigid_after: float
    vibration_after: float
    vibration_held: float | None = None

    @property
    def total_before(self) -> float:
        return self.rigid_before + self.vibration_before

    @property
    def total_after(self) -> float:
        return self.rigid_after + self.vibration_after


@dataclass(frozen=True)
class EnergyAudit:
    """The energy balance of a prediction, both bodies and the contact together.

    ``created = after + stored + dissipated - before - load_work`` (J) is energy that
    came from nowhere: 0 for an exact solution of undamped bodies, negative when the
    bodies' own damping or a Dirac (plastic) part of the force took some.

    Attributes
    ----------
    before, after : float
        Rigid-body kinetic plus vibration energy of both bodies (J) at ``t = 0`` and at
        ``t_end``.
    dissipated : float
        Energy (J) a spring-dashpot contact took: its dashpot's, plus the spring energy
        left behind where the force is clipped at 0 with the bodies still overlapping
        (0 for rigid and purely elastic contacts).
    stored : float
        Elastic energy (J) left in a compliant contact still closed at ``t_end``.
    load_work : float
        Work (J) of the external loads on the bodies.
    scale : float
        The energy the impact can redistribute (J): ``before`` less the centre of mass's
        kinetic energy (which the contact force cannot change), plus ``|load_work|``.
    tolerance : float
        Relative accuracy of the solver's energy (of ``scale``): rounding-level for the
        exact solvers, the discretisation's for the time-stepping ones; with a load on
        an exact solver's result, plus the estimated quadrature error of ``load_work``
        on its output samples (infinite, no check, where they are too few per period of
        the load: :func:`impactpred.solve_impact` warns).
    reasons : tuple of str
        Why the result is flagged (empty when it is not): ``relative`` above
        ``tolerance``, a body left with negative vibration energy, or a restitution above
        ``1 + tolerance`` without pre-impact vibration or load (see
        :func:`impactpred.api.energy_audit`).
    """

    before: float
    after: float
    dissipated: float
    stored: float
    load_work: float
    scale: float
    tolerance: float
    reasons: tuple = ()

    @property
    def created(self) -> float:
        """Energy (J) the prediction ends with beyond what it had and was given."""
        return self.after + self.stored + self.dissipated - self.before - self.load_work

    @property
    def relative(self) -> float:
        """``created / scale`` (0 when nothing moves)."""
        if self.scale > 0.0:
            return self.created / self.scale
        return 0.0 if self.created <= 0.0 else float("inf")

    @property
    def ok(self) -> bool:
        """True when nothing is flagged."""
        return not self.reasons


def _frozen(a, dtype=float):
    """A read-only copy of ``a`` (result arrays are immutable)."""
    a = np.array(a, dtype=dtype, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False, repr=False)
class ImpactResult(ReadOnlyArrays):
    """The predicted impact.

    The attributes up to ``energy_audit`` are what the result holds (its constructor's
    arguments); the rest are computed from them. :meth:`headline` and :meth:`summary` give
    the figures as a dict.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s). For time-stepping solvers the uniform grid ``k * dt``; for the exact
        solvers a grid with every event time inserted.
    force : ndarray, shape (n,)
        Contact force (N), compressive positive. Time-stepping solvers hold it constant
        on ``[t_k, t_k+1)``: ``force[k]`` is its value there. Dirac parts are not in it:
        see ``dirac_impulses``.
    y1, y2 : ndarray, shape (n,)
        Contact-point displacements (m) of body 1 and body 2.
    gap : ndarray, shape (n,)
        ``y2 - y1 + gap0`` (m).
    contact_intervals : tuple of (float, float)
        Every contact interval (start, end) in s within ``t_end`` (a contact still closed
        at ``t_end`` ends there). A pure Dirac contact has start == end.
    dirac_impulses : tuple of (float, float)
        (time s, impulse N s) of every Dirac part of the force.
    velocities_before, velocities_after : tuple of float
        Rigid-body velocities (m/s) of the two bodies before and after all contacts: where
        a free body carries a load, which moves them all the time, at the first contact's
        start and at the last contact's end.
    energy_by_body : tuple of BodyEnergy
        Per body: rigid and vibration energy (J) before and after (:attr:`energy`
        tabulates them), at ``t = 0`` and at the run's end (a load's work between them
        included; unlike ``velocities_before``/``after`` of a loaded body).
    method : str
        The solver used.
    dt : float
        The step (s) it used (the exact solvers: their output step).
    first_contact_impulse, total_impulse : float
        Impulse (N s) of the first contact and of all contacts, Dirac parts included.
    inverse_masses : tuple of float
        ``1/M`` of each body (0 for a grounded one).
    notes : tuple of str
        What the solver wants the user to know (e.g. chosen step, micro-separations).
    points : tuple of (PointResponse or None)
        Per body: displacement, velocity and acceleration histories of its output points
        (None for a body given without outputs); see :class:`impactpred.PointResponse`.
    energy_audit : EnergyAudit or None
        The energy balance (``energy_audit.ok``, ``.created``, ``.relative``), set by
        :func:`impactpred.solve_impact`; None on a result built by a solver directly.
    v1, v2 : numpy.ndarray or None
        The contact points' velocities (m/s) at ``t`` where the solver samples them in
        closed form (the Laplace method; both one-sided limits at event times, the Dirac
        parts not in the samples); None for the time-stepping methods.
    first_contact_load_impulse : tuple of float
        Each body's load impulse (N s, along ``+y``) during the first contact (0 without a
        load on a free body), which ``restitution_first`` counts with the contact's.
    velocities_at_end : tuple of float or None
        Rigid-body velocities (m/s) at the run's end where they differ from
        ``velocities_after`` (a load on a free body acts after the contacts); None
        otherwise.
    success, message : bool, str
        Whether the result can be trusted, and why not (derived from ``energy_audit``).
    energy : pandas.DataFrame
        ``energy_by_body`` as a table (J): rows body1, body2; rigid and vibration energy
        before and after, and their totals.
    vibration_energy_fraction : float
        Share of the energy before delivered to vibration by the end (what the bodies'
        own damping took of it included; see :class:`BodyEnergy`).
    n_contacts, touched : int, bool
        Number of contact intervals; whether the bodies touched (a Dirac counts).
    contact_duration_first, total_contact_time : float
        The first contact's duration, and the time in contact summed (s).
    peak_force_first_contact, peak_force_max : float
        Largest regular force (N) of the first contact, and of the whole history.
    contact_duration, peak_force : float
        ``contact_duration_first`` and ``peak_force_first_contact`` under their earlier
        names.
    impulse : float
        ``total_impulse`` (N s).
    restitution, restitution_first : float or None
        After the last separation, and after the first contact only; None without
        approach or contact, and while that contact is still closed at ``t_end``
        (:attr:`in_contact_at_end`: the bodies have not separated, there is no
        restitution yet).
    in_contact_at_end : bool
        Whether the last contact is still closed at ``t_end``.
    """

    t: np.ndarray
    force: np.ndarray
    y1: np.ndarray
    y2: np.ndarray
    gap: np.ndarray
    contact_intervals: tuple
    dirac_impulses: tuple
    velocities_before: tuple
    velocities_after: tuple
    energy_by_body: tuple
    method: str
    dt: float
    first_contact_impulse: float
    total_impulse: float
    inverse_masses: tuple
    notes: tuple = field(default_factory=tuple)
    points: tuple = (None, None)
    energy_audit: EnergyAudit | None = None
    v1: np.ndarray | None = None
    v2: np.ndarray | None = None
    first_contact_load_impulse: tuple = (0.0, 0.0)
    velocities_at_end: tuple | None = None

    def __post_init__(self):
        for name in ("t", "force", "y1", "y2", "gap"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        for name in ("v1", "v2"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _frozen(getattr(self, name)))
        points = tuple(self.points)
        if len(points) != 2:
            raise ValueError(f"points must hold one entry per body, got {len(points)}")
        object.__setattr__(self, "points", points)

    # ------------------------------------------------------------- derived figures
    @property
    def success(self) -> bool:
        """True unless the :attr:`energy_audit` flags the result (a solve that cannot
        decide or finish raises instead of returning)."""
        return self.energy_audit is None or self.energy_audit.ok

    @property
    def message(self) -> str:
        """One line: ``"ok"``, ``"not audited"`` (no :attr:`energy_audit`), or the
        audit's reasons."""
        if self.energy_audit is None:
            return "not audited"
        return "ok" if self.energy_audit.ok else "; ".join(self.energy_audit.reasons)

    @property
    def n_contacts(self) -> int:
        """Number of contact intervals."""
        return len(self.contact_intervals)

    @property
    def contact_duration_first(self) -> float:
        """Duration (s) of the first contact; 0.0 without contact."""
        if not self.contact_intervals:
            return 0.0
        start, end = self.contact_intervals[0]
        return end - start

    #: the first contact's duration (s): the name kept for existing code
    contact_duration = contact_duration_first

    @property
    def total_contact_time(self) -> float:
        """Time (s) in contact, summed over every contact interval within ``t_end``."""
        return float(sum(end - start for start, end in self.contact_intervals))

    @property
    def peak_force_first_contact(self) -> float:
        """Largest regular force (N) during the first contact (Dirac parts excluded)."""
        if not self.contact_intervals:
            return 0.0
        start, end = self.contact_intervals[0]
        inside = (self.t >= start) & (self.t <= end)
        return float(np.max(self.force[inside], initial=0.0))

    #: the first contact's peak force (N): the name kept for existing code
    peak_force = peak_force_first_contact

    @property
    def peak_force_max(self) -> float:
        """Largest regular force (N) over the whole history (Dirac parts excluded)."""
        return float(np.max(self.force, initial=0.0))

    @property
    def impulse(self) -> float:
        """Total impulse (N s) of all contacts within ``t_end``, Dirac parts included."""
        return self.total_impulse

    @property
    def touched(self) -> bool:
        """True when the bodies touched within ``t_end`` (a Dirac contact counts)."""
        return bool(self.contact_intervals or self.dirac_impulses)

    @property
    def in_contact_at_end(self) -> bool:
        """True when the last contact interval reaches ``t_end``: the bodies are still
        pressed together, and the post-impact figures are not final."""
        if not self.contact_intervals or self.t.size == 0:
            return False
        step = float(self.t[-1] - self.t[-2]) if self.t.size > 1 else 0.0
        return bool(self.contact_intervals[-1][1] >= self.t[-1] - 0.5 * step)

    @property
    def restitution(self):
        """``(u2' - u1') / (u1 - u2)`` after the last separation; None without approach,
        without contact, or while the contact is still closed at ``t_end``."""
        if not self.touched or self.in_contact_at_end:
            return None
        return _restitution(self.velocities_before, self.velocities_after)

    @property
    def restitution_first(self):
        """Restitution after the first contact only; None without approach or contact,
        or while the first contact is still closed at ``t_end``."""
        if not self.touched or (self.in_contact_at_end and len(self.contact_intervals) == 1):
            return None
        u1, u2 = self.velocities_before
        p = self.first_contact_impulse
        q1, q2 = self.first_contact_load_impulse
        after = (u1 + (q1 - p) * self.inverse_masses[0], u2 + (q2 + p) * self.inverse_masses[1])
        return _restitution(self.velocities_before, after)

    @property
    def energy(self) -> pd.DataFrame:
        """Energy table (J): rows body1, body2; rigid/vibration before and after."""
        rows = {f"body{i + 1}": {**vars(e), "total_before": e.total_before,
                                 "total_after": e.total_after}
                for i, e in enumerate(self.energy_by_body)}
        return pd.DataFrame.from_dict(rows, orient="index")

    @property
    def vibration_energy_fraction(self) -> float:
        """Share of the total energy before delivered to the bodies' vibration by the end
        (0 to 1): ``sum vibration_after / sum total_before`` (:class:`BodyEnergy`: what
        their own damping took of it counts, so the figure does not depend on
        ``t_end``)."""
        before = sum(e.total_before for e in self.energy_by_body)
        after_vib = sum(e.vibration_after for e in self.energy_by_body)
        return after_vib / before if before > 0 else 0.0

    def headline(self) -> dict:
        """The headline figures, each named for what it is, with its unit in the key.

        ``peak_force_N`` is the largest regular force over the whole history,
        ``peak_force_first_contact_N`` that of the first contact;
        ``contact_duration_first_s`` is the first contact's duration,
        ``total_contact_time_s`` the sum over all contacts; restitutions are None without
        contact and while it is still closed at ``t_end`` (``in_contact_at_end``). The
        ``energy_*`` entries are the :attr:`energy_audit` (None without one).

        Returns
        -------
        dict
        """
        audit = self.energy_audit
        return {"method": self.method, "dt_s": self.dt, "n_contacts": self.n_contacts,
                "contact_duration_first_s": self.contact_duration_first,
                "total_contact_time_s": self.total_contact_time,
                "peak_force_first_contact_N": self.peak_force_first_contact,
                "peak_force_N": self.peak_force_max,
                "impulse_first_contact_Ns": self.first_contact_impulse,
                "impulse_Ns": self.impulse,
                "restitution_first": self.restitution_first, "restitution": self.restitution,
                "in_contact_at_end": self.in_contact_at_end,
                "vibration_energy_fraction": self.vibration_energy_fraction,
                "n_dirac": len(self.dirac_impulses),
                "energy_before_J": None if audit is None else audit.before,
                "energy_created_J": None if audit is None else audit.created,
                "energy_created_relative": None if audit is None else audit.relative,
                "energy_audit_ok": None if audit is None else audit.ok}

    def summary(self) -> dict:
        """The headline figures as a plain dict, under their original names.

        ``contact_duration`` and ``peak_force`` are the first contact's; see
        :meth:`headline` for the figures named for what they are, with units.

        Returns
        -------
        dict
        """
        return {"method": self.method, "dt": self.dt, "n_contacts": self.n_contacts,
                "contact_duration": self.contact_duration, "peak_force": self.peak_force,
                "impulse": self.impulse, "restitution_first": self.restitution_first,
                "restitution": self.restitution,
                "vibration_energy_fraction": self.vibration_energy_fraction,
                "n_dirac": len(self.dirac_impulses)}

    def point_peaks(self) -> pd.DataFrame:
        """Peaks of every output point of both bodies (see :meth:`PointResponse.peaks`).

        Index ``(body, point)`` with ``body`` 1 or 2; empty without output points.

        Returns
        -------
        pandas.DataFrame
        """
        tables = {i + 1: p.peaks() for i, p in enumerate(self.points) if p is not None}
        if not tables:
            index = pd.MultiIndex.from_tuples([], names=["body", "point"])
            return pd.DataFrame(index=index)
        return pd.concat(tables, names=["body", "point"])

    def to_pandas(self) -> pd.DataFrame:
        """Time histories as a DataFrame indexed by time (s).

        Returns
        -------
        pandas.DataFrame
        """
        return pd.DataFrame({"force": self.force, "y1": self.y1, "y2": self.y2,
                             "gap": self.gap}, index=pd.Index(self.t, name="t"))

    def plot(self, ax=None):
        """Force, gap and displacements on one time axis; returns the force Axes.

        The contact force (N) on the left axis, the displacements and the gap (m) on a
        twin axis on the right, their zeros at the same height (a grey line); the legend
        in a band above the curves, clear of them; Dirac impulses annotated.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).

        Returns
        -------
        matplotlib.axes.Axes
            The force's axes (the displacements' twin is ``ax.figure.axes`` after it).
        """
        import matplotlib.pyplot as plt

        from ._plot_axes import align_zeros, legend_above_data

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        if self.method in ("convolution", "modal"):
            ax.step(self.t, self.force, where="post", color="C0", label="force (N)")
        else:
            ax.plot(self.t, self.force, color="C0", label="force (N)")
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("contact force (N)")
        motion = ax.twinx()
        motion.plot(self.t, self.y1, "C1--", lw=1, label="y1 (m)")
        motion.plot(self.t, self.y2, "C2--", lw=1, label="y2 (m)")
        motion.plot(self.t, self.gap, "C3:", lw=1.2, label="gap (m)")
        motion.set_ylabel("displacement, gap (m)")
        if self.dirac_impulses:
            ax.set_ylim(top=max(ax.get_ylim()[1], 1.1 * max(self.peak_force, 1e-300)))
        align_zeros(ax, motion)
        handles, labels = ax.get_legend_handles_labels()
        more = motion.get_legend_handles_labels()
        legend_above_data(ax, handles + more[0], labels + more[1], axes=(motion,))
        for time, size in self.dirac_impulses:
            ax.annotate(f"Dirac {size:.3g} N s", (time, 0), xytext=(time, 0.9 * max(
                self.peak_force, 1e-300)), arrowprops={"arrowstyle": "->"}, fontsize=8)
        return ax


def _restitution(before, after):
    approach = before[0] - before[1]
    if approach <= 0:
        return None
    return (after[1] - after[0]) / approach
