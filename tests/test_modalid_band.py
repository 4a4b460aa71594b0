"""The automatic band and weighting of ModalFit (modalid._band) on FRFs whose good lines
are known: a clean cantilever receptance with junk lines at the bottom, a coherence that
collapses at the top, a resonance at the lowest lines, and two noise models."""

import numpy as np
import pytest

from data_synth import CantileverBeam
from modalid import FRFData
from modalid._band import choose_band, choose_weighting, roughness


def beam_frf(n_lines=2000, zeta=0.01, first=None):
    truth = CantileverBeam(1.0, 1.0).modal_model(16, damping_ratio=zeta, residual=True)
    wn = truth.modes["omega_n"].to_numpy()
    top = 0.5 * (wn[7] + wn[8]) / (2 * np.pi)
    df = top / n_lines if first is None else wn[0] / (2 * np.pi) / first
    freq = df * np.arange(1, n_lines + 1)
    return freq, truth.frf(2 * np.pi * freq)


def test_roughness_is_zero_on_a_line_and_large_on_noise():
    assert np.allclose(roughness(np.linspace(1, 2, 50) + 0j), 0.0, atol=1e-12)
    rng = np.random.default_rng(0)
    noise = rng.normal(size=500) + 1j * rng.normal(size=500)
    assert np.median(roughness(noise)) > 1.0


def test_a_clean_frf_keeps_every_line():
    freq, h = beam_frf()
    (lo, hi), reason = choose_band(FRFData(freq, h))
    assert (lo, hi) == (freq[0], freq[-1]) and reason == "all lines"


def test_noise_at_the_lowest_lines_is_dropped():
    freq, h = beam_frf(first=60)                 # the first mode at line 60
    rng = np.random.default_rng(1)
    junk = h.copy()
    junk[:12] = np.abs(h[:12]) * np.exp(2j * np.pi * rng.random(12)) * rng.uniform(0.3, 3, 12)
    (lo, hi), reason = choose_band(FRFData(freq, junk))
    assert freq[10] <= lo <= freq[14] and hi == freq[-1]
    assert "scatter like noise" in reason
    (lo, _), _ = choose_band(FRFData(freq, junk), low_end=False)
    assert lo == freq[0]


def test_a_resonance_at_the_lowest_lines_is_never_cut():
    """First mode between lines 2 and 3, 5 % noise: its lines are rough, but they hold a
    resonance."""
    freq, h = beam_frf(first=2.5)
    rng = np.random.default_rng(2)
    noisy = h * (1 + 0.05 * (rng.normal(size=h.size) + 1j * rng.normal(size=h.size)))
    (lo, _), _ = choose_band(FRFData(freq, noisy))
    assert lo == freq[0]


def test_lowest_lines_of_low_coherence_are_dropped():
    """A hammer test's first lines: coherence under 0.5 on four lines (the values smooth,
    so the roughness alone would keep them): they are dropped, and the reason says so."""
    freq, h = beam_frf(first=60)
    coherence = np.full(freq.size, 0.99)
    coherence[:4] = [0.03, 0.47, 0.21, 0.05]
    (lo, hi), reason = choose_band(FRFData(freq, h, coherence=coherence))
    assert lo == freq[4] and hi == freq[-1]
    assert "coherence of the lowest lines is under 0.5" in reason
    # good coherence everywhere: nothing is dropped
    (lo, _), _ = choose_band(FRFData(freq, h, coherence=np.full(freq.size, 0.99)))
    assert lo == freq[0]
    # never more than 5 % of the lines
    coherence[:200] = 0.2
    (lo, _), _ = choose_band(FRFData(freq, h, coherence=coherence))
    assert lo == freq[0]


def test_the_band_ends_where_the_coherence_collapses():
    freq, h = beam_frf()
    coherence = np.where(freq < freq[1499], 0.999, 0.3)
    (lo, hi), reason = choose_band(FRFData(freq, h, coherence=coherence))
    assert lo == freq[0] and freq[1490] <= hi <= freq[1499]
    assert "coherence" in reason
    # a dip in the middle (an antiresonance) and a recovery at the top do not end it
    dip = np.where((freq > freq[900]) & (freq < freq[950]), 0.3, 0.999)
    (_, hi), _ = choose_band(FRFData(freq, h, coherence=dip))
    assert hi == freq[-1]


