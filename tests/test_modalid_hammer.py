"""Hammer FRF estimation against exact synthetic hammer tests, and on real hammer records."""

import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import argrelmax

from data_synth import synthetic_hammer_test
from modalid import (DoubleHitWarning, HammerFRF, ModalFit, ModalModel, correct_exponential_window,
                     find_double_hits, frf_from_hammer)

FS = 10_000.0
DURATION = 4.0        # the slowest mode decays by exp(-50): no leakage
PULSE = 1e-3          # force spectrum: -3 dB near 600 Hz, first zero at 1500 Hz
REAL_DATA = Path("/work/shared/data/measured/pyfrf_hammer_impacts")


@pytest.fixture(scope="module")
def truth():
    return ModalModel.from_modes(2 * np.pi * np.array([100.0, 250.0, 600.0]),
                                 [0.02, 0.01, 0.01], [1.0, 2.0, 0.5])


@pytest.fixture(scope="module")
def clean(truth):
    return synthetic_hammer_test(truth, FS, DURATION, n_hits=2, force_peak=[100.0, 70.0],
                                 pulse_width=PULSE, anti_alias=True)


def in_band(est, fmin=5.0, db=20.0):
    """Lines from fmin where the force spectrum is within db of its maximum."""
    s = est.force_spectrum
    return (est.frf.freq_hz >= fmin) & (s >= s.max() * 10 ** (-db / 10))


def rel_error(est, test, mask):
    exact = test.true_frf(est.frf.freq_hz[mask]).values
    return np.abs(est.frf.values[mask] - exact) / np.abs(exact)


# ---------------------------------------------------------------------- accuracy
def test_clean_long_record_reproduces_the_exact_frf(clean):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DoubleHitWarning)
        est = frf_from_hammer(clean.force, clean.response, FS, force_window="none")
    assert isinstance(est, HammerFRF) and est.n_hits == 2 and est.double_hits == ()
    assert est.frf.quantity == "accelerance" and est.window_decay_rate == 0.0
    np.testing.assert_allclose(est.frf.freq_hz, np.arange(est.frf.freq_hz.size) / DURATION)
    band = in_band(est)
    assert est.frf.freq_hz[band].max() > 1000.0       # the band holds all three modes
    assert np.all(est.coherence[band] > 1 - 1e-9)
    err = rel_error(est, clean, band)
    assert err.max() < 1e-2                           # measured: 2.0e-3 (at 5 Hz)
    assert np.median(err) < 1e-5                      # measured: 2.8e-6
    # the force window (default length) changes nothing on clean data
    windowed = frf_from_hammer(clean.force, clean.response, FS)
    assert windowed.force_window_length == pytest.approx((20 + 5 + 5 * 7) / FS, abs=3 / FS)
    np.testing.assert_allclose(windowed.frf.values[band], est.frf.values[band], rtol=1e-6)
    # the hits 20 samples in, five pulse widths (35) before them is the record's start:
    # there is no pre-trigger to cut
    assert windowed.record_starts is None


@pytest.mark.parametrize("response", ["displacement", "velocity"])
def test_other_response_types(truth, response):
    test = synthetic_hammer_test(truth, FS, DURATION, pulse_width=PULSE, response=response,
                                 anti_alias=True)
    est = frf_from_hammer(test.force[0], test.response[0], FS, response_type=response)
    assert est.frf.quantity == test.quantity
    assert est.coherence is None                      # one hit: coherence is not measured
    assert rel_error(est, test, in_band(est)).max() < 1e-4   # measured: 3.7e-5, 4.2e-5


def test_ideal_sampler_aliases_the_mass_line(truth):
    """Without an anti-aliasing filter the half-sine's 1/f^2 tail times the mass line of the
    accelerance aliases onto the small low-frequency accelerance."""
    test = synthetic_hammer_test(truth, FS, DURATION, pulse_width=PULSE)
    est = frf_from_hammer(test.force, test.response, FS)
    err = rel_error(est, test, in_band(est))
    assert err.max() > 1.0 and np.median(err) > 1e-3
    disp = synthetic_hammer_test(truth, FS, DURATION, pulse_width=PULSE, response="displacement")
    est = frf_from_hammer(disp.force, disp.response, FS, response_type="displacement")
    err = rel_error(est, disp, in_band(est))         # force aliasing only
    assert 1e-3 < np.median(err) < 0.02 and err.max() < 0.1   # measured: 0.013, 0.047


