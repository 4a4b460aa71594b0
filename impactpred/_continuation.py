"""The continuation of a driving-point model above its band: its high-frequency
conductance from the top modes, and the passive tails built from it (the smooth tail,
the tail along a thinning pattern, the single real pole). The method and its numbers
are described in :mod:`impactpred.truncation`, which exports these names.
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass

import numpy as np
from modalid import ModalModel

from ._pattern_tail import PATTERN_BETA, compliance_beyond, growth_pattern, pattern_tail
from ._smooth_tail import smooth_tail_design

__all__ = ["ContinuationInfo", "continue_above_band", "high_frequency_conductance",
           "pattern_share", "static_compliance", "above_band"]


def above_band(poles, band_top_hz):
    """Which ``poles`` lie above the band top (Hz): the fit's pseudo-modes there."""
    return np.abs(poles) > 2 * math.pi * band_top_hz * (1 + 1e-9)


def static_compliance(poles, residues):
    """Each mode's static compliance ``-2 Re(r/p)`` (m/N): its share of the receptance
    at ``s = 0``, by which a pseudo-mode is folded into a residual flexibility."""
    return -2.0 * (np.asarray(residues) / np.asarray(poles)).real


#: lowest allowed sigma, in units of omega_top: below it the term would reach into the band
_SIGMA_MIN = 1.0

#: synthesized modes stop where the compliance left would put sigma above this x omega
_SIGMA_EXTEND = 2.0


@dataclass(frozen=True)
class ContinuationInfo:
    """How a continuation was built (all SI; rad/s for frequencies).

    Parameters
    ----------
    conductance : float
        ``G`` (s/kg).
    sigma : float
        The real pole ``-sigma`` (1/s).
    omega_top : float
        Highest mode kept, synthesized ones included (rad/s).
    mode_spacing : float
        ``dw`` of the top modes (rad/s).
    modal_mass : float
        Mean modal mass of the top modes (kg).
    upper_flexibility : float
        Upper residual flexibility before (m/N).
    flexibility_after : float
        What is left as constant flexibility (m/N).
    folded_modes : int
        Pseudo-modes above the band folded into the flexibility.
    note : str
        A note for the summary.
    tail : {"pole", "smooth", "pattern"}
        The tail's kind (see :func:`continue_above_band`; ``"pattern"``: the smooth tail
        of modes that thin out, continued mode by mode).
    highest_rate : float
        Largest ``|pole|`` of the continuation (rad/s): the solver's cost.
    scale : float
        The smooth tail's conductance (its ``h(0+)``) over ``G``.
    """

    conductance: float          # G (m/(N s) = s/kg)
    sigma: float                # real pole -sigma (1/s)
    omega_top: float            # highest mode kept, synthesized ones included (rad/s)
    mode_spacing: float         # dw of the top modes (rad/s)
    modal_mass: float           # mean modal mass of the top modes (kg)
    upper_flexibility: float    # upper residual flexibility before (m/N)
    flexibility_after: float    # what is left as constant flexibility (m/N)
    folded_modes: int           # pseudo-modes above the band folded into flexibility
    note: str = ""
    tail: str = "pole"          # "pole" or "smooth" (see continue_above_band)
    highest_rate: float = 0.0   # largest |pole| of the continuation (rad/s): solver cost
    scale: float = 1.0          # smooth tail's conductance / G (upper flexibility short)


def _physical_modes(model: ModalModel, band_top_hz: float):
    """Modes table sorted by frequency, split into in-band and above-band parts."""
    modes = model.modes
    above = modes["frequency_hz"].to_numpy() > band_top_hz * (1 + 1e-9)
    return modes[~above], modes[above]


#: a mode whose modal mass exceeds this many times the median of the band's modes is weakly
#: coupled at the point (a noise pole, or a mode with a node there): it stays in the model
#: but not in the top modes' pattern (spacing, mass, damping) the continuation extends. A
#: steel beam's fit at 10 modes and 5 % noise had one at 7854 Hz (modal mass 41 for 0.39)
#: between modes 9 and 10: taken as a top mode, it halved the spacing and the ball's
#: restitution came out 8.7 % low (1.4 % high without it)
_WEAK_MODE = 10.0


