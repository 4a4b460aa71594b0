"""Residues for fixed poles and the variable-projection refinement (modalid._lsfd):
the passivity bounds and the equality that holds an impulse response at 0 at t = 0,
against a general constrained optimiser and against the definition of a minimum."""

import numpy as np
import pytest
from scipy.optimize import minimize

from modalid._global import refine_joint, split_rows
from modalid._lsfd import (Terms, _bounds, _HeldColumns, _Projection, _realify,
                           design_matrix, refine_varpro, split_coefficients)

UPPER = Terms(np.zeros(0), False, True)


def _data(seed=0, noise=0.02):
    """Three lightly damped modes and a noisy background: a receptance whose passive fit
    with two pseudo-modes above the band has a real residue to spare."""
    rng = np.random.default_rng(seed)
    omega = np.linspace(20.0, 400.0, 400)
    poles = np.array([80.0, 170.0, 290.0]) * (-np.array([0.01, 0.02, 0.015]) + 1j)
    residues = -1j * np.array([3e-3, 2e-3, 1e-3]) + np.array([2e-4, -1e-4, 3e-4])
    s = 1j * omega
    h = np.sum(residues / (s[:, None] - poles) + residues.conj() / (s[:, None] - poles.conj()),
               axis=1) + 2e-6
    h *= 1 + noise * (rng.standard_normal(omega.size) + 1j * rng.standard_normal(omega.size))
    pseudo = 400.0 * np.array([1.2, 2.0]) * (-0.05 + 1j)
    return omega, h, np.full(omega.size, 1e3), np.concatenate([poles, pseudo])


def _slsqp_optimum(mat, y, lo, hi, e, *, start=None, ftol=1e-15):
    """The bounded least squares ``|y - mat x|`` with ``e @ x = 0`` by SLSQP, columns
    scaled to unit norm (``fun``: the cost)."""
    scale = np.linalg.norm(mat, axis=0)
    a = mat / scale
    box = [(None if np.isinf(low) else low, None if np.isinf(high) else high)
           for low, high in zip(lo, hi)]
    z0 = np.zeros(a.shape[1]) if start is None else start * scale
    return minimize(lambda z: np.sum((y - a @ z) ** 2), z0,
                    jac=lambda z: -2 * a.T @ (y - a @ z), bounds=box,
                    constraints=[{"type": "eq", "fun": lambda z: e @ (z / scale),
                                  "jac": lambda z: e / scale}],
                    method="SLSQP", options={"maxiter": 1000, "ftol": ftol})


def _jump(x, n):
    return 2 * float(np.sum(x[0:2 * n:2]))


def test_projection_with_the_equality_is_the_constrained_least_squares_optimum():
    omega, h, w, poles = _data()
    n = poles.size
    y = _realify(h * w)
    extra = _realify(design_matrix(1j * omega, np.zeros(0), UPPER) * w[:, None])
    lo, hi, e = _bounds(n, UPPER, True, zero_start=True)
    free = _Projection(omega, w, y, poles, extra, (lo, hi, None))
    held = _Projection(omega, w, y, poles, extra, (lo, hi, e))
    assert abs(_jump(free.x, n)) > 1e-5                      # the data leave a 1/s term
    assert abs(_jump(held.x, n)) < 1e-12 * np.abs(held.x).sum()
    assert np.all(held.x >= lo) and np.all(held.x <= hi)
    ref = _slsqp_optimum(held.mat, y, lo, hi, e, start=held.x)
    assert ref.success
    assert held.cost == pytest.approx(ref.fun, rel=1e-9)
    assert held.cost <= ref.fun * (1 + 1e-12)
    assert held.cost >= free.cost                            # a constraint costs, never gains
    # the projection of the refinement's Jacobian is the one onto the columns restricted
    # to the equality's plane: it keeps any model in that plane, and maps the residual
    # (orthogonal to the plane's models) to 0
    cols = held.mat[:, held.free]

    def project(v):
        return cols @ held._solve(cols.T @ v)

    z = np.random.default_rng(5).standard_normal(cols.shape[1])
    z -= e[held.free] * (e[held.free] @ z) / (e[held.free] @ e[held.free])
    np.testing.assert_allclose(project(cols @ z), cols @ z, rtol=0,
                               atol=1e-9 * np.abs(cols @ z).max())
    assert np.abs(project(held.residual)).max() < 1e-9 * np.abs(y).max()
    unconstrained = cols @ np.linalg.lstsq(cols, y, rcond=None)[0]
    assert np.abs(project(unconstrained) - unconstrained).max() > 1e-6 * np.abs(y).max()


