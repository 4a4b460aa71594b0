"""Synthetic measurements against their exact truth: FRF noise, impulse responses, hammer hits."""

import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad

from data_synth import (CantileverBeam, HammerTest, LumpedMass, Rod, SpringMass,
                        lightly_damped, synthetic_frf, synthetic_hammer_test,
                        synthetic_impulse_response)
from modalid import FRFData, ModalModel

FS = 10_000.0


@pytest.fixture
def truth():
    return ModalModel.from_modes(2 * np.pi * np.array([100.0, 250.0, 600.0]),
                                 [0.02, 0.01, 0.01], [1.0, 2.0, 0.5])


def half_sine_convolution(h, t, t0, width, peak):
    """Independent reference: x(t) = int h(t - tau) f(tau) dtau by adaptive quadrature."""
    def one(ti):
        upper = min(ti - t0, width)
        if upper <= 0:
            return 0.0
        with warnings.catch_warnings():  # tiny values near zero crossings: roundoff notes
            warnings.simplefilter("ignore", IntegrationWarning)
            return quad(lambda u: float(h(np.array(ti - t0 - u))) * peak
                        * np.sin(np.pi * u / width), 0.0, upper, epsabs=0.0, epsrel=1e-12,
                        limit=200)[0]
    return np.array([one(ti) for ti in t])


# ---------------------------------------------------------------------- synthetic_frf
@pytest.mark.parametrize("quantity", ["receptance", "mobility", "accelerance"])
@pytest.mark.parametrize("make", [
    lambda: ModalModel.from_modes([30.0, 80.0], [0.01, 0.05], [1.0, 3.0], flexibility=1e-4),
    lambda: SpringMass(2.0, 5e4, damping_ratio=0.02),
    lambda: Rod(mass=1.5, transit_time=1e-3, support="fixed"),
    lambda: CantileverBeam(mass=0.7, time_scale=2e-3),
])
def test_noise_free_frf_is_the_exact_frf(make, quantity):
    model = make()
    freq = np.linspace(1.0, 2000.0, 517)
    data = synthetic_frf(model, freq, quantity=quantity)
    assert isinstance(data, FRFData) and data.quantity == quantity
    assert data.coherence is None
    np.testing.assert_array_equal(data.values, model.frf(2 * np.pi * freq, quantity=quantity))
    np.testing.assert_array_equal(data.freq_hz, freq)


def test_proportional_noise_statistics(truth):
    freq = np.linspace(1.0, 1000.0, 40_000)
    exact = truth.frf(2 * np.pi * freq)
    noisy = synthetic_frf(truth, freq, noise=0.05, seed=7)
    e = (noisy.values - exact) / np.abs(exact)
    # complex std 0.05, real and imaginary parts 0.05/sqrt(2) each, zero mean, uncorrelated
    assert np.sqrt(np.mean(np.abs(e) ** 2)) == pytest.approx(0.05, rel=0.02)
    assert np.std(e.real) == pytest.approx(0.05 / np.sqrt(2), rel=0.02)
    assert np.std(e.imag) == pytest.approx(0.05 / np.sqrt(2), rel=0.02)
    assert abs(np.mean(e)) < 4 * 0.05 / np.sqrt(freq.size)
    assert abs(np.corrcoef(e.real, e.imag)[0, 1]) < 0.03
    # reproducible with a seed, different with another
    again = synthetic_frf(truth, freq, noise=0.05, seed=7)
    np.testing.assert_array_equal(again.values, noisy.values)
    other = synthetic_frf(truth, freq, noise=0.05, seed=8)
    assert not np.array_equal(other.values, noisy.values)
    gen = synthetic_frf(truth, freq, noise=0.05, seed=np.random.default_rng(7))
    np.testing.assert_array_equal(gen.values, noisy.values)


def test_noise_floor_is_relative_to_the_rms_and_adds_to_the_same_proportional_noise(truth):
    freq = np.linspace(1.0, 1000.0, 40_000)
    exact = truth.frf(2 * np.pi * freq, quantity="accelerance")
    floor_only = synthetic_frf(truth, freq, quantity="accelerance", noise_floor=0.01, seed=3)
    rms = np.sqrt(np.mean(np.abs(exact) ** 2))
    d = floor_only.values - exact
    assert np.sqrt(np.mean(np.abs(d) ** 2)) == pytest.approx(0.01 * rms, rel=0.02)
    # the proportional part for a seed does not depend on the floor
    both = synthetic_frf(truth, freq, quantity="accelerance", noise=0.05, noise_floor=0.01,
                         seed=3)
    prop = synthetic_frf(truth, freq, quantity="accelerance", noise=0.05, seed=3)
    floor_part = both.values - prop.values
    assert np.sqrt(np.mean(np.abs(floor_part) ** 2)) == pytest.approx(0.01 * rms, rel=0.02)