def _pattern_modes(inside):
    """The modes of positive modal mass within :data:`_WEAK_MODE` times their median."""
    mass = inside["modal_mass"].to_numpy()
    positive = mass > 0
    if not positive.any():
        return inside[positive]
    return inside[positive & (mass <= _WEAK_MODE * float(np.median(mass[positive])))]


def high_frequency_conductance(model: ModalModel, band_top_hz: float, *, n_top: int = 3):
    """``(G, omega_top, dw, m_k)`` from the ``n_top`` highest modes inside the band.

    ``G = pi / (2 m_k dw)``: the mean modal mass of the top modes and their mean spacing
    (``n_top`` modes give ``n_top - 1`` spacings; with fewer than 2 modes in the band the
    spacing is taken as the top mode's frequency, i.e. modes evenly spaced from 0).

    Parameters
    ----------
    model : ModalModel
        The identified model.
    band_top_hz : float
        Top of the band it was identified on (Hz).
    n_top : int, keyword-only
        How many of the highest in-band modes to average.

    Returns
    -------
    tuple of float
        ``G`` (s/kg), ``omega_top`` (rad/s), ``dw`` (rad/s), ``m_k`` (kg).
    """
    inside, _ = _physical_modes(model, band_top_hz)
    inside = _pattern_modes(inside)
    if inside.empty:
        raise ValueError("no passive mode inside the band: nothing to continue from")
    n_top = max(int(n_top), 1)
    top = inside.iloc[-min(n_top, len(inside)):]
    omega = top["omega_n"].to_numpy()
    if omega.size >= 2:
        dw = float(np.mean(np.diff(omega)))
    else:
        below = inside["omega_n"].to_numpy()
        dw = float(below[-1] - below[-2]) if below.size >= 2 else float(omega[-1])
    # average conductance per unit frequency: pi/(2 m_k) per mode over dw
    mk = float(1.0 / np.mean(1.0 / top["modal_mass"].to_numpy()))
    return math.pi / (2.0 * mk * dw), float(omega[-1]), dw, mk


