"""The convolution solver (exact continua, samples) against exact answers."""

import warnings

import numpy as np
import pytest

from data_synth import CantileverBeam, LumpedMass, Rod, SpringMass
from data_synth.reference_impacts import mass_on_fixed_rod, two_free_rods_equal_transit
from impactpred import (Body, HarmonicForce, Hertz, LinearSpring, Rigid, SampledResponse,
                        choose_dt, solve_impact)
from impactpred._time_scales import CROSSOVER_STEPS, rigid_crossover
from impactpred.solvers._step_force import StepForce, kernel_ratio
from impactpred.solvers.convolution import online_complementarity
from impactpred.solvers.modal import solve_modal


def test_case_a_two_equal_rods_to_rounding():
    m1, m2, T = 1.0, 2.5, 1.0
    r = solve_impact(Body(Rod(m1, T, support="free"), velocity=1.0),
                     Body(Rod(m2, T, support="free"), velocity=-0.5), t_end=6.0,
                     method="convolution")
    exact = two_free_rods_equal_transit(m1, m2, T, 1.0, -0.5, r.t)
    assert r.contact_intervals == ((0.0, pytest.approx(2.0, abs=1e-12)),)
    assert r.peak_force == pytest.approx(exact.force_height, rel=1e-11)
    np.testing.assert_allclose(r.force[:-1][r.t[:-1] < 2.0], exact.force_height, rtol=1e-10)
    np.testing.assert_allclose(r.y1, exact.y1, atol=1e-11)
    np.testing.assert_allclose(r.y2, exact.y2, atol=1e-11)
    assert r.restitution == pytest.approx(1.0, abs=1e-11)
    assert r.energy["vibration_after"].abs().max() < 1e-11


def test_closed_form_matches_reference():
    r = solve_impact(Body(Rod(1.0, 1.0, support="free"), velocity=1.0),
                     Body(Rod(1.0, 1.0, support="free"), velocity=-1.0), t_end=8.0)
    assert r.method == "closed_form"
    exact = two_free_rods_equal_transit(1.0, 1.0, 1.0, 1.0, -1.0, r.t)
    np.testing.assert_allclose(r.y1, exact.y1, atol=1e-14)
    np.testing.assert_allclose(r.y2, exact.y2, atol=1e-14)
    assert r.contact_duration == 2.0 and r.restitution == 1.0


@pytest.mark.parametrize("mass_ratio", [0.5, 1.0, 4.0])
def test_mass_on_fixed_rod_against_saint_venant(mass_ratio):
    """Whole history, every contact, against the method-of-characteristics solution."""
    M, m, T, v0 = mass_ratio, 1.0, 1.0, 1.0
    dt = T / 1000
    r = solve_impact(Body(LumpedMass(M), velocity=v0), Body(Rod(m, T, support="fixed")),
                     t_end=8.0, dt=dt)
    assert r.method == "convolution"
    exact = mass_on_fixed_rod(M, m, T, v0, r.t[:-1] + 0.5 * dt)
    assert r.n_contacts == len(exact.contact_intervals)
    for (a, b), (ea, eb) in zip(r.contact_intervals, exact.contact_intervals):
        assert a == pytest.approx(ea, abs=2 * dt) and b == pytest.approx(eb, abs=2 * dt)
    assert r.restitution == pytest.approx(exact.restitution, abs=2e-4)
    # the step force approximates the mean force over the step: compare away from jumps
    jumps = np.array(list(exact.force_jump_times) + [x for iv in exact.contact_intervals
                                                      for x in iv])
    far = np.min(np.abs((r.t[:-1, None] + 0.5 * dt) - jumps[None, :]), axis=1) > 3 * dt
    assert np.max(np.abs(r.force[:-1] - exact.force)[far]) < 2e-3 * np.max(exact.force)
    # energy: the rod's vibration energy is the exact one; a re-contact starting inside a
    # step dissipates O(dt) there (the scheme never creates energy)
    assert r.energy.loc["body2", "vibration_after"] == pytest.approx(
        exact.rod_energy_after, rel=5e-3)
    total = r.energy["total_after"].sum()
    assert total <= 0.5 * M * v0**2 * (1 + 1e-12)
    if len(exact.contact_intervals) == 1:  # every contact starts on the grid: exact balance
        assert total == pytest.approx(0.5 * M * v0**2, rel=1e-10)