def test_a_noisy_tests_coherence_ends_the_band_in_its_lower_half():
    """A noisy hammer test's coherence: 0.89 at best, 0.15-0.4 from a third of its lines
    on (a file without its force spectrum kept every line, FRF error 84 %, "suspect").
    The band ends where it falls, in the lower half too; a coherence poor everywhere
    alike (many averages: informative) keeps every line."""
    freq, h = beam_frf()
    rng = np.random.default_rng(3)
    coherence = np.where(freq < freq[650], 0.89, rng.uniform(0.15, 0.4, freq.size))
    (lo, hi), reason = choose_band(FRFData(freq, h, coherence=coherence))
    assert lo == freq[0] and freq[630] <= hi <= freq[650]
    assert "the smoothed coherence falls below" in reason
    (lo, hi), _ = choose_band(FRFData(freq, h, coherence=rng.uniform(0.2, 0.4, freq.size)))
    assert (lo, hi) == (freq[0], freq[-1])


def test_bad_valleys_between_good_peaks_do_not_end_the_band():
    """Coherence poor (0.1-0.45) on every line where the receptance is below its 55 %
    quantile, its valleys and most of its upper band, good (0.93-0.99) at the peaks: the
    running count of good against bad lines favours the band's start, but the band goes
    on past its last good peak, 88.4 Hz (it had ended at 37.7 Hz, losing the 47.5, 66.4
    and 88.4 Hz modes: review); the same coherence poor at the last peak too ends it
    below that peak, above the one before (66.4 Hz)."""
    freq, h = beam_frf()
    rng = np.random.default_rng(5)
    poor, good = rng.uniform(0.1, 0.45, freq.size), rng.uniform(0.93, 0.99, freq.size)
    valleys = np.abs(h) < np.quantile(np.abs(h), 0.55)
    (lo, hi), _ = choose_band(FRFData(freq, h, coherence=np.where(valleys, poor, good)))
    assert lo == freq[0] and hi > 88.5
    everything = np.where(valleys | (freq > 85.0), poor, good)
    (_, hi), reason = choose_band(FRFData(freq, h, coherence=everything))
    assert 66.5 < hi < 88.0 and "the smoothed coherence falls below" in reason


def half_sine_autospectrum(freq, width):
    """``|F(f)|^2`` of a half-sine pulse ``width`` (s) long, 1 at 0 Hz."""
    x = 2.0 * freq * width
    with np.errstate(divide="ignore", invalid="ignore"):
        amp = np.where(np.abs(x - 1.0) < 1e-9, np.pi / 4,
                       np.cos(np.pi * x / 2) / (1.0 - x**2))
    return amp**2


def test_without_coherence_the_band_ends_where_the_hammer_stops_reaching():
    """One hammer hit (no coherence) of a half-sine pulse: its force autospectrum falls
    20 dB below its peak at ``f = 1.30 / width`` and has its first zero at ``1.5 /
    width``. The band ends at the 20 dB point (to the smoothing's few lines), says so,
    and a flat excitation or a measured coherence leaves the band as it was."""
    freq, h = beam_frf()
    width = 1.30 / freq[1200]                 # the 20 dB point near line 1200
    force = half_sine_autospectrum(freq, width)
    exact = freq[np.flatnonzero(force < 1e-2 * force.max())[0]]
    (lo, hi), reason = choose_band(FRFData(freq, h, excitation=force))
    assert lo == freq[0] and abs(hi - exact) <= 10 * (freq[1] - freq[0])
    assert "excitation's spectrum is 20 dB or more below its peak" in reason
    (_, hi), reason = choose_band(FRFData(freq, h, excitation=np.ones(freq.size)))
    assert hi == freq[-1] and reason == "all lines"
    (_, hi), _ = choose_band(FRFData(freq, h, coherence=np.full(freq.size, 0.999),
                                     excitation=force))
    assert hi == freq[-1]


def test_above_the_hammers_reach_only_lines_of_high_coherence_count():
    """Averaged hits (coherence) of the same half-sine pulse, 20 dB down near line 1200:
    where the coherence is fair (0.8: the coherence rule alone keeps such lines) the band
    ends at the 20 dB point; where it stays at 0.999 to line 1600 and is fair above, it
    ends near line 1600, and the reason says which rule ended it."""
    freq, h = beam_frf()
    force = half_sine_autospectrum(freq, 1.30 / freq[1200])
    exact = freq[np.flatnonzero(force < 1e-2 * force.max())[0]]
    line = freq[1] - freq[0]
    fair = np.where(freq < exact, 0.999, 0.8)
    (_, hi), reason = choose_band(FRFData(freq, h, coherence=fair))
    assert hi == freq[-1]                            # the coherence rule alone keeps them
    (_, hi), reason = choose_band(FRFData(freq, h, coherence=fair, excitation=force))
    assert abs(hi - exact) <= 10 * line
    assert "above the excitation's reach (20 dB below its peak) the smoothed coherence " \
           "falls below 0.9" in reason
    high = np.where(freq < freq[1600], 0.999, 0.8)
    (_, hi), _ = choose_band(FRFData(freq, h, coherence=high, excitation=force))
    assert abs(hi - freq[1600]) <= 10 * line


