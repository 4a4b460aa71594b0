"""Tests of data_synth: exact answers only (closed forms, bounds, independent inversions)."""

from __future__ import annotations

import dataclasses
import math
import time
from fractions import Fraction

import numpy as np
import pytest
from scipy.optimize import brentq

from data_synth import (CantileverBeam, ExactModel, LumpedMass, Rod, SpringMass,
                        cantilever_roots)
from data_synth.roots import _power_tail

EPS = np.finfo(float).eps
M, T = 1.7, 0.3  # kg, s: deliberately not round


def make_models():
    return {
        "lumped": LumpedMass(M),
        "spring": SpringMass(M, 5.0),
        "spring_damped": SpringMass(M, 5.0, damping_ratio=0.2),
        "rod_free": Rod(M, T, support="free"),
        "rod_fixed": Rod(M, T, support="fixed"),
        "beam": CantileverBeam(M, T),
    }


MODELS = make_models()
CONTINUA = ["rod_free", "rod_fixed", "beam"]
K = M / T**2  # the continua's K = m/T^2


def bromwich_fft(F, t_max, *, n=2**20, c_period=30.0, period_factor=4.0):
    """Inverse Laplace transform by the Fourier-series (Bromwich) method on Re s = c.

    With period ``P``, ``f(t) = e^{ct}/P [F(c) + 2 Re sum_{k>=1} F(c + 2 pi i k/P)
    e^{2 pi i k t/P}] - sum_{j>=1} e^{-c j P} f(t + jP)``; the last (alias) sum is below
    ``e^{-30}`` relative here; truncation after ``n`` terms costs ``O(n^-2)`` away from kinks.
    Returns the grid ``t_j = j P/n <= t_max`` and ``f(t_j)``.
    """
    period = period_factor * t_max
    c = c_period / period
    omega = 2.0 * np.pi * np.arange(n) / period
    values = F(c + 1j * omega)
    series = np.fft.ifft(values) * n
    t = np.arange(n) * period / n
    keep = t <= t_max
    f = np.exp(c * t[keep]) / period * (2.0 * series.real[keep] - values[0].real)
    return t[keep], f


# =============================================================================== roots
def test_cantilever_roots_table_1_of_the_paper():
    paper = [0.596864163, 1.494175614, 2.500246946, 3.499989319, 4.500000461, 5.499999980]
    # Within one unit of the 9th decimal: the paper rounds eps_1..3, eps_6 correctly but
    # truncates eps_4 = 3.4999893198 pi and eps_5 = 4.5000004615 pi.
    np.testing.assert_allclose(cantilever_roots(6) / np.pi, paper, rtol=0, atol=1e-9)


def test_cantilever_roots_reference_values():
    # Blevins, Formulas for natural frequency and mode shape, table 8-1 (15 digits).
    reference = [1.87510406871196, 4.69409113297418, 7.85475743823761, 10.9955407348755,
                 14.1371683910465, 17.2787595320882]
    np.testing.assert_allclose(cantilever_roots(6), reference, rtol=0, atol=1e-13)


def test_cantilever_roots_match_root_finding_to_rounding():
    roots = cantilever_roots(60)
    for k in range(1, 61):
        x = (k - 0.5) * np.pi
        lo, hi = (1.0, 2.5) if k == 1 else (x - 0.3, x + 0.3)
        ref = brentq(lambda e: np.cos(e) + 1.0 / np.cosh(e), lo, hi, xtol=1e-300,
                     rtol=4 * EPS, maxiter=200)
        assert abs(roots[k - 1] - ref) <= 2 * np.spacing(ref), k


def test_asymptotic_roots_agree_with_root_finding_where_both_apply():
    # eps_k = x_k + (-1)^(k+1) 2 exp(-x_k) overshoots by 4 exp(-2 x_k) (1 + O(exp(-x_k))):
    # check that bound (and the sign of the correction) against root finding for
    # k = 1..5, and agreement to rounding beyond (where the remainder is below an ulp).
    for k in range(1, 30):
        x = (k - 0.5) * np.pi
        asymptotic = x + (-1) ** (k + 1) * 2.0 * np.exp(-x)
        lo, hi = (1.0, 2.5) if k == 1 else (x - 0.3, x + 0.3)
        ref = brentq(lambda e: np.cos(e) + 1.0 / np.cosh(e), lo, hi, xtol=1e-300,
                     rtol=4 * EPS, maxiter=200)
        if k <= 5:
            assert 0 < asymptotic - ref < 4.2 * np.exp(-2.0 * x), k
            assert np.sign(ref - x) == (-1) ** (k + 1), k
        else:
            assert abs(asymptotic - ref) <= 2 * np.spacing(ref), k


def test_cantilever_roots_a_million_fast_and_exact_tail():
    start = time.perf_counter()
    roots = cantilever_roots(10**6)
    assert time.perf_counter() - start < 1.0
    assert roots.shape == (10**6,)
    assert np.all(np.diff(roots) > 2.8)
    k = np.arange(100, 10**6 + 1, 9973.0)
    np.testing.assert_array_equal(roots[k.astype(int) - 1], (k - 0.5) * np.pi)
    assert cantilever_roots(0).shape == (0,)


