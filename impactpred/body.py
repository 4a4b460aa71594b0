"""A body taking part in an impact: its driving-point model and its motion before contact."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from modalid import ModalModel, MultiOutputModalModel
from modalid.receptance import Receptance
from modalid.validation import as_real_array, as_real_scalar

from .result import ReadOnlyArrays
from .sampled import SampledResponse

__all__ = ["Body", "SampledResponse", "check_driving_point", "driving_point_problems"]

#: a mode whose shares of the model's inverse mass and static flexibility are both below
#: this is negligible (e.g. an identified pseudo-mode with a rounding-level residue): it
#: cannot change an impact by more than that share, so its sign is not judged
NEGLIGIBLE_SHARE = 1e-6

#: a mobility whose real part (conductance) falls below minus this share of its largest
#: value somewhere is not passive: the body can give back more energy than it received.
#: Each term of a model made of normal modes (``Re r = 0``, ``Im r <= 0``), positive
#: real-pole residues, mass line and flexibility has a conductance >= 0; a mode with a
#: real residue ``a`` and ``Im r = b`` has one that changes sign unless
#: ``0 <= a <= 2 zeta |b|`` roughly (a pseudo-mode with ``a = 50 |b|`` gave a restitution
#: of 2.8). An identified model for an impact (``truncation.identified_model``: normal
#: modes) has none; a fit's raw ``model_`` may (its residues' real parts)
NEGATIVE_CONDUCTANCE = 1e-3

_WHAT_TO_DO = ("What to do: a transfer FRF is not a driving point: a body needs its "
               "driving-point receptance (force and response at the contact point, same "
               "direction); check the FRF's sign and quantity; refit the band (a passive fit "
               "keeps modal masses positive, e.g. modalid.ModalFit(passive=True))")


#: m/s: no velocity of a body reaches it (a linear elastic model fails far below)
_SPEED_OF_LIGHT = 299_792_458.0


@dataclass(frozen=True, eq=False, repr=False)
class Body(ReadOnlyArrays):
    """One of the two colliding bodies.

    Parameters
    ----------
    model : ModalModel, MultiOutputModalModel, data_synth model or SampledResponse
        Driving-point receptance at the contact point (m/N); a SISO python-control
        system (``control.tf``, ``control.ss``) is read by ``ModalModel.from_control``. A
        ``modalid.MultiOutputModalModel`` gives its driving row (stored in ``model``) and
        its rows as output points (then ``outputs`` must be None).
    velocity : float, keyword-only
        Rigid-body velocity before impact (m/s) along ``+y`` (from body 1 towards body 2).
        A grounded body (no rigid-body mode) must have 0.
    displacement : float, keyword-only
        Rigid-body displacement of the contact point at ``t = 0`` (m).
    vibration : array_like, shape (n, 2), keyword-only
        Vibration present at ``t = 0``: for each of the model's ``n`` lowest modes, its
        contribution to the contact point's displacement (m) and velocity (m/s).
    load : HarmonicForce, callable or (t, f) pair, keyword-only
        External force (N) on the body at the contact point, along ``+y``: a
        :class:`~impactpred.HarmonicForce` (propagated in closed form by the exact
        method, which ``method="auto"`` picks for it), a vectorised callable ``load(t)``
        or samples ``(t, f)`` (linear between samples, 0 outside), which the
        time-stepping solvers take.
    outputs : array_like, shape (n_points,), keyword-only
        For a ``data_synth`` ``Rod`` or ``CantileverBeam`` only: positions ``xi`` of output
        points as fractions of the length measured from the driving point (0 = the
        driving point, 1 = the far end). :attr:`ImpactResult.points` then holds their
        displacement, velocity and acceleration along ``y``.
    check_passive : bool, keyword-only
        Refuse a modal model that is not a stable, passive driving point (see
        :func:`check_driving_point`): a pole with ``Re p > 0``, a mode with a negative or
        non-finite modal mass, a negative ``inverse_mass``, ``flexibility`` or real
        residue (of a ``MultiOutputModalModel``: its driving-point row; ``data_synth``
        models are passive by construction). Such a model can put energy into the impact
        from nowhere. ``False`` skips the check, for
        a model you can justify (e.g. a deliberately active element); the result's
        :attr:`~ImpactResult.energy_audit` still reports any energy created. A negative
        rigid-body term ``1/M`` is refused either way (no rigid-body energy without it).

    Attributes
    ----------
    outputs : MultiOutputModalModel, ndarray or None
        The output points: the multi-output model, the positions ``xi``, or None.

    Notes
    -----
    Rigid-body motion of output points: a multi-output model's rigid term is one rigid
    mode, so point ``i`` moves rigidly by ``inverse_mass_i / inverse_mass`` times the
    driving point's rigid motion (``displacement``, ``velocity``); a rod translates as a
    whole.
    """

    model: Any
    velocity: float = 0.0
    displacement: float = 0.0
    vibration: Any = None
    load: Any = None
    outputs: Any = None
    check_passive: bool = True

    def __init__(self, model, *, velocity=0.0, displacement=0.0, vibration=None, load=None,
                 outputs=None, check_passive=True):
        model, outputs = _split_outputs(control_as_model(model), outputs)
        if isinstance(model, type):
            raise TypeError(f"model must be a model object, got the class {model.__name__}: "
                            f"build one, e.g. {model.__name__}(...)")
        if not isinstance(model, Receptance):
            raise TypeError(f"model must be a ModalModel, a MultiOutputModalModel, a data_synth "
                            f"model, a SampledResponse (a modalid.receptance.Receptance) or a "
                            f"SISO python-control system, got {type(model).__name__}")
        if not isinstance(check_passive, bool):
            raise TypeError(f"check_passive must be True or False, got {check_passive!r}")
        if check_passive and isinstance(model, ModalModel):
            check_driving_point(model, name="the body's model",
                                opt_out="to use it anyway, check_passive=False")
        velocity = as_real_scalar("velocity", velocity)
        displacement = as_real_scalar("displacement", displacement)
        if abs(velocity) >= _SPEED_OF_LIGHT:         # the arithmetic overflows long before
            raise ValueError(f"velocity must be under the speed of light (3e8 m/s), got "
                             f"{velocity!r}")
        if model.inverse_mass < 0.0:
            raise ValueError(f"model is not a driving-point receptance: its rigid-body term "
                             f"1/M = {model.inverse_mass!r} is negative")
        if model.inverse_mass == 0.0 and velocity != 0.0:
            raise ValueError(f"a grounded body (no rigid-body mode) cannot have a rigid-body "
                             f"velocity, got velocity={velocity!r}")
        if model.inverse_mass == 0.0 and displacement != 0.0:
            raise ValueError(f"a grounded body cannot have a rigid-body displacement, got "
                             f"displacement={displacement!r}: use the gap")
        if vibration is not None:
            if isinstance(model, SampledResponse):
                raise ValueError("vibration needs modes: a SampledResponse has none; give the "
                                 "free motion as a load or identify a ModalModel")
            vibration = as_real_array("vibration", vibration)
            if vibration.ndim != 2 or vibration.shape[1] != 2:
                raise ValueError(f"vibration must have shape (n_modes, 2) (displacement, "
                                 f"velocity per mode), got shape {vibration.shape}")
            if getattr(model, "is_rational", False):     # a finite count of modes
                available = model.modal_form(None).n_modes
                rows = vibration.shape[0]
                if rows > available:
                    raise ValueError(f"vibration gives {rows} row{'s' * (rows != 1)} (one "
                                     f"per mode) but the model has {available} mode"
                                     f"{'s' * (available != 1)}")
            vibration = np.array(vibration)
            vibration.setflags(write=False)
        if load is not None:
            load = _as_load(load)
        for name, value in (("model", model), ("velocity", velocity),
                            ("displacement", displacement), ("vibration", vibration),
                            ("load", load), ("outputs", outputs),
                            ("check_passive", check_passive)):
            object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ queries
    @property
    def output_labels(self) -> tuple | None:
        """Labels of the output points (None without outputs)."""
        if self.outputs is None:
            return None
        if isinstance(self.outputs, MultiOutputModalModel):
            return self.outputs.outputs
        labels = tuple(f"xi={x:g}" for x in self.outputs)
        return labels if len(set(labels)) == len(labels) else tuple(
            f"xi={x!r}" for x in self.outputs.tolist())

    @property
    def inverse_mass(self) -> float:
        """``1/M`` of the rigid-body mode (1/kg); 0 for a grounded body."""
        return float(self.model.inverse_mass)

    @property
    def is_rational(self) -> bool:
        """True when the model is a finite pole-residue receptance (Laplace solver applies)."""
        return bool(self.model.is_rational)

    def modal_model(self, n_modes: int | None = None) -> ModalModel:
        """The body's model as a ``ModalModel`` (exact for rational models).

        For a continuum, ``n_modes`` modes plus the residual flexibility are used.

        Parameters
        ----------
        n_modes : int, optional
            Modes of a continuum's truncated form (ignored by rational models).

        Returns
        -------
        modalid.ModalModel
        """
        return self.model.modal_form(n_modes)

    def step_response(self, t) -> np.ndarray:
        """Exact step response (m/N) of the model (``S(0+)`` includes any flexibility).

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        return self.model.step_response(t)

    def vibration_modes(self) -> ModalModel | None:
        """Modal model of the modes that carry :attr:`vibration` (None without vibration).

        Returns
        -------
        modalid.ModalModel or None
        """
        if self.vibration is None:
            return None
        n = self.vibration.shape[0]
        modes = self.model.modal_form(n)
        if n > modes.n_modes:
            raise ValueError(f"vibration gives {n} modes but the model has {modes.n_modes}")
        return modes.truncate(n).without_rigid_body().replace(
            flexibility=0.0, real_poles=(), real_residues=())

    def initial_modal_states(self) -> tuple | None:
        """Complex modal states ``z_k`` (``z' = p z + u``, ``y = 2 Re(r z)``) of
        :attr:`vibration`.

        Returns
        -------
        tuple of numpy.ndarray or None
            ``(p, r, z)``: the vibrating modes' poles (rad/s), residues and states; None
            without vibration.
        """
        modes = self.vibration_modes()
        if modes is None:
            return None
        table_order = np.argsort(np.abs(modes.poles), kind="stable")
        p, r = modes.poles[table_order], modes.residues[table_order]
        q, qdot = self.vibration[:, 0], self.vibration[:, 1]
        # 2 Re(r z) = q and 2 Re(r p z) = qdot, with z = x1 + i x2
        a11, a12 = 2 * r.real, -2 * r.imag
        rp = r * p
        a21, a22 = 2 * rp.real, -2 * rp.imag
        det = a11 * a22 - a12 * a21
        x1 = (q * a22 - a12 * qdot) / det
        x2 = (a11 * qdot - a21 * q) / det
        return p, r, x1 + 1j * x2

    def vibration_energy(self) -> float:
        """Energy (J) of the initial vibration: ``sum 1/2 m_k (qdot^2 + omega_k^2 q^2)``.

        Returns
        -------
        float
            Energy (J).
        """
        modes = self.vibration_modes()
        if modes is None:
            return 0.0
        table = modes.modes
        q, qdot = self.vibration[:, 0], self.vibration[:, 1]
        m, w = table["modal_mass"].to_numpy(), table["omega_n"].to_numpy()
        return float(np.sum(0.5 * m * (qdot**2 + w**2 * q**2)))

    def free_motion(self, t) -> np.ndarray:
        """Contact-point displacement (m) with no contact force and no load, at ``t`` (s).

        Rigid translation plus the free decay of :attr:`vibration`, in closed form.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = np.asarray(t, dtype=float)
        y = self.displacement + self.velocity * t
        states = self.initial_modal_states()
        if states is not None:
            p, r, z0 = states
            y = y + 2.0 * np.sum((r * z0 * np.exp(p * t[..., None])).real, axis=-1)
        return y

    def load_direct_term(self) -> tuple[float, float]:
        """``(d, F(0))``: the flexibility term ``d`` (m/N) through which a rational model's
        load moves the contact point at once, and the load at ``t = 0`` (N). ``(0.0, 0.0)``
        without a load; ``d = 0`` for a non-rational model (a continuum's response has no
        instantaneous term). ``d F(0)`` is the contact point's displacement from it at
        ``t = 0``, ``d F(0)^2 / 2`` the strain energy it holds there.

        Returns
        -------
        tuple of float
        """
        if self.load is None:
            return 0.0, 0.0
        d = self.modal_model().flexibility if self.is_rational else 0.0
        return float(d), float(self.load_samples(np.zeros(1))[0])

    def load_samples(self, t) -> np.ndarray:
        """External force (N) at times ``t``; zeros without a load.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = np.asarray(t, dtype=float)
        if self.load is None:
            return np.zeros_like(t)
        values = np.asarray(self.load(t), dtype=float)
        if values.shape != t.shape or not np.all(np.isfinite(values)):
            raise ValueError(f"load(t) must return finite values of shape {t.shape}, got "
                             f"shape {values.shape}")
        return values


