"""``ImpactDamper``: a primary structure, a free damper mass between two stops, a contact
law and a harmonic excitation; :meth:`ImpactDamper.simulate` runs the exact engine."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from data_synth import SpringMass
from modalid import ModalModel, MultiOutputModalModel
from modalid.validation import (as_count, as_nonnegative_scalar, as_positive_scalar,
                                as_real_scalar)

from ..body import check_driving_point, control_as_model
from ..contact import Hertz, InstantaneousImpact, LinearSpring, Rigid
from ..engine import MAX_SAMPLES
from ..engine.cycle_run import run
from ._engine import Engine, EngineState
from .excitation import BaseExcitation, HarmonicForce
from .result import DamperResult, DamperState, build_result

#: most output samples one ``simulate`` call keeps (``n_cycles * samples_per_cycle``; as
#: ``solve_impact``'s cap on samples): a longer run is continued with ``initial=``
MAX_OUTPUT_SAMPLES = MAX_SAMPLES

__all__ = ["ImpactDamper"]

#: the laws the two-sided engine runs (a ``ContactLaw`` it does not know is refused)
_CONTACTS = (Rigid, LinearSpring, Hertz, InstantaneousImpact)


def _primary_model(primary):
    """(ModalModel, (k, c) of a SpringMass or None) of a primary, validated."""
    if isinstance(primary, SpringMass):
        k, m = primary.stiffness, primary.mass
        return primary.modal_model(1), (k, 2.0 * primary.damping_ratio * math.sqrt(k * m))
    if isinstance(primary, MultiOutputModalModel):
        model = primary.driving
    elif isinstance(primary, ModalModel):
        model = primary
    else:
        raise TypeError(f"primary must be a modalid.ModalModel, a MultiOutputModalModel, a "
                        f"data_synth.SpringMass or a SISO python-control system, got "
                        f"{type(primary).__name__} (for a rod or a beam pass its "
                        f"modal_model(n))")
    if model.inverse_mass != 0.0:
        raise ValueError(f"the primary must be grounded: its inverse_mass is "
                         f"{model.inverse_mass!r} 1/kg (a free body); an impact damper needs a "
                         f"structure that can be excited into steady vibration")
    if model.n_modes == 0 and model.real_poles.size == 0:
        raise ValueError("the primary has no mode: a pure flexibility has no mass to vibrate")
    check_driving_point(model, name="the primary's driving-point receptance")
    return model, None


@dataclass(frozen=True)
class ImpactDamper:
    """A primary structure with an impact damper at its driving point.

    Parameters
    ----------
    primary : ModalModel, MultiOutputModalModel, data_synth.SpringMass or control system
        Grounded (``inverse_mass == 0``), passive driving-point receptance (m/N) at the
        point where the damper acts; a multi-output model gives its driving row, and its
        rows are output points (:attr:`DamperResult.points`: the motion of each); a SISO
        python-control system is read by ``ModalModel.from_control``.
    damper_mass : float, keyword-only
        Mass of the free damper body ``m_d`` (kg), > 0.
    clearance : float, keyword-only
        Free travel ``c >= 0`` (m) on EACH side: the damper mass flies freely while
        ``-c < y_d - y_p < c`` (total free travel ``2 c``).
    contact : Rigid, LinearSpring, Hertz or InstantaneousImpact, keyword-only
        Law at both stops (default ``Rigid()``: a Dirac impulse, then the damper mass
        sticks to the primary until the contact force turns tensile).
    excitation : HarmonicForce or BaseExcitation, keyword-only
        A force at the driving point, or (``SpringMass`` only) a base displacement.

    Notes
    -----
    Exact between events: every phase is a sum of exponentials, the excitation's
    harmonic and a polynomial (the damper mass's free flight), evaluated in closed form;
    events are located by a certified search and safeguarded Newton steps on the closed
    form (:mod:`impactpred.engine.search`). Only ``Hertz`` is time-stepped, during
    contact only. The matrices and eigendecompositions are built once per damper, on the
    first :meth:`simulate`, and reused.
    """

    primary: Any
    damper_mass: float = field(kw_only=True)
    clearance: float = field(kw_only=True)
    contact: Any = field(default=Rigid(), kw_only=True)
    excitation: Any = field(kw_only=True)

    def __post_init__(self):
        object.__setattr__(self, "primary", control_as_model(self.primary))  # stored as such
        model, base = _primary_model(self.primary)
        object.__setattr__(self, "damper_mass", as_positive_scalar("damper_mass",
                                                                    self.damper_mass))
        object.__setattr__(self, "clearance", as_nonnegative_scalar("clearance", self.clearance))
        if not isinstance(self.contact, _CONTACTS):
            raise TypeError(f"contact must be Rigid(), LinearSpring(...), Hertz(...) or "
                            f"InstantaneousImpact(...), got {self.contact!r}")
        exc = self.excitation
        if not isinstance(exc, (HarmonicForce, BaseExcitation)):
            raise TypeError(f"excitation must be a HarmonicForce or a BaseExcitation, got "
                            f"{exc!r}")
        if isinstance(exc, BaseExcitation) and base is None:
            raise ValueError(f"BaseExcitation needs a data_synth.SpringMass primary, got a "
                             f"{type(self.primary).__name__}: a driving-point receptance does "
                             "not contain the base transmissibility (use a HarmonicForce)")
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_base", base if isinstance(exc, BaseExcitation) else None)
        object.__setattr__(self, "_engine_cache", None)

    def __getstate__(self):
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def __setstate__(self, state):
        for name, value in state.items():
            object.__setattr__(self, name, value)
        self.__post_init__()

    # ------------------------------------------------------------------ properties
    @property
    def model(self) -> ModalModel:
        """The primary's driving-point receptance as a ``ModalModel``."""
        return self._model

    @property
    def primary_mass(self) -> float:
        """Modal mass (kg) at the driving point of the primary's lowest mode.

        For a ``SpringMass``: its mass.
        """
        if isinstance(self.primary, SpringMass):
            return self.primary.mass
        modes = self._model.modes
        if modes.empty:
            raise ValueError("the primary has no complex mode: its modal mass is undefined")
        return float(modes["modal_mass"].iloc[0])

    @property
    def mass_ratio(self) -> float:
        """``damper_mass / primary_mass``."""
        return self.damper_mass / self.primary_mass

    def amplitude_without_damper(self) -> float:
        """Steady amplitude (m) of the primary's driving point with no damper.

        ``|H(i Omega)| F0`` for a force; ``Y |k + i c Omega| / |k - m Omega^2 + i c Omega|``
        (absolute displacement) for a base excitation of a ``SpringMass``.

        Returns
        -------
        float
            Amplitude (m).
        """
        exc = self.excitation
        om = exc.omega
        if self._base is None:
            return float(abs(self._model.receptance(1j * om)) * exc.amplitude)
        k, c = self._base
        m = self.primary.mass
        return float(exc.amplitude * abs(k + 1j * c * om) / abs(k - m * om ** 2 + 1j * c * om))

    def replace(self, **changes) -> ImpactDamper:
        """A validated copy with some of ``primary, damper_mass, clearance, contact,
        excitation`` changed.

        Parameters
        ----------
        **changes
            The fields to change and their new values.

        Returns
        -------
        ImpactDamper
        """
        return dataclasses.replace(self, **changes)

    def engine(self) -> Engine:
        """The damper's engine (matrices, decompositions), built once and cached.

        Returns
        -------
        impactpred.damper._engine.Engine
        """
        if self._engine_cache is None:
            outputs = self.primary if isinstance(self.primary, MultiOutputModalModel) else None
            object.__setattr__(self, "_engine_cache", Engine(
                self._model, damper_mass=self.damper_mass, clearance=self.clearance,
                contact=self.contact, excitation=self.excitation, base_spring=self._base,
                outputs=outputs))
        return self._engine_cache

    def initial_state(self, *, damper_displacement=0.0, damper_velocity=0.0,
                      time=0.0) -> DamperState:
        """A start for :meth:`simulate` (``initial=``): the damper mass set going inside a
        primary at rest.

        Parameters
        ----------
        damper_displacement : float, keyword-only
            The damper mass's displacement (m) from the middle of the clearance, which
            moves with the primary's driving point ``y_p`` (0 at rest, or its flexibility's
            response ``D F(time)`` to a force excitation); within the stops,
            ``|damper_displacement| <= clearance``.
        damper_velocity : float, keyword-only
            Its velocity (m/s), in free flight.
        time : float, keyword-only
            Start time (s); the excitation's phase follows from it.

        Returns
        -------
        DamperState
            The primary's modal states at 0 (at rest; under a base excitation the base is
            where the excitation puts it at ``time``, so the primary is not in equilibrium
            there), the damper mass at ``y_p + damper_displacement`` in free flight.
        """
        y_d = as_real_scalar("damper_displacement", damper_displacement)
        v_d = as_real_scalar("damper_velocity", damper_velocity)
        t0 = as_real_scalar("time", time)
        if abs(y_d) > self.clearance:
            raise ValueError(f"damper_displacement={y_d!r} m puts the damper mass past the "
                             f"stops at +-{self.clearance!r} m from the middle")
        eng = self.engine()
        u = eng.units                   # the engine's dimensionless form, back to SI below
        x = np.zeros(eng.n)
        x[eng.i1] = 1.0
        y_p = float(eng.yp0 @ eng.augmented(x, t0 / u.t))      # the primary at rest
        x[eng.iy], x[eng.iv] = y_p + y_d / u.l, v_d / (u.l / u.t)
        return DamperState(t0, x * eng.state_unit, "free", 0, None, self.clearance)

    def _check_start(self, eng, state):
        """Refuse a start this damper cannot continue: inside a contact of another law
        (the engine has no such phase), inside a contact on another clearance than the
        one the run ended on (stuck or spring/Hertz: the force, or a flexible primary's
        driving point, would jump), or in free flight on another clearance with the mass
        past this damper's stops (it would jump to a stop at the first event). On its own
        clearance a run continues as it stands (a frequency step moves a flexible
        primary's driving point by its flexibility times the change of force: the
        model's own)."""
        laws = {"stuck": (Rigid, InstantaneousImpact), "spring": LinearSpring,
                "pen": LinearSpring, "hertz": Hertz}
        mode, side, c, before = state.mode, state.side, self.clearance, state.clearance
        stop = "upper" if side > 0 else "lower"
        if mode in laws and not isinstance(self.contact, laws[mode]):
            raise ValueError(f"initial ended inside a contact ({mode!r} phase on the {stop} "
                             f"stop) of another contact law than this damper's "
                             f"{type(self.contact).__name__}: continue it with the law it ended "
                             "in, or start from initial_state()")
        if before is not None and before == c:
            return
        fix = (f"the run it continues had a clearance of {before:.6g} m: continue with it, "
               "or from initial_state()" if before is not None
               else "a state of unknown clearance: start from initial_state()")
        if mode != "free" and before is not None:
            raise ValueError(f"initial ended inside a contact ({mode!r} phase on the {stop} "
                             f"stop) on a clearance of {before:.6g} m, this damper's is "
                             f"{c:.6g} m: a contact continues on its own clearance only (its "
                             "force, or a flexible primary's driving point, would jump); change "
                             "the clearance in free flight, or start from initial_state()")
        u = eng.units                  # the engine's dimensionless form: r0 in u.l
        xa = eng.augmented(np.asarray(state.state, dtype=float) / eng.state_unit,
                           float(state.time) / u.t)
        rel = float(eng.r0 @ xa) * u.l  # y_d - y_p (without a flexibility's share of the force)
        tol = 1e-9 * (c + float(np.abs(eng.r0) @ np.abs(xa)) * u.l)
        where = (f"initial puts the damper mass {rel:.6g} m from the middle of the clearance "
                 f"(y_d - y_p)")
        if mode == "free" and abs(rel) > c + tol:
            raise ValueError(f"{where}, in free flight past this damper's stops at +-{c:.6g} "
                             f"m ({fix})")
        if mode == "stuck" and eng.rho >= 1 and abs(side * rel - c) > tol:
            raise ValueError(f"{where}, stuck on the {stop} stop, which this damper puts at "
                             f"{side * c:.6g} m ({fix})")
        if mode in ("spring", "pen", "hertz") and -side * rel > c + tol:
            raise ValueError(f"{where}, in contact on the {stop} stop but past the other one "
                             f"at {-side * c:.6g} m ({fix})")

    # ------------------------------------------------------------------ simulation
    def simulate(self, n_cycles, *, initial=None, samples_per_cycle=32,
                 progress=False) -> DamperResult:
        """Run ``n_cycles`` forcing periods with the exact event-driven engine.

        Parameters
        ----------
        n_cycles : int
            Number of forcing periods (>= 1).
        initial : None, DamperResult or DamperState, keyword-only
            ``None``: ``initial_state()``, everything at rest at ``t = 0``, the damper
            mass in the middle of the clearance (which a flexible primary's ``D F(0)``
            moves). A
            ``DamperResult`` (or its ``final_state``) continues that run from its end,
            contact state included; the damper may differ (e.g. a frequency step) as long
            as the primary has the same number of states, the contact law is of the kind
            the run ended in, and a clearance changed leaves the mass within the stops in
            free flight (a run that ended in contact continues on its own clearance).
            :meth:`initial_state` sets the damper mass going inside a primary at rest.
        samples_per_cycle : int, keyword-only
            Output samples per forcing period (>= 4), plus every event time;
            ``n_cycles * samples_per_cycle`` at most ``MAX_OUTPUT_SAMPLES`` (4e6).
        progress : bool, keyword-only
            Print a progress bar to stderr (redrawn at least every 20,000 phases).

        Returns
        -------
        DamperResult

        Raises
        ------
        ValueError
            More than ``MAX_OUTPUT_SAMPLES`` output samples asked for; an ``initial``
            state this damper cannot continue (a run on another clearance that ended with
            the damper mass past a stop or stuck off it, or inside a contact of another
            law), naming the mass's position and the stops.
        RuntimeError
            Contact events repeat without time advancing (an undecidable grazing contact,
            or elastic impacts between stops that coincide to rounding), or more than
            100,000 impacts fall within one forcing period (impacts that do not accumulate
            into sticking, e.g. ``InstantaneousImpact(1.0)`` at a clearance of nanometres).
            An accumulation of impacts with restitution below 1 (a Zeno sequence, every
            ``clearance = 0`` case included) is closed into sticking instead (see
            :class:`InstantaneousImpact`).
        """
        n_cycles = as_count("n_cycles", n_cycles, minimum=1)
        spc = as_count("samples_per_cycle", samples_per_cycle, minimum=4)
        if n_cycles * spc > MAX_OUTPUT_SAMPLES:       # before any work, not as a MemoryError
            raise ValueError(f"n_cycles * samples_per_cycle = {n_cycles} * {spc} output "
                             f"samples exceeds {MAX_OUTPUT_SAMPLES}: run fewer cycles at a "
                             "time (continue with initial=) or sample them less often")
        eng = self.engine()
        if initial is None:
            initial = self.initial_state()
        state = initial.final_state if isinstance(initial, DamperResult) else initial
        if not isinstance(state, DamperState):
            raise TypeError(f"initial must be None, a DamperResult or a DamperState, got "
                            f"{type(initial).__name__}")
        if state.state.shape != (eng.n,):
            raise ValueError(f"initial has {state.state.size} states, this damper's engine "
                             f"{eng.n}: it comes from another primary")
        self._check_start(eng, state)
        start = EngineState(state.time, state.state, state.mode, state.side,
                            state.open_impact)
        # the engine runs on a dimensionless form (impactpred.damper._engine), SI outside
        raw = run(eng, start=eng.to_engine(start), n_cycles=n_cycles, samples_per_cycle=spc,
                  progress=bool(progress))
        return build_result(self, eng.to_si(raw), n_cycles=n_cycles, samples_per_cycle=spc)