def test_synthetic_frf_rejects_bad_input(truth):
    with pytest.raises(ValueError, match="infinite at freq_hz = 0.0"):
        synthetic_frf(LumpedMass(2.0), [0.0, 1.0])
    with pytest.raises(ValueError, match="noise must be non-negative, got -0.1"):
        synthetic_frf(truth, [1.0, 2.0], noise=-0.1)
    with pytest.raises(ValueError, match="freq_hz must be finite"):
        synthetic_frf(truth, [1.0, np.nan])
    with pytest.raises(TypeError, match="model must be"):
        synthetic_frf("beam", [1.0, 2.0])
    with pytest.raises(ValueError, match="quantity must be one of"):
        synthetic_frf(truth, [1.0, 2.0], quantity="compliance")


def test_lightly_damped_is_the_damped_truncated_modal_model():
    rod = Rod(mass=1.5, transit_time=1e-3, support="free")
    model = lightly_damped(rod, 4, 0.01)
    assert model == rod.modal_model(4, damping_ratio=0.01, residual=True)
    np.testing.assert_allclose(model.modes["damping_ratio"], 0.01, rtol=1e-12)
    np.testing.assert_allclose(model.static_flexibility(), rod.static_flexibility, rtol=1e-12)
    assert lightly_damped(rod, 4, 0.01, residual=False).flexibility == 0.0
    with pytest.raises(TypeError, match="model must be a ExactModel"):
        lightly_damped(model, 2, 0.01)
    with pytest.raises(ValueError, match="damping_ratio"):
        lightly_damped(rod, 2, 1.5)


# ------------------------------------------------------------ synthetic_impulse_response
def test_impulse_response_noise_free_and_noisy():
    rod = Rod(mass=1.5, transit_time=1e-3, support="fixed")
    t, h = synthetic_impulse_response(rod, 20_000.0, 2000)
    np.testing.assert_array_equal(t, np.arange(2000) / 20_000.0)
    np.testing.assert_array_equal(h, rod.impulse_response(t))
    _, hn = synthetic_impulse_response(rod, 20_000.0, 2000, noise=0.1, seed=1)
    assert np.std(hn - h) == pytest.approx(0.1 * np.sqrt(np.mean(h**2)), rel=0.05)
    _, hn2 = synthetic_impulse_response(rod, 20_000.0, 2000, noise=0.1, seed=1)
    np.testing.assert_array_equal(hn, hn2)
    modal = lightly_damped(rod, 3, 0.02)
    t, h = synthetic_impulse_response(modal, 20_000.0, 100)
    np.testing.assert_array_equal(h, modal.impulse_response(t))
    with pytest.raises(ValueError, match="fs must be positive, got 0.0"):
        synthetic_impulse_response(rod, 0.0, 10)


# -------------------------------------------------------------- synthetic_hammer_test
@pytest.mark.parametrize("response", ["displacement", "acceleration"])
def test_hammer_response_is_the_exact_convolution(truth, response):
    width, peak, t0 = 1e-3, 50.0, 2e-3
    test = synthetic_hammer_test(truth, FS, 0.05, hit_times=t0, pulse_width=width,
                                 force_peak=peak, response=response)
    assert isinstance(test, HammerTest) and test.force.shape == (1, 500)
    t = test.t
    np.testing.assert_allclose(test.force[0], np.where((t >= t0) & (t <= t0 + width),
                               peak * np.sin(np.pi * (t - t0) / width), 0.0), atol=1e-12)
    idx = np.array([0, 19, 20, 25, 29, 30, 31, 45, 120, 499])
    x = half_sine_convolution(truth.impulse_response, t[idx], t0, width, peak)
    if response == "displacement":
        expected = x
    else:
        # a = h * f'' with f'' = -(pi/Tc)^2 f + peak pi/Tc [delta(t0) + delta(t0 + Tc)]
        wc = np.pi / width
        h = truth.impulse_response
        expected = peak * wc * (h(t[idx] - t0) + h(t[idx] - t0 - width)) - wc**2 * x
    scale = np.max(np.abs(test.response))
    np.testing.assert_allclose(test.response[0, idx], expected, rtol=0, atol=1e-10 * scale)