@pytest.mark.parametrize("mass, t_end", [(5e-3, 2e-3), (1e-4, 5e-4)])
def test_light_mass_on_a_fixed_rod_gets_a_step_that_resolves_its_contact(mass, t_end):
    """A 5 g pellet at 3 m/s on a 1 m steel rod (7.85 kg, transit 0.196 ms), no step given:
    the force Z v0 exp(-Z t / M) changes regime at 2 M / Z = 0.25 us, shorter than the
    rod's 1000 steps per transit (0.2 us). Stepped at those, the restitution came out
    0.985 for the exact 0.7358, with no warning (and 1e-4 kg: 0.667 in one step; its
    contact, until the wave's return at 2 T, within a t_end of 4e6 such steps)."""
    rod = Rod(7.85, 1.96e-4, support="fixed")
    bodies = [Body(LumpedMass(mass), velocity=3.0), Body(rod)]
    impedance = 7.85 / 1.96e-4
    assert rigid_crossover(bodies, 1.96e-4) == pytest.approx(2 * mass / impedance, rel=1e-6)
    assert choose_dt(bodies, Rigid(), t_end=t_end) <= 2 * mass / impedance / CROSSOVER_STEPS
    r = solve_impact(*bodies, t_end=t_end)
    exact = mass_on_fixed_rod(mass, 7.85, 1.96e-4, 3.0, [0.0])
    assert r.method == "convolution"
    assert r.restitution == pytest.approx(exact.restitution, rel=2e-3)
    # (the 0.1 g mass's force, Z v0 exp(-Z t / M), is below rounding from 4 us until the
    # wave returns at 2 T: two contacts where the exact has one, ending as it does)
    assert r.contact_intervals[-1][1] == pytest.approx(exact.separation_time, rel=1e-3)
    # two bodies of one regime do not cross (rod on rod, t / Z each), nor where the mass's
    # crossover lies above the rod's own time scale (a heavy mass, 2 M / Z = 5e-4 s: the
    # transit decides)
    assert rigid_crossover([Body(Rod(1.0, 1e-3, support="free"), velocity=1.0),
                            Body(Rod(2.0, 1e-3, support="fixed"))], 1e-3) is None
    assert rigid_crossover([Body(LumpedMass(10.0), velocity=1.0), Body(rod)], 1.96e-4) is None
    # nor a mass on a beam (slope 1.5 against 2: rounding had decided, at a threshold of
    # 0.5, and 10 g was found where 1 g and 100 g were not)
    beam = CantileverBeam(4.76, 2.65)
    for m in (1e-3, 1e-2, 1e-1):
        assert rigid_crossover([Body(LumpedMass(m), velocity=1.0), Body(beam)],
                               beam.time_scales()[0].seconds) is None


def test_heavy_mass_has_no_false_separation_at_4T():
    """method.md section 5: the force stays positive just before 4T and jumps up there."""
    r = solve_impact(Body(LumpedMass(2.0), velocity=1.0), Body(Rod(1.0, 1.0, support="fixed")),
                     t_end=6.0, dt=1.0 / 700)
    exact = mass_on_fixed_rod(2.0, 1.0, 1.0, 1.0, [0.0])
    assert r.contact_intervals[0][1] == pytest.approx(exact.separation_time, abs=2.0 / 700)


def test_observed_order_of_convergence_in_dt():
    exact = mass_on_fixed_rod(1.0, 1.0, 1.0, 1.0, [0.0])
    errors = []
    steps = [1 / 101, 1 / 202, 1 / 404]  # not aligned with the reflections
    for dt in steps:
        r = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(Rod(1.0, 1.0, support="fixed")),
                         t_end=3.5, dt=dt)
        errors.append(abs(r.restitution_first - exact.restitution_first_contact))
    order = np.log2(errors[0] / errors[1]), np.log2(errors[1] / errors[2])
    assert min(order) > 0.8  # first order (the force is piecewise constant)