# ------------------------------------------------------------- exponential window
@pytest.mark.parametrize("response", ["acceleration", "displacement"])
@pytest.mark.parametrize("decay", [5.0, 30.0])
def test_exponential_window_shifts_every_pole_and_keeps_residues(truth, response, decay):
    test = synthetic_hammer_test(truth, FS, DURATION, pulse_width=PULSE, response=response,
                                 anti_alias=True)
    est = frf_from_hammer(test.force, test.response, FS, response_type=response,
                          exponential_decay=decay)
    assert est.window_decay_rate == decay
    shifted = ModalModel(poles=truth.poles - decay, residues=truth.residues)
    band = in_band(est, fmin=20.0)
    f = est.frf.freq_hz[band]
    exact = shifted.frf(2 * np.pi * f, quantity=test.quantity)
    err = np.abs(est.frf.values[band] - exact)
    assert err.max() < 1e-4 * np.abs(exact).max()     # measured: 1.6e-6
    assert np.median(err / np.abs(exact)) < 1e-5
    # and it is not the unwindowed FRF: the window adds damping
    unshifted = truth.frf(2 * np.pi * f, quantity=test.quantity)
    assert np.max(np.abs(est.frf.values[band] - unshifted)) > 0.1 * np.abs(unshifted).max()
    # undoing the window restores the model exactly
    restored = est.correct(shifted)
    np.testing.assert_allclose(restored.poles, truth.poles, rtol=1e-14)
    np.testing.assert_array_equal(restored.residues, truth.residues)


def test_correct_exponential_window_models_and_poles():
    model = ModalModel(poles=[-3.0 + 100j, -8.0 + 400j], residues=[-1e-3j, 2e-4 - 1e-4j],
                       real_poles=[-50.0], real_residues=[0.2], inverse_mass=0.5,
                       flexibility=1e-6)
    out = correct_exponential_window(model, 2.5)
    np.testing.assert_allclose(out.poles, [-0.5 + 100j, -5.5 + 400j])
    np.testing.assert_allclose(out.real_poles, [-47.5])
    np.testing.assert_array_equal(out.residues, model.residues)
    assert (out.inverse_mass, out.flexibility) == (0.5, 1e-6)
    # the shift theorem: H_w(s) = H(s + 1/tau) for the non-rigid part
    s = 1j * np.linspace(1, 600, 50)
    np.testing.assert_allclose(model.without_rigid_body().receptance(s),
                               out.without_rigid_body().receptance(s + 2.5), rtol=1e-12)
    np.testing.assert_allclose(correct_exponential_window([-3 + 1j, -4 + 2j], 1.0),
                               [-2 + 1j, -3 + 2j])
    assert correct_exponential_window(model, 0.0) == model
    # a pole the window did not damp alone is refused, not moved to Re p > 0
    with pytest.raises(ValueError, match=r"moves the pole -1\+10j to Re p >= 0"):
        correct_exponential_window([-1 + 10j], 5.0)
    with pytest.raises(ValueError, match=r"moves the pole -1\+10j to Re p >= 0"):
        correct_exponential_window(ModalModel(poles=[-1 + 10j], residues=[1j]), 5.0)
    undamped = ModalModel(poles=[10j], residues=[-0.05j])    # at decay 0: nothing moves
    assert correct_exponential_window(undamped, 0.0) == undamped
    with pytest.raises(ValueError, match="decay_rate must be non-negative, got -1.0"):
        correct_exponential_window(model, -1.0)
    with pytest.raises(ValueError, match="moves the real pole -50.0"):
        correct_exponential_window(model, 60.0)


# ------------------------------------------------------------- noise and averaging
def test_averaging_lowers_the_noise_and_coherence_drops_with_noise(truth):
    test = synthetic_hammer_test(truth, FS, 1.0, n_hits=16, pulse_width=PULSE,
                                 noise=(0.0, 0.002), anti_alias=True, seed=11)
    one = frf_from_hammer(test.force[:1], test.response[:1], FS, exponential_decay=10.0)
    four = frf_from_hammer(test.force[:4], test.response[:4], FS, exponential_decay=10.0)
    all16 = frf_from_hammer(test.force, test.response, FS, exponential_decay=10.0)
    shifted = ModalModel(poles=truth.poles - 10.0, residues=truth.residues)
    band = in_band(one, fmin=20.0)

    def rms_error(est):
        exact = shifted.frf(est.frf.omega[band], quantity="accelerance")
        return np.sqrt(np.mean(np.abs(est.frf.values[band] - exact) ** 2))

    e1, e4, e16 = rms_error(one), rms_error(four), rms_error(all16)
    # H1 with response noise: error std ~ 1/sqrt(n_hits)   (measured: 1 : 0.48 : 0.25)
    assert e4 < 0.65 * e1 and e16 < 0.6 * e4 and e16 < 0.35 * e1
    # coherence: below 1 with noise, lowest where the response is small
    coh = all16.coherence[band]
    assert 0.9 < np.median(coh) < 1 - 1e-6           # measured: 0.9998 (0.80 at worst)
    clean = synthetic_hammer_test(truth, FS, 1.0, n_hits=4, pulse_width=PULSE, anti_alias=True)
    clean_coh = frf_from_hammer(clean.force, clean.response, FS).coherence[band]
    assert np.min(clean_coh) > 1 - 1e-9 and np.median(coh) < np.median(clean_coh)
    noisier = synthetic_hammer_test(truth, FS, 1.0, n_hits=16, pulse_width=PULSE,
                                    noise=(0.0, 0.02), anti_alias=True, seed=11)
    coh2 = frf_from_hammer(noisier.force, noisier.response, FS).coherence[band]
    assert np.median(coh2) < np.median(coh)          # measured: 0.73