def test_hammer_velocity_is_the_derivative_of_displacement(truth):
    kw = dict(pulse_width=1.3e-3, hit_times=1e-3)
    fine = 200 * FS
    x = synthetic_hammer_test(truth, fine, 0.03, response="displacement", **kw).response[0]
    v = synthetic_hammer_test(truth, fine, 0.03, response="velocity", **kw).response[0]
    a = synthetic_hammer_test(truth, fine, 0.03, response="acceleration", **kw).response[0]
    dt = 1 / fine
    t = np.arange(x.size) * dt
    # central differences, away from the record ends and the kinks at both pulse ends
    ok = np.ones(x.size, bool)
    ok[:2] = ok[-2:] = False
    for edge in (1e-3, 2.3e-3):
        ok[np.abs(t - edge) < 2.5 * dt] = False
    np.testing.assert_allclose(np.gradient(x, dt)[ok], v[ok], atol=1e-6 * np.abs(v).max())
    np.testing.assert_allclose(np.gradient(v, dt)[ok], a[ok], atol=1e-5 * np.abs(a).max())


def test_hammer_resonant_undamped_mode_has_no_zero_division():
    width = 1e-3
    wc = np.pi / width                       # the mode sits exactly on the pulse frequency
    model = ModalModel.from_modes([wc], 0.0, 2.0)
    test = synthetic_hammer_test(model, FS, 0.02, pulse_width=width, hit_times=0.0,
                                 response="displacement")
    idx = np.array([3, 10, 15, 60, 190])
    x = half_sine_convolution(model.impulse_response, test.t[idx], 0.0, width, 100.0)
    np.testing.assert_allclose(test.response[0, idx], x, rtol=0, atol=1e-10 * np.abs(x).max())


def test_hammer_exact_rational_models_and_free_body():
    spring = SpringMass(2.0, 4e5, damping_ratio=0.03)
    test = synthetic_hammer_test(spring, FS, 0.05, response="displacement")
    assert test.model == spring.modal_model(1)
    idx = np.array([25, 40, 300])
    x = half_sine_convolution(spring.impulse_response, test.t[idx], 20 / FS, 10 / FS, 100.0)
    np.testing.assert_allclose(test.response[0, idx], x, rtol=1e-9)
    # free mass: acceleration is f/M, velocity ends at impulse/M
    mass = LumpedMass(4.0)
    acc = synthetic_hammer_test(mass, FS, 0.01, response="acceleration")
    np.testing.assert_allclose(acc.response, acc.force / 4.0, atol=1e-13)
    vel = synthetic_hammer_test(mass, FS, 0.01, response="velocity")
    impulse = 100.0 * 2 * (10 / FS) / np.pi
    assert vel.response[0, -1] == pytest.approx(impulse / 4.0, rel=1e-12)


def test_hammer_anti_alias_filter_is_common_and_consistent(truth):
    plain = synthetic_hammer_test(truth, FS, 0.05, response="velocity")
    filt = synthetic_hammer_test(truth, FS, 0.05, response="velocity", anti_alias=True)
    assert filt.anti_alias and not plain.anti_alias
    # the pulse spectrum lies far below the 0.4 fs cutoff: the filtered force is a delayed,
    # slightly smoothed half-sine carrying the same impulse (G(0) = 1); the sum of samples
    # is exact but for the filter's stopband leakage: G(fs) F(fs) / F(0) = 1.6e-6 aliases onto 0 Hz
    impulse = 100.0 * 2 * (10 / FS) / np.pi
    assert np.sum(filt.force) / FS == pytest.approx(impulse, rel=1e-5)
    assert np.sum(plain.force) / FS == pytest.approx(impulse, rel=1e-2)  # aliased, ~0.8 %
    assert np.max(filt.force) == pytest.approx(100.0, rel=0.02)
    # derivatives agree on a fine grid (each quantity has its own partial fractions);
    # central differences are poor only within a few filter time constants of the kinks
    fine = 100 * FS
    kw = dict(anti_alias=True, pulse_width=1e-3, hit_times=1e-3)
    fx = synthetic_hammer_test(truth, fine, 0.02, response="displacement", **kw).response[0]
    fv = synthetic_hammer_test(truth, fine, 0.02, response="velocity", **kw).response[0]
    fa = synthetic_hammer_test(truth, fine, 0.02, response="acceleration", **kw).response[0]
    dt = 1 / fine
    t = np.arange(fx.size) * dt
    ok = (np.abs(t - 1e-3) > 1e-4) & (np.abs(t - 2e-3) > 1e-4) & (t > 2 * dt) & (t < t[-2])
    np.testing.assert_allclose(np.gradient(fx, dt)[ok], fv[ok], atol=1e-5 * np.abs(fv).max())
    np.testing.assert_allclose(np.gradient(fv, dt)[ok], fa[ok], atol=1e-4 * np.abs(fa).max())