def test_online_convolution_equals_direct_history_sum():
    rng = np.random.default_rng(7)
    n = 700
    kernel = np.abs(rng.normal(size=n)) * np.exp(-np.arange(n) / 200) + 0.1
    free_gap = np.cumsum(rng.normal(size=n)) * 0.3 - 1.0
    for k1 in (kernel[1], 3 * kernel[0]):       # as drawn; a pair of masses (StepForce)
        kernel[1] = k1
        force = online_complementarity(kernel, free_gap, Rigid(), 1e-3, 0.0)
        rule = StepForce(Rigid(), kernel[0], kernel[1], 1e-3)
        assert rule.plastic == (k1 > 2.5 * kernel[0])
        direct, g_prev = np.zeros(n), 0.0
        g_before = 3 * g_prev - 3 * free_gap[0] + free_gap[1]
        for k in range(n):
            g_free = free_gap[k] + (np.dot(direct[:k], kernel[k:0:-1]) if k else 0.0)
            direct[k] = rule.force(g_free, g_prev, g_before)
            g_before, g_prev = g_prev, g_free + kernel[0] * direct[k]
        np.testing.assert_allclose(force, direct, rtol=1e-10, atol=1e-12)


def test_sampled_response_reproduces_the_exact_model():
    rod = Rod(1.0, 1.0, support="fixed")
    t = np.linspace(0.0, 10.0, 20001)
    sampled = SampledResponse(t, rod.impulse_response(t))
    exact = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(rod), t_end=8.0, dt=1e-3)
    meas = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(sampled), t_end=8.0, dt=1e-3)
    assert meas.restitution == pytest.approx(exact.restitution, abs=2e-3)
    assert meas.contact_duration == pytest.approx(exact.contact_duration, abs=3e-3)
    with pytest.raises(ValueError, match="covers 0 to 10"):
        solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(sampled), t_end=12.0, dt=1e-3)


def test_hertz_between_masses_matches_the_classical_solution():
    from scipy.integrate import quad

    m1, m2, k, v = 1.0, 3.0, 1e7, 1.5
    mu = m1 * m2 / (m1 + m2)
    r = solve_impact(Body(LumpedMass(m1), velocity=v), Body(LumpedMass(m2)),
                     contact=Hertz(k), t_end=1e-2)
    assert r.method == "modal"
    depth = (5 * mu * v**2 / (4 * k)) ** 0.4
    duration = 2 * depth / v * quad(lambda x: 1 / np.sqrt(1 - x**2.5), 0, 1)[0]
    assert r.contact_duration == pytest.approx(duration, rel=2e-3)
    assert r.peak_force == pytest.approx(k * depth**1.5, rel=2e-3)
    assert r.restitution == pytest.approx(1.0, abs=5e-3)


def test_linear_spring_solvers_agree():
    body1 = Body(LumpedMass(1.0), velocity=1.0)
    body2 = Body(Rod(1.0, 1.0, support="fixed").modal_model(20, residual=True))
    exact = solve_impact(body1, body2, contact=LinearSpring(50.0), t_end=6.0, method="laplace")
    # the zero-order hold (the convolution solver's discretisation): equal to rounding
    modal = solve_modal((body1, body2), 0.0, LinearSpring(50.0), 6.0, 1e-4, hold="constant")
    conv = solve_impact(body1, body2, contact=LinearSpring(50.0), t_end=6.0,
                        method="convolution", dt=1e-4)
    assert modal.restitution == pytest.approx(exact.restitution, abs=1e-3)
    assert conv.restitution == pytest.approx(modal.restitution, abs=1e-9)
    np.testing.assert_allclose(conv.force, modal.force, atol=1e-9)


