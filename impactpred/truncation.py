"""Truncation control: what a model identified on a finite band is missing above it.

A measured FRF covers a finite band, so the identified model has finitely many modes,
while a rigid impact excites every frequency. A finite modal sum has ``h(0+) = 0``: rigid
contact against it becomes a train of tiny plastic impacts (chatter). The upper residual
flexibility (the omitted modes' static compliance) fixes the energy balance only on
average; the short-time behaviour needs the structure's *high-frequency impedance*.

:func:`continue_above_band` estimates it from the top identified modes. Averaged over
many lightly damped modes, the driving-point mobility's real part (conductance) is

    G = pi / (2 m_k dw_k)        (modal mass m_k, mode spacing dw_k)

per mode (integrate ``Re s/(m_k (s^2 + w_k^2))`` over one resonance: ``pi/(2 m_k)``;
spread it over the spacing ``dw_k``). For a uniform rod ``m_k = m/2``, ``dw = pi/T``
and ``G = T/m = 1/Z`` exactly: the rod's ``h(0+)``. Above the band the structure then
behaves like a dashpot of admittance ``G``, i.e. a receptance ``G/s``.

The simplest passive continuation is one real pole, ``G/(s + sigma)`` (impulse
response ``G exp(-sigma t)``, positive residue: a spring and dashpot in series, which is
passive). Its static compliance ``G/sigma`` is taken out of the upper residual
flexibility, so the static flexibility and the low-frequency FRF are unchanged. The rate
``sigma`` is chosen so that ``G/sigma`` equals the upper residual flexibility (the
omitted modes' compliance) when that is at least ``G/(c omega_top)``; the exact rod gives
``sigma = (pi/2) omega_top`` approximately. Pseudo-modes above the band (placed there by
:class:`modalid.ModalFit` to stand for the omitted modes) are folded into the residual
flexibility first: the continuation replaces them.

A single real pole just above the band damps the in-band FRF by a few per cent (its
``-G omega/(omega^2 + sigma^2)`` imaginary part). The top modes' pattern is therefore first
continued with synthesized modes (same modal mass, spacing and damping) up to ``extend``
(4) times the top mode's frequency, paid for out of the upper residual flexibility; the
real pole then carries only the rest, far above the band (``tail="pole"``).

That hard junction between discrete modes and a real pole rings like a Gibbs jump: the
impulse response dips to 0.76 G right after ``t = 0`` and two equal rods get a contact
force 30 % above the exact rectangle, at any ``extend`` (the dip's time scales with
``1/(extend omega_top)``). The default ``tail="smooth"`` fits the junction instead. In
units ``x = omega_a t``, ``omega_a = omega_top + dw/2`` (where the midpoint rule puts the
continuum of the omitted modes), those modes' impulse response is
``G (1 - (2/pi) Si(x))``, their mobility ``(2G/pi) arctan(s/omega_a)``. A linear program
(:func:`smooth_tail_design`, once per ``extend``) approximates it, in the max norm on
``0 <= x <= 150``, by positive terms only: the synthesized modes with tapered weights
``W(omega/omega_a)`` (modal mass ``m_k/W``) up to ``extend omega_a``, damped modes
(``zeta`` 0.05..0.7) and real poles above, with ``h(0+) = G`` and the omitted modes'
compliance ``2G/(pi omega_a)`` exactly. The impulse response stays within 0.12 % of
``G (1 - (2/pi) Si(x))`` for ``extend = 16`` (the default), 1.1 % for 4 (the single pole:
24 %). With ``extend = 4`` the tail's highest rate is about ``8.6 omega_a`` (the single
pole's: ``6.1 omega_a`` for a rod) and the exact solver takes about 1.5 times as long as
with the single pole (two equal rods, 10 modes: 45 ms instead of 28 ms); with 16, whose
synthesized modes quadruple, about 0.2 s.
The terms that dissipate (real poles, damped modes; 31 % of the omitted compliance, the
single pole 26 %) lose about as much of the energy sent above the band. On the lightly
damped truths of the benchmark (10 modes, zeta = 1e-3), the peak force of two equal rods is
0.2 % high with synthesized modes to 16 times the band top (``extend``, the default), 1.9 %
with 4 times, 30 % with the single pole; the energy kept below the band grows with
``extend`` (their restitution -0.83 % at 16, -1.24 % at 4).
Where the top modes thin out (their spacing grows like ``omega**beta``, ``beta >= 1/4``: a
beam, ``omega_k ~ k^2``, has 1/2) the uniform continuum is the wrong shape: the tail then
continues the pattern itself, mode by mode at the top modes' modal mass up to ``extend
omega_a``, and one real pole carries the compliance of the pattern's modes after them
(:mod:`impactpred._pattern_tail`; ``ContinuationInfo.tail == "pattern"``). Where they thin
out less, the uniform tail's conductance is scaled down to the pattern's compliance.

:func:`impact_figures` (from :mod:`impactpred._figures`, exported here) reads duration,
peak, impulse and restitution off a prediction; their uncertainty band is
:mod:`impactpred.uncertainty`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from modalid import ModalModel, MultiOutputModalModel

from ._continuation import (ContinuationInfo, continue_above_band, high_frequency_conductance,
                            pattern_share, above_band, static_compliance)
from ._figures import FIGURES, band_resolution, impact_figures
from ._smooth_tail import TailDesign, smooth_tail_design

__all__ = ["FIGURES", "ContinuationInfo", "NoComplianceAbove", "TailDesign",
           "band_resolution", "continue_above_band", "high_frequency_conductance",
           "identified_model", "impact_figures", "pattern_share", "smooth_tail_design",
           "tail_extent"]

def _fold_multi_output(model, band_hz, *, normal_modes):
    """A multi-output model with the modes outside ``band_hz`` folded into every row's
    residual flexibility (static compliance ``-2 Re(r/p)``) and, with ``normal_modes``,
    the real parts of the residues inside dropped."""
    low, top = (2 * math.pi * f for f in band_hz)
    w = np.abs(model.poles)
    inside = (w >= low * (1 - 1e-9)) & (w <= top * (1 + 1e-9))
    r = model.residues
    static = np.sum(static_compliance(model.poles[~inside], r[:, ~inside]), axis=1)
    kept = r[:, inside]
    if normal_modes:
        kept = 1j * kept.imag
    return model.replace(poles=model.poles[inside], residues=kept,
                         flexibility=model.flexibility + static)


#: the continuation's extent (in band tops) for bands of up to this many modes; wider bands
#: get ``16 sqrt(TAIL_MODES / n)`` (:func:`tail_extent`)
TAIL_MODES = 10


def tail_extent(n_modes: int) -> float:
    """The continuation's extent ``extend`` for a band of ``n_modes`` identified modes.

    16 up to :data:`TAIL_MODES` modes, then ``16 sqrt(10 / n)`` (11.3 at 20 modes, 8 at
    40): the synthesized modes ``~ n extend`` then grow like ``sqrt(n)`` instead of ``n``
    and the exact solver's cost (which grows like the cube of the modes) stays within 6x
    of the 10-mode band's (two free rods at 40 modes: 1.2 s instead of 13.6 s with 16).
    The price is in the peak of a force that jumps (two equal free rods, 40 modes, 1 %
    noise: +5.2 % at 8, +0.6 % at 16; +8.0 % at 8 with 20 modes): a Gibbs overshoot set by
    the tail's reach; duration, impulse and restitution change by < 0.05 %.

    Parameters
    ----------
    n_modes : int
        Identified modes in the band.

    Returns
    -------
    float
        ``extend``, in multiples of the band top.
    """
    n = int(n_modes)
    return 16.0 if n <= TAIL_MODES else 16.0 * math.sqrt(TAIL_MODES / n)


#: an identified model is continued above its band only where the band shows compliance
#: above it: its upper residual flexibility (with the pseudo-modes above the band folded
#: in) at least this share of the compliance ``2G/(pi omega_a)`` the continuum the
#: continuation builds would hold. Over 180 random noisy driving-point files (3-14 modes
#: in band, benchmarks/random_predictions.py) a rod's or free rod's came out 0.99-1.19,
#: a cantilever's 0.23-0.68, a spring-mass's 0-0.0015 (its band above the mode is the mass
#: line: continued as a continuum, its restitution had been off by up to 0.55); a
#: cantilever's band cut below its second mode (0-3 % noise) 0.044-0.053, a fixed rod's
#: 0.35. The threshold sits between, about 7 and 4 times from either side
MIN_COMPLIANCE_ABOVE = 0.01


class NoComplianceAbove(ValueError):
    """A band that shows no compliance above it (:data:`MIN_COMPLIANCE_ABOVE`): not
    continued, and its upper residual terms, noise there, dropped (``identified_model``'s
    default ``upper_residual="auto"``)."""


def _no_compliance_above(model, band_top_hz, *, n_top):
    """Why ``model``'s band shows no compliance above it (see
    :data:`MIN_COMPLIANCE_ABOVE`), or None. Raises ``ValueError`` when it has no passive
    mode inside the band to judge by."""
    G, omega_top, dw, _ = high_frequency_conductance(model, band_top_hz, n_top=n_top)
    tail = 2.0 * G / (math.pi * (omega_top + 0.5 * dw))
    above = above_band(model.poles, band_top_hz)
    upper = model.flexibility + float(np.sum(static_compliance(model.poles[above],
                                                               model.residues[above])))
    if upper >= MIN_COMPLIANCE_ABOVE * tail:
        return None
    return (f"the band shows no compliance above it: its upper residual flexibility "
            f"{upper:.3g} m/N is {upper / tail:.2g} of the {tail:.3g} m/N a continuum "
            "above it would hold, as a lumped body's (its receptance above the band is its "
            "mass line)")


def _normal_residues(model, band_top_hz):
    """``model``'s residues as normal modes' (``Re r = 0``): inside the band (top
    ``band_top_hz``, Hz) and below it their imaginary parts kept (the modal masses; a lower
    pseudo-mode's share of the mass line); above it, each pseudo-mode keeps its static
    compliance ``K = -2 Re(r/p)`` (the share of the omitted modes it stands for),
    ``Im r = -K |p|^2/(2 Im p)``. Returns ``(residues, flexibility)``: the positive ``K``
    and the residual flexibility scaled together so that they sum to the net static
    compliance above the band (pseudo-modes and flexibility; 0 where it is not positive),
    the negative ``K`` made 0. Terms may cancel: a fixed rod refitted on 80 % of its band
    put two pseudo-modes at 8.459 Hz, residues +-106, static compliances +0.206 and
    -0.202 m/N; each clipped alone (the negative one to 0) they had left 0.206 m/N of
    flexibility for the net 0.004, and the impact a restitution of 0.861 for 0.698 (the
    uncertainty band's restitution -0.44..1).

    A residue's real part is not a passive term: the mobility's real part changes sign
    across the resonance (unless ``Re r`` is under about ``2 zeta |Im r|``), and their sum
    ``h(0)`` is a jump of the impulse response, which no structure has. A spring-mass's
    noisy mobility fitted a pseudo-mode at 10 times its mode with ``Re r`` 50 times
    ``|Im r|``, and its impact came out with a restitution of 2.8; a fixed rod fitted
    from between its second and third modes kept a lower pseudo-mode's real residue, a
    negative ``h(0)`` the impact solvers refused."""
    p, r = model.poles, model.residues
    above = above_band(p, band_top_hz)
    compliance = np.where(above, static_compliance(p, r), 0.0)
    # a negative flexibility is not a passive term: left as it is, for the checks to refuse
    flexibility = float(model.flexibility) if model.flexibility > 0 else 0.0
    positive = flexibility + float(np.sum(np.maximum(compliance, 0.0)))
    net = flexibility + float(np.sum(compliance))
    scale = max(net, 0.0) / positive if positive > 0 else 0.0
    kept = np.maximum(compliance, 0.0) * scale
    with np.errstate(divide="ignore", invalid="ignore"):
        im_above = -kept * np.abs(p)**2 / (2.0 * p.imag)
    return (1j * np.where(above, im_above, r.imag),
            flexibility * scale if flexibility > 0 else float(model.flexibility))


def identified_model(fit, *, continuation: bool = True, n_top: int = 3,
                     extend: float | None = None, model=None, normal_modes: bool = True,
                     upper_residual="auto") -> ModalModel:
    """The model of ``fit`` (or ``model``) for an impact, continued above the fit's band
    when asked (to ``extend`` times the band top; default :func:`tail_extent` of the
    fit's modes: 16 up to 10 modes).

    ``normal_modes``: drop the real parts of the residues (keep the modal masses of the
    modes inside the band and below it, the static compliances of those above it, by
    which :func:`continue_above_band` folds them); a mode is inside when ``|p|`` lies in
    the fit's band (:func:`_normal_residues`).
    A driving point's displacement starts from 0 after an impulse, ``h(0+) = sum 2 Re r_k
    = 0``: the real parts an identification leaves (noise; or non-proportional damping,
    whose sum over all modes is 0) act as a spurious instantaneous compliance that a short
    contact feels at full strength, while the continuation sets ``h(0+)`` to its ``G``.
    On the benchmark's cantilever (10 modes, 1 % noise) they summed to 30 % of ``G`` and
    took the Hertz ball's restitution from +1.4 % to -5.3 %.

    A :class:`~modalid.MultiOutputModalModel` (a fit of an FRFSet) has its modes outside
    the band (the fit's pseudo-modes) folded into every row's residual flexibility, their
    static compliance ``-2 Re(r/p)`` (their complex residues would move the points at
    ``t = 0+`` and make the driving point's force jump there; a transfer row's constant with
    no match at the driving point moved the README's mid-span point at 142 m/s), the modes
    inside made normal modes; it takes ``continuation=False`` (the continuation is built for
    a driving point).

    Parameters
    ----------
    fit : ModalFit
        A fitted estimator (its ``model_`` and ``report_``).
    continuation : bool, keyword-only
        Continue the model above the fit's band.
    n_top : int, keyword-only
        Top modes that set the continuation's impedance.
    extend : float, optional, keyword-only
        The continuation's extent, in multiples of the band top.
    model : ModalModel or MultiOutputModalModel, optional, keyword-only
        The model to use instead of ``fit.model_`` (a drawn or refitted one).
    normal_modes : bool, keyword-only
        Drop the real parts of the residues (see :func:`_normal_residues`).
    upper_residual : {"auto", True, False}, keyword-only
        Keep the terms that stand for the modes above the band (the pseudo-modes there,
        the flexibility). ``"auto"`` drops them where the band shows no compliance above
        it (:class:`NoComplianceAbove`; noise there): a noise-level flexibility of
        1.6e-10 m/N turned a rigid contact on a spring-mass from a plastic impulse into
        six bounces on a stiff spring (restitution 0.984 for the exact 0.880). ``False``
        drops them always (not with ``continuation``, which is built from them), ``True``
        never.

    Returns
    -------
    ModalModel or MultiOutputModalModel
        The model to give :class:`~impactpred.Body`.

    Raises
    ------
    ValueError
        With ``continuation``: no passive mode inside the band to continue from, or a
        band that shows no compliance above it (:class:`NoComplianceAbove`, see
        :data:`MIN_COMPLIANCE_ABOVE`: a lumped body, whose receptance above the band is
        its mass line); ``predict`` then keeps the model as identified (without its
        upper residual terms in the second case) and says so.
    """
    if not (upper_residual == "auto" or isinstance(upper_residual, (bool, np.bool_))):
        raise ValueError(f"upper_residual must be 'auto', True or False, got "
                         f"{upper_residual!r}")
    if continuation and upper_residual is False:
        raise ValueError("identified_model: the continuation is built from the upper "
                         "residual terms; upper_residual=False needs continuation=False")
    model = fit.model_ if model is None else model
    if isinstance(model, MultiOutputModalModel):
        if continuation or upper_residual is False:
            raise ValueError("identified_model: the continuation and upper_residual=False "
                             "apply to a driving-point ModalModel; for a "
                             "MultiOutputModalModel pass continuation=False")
        return _fold_multi_output(model, fit.report_["band_hz"], normal_modes=normal_modes)
    band_top = fit.report_["band_hz"][1]
    if normal_modes and model.n_modes:
        residues, flexibility = _normal_residues(model, band_top)
        model = model.replace(residues=residues, flexibility=flexibility)
    lumped = None
    if continuation or upper_residual == "auto":
        try:
            lumped = _no_compliance_above(model, band_top, n_top=n_top)
        except ValueError:
            if continuation:
                raise                            # no passive mode inside the band
    if continuation:
        if lumped:
            raise NoComplianceAbove(lumped)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            if extend is None:
                extend = tail_extent(fit.report_.get("n_modes", 0))
            return continue_above_band(model, band_top, n_top=n_top, extend=extend)
    if upper_residual is False or (upper_residual == "auto" and lumped):
        inside = ~above_band(model.poles, band_top)
        model = model.replace(poles=model.poles[inside], residues=model.residues[inside],
                              flexibility=0.0)
    return model
