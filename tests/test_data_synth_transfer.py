"""Tests of data_synth's responses away from the driving point: exact answers only.

Transfer receptances against the driving point, naive formulas where those are accurate,
modal sums built from the mode shapes (with rigorous truncation bounds), reflected-wave
solutions and numerical inverse Laplace transforms; mode shapes against closed forms and
mass-orthonormality by Gauss-Legendre quadrature; static transfer flexibilities against
beam/rod statics and brute-force modal sums.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from data_synth import CantileverBeam, Rod, cantilever_roots
from data_synth.roots import _power_tail
from modalid import MultiOutputModalModel

EPS = np.finfo(float).eps
M, T = 1.7, 0.3  # kg, s: deliberately not round
K = M / T**2      # N/m
Z = M / T         # rod impedance (N s/m)
MODELS = {"rod_free": Rod(M, T, support="free"), "rod_fixed": Rod(M, T, support="fixed"),
          "beam": CantileverBeam(M, T)}
NAMES = list(MODELS)
XI = np.array([0.0, 0.1, 0.37, 0.5, 0.83, 1.0])


def bromwich_fft(F, t_max, *, n=2**20, c_period=30.0, period_factor=4.0):
    """Inverse Laplace transform by the Fourier-series (Bromwich) method on Re s = c.

    As in tests/test_data_synth.py: alias terms below e^-30 relative, truncation
    ``O(n^-2)`` away from kinks. Returns the grid ``t_j <= t_max`` and ``f(t_j)``.
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


def modal_mass(name):
    return M / 4 if name == "beam" else M / 2


