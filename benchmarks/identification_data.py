"""Synthetic identification cases with an exact truth, and the per-mode error metrics.

Shared by the identification benchmarks (``anchors.py``: third-party anchors;
``bench_identification.py``: modalid's own fit). Nothing here depends on an anchor package.

Cases
-----
``name`` is one of :data:`CASES`:

* ``"cantilever"`` - ``data_synth.CantileverBeam(1, 1)``, tip driving point;
* ``"fixed_rod"`` - ``data_synth.Rod(1, 1, support="fixed")``;
* ``"free_rod"`` - ``data_synth.Rod(1, 1, support="free")`` (rigid-body term ``1/(m s^2)``).

The truth is ``data_synth.lightly_damped(model, n_in_band + 10, zeta)``: the first
``n_in_band + 10`` modes, each with viscous damping ``zeta``, plus the exact static
flexibility of the omitted ones. :func:`make_case` samples its receptance on
``n_lines`` equally spaced lines from ``fmax/n_lines`` to ``fmax``, with ``fmax`` halfway
between the natural frequencies of modes ``n_in_band`` and ``n_in_band + 1``, so exactly
``n_in_band`` modes lie in the band and the 10 above it act as residual terms.
:func:`make_impulse_case` samples the same truth's impulse response.

Metrics
-------
:func:`mode_errors` matches each true in-band mode to the identified pole nearest in
frequency and reports the worst relative errors over the matched modes plus the counts of
missed, spurious, unstable and negative-modal-mass modes.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

import data_synth
import modalid

__all__ = ["CASES", "model_of", "make_case", "make_impulse_case", "mode_errors",
           "MATCH_TOL"]

CASES = ("cantilever", "fixed_rod", "free_rod")

#: Relative frequency tolerance within which an identified pole matches a true mode.
MATCH_TOL = 0.01

_N_EXTRA = 10  # modes kept above the band in the truth


def model_of(name: str) -> data_synth.ExactModel:
    """The exact (undamped) model of case ``name``."""
    if name == "cantilever":
        return data_synth.CantileverBeam(1.0, 1.0)
    if name == "fixed_rod":
        return data_synth.Rod(1.0, 1.0, support="fixed")
    if name == "free_rod":
        return data_synth.Rod(1.0, 1.0, support="free")
    raise ValueError(f"name must be one of {CASES}, got {name!r}")


def _truth(name: str, n_in_band: int, zeta: float):
    model = model_of(name)
    truth = data_synth.lightly_damped(model, n_in_band + _N_EXTRA, zeta)
    f_nat = model.natural_frequencies(n_in_band + 1) / (2.0 * math.pi)
    return truth, f_nat


def _truth_modes(truth: modalid.ModalModel, n_in_band: int, band_hz) -> pd.DataFrame:
    modes = truth.modes.iloc[:n_in_band][["frequency_hz", "omega_n", "damping_ratio",
                                          "residue", "modal_mass"]].reset_index(drop=True)
    modes.attrs["band_hz"] = (float(band_hz[0]), float(band_hz[1]))
    modes.attrs["inverse_mass"] = float(truth.inverse_mass)
    return modes


def make_case(name, *, noise, seed, n_in_band=8, n_lines=4000, zeta=0.01):
    """Noisy driving-point receptance of case ``name`` and its exact truth.

    Parameters
    ----------
    name : {"cantilever", "fixed_rod", "free_rod"}
    noise : float
        Proportional complex noise level (``0.05`` is 5 %), see
        :func:`data_synth.synthetic_frf`.
    seed : int
        Noise seed.
    n_in_band : int
        Number of modes in the band.
    n_lines : int
        Number of frequency lines, equally spaced from ``fmax/n_lines`` to ``fmax``.
    zeta : float
        Viscous damping ratio of every mode.

    Returns
    -------
    truth : modalid.ModalModel
        ``n_in_band + 10`` damped modes, the omitted modes' static flexibility and (free
        rod) the rigid-body ``inverse_mass``.
    frf : modalid.FRFData
        Receptance (m/N) on the band, with noise.
    truth_modes : pandas.DataFrame
        The first ``n_in_band`` modes of ``truth`` (columns ``frequency_hz``, ``omega_n``,
        ``damping_ratio``, ``residue``, ``modal_mass``); ``attrs["band_hz"]`` holds the
        band ``(freq_hz[0], freq_hz[-1])`` and ``attrs["inverse_mass"]`` the rigid term.
    """
    truth, f_nat = _truth(name, n_in_band, zeta)
    fmax = 0.5 * (f_nat[n_in_band - 1] + f_nat[n_in_band])
    freq_hz = np.linspace(fmax / n_lines, fmax, n_lines)
    frf = data_synth.synthetic_frf(truth, freq_hz, quantity="receptance", noise=noise,
                                   seed=seed)
    return truth, frf, _truth_modes(truth, n_in_band, (freq_hz[0], freq_hz[-1]))


def make_impulse_case(name, *, noise, seed, n_samples=8000, n_in_band=8, zeta=0.01,
                      fs_factor=4.0):
    """Noisy sampled impulse response of case ``name`` and its exact truth.

    The truth is the one of :func:`make_case` (``n_in_band + 10`` modes). The sampling
    frequency is ``fs = fs_factor * f_{n_in_band + 1}`` (default 4x the first mode above
    the band), so modes ``1 .. n_in_band`` lie well below Nyquist; note that the truth's
    modes up to Nyquist (``fs/2 = 2 f_{n_in_band+1}``) are also in the record (the
    ``flexibility * delta(t)`` term is not, see :func:`data_synth.synthetic_impulse_response`).

    Returns
    -------
    truth : modalid.ModalModel
    t, h : ndarray, shape (n_samples,)
        Times (s) and impulse-response samples (m/(N s)); noise of standard deviation
        ``noise * rms(h)``.
    truth_modes : pandas.DataFrame
        As in :func:`make_case`, with ``attrs["band_hz"] = (0, f_mid)`` where ``f_mid`` is
        halfway between modes ``n_in_band`` and ``n_in_band + 1``, ``attrs["fs"]`` and
        ``attrs["n_below_nyquist"]`` (number of truth modes below ``fs/2``).
    """
    truth, f_nat = _truth(name, n_in_band, zeta)
    fs = fs_factor * f_nat[n_in_band]
    t, h = data_synth.synthetic_impulse_response(truth, fs, n_samples, noise=noise, seed=seed)
    f_mid = 0.5 * (f_nat[n_in_band - 1] + f_nat[n_in_band])
    modes = _truth_modes(truth, n_in_band, (0.0, f_mid))
    modes.attrs["fs"] = float(fs)
    modes.attrs["n_below_nyquist"] = int(np.sum(truth.modes["frequency_hz"] < fs / 2))
    return truth, t, h, modes


def mode_errors(truth_modes, poles, residues, *, band_hz=None, tol=MATCH_TOL) -> dict:
    """Worst per-mode errors of an identified pole-residue set against the truth.

    Parameters
    ----------
    truth_modes : DataFrame
        Columns ``omega_n``, ``damping_ratio``, ``residue`` (as returned by
        :func:`make_case`).
    poles, residues : array_like of complex
        Identified poles (rad/s) and residues in the convention
        ``H(s) = sum r/(s - p) + conj(r)/(s - conj(p))``. Poles with ``Im p < 0`` are
        replaced by their conjugates (and their residues by the conjugates); real poles
        (``Im p == 0``) are ignored.
    band_hz : (float, float), optional
        Band in which an unmatched identified pole counts as spurious; default
        ``truth_modes.attrs["band_hz"]``.
    tol : float
        Relative frequency tolerance for a match (default 1 %).

    Returns
    -------
    dict
        ``freq_err`` (worst ``|w - w_true|/w_true`` with ``w = |p|``), ``damp_err`` (worst
        ``|zeta - zeta_true|/zeta_true``), ``res_err`` (worst ``|r - r_true|/|r_true|``),
        each over the matched true modes (``nan`` if none); ``missed`` (true modes with no
        identified pole within ``tol`` in frequency), ``spurious`` (identified poles in the
        band matched to no true mode), ``unstable`` (identified poles in the band with
        ``Re p > 0``), ``neg_mass`` (identified poles in the band with modal mass
        ``-1/(2 Im p Im r) < 0``) and ``n_identified`` (complex poles in the band). Poles
        outside the band (an anchor's residual terms, aliases) count in none of these.
    """
    p = np.asarray(poles, dtype=complex).ravel()
    r = np.asarray(residues, dtype=complex).ravel()
    if p.shape != r.shape:
        raise ValueError(f"poles and residues differ in shape: {p.shape} vs {r.shape}")
    complex_ = p.imag != 0
    p, r = p[complex_], r[complex_]
    flip = p.imag < 0
    p = np.where(flip, p.conj(), p)
    r = np.where(flip, r.conj(), r)
    if band_hz is None:
        band_hz = truth_modes.attrs["band_hz"]
    w_true = truth_modes["omega_n"].to_numpy(float)
    z_true = truth_modes["damping_ratio"].to_numpy(float)
    r_true = truth_modes["residue"].to_numpy(complex)

    w = np.abs(p)
    f = w / (2 * math.pi)
    in_band = (f >= band_hz[0]) & (f <= band_hz[1])
    zeta = -p.real / np.where(w > 0, w, np.inf)

    matched = np.zeros(p.size, dtype=bool)
    fe, de, re_ = [], [], []
    missed = 0
    for wt, zt, rt in zip(w_true, z_true, r_true):
        if p.size == 0:
            missed += 1
            continue
        k = int(np.argmin(np.abs(w - wt)))
        if abs(w[k] - wt) > tol * wt:
            missed += 1
            continue
        matched[k] = True
        fe.append(abs(w[k] - wt) / wt)
        de.append(abs(zeta[k] - zt) / zt if zt else abs(zeta[k]))
        re_.append(abs(r[k] - rt) / abs(rt))
    with np.errstate(divide="ignore", invalid="ignore"):
        modal_mass = -1.0 / (2.0 * p.imag * r.imag)

    def worst(v):
        return float(np.max(v)) if v else float("nan")

    return {
        "freq_err": worst(fe),
        "damp_err": worst(de),
        "res_err": worst(re_),
        "missed": int(missed),
        "spurious": int(np.sum(in_band & ~matched)),
        "unstable": int(np.sum(in_band & (p.real > 0))),
        "neg_mass": int(np.sum(in_band & (modal_mass < 0))),
        "n_identified": int(np.sum(in_band)),
    }