def continue_above_band(model: ModalModel, band_top_hz: float, *, n_top: int = 3,
                        extend: float = 16.0, fold_pseudo_modes: bool = True,
                        return_info: bool = False, tail: str = "smooth"):
    """``model`` plus a passive high-frequency continuation term above ``band_top_hz``.

    Parameters
    ----------
    model : ModalModel
        An identified (or truncated) driving-point model.
    band_top_hz : float
        Top of the band the model describes (Hz), e.g. ``fit.report_["band_hz"][1]``.
    n_top : int
        Number of top in-band modes whose modal mass and spacing give ``G``.
    extend : float
        Continue the top modes' pattern (same modal mass, spacing and damping) with
        synthesized modes up to ``extend`` times the top mode's frequency, as long as the
        upper residual flexibility can pay for them; the real pole then sits beyond them,
        where its damping no longer shows in the band. ``1``: the real pole alone.
        With ``tail="smooth"`` the synthesized modes run to ``extend omega_a``
        (``omega_a = omega_top + dw/2``) with tapered weights.
    fold_pseudo_modes : bool
        Replace modes above ``band_top_hz`` (pseudo-modes of the fit) by their static
        flexibility before building the continuation.
    return_info : bool
        Also return a :class:`ContinuationInfo`.
    tail : {"smooth", "pole"}
        ``"smooth"``: the minimax passive fit of the omitted modes' continuum
        (:func:`smooth_tail_design`): tapered synthesized modes, damped modes and a real
        pole, all positive; for top modes that thin out (a beam), their pattern
        continued mode by mode and one real pole (see the module docstring).
        ``"pole"``: the synthesized modes at full weight, then one real pole (the earlier
        default; it overshoots a step in force by about 30 %).

    Returns
    -------
    ModalModel (and ContinuationInfo)
        ``"pole"``: the same model with the synthesized modes, one more real pole
        ``G/(s + sigma)`` and the upper residual flexibility reduced by their compliance
        (kept >= 0). ``"smooth"``: the model with the design's terms scaled by
        ``omega_a`` and ``G``, the upper residual flexibility reduced by the omitted modes'
        compliance ``2G/(pi omega_a)``; when the upper residual flexibility is smaller
        (the omitted modes thin out, as a beam's), the tail's conductance is scaled down
        (to at least ``G/4``) until it fits. Static flexibility unchanged, except where
        the upper residual flexibility cannot pay (a warning says so).
    """
    if not isinstance(model, ModalModel):
        raise TypeError(f"model must be a ModalModel, got {type(model).__name__}")
    if not (isinstance(extend, numbers.Real) and math.isfinite(extend) and extend > 0):
        raise ValueError(f"extend must be a positive finite number, got {extend!r}")
    band_top_hz = float(band_top_hz)
    if not band_top_hz > 0:
        raise ValueError(f"band_top_hz must be positive, got {band_top_hz!r}")
    G, omega_top, dw, mk = high_frequency_conductance(model, band_top_hz, n_top=n_top)
    poles, residues = model.poles, model.residues
    flexibility = model.flexibility
    folded = 0
    if fold_pseudo_modes:
        above = above_band(poles, band_top_hz)
        if np.any(above):
            flexibility += float(np.sum(static_compliance(poles[above], residues[above])))
            poles, residues = poles[~above], residues[~above]
            folded = int(np.sum(above))
    upper = flexibility
    # synthesized modes continuing the top modes' pattern up to extend * omega_top
    inside, _ = _physical_modes(ModalModel(poles=poles, residues=residues), band_top_hz)
    top = _pattern_modes(inside).iloc[-max(int(n_top), 1):]
    zeta = float(np.median(top["damping_ratio"].to_numpy()))
    if tail == "smooth":
        return _smooth_continuation(model, poles, residues, upper, G, omega_top, dw, mk,
                                    zeta, extend, folded, return_info,
                                    top["omega_n"].to_numpy())
    if tail != "pole":
        raise ValueError(f"tail must be 'smooth' or 'pole', got {tail!r}")
    extra_w = []
    w = omega_top + dw
    while w <= extend * omega_top * (1 + 1e-12):
        if upper - 1.0 / (mk * w * w) < G / (_SIGMA_EXTEND * w):
            break                      # keep enough compliance for the far term
        extra_w.append(w)
        upper -= 1.0 / (mk * w * w)
        w += dw
    if extra_w:
        extra = ModalModel.from_modes(np.array(extra_w), zeta, mk)
        poles = np.concatenate([poles, extra.poles])
        residues = np.concatenate([residues, extra.residues])
        omega_top = extra_w[-1]
    sigma_min = _SIGMA_MIN * omega_top
    note = ""
    if upper <= 0:
        # nothing to take the static compliance from: keep the term's compliance tiny
        sigma = 0.5 * math.pi * omega_top
        note = ("no upper residual flexibility to draw from: continuation rate set to "
                "(pi/2) omega_top, the rod's value; static flexibility grows by G/sigma")
        flex_after = max(upper, 0.0)
    else:
        sigma = G / upper
        if sigma < sigma_min:
            sigma = sigma_min
            note = (f"upper residual flexibility {upper:.4g} exceeds G/omega_top: sigma held "
                    "at omega_top, the rest stays as constant flexibility")
        flex_after = max(upper - G / sigma, 0.0)
    out = ModalModel(poles=poles, residues=residues,
                     real_poles=np.concatenate([model.real_poles, [-sigma]]),
                     real_residues=np.concatenate([model.real_residues, [G]]),
                     inverse_mass=model.inverse_mass, flexibility=flex_after)
    if note:
        warnings.warn(note, RuntimeWarning, stacklevel=2)
    if return_info:
        return out, ContinuationInfo(G, sigma, omega_top, dw, mk, upper, flex_after,
                                     folded, note, "pole", max(sigma, omega_top))
    return out