@pytest.mark.parametrize("method", ["convolution", "modal"])
def test_progress_draws_a_bar_over_the_steps_and_changes_nothing(method, capsys):
    """A Hertz contact on an exact fixed rod ran a million Python steps (17 s at t_end =
    0.2 s) without a word; ``progress=True`` draws a bar over the steps on stderr."""
    body1 = Body(LumpedMass(1.0), velocity=1.0)
    body2 = Body(Rod(1.0, 1.0, support="fixed") if method == "convolution"
                 else Rod(1.0, 1.0, support="fixed").modal_model(10, residual=True))
    if method == "convolution":
        def solve(**extra):
            return solve_impact(body1, body2, contact=Hertz(1e5), t_end=1.0, dt=2e-4,
                                method=method, **extra)
    else:           # the zero-order hold's Python loop (the first-order hold's is compiled)
        def solve(**extra):
            return solve_modal((body1, body2), 0.0, Hertz(1e5), 1.0, 2e-4, hold="constant",
                               **extra)
    quiet = solve()
    assert capsys.readouterr().err == ""
    shown = solve(progress=True)
    err = capsys.readouterr().err
    assert f"{method}: 100%" in err and "5000/5000" in err, err
    np.testing.assert_array_equal(shown.force, quiet.force)
    with pytest.raises(TypeError, match="progress must be True, False or 'auto', got 'yes'"):
        solve_impact(body1, body2, progress="yes", t_end=1.0)


def test_auto_progress_appears_only_on_a_long_run(capsys, monkeypatch):
    """``progress="auto"`` (solve_impact's default): no bar on a run shorter than
    :data:`impactpred.parallel.AUTO_PROGRESS_DELAY`; the bar where the run outlasts it
    (the delay set to 0 here)."""
    import impactpred.parallel as parallel

    body1 = Body(LumpedMass(1.0), velocity=1.0)
    body2 = Body(Rod(1.0, 1.0, support="fixed"))

    def solve():
        return solve_impact(body1, body2, contact=Hertz(1e5), t_end=1.0, dt=2e-4,
                            method="convolution")
    quiet = solve()
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(parallel, "AUTO_PROGRESS_DELAY", 0.0)
    shown = solve()
    assert "convolution: 100%" in capsys.readouterr().err
    np.testing.assert_array_equal(shown.force, quiet.force)


def test_dashpot_never_pulls():
    r = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(LumpedMass(1.0)),
                     contact=LinearSpring(1e4, damping=40.0), t_end=0.1)
    assert np.all(r.force >= 0)
    assert 0.0 < r.restitution < 1.0


def test_rod_on_cantilever_conserves_energy():
    r = solve_impact(Body(Rod(1.0, 1.0, support="free"), velocity=1.0),
                     Body(CantileverBeam(10.0, 4.0)), t_end=8.0, dt=2e-3)
    assert r.contact_intervals[0] == pytest.approx((0.0, 2.0), abs=4e-3)
    assert r.energy["total_after"].sum() == pytest.approx(0.5, rel=1e-8)
    assert 0.0 < r.restitution < 1.0


# Rigid contact between bodies that are masses at the contact (h1(0+) + h2(0+) = 0): the
# exact force starts with a plastic Dirac impulse. The law's f = -G/K0 gave these pairs a
# rebound instead (a mass on a spring-mass: e 0.92 for the exact 0.5; a mass on a 5-mode
# rod: 18-57 contacts for the exact 1-2), the plastic start of StepForce gives the exact
# figures to first order in dt.
@pytest.mark.parametrize("method", ["modal", "convolution"])
def test_a_mass_on_a_spring_mass_sticks_as_the_exact_solution_does(method):
    # equal masses: a plastic impact to v/2 each, then stuck for half a period of the
    # pair on the spring, parted at -v/2 (e = 1/2); the contact starts inside a step
    m, k, v, gap = 1.0, (2 * np.pi * 10) ** 2, 1.0, 1.234e-3
    duration = np.pi / np.sqrt(k / (2 * m))
    bodies = (Body(LumpedMass(m), velocity=v), Body(SpringMass(m, k)))
    exact = solve_impact(*bodies, gap=gap, t_end=0.2, method="laplace")
    assert exact.restitution == pytest.approx(0.5, rel=1e-12)
    for dt in (1e-4, 2.5e-5):
        r = solve_impact(*bodies, gap=gap, t_end=0.2, dt=dt, method=method)
        (start, end), = r.contact_intervals
        assert abs(start - gap / v) <= dt and abs(end - start - duration) <= 2 * dt
        assert r.restitution == pytest.approx(0.5, abs=1e-5)
        audit = r.energy_audit
        assert audit.after == pytest.approx(0.25 * m * v**2, rel=1e-5)   # half lost at once