def test_sum_of_inverse_fourth_and_eighth_powers():
    roots = cantilever_roots(10**6)
    # Tails beyond 10^6 terms are below 4e-21 and 1e-42: the partial sums are exact.
    assert math.fsum(roots ** -4.0) == pytest.approx(1.0 / 12.0, rel=2e-15)
    # 11/1680 follows from the Taylor series of H: K H = 1/3 + 11 e^4/420 + ...
    assert math.fsum(roots ** -8.0) == pytest.approx(11.0 / 1680.0, rel=2e-15)
    assert _power_tail(0, 4) == pytest.approx(1.0 / 12.0, rel=2e-15)
    for n in (0, 3, 19, 20, 21, 500):
        assert _power_tail(n, 4) == pytest.approx(math.fsum(roots[n:] ** -4.0), rel=1e-13)
        assert _power_tail(n, 2) == pytest.approx(
            math.fsum(roots[n:] ** -2.0) + _power_tail(10**6, 2), rel=1e-13)


# ================================================================ static flexibility
def test_static_flexibilities_exact():
    m = MODELS
    assert m["rod_fixed"].receptance(0.0) == pytest.approx(1.0 / K, rel=1e-15)
    assert m["rod_fixed"].static_flexibility == pytest.approx(1.0 / K, rel=1e-15)
    assert m["beam"].receptance(0.0) == pytest.approx(1.0 / (3.0 * K), rel=1e-15)
    assert m["beam"].static_flexibility == pytest.approx(1.0 / (3.0 * K), rel=1e-15)
    assert m["rod_free"].elastic_receptance(0.0) == pytest.approx(1.0 / (3.0 * K), rel=1e-15)
    assert m["rod_free"].static_flexibility == pytest.approx(1.0 / (3.0 * K), rel=1e-15)
    assert m["rod_free"].receptance(0.0) == np.inf
    assert m["spring"].receptance(0.0) == pytest.approx(1.0 / 5.0, rel=1e-15)
    assert m["spring_damped"].static_flexibility == pytest.approx(1.0 / 5.0, rel=1e-15)
    assert m["lumped"].static_flexibility == 0.0
    assert m["lumped"].receptance(0.0) == np.inf


@pytest.mark.parametrize("name", CONTINUA + ["spring", "spring_damped"])
def test_residual_modal_models_keep_the_static_flexibility(name):
    model = MODELS[name]
    counts = (0, 1) if name.startswith("spring") else (0, 1, 3, 50, 1000)
    for n in counts:
        modal = model.modal_model(n, residual=True)
        assert modal.static_flexibility() == pytest.approx(model.static_flexibility,
                                                           rel=1e-14)
        assert modal.inverse_mass == model.inverse_mass


@pytest.mark.parametrize("name", CONTINUA)
def test_tail_flexibility_matches_a_brute_force_sum(name):
    model = MODELS[name]
    n_big = 200_000
    omega = model.natural_frequencies(n_big)
    modal_mass = {"beam": M / 4}.get(name, M / 2)
    terms = 1.0 / (modal_mass * omega**2)
    for n in (0, 7, 100):
        flex = model.modal_model(n, residual=True).flexibility
        brute = math.fsum(terms[n:])
        # remainder of the brute-force sum beyond n_big terms, bounded by an integral
        remainder = {"beam": 4 * T**2 / M / (3 * np.pi**4 * (n_big - 1) ** 3)}.get(
            name, 2 * T**2 / (M * np.pi**2 * (n_big - 1)))
        assert brute <= flex * (1 + 1e-14) and flex <= (brute + remainder) * (1 + 1e-14)


# ========================================================= modal sum vs exact receptance
def _frequencies_between_poles(model, n_intervals=10, per_interval=40, seed=0):
    rng = np.random.default_rng(seed)
    w = np.concatenate([[0.0], model.natural_frequencies(n_intervals)])
    frac = rng.uniform(0.1, 0.9, size=(n_intervals, per_interval))
    return (w[:-1, None] + frac * np.diff(w)[:, None]).ravel()