def test_gradient_of_the_projected_cost_holding_the_equality():
    """Kaufman's gradient ``-2 G^T r`` (what the refinement descends) is the derivative of
    the variable-projection cost with the equality held: by the envelope theorem, as
    without it; checked against central differences in every pole's real and imaginary
    part (the active set unchanged)."""
    omega, h, w, poles = _data(seed=1)
    n = poles.size
    y = _realify(h * w)
    extra = _realify(design_matrix(1j * omega, np.zeros(0), UPPER) * w[:, None])
    bounds = _bounds(n, UPPER, True, zero_start=True)

    def project(q):
        return _Projection(omega, w, y, q, extra, bounds)

    base = project(poles)
    _, jtr = base.normal_equations()
    numeric = np.empty(2 * n)
    for k in range(n):
        for part, step in ((0, 1e-6), (1, 1e-6j)):
            hstep = step * abs(poles[k])
            up, down = poles.copy(), poles.copy()
            up[k] += hstep
            down[k] -= hstep
            numeric[2 * k + part] = (project(up).cost - project(down).cost) / (2 * abs(hstep))
    np.testing.assert_allclose(-2 * jtr, numeric, rtol=0, atol=1e-4 * np.abs(numeric).max())


def test_held_poles_keep_their_gram_block_and_give_the_same_normal_equations():
    """With most poles held (the segments' poles while the pseudo-modes are refined) the
    projection computes only the moving columns' rows of the Gram matrix and the moving
    poles' derivatives: the same Gram matrix, cost and normal equations (held rows and
    columns 0) as the full computation, for the poles it cached and for moved ones."""
    omega, h, w, poles = _data(seed=3)
    y = _realify(h * w)
    extra = _realify(design_matrix(1j * omega, np.zeros(0), UPPER) * w[:, None])
    hold = np.array([True, False, True, True, True])
    held = _HeldColumns(hold, extra.shape[1])
    moving = np.repeat(~hold, 2)
    for shift in (0.0, 3.0 + 2.0j):                  # the first call caches the block
        trial = poles.copy()
        trial[~hold] += shift
        full = _Projection(omega, w, y, trial, extra)
        part = _Projection(omega, w, y, trial, extra, held=held)
        np.testing.assert_allclose(part.gram, full.gram, rtol=1e-12, atol=0)
        assert part.cost == pytest.approx(full.cost, rel=1e-12)
        jtj, jtr = full.normal_equations()
        jtj_h, jtr_h = part.normal_equations()
        np.testing.assert_allclose(jtj_h[np.ix_(moving, moving)], jtj[np.ix_(moving, moving)],
                                   rtol=1e-9)
        np.testing.assert_allclose(jtr_h[moving], jtr[moving], rtol=1e-9)
        assert not jtj_h[~moving].any() and not jtr_h[~moving].any()
    # the refinement through it: the held poles stay, the moving one where the full
    # computation takes it
    p, x, info = refine_varpro(omega, h, w, poles, UPPER, hold=hold, with_std=False,
                               held_gram=True)
    assert info["converged"] and np.array_equal(p[hold], poles[hold])
    q, _, reference = refine_varpro(omega, h, w, poles, UPPER, hold=hold, with_std=False)
    # (both stop where a step would gain under 1e-4 of a residual variance)
    assert reference["cost"] == pytest.approx(info["cost"], rel=1e-7)
    np.testing.assert_allclose(q, p, rtol=1e-7)


