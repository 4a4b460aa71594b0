"""modalid._unresolved_damping: the rule that takes a damping ratio the lines cannot resolve
off the refinement's bound, against a refit whose cost is known exactly (the fits that use
it are tested in test_modalid_fit.py and test_modalid_global_fit.py)."""

import numpy as np

from modalid._unresolved_damping import BANDWIDTH_SHARES, FLOOR, damping_off_bound
from modalid._verdict import MIN_DAMPING

N_DATA, N_PARAMS = 2000, 20
SIGMA2 = 1.0                                  # cost 1980 over 1980 degrees of freedom
COST = SIGMA2 * (N_DATA - N_PARAMS)
ALLOWED = np.log(N_DATA)                      # 7.6 residual variances


def poles_of(freq_hz, zeta):
    wn = 2 * np.pi * np.asarray(freq_hz, float)
    zeta = np.asarray(zeta, float)
    return wn * (-zeta + 1j * np.sqrt(1 - zeta**2))


def refit_costing(price):
    """A refit whose cost is the start's plus ``price(zeta_k)`` per held pole ``k``, the
    poles returned as given, converged; it records what it was asked."""
    calls = []

    def refit(trial, hold):
        zeta = -trial.real / np.abs(trial)
        calls.append((trial.copy(), hold.copy()))
        cost = COST + sum(price(z) for z in zeta[hold])
        return trial, np.zeros(3), {"cost": cost, "converged": True, "n_iter": 2}

    return refit, calls


def test_the_largest_ratio_that_costs_less_than_its_price_is_taken():
    """A pole at the bound (1e-9) at 100 Hz on 0.5 Hz lines: a bandwidth of a quarter of a
    line costs 20 variances (refused), a fortieth 3 (taken); the other poles untouched."""
    poles = poles_of([100.0, 300.0], [1e-9, 0.01])
    kinds = np.array(["mode", "mode"])
    refit, calls = refit_costing(lambda z: 20.0 if z > 1e-4 else 3.0)
    fit, notes, n_iter = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles, kinds, COST, refit)
    zeta = -fit[0].real / np.abs(fit[0])
    np.testing.assert_allclose(zeta, [BANDWIDTH_SHARES[1] * 0.5 / 200.0, 0.01])
    assert len(calls) == 2 and n_iter == 4 and calls[1][1].tolist() == [True, False]
    assert "(half-power bandwidth 0.025 of a line)" in notes[0]
    assert "cost +3 residual variances" in notes[0]


def test_each_pole_pays_its_own_price_and_none_is_left_below_the_verdicts_bound():
    """Three poles at or below the verdict's bound, each costing 0.6 of the price when
    held: each is taken against the fit before it (together they cost 1.8 prices). A pole
    at 1400 Hz on 0.5 Hz lines (f/df 2800) gets no candidate under FLOOR times the bound
    (a fortieth of a line would be 2.2e-7); one that is not a mode is left alone."""
    poles = poles_of([100.0, 700.0, 1400.0, 1500.0], [1e-9, 4e-7, 1e-9, 1e-9])
    kinds = np.array(["mode", "mode", "mode", "upper"])
    refit, calls = refit_costing(lambda z: 0.6 * ALLOWED)
    fit, notes, _ = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles, kinds, COST, refit)
    zeta = -fit[0].real / np.abs(fit[0])
    assert len(notes) == 3 and len(calls) == 3
    assert np.all(zeta[:3] >= FLOOR * MIN_DAMPING)
    np.testing.assert_allclose(zeta[3], 1e-9)
    np.testing.assert_allclose(zeta[:3], [0.25 * 0.5 / 200, 0.25 * 0.5 / 1400,
                                          0.25 * 0.5 / 2800])
    refit, calls = refit_costing(lambda z: 2 * ALLOWED if z > FLOOR * MIN_DAMPING else 0.5)
    fit, notes, _ = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles_of([1400.0], [1e-9]),
                                      np.array(["mode"]), COST, refit)
    tried = [-t[0].real / abs(t[0]) for t, _ in calls]
    np.testing.assert_allclose(tried, [0.25 * 0.5 / 2800, 0.025 * 0.5 / 2800,
                                       FLOOR * MIN_DAMPING])
    np.testing.assert_allclose(-fit[0][0].real / abs(fit[0][0]), FLOOR * MIN_DAMPING)


def test_a_pole_the_lines_hold_at_the_bound_stays_there_and_a_resolved_one_is_untouched():
    """Every candidate costs more than its price (or its refit did not converge): no fit,
    a note that says the pole stays; a pole above the bound is not looked at."""
    poles = poles_of([100.0, 200.0], [1e-9, 1e-4])
    kinds = np.array(["mode", "mode"])
    refit, calls = refit_costing(lambda z: 2 * ALLOWED)
    fit, notes, n_iter = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles, kinds, COST, refit)
    assert fit is None and len(calls) == len(BANDWIDTH_SHARES) and n_iter == 6
    assert notes == ["mode at 100 Hz: its damping ratio stays at 1e-09: the lines prefer it "
                     "to a half-power bandwidth of 0.0025 of a line"]

    def unconverged(trial, hold):
        return trial, np.zeros(3), {"cost": COST, "converged": False, "n_iter": 50}

    fit, _, n_iter = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles, kinds, COST, unconverged)
    assert fit is None and n_iter == 150
    fit, notes, n_iter = damping_off_bound(N_DATA, N_PARAMS, 0.5, poles_of([200.0], [1e-4]),
                                           np.array(["mode"]), COST, unconverged)
    assert fit is None and notes == [] and n_iter == 0