@pytest.mark.parametrize("method", ["modal", "convolution"])
def test_two_free_masses_meet_plastically_and_stay_apart_from_rounding(method):
    m1, m2, v1, v2 = 1.0, 2.0, 1.0, -0.2
    common = (m1 * v1 + m2 * v2) / (m1 + m2)
    r = solve_impact(Body(LumpedMass(m1), velocity=v1), Body(LumpedMass(m2), velocity=v2),
                     gap=1e-3, t_end=0.05, dt=2.5e-5, method=method)
    assert len(r.contact_intervals) == 1          # no contact made of rounding afterwards
    (start, end), = r.contact_intervals           # a pure Dirac, as the exact solver's
    (time, impulse), = r.dirac_impulses
    assert start == end == time and abs(time - 1e-3 / (v1 - v2)) <= 2.5e-5
    assert impulse == pytest.approx(m1 * (v1 - common), rel=1e-12) and r.peak_force == 0.0
    np.testing.assert_allclose(r.velocities_after, [common, common], rtol=1e-12)
    assert r.energy_audit.after == pytest.approx(0.5 * (m1 + m2) * common**2, rel=1e-12)


@pytest.mark.parametrize("mass", [0.5, 2.0])
def test_a_mass_on_a_truncated_rod_matches_the_exact_solver(mass):
    model = Rod(1.0, 1.0, support="fixed").modal_model(5)
    bodies = (Body(LumpedMass(mass), velocity=1.0), Body(model))
    exact = solve_impact(*bodies, t_end=8.0, method="laplace")
    for method in ("modal", "convolution"):
        r = solve_impact(*bodies, t_end=8.0, dt=2e-3, method=method)
        assert len(r.contact_intervals) == len(exact.contact_intervals)
        # within three steps: a contact starts inside the bodies by up to half a step's
        # travel, and after a separation they touch again at a gap of 0
        np.testing.assert_allclose(r.contact_intervals, exact.contact_intervals, atol=6e-3)
        assert r.restitution == pytest.approx(exact.restitution, abs=1e-3)


@pytest.mark.parametrize("method", ["modal", "convolution"])
def test_a_plastic_start_is_a_dirac_impulse_not_a_force_of_impulse_over_dt(method):
    # a unit mass on a 5-mode fixed rod: the exact force is a Dirac at each contact's start
    # and a regular press after it. The start step's impulse is listed as a Dirac; the
    # force keeps the press (1481 N exact), which had been impulse/dt: 9105 N at 1e-5 s,
    # 90 910 N at 1e-6 s
    bodies = (Body(LumpedMass(1.0), velocity=1.0),
              Body(Rod(1.0, 1e-3, support="fixed").modal_model(5)))
    exact = solve_impact(*bodies, t_end=0.01, method="laplace")
    assert len(exact.dirac_impulses) == 2
    for dt, rtol in ((1e-5, 0.02), (1e-6, 0.002)):
        r = solve_impact(*bodies, t_end=0.01, dt=dt, method=method)
        assert r.peak_force == pytest.approx(exact.peak_force, rel=rtol)
        assert r.peak_force_max == pytest.approx(exact.peak_force_max, rel=rtol)
        assert len(r.dirac_impulses) == len(exact.dirac_impulses)
        for (t, j), (t_exact, j_exact) in zip(r.dirac_impulses, exact.dirac_impulses):
            assert abs(t - t_exact) <= dt and j == pytest.approx(j_exact, rel=rtol)
        # the split keeps the force's integral: the momentum passed is the same
        diracs = sum(j for _, j in r.dirac_impulses)
        assert np.sum(r.force[:-1]) * dt + diracs == pytest.approx(r.impulse, rel=1e-12)
        # the start step keeps the press that follows it (the contact holds)
        start = int(round(r.dirac_impulses[0][0] / dt))
        assert r.force[start] == r.force[start + 1] > 0.0