def test_above_the_hammers_reach_the_force_must_not_have_fallen_40_db():
    """An analyzer's anti-aliasing filter (order 8) cuts the force near the Nyquist line
    while the coherence stays at 0.999: a fixed rod's H1 was 30-436 % off there, and the
    automatic band took those lines (walkthrough). Above the hammer's reach the lines count
    while the force stays within 40 dB of its peak too: the band ends where the filtered
    force falls that far, and the reason says so."""
    freq, h = beam_frf()
    force = half_sine_autospectrum(freq, 0.5 / freq[1200])       # reaches past the band
    cut = freq[1000]
    filtered = force / (1.0 + (freq / cut) ** 16)
    smooth = filtered / filtered.max()
    exact = freq[np.flatnonzero(smooth < 1e-4)[0]]
    (_, hi), reason = choose_band(FRFData(freq, h, coherence=np.full(freq.size, 0.999),
                                          excitation=filtered))
    assert abs(hi - exact) <= 10 * (freq[1] - freq[0]) and hi < freq[-1]
    assert "or the excitation 40 dB below its peak" in reason
    (_, hi), _ = choose_band(FRFData(freq, h, coherence=np.full(freq.size, 0.999),
                                     excitation=force))
    assert hi == freq[-1]


def test_a_band_limited_excitation_ends_the_band_above_its_peak_only():
    """A shaker driven over the middle of the band only: its autospectrum is 40 dB down
    over the lowest 500 lines, flat over lines 500-1499 and falls away above. The band
    ends where it falls above its peak (the lowest lines are no fall: the data there are
    judged by their scatter, as without excitation)."""
    freq, h = beam_frf()
    drive = np.where((freq >= freq[500]) & (freq < freq[1500]), 1.0, 1e-4)
    (lo, hi), reason = choose_band(FRFData(freq, h, excitation=drive))
    assert lo == freq[0] and freq[1495] <= hi <= freq[1505]
    assert f"above {hi:.6g} Hz (the excitation's spectrum" in reason


def test_no_usable_band_is_an_error():
    freq, h = beam_frf(n_lines=200)
    with pytest.raises(ValueError, match="no usable band"):
        choose_band(FRFData(freq, h, coherence=np.where(freq < freq[3], 0.999, 0.01)))
    with pytest.raises(ValueError, match="no usable band"):
        choose_band(FRFData(freq[:5], h[:5]))


def test_the_weighting_follows_the_noise_model():
    freq, h = beam_frf()
    rng = np.random.default_rng(3)
    e = (rng.normal(size=h.size) + 1j * rng.normal(size=h.size)) / np.sqrt(2)
    proportional, _ = choose_weighting(h * (1 + 0.05 * e))
    floor, reason = choose_weighting(h + 0.05 * np.sqrt(np.mean(np.abs(h) ** 2)) * e)
    assert proportional == "relative" and floor == "noise" and "noise floor" in reason
    assert choose_weighting(h)[0] == "relative"


def test_decimation_keeps_four_lines_across_the_sharpest_peak():
    """A 200 000-line FRF whose sharpest peak spans ~100 lines at half power: every k-th
    line is kept with 4 or more lines across it; bands of 50 000 lines or fewer, and
    peaks too sharp to thin, keep every line."""
    from data_synth import CantileverBeam
    from modalid._band import MANY_LINES, decimation

    truth = CantileverBeam(1.0, 1.0).modal_model(6, damping_ratio=0.01)
    wn = truth.modes["omega_n"].to_numpy()
    freq = np.linspace(0.2, 1.2, 200_000) * wn[3] / (2 * np.pi)
    h = truth.frf(2 * np.pi * freq)
    k, reason = decimation(h)
    width = 2 * 0.01 * wn[1] / (2 * np.pi) / (freq[1] - freq[0])   # mode 2, in lines
    assert 1 < k <= width / 4 and "every" in reason
    assert decimation(h[:MANY_LINES]) == (1, "")
    sharp = truth.frf(2 * np.pi * np.linspace(0.2, 1.2, 60_000) * wn[3] / (2 * np.pi))
    sharp_k, why = decimation(np.where(np.arange(60_000) % 997 == 0, 50.0, 1.0) * sharp)
    assert sharp_k == 1 and "kept" in why


# ------------------------------------------------------------------ the noise level
def test_running_percentile_keeps_its_window_inside_the_data():
    """Five large values at the start of 200 ones: a running median of 31 lines is 1
    everywhere (a window padded with the first value would read 100 there), and the
    window is centred away from the ends."""
    from modalid._noise import running_percentile

    x = np.ones(200)
    x[:5] = 100.0
    assert np.array_equal(running_percentile(x, 50, 31), np.ones(200))
    x = np.arange(100.0)
    centred = running_percentile(x, 50, 31)
    assert np.array_equal(centred[15:85], x[15:85])
    assert np.all(centred[:15] == 15.0) and np.all(centred[85:] == 84.0)
    assert np.array_equal(running_percentile(x[:10], 50, 31), np.full(10, 4.5))


