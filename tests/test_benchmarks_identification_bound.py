"""benchmarks/identification_bound.py: the Jacobian and the Cramer-Rao covariance it rests on.

The benchmark's bound is only as good as ``relative_jacobian``; it is checked here against
central differences of the exact model's receptance, and the covariance against the
Fisher information it inverts.
"""

import importlib.util
import pathlib

import numpy as np
import pytest

from data_synth import CantileverBeam, Rod
from modalid import ModalModel

_PATH = pathlib.Path(__file__).resolve().parents[1] / "benchmarks" / "identification_bound.py"
_SPEC = importlib.util.spec_from_file_location("identification_bound", _PATH)
bound = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(bound)


def _model(theta, rigid):
    """A ModalModel from ``[omega_n, zeta, Re r, Im r] * n, flexibility[, inverse_mass]``."""
    n = (theta.size - 1 - rigid) // 4
    wn, zeta = theta[0:4 * n:4], theta[1:4 * n:4]
    poles = wn * (-zeta + 1j * np.sqrt(1 - zeta**2))
    residues = theta[2:4 * n:4] + 1j * theta[3:4 * n:4]
    return ModalModel(poles=poles, residues=residues, flexibility=theta[4 * n],
                      inverse_mass=theta[4 * n + 1] if rigid else 0.0)


@pytest.mark.parametrize("structure", [CantileverBeam(1.0, 1.0), Rod(1.0, 1.0, support="free")],
                         ids=["beam", "free rod"])
def test_relative_jacobian_matches_central_differences(structure):
    truth = structure.modal_model(4, damping_ratio=0.02, residual=True)
    rigid = truth.inverse_mass > 0
    modes = truth.modes.iloc[:3]
    theta = np.r_[np.column_stack([modes["omega_n"], modes["damping_ratio"],
                                   modes["residue"].to_numpy().real,
                                   modes["residue"].to_numpy().imag]).ravel(),
                  truth.flexibility, [truth.inverse_mass] if rigid else []]
    # the relative scale of each column, as relative_jacobian defines it
    r_abs = np.abs(modes["residue"].to_numpy())
    scale = np.r_[np.column_stack([modes["omega_n"], modes["damping_ratio"], r_abs,
                                   r_abs]).ravel(),
                  abs(truth.flexibility), [truth.inverse_mass] if rigid else []]
    reference = _model(theta, rigid)
    omega = np.linspace(0.2, 1.2, 300) * modes["omega_n"].iloc[-1]
    jac = bound.relative_jacobian(reference, omega, 3)
    assert jac.shape == (omega.size, theta.size)
    for j in range(theta.size):
        h = 1e-6 * scale[j]
        up, down = theta.copy(), theta.copy()
        up[j] += h
        down[j] -= h
        numeric = (_model(up, rigid).frf(omega) - _model(down, rigid).frf(omega)) / (2 * h)
        numeric *= scale[j]
        np.testing.assert_allclose(jac[:, j], numeric, rtol=1e-6,
                                   atol=1e-6 * np.abs(numeric).max(), err_msg=f"column {j}")


def test_crb_covariance_inverts_the_fisher_information():
    truth = Rod(1.0, 1.0, support="fixed").modal_model(5, damping_ratio=0.01, residual=True)
    omega = np.linspace(1.0, 1.1 * truth.modes["omega_n"].iloc[2], 2000)
    jac = bound.relative_jacobian(truth, omega, 3)
    exact = truth.frf(omega)
    cov = bound.crb_covariance(jac, exact, 0.05)
    jw = jac / (0.05 * np.abs(exact))[:, None]
    fisher = 2 * np.real(jw.conj().T @ jw)
    np.testing.assert_allclose(fisher @ cov, np.eye(cov.shape[0]), atol=1e-8)
    # halving the noise halves every standard deviation
    half = bound.crb_covariance(jac, exact, 0.025)
    np.testing.assert_allclose(np.sqrt(np.diag(half)), 0.5 * np.sqrt(np.diag(cov)), rtol=1e-10)


