"""The missed-mode search (modalid._pole_checks): the noise a trial mode is judged against,
and the refinement that follows a mode added late."""

import warnings

import numpy as np

from modalid import FRFData, ModalFit, ModalModel
from modalid._lsfd import Terms
from modalid._pole_checks import PoleChecks

F_MODES = np.array([810., 851.5, 900., 1300., 1518., 1700., 1850.])


def varying_noise_data(seed=3):
    """Transfer accelerance, 600-2000 Hz at 1 Hz: 0.3 % noise below 1100 Hz, 3 % above
    (the noisier strong modes dominate the strongest lines), with the coherence of that
    noise for one average."""
    mass = np.array([1.0, 2.0, 0.25, 0.05, -0.05, 0.05, 0.05])
    truth = ModalModel.from_modes(2 * np.pi * F_MODES, np.full(F_MODES.size, 1.1e-3), mass)
    rng = np.random.default_rng(seed)
    freq = np.arange(600.0, 2001.0)
    h = truth.frf(2 * np.pi * freq, quantity="accelerance")
    noise = (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)) / np.sqrt(2)
    sigma = np.where(freq < 1100, 0.003, 0.03)
    coherence = 1.0 / (1.0 + 2.0 * sigma**2)          # (1 - g)/g = 2 sigma^2
    return freq, sigma, h * (1 + sigma * noise), coherence


def line_noise(fit, data):
    """The fitted estimator's per-line noise on ``data``'s band (receptance)."""
    band = data.to_receptance()
    fit._noise = None
    return fit._line_noise(band.values)


def test_line_noise_follows_the_coherence_where_the_data_are_quieter():
    freq, sigma, values, coherence = varying_noise_data()
    with_coherence = FRFData(freq, values, quantity="accelerance", coherence=coherence)
    fit = ModalFit(passive=False).fit(with_coherence)
    std, measured = line_noise(fit, with_coherence)
    assert measured
    mag = np.abs(with_coherence.to_receptance().values)
    quiet = (freq < 1100) & (mag > np.quantile(mag[freq < 1100], 0.5))
    # the coherence's bound for one average, sqrt(2) sigma |H|, and the floor
    ratio = std[quiet] / (sigma[quiet] * mag[quiet])
    assert np.all(ratio >= 1.0) and np.median(ratio) < 2.0
    # without the coherence the strongest lines' scatter (the noisy band's) is used
    # everywhere, several times the quiet lines' noise, and the criterion is stricter
    without = FRFData(freq, values, quantity="accelerance")
    fit_plain = ModalFit(passive=False).fit(without)
    std_plain, measured_plain = line_noise(fit_plain, without)
    assert not measured_plain
    assert np.median(std_plain[quiet] / (sigma[quiet] * mag[quiet])) > 3.0
    np.testing.assert_allclose(np.sort(fit.report_["modes"]["frequency_hz"]), F_MODES,
                               rtol=1e-4)


def close_pair_data(seed, weak_mass):
    """As :func:`varying_noise_data` with a weak partner 6.5 Hz above the 900 Hz mode and
    a weak 824 Hz mode, no coherence: the search adds modes in both of its stages."""
    freq_modes = np.array([810., 824., 851.5, 900., 906.5, 1300., 1518., 1700., 1850.])
    zeta = np.array([1.3e-3, 1.4e-3, 1.1e-3, 1.1e-3, 1.7e-3, 1e-3, 1e-3, 1e-3, 1e-3])
    mass = np.array([1.0, -8.0, 2.0, 0.25, weak_mass, 0.05, -0.05, 0.05, 0.05])
    truth = ModalModel.from_modes(2 * np.pi * freq_modes, zeta, mass)
    rng = np.random.default_rng(seed)
    freq = np.arange(600.0, 2001.0)
    h = truth.frf(2 * np.pi * freq, quantity="accelerance")
    noise = (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)) / np.sqrt(2)
    sigma = np.where(freq < 1100, 0.003, 0.03)
    return FRFData(freq, h * (1 + sigma * noise), quantity="accelerance")


def test_a_mode_added_by_the_second_search_is_refined_in_full(monkeypatch):
    """A mode the second search adds comes from a quick trial refinement (15 steps, no
    standard deviations under relative weights); the fit refines in full after it, so
    every mode has its standard deviation (before: NaN for the whole fit). Which noise
    draws make the second search add a mode depends on the rounding of the machine
    (seed 1 did, with numpy 2.4.6 seed 11 of the stronger partner does): the draws
    where it does are found by watching the search (a mode added from a full
    refinement under relative weights: the second search), and there must be one."""
    started_full = []
    search = PoleChecks._missed_mode

    def watched(self, omega, h, w, poles, kinds, x, info, *rest):
        out = search(self, omega, h, w, poles, kinds, x, info, *rest)
        if out[-1]:
            started_full.append(not info.get("quick"))
        return out

    monkeypatch.setattr(PoleChecks, "_missed_mode", watched)
    draws = [(seed, weak_mass) for seed in (1, 11) + tuple(range(2, 11)) + (12,)
             for weak_mass in (-8.0, 8.0)]
    for seed, weak_mass in draws:
        started_full.clear()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = ModalFit(passive=False).fit(close_pair_data(seed, weak_mass))
        if fit.report_["weighting"] == "relative" and any(started_full):
            break
    else:
        raise AssertionError("no draw made the second search add a mode")
    modes = fit.report_["modes"]
    for column in ("frequency_hz_std", "damping_ratio_std"):
        assert np.all(np.isfinite(modes[column])) and np.all(modes[column] > 0)


def test_a_kept_local_trial_joins_with_its_own_poles_unless_a_mode_moved_away():
    """A mode kept by the local trial enters the model with the local fit's poles and
    linear residues (no refinement over the band), and the search goes on from there;
    when the local fit moved another mode by more than three half-power half-widths
    (onto another feature, to make room) the trial is refined over the band instead.
    Exact data with a mode the model lacks: the joined model holds it where the truth
    has it, and the linear residues make the model exact (the cost of the model without
    it is 20 orders of magnitude larger)."""
    omega = 2 * np.pi * np.arange(600.0, 1400.0)
    wn = 2 * np.pi * np.array([800.0, 1000.0, 1200.0])
    truth = ModalModel.from_modes(wn, [1e-3, 1e-3, 1e-3], [1.0, 1.5, 2.0])
    h = truth.frf(omega)
    poles = truth.poles[[0, 2]]                         # the 1000 Hz mode is missing
    assert ModalFit._stayed(omega, poles, poles + 2.9 * np.maximum(-poles.real, 2 * np.pi))
    assert not ModalFit._stayed(omega, poles, poles * 1.06)
    fit = ModalFit(passive=False)
    fit._buffers = {}
    kinds = np.array(["mode", "mode"])
    terms = Terms(np.zeros(0), False, False, 0.0)
    joined, kinds_j, x, info = fit._join(omega, h, np.ones_like(omega), poles, kinds,
                                         terms, truth.poles[1:2])
    assert info["quick"] and list(kinds_j) == ["mode"] * 3
    np.testing.assert_allclose(np.sort(np.abs(joined)), np.sort(np.abs(truth.poles)),
                               rtol=1e-15)
    *_, lacking = fit._join(omega, h, np.ones_like(omega), poles, kinds, terms,
                            np.zeros(0, complex))
    assert info["cost"] < 1e-20 * lacking["cost"]