@pytest.mark.parametrize("method", ["modal", "convolution"])
def test_a_plastic_start_on_the_last_step_is_still_in_contact_at_the_end(method):
    # a 1 kg mass meets a spring-mass at 0.00995 s, within the last step of t_end 0.01:
    # the exact solver has the bodies pressed together at t_end (no restitution); the
    # start is a Dirac, and the contact is not shrunk to a point (it goes on)
    bodies = (Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(1.0, 1e4)))
    with pytest.warns(UserWarning, match="still closed at t_end"):
        exact = solve_impact(*bodies, gap=0.00995, t_end=0.01, method="laplace")
        r = solve_impact(*bodies, gap=0.00995, t_end=0.01, dt=1e-4, method=method)
    assert exact.in_contact_at_end and r.in_contact_at_end and r.restitution is None
    (t, j), = r.dirac_impulses
    assert t == pytest.approx(0.0099) and j == pytest.approx(exact.dirac_impulses[0][1],
                                                              rel=1e-4)


def test_a_step_too_fine_to_resolve_a_plastic_hold_says_so():
    # a mass pressed by a 1e3 N/m spring-mass: at the automatic step one contact and no
    # warning; over 10^5 steps of 0.2 us a step's gap change at the contact force is
    # below the gaps' rounding, and the holds part and touch again on it
    bodies = (Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(0.5, 1e3)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        r = solve_impact(*bodies, gap=1e-4, t_end=0.02, method="convolution")
    assert len(r.contact_intervals) == 1
    with pytest.warns(RuntimeWarning, match="too fine for a rigid contact between masses"):
        r = solve_impact(*bodies, gap=1e-4, t_end=0.02, dt=2e-7, method="convolution")
    assert any("too fine" in note for note in r.notes)


def test_many_plastic_contacts_neither_drift_nor_split():
    """A forced spring-mass rattling against another: 65 contacts in 5 s (exact). The gap
    each contact holds is off by less than half a step's travel; it must not carry from
    contact to contact (it had random-walked to 30 mm in 20 s, the clearance 1 mm), and
    the held force's step-to-step alternation must not part the bodies for a step (86
    contacts had been counted)."""
    k = (2 * np.pi * 10) ** 2
    bodies = (Body(SpringMass(1.0, k), load=HarmonicForce(60.0, 13.0)),
              Body(SpringMass(0.5, 2 * k)))
    exact = solve_impact(*bodies, gap=1e-3, t_end=5.0, method="laplace")
    r = solve_impact(*bodies, gap=1e-3, t_end=5.0, method="convolution")
    assert len(r.contact_intervals) == len(exact.contact_intervals) == 65
    assert r.total_impulse == pytest.approx(exact.total_impulse, rel=2e-3)
    assert np.max(np.abs(r.gap[:-1][r.force[:-1] > 0])) < 1e-3


def test_a_flexibility_seen_as_a_mass_by_a_coarse_step_keeps_the_laws_rule():
    """A light mass on a beam with its residual flexibility: no Dirac part in the exact
    force. At dt = 5 ms the step's kernel looks like a mass's (ratio above 2.5), the
    small-time one does not (about 0): the law's rule, not the plastic start (which had
    taken 78 % of the energy, e 0.021 for the exact 0.668)."""
    bodies = (Body(LumpedMass(0.01), velocity=1.0),
              Body(CantileverBeam(1.0, 1.0).modal_model(5, residual=True)))
    ratio, small_time = kernel_ratio([b.step_response for b in bodies], 5e-3)
    assert ratio > 2.5 and small_time < 0.5
    assert not StepForce(Rigid(), 1.0, ratio, 5e-3, small_time_ratio=small_time).plastic
    r = solve_impact(*bodies, t_end=2.0, method="convolution", dt=5e-3)
    assert r.restitution > 0.5


def test_a_step_as_long_as_a_rods_period_is_named_as_such():
    """A fixed rod's step response returns to 0 after four transit times: with that step
    the first increment is 0 and the refusal said only "not a driving point"."""
    from data_synth import LumpedMass, Rod
    from impactpred import Body, solve_impact

    with pytest.raises(ValueError, match=r"over the first step \(dt = 4 s\) is 0.0 m/N, "
                                         "not positive: not a driving point, or a step far "
                                         "too long"):
        solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(Rod(1.0, 1.0, support="fixed")),
                     t_end=8.0, dt=4.0, method="convolution")