#: the smooth tail's conductance is scaled down to at least this share of G when the upper
#: residual flexibility is short (a structure whose modes thin out, as a beam's: scaling
#: keeps the tail's frequencies, a beam's next modes are only 20 % apart at 10 modes);
#: beyond, the static flexibility grows
_MIN_SCALE = 0.25

#: shortfalls of the upper residual flexibility below this share of the continuum's (the
#: midpoint rule's 1/(12 n^2) for a rod) are taken from the strongest real pole instead
_SCALE_TOLERANCE = 0.01


def pattern_share(omega, omega_a: float, dw: float, *, n_sum: int = 4000) -> float:
    """The omitted modes' compliance over the uniform continuum's ``2G/(pi omega_a)``, from
    the top modes' pattern.

    ``omega`` (rad/s, ascending, >= 3 values): the top in-band modes' frequencies. Their
    spacing is taken to grow like ``omega**beta`` (``beta = 0``: a rod, evenly spaced;
    ``1/2``: a beam, ``omega_k ~ k^2``), so that ``omega**(1 - beta)`` grows linearly with
    the mode index; the modes are continued so at the top modes' modal mass, and their
    compliance ``sum 1/(m omega_j^2)`` (``n_sum`` modes, then the integral) is divided by
    ``1/(m dw omega_a)``, the uniform continuum's. 1 for evenly spaced modes (fewer than 3
    values, or a spacing that shrinks, give 1); about 2/3 for a beam. Exact for modes
    that follow the pattern, an extrapolation otherwise.

    Parameters
    ----------
    omega : array_like of float
        The top in-band modes' natural frequencies (rad/s), ascending.
    omega_a : float
        Where the continuation starts (rad/s).
    dw : float
        The top modes' mean spacing (rad/s).
    n_sum : int, keyword-only
        Modes summed before the integral takes over.

    Returns
    -------
    float
        The compliance ratio (1 for evenly spaced modes).
    """
    pattern = growth_pattern(omega)
    if pattern is None:
        return 1.0
    _, q, growth = pattern
    compliance = compliance_beyond(float(np.asarray(omega, dtype=float)[-1]), q, growth,
                                   n_sum=n_sum)
    return float(compliance * dw * omega_a)