@pytest.mark.parametrize("name", CONTINUA)
def test_modal_sum_converges_to_the_exact_receptance(name):
    model = MODELS[name]
    omega = _frequencies_between_poles(model)
    assert omega.size == 400
    exact = model.receptance(1j * omega)
    errors, residual_errors = [], []
    for n in (20, 40, 80, 160):
        plain = exact - model.modal_model(n).receptance(1j * omega)
        modal_res = model.modal_model(n, residual=True)
        resid = exact - modal_res.receptance(1j * omega)
        tail = modal_res.flexibility
        w_next = model.natural_frequencies(n + 1)[-1]
        # rounding: of the exact H and of the modal sum's terms
        w_kept, mass_kept = model.natural_frequencies(n), {"beam": M / 4}.get(name, M / 2)
        terms = np.sum(1.0 / (mass_kept * np.abs(w_kept**2 - omega[:, None] ** 2)), axis=1)
        atol = 64 * EPS * (np.abs(exact) + terms + model.inverse_mass / omega**2)
        # sum_{k>n} a_k/(w_k^2 - w^2) lies in [tail, tail w_{n+1}^2/(w_{n+1}^2 - w^2)]
        assert np.all(np.abs(plain.imag) <= atol)
        assert np.all(plain.real >= tail - atol)
        assert np.all(plain.real <= tail * w_next**2 / (w_next**2 - omega**2) + atol)
        # with the residual: sum a_k w^2/(w_k^2 (w_k^2 - w^2)) in [0, tail w^2/(w_n+1^2 - w^2)]
        assert np.all(resid.real >= -atol)
        assert np.all(resid.real <= tail * omega**2 / (w_next**2 - omega**2) + atol)
        errors.append(np.max(np.abs(plain / exact)))
        residual_errors.append(np.max(np.abs(resid / exact)))
    assert all(b < 0.6 * a for a, b in zip(errors, errors[1:]))
    assert all(b < 0.6 * a for a, b in zip(residual_errors, residual_errors[1:]))
    assert all(r < 0.05 * e for r, e in zip(residual_errors, errors))


def test_spring_mass_modal_model_is_exact():
    rng = np.random.default_rng(1)
    s = rng.normal(size=300) * 3 + 1j * rng.normal(size=300) * 3
    for name in ("spring", "spring_damped"):
        model = MODELS[name]
        modal = model.modal_model(1)
        np.testing.assert_allclose(modal.receptance(s), model.receptance(s), rtol=1e-14)
        assert modal.modes["damping_ratio"].iloc[0] == pytest.approx(model.damping_ratio,
                                                                     abs=1e-15)
    # An explicit damping ratio replaces the model's own.
    other = MODELS["spring"].modal_model(1, damping_ratio=0.2)
    np.testing.assert_allclose(other.receptance(s), MODELS["spring_damped"].receptance(s),
                               rtol=1e-14)
    assert MODELS["spring"].modal_model(0, residual=True).flexibility == 1.0 / 5.0
    lumped = MODELS["lumped"].modal_model(0)
    assert lumped.n_modes == 0 and lumped.inverse_mass == 1.0 / M
    np.testing.assert_allclose(lumped.receptance(s), MODELS["lumped"].receptance(s),
                               rtol=1e-15)


@pytest.mark.parametrize("name", CONTINUA)
def test_modal_damping_and_frequencies(name):
    model = MODELS[name]
    modal = model.modal_model(6, damping_ratio=0.02)
    np.testing.assert_allclose(modal.modes["damping_ratio"], 0.02, rtol=1e-14)
    np.testing.assert_allclose(modal.modes["omega_n"], model.natural_frequencies(6),
                               rtol=1e-15)
    expected_mass = M / 4 if name == "beam" else M / 2
    np.testing.assert_allclose(modal.modes["modal_mass"], expected_mass, rtol=1e-13)


def test_natural_frequencies():
    k = np.arange(1, 8)
    np.testing.assert_allclose(MODELS["rod_fixed"].natural_frequencies(7),
                               (k - 0.5) * np.pi / T, rtol=1e-15)
    np.testing.assert_allclose(MODELS["rod_free"].natural_frequencies(7), k * np.pi / T,
                               rtol=1e-15)
    np.testing.assert_allclose(MODELS["beam"].natural_frequencies(7),
                               cantilever_roots(7) ** 2 / T, rtol=1e-15)
    np.testing.assert_allclose(MODELS["spring"].natural_frequencies(1), [np.sqrt(5 / M)],
                               rtol=1e-15)
    assert MODELS["lumped"].natural_frequencies(0).shape == (0,)
    # the exact receptances have poles there, with residues 1/(modal mass):
    # H(s) (s^2 + w_k^2) -> 1/m_k as s -> i w_k
    for name in CONTINUA:
        model = MODELS[name]
        w = model.natural_frequencies(5)
        modal_mass = M / 4 if name == "beam" else M / 2
        s = 1j * w * (1 + 1e-7)
        np.testing.assert_allclose(model.receptance(s) * (s**2 + w**2) * modal_mass, 1.0,
                                   rtol=1e-5)


# ======================================================== stability of the receptances
@pytest.mark.parametrize("name", list(MODELS))
def test_receptances_finite_everywhere(name):
    model = MODELS[name]
    r = np.array([1e-300, 1e-160, 1e-150, 1e-9, 1.0, 1e3, 1e8, 1e15, 1e100, 1e300])
    phi = np.linspace(-np.pi, np.pi, 73)
    with np.errstate(under="ignore"):
        s = np.concatenate([(r[:, None] * np.exp(1j * phi[None, :])).ravel(), 1j * r, -r])
    for values in (model.receptance(s), model.elastic_receptance(s)):
        assert not np.any(np.isnan(values))
    # grounded: finite everywhere; free: 1/(m s^2) overflows only below |s| ~ 1e-154
    h = model.receptance(s)
    assert np.all(np.isfinite(h[np.abs(s) > (0 if model.is_grounded else 1e-150)]))
    assert np.all(np.isfinite(model.elastic_receptance(s)))
    if model.is_grounded:
        assert model.receptance(0.0) == pytest.approx(model.static_flexibility, rel=1e-15)
    else:
        assert model.receptance(0.0) == np.inf
    if name in CONTINUA:  # at the poles: inf allowed, nan never
        w = model.natural_frequencies(50)
        assert not np.any(np.isnan(model.receptance(1j * w)))
        assert not np.any(np.isnan(model.elastic_receptance(1j * w)))