def driving_point_problems(model: ModalModel) -> list:
    """Why ``model`` cannot be a driving-point receptance: one sentence per fault.

    Parameters
    ----------
    model : ModalModel
        Pole-residue receptance (m/N).

    Returns
    -------
    list of str
        Empty for a stable, passive driving point. Faults: a pole with ``Re p > 0``
        (unstable) or a real pole ``>= 0``; a mode whose modal mass
        ``-1/(2 Im p Im r)`` (kg) is negative or not finite; a negative real residue, rigid
        term ``inverse_mass`` (1/kg) or ``flexibility`` (m/N); where none of these, a
        mobility whose real part is negative somewhere (below
        :data:`NEGATIVE_CONDUCTANCE` of its largest).

    Notes
    -----
    The conditions of :meth:`modalid.ModalModel.is_passive` and the mobility's real part
    (which ``is_passive`` does not sample: a fit's raw ``model_`` can pass it and fail
    here; give ``impactpred.truncation.identified_model(fit)``), except that a mode
    whose shares of the model's inverse mass ``sum |2 Im p Im r|`` and static flexibility
    ``sum |r/p|`` are both below :data:`NEGLIGIBLE_SHARE` is not judged: a pseudo-mode with
    a rounding-level residue has an undefined (infinite) modal mass of either sign and no
    effect on an impact.
    """
    problems = []
    p, r = model.poles, model.residues
    inverse_share = np.abs(2.0 * p.imag * r.imag)
    static_share = np.abs(r / p)
    negligible = ((inverse_share <= NEGLIGIBLE_SHARE * (np.sum(inverse_share)
                                                        + abs(model.inverse_mass)))
                  & (static_share <= NEGLIGIBLE_SHARE * (np.sum(static_share)
                                                         + abs(model.flexibility))))
    with np.errstate(divide="ignore"):
        modal_mass = -1.0 / (2.0 * p.imag * r.imag)
    for k in np.argsort(np.abs(p), kind="stable"):
        where = f"the mode at {abs(p[k]) / (2 * np.pi):.6g} Hz"
        if p[k].real > 0.0:
            problems.append(f"{where} is unstable (Re p = {p[k].real:.4g} rad/s > 0: it "
                            "grows without a force)")
        elif not negligible[k] and not (np.isfinite(modal_mass[k]) and modal_mass[k] > 0.0):
            hint = (" (a residue with no imaginary part: a mobility or an accelerance "
                    "given as a receptance?)" if r[k].imag == 0.0 else "")
            problems.append(f"{where} has modal mass {modal_mass[k]:.4g} kg (residue "
                            f"{r[k].real:.4g}{r[k].imag:+.4g}j): not positive, a mode that "
                            f"gives back energy it never received{hint}")
    for sigma, a in zip(model.real_poles, model.real_residues):
        if sigma >= 0.0:
            problems.append(f"the real pole {sigma:.4g} rad/s is unstable (>= 0)")
        elif a < 0.0:
            problems.append(f"the real pole {sigma:.4g} rad/s has a negative residue {a:.4g}")
    if model.inverse_mass < 0.0:
        problems.append(f"its rigid-body term 1/M = {model.inverse_mass:.4g} 1/kg is negative")
    if model.flexibility < 0.0:
        problems.append(f"its residual flexibility {model.flexibility:.4g} m/N is negative")
    if not problems:
        worst = _negative_conductance(model)
        if worst is not None:
            problems.append(f"its mobility's real part is {worst[1]:.4g} s/kg at "
                            f"{worst[0]:.6g} Hz ({worst[1] / worst[2]:.2g} of its largest "
                            "magnitude): "
                            "not passive, the body can give back more energy than it "
                            "received (a mode's residue with a real part out of proportion "
                            "to its imaginary part; for a fitted model, predict from its FRF "
                            "file, which takes the fit's normal modes)")
    return problems


