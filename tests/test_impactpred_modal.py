"""The modal solver's first-order hold (the default) against exact answers."""

import math

import numpy as np
import pytest

from data_synth import CantileverBeam, LumpedMass, Rod, SpringMass
from impactpred import Body, Hertz, LinearSpring, Rigid, solve_impact
from impactpred.solvers.modal import solve_modal
from modalid import ModalModel, MultiOutputModalModel


def _errors(res, exact):
    assert res.n_contacts == exact.n_contacts
    ends = np.abs(np.array(res.contact_intervals) - np.array(exact.contact_intervals))
    return abs(res.restitution - exact.restitution), float(np.max(ends))


def test_mass_on_truncated_rod_converges_at_second_order_to_the_exact_solution():
    """The benchmark's case, smaller: rigid contact on a 10-mode rod with its residual."""
    striker = Body(LumpedMass(1.0), velocity=1.0)
    rod = Body(Rod(1.0, 1.0, support="fixed").modal_model(10, residual=True))
    exact = solve_impact(striker, rod, t_end=3.0, method="laplace")
    assert exact.n_contacts > 3          # the truncated model chatters
    errors = []
    for n in (1000, 2000):
        res = solve_impact(striker, rod, t_end=3.0, method="modal", dt=1.0 / n)
        assert any("first-order hold" in note for note in res.notes)
        errors.append(_errors(res, exact))
    (de0, ep0), (de1, ep1) = errors
    assert de1 < 0.3 * de0 and ep1 < 0.3 * ep0        # order ~2 (ratio 1/4)
    assert de1 < 2e-5 and ep1 < 2e-5
    # momentum to rounding
    m = (1.0, None)
    assert res.velocities_after[0] == pytest.approx(1.0 - res.total_impulse * m[0], abs=1e-14)


def test_constant_load_and_spring_contact_against_the_closed_form():
    """Mass with a constant load closing a gap onto a mass, linear spring contact.

    Free approach: ``g(t) = g0 - v0 t - F t^2/(2 m1)``, exact under the (linear) held load,
    so the contact start is exact to rounding. In contact the penetration obeys
    ``d'' = F/m1 - (k/mu) d``: ``d = d_s (1 - cos wt) + (v/w) sin wt`` ends at
    ``w t = 2 (pi - atan(v/(w d_s)))``.
    """
    m1, m2, k, F, v0, g0 = 1.0, 2.0, 1e4, 3.0, 0.5, 2e-3
    mu = m1 * m2 / (m1 + m2)
    w = math.sqrt(k / mu)
    t_c = (-v0 + math.sqrt(v0**2 + 2 * F / m1 * g0)) / (F / m1)
    v = v0 + F / m1 * t_c
    d_s = F * mu / (m1 * k)
    t_e = t_c + 2 * (math.pi - math.atan(v / (w * d_s))) / w
    body1 = Body(LumpedMass(m1), velocity=v0, load=lambda t: F * np.ones_like(t))
    body2 = Body(LumpedMass(m2))
    errs = []
    for dt in (4e-4, 2e-4):
        res = solve_impact(body1, body2, gap=g0, contact=LinearSpring(k), t_end=0.04,
                           method="modal", dt=dt)
        start, end = res.contact_intervals[0]
        assert start == pytest.approx(t_c, abs=1e-13)
        errs.append(abs(end - t_e))
        # the work on rigid bodies is their kinetic-energy change: exact integration
        for energy in res.energy_by_body:
            assert abs(energy.vibration_after) < 1e-12
    assert errs[1] < 0.3 * errs[0] and errs[1] < 1e-6


def test_energy_left_in_a_struck_spring_mass_is_the_exact_one_of_the_stepped_motion():
    """The work is integrated exactly: the grounded oscillator's energy from the balance
    equals ``k X^2/2`` of its free oscillation after the contact, to rounding."""
    m2, k2 = 2.0, 400.0
    res = solve_impact(Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(m2, k2)),
                       contact=LinearSpring(2e4), t_end=0.3, method="modal", dt=2e-4)
    assert res.n_contacts == 1 and res.contact_intervals[0][1] < 0.2
    omega = math.sqrt(k2 / m2)
    i, j = np.searchsorted(res.t, 0.22), np.searchsorted(res.t, 0.25)
    ya, yb, c = res.y2[i], res.y2[j], math.cos(omega * (res.t[j] - res.t[i]))
    amplitude2 = (ya**2 + yb**2 - 2 * ya * yb * c) / (1 - c**2)
    stored = res.energy.loc["body2", "vibration_after"]
    assert stored == pytest.approx(0.5 * k2 * amplitude2, rel=1e-10)


def test_hertz_between_masses_converges_to_the_classical_duration():
    from scipy.integrate import quad

    m1, m2, k, v = 1.0, 3.0, 1e7, 1.5
    mu = m1 * m2 / (m1 + m2)
    depth = (5 * mu * v**2 / (4 * k)) ** 0.4
    duration = 2 * depth / v * quad(lambda x: 1 / np.sqrt(1 - x**2.5), 0, 1)[0]
    errors = []
    for n in (100, 200):
        r = solve_impact(Body(LumpedMass(m1), velocity=v), Body(LumpedMass(m2)),
                         contact=Hertz(k), t_end=1.2 * duration, dt=duration / n,
                         method="modal")
        errors.append((abs(r.contact_duration - duration), abs(r.restitution - 1.0)))
    assert errors[1][0] < 0.4 * errors[0][0] and errors[1][0] < 2e-5 * duration
    assert errors[1][1] < 1e-6