@pytest.mark.parametrize("support", ["fixed", "free"])
def test_rod_large_s_asymptotics(support):
    rod = Rod(M, T, support=support)
    phi = np.linspace(-1.5, 1.5, 31)
    for r in (1e4, 1e8, 1e15):
        s = r / T * np.exp(1j * phi)
        # tanh(eps) = 1 to rounding for Re eps > 19: H = 1/(K eps) exactly
        np.testing.assert_allclose(rod.receptance(s) * K * s * T, 1.0, rtol=4 * EPS)
        # and on the imaginary axis: tanh(i y) = i tan(y) (y as the model forms it: tan
        # amplifies the rounding of a large y)
        s = 1j * np.array([r, r * 1.37]) / T
        y = (s * T).imag
        expected = np.tan(y) / (K * y) if support == "fixed" else -1.0 / (K * y * np.tan(y))
        np.testing.assert_allclose(rod.receptance(s), expected, rtol=1e-13)


def test_rod_small_s_series():
    for x in (1e-9, 1e-5, 1e-3 * (1 + 1j), 0.05j, 0.04 - 0.03j):
        s = np.array(x / T)
        eps = s * T
        fixed = Rod(M, T, support="fixed").receptance(s) * K
        np.testing.assert_allclose(fixed, 1 - eps**2 / 3 + 2 * eps**4 / 15
                                   - 17 * eps**6 / 315 + 62 * eps**8 / 2835, rtol=2e-14)
        free = Rod(M, T, support="free")
        elastic = free.elastic_receptance(s) * K
        np.testing.assert_allclose(elastic, 1 / 3 - eps**2 / 45 + 2 * eps**4 / 945
                                   - eps**6 / 4725 + 2 * eps**8 / 93555, rtol=2e-14)
        # free: H = 1/(K eps^2) + elastic part
        np.testing.assert_allclose(free.receptance(s) * K, 1 / eps**2 + elastic, rtol=1e-14)
    # continuity of the elastic part across the series/closed-form switch at |eps| = 1
    free = Rod(M, T, support="free")
    for phi in np.linspace(-np.pi, np.pi, 13):
        a = free.elastic_receptance((1 - 1e-15) * np.exp(1j * phi) / T)
        b = free.elastic_receptance((1 + 1e-15) * np.exp(1j * phi) / T)
        assert abs(a - b) <= 1e-14 * abs(a)
    # the series (|eps| < 1) against the closed form, whose cancellation costs < 4 eps/|eps|^2
    rng = np.random.default_rng(4)
    eps = rng.uniform(0.7, 0.999, 100) * np.exp(1j * rng.uniform(-np.pi, np.pi, 100))
    closed = (1.0 / np.tanh(eps) - 1.0 / eps) / eps
    np.testing.assert_allclose(free.elastic_receptance(eps / T) * K, closed, rtol=2e-15)


def test_beam_large_s_asymptotics():
    beam = MODELS["beam"]
    phi = np.linspace(-1.2, 1.2, 25)
    for r in (1e4, 1e8, 1e12):
        s = r / T * np.exp(1j * phi)
        expected = np.sqrt(2.0) / (K * (s * T) ** 1.5)
        np.testing.assert_allclose(beam.receptance(s), expected, rtol=1e-14)


def _beam_taylor_coefficients(n):
    """Exact Taylor coefficients of K H in z = e^4, from the closed form's series.

    N(e)/e^3 = sum_j 4 (-4)^j z^j/(4j+3)!, 1 + cosh e cos e = 2 + sum_{j>=1} (-4)^j z^j/(4j)!.
    """
    num = [Fraction(4 * (-4) ** j, math.factorial(4 * j + 3)) for j in range(n)]
    den = [Fraction(2)] + [Fraction((-4) ** j, math.factorial(4 * j)) for j in range(1, n)]
    out = []
    for j in range(n):  # series division
        out.append((num[j] - sum(out[i] * den[j - i] for i in range(j))) / den[0])
    return out


def test_beam_taylor_series_matches_the_modal_sums():
    # K H = sum_k 4/(eps_k^4 - z) = sum_j z^j 4 sum_k eps_k^-(4j+4): each Taylor
    # coefficient of the closed form is a power sum of the roots (1/3 -> 1/12, ...).
    coefficients = _beam_taylor_coefficients(4)
    assert coefficients[0] == Fraction(1, 3) and coefficients[1] == Fraction(11, 420)
    roots = cantilever_roots(10**5)
    for j, c in enumerate(coefficients):
        assert 4 * math.fsum(roots ** (-4.0 * j - 4.0)) == pytest.approx(float(c), rel=1e-14)


