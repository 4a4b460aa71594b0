"""Contact laws: the scalar step problems and Hertz's constants."""

import numpy as np
import pytest

from impactpred import Hertz, LinearSpring, Rigid


def test_rigid_step_force_closes_the_gap_exactly():
    assert Rigid().step_force(-2e-3, 1e-4, 0.0, 1e-3) == pytest.approx(20.0)
    assert Rigid().step_force(1e-3, 1e-4, 0.0, 1e-3) == 0.0


def test_linear_spring_step_force_solves_the_implicit_law():
    k, c, K0, dt, g_prev, G = 1e5, 20.0, 1e-6, 1e-4, -1e-5, -3e-5
    f = LinearSpring(k, damping=c).step_force(G, K0, g_prev, dt)
    g_new = G + K0 * f
    assert f == pytest.approx(k * (-g_new) + c * (-(g_new - g_prev)) / dt, rel=1e-12)


@pytest.mark.parametrize("G", [-1e-4, -1e-6, -1e-9])
def test_hertz_step_force_solves_the_power_law(G):
    law, K0 = Hertz(1e9), 1e-7
    f = law.step_force(G, K0, 0.0, 1e-5)
    assert f == pytest.approx(1e9 * (-(G + K0 * f)) ** 1.5, rel=1e-10)
    assert law.step_force(1e-6, K0, 0.0, 1e-5) == 0.0


def test_hertz_step_force_at_the_top_of_its_bracket_is_not_nan():
    """A stiff law starts Newton at the bracket's top ``-G/K``, where ``G + K f`` can round
    past 0: ``d**1.5`` of a negative ``d`` was NaN ("invalid value in scalar power", a
    Hertz contact under the modal solver's zero-order hold); the compiled kernel clipped
    it, the Python law did not. Both are now one function, in the kernel's file."""
    from impactpred.solvers import _modal_kernel
    from impactpred.solvers._modal_kernel import hertz_force, hertz_step_force

    G, K = -1.1422907808931682e-07, 0.0009195205869545325
    assert -(G + K * (-G / K)) < 0.0                    # the top rounds past zero
    with np.errstate(all="raise"):
        f = Hertz(1e12).step_force(G, K, 0.0, 1e-6)
    assert 0.0 < f <= -G / K and np.isfinite(f)
    assert f == pytest.approx(1e12 * max(-(G + K * f), 0.0) ** 1.5, rel=1e-6, abs=1e-12 * f)
    assert hertz_force(G, K, 1e12, 1.5) == hertz_step_force(G, K, 1e12, 1.5) == f
    # compiled from the function defined in the kernel's own file: numba keys the cache of
    # the compiled callers (law_force) on that file alone
    assert hertz_force.py_func is hertz_step_force
    assert hertz_step_force.__code__.co_filename == _modal_kernel.__file__


def test_hertz_from_materials_steel_ball_on_steel():
    law = Hertz.from_materials(radius1=5e-3, youngs_modulus1=210e9, poisson1=0.3,
                               youngs_modulus2=210e9, poisson2=0.3)
    e_star = 210e9 / (2 * (1 - 0.09))
    assert law.stiffness == pytest.approx(4 / 3 * e_star * np.sqrt(5e-3), rel=1e-12)
    two_balls = Hertz.from_materials(radius1=5e-3, radius2=5e-3, youngs_modulus1=210e9,
                                     poisson1=0.3, youngs_modulus2=210e9, poisson2=0.3)
    assert two_balls.stiffness == pytest.approx(law.stiffness / np.sqrt(2), rel=1e-12)
    # an incompressible ball (rubber, Poisson 0.5) was refused (walkthrough)
    rubber = Hertz.from_materials(radius1=5e-3, youngs_modulus1=5e6, poisson1=0.5,
                                  youngs_modulus2=210e9, poisson2=0.3)
    e_star = 1 / (0.75 / 5e6 + 0.91 / 210e9)
    assert rubber.stiffness == pytest.approx(4 / 3 * e_star * np.sqrt(5e-3), rel=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(radius1=-1.0), "radius1"), (dict(poisson1=0.7), "poisson1"),
    (dict(youngs_modulus2=0.0), "youngs_modulus2"),
])
def test_hertz_from_materials_rejects_bad_values(kwargs, match):
    args = dict(radius1=5e-3, youngs_modulus1=210e9, poisson1=0.3, youngs_modulus2=210e9,
                poisson2=0.3)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        Hertz.from_materials(**args)


def test_each_law_says_once_how_it_may_be_solved():
    from impactpred import ContactLaw, InstantaneousImpact

    laws = {Rigid(): (True, False), LinearSpring(1e5): (True, False),
            LinearSpring(1e5, damping=3.0): (False, False), Hertz(1e9): (False, False),
            InstantaneousImpact(0.5): (False, True)}
    for law, (linear, impulsive) in laws.items():
        assert isinstance(law, ContactLaw)
        assert (law.is_linear, law.is_impulsive) == (linear, impulsive), law


def test_solve_impact_chooses_by_is_linear_and_refuses_an_impulsive_law():
    from data_synth import LumpedMass, SpringMass
    from impactpred import Body, InstantaneousImpact, solve_impact

    bodies = (Body(LumpedMass(1.0), velocity=1.0), Body(SpringMass(1.0, 1e4)))
    assert solve_impact(*bodies, contact=LinearSpring(1e5), t_end=0.05).method == "laplace"
    damped = solve_impact(*bodies, contact=LinearSpring(1e5, damping=3.0), t_end=0.05)
    assert damped.method == "modal"
    with pytest.raises(ValueError, match="linear contact"):
        solve_impact(*bodies, contact=LinearSpring(1e5, damping=3.0), t_end=0.05,
                     method="laplace")
    with pytest.raises(TypeError, match="impulsive law"):
        solve_impact(*bodies, contact=InstantaneousImpact(0.5), t_end=0.05)
    with pytest.raises(TypeError, match=r"contact must be Rigid\(\)"):
        solve_impact(*bodies, contact=1e5, t_end=0.05)