def test_a_sensor_offset_is_removed_from_the_pre_trigger(truth, clean):
    """A constant on a channel (an accelerometer's DC offset) is measured on the samples
    before the hits, where the structure is at rest, and removed: the H1 is the offset-
    free one to rounding, windowed or not. Noise alone is left as it is."""
    for decay in (0.0, 10.0):
        exact = frf_from_hammer(clean.force, clean.response, FS, exponential_decay=decay)
        est = frf_from_hammer(clean.force + 0.01, clean.response + 0.3, FS,
                              exponential_decay=decay)
        assert est.offsets == pytest.approx((0.01, 0.3), rel=1e-9)
        band = in_band(exact)             # not at the force spectrum's zeros (rounding)
        np.testing.assert_allclose(est.frf.values[band], exact.frf.values[band], rtol=1e-9)
        kept = frf_from_hammer(clean.force, clean.response + 0.3, FS, exponential_decay=decay,
                               baseline="none")
        assert kept.offsets is None
        wrong = np.abs(kept.frf.values[1:6] / exact.frf.values[1:6] - 1)
        assert np.all(wrong > (0.5 if decay else 0.0))   # the window spreads it to low lines
    noisy = synthetic_hammer_test(truth, FS, 1.0, n_hits=4, pulse_width=PULSE, anti_alias=True,
                                  noise=(0.01, 0.01), seed=5)
    est = frf_from_hammer(noisy.force, noisy.response, FS, exponential_decay=10.0)
    as_is = frf_from_hammer(noisy.force, noisy.response, FS, exponential_decay=10.0,
                            baseline="none")
    assert est.offsets == (0.0, 0.0)
    np.testing.assert_array_equal(est.frf.values, as_is.frf.values)
    # a 50 Hz hum is a constant within a 2 ms pre-trigger, but not from hit to hit: not an
    # offset (the white-noise standard error alone took it for one in half the trials)
    rng = np.random.default_rng(7)
    t = np.arange(noisy.force.shape[1]) / FS
    hum = 0.02 * np.sin(2 * np.pi * 50 * t + rng.uniform(0, 2 * np.pi, (4, 1)))
    assert frf_from_hammer(noisy.force, noisy.response + hum, FS).offsets[1] == 0.0
    # a force offset beyond 5 % of the peak still leaves its pre-trigger (the level is
    # measured from the record's median); one hit or no pre-trigger: none measured
    shifted = frf_from_hammer(clean.force + 10.0, clean.response, FS)
    assert shifted.offsets == pytest.approx((10.0, 0.0), rel=1e-9)
    assert frf_from_hammer(clean.force[:1], clean.response[:1] + 0.3, FS).offsets is None
    late = frf_from_hammer(clean.force[:, 18:], clean.response[:, 18:] + 0.3, FS)
    assert late.offsets is None
    with pytest.raises(ValueError, match="baseline must be one of"):
        frf_from_hammer(noisy.force, noisy.response, FS, baseline="mean")


def test_force_window_removes_force_channel_noise(clean):
    """Noise on the force over the whole record biases H1 low (it adds to Sff only); the
    force window keeps the pulse and drops that noise."""
    test = synthetic_hammer_test(clean.model, FS, 1.0, n_hits=8, pulse_width=PULSE,
                                 noise=(0.01, 0.0), anti_alias=True, seed=2)
    bare = frf_from_hammer(test.force, test.response, FS, force_window="none")
    windowed = frf_from_hammer(test.force, test.response, FS)
    assert windowed.force_window_length < 0.01
    band = in_band(windowed, fmin=20.0)
    exact = test.true_frf(bare.frf.freq_hz[band]).values
    ratio_bare = np.abs(bare.frf.values[band]) / np.abs(exact)
    err_bare = rel_error(bare, test, band)
    err = rel_error(windowed, test, band)
    assert np.median(ratio_bare) < 0.97               # biased low; measured: 0.93
    assert np.median(err) < 0.2 * np.median(err_bare)  # measured: 0.007 against 0.094


# ------------------------------------------------------------------- double hits
def test_double_hit_warns_with_hit_index_and_time(truth):
    test = synthetic_hammer_test(truth, FS, 1.0, n_hits=3, pulse_width=PULSE, double_hit=[2],
                                 hit_times=0.01)
    second_peak = 0.01 + 3 * PULSE + PULSE / 2
    with pytest.warns(DoubleHitWarning, match=r"hit 2: .* 30% .* t = 0\.0135 s") as record:
        est = frf_from_hammer(test.force, test.response, FS)
    assert len(record) == 1
    assert est.double_hits == (2,)
    [(hit, time, ratio)] = find_double_hits(test.force, FS)
    assert hit == 2 and time == pytest.approx(second_peak, abs=0.5 / FS)
    assert ratio == pytest.approx(0.3, rel=1e-12)
    # a smaller second pulse below the threshold is not flagged; sign does not matter
    assert find_double_hits(-test.force, FS, threshold=0.35) == []
    assert find_double_hits(-test.force[2], FS)[0][0] == 0
    # pulses that merge (no drop below the threshold between them) are one pulse
    merged = synthetic_hammer_test(truth, FS, 0.2, pulse_width=PULSE, double_hit=True,
                                   double_hit_delay=PULSE)
    assert find_double_hits(merged.force, FS, threshold=0.5) == []