def test_beam_small_s_series():
    beam = MODELS["beam"]
    c = [float(v) for v in _beam_taylor_coefficients(3)]
    for x in (1e-9, 1e-5, 1e-3j, 1e-3 * (1 + 1j), 0.05, 0.1j):
        s = x / T
        z = -(s * T) ** 2
        # K H = 1/3 + 11 z/420 + c_2 z^2 + O(z^3), z = e^4 = -s^2 T^2
        expected = c[0] + c[1] * z + c[2] * z**2
        assert abs(beam.receptance(s) * K - expected) <= 1e-3 * abs(z) ** 3 + 4 * EPS
    # continuity across the series/closed-form switch at |sT| = 1
    for phi in np.linspace(-np.pi, np.pi, 13):
        a = beam.receptance((1 - 1e-15) * np.exp(1j * phi) / T)
        b = beam.receptance((1 + 1e-15) * np.exp(1j * phi) / T)
        assert abs(a - b) <= 1e-14 * abs(a)


def test_beam_receptance_equals_the_naive_formula_where_that_is_accurate():
    # 1 < |sT| < 30: no overflow and little cancellation in the textbook expression
    beam = MODELS["beam"]
    rng = np.random.default_rng(5)
    x = rng.uniform(1.5, 30, 300) * np.exp(1j * rng.uniform(-np.pi, np.pi, 300))
    e = np.sqrt(1j * x) * 1j ** rng.integers(0, 4, 300)  # any of the 4 branches
    naive = ((np.cosh(e) * np.sin(e) - np.sinh(e) * np.cos(e))
             / (K * e**3 * (1 + np.cosh(e) * np.cos(e))))
    np.testing.assert_allclose(beam.receptance(x / T), naive, rtol=1e-11)


def test_beam_receptance_equals_its_modal_sum_off_axis():
    beam = MODELS["beam"]
    rng = np.random.default_rng(2)
    s = (rng.uniform(0.2, 3, 200) + 1j * rng.uniform(-60, 60, 200)) / T
    modal = beam.modal_model(20000, residual=True)
    # residual error <= |s|^2 sum_{k>n} 4/(m w_k^2 |s^2 + w_k^2|) < 1e-12 relative here
    np.testing.assert_allclose(beam.receptance(s), modal.receptance(s), rtol=1e-11)


def test_frf_quantities_and_free_body_accelerance_at_zero():
    omega = np.array([0.0, 0.5, 3.0, 40.0]) / T
    for name, model in MODELS.items():
        h = model.frf(omega[1:])
        np.testing.assert_array_equal(h, model.receptance(1j * omega[1:]))
        np.testing.assert_allclose(model.frf(omega[1:], quantity="mobility"),
                                   1j * omega[1:] * h, rtol=1e-15)
        acc = model.frf(omega, quantity="accelerance")
        np.testing.assert_allclose(acc[1:], -omega[1:] ** 2 * h, rtol=1e-13)
        if not model.is_grounded:
            assert acc[0] == pytest.approx(1.0 / M, rel=1e-15)
            assert model.frf(omega[:1], quantity="mobility")[0] == np.inf
            assert model.frf(omega[:1])[0] == np.inf
            modal = model.modal_model(0 if name == "lumped" else 5)
            assert modal.frf(omega[:1], quantity="accelerance")[0] == pytest.approx(1 / M)
        else:
            assert acc[0] == 0.0


# ======================================================================= time domain
def _away_from(t, jumps, gap):
    if jumps.size == 0:
        return t
    d = np.min(np.abs(t[:, None] - jumps[None, :]), axis=1)
    return t[d > gap]


@pytest.mark.parametrize("name", list(MODELS))
def test_impulse_response_is_derivative_of_step_response(name):
    model = MODELS[name]
    tau = model.time_scale or T
    rng = np.random.default_rng(3)
    t = _away_from(rng.uniform(0.01, 10, 200) * tau, model.jump_times(11 * tau), 1e-3 * tau)
    # beam: 20 modes, |h''| < (4/(mT)) sum eps_k^2 = 2e5/(mT): truncation error
    # delta^2/6 |h''| ~ 3e-9, rounding ~ 1e-16 S/delta ~ 1e-11 (in T/m)
    kw = {"n_terms": 20} if name == "beam" else {}
    delta = 1e-6 * tau if name == "beam" else 1e-4 * tau
    fd = (model.step_response(t + delta, **kw)
          - model.step_response(t - delta, **kw)) / (2 * delta)
    h = model.impulse_response(t, **kw)
    scale = np.max(np.abs(h))
    # rods, lumped mass: S piecewise linear / quadratic, the central difference is exact
    np.testing.assert_allclose(fd, h, rtol=0, atol=(1e-7 if name == "beam" else 1e-8) * scale)


@pytest.mark.parametrize("name", list(MODELS))
def test_responses_vanish_before_zero_and_start_at_zero(name):
    model = MODELS[name]
    t = np.array([-5.0, -1e-12, 0.0])
    kw = {"n_terms": 50} if name == "beam" else {}
    np.testing.assert_array_equal(model.step_response(t, **kw), 0.0)
    h = model.impulse_response(t, **kw)
    np.testing.assert_array_equal(h[:2], 0.0)
    expected_h0 = T / M if name.startswith("rod") else 0.0  # right limit at 0
    assert h[2] == pytest.approx(expected_h0, abs=1e-300)