def test_worst_of_groups_consecutive_draws():
    np.testing.assert_array_equal(bound.worst_of(np.arange(11.0), 5), [4.0, 9.0])


def test_crb_matches_the_scatter_of_a_weighted_least_squares_fit():
    """The bound's noise model is frf_case's: H (1 + eta (n1 + i n2) / sqrt 2). A weighted
    linear least-squares fit of the linearised model to that noise scatters by exactly the
    bound (the efficient estimator here), which checks the factor 2 and the variance."""
    truth = Rod(1.0, 1.0, support="fixed").modal_model(5, damping_ratio=0.01, residual=True)
    omega = np.linspace(1.0, 1.1 * truth.modes["omega_n"].iloc[2], 600)
    jac = bound.relative_jacobian(truth, omega, 3)
    exact = truth.frf(omega)
    eta = 0.05
    cov = bound.crb_covariance(jac, exact, eta)
    jw = jac / (eta * np.abs(exact))[:, None]
    a = np.vstack([jw.real, jw.imag])
    rng = np.random.default_rng(3)
    fits = []
    for _ in range(400):
        noise = exact * eta * (rng.normal(size=omega.size)
                               + 1j * rng.normal(size=omega.size)) / np.sqrt(2)
        nw = noise / (eta * np.abs(exact))
        fits.append(np.linalg.lstsq(a, np.r_[nw.real, nw.imag], rcond=None)[0])
    ratio = np.std(fits, axis=0) / np.sqrt(np.diag(cov))
    assert np.all(np.abs(ratio - 1) < 0.12), ratio


def test_bound_draws_map_the_covariance_to_the_metrics():
    """One mode in band, a rigid body: df, dz are |errors| of the first two columns, dr the
    modulus of the residue pair, dM the inverse mass's (medians of |N(0, s)| are 0.674 s),
    nrmse the linearised FRF error."""
    truth = Rod(1.0, 1.0, support="free").modal_model(3, damping_ratio=0.01, residual=True)
    omega = np.linspace(0.2, 1.5, 500) * truth.modes["omega_n"].iloc[0]
    exact = truth.frf(omega)
    cov = bound.crb_covariance(bound.relative_jacobian(truth, omega, 2), exact, 0.05)
    d = bound.bound_draws(truth, omega, exact, 0.05, n_modes=2, n_band=1, draws=40000,
                          rng=np.random.default_rng(0))
    sd = np.sqrt(np.diag(cov))
    for key, col in (("df", 0), ("dz", 1), ("dM", -1)):
        assert np.median(d[key]) == pytest.approx(0.6745 * sd[col], rel=0.03), key
    # mean squares: E|dr|^2 = var(Re r) + var(Im r); E nrmse^2 = tr(J C J^H) / ||H||^2
    assert np.mean(d["dr"] ** 2) == pytest.approx(cov[2, 2] + cov[3, 3], rel=0.03)
    jac = bound.relative_jacobian(truth, omega, 2)
    expected = np.real(np.trace(jac @ cov @ jac.conj().T)) / np.sum(np.abs(exact) ** 2)
    assert np.mean(d["nrmse"] ** 2) == pytest.approx(expected, rel=0.03)


def test_runs_meeting_counts_runs_under_every_target():
    draws = {"a": np.array([1.0, 3.0, 1.0, 1.0, 2.0, 0.5]), "b": np.array([0.0, 0.0, 5.0,
                                                                          0.0, 0.0, 0.0])}
    stats, all_met = bound.runs_meeting(draws, {"a": 2.5, "b": 1.0}, 2)
    # runs (1, 3), (1, 1), (2, 0.5) of a; (0, 0), (5, 0), (0, 0) of b
    assert stats["a"] == (pytest.approx(2.0), pytest.approx(2 / 3))
    assert stats["b"] == (pytest.approx(0.0), pytest.approx(2 / 3))
    assert all_met == pytest.approx(1 / 3)