def test_noise_spikes_are_not_double_hits(truth):
    # white noise of 5 % of the peak on the force: single samples pass 10 % of the peak
    # after the pulse (a raw-sample test would flag every hit), a pulse never does
    test = synthetic_hammer_test(truth, FS, 1.0, n_hits=5, pulse_width=PULSE, noise=0.05,
                                 seed=4, hit_times=0.01)
    force = test.force
    k0 = np.argmax(np.abs(force), axis=1)
    spikes = [np.sum(np.abs(f[k + 3 * int(PULSE * FS):]) > 0.1 * np.abs(f[k]))
              for f, k in zip(force, k0)]
    assert min(spikes) > 0
    assert find_double_hits(force, FS) == []
    # a real second pulse in the same noise is still found
    double = synthetic_hammer_test(truth, FS, 1.0, n_hits=5, pulse_width=PULSE, noise=0.05,
                                   seed=4, hit_times=0.01, double_hit=[3])
    assert [hit for hit, _, _ in find_double_hits(double.force, FS)] == [3]


# ------------------------------------------------------------------- bad input
def test_bad_inputs_raise_naming_the_value(clean):
    f, x = clean.force, clean.response
    bad = f.copy()
    bad[1, 7] = np.nan
    with pytest.raises(ValueError, match="force must be finite, got .*nan"):
        frf_from_hammer(bad, x, FS)
    with pytest.raises(ValueError, match=r"same shape, got \(2, 40000\) and \(2, 39999\)"):
        frf_from_hammer(f, x[:, 1:], FS)
    for fs in (0.0, -FS):
        with pytest.raises(ValueError, match=f"fs must be positive, got {fs!r}"):
            frf_from_hammer(f, x, fs)
    with pytest.raises(ValueError, match="force_window_length must not exceed the record "
                                         r"length 4 s .* got 5.0"):
        frf_from_hammer(f, x, FS, force_window_length=5.0)
    with pytest.raises(ValueError, match="ends before the force peak of hit 0"):
        frf_from_hammer(f, x, FS, force_window_length=1e-3)
    with pytest.raises(ValueError, match="force_window_length is used only with"):
        frf_from_hammer(f, x, FS, force_window="none", force_window_length=0.1)
    with pytest.raises(ValueError,
                       match=r"n_fft must be >= the record length 40000 \(.*\), got 100"):
        frf_from_hammer(f, x, FS, n_fft=100)
    with pytest.raises(ValueError, match=r"n_fft must be at most 16777216 \(64 times the "
                                         r"record length 40000, .*\), got 100000000000"):
        frf_from_hammer(f, x, FS, n_fft=10**11)           # was a MemoryError
    with pytest.raises(ValueError, match="exponential_decay must be non-negative, got -2.0"):
        frf_from_hammer(f, x, FS, exponential_decay=-2.0)
    with pytest.raises(ValueError, match="response_type must be one of"):
        frf_from_hammer(f, x, FS, response_type="strain")
    with pytest.raises(ValueError, match=r"1-D \(one hit\) or 2-D .* got shape \(1, 1, 40000\)"):
        frf_from_hammer(f[None, :1], x[None, :1], FS)
    with pytest.raises(ValueError, match="force of hit 0 is identically zero"):
        frf_from_hammer(np.zeros(100), np.ones(100), FS)
    with pytest.raises(TypeError, match="force must be real"):
        frf_from_hammer(f + 0j, x, FS)


def test_the_lines_stop_where_asked(clean):
    """Every line to the Nyquist frequency by default; ``max_freq_hz`` chooses a lower top
    (an analyzer's is fs / 2.56), never above it."""
    n = clean.force.shape[1]
    full = frf_from_hammer(clean.force, clean.response, FS)
    assert full.frf.freq_hz[-1] == FS / 2 and len(full.frf) == n // 2 + 1
    cut = frf_from_hammer(clean.force, clean.response, FS, max_freq_hz=FS / 2.56)
    assert cut.frf.freq_hz[-1] <= FS / 2.56 < cut.frf.freq_hz[-1] + FS / n
    assert cut.force_spectrum.shape == cut.frf.values.shape == cut.frf.coherence.shape
    np.testing.assert_array_equal(full.frf.values[:len(cut.frf)], cut.frf.values)
    with pytest.raises(ValueError, match=r"max_freq_hz must be at most the Nyquist frequency "
                                         r"fs / 2 = 5000 Hz, got 6000"):
        frf_from_hammer(clean.force, clean.response, FS, max_freq_hz=6000)
    with pytest.raises(ValueError, match="max_freq_hz must be positive"):
        frf_from_hammer(clean.force, clean.response, FS, max_freq_hz=-1.0)