def test_noise_level_beside_a_resonance_at_the_band_edge():
    """White noise of 1 % of the peak on an FRF whose first resonance sits on line 3: the
    estimate of the lowest lines is the noise's within 50 % (the rest is the curvature
    of the lines around the peak); a window padded with the edge line's curvature read
    it 49x too high on line 0."""
    from modalid._noise import noise_level

    freq, h = beam_frf(n_lines=3000, zeta=0.01, first=3)
    sigma = 1e-2 * np.max(np.abs(h))
    rng = np.random.default_rng(5)
    noisy = h + sigma * (rng.normal(size=h.size) + 1j * rng.normal(size=h.size)) / np.sqrt(2)
    ratio = noise_level(noisy) / sigma
    assert np.all((ratio[:20] > 0.8) & (ratio[:20] < 1.5))
    assert abs(np.median(ratio) - 1.0) < 0.1


def test_noise_weighting_is_estimated_in_the_quantity_measured():
    """An accelerance with a flat noise floor (0.1 % of its RMS) and its first mode, 1.3
    lines wide, on line 3: the noise weighting estimated in accelerance and carried to
    receptance finds that mode to 1e-6 in frequency and 0.2 % in modal mass. Estimated in
    receptance, where the floor grows like 1/omega^2 towards the lowest lines and the
    window was padded with the edge line, it read that mode's curvature as noise: -0.41 %
    in frequency."""
    from modalid import ModalFit

    freq, h = beam_frf(n_lines=3000, zeta=0.002, first=3)
    truth = CantileverBeam(1.0, 1.0).modal_model(16, damping_ratio=0.002, residual=True)
    acc = -((2 * np.pi * freq) ** 2) * h
    rng = np.random.default_rng(7)
    sigma = 1e-3 * np.sqrt(np.mean(np.abs(acc) ** 2))
    noisy = acc + sigma * (rng.normal(size=h.size) + 1j * rng.normal(size=h.size)) / np.sqrt(2)
    fit = ModalFit(weighting="noise").fit(FRFData(freq, noisy, quantity="accelerance"))
    modes = fit.model_.modes.sort_values("omega_n")
    true = truth.modes.sort_values("omega_n").iloc[0]
    assert modes["omega_n"].iloc[0] == pytest.approx(true["omega_n"], rel=1e-4)
    assert modes["modal_mass"].iloc[0] == pytest.approx(true["modal_mass"], rel=0.005)


def test_a_band_given_at_one_end_keeps_the_automatic_other_end():
    """``freq_range=(None, fmax)`` (``--fmax`` alone): the noisy lowest lines are still
    dropped; ``(fmin, None)``: the automatic top. An end given wins, to a line's rounding
    (a hammer FRF's 6.99999999999986 Hz line is the 7 Hz a user names)."""
    from modalid import ModalFit
    from modalid._band import given_band

    freq, h = beam_frf(first=60)
    rng = np.random.default_rng(1)
    junk = h.copy()
    junk[:12] = np.abs(h[:12]) * np.exp(2j * np.pi * rng.random(12)) * rng.uniform(0.3, 3, 12)
    data = FRFData(freq, junk)
    (auto_lo, auto_hi), why = choose_band(data)
    top = float(freq[1500])
    band, reason = given_band((None, top), lambda: choose_band(data))
    assert band == (auto_lo, top)
    # the reason speaks of the end chosen only (the other's "dropped" contradicted it)
    low_why = "; ".join(p for p in why.split("; ") if not p.startswith("dropped the"))
    assert reason == f"freq_range, the low end chosen from the data ({low_why})"
    assert low_why.startswith("dropped 13 lines below")
    band, reason = given_band((freq[20], None), lambda: choose_band(data))
    assert band == (freq[20], auto_hi)
    assert "below" not in reason and reason.startswith("freq_range, the top chosen from the "
                                                       "data (")
    assert given_band((None, None), lambda: choose_band(data))[1] == (
        f"freq_range, both ends chosen from the data ({why})")
    assert given_band((1.0, 2.0), None) == ((1.0, 2.0), "freq_range")   # not called
    with pytest.raises(TypeError, match="freq_range must be a pair"):
        given_band(3.0, lambda: choose_band(data))
    fit = ModalFit(freq_range=(None, top), n_modes=4).fit(data)
    assert fit.report_["band_hz"][0] == pytest.approx(auto_lo)
    assert fit.report_["band_hz"][1] <= top
    rounded = FRFData(freq * (1 - 1e-13), junk)
    assert rounded.band((freq[20], freq[40])).freq_hz.size == 21
