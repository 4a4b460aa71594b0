"""Real hammer data: identify from hits 1-4, predict hit 5's acceleration from its force.

Run:  python benchmarks/hammer_hit5.py [--quick] [--output-error]
      A full run takes about 3 min on 2 cores. ``--quick`` leaves out the two
      unweighted ``ModalFit`` rows (about 10 s); ``--output-error`` adds the older, slow
      ``least_squares`` output-error experiment (minutes).

Data: ``../shared/data/measured/pyfrf_hammer_impacts/measurements_{1..5}.npy`` (GPL-3.0,
read in place, never copied): rows (t, force, acceleration), 25600 samples at 25.6 kHz.

Pipeline
--------
1. H1 accelerance of hits 1-4 with ``modalid.frf_from_hammer``: force window 2 ms (the
   pulse is ~0.3 ms; the rest of the force channel is noise), with and without an
   exponential window of decay 4.6 1/s (pyFRF's ``Exponential:0.01``: 1 % at the end).
   Hit 5 is used only for the evaluation.
2. First, the automatic rows: the H1 of hits 1-4 from ``frf_from_hammer`` with its
   defaults (no windows), fitted by ``ModalFit(**est.fit_options())`` and nothing else
   (the whole file: automatic band, segments), unweighted and with the response weights
   of ``fit_options(weighted=True)``, and the latter with ``missed_modes="dense"``;
   hit 5's force unwindowed. Then identification over 50-11000 Hz (the band the coherence and
   the force spectrum support; it holds all but ~0.01 % of the acceleration energy, and 5 %
   of it lies above 5 kHz), all with ``passive=False`` (not a driving point: several modes have
   negative modal masses), each reported on its own row:
   * ``ModalFit`` with its own weighting (``"relative"``), on the H1 without exponential
     window: automatic, and with ``n_modes`` = the H1 peaks (left out by ``--quick``);
   * ``ModalFit`` with ``weights = sqrt(S_ff * coherence)`` (S_ff: force autospectrum of
     hits 1-4; the weighted FRF error is then the error of the predicted acceleration
     spectrum of the average hit, i.e. the output error) and ``max_real = -(window decay
     + 1)`` 1/s (every pole stays stable, decay >= 1 1/s, once the window is undone):
     ``method="vf"`` with ``n_modes=60`` and ``50`` (vector fitting started from the
     LSCF poles selected for that count plus 2 pairs, BIC screening of its poles, upper
     pseudo-modes, residual flexibility, variable-projection refinement),
     on the windowed H1 (model corrected with ``HammerFRF.correct``, and once NOT
     corrected, to show what that costs) and with ``n_modes=60`` on the unwindowed H1;
     ``method="vf"`` and ``method="lscf"`` with automatic mode counts (windowed), with
     the default ``missed_modes="strict"`` and with ``"dense"``;
   * the same idea written out here without ``ModalFit``'s automation
     (:func:`vf_output_error_fit`): 60 pairs of vector-fitting poles, then
     ``refine_varpro`` with a constant flexibility, same weights and bound, windowed H1,
     corrected.
   Every identified model is a ``ModalModel`` (poles, residues, residual terms).
3. Prediction, in the frequency domain: ``a5 = irfft(Acc_model(f) * F5(f))`` with the
   records zero-padded to 4x their length. This is exact for the band-limited
   (anti-aliased, sinc-interpolated) force the samples represent, which is the same
   convention as the measured H1; the 4x padding makes the wrap-around of the model's
   impulse response negligible (the measured response has decayed to ~0.4 % after the
   1 s record; the bound ``max_real`` lets a weak pole decay as slowly as 1 1/s, but
   for the script's 60-pair model 8x and 16x padding change the NRMSE by < 1e-6).
   A time-domain ``lsim`` with first-order hold is *not* exact here: the accelerance
   ``s^2 H(s)`` has a direct term ``flexibility * f''(t)`` and a ``C B f'(t)`` term,
   which a piecewise-linear force does not define.
4. References: the non-parametric H1 (hits 1-4) times F5 (same padding), and the
   repeatability floor: each of hits 1-4 against hit 5 after aligning time (fractional
   delay, spectral shift) and gain (least squares).

Metric: ``NRMSE = ||a_pred - a_meas|| / ||a_meas||`` over the first 0.1 s (from the record
start; the hit is ~20 samples in) and, for information, over the whole 1 s record.
Hit 5's force gets the same 2 ms force window as hits 1-4. The table also gives each
approach's notes and the time each stage took. Nothing is asserted.
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.fft as sf
from scipy.optimize import least_squares
from scipy.signal import find_peaks

import modalid
from modalid._lsfd import Terms, refine_varpro, split_coefficients
from modalid._vf import vector_fit_poles

DATA = (Path(__file__).resolve().parents[2] / "shared" / "data" / "measured"
        / "pyfrf_hammer_impacts")
FS = 25600.0
FORCE_WINDOW = 0.002            # s
DECAY = np.log(100.0)           # 1/s: exponential window ending at 1 % after 1 s
BAND = (50.0, 11000.0)          # Hz: coherence and force spectrum support this band
PAD = 4                         # zero padding factor of the prediction
T_EVAL = 0.1                    # s


def load():
    recs = [np.load(DATA / f"measurements_{i}.npy", allow_pickle=False) for i in range(1, 6)]
    return np.array([r[1] for r in recs]), np.array([r[2] for r in recs])


def nrmse(pred, meas, n):
    return float(np.linalg.norm(pred[:n] - meas[:n]) / np.linalg.norm(meas[:n]))


def predict_from_accelerance(acc_fn, force, n_fft):
    """irfft(acc(f) F(f)) on a zero-padded grid; acc_fn(freq_hz) -> complex accelerance."""
    freq = sf.rfftfreq(n_fft, 1.0 / FS)
    return sf.irfft(acc_fn(freq) * sf.rfft(force, n_fft), n_fft)[:force.size]


def model_accelerance(model):
    def acc(freq):
        out = np.empty(freq.size, complex)
        out[1:] = model.frf(2 * np.pi * freq[1:], quantity="accelerance")
        out[0] = model.inverse_mass         # the limit at 0 Hz (0 for a grounded model)
        return out
    return acc


# ------------------------------------------------------------ output-error refinement
def _basis(omega, poles):
    """Real-parameter basis of the accelerance: columns for Re r, Im r of every pole
    (with its conjugate) and the constant flexibility; accelerance = -omega^2 H."""
    s = 1j * omega[:, None]
    a = 1.0 / (s - poles) + 1.0 / (s - poles.conj())
    b = 1j / (s - poles) - 1j / (s - poles.conj())
    cols = np.concatenate([a, b, np.ones((omega.size, 1))], axis=1)
    return -(omega**2)[:, None] * cols


def _solve_linear(omega, h, w, poles):
    m = _basis(omega, poles) * w[:, None]
    big = np.concatenate([m.real, m.imag])
    rhs = np.concatenate([(h * w).real, (h * w).imag])
    scale = np.linalg.norm(big, axis=0)
    x = np.linalg.lstsq(big / scale, rhs, rcond=None)[0] / scale
    return x, big @ x - rhs


def output_error_fit(frf, weights, start_hz, *, zeta0=0.005):
    """Poles refined by variable projection; residues, flexibility and three pseudo-modes
    (one below, two above the band) by linear least squares. Returns a ModalModel."""
    sel = (frf.freq_hz >= BAND[0]) & (frf.freq_hz <= BAND[1])
    omega, h, w = frf.omega[sel], frf.values[sel], weights[sel]
    w = w / np.sqrt(np.mean(w**2 * np.abs(h) ** 2))
    wn = 2 * np.pi * np.asarray(start_hz, float)
    lo, hi = 2 * np.pi * BAND[0], 2 * np.pi * BAND[1]
    pseudo = np.array([0.5 * lo, 1.15 * hi, 1.6 * hi])
    wn = np.concatenate([wn, pseudo])
    zeta = np.concatenate([np.full(len(start_hz), zeta0), [0.05, 0.05, 0.05]])

    def poles_of(theta):
        z, lw = theta[: wn.size], theta[wn.size:]
        om = np.exp(lw)
        zz = 1.0 / (1.0 + np.exp(-z))          # damping ratio in (0, 1)
        return -zz * om + 1j * om * np.sqrt(1 - zz**2)

    theta0 = np.concatenate([np.log(zeta / (1 - zeta)), np.log(wn)])
    # bounds: damping 1e-5..0.5; a mode within 3 % of its peak, pseudo-modes off the band
    n_m = len(start_hz)
    lo_b = np.concatenate([np.full(wn.size, np.log(1e-5)),
                           np.log(wn[:n_m] / 1.03), np.log([0.05 * lo, hi, hi])])
    hi_b = np.concatenate([np.full(wn.size, np.log(0.5)),
                           np.log(wn[:n_m] * 1.03), np.log([lo, 4 * hi, 4 * hi])])
    theta0 = np.clip(theta0, lo_b + 1e-9, hi_b - 1e-9)
    res = least_squares(lambda th: _solve_linear(omega, h, w, poles_of(th))[1], theta0,
                        bounds=(lo_b, hi_b), method="trf", x_scale="jac", max_nfev=60)
    poles = poles_of(res.x)
    x, _ = _solve_linear(omega, h, w, poles)
    n = poles.size
    residues = x[:n] + 1j * x[n:2 * n]
    model = modalid.ModalModel(poles=poles, residues=residues, flexibility=x[-1])
    fitted = model.frf(omega, quantity="accelerance")
    return model, {"nfev": res.nfev, "status": res.status,
                   "acc_nrmse": float(np.linalg.norm(fitted - h) / np.linalg.norm(h))}


# ------------------------------------------- vector fitting + output-error refinement
def vf_output_error_fit(est, n_pairs, *, vf_iterations=15, vp_iterations=40):
    """Pole-residue model of the whole band from an H1 estimate, fitted for prediction.

    The weighted error is the error of the predicted acceleration spectrum of the average
    hit: ``|W (Acc_model - H1)|`` with ``W = sqrt(S_ff * coherence)`` (S_ff: force
    autospectrum of hits 1-4), i.e. in receptance ``W omega^2 |H_model - H1/(-omega^2)|``.
    Poles: ``n_pairs`` complex pairs relocated by relaxed vector fitting
    (``modalid._vf.vector_fit_poles``, default start: poles spread over the band), then
    all poles and residues refined by variable projection (``modalid._lsfd.refine_varpro``)
    with a constant residual flexibility. ``Re p <= -(window decay + 1)`` 1/s keeps every
    pole stable (decay >= 1 1/s) once ``est.correct`` has undone the exponential window.
    Returns the model (window NOT yet corrected) and the refinement's info.
    """
    frf = est.frf.band(BAND).to_receptance()
    omega, h = frf.omega, frf.values
    inband = (est.frf.freq_hz >= BAND[0]) & (est.frf.freq_hz <= BAND[1])
    w = np.sqrt(est.force_spectrum[inband] * np.clip(frf.coherence, 1e-3, 1.0)) * omega**2
    w = w / np.sqrt(np.mean((w * np.abs(h)) ** 2))
    poles, _ = vector_fit_poles(omega, h, w, n_pairs, n_iter=vf_iterations)
    terms = Terms(np.zeros(0), False, True)
    poles, x, info = refine_varpro(omega, h, w, poles, terms, max_iter=vp_iterations,
                                   with_std=False, max_real=-(est.window_decay_rate + 1.0))
    residues, _, _, flex = split_coefficients(x, poles.size, terms)
    info["frf_nrmse_weighted"] = float(np.sqrt(info["cost"]) / np.linalg.norm(w * h))
    return modalid.ModalModel(poles=poles, residues=residues, flexibility=flex), info


# ------------------------------------------------------------------------- main
def main():
    times = {}
    t0 = time.perf_counter()
    force, acc = load()
    n = force.shape[1]
    n_eval = int(round(T_EVAL * FS))
    t = np.arange(n) / FS
    f5 = np.where(t <= FORCE_WINDOW, force[4], 0.0)
    a5 = acc[4]
    n_fft = PAD * n
    times["load"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    est = modalid.frf_from_hammer(force[:4], acc[:4], FS, force_window_length=FORCE_WINDOW)
    est_w = modalid.frf_from_hammer(force[:4], acc[:4], FS, force_window_length=FORCE_WINDOW,
                                    exponential_decay=DECAY)
    # the H1 used for prediction: same estimator on the zero-padded grid
    est_pad = modalid.frf_from_hammer(force[:4], acc[:4], FS, force_window_length=FORCE_WINDOW,
                                      n_fft=n_fft)
    times["H1 (3 estimates)"] = time.perf_counter() - t0

    rows = []

    def add(name, pred, note=""):
        rows.append((name, nrmse(pred, a5, n_eval), nrmse(pred, a5, n), note))

    t0 = time.perf_counter()
    h1 = est_pad.frf.values
    add("H1 of hits 1-4 x F5 (non-parametric)", predict_from_accelerance(lambda f: h1, f5, n_fft))
    times["H1 prediction"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    freq = sf.rfftfreq(n, 1 / FS)
    spec = sf.rfft(acc, axis=-1)
    for i in range(4):
        best = None
        for d in np.linspace(-2, 2, 401):         # samples
            x = sf.irfft(spec[i] * np.exp(-2j * np.pi * freq * d / FS), n)
            g = np.dot(x[:n_eval], a5[:n_eval]) / np.dot(x[:n_eval], x[:n_eval])
            e = nrmse(g * x, a5, n_eval)
            if best is None or e < best[0]:
                best = (e, d, g, g * x)
        add(f"repeatability: hit {i + 1} vs 5 (aligned)", best[3],
            f"delay {best[1]:+.2f} samples, gain {best[2]:.3f}")
    times["repeatability"] = time.perf_counter() - t0

    # peaks of H1 in the band: start values / mode list
    frf = est.frf.with_measurement()
    inband = (frf.freq_hz >= BAND[0]) & (frf.freq_hz <= BAND[1])
    pk, _ = find_peaks(np.log10(np.abs(frf.values[inband])), prominence=0.5)
    peaks_hz = frf.freq_hz[inband][pk]

    # the automatic fits the issue names: the H1 of frf_from_hammer with its defaults (no
    # force window, no exponential window), ModalFit(**est.fit_options()) and nothing else
    est_auto = modalid.frf_from_hammer(force[:4], acc[:4], FS, response_type="acceleration")
    auto_runs = [("ModalFit(**est.fit_options())", est_auto.fit_options()),
                 ("ModalFit(**est.fit_options(weighted=True))",
                  est_auto.fit_options(weighted=True)),
                 ("same, missed_modes='dense'",
                  dict(est_auto.fit_options(weighted=True), missed_modes="dense"))]
    for label, options in auto_runs:
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = modalid.ModalFit(**options).fit(est_auto.frf)
        times[label] = time.perf_counter() - t0
        r = fit.report_
        add(f"{label}, defaults", predict_from_accelerance(
            model_accelerance(fit.model_), force[4], n_fft),
            f"{r['n_modes']} modes, band {r['band_hz'][0]:g}-{r['band_hz'][1]:g} Hz, "
            f"{r['segments']} segments, verdict {r['verdict']}; {len(caught)} warnings")

    modalfit_runs = [("ModalFit auto", dict()),
                     ("ModalFit n_modes=H1 peaks", dict(n_modes=list(peaks_hz)))]
    for label, kwargs in ([] if "--quick" in sys.argv else modalfit_runs):
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = modalid.ModalFit(passive=False, freq_range=BAND, **kwargs).fit(frf)
        times[label] = time.perf_counter() - t0
        r = fit.report_
        add(f"{label}, passive=False, {BAND[0]:g}-{BAND[1]:g} Hz",
            predict_from_accelerance(model_accelerance(fit.model_), f5, n_fft),
            f"{r['n_modes']} modes + {r['upper_residual_modes']} upper; converged "
            f"{r['converged']}; {len(caught)} warnings")

    # ModalFit with the prediction-error weights sqrt(S_ff * coherence) (option `weights`)
    # and the poles kept left of -(window decay + 1) 1/s (option `max_real`)
    weighted_runs = [
        ("ModalFit vf n_modes=60, weights, exp. window", est_w, dict(method="vf", n_modes=60)),
        ("ModalFit vf n_modes=50, weights, exp. window", est_w, dict(method="vf", n_modes=50)),
        ("ModalFit vf n_modes=60, weights, no exp. window", est, dict(method="vf", n_modes=60)),
        ("ModalFit vf auto, weights, exp. window", est_w, dict(method="vf")),
        ("ModalFit lscf auto, weights, exp. window", est_w, dict()),
        ("ModalFit vf auto dense, weights, exp. window", est_w,
         dict(method="vf", missed_modes="dense")),
        ("ModalFit lscf auto dense, weights, exp. window", est_w, dict(missed_modes="dense")),
    ]
    for label, e, kwargs in weighted_runs:
        t0 = time.perf_counter()
        weights = np.sqrt(e.force_spectrum * np.clip(e.coherence, 1e-3, 1.0))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = modalid.ModalFit(passive=False, freq_range=BAND, weights=weights,
                                   max_real=-(e.window_decay_rate + 1.0),
                                   **kwargs).fit(e.frf.with_measurement())
        times[label] = time.perf_counter() - t0
        r = fit.report_
        note = (f"{r['n_modes']} modes + {r['upper_residual_modes']} upper + flexibility; "
                f"converged {r['converged']}; {len(caught)} warnings")
        if e.window_decay_rate:
            add(f"{label}, corrected", predict_from_accelerance(
                model_accelerance(e.correct(fit.model_)), f5, n_fft), note)
            if kwargs.get("n_modes") == 60:
                add(f"{label}, NOT corrected", predict_from_accelerance(
                    model_accelerance(fit.model_), f5, n_fft), note)
        else:
            add(label, predict_from_accelerance(model_accelerance(fit.model_), f5, n_fft), note)

    # the same idea written out in this script (no ModalFit automation): VF poles + VP
    t0 = time.perf_counter()
    model, info = vf_output_error_fit(est_w, 60)
    label = "script VF(60 pairs)+varpro, exp. window, corrected"
    times[label] = time.perf_counter() - t0
    add(label, predict_from_accelerance(model_accelerance(est_w.correct(model)), f5, n_fft),
        f"{model.n_modes} poles + flexibility; weighted FRF nrmse "
        f"{info['frf_nrmse_weighted']:.4f}; {info['n_iter']} LM steps")

    experiments = [] if "--output-error" not in sys.argv else [("no exp. window", est),
                                                                ("exp. window", est_w)]
    for label, e in experiments:  # slow (minutes): an output-error fit outside modalid
        t0 = time.perf_counter()
        weights = np.sqrt(e.force_spectrum * np.clip(e.coherence, 1e-3, 1))
        model, info = output_error_fit(e.frf, weights, peaks_hz)
        times[f"output-error fit, {label}"] = time.perf_counter() - t0
        note = (f"{model.n_modes - 3} modes + 3 pseudo; FRF nrmse {info['acc_nrmse']:.4f}; "
                f"nfev {info['nfev']}")
        if e.window_decay_rate:
            add(f"output-error model, {label}, corrected", predict_from_accelerance(
                model_accelerance(e.correct(model)), f5, n_fft), note)
            add(f"output-error model, {label}, NOT corrected", predict_from_accelerance(
                model_accelerance(model), f5, n_fft), note)
        else:
            add(f"output-error model, {label}",
                predict_from_accelerance(model_accelerance(model), f5, n_fft), note)

    print(f"hit 5 acceleration predicted from its force; NRMSE over the first {T_EVAL:g} s "
          f"({n_eval} samples) and over the full 1 s record")
    print(f"{len(peaks_hz)} H1 peaks in {BAND[0]:g}-{BAND[1]:g} Hz: "
          + ", ".join(f"{f:.0f}" for f in peaks_hz))
    print()
    print(f"| {'prediction':<58} | NRMSE 0.1 s | NRMSE 1 s | notes |")
    print(f"|{'-' * 60}|-------------|-----------|-------|")
    for name, e1, e2, note in rows:
        print(f"| {name:<58} | {100 * e1:10.2f}% | {100 * e2:8.2f}% | {note} |")
    print()
    print("stage times (s): " + "; ".join(f"{k} {v:.2f}" for k, v in times.items()))


if __name__ == "__main__":
    main()