@pytest.mark.parametrize("samples, anti_alias, said", [(3, False, True), (20, False, False),
                                                      (3, True, False)])
def test_force_above_the_nyquist_frequency_is_said(truth, samples, anti_alias, said):
    """A hit of a few samples puts force above fs / 2; sampled without an anti-aliasing
    filter it folds onto the band (a fixed rod's H1 was then called a transfer FRF, and
    nothing had said why). The force spectrum near the Nyquist line within 30 dB of its
    peak is said; a hit of 20 samples, or the records through a filter, are not."""
    test = synthetic_hammer_test(truth, FS, 1.0, n_hits=2, pulse_width=samples / FS,
                                 anti_alias=anti_alias, noise=0.01, seed=1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf_from_hammer(test.force, test.response, FS)
    words = [str(w.message) for w in caught if "Nyquist" in str(w.message)]
    assert len(words) == said
    if said:
        assert re.match(r"the force spectrum near the Nyquist frequency \(4500-5000 Hz\) is "
                        r"only \d+\.?\d* dB below its peak", words[0])


def test_zero_padding_interpolates_the_same_frf(clean):
    est = frf_from_hammer(clean.force, clean.response, FS, n_fft=2 * clean.force.shape[1])
    assert est.frf.freq_hz[1] == pytest.approx(1 / (2 * DURATION))
    band = in_band(est)
    assert rel_error(est, clean, band).max() < 1e-2


def test_one_hit_is_fitted_where_the_hammer_reached(truth):
    """One hit (no coherence) of a 2 ms half-sine pulse: its force autospectrum falls
    20 dB below its peak at 650 Hz (1.3 / width) and has its first zero at 750 Hz;
    above, the response is the sensor's noise over a force that is not there. The FRF
    carries the force spectrum (``excitation``), and ``ModalFit()`` with no options ends
    its band there, says why, and finds the three modes below it to 1e-3."""
    test = synthetic_hammer_test(truth, FS, 2.0, pulse_width=2e-3, noise=(0.0, 0.002),
                                 anti_alias=True, seed=1)
    est = frf_from_hammer(test.force, test.response, FS)
    assert est.coherence is None
    np.testing.assert_array_equal(est.frf.excitation, est.force_spectrum)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(est.frf)
    lo, hi = fit.report_["band_hz"]
    assert 600 <= hi <= 700, (lo, hi)
    assert "excitation's spectrum is 20 dB" in fit.report_["band_reason"]
    found = np.sort(fit.report_["modes"]["frequency_hz"].to_numpy())
    np.testing.assert_allclose(found, [100.0, 250.0, 600.0], rtol=1e-3)


# ------------------------------------------------------------------- real data
@pytest.fixture(scope="module")
def real_records():
    files = [REAL_DATA / f"measurements_{i}.npy" for i in range(1, 6)]
    if not all(p.exists() for p in files):
        pytest.skip(f"real hammer records not found in {REAL_DATA}")
    return np.array([np.load(p) for p in files])            # (5, 3, 25600): t, force, acc


def real_h1(records):
    """The H1 accelerance of the five real hits, frf_from_hammer's defaults."""
    fs = 1.0 / np.mean(np.diff(records[0, 0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return frf_from_hammer(records[:, 1], records[:, 2], fs,
                               response_type="acceleration").frf


def test_real_hammer_records_show_the_documented_peaks(real_records):
    t = real_records[0, 0]
    fs = 1.0 / np.mean(np.diff(t))
    assert fs == pytest.approx(25_600.0, rel=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DoubleHitWarning)
        est = frf_from_hammer(real_records[:, 1], real_records[:, 2], fs,
                              response_type="acceleration", force_window="none")
    assert est.n_hits == 5 and est.frf.quantity == "accelerance"
    f, mag = est.frf.freq_hz, np.abs(est.frf.values)
    maxima = f[argrelmax(mag)[0]]
    for peak in (810, 824, 851, 900, 1518, 2640, 3008, 3035, 3108, 3162, 3669, 4128, 4164,
                 4392, 4470):
        assert np.min(np.abs(maxima - peak)) <= 2.0, f"no local maximum of |H| near {peak} Hz"
    band = (f >= 20) & (f <= 5000)
    assert np.median(est.coherence[band]) > 0.99              # measured: 0.9989
    # pyFRF's showcase settings: force window 1 % and exponential window to 1 % of the record
    windowed = frf_from_hammer(real_records[:, 1], real_records[:, 2], fs,
                               force_window_length=0.01, exponential_decay=-np.log(0.01))
    assert np.median(windowed.coherence[band]) > 0.999        # measured: 0.9999
    assert windowed.window_decay_rate == pytest.approx(4.60517, rel=1e-5)


def test_response_weighted_fit_options(truth):
    """fit_options(weighted=True) adds weights sqrt(S_ff coherence), one per line of the
    estimate (S_ff alone for one hit); ModalFit fits est.frf with them and finds the
    truth's modes; the unweighted default is unchanged."""
    from modalid import ModalFit

    test = synthetic_hammer_test(truth, FS, 1.0, n_hits=4, pulse_width=PULSE,
                                 noise=(0.0, 0.002), anti_alias=True, seed=3)
    est = frf_from_hammer(test.force, test.response, FS)
    options = est.fit_options(weighted=True)
    assert set(options) == {"window_decay_rate", "record_length", "weights"}
    np.testing.assert_allclose(
        options["weights"], np.sqrt(est.force_spectrum * np.clip(est.coherence, 1e-3, 1)))
    assert "weights" not in est.fit_options()
    one = frf_from_hammer(test.force[:1], test.response[:1], FS)
    np.testing.assert_allclose(one.fit_options(weighted=True)["weights"],
                               np.sqrt(one.force_spectrum))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(**options).fit(est.frf)
    found = np.sort(fit.report_["modes"]["frequency_hz"].to_numpy())
    exact = np.sort(truth.modes["frequency_hz"].to_numpy())
    exact = exact[exact < fit.report_["band_hz"][1]]
    assert np.all(np.min(np.abs(found[:, None] - exact), axis=0) < 1e-3 * exact)


@pytest.mark.parametrize("freq_range, peaks", [
    ((4000, 4600), [4128, 4164, 4392, 4470]),
    ((3500, 4500), [3669, 4128, 4164, 4392, 4470]),
])
def test_real_hammer_frf_on_a_band_the_user_chose(real_records, freq_range, peaks):
    """The real hammer test's H1 (a transfer FRF) on a band a user zooms into, no other
    option: the global estimator finds no stable pole on 4000-4600 Hz (one on 3500-4500),
    so the quick unconstrained probe found no resonance (one) and, for want of evidence,
    the FRF was taken for a driving point and the passive fit dropped every mode (verdict
    failed). A probe that misses what the band holds (no resonance, or a median line error
    above the verdict's tolerance) no longer decides: the full unconstrained
    identification does. Every documented peak of the band within 0.3 %, verdict ok."""
    frf = real_h1(real_records)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit(freq_range=freq_range).fit(frf)
    f = fit.report_["modes"]["frequency_hz"].to_numpy()
    for p in peaks:
        assert np.min(np.abs(f - p)) < 3e-3 * p, (p, f)
    assert fit.report_["verdict"] == "ok" and not fit.report_["driving_point"]


def test_real_hammer_frf_on_a_wide_band_the_user_chose(real_records):
    """The real hammer test's H1 on 10-4600 Hz (4590 lines, 22 peaks of |H|) and 100-6000
    Hz (27 peaks), fitted as one band: the missed-mode search added at most six modes per
    pass, used them all on stronger peaks, and never reached the 3108 Hz mode (a weak
    peak between the 3035 and 3669 Hz ones; 100-6000 Hz at 11.5 % FRF error). Its budget
    now grows with the band's peaks (half of them per pass): every documented peak in
    these bands but 3162 Hz (the file's deepest antiresonance, benchmarks/README.md)
    within 0.3 %, and 100-6000 Hz at 6.6 %."""
    frf = real_h1(real_records)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fits = [ModalFit(freq_range=band).fit(frf) for band in ((10, 4600), (100, 6000))]
    peaks = (810, 824, 851, 900, 1518, 2640, 3008, 3035, 3108, 3669, 4128, 4164, 4392, 4470)
    for fit in fits:
        report = fit.report_
        assert report["segments"] == 1 and report["verdict"] == "ok"
        f = report["modes"]["frequency_hz"].to_numpy()
        for p in peaks:
            assert np.min(np.abs(f - p)) < 3e-3 * p, (p, f)
        assert report["frf_nrmse"] < 0.07


def test_a_windowed_fit_is_judged_as_delivered(real_records):
    """The real hits with an exponential window, fitted on 1-7020 Hz with the window
    undone: a pseudo-mode at four times the band top, all but undamped, has its damping
    held when the window is removed (``window_clipped``). The report speaks of the model
    delivered (the one plotted), windowed again. That model used to miss the data by 30 %
    where the fit did by 10 %: the pseudo-mode, on a DFT line, had its residue divided by
    its record-end factor. A pseudo-mode is not a free decay the record cut; kept as
    fitted, the delivered model misses the data by the fit's own 10 %."""
    fs = 1.0 / np.mean(np.diff(real_records[0, 0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est = frf_from_hammer(real_records[:, 1], real_records[:, 2], fs,
                              response_type="acceleration", exponential_decay=4.6)
        fit = ModalFit(freq_range=(0, 7020), **est.fit_options()).fit(est.frf)
    report = fit.report_
    row = fit.data_.select(fit.data_.freq_hz > 0)
    delivered = fit._fitted_values(row)           # what plot_fit draws
    error = np.linalg.norm(delivered - row.values) / np.linalg.norm(row.values)
    assert report["frf_nrmse"] == pytest.approx(error, rel=1e-9)
    assert report["window_clipped"] >= 1 and error < 0.11
    # the accelerometer's offset (0.27 m/s^2 before the hits), windowed, was a false term
    # at the lowest lines that took the fit's low-end model away: "suspect", a median
    # error per line of 11.4 %; removed (the default), "ok" at 2.8 %. Kept, the model
    # missed the band's lowest lines (1-548 Hz) with no term below the band: refitted
    # with the lower residual (session #36), which takes the offset's term, "ok" at 0.7 %
    assert est.offsets[0] == 0.0 and est.offsets[1] == pytest.approx(0.2676, abs=1e-4)
    assert report["verdict"] == "ok" and report["frf_median_relative_error"] < 0.04
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kept = frf_from_hammer(real_records[:, 1], real_records[:, 2], fs,
                               response_type="acceleration", exponential_decay=4.6,
                               baseline="none")
        fit = ModalFit(freq_range=(0, 7020), **kept.fit_options()).fit(kept.frf)
    assert fit.report_["verdict"] == "ok" and fit.report_["lower_residual_mode"]
    assert any(n.startswith("refitted with the lower residual: without it the model missed "
                            "the band's lowest lines (1-") for n in fit.report_["notes"])


def test_the_pretrigger_force_is_windowed_out():
    """Five hits after a 5 % pre-trigger, 1 % noise, a window to 1 %: the pre-trigger's
    force noise held the averaged force spectrum up past the hammer's reach, and the
    automatic band ran to the Nyquist line (12800 Hz: 43 modes for the rod's 13 there,
    "suspect"). The automatic force window starts five half-widths before each hit, so
    the band stops at the reach, as after a 1 % pre-trigger (6.5 kHz, verdict ok)."""
    from data_synth import Rod, lightly_damped

    fs = 25600.0
    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, fs, 1.0, n_hits=5, pulse_width=2e-4, hit_times=0.05,
                                 noise=1e-2, seed=3, anti_alias=True)
    est = frf_from_hammer(test.force, test.response, fs, exponential_decay=4.6)
    starts = np.array(est.force_window_starts)
    assert starts.shape == (5,) and np.all((starts > 0.05 - 10 * 2e-4) & (starts < 0.05))
    fit = ModalFit().fit(est.frf)
    assert fit.report_["band_hz"][1] < 7000 and fit.report_["verdict"] == "ok"
    assert len(fit.model_.modes) <= 16
    given = frf_from_hammer(test.force, test.response, fs, force_window_length=0.06)
    assert given.force_window_starts is None       # a given length starts at t = 0


def test_a_force_offset_does_not_widen_the_force_window():
    """One hit (its offset cannot be measured: no pre-trigger) on a force channel offset
    by 1.5 times the pulse's height: the pulse's width is measured from the record's
    median, so the automatic force window is the one without the offset (it took the
    whole record: every sample lay above half the offset peak)."""
    from data_synth import Rod, lightly_damped

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, 25600.0, 1.0, n_hits=1, pulse_width=2e-4,
                                 hit_times=0.0, noise=1e-2, seed=4, anti_alias=True)
    clean = frf_from_hammer(test.force, test.response, 25600.0)
    offset = test.force + 1.5 * np.max(np.abs(test.force))
    shifted = frf_from_hammer(offset, test.response, 25600.0)
    assert shifted.force_window_length == clean.force_window_length < 2e-3


def test_swapped_channels_are_said():
    """Force and response given the other way round: the force lies within five
    half-widths of its peak (pyFRF's real hits: 99.9 % of its energy, the response 2.4 %;
    a synthetic rod's at 1 % noise: 51 % and 6 %), so a warning says the channels look
    swapped, before the double hits the ringing response shows as a force; in order, no
    word."""
    from data_synth import Rod, lightly_damped

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, 25600.0, 1.0, n_hits=3, pulse_width=2e-4,
                                 noise=0.01, seed=1, anti_alias=True)
    pairs = [(test.force, test.response)]
    paths = [REAL_DATA / f"measurements_{i}.npy" for i in range(1, 6)]
    if all(p.is_file() for p in paths):
        records = np.array([np.load(p, allow_pickle=False) for p in paths])
        pairs.append((records[:, 1], records[:, 2]))
    for force, response in pairs:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            frf_from_hammer(force, response, 25600.0)
        assert not [w for w in said if "swapped" in str(w.message)]
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            frf_from_hammer(response, force, 25600.0)
        assert "channels swapped?" in str(said[0].message)


def test_a_pretrigger_is_cut_where_the_record_end_matters():
    """A fixed rod (zeta 1e-3: its modes ring to the end of the 1 s records), five hits
    after a 5 % pre-trigger, no window, 1e-3 noise: the record's end is modelled for a
    hit at the record's start, and kept whole the pre-trigger turned its terms by
    omega t_0 (restitution of a 1 kg mass at 1 m/s 0.031 too high). By default the records
    are cut at each hit's force window start (0.006 too high); with a window the records
    are kept (its terms are small there)."""
    from data_synth import LumpedMass, Rod, lightly_damped

    from impactpred import Body, predict, solve_impact

    fs = 25600.0
    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, fs, 1.0, n_hits=5, pulse_width=2e-4, hit_times=0.05,
                                 noise=1e-3, seed=1, anti_alias=True)
    exact = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(truth),
                         t_end=0.01).restitution
    errors = {}
    for pretrigger in ("auto", "keep"):
        est = frf_from_hammer(test.force, test.response, fs, pretrigger=pretrigger)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pred = predict("mass:1", ModalFit().fit(est.frf), velocity1=1.0, t_end=0.01,
                           band_check=False)
        errors[pretrigger] = abs(pred.figures["restitution"] - exact)
        if pretrigger == "auto":
            starts = np.array(est.record_starts)
            assert np.all((starts > 0.05 - 20 * 2e-4) & (starts < 0.05))
            assert est.record_length == pytest.approx(1.0 - starts.max())
            np.testing.assert_allclose(np.diff(est.frf.freq_hz), 1 / est.record_length)
        else:
            assert est.record_starts is None and est.record_length == 1.0
    assert errors["auto"] < 0.012 and errors["keep"] > 0.02       # measured 0.0064, 0.031
    windowed = frf_from_hammer(test.force, test.response, fs, exponential_decay=4.6)
    assert windowed.record_starts is None and windowed.record_length == 1.0


def test_the_force_window_keeps_a_double_hits_second_pulse():
    """One hit with a second pulse of 57 % 2 ms later (warned of as a double hit): the
    automatic force window ended five widths after the main peak, zeroing the second
    pulse the response still held; the fit of the fixed rod was refused as a transfer
    FRF (unwindowed) or "suspect" at 0.757 for 0.690 (window to 1 %). It now ends five
    widths after the second pulse: 0.693 and 0.701."""
    from data_synth import LumpedMass, Rod, lightly_damped

    from impactpred import Body, predict, solve_impact

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, 25600.0, 1.0, n_hits=1, pulse_width=2e-4,
                                 hit_times=0.01, noise=1e-3, seed=1, anti_alias=True,
                                 double_hit=True, double_hit_delay=2e-3, double_hit_ratio=0.57)
    exact = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(truth),
                         t_end=0.01).restitution
    with pytest.warns(DoubleHitWarning):
        est = frf_from_hammer(test.force, test.response, 25600.0)
    start = est.force_window_starts[0]
    assert start + est.force_window_length > 0.01 + 2e-3 + 2e-4   # past the second pulse
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ModalFit().fit(est.frf)
        pred = predict("mass:1", fit, velocity1=1.0, t_end=0.01, band_check=False)
    assert fit.report_["verdict"] == "ok"
    assert abs(pred.figures["restitution"] - exact) < 0.01


