"""``solve_impact``: the one entry point of the impact solvers."""

from __future__ import annotations

import math
import warnings

import numpy as np

from data_synth import ExactModel, Rod
from modalid import ModalModel
from modalid._checks import as_choice, as_positive_scalar, as_real_scalar

from .body import Body, SampledResponse
from .contact import Hertz, LinearSpring, Rigid, check_contact
from .solvers.closed_form import applies_closed_form, solve_closed_form
from .solvers.convolution import solve_convolution
from .solvers.laplace import solve_laplace
from .solvers.modal import solve_modal

__all__ = ["solve_impact", "choose_dt", "METHODS"]

METHODS = ("auto", "laplace", "modal", "convolution", "closed_form")

#: steps per fastest time scale that resolve duration and restitution to about 0.1 %
_STEPS_PER_SCALE = 1000
_MAX_STEPS = 4_000_000
#: output samples of the exact (laplace) solver per 1/omega of the fastest time scale
_LAPLACE_SAMPLES_PER_SCALE = 8


def solve_impact(body1: Body, body2: Body, *, gap: float = 0.0, contact=Rigid(),
                 t_end: float, dt: float | None = None, method: str = "auto"):
    """Predict the impact of two bodies touching at one point each.

    Parameters
    ----------
    body1, body2 : Body
        Body 1 approaches from below (``-y`` side); ``+y`` points from body 1 to body 2.
    gap : float, keyword-only
        Initial clearance ``g0 >= 0`` (m) between the contact points.
    contact : Rigid, LinearSpring or Hertz, keyword-only
        Contact law; ``Rigid()`` is the paper's.
    t_end : float, keyword-only
        End of the prediction (s): every contact, separation and re-contact up to it.
    dt : float or None, keyword-only
        Time step (s) of the time-stepping solvers, or the output step of the exact ones.
        ``None`` picks one from the bodies' time scales (see :func:`choose_dt`).
    method : {"auto", "laplace", "modal", "convolution", "closed_form"}, keyword-only
        ``"auto"``: the closed form for two free rods of equal transit time (without
        output points), the exact Laplace solver for rational models with a linear contact
        law and no load, the modal solver for other rational cases, the convolution solver
        otherwise.

    Returns
    -------
    ImpactResult
        With ``points``: a :class:`PointResponse` per body given with outputs
        (``Body(MultiOutputModalModel)`` or ``Body(Rod/CantileverBeam, outputs=xi)``).
    """
    for name, body in (("body1", body1), ("body2", body2)):
        if not isinstance(body, Body):
            raise TypeError(f"{name} must be an impactpred.Body, got {type(body).__name__}")
    gap = as_real_scalar("gap", gap)
    if gap < 0:
        raise ValueError(f"gap must be >= 0 (the bodies may not start overlapping), got {gap!r}")
    y1_0, y2_0 = float(body1.free_motion(0.0)), float(body2.free_motion(0.0))
    start_gap = gap + y2_0 - y1_0
    if start_gap < -1e-12 * max(abs(gap), abs(y1_0), abs(y2_0)):
        raise ValueError(f"the bodies start overlapping: gap + y2(0) - y1(0) = {start_gap!r} m "
                         f"< 0 (gap={gap!r}, contact-point displacements at t = 0 from "
                         f"displacement and vibration: y1(0)={y1_0!r}, y2(0)={y2_0!r})")
    contact = check_contact(contact)
    t_end = as_positive_scalar("t_end", t_end)
    if dt is not None:
        dt = as_positive_scalar("dt", dt)
    as_choice("method", method, METHODS)
    bodies = (body1, body2)
    chosen = _choose_method(bodies, contact, method)
    notes = []
    if dt is None:
        dt = choose_dt(bodies, contact, t_end=t_end, method=chosen)
        notes.append(f"dt chosen automatically: {dt:.6g} s")
    elif chosen in ("modal", "convolution"):
        recommended = choose_dt(bodies, contact, t_end=t_end, method=chosen)
        if dt > 20 * recommended:
            warnings.warn(f"dt={dt:.4g} s is {dt / recommended:.0f} times the step that "
                          f"resolves these bodies: expect contact duration and restitution "
                          f"errors of several per cent; dt={recommended:.4g} s would resolve "
                          "them to about 0.1 %", RuntimeWarning, stacklevel=2)
    solver = {"laplace": solve_laplace, "modal": solve_modal, "convolution": solve_convolution,
              "closed_form": solve_closed_form}[chosen]
    if chosen in ("modal", "convolution") and t_end / dt > _MAX_STEPS:
        raise ValueError(f"t_end/dt = {t_end / dt:.3g} steps exceeds {_MAX_STEPS}: increase dt "
                         "or shorten t_end")
    return solver(bodies, gap, contact, t_end, dt, notes=tuple(notes))


def _choose_method(bodies, contact, method):
    rational = all(b.is_rational for b in bodies)
    has_load = any(b.load is not None for b in bodies)
    linear = isinstance(contact, Rigid) or (isinstance(contact, LinearSpring)
                                            and contact.damping == 0.0)
    outputs = any(b.outputs is not None for b in bodies)
    if method == "auto":
        if applies_closed_form(bodies, contact) and not outputs:
            return "closed_form"
        if rational and linear and not has_load:
            return "laplace"
        return "modal" if rational else "convolution"
    if method in ("laplace", "modal") and not rational:
        names = [type(b.model).__name__ for b in bodies if not b.is_rational]
        raise ValueError(f"method={method!r} needs rational models (ModalModel, LumpedMass, "
                         f"SpringMass), got {', '.join(names)}: use method='convolution' or "
                         "give model.modal_model(n_modes, residual=True)")
    if method == "laplace" and not linear:
        raise ValueError(f"method='laplace' needs a linear contact law (Rigid or an undamped "
                         f"LinearSpring), got {contact!r}: use method='modal'")
    if method == "laplace" and has_load:
        raise ValueError("method='laplace' takes no external load: use method='modal'")
    if method == "closed_form" and not applies_closed_form(bodies, contact):
        raise ValueError("method='closed_form' applies to two free rods of equal transit time "
                         "with rigid contact and rigid-body motion only")
    if method == "closed_form" and outputs:
        raise ValueError("method='closed_form' gives no output points: use "
                         "method='convolution' (exact transfer responses of the rods)")
    return method


