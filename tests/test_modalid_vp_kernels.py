"""The compiled variable-projection kernels against exact complex arithmetic."""

import numpy as np
import pytest

from modalid._lsfd import Terms, _cho_solve, _cholesky, _Projection, _realify, design_matrix
from modalid._lsfd import evaluate
from modalid._vp_kernels import fill_columns, fill_derivative, sum_modes


def _case(m=300, n=5, seed=3):
    rng = np.random.default_rng(seed)
    omega = np.linspace(50.0, 900.0, m)
    wn = np.sort(rng.uniform(80.0, 850.0, n))
    poles = wn * (-rng.uniform(1e-3, 0.1, n) + 1j)
    residues = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    w = rng.uniform(0.5, 2.0, m)
    return omega, w, poles, residues


def test_columns_are_the_weighted_design_matrix():
    omega, w, poles, _ = _case()
    m, n = omega.size, poles.size
    mat = np.full((2 * m, 2 * n + 2), 7.0)
    wd, a, b = (np.empty((m, n)) for _ in range(3))
    fill_columns(omega, w, poles.real.copy(), poles.imag.copy(), mat, wd, a, b,
                 np.arange(n))
    exact = _realify(design_matrix(1j * omega, poles, Terms(np.zeros(0), False, False))
                     * w[:, None])
    np.testing.assert_allclose(mat[:, :2 * n], exact, rtol=1e-12, atol=1e-14 * abs(exact).max())
    assert np.all(mat[:, 2 * n:] == 7.0)              # other columns untouched


def test_some_columns_only_leave_the_others_and_match_all_columns():
    omega, w, poles, _ = _case()
    m, n = omega.size, poles.size
    full, part = np.empty((2 * m, 2 * n)), np.full((2 * m, 2 * n), 7.0)
    bufs_full, bufs_part = ([np.empty((m, n)) for _ in range(3)] for _ in range(2))
    args = (omega, w, poles.real.copy(), poles.imag.copy())
    fill_columns(*args, full, *bufs_full, np.arange(n))
    fill_columns(*args, part, *bufs_part, np.array([3, 1]))
    cols = np.array([2, 3, 6, 7])                      # Re r, Im r of poles 1 and 3
    np.testing.assert_array_equal(part[:, cols], full[:, cols])
    assert np.all(np.delete(part, cols, axis=1) == 7.0)
    np.testing.assert_array_equal(bufs_part[0][:, [1, 3]], bufs_full[0][:, [1, 3]])


def test_sum_of_modes_is_the_complex_partial_fractions():
    omega, _, poles, r = _case(n=7)
    s = 1j * omega[:, None]
    exact = 2.5e-3 + np.sum(r / (s - poles) + np.conj(r) / (s - np.conj(poles)), axis=1)
    out = np.full(omega.size, 2.5e-3, dtype=complex)
    sum_modes(omega, poles.real.copy(), poles.imag.copy(), r.real.copy(), r.imag.copy(), out)
    np.testing.assert_allclose(out, exact, rtol=1e-12, atol=1e-14 * abs(exact).max())
    # evaluate() uses it (any shape of omega), with the mass line and flexibility added
    model = evaluate(omega.reshape(20, -1), poles, r, (), (), 0.5, 2.5e-3)
    np.testing.assert_allclose(model.ravel(), exact + 0.5 / s[:, 0] ** 2, rtol=1e-12,
                               atol=1e-14 * abs(exact).max())


def test_derivative_is_the_complex_derivative():
    # d/dp [r/(s - p) + conj r/(s - conj p)] = r/(s - p)^2 (holomorphic part) and its
    # conjugate partner: d/dRe p and d/dIm p of the real-form model
    omega, w, poles, r = _case()
    m, n = omega.size, poles.size
    mat = np.empty((2 * m, 2 * n))
    wd, a, b = (np.empty((m, n)) for _ in range(3))
    fill_columns(omega, w, poles.real.copy(), poles.imag.copy(), mat, wd, a, b,
                 np.arange(n))
    out = np.empty((2 * m, 2 * n))
    fill_derivative(omega, poles.real.copy(), poles.imag.copy(), r.real.copy(),
                    r.imag.copy(), wd, a, b, out)
    s = 1j * omega[:, None]
    first = r / (s - poles) ** 2                      # d/dp of r/(s - p)
    second = np.conj(r) / (s - np.conj(poles)) ** 2   # d/d(conj p) of its partner
    d_re = (first + second) * w[:, None]              # dRe p moves p and conj p alike
    d_im = 1j * (first - second) * w[:, None]
    np.testing.assert_allclose(out[:, 0::2], _realify(d_re), rtol=1e-10,
                               atol=1e-12 * abs(d_re).max())
    np.testing.assert_allclose(out[:, 1::2], _realify(d_im), rtol=1e-10,
                               atol=1e-12 * abs(d_im).max())


def test_projection_recovers_exact_residues():
    omega, w, poles, r = _case(n=4)
    terms = Terms(np.zeros(0), False, True)
    h = (np.sum(r / (1j * omega[:, None] - poles)
                + np.conj(r) / (1j * omega[:, None] - np.conj(poles)), axis=1) + 3e-3)
    extra = _realify(design_matrix(1j * omega, np.zeros(0), terms) * w[:, None])
    proj = _Projection(omega, w, _realify(h * w), poles, extra)
    np.testing.assert_allclose(proj.x[0:8:2] + 1j * proj.x[1:8:2], r, rtol=1e-9)
    assert proj.x[-1] == pytest.approx(3e-3, rel=1e-9)
    assert proj.cost < 1e-20 * np.sum(np.abs(h * w) ** 2)


def test_cholesky_helpers():
    a = np.array([[4.0, 1.0], [1.0, 3.0]])
    factor = _cholesky(a)
    np.testing.assert_allclose(_cho_solve(factor, np.array([1.0, 2.0])),
                               np.linalg.solve(a, [1.0, 2.0]), rtol=1e-14)
    assert _cholesky(np.array([[1.0, 2.0], [2.0, 1.0]])) is None       # indefinite
    assert _cholesky(np.array([[np.nan, 0.0], [0.0, 1.0]])) is None
    empty = _cholesky(np.zeros((0, 0)))                               # no unknowns
    assert _cho_solve(empty, np.zeros(0)).shape == (0,)