@pytest.mark.parametrize("name", list(MODELS))
def test_step_response_against_numerical_inverse_laplace(name):
    model = MODELS[name]
    tau = model.time_scale or T
    t, f = bromwich_fft(lambda s: model.receptance(s) / s, 6 * tau)
    t, f = t[::97], f[::97]
    keep = (t > 0.05 * tau)
    jumps = model.jump_times(6 * tau)
    if jumps.size:
        keep &= np.min(np.abs(t[:, None] - jumps[None, :]), axis=1) > 0.01 * tau
    t, f = t[keep], f[keep]
    s = model.step_response(t)
    scale = model.static_flexibility or tau**2 / M
    np.testing.assert_allclose(s, f, rtol=1e-8, atol=5e-9 * scale)


@pytest.mark.parametrize("name", ["lumped", "spring", "spring_damped"])
def test_impulse_response_against_numerical_inverse_laplace(name):
    model = MODELS[name]
    tau = model.time_scale or T
    t, f = bromwich_fft(model.receptance, 6 * tau)
    t, f = t[::97], f[::97]
    t, f = t[t > 0.05 * tau], f[t > 0.05 * tau]  # the periodised h jumps at t = 0
    h = model.impulse_response(t)
    np.testing.assert_allclose(h, f, rtol=0, atol=1e-8 * np.max(np.abs(h)))


def test_rod_closed_forms():
    fixed, free = MODELS["rod_fixed"], MODELS["rod_free"]
    jumps = fixed.jump_times(20 * T)
    np.testing.assert_array_equal(jumps, 2 * T * np.arange(1.0, 11.0))
    np.testing.assert_array_equal(free.jump_times(20 * T - 1e-12), 2 * T * np.arange(1.0, 10.0))
    assert fixed.jump_times(0.0).size == 0
    before = np.nextafter(jumps, -np.inf)
    # fixed: -2T/m, +2T/m, ... ; free: +2T/m at every reflection
    np.testing.assert_allclose(fixed.impulse_response(jumps) - fixed.impulse_response(before),
                               2 * T / M * (-1.0) ** np.arange(1, 11), rtol=1e-15)
    np.testing.assert_allclose(free.impulse_response(jumps) - free.impulse_response(before),
                               2 * T / M, rtol=1e-14)
    # step responses are continuous at the jumps
    np.testing.assert_allclose(fixed.step_response(jumps), fixed.step_response(before),
                               rtol=0, atol=1e-14 * T**2 / M)
    # free rod: S(2nT) equals the rigid-body t^2/(2m); fixed rod: triangle wave
    np.testing.assert_allclose(free.step_response(jumps), jumps**2 / (2 * M), rtol=1e-14)
    np.testing.assert_allclose(fixed.step_response(jumps),
                               np.where(np.arange(1, 11) % 2 == 1, 2 * T**2 / M, 0.0),
                               rtol=1e-14, atol=1e-13 * T**2 / M)
    # mean of the triangle wave over a period is the static flexibility 1/K
    t = np.linspace(0, 4 * T, 400001)
    s = fixed.step_response(t)
    assert np.trapezoid(s, t) / (4 * T) == pytest.approx(1 / K, rel=1e-10)
    # far in time: no loop over periods, still exact
    big = np.array([1e6 * T + 0.5 * T])
    assert fixed.step_response(big)[0] == pytest.approx(0.5 * T**2 / M, rel=1e-8)
    assert free.impulse_response(big)[0] == pytest.approx((2 * 500000 + 1) * T / M, rel=1e-15)


def test_spring_mass_closed_forms():
    model = MODELS["spring_damped"]
    wn = np.sqrt(5.0 / M)
    wd = wn * np.sqrt(1 - 0.04)
    t = np.array([1e-9, 1e-3, 0.5, 0.999, 1.001, 3.0, 40.0]) / wn
    expected = (1 - np.exp(-0.2 * wn * t) * (np.cos(wd * t) + 0.2 / np.sqrt(0.96)
                                             * np.sin(wd * t))) / 5.0
    # naive formula loses ~ eps/(wn t) relative digits: compare where it is accurate
    np.testing.assert_allclose(model.step_response(t[2:]), expected[2:], rtol=1e-13)
    # small t: S = (1/k)(x^2/2 - zeta x^3/3 + (2 zeta^2 - 1/2) x^4/12 + O(x^5)), x = wn t
    x = wn * t[:2]
    np.testing.assert_allclose(model.step_response(t[:2]),
                               (x**2 / 2 - 0.2 * x**3 / 3 + (0.08 - 0.5) * x**4 / 12) / 5.0,
                               rtol=1e-10)
    undamped = MODELS["spring"]
    np.testing.assert_allclose(undamped.step_response(t), 2 * np.sin(wn * t / 2) ** 2 / 5.0,
                               rtol=1e-14)
    np.testing.assert_allclose(undamped.impulse_response(t), np.sin(wn * t) / (M * wn),
                               rtol=1e-14)