def gauss_legendre_01(n_nodes, n_panels):
    """Composite Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n_nodes)
    edges = np.linspace(0.0, 1.0, n_panels + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    return (mid[:, None] + half[:, None] * x).ravel(), (half[:, None] * w).ravel()


# ============================================================ transfer receptance
def _wide_s():
    r = np.array([1e-300, 1e-160, 1e-150, 1e-9, 1e-3, 0.5, 1.0, 3.0, 1e3, 1e8, 1e15,
                  1e100, 1e300])
    phi = np.linspace(-np.pi, np.pi, 37)
    with np.errstate(under="ignore"):
        return np.concatenate([(r[:, None] * np.exp(1j * phi)).ravel(), 1j * r, -r, [0.0]])


@pytest.mark.parametrize("name", NAMES)
def test_transfer_at_the_driving_point_equals_the_receptance(name):
    model = MODELS[name]
    s = _wide_s()
    h = model.transfer_receptance(s, 0.0)
    assert h.shape == (1,) + s.shape
    np.testing.assert_allclose(h[0], model.receptance(s), rtol=8 * EPS, atol=0)
    # and on a 2-D s, among other points
    s2 = s[:506].reshape(-1, 2)
    h2 = model.transfer_receptance(s2, XI)
    assert h2.shape == (XI.size,) + s2.shape
    np.testing.assert_array_equal(h2[0], h[0, :506].reshape(-1, 2))


@pytest.mark.parametrize("name", NAMES)
def test_transfer_receptance_finite_everywhere(name):
    model = MODELS[name]
    s = _wide_s()
    xi = np.linspace(0.0, 1.0, 21)
    h = model.transfer_receptance(s, xi)
    assert not np.any(np.isnan(h))
    # grounded: finite everywhere; free rod: the rigid 1/(m s^2) overflows below ~1e-154
    finite = np.abs(s) > (0 if model.is_grounded else 1e-150)
    assert np.all(np.isfinite(h[:, finite]))
    if not model.is_grounded:
        assert np.all(h[:, s == 0] == np.inf)
    w = model.natural_frequencies(50)
    assert not np.any(np.isnan(model.transfer_receptance(1j * w, xi)))
    # grounded far end: the fixed rod's end and the clamp do not move
    if model.is_grounded:
        np.testing.assert_array_equal(np.abs(h[-1]) <= 1e-15 * np.abs(h[0]), True)


@pytest.mark.parametrize("support", ["free", "fixed"])
def test_rod_transfer_equals_the_naive_formula(support):
    rod = MODELS["rod_" + support]
    rng = np.random.default_rng(10)
    eps = rng.uniform(0.01, 30.0, 400) * np.exp(1j * rng.uniform(-np.pi, np.pi, 400))
    xi = np.array([0.0, 0.2, 0.5, 0.77, 1.0])
    u = (1.0 - xi)[:, None]
    if support == "free":
        naive = np.cosh(eps * u) / (Z * (eps / T) * np.sinh(eps))
    else:
        naive = np.sinh(eps * u) / (Z * (eps / T) * np.cosh(eps))
    scale = np.abs(naive[0])  # |Re eps| <= 30: little cancellation in the naive form
    h = rod.transfer_receptance(eps / T, xi)
    assert np.all(np.abs(h - naive) <= 1e-13 * scale)
    # near the fixed end the closed form keeps its relative accuracy (u = 2^-30 exactly)
    if support == "fixed":
        d = 2.0**-30
        near = rod.transfer_receptance(eps / T, 1.0 - d)[0]
        np.testing.assert_allclose(near, np.sinh(eps * d) / (K * eps * np.cosh(eps)),
                                   rtol=1e-13)


def test_rod_static_limits():
    xi = np.linspace(0.0, 1.0, 11)
    fixed, free = MODELS["rod_fixed"], MODELS["rod_free"]
    np.testing.assert_allclose(fixed.transfer_receptance([0.0], xi)[:, 0], (1 - xi) / K,
                               rtol=1e-15, atol=1e-300)
    np.testing.assert_allclose(fixed.static_transfer_flexibility(xi), (1 - xi) / K, rtol=1e-15)
    # free: H - 1/(m s^2) -> (1/3 - xi + xi^2/2)/K; the next term is O((sT)^2)/K
    s = np.array([1e-3, 1e-3j]) / T
    elastic = free.transfer_receptance(s, xi) - 1.0 / (M * s**2)
    expected = (1 / 3 - xi + xi**2 / 2) / K
    np.testing.assert_allclose(elastic, np.broadcast_to(expected[:, None] + 0j, elastic.shape),
                               rtol=0, atol=1e-6 / K)
    np.testing.assert_allclose(free.static_transfer_flexibility(xi), expected, rtol=1e-15,
                               atol=1e-16 / K)


def test_beam_transfer_equals_the_naive_formula():
    # 0.05 < |sT| < 30: the textbook form, in long double, loses < 1e-19 e^(Re e xi)
    beam = MODELS["beam"]
    rng = np.random.default_rng(11)
    x = rng.uniform(0.05, 30.0, 300) * np.exp(1j * rng.uniform(-np.pi, np.pi, 300))
    xi = np.array([0.0, 0.15, 0.5, 0.9, 1.0])
    e = np.sqrt(1j * x.astype(np.clongdouble)) * 1j ** rng.integers(0, 4, 300)
    ch, sh, c, s = np.cosh(e), np.sinh(e), np.cos(e), np.sin(e)
    xb = xi[:, None]
    num = ((ch * s - sh * c) * (np.cosh(e * xb) + np.cos(e * xb))
           - (1 + c * ch + s * sh) * (np.sinh(e * xb) + np.sin(e * xb))
           + 2 * (1 + ch * c) * np.sinh(e * xb))
    naive = (num / (2 * e**3 * (1 + ch * c))).astype(complex) / K
    h = beam.transfer_receptance(x / T, xi)
    scale = np.abs(h[0])
    err = np.abs(h - naive) / scale
    assert np.max(err) < 1e-14, np.max(err)


def test_beam_transfer_series_and_closed_form_agree_at_the_switch():
    beam = MODELS["beam"]
    xi = np.array([0.0, 0.3, 0.7, 0.99])
    for phi in np.linspace(-np.pi, np.pi, 13):
        a = beam.transfer_receptance((1 - 1e-15) * np.exp(1j * phi) / T, xi)
        b = beam.transfer_receptance((1 + 1e-15) * np.exp(1j * phi) / T, xi)
        assert np.all(np.abs(a - b) <= 1e-14 * np.abs(a[0]))


def test_beam_static_transfer_is_the_euler_bernoulli_deflection():
    # tip load P on a cantilever: y(x) = P x^2 (3l - x)/(6 EI) from the clamp, x = l(1 - xi)
    beam = MODELS["beam"]
    xi = np.linspace(0.0, 1.0, 11)
    expected = (1 - xi) ** 2 * (2 + xi) / (6 * K)
    np.testing.assert_allclose(beam.transfer_receptance([0.0], xi)[:, 0], expected, rtol=1e-14,
                               atol=1e-300)
    np.testing.assert_allclose(beam.transfer_receptance([1e-9j / T], xi)[:, 0], expected,
                               rtol=1e-14, atol=1e-300)
    np.testing.assert_allclose(beam.static_transfer_flexibility(xi), expected, rtol=1e-15)


def test_large_s_decay_away_from_the_driving_point():
    # Off the imaginary axis a disturbance decays: rod exp(-sT xi) (a wave not yet
    # arrived), beam exp(-e xi) with Re e ~ |sT|^(1/2)
    xi = np.array([0.0, 0.5, 1.0])
    s = np.array([1e4 / T])
    rod = MODELS["rod_free"].transfer_receptance(s, xi)[:, 0]
    np.testing.assert_allclose(rod, [1 / (K * 1e4), 0.0, 0.0], rtol=1e-15, atol=1e-300)
    # (the slower of the two decays, |exp(i e xi)| = exp(-Im e xi), Im e = sqrt(x/2))
    x = np.array([1e2, 1e4, 1e8])
    beam = MODELS["beam"].transfer_receptance(x / T, xi)
    for i in (1, 2):
        assert np.all(np.abs(beam[i]) <= 2 * np.exp(-np.sqrt(x / 2) * xi[i]) * np.abs(beam[0]))
    assert beam[1, 0] != 0 and beam[1, 2] == 0


# =================================================================== modal sums
def _frequencies_between_poles(model, n_intervals=8, per_interval=25, seed=0):
    rng = np.random.default_rng(seed)
    w = np.concatenate([[0.0], model.natural_frequencies(n_intervals)])
    frac = rng.uniform(0.1, 0.9, size=(n_intervals, per_interval))
    return (w[:-1, None] + frac * np.diff(w)[:, None]).ravel()


@pytest.mark.parametrize("name", NAMES)
def test_transfer_receptance_equals_the_modal_sum_of_the_mode_shapes(name):
    model = MODELS[name]
    xi = XI[1:-1]
    omega = _frequencies_between_poles(model)
    s = 1j * omega
    exact = model.transfer_receptance(s, xi)
    scale = np.abs(model.receptance(s))
    errors, residual_errors = [], []
    for n in (20, 40, 80, 160):
        w = model.natural_frequencies(n)
        phi = model.mode_shapes(xi, n)
        phi0 = model.mode_shapes(0.0, n)[0]
        sum_kept = (phi * phi0) @ (1.0 / (w[:, None] ** 2 - omega[None, :] ** 2))
        plain = exact - (model.inverse_mass / s**2 + sum_kept)
        # residual: the omitted modes' static transfer flexibility
        mo = model.multi_output_model(np.concatenate([[0.0], xi]), n, residual=True)
        tail = mo.flexibility[1:]
        tail_driving = mo.flexibility[0]
        w_next = model.natural_frequencies(n + 1)[-1]
        # sum_{k>n} a_k psi_k w^2/(w_k^2 (w_k^2 - w^2)), |psi_k| <= 1, a_k = 1/m_k > 0
        bound = tail_driving * omega**2 / (w_next**2 - omega**2)
        terms = np.sum(1.0 / (modal_mass(name) * np.abs(w[:, None] ** 2 - omega**2)), axis=0)
        atol = 64 * EPS * (scale + terms + model.inverse_mass / omega**2)
        resid = plain - tail[:, None]
        assert np.all(np.abs(plain.imag) <= atol)
        assert np.all(np.abs(resid) <= bound + atol)
        errors.append(np.max(np.abs(plain) / scale))
        residual_errors.append(np.max(np.abs(resid) / scale))
    assert all(b < 0.6 * a for a, b in itertools.pairwise(errors)), errors
    assert all(b < 0.6 * a for a, b in itertools.pairwise(residual_errors))
    assert all(r < 0.2 * e for r, e in zip(residual_errors, errors)), (residual_errors, errors)


@pytest.mark.parametrize("name", NAMES)
def test_multi_output_rows_equal_the_transfer_receptances(name):
    model = MODELS[name]
    xi = np.array([0.37, 0.0, 0.83, 1.0])  # the driving point need not come first
    rng = np.random.default_rng(12)
    s = (rng.uniform(0.3, 3, 100) + 1j * rng.uniform(-60, 60, 100)) / T
    exact = model.transfer_receptance(s, xi)
    scale = np.abs(exact[1])
    n = 2000
    errs = {}
    for residual in (False, True):
        mo = model.multi_output_model(xi, n, residual=residual)
        assert isinstance(mo, MultiOutputModalModel)
        assert mo.driving_point == 1 and mo.outputs == ("xi=0.37", "xi=0", "xi=0.83", "xi=1")
        np.testing.assert_array_equal(mo.inverse_mass, model.inverse_mass)
        err = np.abs(mo.receptance(s) - exact)
        errs[residual] = np.max(err / scale)
    # with the residual:
    # |sum_{k>n} a_k psi_k s^2/(w_k^2 (s^2 + w_k^2))| <= tail |s|^2/(w^2 - |s|^2)
    tail = model.modal_model(n, residual=True).flexibility
    w_next = model.natural_frequencies(n + 1)[-1]
    bound = tail * np.abs(s) ** 2 / (w_next**2 - np.abs(s) ** 2)
    # (plus the rounding of the 2000-term sum, ~1e-14 of the driving point's |H|)
    assert np.all(err <= bound + 1e-12 * scale)
    assert errs[False] > 1e3 * errs[True], errs


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("damping_ratio", [None, 0.02])
@pytest.mark.parametrize("residual", [False, True])
def test_multi_output_driving_row_is_the_modal_model(name, damping_ratio, residual):
    model = MODELS[name]
    mo = model.multi_output_model([0.5, 0.0], 7, damping_ratio=damping_ratio,
                                  residual=residual)
    ref = model.modal_model(7, damping_ratio=damping_ratio, residual=residual)
    row = mo.driving
    np.testing.assert_array_equal(row.poles, ref.poles)
    np.testing.assert_array_equal(row.residues, ref.residues)
    assert row.flexibility == ref.flexibility and row.inverse_mass == ref.inverse_mass
    # other rows: r_ik = phi_k(xi) phi_k(0)/(2 i w_dk)
    phi = model.mode_shapes([0.5, 0.0], 7)
    wd = ref.poles.imag
    np.testing.assert_allclose(mo.residues[0], phi[0] * phi[1] / (2j * wd), rtol=1e-14)
    # mass-scaled shapes of the multi-output model are the mode shapes
    np.testing.assert_allclose(mo.mode_shapes(scaling="mass").real, phi, rtol=1e-12,
                               atol=1e-14 * np.max(np.abs(phi)))
    if not residual:
        np.testing.assert_array_equal(mo.flexibility, 0.0)
    zero = model.multi_output_model([0.0, 1.0], 0, residual=True)
    assert zero.n_modes == 0
    np.testing.assert_allclose(zero.flexibility, model.static_transfer_flexibility([0.0, 1.0]),
                               rtol=1e-15, atol=1e-17 / K)


@pytest.mark.parametrize("name", NAMES)
def test_residual_transfer_flexibility_matches_a_brute_force_sum(name):
    model = MODELS[name]
    xi = np.array([0.0, 0.37, 0.5, 0.83])
    n_big = 400_000 if name.startswith("rod") else 100_000
    w = model.natural_frequencies(n_big)
    terms = model.mode_shapes(xi, n_big) * model.mode_shapes(0.0, n_big) / w**2
    mo = {n: model.multi_output_model(xi, n, residual=True).flexibility for n in (0, 7, 100)}
    for n, flex in mo.items():
        brute = np.array([math.fsum(row[n:]) for row in terms])
        # remainder beyond n_big: beam (4T^2/m) tail4 (|psi| <= 1); rod by summation by
        # parts: the partial sums of cos(k' theta) are at most 1/(2|sin(theta/2)|) + 1/2, so
        # |sum_{k>N} cos(k' theta)/k'^2| <= (1 + 1/|sin(theta/2)|)/N^2 (0 < theta < 2 pi).
        # (For the free rod at these xi, N xi is an even integer and the remainder is
        # -1/(2(N+1)^2) + O(N^-3): the brute-force sum is short by 1.9e-12 x 1/(3K).)
        if name == "beam":
            remainder = np.full(xi.size, 4 * T**2 / M * _power_tail(n_big, 4))
        else:
            theta = np.pi * xi
            with np.errstate(divide="ignore"):
                remainder = 2 / (K * np.pi**2) * (1 + 1 / np.abs(np.sin(theta / 2))) / n_big**2
            remainder[0] = 2 / (K * np.pi**2) / (n_big - 1)
        scale = model.static_flexibility
        assert np.all(np.abs(flex - brute) <= remainder + 1e-14 * scale), (n, flex - brute)


# ================================================================== mode shapes
@pytest.mark.parametrize("support", ["free", "fixed"])
def test_rod_mode_shapes_closed_form(support):
    rod = MODELS["rod_" + support]
    xi = np.linspace(0, 1, 41)
    k = np.arange(1.0, 31.0) - (0.5 if support == "fixed" else 0.0)
    phi = rod.mode_shapes(xi, 30)
    assert phi.shape == (41, 30)
    np.testing.assert_allclose(phi, np.sqrt(2 / M) * np.cos(np.pi * np.outer(xi, k)),
                               rtol=0, atol=1e-14)
    # the fixed end does not move; the free end moves as much as the struck one
    if support == "fixed":
        assert np.all(np.abs(phi[-1]) < 1e-13)
    else:
        np.testing.assert_allclose(np.abs(phi[-1]), np.sqrt(2 / M), rtol=1e-14)


def test_beam_mode_shapes_closed_form_and_boundary_conditions():
    beam = MODELS["beam"]
    beta = cantilever_roots(5)
    xi = np.linspace(0, 1, 101)
    x = 1.0 - xi  # from the clamp
    # textbook form, in long double (its cancellation, ~1e-19 cosh(beta) < 1e-13 here, is
    # too much beyond a few modes): Y = cosh - cos - sigma (sinh - sin)
    b = beta.astype(np.longdouble)
    xb = x[:, None].astype(np.longdouble)
    sigma = (np.sinh(b) - np.sin(b)) / (np.cosh(b) + np.cos(b))
    y = np.cosh(b * xb) - np.cos(b * xb) - sigma * (np.sinh(b * xb) - np.sin(b * xb))
    y = (y * np.sign(y[0]) / np.sqrt(M)).astype(float)  # int Y^2 = 1; phi(0) > 0
    phi = beam.mode_shapes(xi, 5)
    np.testing.assert_allclose(phi, y, rtol=0, atol=1e-12 / np.sqrt(M))
    np.testing.assert_allclose(phi[0], 2 / np.sqrt(M), rtol=2e-15)
    # clamp: phi = phi' = 0 (one-sided difference, slope ~ beta phi)
    many = beam.mode_shapes([1.0, 1.0 - 1e-7], 200)
    assert np.all(np.abs(many[0]) < 1e-12 / np.sqrt(M))
    slope = (many[1] - many[0]) / 1e-7
    beta200 = cantilever_roots(200)
    assert np.all(np.abs(slope) < beta200**2 * 1e-7 / np.sqrt(M) * 4)


@pytest.mark.parametrize("name", NAMES)
def test_mode_shapes_are_mass_orthonormal(name):
    model = MODELS[name]
    x, w = gauss_legendre_01(20, 200)  # exact for these smooth shapes to rounding
    modes = np.r_[0:30, 990:1000]
    phi = model.mode_shapes(x, 1000)[:, modes]
    gram = M * (phi * w[:, None]).T @ phi
    np.testing.assert_allclose(gram, np.eye(modes.size), rtol=0, atol=1e-12)
    # driving point: phi_k(0)^2 = 1/m_k, phi_k(0) > 0
    phi0 = model.mode_shapes(0.0, 1000)[0]
    np.testing.assert_allclose(phi0**2 * modal_mass(name), 1.0, rtol=4 * EPS)
    assert np.all(phi0 > 0)


def test_beam_mode_shapes_never_exceed_the_tip_value():
    # |phi_k(xi)| <= phi_k(0): the premise of the transfer series' error bounds
    beam = MODELS["beam"]
    xi = np.linspace(0, 1, 2001)
    phi = beam.mode_shapes(xi, 2000)
    ratio = np.abs(phi) / phi[0]
    assert np.max(ratio[1:]) <= 1.0
    # large modes: bounded, no loss of digits, |phi(0)| = 2/sqrt(m) to rounding
    np.testing.assert_allclose(phi[0], 2 / np.sqrt(M), rtol=4 * EPS)


# ================================================================== time domain
@pytest.mark.parametrize("support", ["free", "fixed"])
def test_rod_transfer_time_responses_at_the_driving_point(support):
    rod = MODELS["rod_" + support]
    t = np.concatenate([np.linspace(-T, 21 * T, 1001), 2 * T * np.arange(1.0, 11.0)])
    np.testing.assert_array_equal(rod.transfer_impulse_response(t, 0.0)[0],
                                  rod.impulse_response(t))
    np.testing.assert_allclose(rod.transfer_step_response(t, [0.0])[0], rod.step_response(t),
                               rtol=1e-15, atol=1e-15 * T**2 / M)


def test_free_rod_far_end_waits_for_the_wave():
    rod = MODELS["rod_free"]
    t = np.linspace(-T, 7 * T, 8001)
    h = rod.transfer_impulse_response(t, 1.0)[0]  # the velocity under a unit step force
    s = rod.transfer_step_response(t, 1.0)[0]
    before, first, second, third = (t < T), (t > T) & (t < 3 * T), (t > 3 * T) & (t < 5 * T), \
        (t > 5 * T) & (t < 7 * T)
    np.testing.assert_array_equal(h[before], 0.0)
    np.testing.assert_array_equal(s[before], 0.0)
    # the wave doubles at the free end: velocity 2F/Z, then 4F/Z, 6F/Z...
    np.testing.assert_allclose(h[first], 2 / Z, rtol=1e-15)
    np.testing.assert_allclose(h[second], 4 / Z, rtol=1e-15)
    np.testing.assert_allclose(h[third], 6 / Z, rtol=1e-15)
    np.testing.assert_allclose(s[first], 2 * (t[first] - T) / Z, rtol=1e-14)
    np.testing.assert_allclose(s[second], (4 * T + 4 * (t[second] - 3 * T)) / Z, rtol=1e-14)


@pytest.mark.parametrize("support", ["free", "fixed"])
def test_rod_wave_fronts_and_periodicity(support):
    rod = MODELS["rod_" + support]
    xi = np.array([0.1, 0.37, 0.83])
    t = np.linspace(0, 2 * T, 2001)
    h = rod.transfer_impulse_response(t, xi)
    for i, x in enumerate(xi):  # first wave: nothing before xi T, 1/Z until (2 - xi) T
        np.testing.assert_array_equal(h[i, t < x * T], 0.0)
        np.testing.assert_allclose(h[i, (t > x * T) & (t < (2 - x) * T)], 1 / Z, rtol=1e-15)
    n = np.array([1.0, 7.0, 1e5, 5e5])
    s_even = rod.transfer_step_response(4 * n * T, xi)
    s_odd = rod.transfer_step_response((4 * n + 2) * T, xi)
    if support == "free":
        # at t = 2jT every elastic mode is back at rest: S = t^2/(2m) at every point
        np.testing.assert_allclose(s_even, np.broadcast_to((4 * n * T) ** 2 / (2 * M),
                                                           s_even.shape), rtol=1e-14)
        np.testing.assert_allclose(s_odd, np.broadcast_to(((4 * n + 2) * T) ** 2 / (2 * M),
                                                          s_odd.shape), rtol=1e-14)
    else:
        # all periods divide 4T: S(4jT) = 0, S((4j+2)T) = 2 x static = 2(1 - xi)/K
        np.testing.assert_allclose(s_even, 0.0, atol=1e-9 * T**2 / M)
        np.testing.assert_allclose(s_odd, np.broadcast_to(2 * (1 - xi)[:, None] / K,
                                                          s_odd.shape), rtol=1e-9)
        np.testing.assert_array_equal(rod.transfer_step_response(t, 1.0), 0.0)
        np.testing.assert_array_equal(rod.transfer_impulse_response(t, 1.0), 0.0)


@pytest.mark.parametrize("support", ["free", "fixed"])
def test_rod_transfer_step_response_against_numerical_inverse_laplace(support):
    rod = MODELS["rod_" + support]
    xi = 0.37
    t, f = bromwich_fft(lambda s: rod.transfer_receptance(s, xi)[0] / s, 6 * T, n=2**19)
    t, f = t[::97], f[::97]
    # kinks at (2n + xi) T and (2n + 2 - xi) T
    kinks = np.concatenate([(2 * np.arange(4) + xi) * T, (2 * np.arange(4) + 2 - xi) * T])
    keep = (t > 0.05 * T) & (np.min(np.abs(t[:, None] - kinks), axis=1) > 0.01 * T)
    t, f = t[keep], f[keep]
    np.testing.assert_allclose(rod.transfer_step_response(t, xi)[0], f, rtol=1e-8,
                               atol=5e-9 * T**2 / M)
    # impulse = dS/dt (S piecewise linear: the central difference is exact)
    d = 1e-4 * T
    fd = (rod.transfer_step_response(t + d, xi) - rod.transfer_step_response(t - d, xi)) / (2 * d)
    np.testing.assert_allclose(fd, rod.transfer_impulse_response(t, xi), rtol=0,
                               atol=1e-9 * np.max(np.abs(fd)))


def test_beam_mid_span_step_response_against_a_fine_modal_sum_and_bromwich():
    beam = MODELS["beam"]
    xi = 0.5
    t = np.linspace(0, 6 * T, 31)
    s = beam.transfer_step_response(t, xi)[0]
    n_default = 4347  # default rtol 1e-12
    # independent: ModalModel.step_response of a 20000-mode row with its residual
    # (|error| <= (4T^2/m) tail4(20000) ~ 6e-16/(3K))
    ref = beam.multi_output_model([0.0, xi], 20000, residual=True).step_response(t)[1]
    bound = beam.step_error_bound(n_default) + 4 * T**2 / M * _power_tail(20000, 4)
    assert bound <= 1.1e-12 * beam.static_flexibility
    assert np.all(np.abs(s - ref) <= bound + 1e-15 * beam.static_flexibility)
    # coarse series: within its stated two-sided bound
    coarse = beam.transfer_step_response(t, xi, n_terms=30)[0]
    assert np.all(np.abs(coarse - s) <= beam.step_error_bound(30) * (1 + 1e-9))
    assert np.max(np.abs(coarse - s)) > 0.05 * beam.step_error_bound(30)
    # numerical inverse Laplace transform of the closed-form transfer receptance
    tb, f = bromwich_fft(lambda z: beam.transfer_receptance(z, xi)[0] / z, 6 * T, n=2**19)
    tb, f = tb[::97], f[::97]
    keep = tb > 0.05 * T
    np.testing.assert_allclose(beam.transfer_step_response(tb[keep], xi)[0], f[keep],
                               rtol=1e-8, atol=5e-9 * beam.static_flexibility)
    # S oscillates about the static deflection (1-xi)^2(2+xi)/(6K): its long-time mean
    mean = np.mean(beam.transfer_step_response(np.linspace(0, 300 * T, 6001), xi,
                                               n_terms=200))
    assert mean == pytest.approx(0.25 * 2.5 / 6 / K, rel=1e-2)


def test_beam_transfer_time_responses_at_the_tip_and_clamp():
    beam = MODELS["beam"]
    t = np.concatenate([[-1.0, -1e-12, 0.0], np.linspace(0, 10 * T, 37)])
    for kw in ({"n_terms": 300}, {}):
        np.testing.assert_allclose(beam.transfer_step_response(t, 0.0, **kw)[0],
                                   beam.step_response(t, **kw), rtol=1e-14, atol=1e-300)
    np.testing.assert_allclose(beam.transfer_impulse_response(t, [0.0], n_terms=300)[0],
                               beam.impulse_response(t, n_terms=300), rtol=1e-13,
                               atol=1e-15 * T / M)
    clamp = beam.transfer_step_response(t, [1.0, 0.5], n_terms=300)
    assert np.all(np.abs(clamp[0]) < 1e-13 * beam.static_flexibility)
    np.testing.assert_array_equal(clamp[:, :3], 0.0)
    # impulse response = dS/dt (20 modes, central difference as in test_data_synth)
    rng = np.random.default_rng(13)
    tt = rng.uniform(0.01, 10, 100) * T
    d = 1e-6 * T
    fd = (beam.transfer_step_response(tt + d, 0.5, n_terms=20)
          - beam.transfer_step_response(tt - d, 0.5, n_terms=20)) / (2 * d)
    h = beam.transfer_impulse_response(tt, 0.5, n_terms=20)
    np.testing.assert_allclose(fd, h, rtol=0, atol=1e-7 * np.max(np.abs(h)))
    # impulse error bound with the default tolerance, against a coarse series
    tt = np.array([0.37, 1.0, 2.9]) * T
    coarse = beam.transfer_impulse_response(tt, 0.5, n_terms=100)
    fine = beam.transfer_impulse_response(tt, 0.5, rtol=1e-4)
    assert np.all(np.abs(coarse - fine) <= beam.impulse_error_bound(100) + 1e-4 * T / M)


# ==================================================================== bad input
BAD_INPUTS = [
    (lambda m: m.transfer_receptance(1.0, -0.1), ValueError, ["xi", "-0.1"]),
    (lambda m: m.transfer_receptance(1.0, [0.5, 1.5]), ValueError, ["xi", "1.5"]),
    (lambda m: m.transfer_receptance(1.0, [0.5, np.nan]), ValueError, ["xi", "nan"]),
    (lambda m: m.transfer_receptance(1.0, [[0.5]]), ValueError, ["xi", "(1, 1)"]),
    (lambda m: m.transfer_receptance(1.0, [0.5j]), TypeError, ["xi", "0.5j"]),
    (lambda m: m.transfer_receptance(1.0, "0.5"), TypeError, ["xi", "'0.5'"]),
    (lambda m: m.transfer_receptance([np.nan], 0.5), ValueError, ["s", "nan"]),
    (lambda m: m.transfer_step_response([np.inf], 0.5), ValueError, ["t", "inf"]),
    (lambda m: m.transfer_impulse_response([1j], 0.5), TypeError, ["t", "1j"]),
    (lambda m: m.transfer_step_response([1.0], np.inf), ValueError, ["xi", "inf"]),
    (lambda m: m.mode_shapes([0.0, 2.0], 3), ValueError, ["xi", "2.0"]),
    (lambda m: m.mode_shapes([0.0], -1), ValueError, ["n_modes", "-1"]),
    (lambda m: m.mode_shapes([0.0], 2.0), TypeError, ["n_modes", "2.0"]),
    (lambda m: m.static_transfer_flexibility(-1e-9), ValueError, ["xi", "-1e-09"]),
    (lambda m: m.multi_output_model([0.5, 1.0], 3), ValueError, ["xi", "0.0", "[0.5, 1.0]"]),
    (lambda m: m.multi_output_model([0.0, 0.5, 0.5], 3), ValueError, ["xi", "0.5"]),
    (lambda m: m.multi_output_model([0.0, 1.2], 3), ValueError, ["xi", "1.2"]),
    (lambda m: m.multi_output_model([0.0], -2), ValueError, ["n_modes", "-2"]),
    (lambda m: m.multi_output_model([0.0], 3, damping_ratio=1.0), ValueError,
     ["damping_ratio", "1.0"]),
    (lambda m: m.multi_output_model([0.0], 3, residual=1), TypeError, ["residual", "1"]),
]


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("call, error, words", BAD_INPUTS)
def test_bad_input_raises_and_names_the_value(name, call, error, words):
    with pytest.raises(error) as info:
        call(MODELS[name])
    message = str(info.value)
    for word in words:
        assert word in message, (word, message)


def test_beam_series_bad_tolerances():
    beam = MODELS["beam"]
    with pytest.raises(ValueError, match="rtol"):
        beam.transfer_step_response([1.0], 0.5, rtol=2.0)
    with pytest.raises(ValueError, match="n_terms"):
        beam.transfer_impulse_response([1.0], 0.5, rtol=1e-3, n_terms=3)


def test_shapes_of_the_outputs():
    for model in MODELS.values():
        t = np.zeros((2, 3))
        assert model.transfer_step_response(t, [0.1, 0.2, 0.3]).shape == (3, 2, 3)
        assert model.transfer_impulse_response(t, 0.4).shape == (1, 2, 3)
        assert model.transfer_receptance(1j, [0.0, 1.0]).shape == (2,)
        assert model.mode_shapes(np.linspace(0, 1, 5), 0).shape == (5, 0)
        assert model.static_transfer_flexibility(0.0).shape == (1,)