def _smooth_continuation(model, poles, residues, upper, G, omega_top, dw, mk, zeta, extend,
                         folded, return_info, top_omega):
    """``tail="smooth"`` of :func:`continue_above_band` (see the module docstring)."""
    omega_a = omega_top + 0.5 * dw
    pattern = growth_pattern(top_omega)
    if pattern is not None and pattern[0] >= PATTERN_BETA:
        return _pattern_continuation(model, poles, residues, upper, G, top_omega, dw, mk,
                                     zeta, max(float(extend), 1.0) * omega_a, folded,
                                     return_info)
    design = smooth_tail_design(max(float(extend), 1.0))
    C = 2.0 * G / (math.pi * omega_a)     # compliance of the omitted continuum
    note = ""
    # the omitted modes' compliance as the top modes' pattern continues it (not the fit's
    # upper residual flexibility: on noisy data that came out 4-12 % short on a rod, the
    # tail's conductance with it and the peak forces 5-13 % high)
    share = pattern_share(top_omega, omega_a, dw)
    scale = 1.0 if share > 1.0 - _SCALE_TOLERANCE else max(share, _MIN_SCALE)
    if upper <= 0:
        note = ("no upper residual flexibility to draw from: the continuation's compliance "
                f"2G/(pi omega_a) = {C:.4g} m/N adds to the static flexibility")
    elif share < _MIN_SCALE:
        note = (f"the top modes thin out to {share:.3g} of the uniform continuum's compliance"
                f" 2G/(pi omega_a) = {C:.4g}: the continuation's conductance is "
                f"{_MIN_SCALE:g} G")
    G, mk, C = G * scale, mk / scale, C * scale
    wa = omega_a
    omega, damping, mass = [], [], []
    nodes = np.asarray(design.nodes)
    if nodes.size:
        n_u = math.floor((design.extend - 1.0) * wa / dw + 1e-9)
        w = wa + dw * (np.arange(n_u) + 0.5)
        weight = np.interp(w / wa, nodes, np.asarray(design.weights), right=0.0)
        keep = weight > 1e-9
        omega += list(w[keep])
        damping += [zeta] * int(np.sum(keep))
        mass += list(mk / weight[keep])
    for u, z, c in design.modes:
        omega.append(u * wa)
        damping.append(z)
        mass.append(1.0 / (c * wa * G))
    extra = ModalModel.from_modes(np.array(omega), np.array(damping), np.array(mass))
    rates = np.array([s * wa for s, _ in design.poles])
    gains = np.array([c * G for _, c in design.poles])
    added = float(np.sum(1.0 / (np.array(mass) * np.array(omega) ** 2))
                  + np.sum(gains / rates))
    left = upper - added if upper > 0 else 0.0
    if left > 0.0 or -left <= _SCALE_TOLERANCE * C:
        # the budget's difference from the design's compliance goes into the strongest
        # pole (a softer or stiffer Kelvin-Voigt term): its rate stays between the top of
        # the synthesized modes and twice its design value; the rest is a spring (left > 0).
        # A larger shortfall is the fit's (its upper residual flexibility short of what the
        # top modes' pattern implies: noise): the tail keeps its design and the static
        # flexibility grows by it (a stiffer pole made h(t) dip to 0.87 G after t = 0 on a
        # free rod 3 % short and the equal rods' peak force +14 %)
        k = int(np.argmax(gains))
        low, high = min(design.extend * wa, rates[k]), 2.0 * rates[k]
        wanted = gains[k] / rates[k] + left
        new_rate = min(max(gains[k] / wanted, low), high) if wanted > 0 else high
        left -= gains[k] / new_rate - gains[k] / rates[k]
        rates[k] = new_rate
    flex_after = left if left > 1e-9 * C else 0.0
    out = ModalModel(poles=np.concatenate([poles, extra.poles]),
                     residues=np.concatenate([residues, extra.residues]),
                     real_poles=np.concatenate([model.real_poles, -rates]),
                     real_residues=np.concatenate([model.real_residues, gains]),
                     inverse_mass=model.inverse_mass, flexibility=max(flex_after, 0.0))
    if note:
        warnings.warn(note, RuntimeWarning, stacklevel=3)
    if return_info:
        top_w = float(max(omega[:len(omega) - len(design.modes)], default=omega_top))
        highest = float(max(np.max(rates), max(omega)))
        return out, ContinuationInfo(G / scale, float(rates[int(np.argmax(gains))]), top_w,
                                     dw, mk * scale, upper, max(flex_after, 0.0), folded,
                                     note, "smooth", highest, scale)
    return out


def _pattern_continuation(model, poles, residues, upper, G, top_omega, dw, mk, zeta,
                          extend_to, folded, return_info):
    """The smooth tail of modes that thin out (a beam): :func:`._pattern_tail.pattern_tail`
    to ``extend_to`` (rad/s). Like the uniform smooth tail it follows the pattern, not the
    fit's upper residual flexibility: what that holds beyond the pattern's compliance is
    kept as a spring; a shortfall (noise) makes the static flexibility grow by it."""
    w, sigma, gain = pattern_tail(top_omega, mk, extend_to)
    extra = ModalModel.from_modes(w, zeta, mk) if w.size else None
    added = float(np.sum(1.0 / (mk * w**2))) + gain / sigma
    flex_after = max(upper - added, 0.0) if upper > 0 else 0.0
    out = ModalModel(poles=poles if extra is None else np.concatenate([poles, extra.poles]),
                     residues=(residues if extra is None
                               else np.concatenate([residues, extra.residues])),
                     real_poles=np.concatenate([model.real_poles, [-sigma]]),
                     real_residues=np.concatenate([model.real_residues, [gain]]),
                     inverse_mass=model.inverse_mass, flexibility=flex_after)
    if return_info:
        top_w = float(w[-1]) if w.size else float(top_omega[-1])
        return out, ContinuationInfo(G, sigma, top_w, dw, mk, upper, flex_after, folded, "",
                                     "pattern", max(sigma, top_w), gain / G)
    return out