def test_lumped_mass_closed_forms():
    model = MODELS["lumped"]
    t = np.array([0.0, 0.1, 2.0, 1e5])
    np.testing.assert_array_equal(model.impulse_response(t), t / M)
    np.testing.assert_array_equal(model.step_response(t), t**2 / (2 * M))
    np.testing.assert_array_equal(model.elastic_receptance([1.0, 2j]), 0.0)


# ============================================================= beam series and bounds
def test_beam_series_equal_the_modal_model():
    beam = MODELS["beam"]
    t = np.linspace(0, 20 * T, 57)
    modal = beam.modal_model(300)
    np.testing.assert_allclose(beam.impulse_response(t, n_terms=300),
                               modal.impulse_response(t), rtol=0, atol=1e-12 * T / M)
    np.testing.assert_allclose(beam.step_response(t, n_terms=300), modal.step_response(t),
                               rtol=0, atol=1e-14 * T**2 / M)


def test_beam_step_response_accuracy():
    beam = MODELS["beam"]
    t = np.linspace(0, 20 * T, 41)
    reference = beam.modal_model(20000, residual=True).step_response(t)
    # reference error <= (4T^2/m) sum_{k>20000} eps_k^-4 = 6e-16 * 1/(3K)
    np.testing.assert_allclose(beam.step_response(t), reference, rtol=0,
                               atol=1.5e-12 * beam.static_flexibility)
    # monotone in the number of terms, within the stated bound
    n1 = 40
    coarse = beam.step_response(t, n_terms=n1)
    fine = beam.step_response(t)
    assert np.all(fine - coarse >= -1e-16)
    assert np.all(fine - coarse <= beam.step_error_bound(n1) * (1 + 1e-12))
    # the default tolerance: smallest N with bound <= 1e-12/(3K)
    bound_ok = beam.step_error_bound(4347) <= 1e-12 * beam.static_flexibility
    bound_prev = beam.step_error_bound(4346) > 1e-12 * beam.static_flexibility
    assert bound_ok and bound_prev


def test_beam_impulse_response_error_bound():
    beam = MODELS["beam"]
    t = np.array([0.013, 0.37, 1.0, 2.9, 11.3]) * T
    rough = beam.impulse_response(t, rtol=1e-2)
    good = beam.impulse_response(t, rtol=1e-5)
    n_rough = next(n for n in range(1000) if beam.impulse_error_bound(n) <= 1e-2 * T / M)
    assert n_rough > 30
    np.testing.assert_array_equal(rough, beam.impulse_response(t, n_terms=n_rough))
    assert np.all(np.abs(rough - good)
                  <= beam.impulse_error_bound(n_rough) + 1e-5 * T / M)
    assert beam.impulse_error_bound(0) == pytest.approx(4 * T / M * _power_tail(0, 2))


def test_from_material():
    rod = Rod.from_material(2.0, 1e-4, 2.1e11, 7850.0, support="fixed")
    assert rod.mass == pytest.approx(7850 * 1e-4 * 2.0, rel=1e-15)
    assert rod.transit_time == pytest.approx(2.0 / np.sqrt(2.1e11 / 7850), rel=1e-15)
    assert rod.stiffness == pytest.approx(2.1e11 * 1e-4 / 2.0, rel=1e-14)
    assert rod.support == "fixed" and Rod.from_material(1, 1, 1, 1).support == "free"
    beam = CantileverBeam.from_material(0.8, 7e10, 2e-9, 3e-4, 2700.0)
    assert beam.mass == pytest.approx(2700 * 3e-4 * 0.8, rel=1e-15)
    assert beam.stiffness == pytest.approx(7e10 * 2e-9 / 0.8**3, rel=1e-14)


def test_properties():
    m = MODELS
    assert [m[n].is_rational for n in m] == [True, True, True, False, False, False]
    assert [m[n].is_grounded for n in m] == [False, True, True, False, True, True]
    assert [m[n].inverse_mass for n in m] == [1 / M, 0.0, 0.0, 1 / M, 0.0, 0.0]
    assert m["lumped"].time_scale is None
    assert m["spring"].time_scale == pytest.approx(np.sqrt(M / 5.0), rel=1e-15)
    assert m["rod_free"].time_scale == T and m["beam"].time_scale == T
    for model in m.values():
        assert isinstance(model, ExactModel) and model.mass == M
        with pytest.raises(dataclasses.FrozenInstanceError):
            model.mass = 2.0
        if not isinstance(model, Rod):
            assert model.jump_times(100.0).size == 0
    assert Rod(M, T) == Rod(M, T, support="free") and hash(Rod(M, T)) == hash(Rod(M, T))


