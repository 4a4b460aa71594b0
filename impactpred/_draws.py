"""Draws of an identified model's parameters from their reported standard deviations.

The uncertainty band (:func:`impactpred.uncertainty.uncertainty_band`) measures the
identification's random error by solving the impact again with models whose parameters
are drawn from the fit's reported standard deviations (``report_["modes"]``,
``report_["inverse_mass_std"]``, ``report_["flexibility_std"]``). Two kinds of draw, kept
apart because they move different figures: :func:`perturb_residues` (the residues, the
rigid mass and the residual flexibility: how strongly each mode responds) and
:func:`perturb_poles` (the natural frequencies and damping ratios: when and how long).
A figure decided by one lightly damped mode (a mass struck on a spring: its contact lasts
about half that mode's period) moves with the poles only. Every parameter is drawn from its
own standard deviation, independently: the fit's covariances between them (a pole and its
residue) are not used, so a combination of draws may over- or understate the scatter of a
figure that depends on both (the coverage study, benchmarks/README.md, measures the net).
"""

from __future__ import annotations

import math

import numpy as np

from modalid import ModalModel

__all__ = ["perturb_poles", "perturb_residues"]

#: a drawn damping ratio stays below this (a complex pair; 1 would be a real double pole)
MAX_DRAWN_DAMPING = 0.99


def _mode_indices(fit) -> list:
    """Per physical mode of ``fit.report_["modes"]`` (in its order), the index of its pole
    in ``fit.model_.poles`` (the model also holds the pseudo-modes outside the band)."""
    poles = fit.model_.poles
    return [int(np.argmin(np.abs(poles - pole))) for pole in fit.poles_]


def perturb_residues(fit, rng) -> ModalModel:
    """``fit.model_`` with its identified parameters moved by a draw of their std.

    Each physical mode's residue moves by a Gaussian in its real and its imaginary part,
    each of that part's reported standard deviation (``residue_real_std``,
    ``residue_imag_std``; without them, half the variance ``residue_std**2`` each). For a
    lightly damped mode the imaginary part (the modal mass) carries nearly all of it: an
    even split had drawn it with 71 % of its std. The rigid body's inverse mass and the
    residual flexibility (the constant term) move by a real Gaussian of theirs
    (``report_["inverse_mass_std"]``, ``report_["flexibility_std"]``), kept >= 0.

    For a driving point (``report_["driving_point"]`` not False) every drawn mode has a
    positive modal mass: a draw whose residue's imaginary part falls on the wrong side of
    zero is reflected (``Im r -> -Im r``), so that the draw stays a passive driving point
    (a modal mass of the wrong sign would be refused by the passivity check) and the
    draw sequence stays the same. That includes a mode whose nominal residue is real to
    rounding (a weak pole of the fit, modal mass ~1e13 kg either way: the 40-mode
    cantilever at 5 % noise has six, and every draw of that fit was refused).

    Parameters
    ----------
    fit : ModalFit
        A fitted estimator with standard deviations in its report.
    rng : numpy.random.Generator
        The draws' source.

    Returns
    -------
    ModalModel
        The drawn model.
    """
    model = fit.model_
    modes = fit.report_["modes"]
    if "residue_real_std" in modes and "residue_imag_std" in modes:
        re_std = modes["residue_real_std"].to_numpy(float)
        im_std = modes["residue_imag_std"].to_numpy(float)
    else:
        re_std = im_std = modes["residue_std"].to_numpy(float) / math.sqrt(2.0)
    residues = model.residues.copy()
    driving = fit.report_.get("driving_point") is not False
    for k, s_re, s_im in zip(_mode_indices(fit), re_std, im_std):
        if not (np.isfinite(s_re) and np.isfinite(s_im)):
            continue
        nominal = residues[k]
        drawn = nominal + complex(s_re * rng.standard_normal(), s_im * rng.standard_normal())
        # modal mass -1/(2 Im p Im r) > 0  <=>  Im r has the sign of -Im p
        if driving and drawn.imag * model.poles[k].imag > 0:
            drawn = complex(drawn.real, -drawn.imag)
        residues[k] = drawn
    scalars = {}
    for name in ("inverse_mass", "flexibility"):
        value, s = getattr(model, name), fit.report_.get(f"{name}_std", math.nan)
        draw = rng.standard_normal()        # drawn always: the sequence stays reproducible
        scalars[name] = max(value + s * draw, 0.0) if value and np.isfinite(s) else value
    return ModalModel(poles=model.poles, residues=residues, real_poles=model.real_poles,
                      real_residues=model.real_residues, **scalars)


def perturb_poles(fit, rng) -> ModalModel:
    """``fit.model_`` with each physical mode's pole moved by a draw of its std.

    The natural frequency and the damping ratio of each mode in ``report_["modes"]`` move
    by independent Gaussians of their reported standard deviations
    (``frequency_hz_std``, ``damping_ratio_std``), the damping ratio only where the fit
    resolved it (``damping_resolved``): an unresolved one's std is a linearization's
    figure, not the data's (a cantilever's first mode, zeta 1e-5 with a std of 2.5e-3, drawn
    at 1.2e-3, made the rod-cantilever's contact last to ``t_end`` at 1900 times its
    force); the residues, the rigid body and the
    residual flexibility stay as identified (they are :func:`perturb_residues`'s). A drawn
    frequency or damping ratio below zero is reflected (``x -> -x``: the pole stays
    stable) and a damping ratio is kept below :data:`MAX_DRAWN_DAMPING` (the pair stays
    complex). A mode whose std is not finite is left as identified. Both numbers are
    drawn for every mode, so that the sequence is reproducible.

    Parameters
    ----------
    fit : ModalFit
        A fitted estimator with standard deviations in its report.
    rng : numpy.random.Generator
        The draws' source.

    Returns
    -------
    ModalModel
        The drawn model.
    """
    model = fit.model_
    modes = fit.report_["modes"]
    f_std = 2.0 * np.pi * modes["frequency_hz_std"].to_numpy(float)   # rad/s
    z_std = modes["damping_ratio_std"].to_numpy(float)
    if "damping_resolved" in modes:
        z_std = np.where(modes["damping_resolved"].to_numpy(bool), z_std, 0.0)
    poles = model.poles.copy()
    for k, ws, zs in zip(_mode_indices(fit), f_std, z_std):
        dw, dz = rng.standard_normal(2)
        if not (np.isfinite(ws) and np.isfinite(zs)):
            continue
        wn = abs(poles[k])
        zeta = -poles[k].real / wn
        wn = abs(wn + ws * dw)
        zeta = min(abs(zeta + zs * dz), MAX_DRAWN_DAMPING)
        poles[k] = complex(-zeta * wn, math.copysign(wn * math.sqrt(1.0 - zeta**2),
                                                     poles[k].imag))
    return ModalModel(poles=poles, residues=model.residues, real_poles=model.real_poles,
                      real_residues=model.real_residues, inverse_mass=model.inverse_mass,
                      flexibility=model.flexibility)