def test_hammer_hits_noise_and_double_hit(truth):
    test = synthetic_hammer_test(truth, FS, 0.1, n_hits=3, force_peak=[80.0, 100.0, 120.0],
                                 hit_times=[1e-3, 2e-3, 3e-3], double_hit=[1], seed=4)
    assert test.force.shape == test.response.shape == (3, 1000)
    np.testing.assert_allclose(test.force.max(axis=1), [80.0, 100.0, 120.0], rtol=1e-12)
    assert test.double_hits == (1,)
    # the double hit: 0.3 x the peak, starting 3 pulse widths after the main pulse
    second = test.force[1, (test.t > 2e-3 + 2e-3)]
    assert second.max() == pytest.approx(30.0, rel=1e-12)
    assert test.quantity == "accelerance"
    with pytest.raises(ValueError, match="read-only"):
        test.force[0, 0] = 1.0
    with pytest.raises(AttributeError):
        test.fs = 1.0
    noisy = synthetic_hammer_test(truth, FS, 0.1, n_hits=2, noise=(0.01, 0.02), seed=5)
    clean = synthetic_hammer_test(truth, FS, 0.1, n_hits=2)
    d = noisy.response - clean.response
    assert np.std(d[0]) == pytest.approx(0.02 * np.abs(clean.response[0]).max(), rel=0.15)
    again = synthetic_hammer_test(truth, FS, 0.1, n_hits=2, noise=(0.01, 0.02), seed=5)
    np.testing.assert_array_equal(again.response, noisy.response)
    # relative to each record's RMS instead: the same draws, scaled by the RMS
    rms = synthetic_hammer_test(truth, FS, 0.1, n_hits=2, noise=(0.01, 0.02), seed=5,
                                noise_reference="rms")
    assert rms.noise_reference == "rms" and noisy.noise_reference == "max"
    scale = np.sqrt(np.mean(clean.response[1] ** 2)) / np.abs(clean.response[1]).max()
    np.testing.assert_allclose(rms.response[1] - clean.response[1], scale * d[1], rtol=1e-9,
                               atol=1e-12 * np.abs(clean.response).max())
    with pytest.raises(ValueError, match="noise_reference"):
        synthetic_hammer_test(truth, FS, 0.1, noise=0.01, noise_reference="peak")
    frf = test.true_frf([10.0, 20.0])
    np.testing.assert_array_equal(frf.values, truth.frf(2 * np.pi * np.array([10.0, 20.0]),
                                                        quantity="accelerance"))


def test_hammer_rejects_bad_input(truth):
    with pytest.raises(ValueError, match="Rod is not rational"):
        synthetic_hammer_test(Rod(mass=1.0, transit_time=1e-3), FS, 0.1)
    with pytest.raises(ValueError, match="flexibility"):
        synthetic_hammer_test(truth.replace(flexibility=1e-6), FS, 0.1)
    with pytest.raises(ValueError, match="pulse_width must be at least 2 samples"):
        synthetic_hammer_test(truth, FS, 0.1, pulse_width=1e-4)
    with pytest.raises(ValueError, match="does not end within the record"):
        synthetic_hammer_test(truth, FS, 0.1, hit_times=0.0999)
    with pytest.raises(ValueError, match="fs must be positive"):
        synthetic_hammer_test(truth, -1.0, 0.1)
    with pytest.raises(ValueError, match="n_hits = 2"):
        synthetic_hammer_test(truth, FS, 0.1, n_hits=2, force_peak=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="double_hit index 5"):
        synthetic_hammer_test(truth, FS, 0.1, double_hit=[5])
    with pytest.raises(ValueError, match="response must be one of"):
        synthetic_hammer_test(truth, FS, 0.1, response="strain")
    with pytest.raises(ValueError, match=r"n_hits \* duration \* fs = 2 \* 1 s \* 1e\+09 "
                                         r"Hz samples exceeds 33554432"):
        synthetic_hammer_test(truth, 1e9, 1.0, n_hits=2)
    for seed in ("a", 1.5, True):
        with pytest.raises(TypeError, match="seed must be None, an integer or a"):
            synthetic_hammer_test(truth, FS, 0.1, seed=seed)
    with pytest.raises(ValueError, match="seed must be >= 0, got -1"):
        synthetic_hammer_test(truth, FS, 0.1, seed=-1)