def test_refinement_holding_the_equality_keeps_it():
    omega, h, w, poles = _data(seed=1)
    n = poles.size
    p, x, info = refine_varpro(omega, h, w, poles, UPPER, passive=True, zero_start=True,
                               hold=np.array([False, False, False, False, True]))
    assert info["converged"] and np.all(p.real < 0)
    assert abs(_jump(x, n)) < 1e-12 * np.abs(x).sum()
    assert np.all(x[1:2 * n:2] <= 0)
    # without the equality the fit keeps a 1/s term, at a lower cost
    q, x_free, free = refine_varpro(omega, h, w, poles, UPPER, passive=True,
                                    hold=np.array([False, False, False, False, True]))
    assert abs(_jump(x_free, n)) > 1e-5 and free["cost"] < info["cost"]


def test_common_poles_hold_the_equality_in_the_driving_point_row_only():
    omega, h, w, poles = _data(seed=2)
    rows = np.array([h, 0.5 * h.conj() * 1j, h * (1 + 0.3j)])
    weights = np.full(rows.shape, 1e3)
    p, xs, info = refine_joint(omega, rows, weights, poles, UPPER, passive_row=0,
                               zero_start=True, max_iter=20, with_std=False)
    residues = split_rows(xs, p.size, UPPER)[0]
    assert abs(2 * residues[0].real.sum()) < 1e-12 * np.abs(residues[0]).sum()
    assert abs(2 * residues[2].real.sum()) > 1e-5             # transfer rows are free
    assert np.all(residues[0].imag <= 0)
    r, _, _, d = split_coefficients(xs[0], p.size, UPPER)
    assert d >= 0 and np.allclose(r, residues[0])


def test_the_multiplier_releases_a_bounded_real_pole_residue_the_right_way():
    """Real-pole residues are bounded (``c_j >= 0``) and enter the equality (``h(0) =
    sum 2 Re r + sum c_j``): whether a bound is released depends on the Lagrangian's
    gradient, multiplier included. Twenty random problems, each the constrained optimum
    SLSQP finds (with the multiplier's sign flipped, about 40 % of such problems are
    not)."""
    terms = Terms(np.array([-60.0, -250.0]), False, True)
    rng = np.random.default_rng(11)
    omega = np.linspace(20.0, 400.0, 200)
    for _ in range(20):
        poles = np.sort(rng.uniform(60, 380, 2)) * (-rng.uniform(0.01, 0.1, 2) + 1j)
        y = _realify((rng.standard_normal(omega.size) + 1j * rng.standard_normal(omega.size))
                     * 1e-3)
        w = np.ones(omega.size)
        extra = _realify(design_matrix(1j * omega, np.zeros(0), terms))
        lo, hi, e = _bounds(poles.size, terms, True, zero_start=True)
        held = _Projection(omega, w, y, poles, extra, (lo, hi, e))
        ref = _slsqp_optimum(held.mat, y, lo, hi, e, ftol=1e-16)
        assert held.cost == pytest.approx(ref.fun, rel=1e-7)
        assert abs(e @ held.x) < 1e-9 * np.abs(held.x).sum()


def test_a_step_without_a_projection_gives_its_workspace_back(monkeypatch):
    """A trial step whose projection raises LinAlgError is a rejected step; its workspace
    went with it, and the next trial found none (IndexError). The refinement with the
    first trial failing goes on and ends where the one without the failure does."""
    import modalid._lsfd as lsfd

    omega, h, w, poles = _data()
    start = poles * (1 + 0.01j)
    calls = {"n": 0}

    class FailingOnce(_Projection):
        def __init__(self, *args, **kwargs):
            calls["n"] += 1
            if calls["n"] == 2:                   # the first trial step
                raise np.linalg.LinAlgError("no projection there")
            super().__init__(*args, **kwargs)

    clean = refine_varpro(omega, h, w, start, UPPER, max_iter=200)
    monkeypatch.setattr(lsfd, "_Projection", FailingOnce)
    failed = refine_varpro(omega, h, w, start, UPPER, max_iter=200)
    assert calls["n"] > 3                         # it went on after the failure
    # the step shortened after the failure: another path to the same basin
    assert failed[2]["cost"] == pytest.approx(clean[2]["cost"], rel=1e-3)
