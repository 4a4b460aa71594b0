"""The contact phase split as a rank-one update of the free flight
(``impactpred.engine.rank_one``).

Checked against the general route (ordered Schur form) and against matrix exponentials:
the same eigenvalues, and the same state at any time, on the exact solver's own phase
matrices (mass on a rod, two free bodies, damped beams, rigid and spring contact).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from data_synth import CantileverBeam, LumpedMass, Rod
from impactpred import Body, LinearSpring, Rigid, solve_impact
from impactpred.engine import spectral as _spectral
from impactpred.engine import impact_run
from impactpred.engine.rank_one import rank_one_split
from impactpred.engine.spectral import SpectralPhase


def _phase_matrices(monkeypatch, bodies, contact):
    """The free and contact phase matrices and the update ``(b, r)`` the solver builds."""
    seen = []
    real = impact_run._phase_form

    def spy(M, update_of=None):
        seen.append((M.copy(), update_of))
        return real(M, update_of)

    monkeypatch.setattr(impact_run, "_phase_form", spy)
    solve_impact(*bodies, contact=contact, t_end=0.5, dt=0.1, method="laplace")
    (M_free, _), (M_con, (_, b, r)) = seen[:2]      # a sequence's sensitivity runs follow
    return M_free, M_con, b, r


def _state(form, x0, tau):
    c0, c1 = form.coordinates(x0)
    x = (form._modes @ (np.exp(form.rates * tau) * c1)).real
    for j, power in enumerate(form.powers):
        x = x + tau ** j * (form.s0 @ power @ c0)
    return x


CASES = {
    "mass on a fixed rod, 50 modes": (
        (Body(LumpedMass(1.0), velocity=1.0),
         Body(Rod(1.0, 1.0, support="fixed").modal_model(50, residual=True))), Rigid()),
    "mass on a rod without flexibility (Dirac)": (
        (Body(LumpedMass(1.0), velocity=1.0),
         Body(Rod(1.0, 1.0, support="fixed").modal_model(12))), Rigid()),
    "two free bodies (common rigid motion)": (
        (Body(LumpedMass(0.3), velocity=1.0),
         Body(Rod(1.0, 0.8, support="free").modal_model(10, residual=True), velocity=-0.5)),
        Rigid()),
    "damped beam, spring contact": (
        (Body(LumpedMass(0.1), velocity=1.0),
         Body(CantileverBeam(1.0, 1.0).modal_model(20, damping_ratio=0.02))),
        LinearSpring(1e6)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_rank_one_route_matches_schur_and_expm(monkeypatch, name):
    bodies, contact = CASES[name]
    M_free, M_con, b, r = _phase_matrices(monkeypatch, bodies, contact)
    assert np.array_equal(M_con, M_free + np.outer(b, r))
    free = SpectralPhase(M_free)
    fast = SpectralPhase(M_con, update_of=(free, b, r))
    general = SpectralPhase(M_con)
    assert fast.route == "rank-one update" and general.route in ("schur", "blocks")
    assert fast.k == general.k and fast.lam.size == general.lam.size
    # the same spectrum: every eigenvalue of one has its match in the other
    gap = np.abs(fast.lam[:, None] - general.lam[None, :]).min(axis=1)
    assert np.all(gap <= 1e-9 * np.maximum(np.abs(fast.lam), 1.0))
    x0 = np.random.default_rng(3).normal(size=M_con.shape[0])
    scale = np.abs(M_con).sum(axis=1).max()
    for tau in (0.0, 0.3 / scale ** 0.5, 0.01, 0.4):
        exact = scipy.linalg.expm(M_con * tau) @ x0
        err = np.max(np.abs(_state(fast, x0, tau) - exact))
        ref = np.max(np.abs(_state(general, x0, tau) - exact))
        assert err <= max(10.0 * ref, 1e-11 * np.max(np.abs(exact)))


@pytest.mark.parametrize("T2, zeta, contact", [
    (1.0, 0.0, Rigid()),                  # equal rods: every free pole twice
    (1.0, 0.02, LinearSpring(1e4)),       # damped equal rods, spring contact
    (0.75, 0.0, Rigid()),                 # one pole shared (4 pi/s: 4th and 3rd modes)
])
def test_repeated_free_poles_are_deflated(monkeypatch, T2, zeta, contact):
    """Two bodies with equal poles: the update keeps one copy of each, split exactly."""
    rods = [Rod(1.0, T, support="free").modal_model(12, residual=True, damping_ratio=zeta)
            for T in (1.0, T2)]
    M_free, M_con, b, r = _phase_matrices(
        monkeypatch, (Body(rods[0], velocity=1.0), Body(rods[1], velocity=-1.0)), contact)
    free = SpectralPhase(M_free)
    fast = SpectralPhase(M_con, update_of=(free, b, r))
    general = SpectralPhase(M_con)
    assert fast.route == "rank-one update"
    assert fast.k == general.k and fast.lam.size == general.lam.size
    x0 = np.random.default_rng(5).normal(size=M_con.shape[0])
    for tau in (0.0, 0.01, 0.3, 1.7):
        exact = scipy.linalg.expm(M_con * tau) @ x0
        err = np.max(np.abs(_state(fast, x0, tau) - exact))
        ref = np.max(np.abs(_state(general, x0, tau) - exact))
        assert err <= max(10.0 * ref, 1e-11 * np.max(np.abs(exact)))


def test_close_but_unequal_poles_fall_back_to_the_general_route(monkeypatch):
    """Poles 1e-10 apart (relative) are neither equal nor safely distinct: Schur route."""
    rod = Rod(1.0, 1.0, support="free").modal_model(6)
    other = rod.replace(poles=rod.poles * (1.0 + 1e-10))
    M_free, M_con, b, r = _phase_matrices(
        monkeypatch, (Body(rod, velocity=1.0), Body(other, velocity=-1.0)), Rigid())
    free = SpectralPhase(M_free)
    assert rank_one_split(M_con, free, b, r, tol=1e-9, max_cond=1e8) is None
    assert SpectralPhase(M_con, update_of=(free, b, r)).route in ("schur", "blocks")


def test_solutions_agree_with_the_general_route(monkeypatch):
    """Whole solves: contact intervals and restitution of both routes, to rounding."""
    bodies = CASES["mass on a fixed rod, 50 modes"][0]
    fast = solve_impact(*bodies, t_end=4.0, method="laplace")
    monkeypatch.setattr(_spectral, "rank_one_split", lambda *args, **kwargs: None)
    slow = solve_impact(*bodies, t_end=4.0, method="laplace")
    assert len(fast.contact_intervals) == len(slow.contact_intervals) > 10
    assert np.allclose(fast.contact_intervals, slow.contact_intervals, rtol=0, atol=1e-10)
    assert fast.restitution == pytest.approx(slow.restitution, rel=1e-10)


def test_update_of_is_checked(monkeypatch):
    bodies, contact = CASES["mass on a rod without flexibility (Dirac)"]
    M_free, M_con, b, r = _phase_matrices(monkeypatch, bodies, contact)
    free = SpectralPhase(M_free)
    with pytest.raises(ValueError, match="outer"):
        SpectralPhase(M_con, update_of=(free, b, 2.0 * r))
    with pytest.raises(ValueError, match="shape"):
        SpectralPhase(M_con, update_of=(free, b[:-1], r))
    with pytest.raises(ValueError, match="non-finite"):
        SpectralPhase(M_con, update_of=(free, np.where(b == b.max(), np.nan, b), r))
    with pytest.raises(TypeError, match="SpectralPhase"):
        SpectralPhase(M_con, update_of=("free", b, r))


@pytest.mark.parametrize("n_modes", [6, 10, 17, 30, 58])
@pytest.mark.parametrize("contact", [Rigid(), LinearSpring(1e5)])
def test_the_rank_one_route_is_taken_on_ordinary_contacts(monkeypatch, n_modes, contact):
    """A lightly damped mass-on-rod contact over several mode counts: the fast route
    applies (its checks pass), not a silent fall back to the Schur route."""
    rod = Rod(1.0, 1.0, support="fixed").modal_model(n_modes, damping_ratio=0.01)
    M_free, M_con, b, r = _phase_matrices(
        monkeypatch, (Body(LumpedMass(0.7), velocity=1.0), Body(rod)), contact)
    fast = SpectralPhase(M_con, update_of=(SpectralPhase(M_free), b, r))
    assert fast.route == "rank-one update"


def test_a_pole_repeated_three_times_keeps_two_copies():
    """Three equal damped oscillators and a free mass, coupled by a random rank-one update."""
    w, z = 7.0, 0.03
    osc = np.array([[0.0, 1.0], [-w * w, -2 * z * w]])
    mass = np.array([[0.0, 1.0], [0.0, 0.0]])
    M_free = scipy.linalg.block_diag(osc, osc, osc, mass)
    rng = np.random.default_rng(11)
    b, r = rng.normal(size=8), rng.normal(size=8)
    M = M_free + np.outer(b, r)
    free = SpectralPhase(M_free)
    fast = SpectralPhase(M, update_of=(free, b, r))
    assert fast.route == "rank-one update"
    assert np.sum(np.abs(fast.lam - free.lam[0]) < 1e-12 * w) >= 2      # two kept copies
    x0 = rng.normal(size=8)
    for tau in (0.0, 0.05, 0.7):
        exact = scipy.linalg.expm(M * tau) @ x0
        assert np.allclose(_state(fast, x0, tau), exact, rtol=0, atol=1e-10 * np.max(
            np.abs(exact)))


def _propagated(form, x0, tau):
    c0, c1 = form.coordinates(x0)
    x = (form._modes @ (np.exp(form.rates * tau) * c1)).real
    if form.k:
        x += sum(form._s0_powers[j] @ c0 * tau**j for j in range(form.k))
    return x


@pytest.mark.parametrize("coupled", [False, True])
def test_slow_modes_beside_a_stiff_term_are_not_taken_for_zeros(coupled):
    """A stiff term (1e10 /s, a stiff contact spring) makes the matrix norm large; slow
    modes (1 and 3 rad/s) far below ``1e-9`` of it are still modes, not a polynomial
    (which is off by orders of magnitude at 10 s; the reference ``expm`` itself loses
    about 1e-7 to the stiff term's squarings)."""
    M = np.zeros((6, 6))
    M[0, 1] = 1.0                                        # a rigid-body pair
    M[2:4, 2:4] = [[0.0, 1.0], [-1.0, -0.01]]            # 1 rad/s
    M[4:6, 4:6] = [[0.0, 1.0], [-9.0, -0.03]]            # 3 rad/s
    big = np.zeros((7, 7))
    big[:6, :6] = M
    big[6, 6] = -1e10
    if coupled:
        big[6, 2] = big[3, 6] = 1e3                     # one block: the Schur route
    form = SpectralPhase(big)
    assert form.k == 2                                   # the rigid body only
    x0 = np.arange(1.0, 8.0)
    for tau in (0.5, 10.0):
        want = scipy.linalg.expm(big * tau) @ x0
        assert _propagated(form, x0, tau) == pytest.approx(want, rel=1e-6, abs=1e-6)