# ========================================================================= bad input
BAD_INPUTS = [
    (lambda: LumpedMass(-1.0), ValueError, ["mass", "-1.0"]),
    (lambda: LumpedMass(0.0), ValueError, ["mass", "0.0"]),
    (lambda: LumpedMass(float("nan")), ValueError, ["mass", "nan"]),
    (lambda: LumpedMass(np.inf), ValueError, ["mass", "inf"]),
    (lambda: LumpedMass(1e-320), ValueError, ["mass", "1e-320"]),   # 1/m overflows
    (lambda: LumpedMass("1.0"), TypeError, ["mass", "'1.0'"]),
    (lambda: LumpedMass(True), TypeError, ["mass", "True"]),
    (lambda: LumpedMass(np.array([1.0, 2.0])), TypeError, ["mass", "array([1., 2.])"]),
    (lambda: SpringMass(1.0, -2.0), ValueError, ["stiffness", "-2.0"]),
    (lambda: SpringMass(1.0, 1.0, damping_ratio=1.0), ValueError, ["damping_ratio", "1.0"]),
    (lambda: SpringMass(1.0, 1.0, damping_ratio=-0.1), ValueError, ["damping_ratio", "-0.1"]),
    (lambda: SpringMass(1.0, None), TypeError, ["stiffness", "None"]),
    (lambda: Rod(1.0, 0.0), ValueError, ["transit_time", "0.0"]),
    (lambda: Rod(-3.0, 1.0), ValueError, ["mass", "-3.0"]),
    (lambda: Rod(1.0, 1.0, support="pinned"), ValueError, ["support", "'pinned'"]),
    (lambda: Rod(1.0, 1.0, support=1), TypeError, ["support", "1"]),
    (lambda: Rod.from_material(-1.0, 1.0, 1.0, 1.0), ValueError, ["length", "-1.0"]),
    (lambda: Rod.from_material(1.0, 1.0, 1.0, float("nan")), ValueError, ["density", "nan"]),
    (lambda: CantileverBeam(1.0, -1.0), ValueError, ["time_scale", "-1.0"]),
    (lambda: CantileverBeam.from_material(1.0, 1.0, 0.0, 1.0, 1.0), ValueError,
     ["second_moment", "0.0"]),
    (lambda: MODELS["beam"].modal_model(-1), ValueError, ["n_modes", "-1"]),
    (lambda: MODELS["beam"].modal_model(1.5), TypeError, ["n_modes", "1.5"]),
    (lambda: MODELS["lumped"].modal_model(1), ValueError, ["n_modes", "1"]),
    (lambda: MODELS["spring"].modal_model(2), ValueError, ["n_modes", "2"]),
    (lambda: MODELS["rod_free"].modal_model(3, damping_ratio=1.5), ValueError,
     ["damping_ratio", "1.5"]),
    (lambda: MODELS["rod_free"].modal_model(3, residual="yes"), TypeError,
     ["residual", "'yes'"]),
    (lambda: MODELS["rod_free"].natural_frequencies(-2), ValueError, ["n", "-2"]),
    (lambda: MODELS["lumped"].natural_frequencies(1), ValueError, ["n", "1"]),
    (lambda: MODELS["spring"].natural_frequencies(2), ValueError, ["n", "2"]),
    (lambda: MODELS["beam"].receptance("abc"), TypeError, ["s", "'abc'"]),
    (lambda: MODELS["beam"].receptance([1.0, np.nan]), ValueError, ["s", "nan"]),
    (lambda: MODELS["rod_fixed"].impulse_response([[0.0, np.inf]]), ValueError, ["t", "inf"]),
    (lambda: MODELS["rod_fixed"].step_response([1j]), TypeError, ["t", "1j"]),
    (lambda: MODELS["spring"].frf([1.0], quantity="velocity"), ValueError,
     ["quantity", "'velocity'"]),
    (lambda: MODELS["spring"].frf([1j]), TypeError, ["omega", "1j"]),
    (lambda: MODELS["rod_fixed"].jump_times(-1.0), ValueError, ["t_end", "-1.0"]),
    (lambda: MODELS["rod_fixed"].jump_times([1.0, 2.0]), TypeError, ["t_end", "[1.0, 2.0]"]),
    (lambda: cantilever_roots(-1), ValueError, ["n", "-1"]),
    (lambda: cantilever_roots(2.0), TypeError, ["n", "2.0"]),
    (lambda: cantilever_roots(np.array([3])), TypeError, ["n", "array([3])"]),
    (lambda: MODELS["beam"].impulse_response([1.0], rtol=0.0), ValueError, ["rtol", "0.0"]),
    (lambda: MODELS["beam"].impulse_response([1.0], rtol=2.0), ValueError, ["rtol", "2.0"]),
    (lambda: MODELS["beam"].step_response([1.0], n_terms=-3), ValueError, ["n_terms", "-3"]),
    (lambda: MODELS["beam"].step_response([1.0], rtol=1e-3, n_terms=3), ValueError,
     ["rtol=0.001", "n_terms=3"]),
    (lambda: MODELS["beam"].step_error_bound(-1), ValueError, ["n_terms", "-1"]),
]


@pytest.mark.parametrize("call, error, words", BAD_INPUTS)
def test_bad_input_raises_and_names_the_value(call, error, words):
    with pytest.raises(error) as info:
        call()
    message = str(info.value)
    for word in words:
        assert word in message, (word, message)