def _time_scales(body):
    """(time scale s, steps per scale) pairs of one body's own dynamics."""
    model = body.model
    if isinstance(model, SampledResponse):
        return [(float(np.min(np.diff(model.t))), 1)]
    if isinstance(model, ModalModel):
        # modes are discretised exactly: a few dozen steps per 1/omega_max suffice
        poles = np.concatenate([np.abs(model.poles), np.abs(model.real_poles)])
        return [(1.0 / float(np.max(poles)), 50)] if poles.size else []
    if isinstance(model, Rod):
        return [(model.transit_time, _STEPS_PER_SCALE)]
    if isinstance(model, ExactModel):
        try:
            omega_1 = float(model.natural_frequencies(1)[0])
        except ValueError:  # a lumped mass: no elastic time scale of its own
            return []
        return [(1.0 / omega_1, 50 if model.is_rational else _STEPS_PER_SCALE)]
    return []


def choose_dt(bodies, contact, *, t_end, method="convolution") -> float:
    """A step (s) that resolves contact duration and restitution to about 0.1 %.

    Each time scale gets its own number of steps: 1000 per rod transit time or beam
    ``1/omega_1`` (wave fronts are resolved only by the grid), 50 per ``1/omega`` of the
    fastest mode of a modal model (modes are discretised exactly), 300 per period scale
    of a compliant contact or of a residual flexibility against the bodies' masses, one
    per sample of a measured response. With rods, the step divides every transit time
    when it can, so that wave reflections fall on grid points.

    ``method="laplace"`` is exact at any step: its step only places the output samples,
    ``_LAPLACE_SAMPLES_PER_SCALE`` (8) per ``1/omega`` of the fastest time scale (about 50
    per period) and at least 200 over ``t_end``; the first contact's exact peak is added.
    """
    pairs = [p for b in bodies for p in _time_scales(b)]
    contact_scale = _contact_time_scale(bodies, contact)
    if contact_scale is not None:
        pairs.append((contact_scale, 300))
    pairs = [(s, n) for s, n in pairs if s > 0 and math.isfinite(s)]
    if not pairs:
        return t_end / 1000
    if method == "laplace":
        return max(min(min(s for s, _ in pairs) / _LAPLACE_SAMPLES_PER_SCALE, t_end / 200),
                   t_end / _MAX_STEPS)
    sampled = [float(np.min(np.diff(b.model.t))) for b in bodies
               if isinstance(b.model, SampledResponse)]
    dt = min(sampled) if sampled else min(s / n for s, n in pairs)
    rods = [b.model.transit_time for b in bodies if isinstance(b.model, Rod)]
    if rods and not sampled:
        dt = _aligned_step(rods, dt)
    return max(dt, t_end / _MAX_STEPS)


def _aligned_step(transit_times, dt):
    """The largest step <= ``dt`` dividing every transit time, else one dividing the shortest."""
    t_min = min(transit_times)
    n0 = math.ceil(t_min / dt - 1e-9)
    for n in range(n0, 4 * n0 + 1):
        ratios = [t * n / t_min for t in transit_times]
        if all(abs(r - round(r)) <= 1e-9 * r for r in ratios):
            return t_min / n
    return t_min / n0


def _effective_inverse_mass(body):
    """High-frequency ``1/m`` seen at the contact point (1/kg); 0 for a pure compliance."""
    model = body.model
    if isinstance(model, SampledResponse):
        return 0.0
    modal = body.modal_model(20) if not isinstance(model, ModalModel) else model
    inverse_masses = -2.0 * modal.poles.imag * modal.residues.imag   # 1/modal_mass
    return modal.inverse_mass + float(np.sum(inverse_masses[inverse_masses > 0]))


def _contact_time_scale(bodies, contact):
    """``sqrt(m_eff/k)`` of the stiffness that closes the contact, or None.

    The stiffness is the contact's own (spring; Hertz at its peak) or, for rigid contact,
    that of the bodies' residual flexibility; ``m_eff`` comes from the bodies'
    high-frequency inverse masses.
    """
    inv = sum(_effective_inverse_mass(b) for b in bodies)
    if inv <= 0:
        return None
    m_eff = 1.0 / inv
    if isinstance(contact, LinearSpring):
        return math.sqrt(m_eff / contact.stiffness)
    if isinstance(contact, Hertz):
        v = abs(bodies[0].velocity - bodies[1].velocity) or 1.0
        depth = (5 * m_eff * v**2 / (4 * contact.stiffness)) ** (1 / (contact.exponent + 1))
        return depth / v
    # rounding-level flexibilities (e.g. left by a continuation) are no compliance
    flex = sum(b.model.flexibility for b in bodies if isinstance(b.model, ModalModel)
               and b.model.flexibility > 1e-9 * abs(b.model.static_flexibility()))
    return math.sqrt(m_eff * flex) if flex > 0 else None