def test_a_sample_rate_in_khz_is_doubted():
    """25600 Hz given as 25.6 (kHz typed): the 0.2 ms pulse would last 0.2 s, no hammer's
    (0.05-20 ms): a warning asks whether fs is in Hz; the right rate gives no such word."""
    from data_synth import Rod, lightly_damped

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, 25600.0, 0.5, n_hits=2, pulse_width=2e-4,
                                 noise=1e-3, seed=1, anti_alias=True)
    with pytest.warns(UserWarning, match=r"lasts \d+ ms at half its height.*is fs=25.6 in Hz"):
        frf_from_hammer(test.force, test.response, 25.6)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        frf_from_hammer(test.force, test.response, 25600.0)
    assert not [w for w in said if "half its height" in str(w.message)]


def test_a_cut_that_cannot_be_made_is_refused_and_a_large_one_said():
    """pretrigger='cut' with a given n_fft or force window length cannot cut: refused
    (it was ignored); a late hit that leaves under 80 % of every record is warned of."""
    from data_synth import Rod, lightly_damped

    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 0.001, residual=True)
    test = synthetic_hammer_test(truth, 25600.0, 0.5, n_hits=2, pulse_width=2e-4,
                                 hit_times=[0.05, 0.3], noise=1e-3, seed=1, anti_alias=True)
    n = test.force.shape[1]
    for given in ({"n_fft": n}, {"force_window_length": 0.4}, {"force_window": "none"}):
        with pytest.raises(ValueError, match="pretrigger='cut' needs the automatic force"):
            frf_from_hammer(test.force, test.response, 25600.0, pretrigger="cut", **given)
    with pytest.warns(UserWarning, match=r"the pre-trigger cut keeps \d+ of 12800 samples"):
        est = frf_from_hammer(test.force, test.response, 25600.0)
    assert est.record_length < 0.21