def test_zero_order_hold_where_the_first_order_hold_does_not_apply():
    # rigid contact without flexibility: the first-order hold would oscillate
    bodies = (Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(1.0, 100.0)))
    with pytest.raises(ValueError, match="force would oscillate"):
        solve_modal(bodies, 0.0, Rigid(), 0.5, 1e-3, hold="linear")
    res = solve_modal(bodies, 0.0, Rigid(), 0.5, 1e-3)
    assert any("zero-order hold" in note for note in res.notes)
    same = solve_modal(bodies, 0.0, Rigid(), 0.5, 1e-3, hold="constant")
    np.testing.assert_array_equal(res.force, same.force)
    # output points stay on the zero-order hold
    multi = MultiOutputModalModel(poles=[-0.3 + 40j], residues=[[-0.05j], [0.02j]],
                                  inverse_mass=[0.5, 0.5], flexibility=[2e-4, 0.0],
                                  outputs=["drv", "b"], driving_point=0)
    res = solve_modal((bodies[0], Body(multi)), 0.0, LinearSpring(1e3), 0.2, 1e-3)
    assert any("output points" in note for note in res.notes)
    assert res.points[1] is not None
    with pytest.raises(ValueError, match="hold"):
        solve_modal(bodies, 0.0, Rigid(), 0.5, 1e-3, hold="quadratic")


def test_a_dashpot_like_model_takes_the_zero_order_hold():
    """A mass on a mode and a fast real pole without flexibility: the model's mobility has
    an instantaneous part (a dashpot at the contact), the first-order hold's force ratio is
    0.997 and its force alternated 0, 16 700, 200, 16 800 N about the true 8 400 N: five
    contacts instead of one and a work on the body 13 % above the energy the mass lost, at
    every dt (the energy audit flagged it, "refine dt" did nothing). The zero-order hold
    agrees with the convolution solver and its books close."""
    model = ModalModel(poles=[-1 + 600j], residues=[-1e-3j], real_poles=[-1e6],
                       real_residues=[2.4e-4])
    bodies = (Body(LumpedMass(0.05), velocity=2.0), Body(model))
    res = solve_impact(*bodies, t_end=1e-4, method="modal", dt=1e-8)
    assert any("zero-order hold" in note and "oscillate" in note for note in res.notes)
    ref = solve_impact(*bodies, t_end=1e-4, method="convolution", dt=1e-8)
    assert res.n_contacts == ref.n_contacts == 1
    assert res.impulse == pytest.approx(ref.impulse, rel=1e-9)
    lost = bodies[0].velocity ** 2 * 0.05 / 2 - res.energy_by_body[0].rigid_after
    assert res.energy_by_body[1].vibration_after == pytest.approx(lost, rel=1e-9)
    assert res.energy_audit.ok
    with pytest.raises(ValueError, match="force would oscillate"):
        solve_modal(bodies, 0.0, Rigid(), 1e-4, 1e-8, hold="linear")


def test_first_order_hold_with_damped_modes_and_real_poles_against_the_exact_solver():
    model = ModalModel(poles=[-0.2 + 6j], residues=[-0.08j], real_poles=[-5.0],
                       real_residues=[0.01], inverse_mass=0.5)
    body1, body2 = Body(LumpedMass(1.0), velocity=1.0), Body(model)
    exact = solve_impact(body1, body2, contact=LinearSpring(100.0), t_end=2.0,
                         method="laplace")
    errors = [_errors(solve_impact(body1, body2, contact=LinearSpring(100.0), t_end=2.0,
                                   method="modal", dt=dt), exact) for dt in (4e-3, 2e-3)]
    assert errors[1][0] < 0.3 * errors[0][0] and errors[1][1] < 0.3 * errors[0][1]