def _negative_conductance(model: ModalModel):
    """``(freq_hz, value, largest)`` where the mobility's real part is most negative, if
    below :data:`NEGATIVE_CONDUCTANCE` times its largest magnitude; else None. Sampled at
    each mode's resonance and 0.25-16 half-power bandwidths either side, and on a
    logarithmic grid from 1/100 of the lowest pole to 100 times the highest (a few
    thousand evaluations)."""
    p = model.poles
    if p.size == 0:
        return None
    offsets = np.concatenate([-np.geomspace(0.25, 16, 7)[::-1], [0.0], np.geomspace(0.25, 16, 7)])
    damped = p.real < 0                    # an undamped mode's conductance is a Dirac
    near = (p.imag[damped, None] + np.abs(p.real[damped, None]) * offsets).ravel()
    w = np.abs(p)
    omega = np.concatenate([near[near > 0], np.geomspace(w.min() / 100, w.max() * 100, 400)])
    omega = omega[np.min(np.abs(omega[:, None] - p.imag[None, :]), axis=1) > 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        conductance = model.frf(omega, quantity="mobility").real
    finite = np.isfinite(conductance)
    omega, conductance = omega[finite], conductance[finite]
    if conductance.size == 0:
        return None
    largest = float(np.max(np.abs(conductance)))
    k = int(np.argmin(conductance))
    if conductance[k] >= -NEGATIVE_CONDUCTANCE * largest:
        return None
    return float(omega[k] / (2 * np.pi)), float(conductance[k]), largest


def control_as_model(model):
    """A python-control LTI system as its ``ModalModel`` (``ModalModel.from_control``, which
    refuses what is not a receptance: MIMO, discrete time, a simple pole at 0 ...);
    anything else unchanged."""
    if type(model).__module__.split(".")[0] != "control":
        return model
    import control

    return ModalModel.from_control(model) if isinstance(model, control.LTI) else model


def check_driving_point(model, *, name: str = "model", opt_out: str = "") -> None:
    """Raise ``ValueError`` unless ``model`` is a stable, passive driving point.

    Parameters
    ----------
    model : ModalModel or MultiOutputModalModel
        Receptance (m/N); of a multi-output model, its driving-point row is checked.
    name : str, keyword-only
        What to call the model in the message (e.g. ``"the primary"``).
    opt_out : str, keyword-only
        How the caller's user can skip the check, appended to the message (none if empty).

    Raises
    ------
    ValueError
        Naming each faulty mode (frequency in Hz) and why (see
        :func:`driving_point_problems`), and what to do about it.
    """
    if isinstance(model, MultiOutputModalModel):
        model = model.driving
    problems = driving_point_problems(model)
    if problems:
        raise ValueError(f"{name} is not a stable, passive driving-point receptance: "
                         f"{'; '.join(problems)}. {_WHAT_TO_DO}"
                         + (f"; {opt_out}" if opt_out else ""))


def _split_outputs(model, outputs):
    """``(driving model, outputs)`` from the constructor's ``model`` and ``outputs``."""
    if isinstance(model, MultiOutputModalModel):
        if outputs is not None:
            raise ValueError("a MultiOutputModalModel carries its own outputs (its rows): "
                             "give outputs=None")
        inv = model.inverse_mass
        if inv[model.driving_point] == 0.0 and np.any(inv != 0.0):
            raise ValueError("the driving point has no rigid-body term (1/M = 0) but other "
                             f"outputs have one ({inv.tolist()}): a force at the driving point "
                             "cannot move them rigidly; the model is inconsistent")
        return model.driving, model
    if outputs is None:
        return model, None
    if not hasattr(model, "transfer_step_response"):
        raise TypeError(f"outputs (positions xi along the length) apply to a data_synth Rod or "
                        f"CantileverBeam, got a {type(model).__name__}: for a modal model give "
                        "a modalid.MultiOutputModalModel with one row per output point")
    xi = as_real_array("outputs", outputs)
    if xi.ndim != 1 or xi.size == 0:
        raise ValueError(f"outputs must be a non-empty 1-D array of positions xi, got shape "
                         f"{xi.shape}")
    if np.any((xi < 0.0) | (xi > 1.0)):
        raise ValueError(f"outputs positions xi must lie in [0, 1] (fractions of the length "
                         f"from the driving point), got {xi.tolist()}")
    if np.unique(xi).size != xi.size:
        raise ValueError(f"outputs positions must be distinct, got {xi.tolist()}")
    xi = np.array(xi)
    xi.setflags(write=False)
    return model, xi


def _as_load(load):
    if callable(load):
        return load
    try:
        t, f = load
    except (TypeError, ValueError) as exc:
        raise TypeError(f"load must be a callable load(t) or a pair (t, f), got "
                        f"{type(load).__name__}") from exc
    t = as_real_array("load t", t, ndim=1)
    f = as_real_array("load f", f, ndim=1)
    if t.shape != f.shape or np.any(np.diff(t) <= 0):
        raise ValueError(f"load (t, f) must be samples of equal shape with increasing t, got "
                         f"shapes {t.shape} and {f.shape}")
    return SampledLoad(t, f)


class SampledLoad:
    """A load given as samples ``(t, f)`` (s, N): linear between them, zero outside.

    Callable like any load; :meth:`impulse` integrates it exactly.
    """

    def __init__(self, t, f):
        self.t, self.f = t, f

    def __call__(self, tt):
        return np.interp(tt, self.t, self.f, left=0.0, right=0.0)

    def impulse(self, a, b) -> float:
        """``int_a^b f dt`` (N s) of the piecewise-linear load, exactly."""
        inside = self.t[(self.t > a) & (self.t < b)]
        knots = np.concatenate([[a], inside, [b]])
        return float(np.trapezoid(self(knots), knots))