def test_spring_dashpot_between_masses_against_the_kelvin_voigt_closed_form():
    """Two masses, contact f = k d + c d' (d the overlap): during contact the overlap is a
    damped oscillator from d = 0, d' = v0; the contact ends where f turns to 0 (the
    dashpot pulls before the spring is relaxed), at tan(wd t) = -2 zeta sqrt(1-zeta^2) /
    (1 - 2 zeta^2) in (pi/2, pi) / wd; e = -d'(t_end)/v0."""
    m1, m2, k, c, v0 = 1.0, 3.0, 4.0e4, 60.0, 1.5
    mr = m1 * m2 / (m1 + m2)
    wn = math.sqrt(k / mr)
    zeta = c / (2 * math.sqrt(k * mr))
    wd = wn * math.sqrt(1 - zeta**2)
    t_end = (math.pi - math.atan(2 * zeta * math.sqrt(1 - zeta**2) / (1 - 2 * zeta**2))) / wd
    d_rate = v0 * math.exp(-zeta * wn * t_end) * (
        math.cos(wd * t_end) - zeta * wn / wd * math.sin(wd * t_end))
    e_exact = -d_rate / v0
    bodies = (Body(LumpedMass(m1), velocity=v0), Body(LumpedMass(m2)))
    errors = []
    for n in (400, 800):
        dt = t_end / n
        res = solve_impact(*bodies, contact=LinearSpring(k, damping=c), t_end=3 * t_end,
                           method="modal", dt=dt)
        assert any("first-order hold" in note for note in res.notes)
        assert res.n_contacts == 1
        (start, end), = res.contact_intervals
        errors.append((abs(end - start - t_end), abs(res.restitution - e_exact)))
        # momentum to rounding
        p_after = m1 * res.velocities_after[0] + m2 * res.velocities_after[1]
        assert p_after == pytest.approx(m1 * v0, rel=1e-13)
    (dt0, de0), (dt1, de1) = errors
    # the dashpot's force jump at contact start is spread over a step: first order there
    assert dt1 < 0.6 * dt0 and de1 < 0.6 * de0
    assert dt1 < 2e-3 * t_end and de1 < 2e-3


@pytest.mark.parametrize("c, t_end", [(1e3, 0.02), (1e6, 2e-4)])
def test_an_overdamped_dashpot_ends_and_dissipates_as_the_closed_form(c, t_end):
    """Two 1 kg masses at 1 m/s through ``f = k d + c d'`` (``k = 1e4`` N/m, reduced mass
    0.5 kg), overdamped: ``d = v (e^{r1 t} - e^{r2 t}) / (r1 - r2)``, the force vanishes
    at ``t_s = 2 ln(r1/r2) / (r2 - r1)``, ``e = (r1/r2) e^{r1 t_s}``, and the contact took
    all the relative kinetic energy but ``e^2`` of it (dashpot, and the spring energy left
    at ``t_s``, released as the overlap relaxes or stored at ``t_end``). The audit's
    ``dissipated`` had been 4.6 % (c = 1e3) and 9.4 % (1e6) short (the grid's secant rates,
    the start's force jump left out), and at c = 1e6 the force, below 1e-13 of its peak
    after 1.5e-5 s, had crept at its rounding's drift to 3.9e-5 s: twice ``t_s``. The
    contact now ends where the force falls to its rounding
    (:func:`impactpred.solvers._modal_kernel.dashpot_floor`): at c = 1e6, 0.8 ``t_s``, the
    rest of the exact contact carrying under 1e-13 of the peak."""
    mu, k, v0 = 0.5, 1e4, 1.0
    root = math.sqrt(c * c - 4 * mu * k)
    r1, r2 = (-c + root) / (2 * mu), (-c - root) / (2 * mu)
    t_s = 2 * math.log(r1 / r2) / (r2 - r1)
    e = r1 / r2 * math.exp(r1 * t_s)
    res = solve_impact(Body(LumpedMass(1.0), velocity=v0), Body(LumpedMass(1.0)),
                       contact=LinearSpring(k, damping=c), t_end=t_end)
    assert res.method == "modal" and res.n_contacts == 1 and not res.in_contact_at_end
    (start, end), = res.contact_intervals
    if c < 1e4:
        assert end - start == pytest.approx(t_s, rel=1e-3)
    else:
        assert 0.75 * t_s < end - start < t_s
    audit = res.energy_audit
    # the spring energy left at t_s: dissipated as the overlap relaxes, the rest stored
    taken = 0.5 * mu * v0**2 * (1 - e * e)
    assert audit.dissipated + audit.stored == pytest.approx(taken, rel=1e-5)
    assert abs(audit.relative) < 1e-5


@pytest.mark.parametrize("method", ["modal", "convolution"])
def test_a_loaded_flexibility_counts_its_strain_energy_as_the_exact_method_does(method):
    """A body with a flexibility term ``D`` loaded at ``t = 0`` holds ``D F(0)^2 / 2``
    there; every method reports the same body energies (the time-stepping ones had left
    it out of ``before``, and so out of ``after`` too)."""
    from impactpred import HarmonicForce

    beam = CantileverBeam(1.0, 0.0559591).modal_model(6, damping_ratio=0.0, residual=True)
    bodies = (Body(LumpedMass(0.2), velocity=0.5, load=HarmonicForce(2.0, 30.0)),
              Body(beam, load=HarmonicForce(5.0, 17.0)))
    exact = solve_impact(*bodies, gap=1e-4, contact=LinearSpring(1e6), t_end=0.002,
                         method="laplace")
    r = solve_impact(*bodies, gap=1e-4, contact=LinearSpring(1e6), t_end=0.002, dt=2e-7,
                     method=method)
    before = 0.5 * beam.flexibility * 5.0**2
    assert exact.energy_by_body[1].vibration_before == pytest.approx(before, rel=1e-12)
    assert r.energy_by_body[1].vibration_before == pytest.approx(before, rel=1e-12)
    assert r.energy_by_body[1].vibration_after == pytest.approx(
        exact.energy_by_body[1].vibration_after, rel=2e-3)
