"""ModalModel against exact answers: closed-form modes, python-control round trips."""

import control
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modalid import ModalModel


def single_mode_receptance(s, omega_n, zeta, modal_mass):
    return 1.0 / (modal_mass * (s**2 + 2 * zeta * omega_n * s + omega_n**2))


@pytest.fixture
def model():
    return ModalModel.from_modes([10.0, 25.0, 70.0], [0.01, 0.02, 0.0], [1.0, 2.0, 0.5],
                                 inverse_mass=0.5, flexibility=1e-3)


def test_from_modes_is_the_sum_of_single_dof_receptances(model):
    s = 1j * np.linspace(0.5, 120, 400) + 0.3
    exact = (0.5 / s**2 + 1e-3 + single_mode_receptance(s, 10.0, 0.01, 1.0)
             + single_mode_receptance(s, 25.0, 0.02, 2.0)
             + single_mode_receptance(s, 70.0, 0.0, 0.5))
    np.testing.assert_allclose(model.receptance(s), exact, rtol=1e-13)
    np.testing.assert_allclose(model(s), exact, rtol=1e-13)


def test_modes_table(model):
    table = model.modes
    np.testing.assert_allclose(table["omega_n"], [10, 25, 70], rtol=1e-14)
    np.testing.assert_allclose(table["frequency_hz"], np.array([10, 25, 70]) / (2 * np.pi))
    np.testing.assert_allclose(table["damping_ratio"], [0.01, 0.02, 0.0], atol=1e-15)
    np.testing.assert_allclose(table["modal_mass"], [1.0, 2.0, 0.5], rtol=1e-13)
    assert model.n_modes == 3
    assert model.is_stable() and model.is_passive()


def test_frf_quantities(model):
    omega = np.linspace(1.0, 100.0, 50)
    h = model.frf(omega)
    np.testing.assert_allclose(model.frf(omega, quantity="mobility"), 1j * omega * h)
    np.testing.assert_allclose(model.frf(omega, quantity="accelerance"), -omega**2 * h,
                               rtol=1e-12)
    # the accelerance of a free body at 0 Hz is its finite limit 1/M
    assert model.frf([0.0], quantity="accelerance")[0] == pytest.approx(0.5)
    assert model.receptance(0.0) == np.inf


def test_step_response_closed_form_single_mode():
    wn, zeta, mm = 12.0, 0.05, 3.0
    m = ModalModel.from_modes([wn], zeta, mm)
    t = np.linspace(0, 5, 301)
    wd = wn * np.sqrt(1 - zeta**2)
    h_exact = np.exp(-zeta * wn * t) * np.sin(wd * t) / (mm * wd)
    s_exact = (1 - np.exp(-zeta * wn * t)
               * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))) / (mm * wn**2)
    np.testing.assert_allclose(m.impulse_response(t), h_exact, atol=1e-15)
    np.testing.assert_allclose(m.step_response(t), s_exact, atol=1e-15)
    assert m.impulse_response([-1.0])[0] == 0.0 and m.step_response([-1.0])[0] == 0.0


def test_impulse_response_is_derivative_of_step_response(model):
    t = np.linspace(0.01, 3.0, 4001)
    dt = 1e-6
    derivative = (model.step_response(t + dt) - model.step_response(t - dt)) / (2 * dt)
    np.testing.assert_allclose(derivative, model.impulse_response(t), rtol=1e-6, atol=1e-9)
    # the flexibility is the jump of the step response at t = 0
    assert model.step_response([0.0])[0] == pytest.approx(1e-3)
    assert model.static_flexibility() == pytest.approx(
        1e-3 + 1 / 100 + 1 / (2 * 625) + 1 / (0.5 * 4900))


def test_impulse_response_against_numerical_inverse_laplace():
    """Bromwich integral along Re s = c, evaluated by quadrature, for a damped model."""
    m = ModalModel.from_modes([3.0, 8.0], [0.05, 0.1], [1.0, 0.7],
                              inverse_mass=0.0).__class__(
        poles=[-0.15 + 3j, -0.8 + 8j], residues=[-0.17j + 0.01, -0.09j],
        real_poles=[-2.0], real_residues=[0.3])
    c = 0.5
    w = np.linspace(-4000, 4000, 2_000_001)
    s = c + 1j * w
    H = m.receptance(s)
    for t in (0.3, 1.1, 2.7):
        integrand = (H * np.exp(s * t)).real
        value = np.trapezoid(integrand, w) / (2 * np.pi)
        assert value == pytest.approx(m.impulse_response([t])[0], abs=2e-4)


def test_statespace_round_trip(model):
    sys = model.to_statespace()
    assert isinstance(sys, control.StateSpace)
    assert np.isrealobj(sys.A)
    s = 1j * np.linspace(0.3, 150, 700)
    ss_values = np.array([sys(x) for x in s]).ravel()
    np.testing.assert_allclose(ss_values, model.receptance(s), rtol=1e-10)
    back = ModalModel.from_control(sys)
    np.testing.assert_allclose(back.receptance(s), model.receptance(s), rtol=1e-10)
    assert back.inverse_mass == pytest.approx(0.5, rel=1e-12)
    assert back.flexibility == pytest.approx(1e-3, rel=1e-12)


def test_transfer_function_round_trip_low_order():
    m = ModalModel.from_modes([4.0, 9.0], [0.02, 0.0], [1.0, 0.5], inverse_mass=0.25)
    tf = m.to_transfer_function()
    assert isinstance(tf, control.TransferFunction)
    back = ModalModel.from_control(tf)
    s = 1j * np.linspace(0.3, 30, 500)
    np.testing.assert_allclose(back.receptance(s), m.receptance(s), rtol=1e-10)


def test_real_poles_round_trip():
    m = ModalModel(poles=[-0.5 + 10j], residues=[0.01 - 0.05j], real_poles=[-3.0, -40.0],
                   real_residues=[0.2, 1.5], flexibility=0.01)
    back = ModalModel.from_control(m.to_statespace())
    np.testing.assert_allclose(np.sort(back.real_poles), [-40.0, -3.0], rtol=1e-12)
    s = 1j * np.linspace(0.1, 100, 300)
    np.testing.assert_allclose(back.receptance(s), m.receptance(s), rtol=1e-10)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.floats(0.5, 500.0), st.floats(0.0, 0.3), st.floats(0.01, 100.0)),
                min_size=1, max_size=12),
       # from_control reads an inverse mass under 1e-9 of the modes' compliance (at the
       # lowest pole) as rounding: 1e-7 next to a 0.01 kg mode at 1 rad/s was dropped
       st.one_of(st.just(0.0), st.floats(1e-3, 10.0)), st.floats(0.0, 1e-2))
def test_statespace_round_trip_property(modes, inverse_mass, flexibility):
    wn, zeta, mm = (np.array(x) for x in zip(*modes))
    wn = wn * (1 + 1e-3 * np.arange(wn.size))  # distinct poles
    m = ModalModel.from_modes(wn, zeta, mm, inverse_mass=inverse_mass, flexibility=flexibility)
    back = ModalModel.from_control(m.to_statespace())
    s = 1j * np.geomspace(0.1, 1000, 200) + 0.05
    np.testing.assert_allclose(back.receptance(s), m.receptance(s), rtol=1e-10)


def test_truncate_keeps_lowest_modes_and_static_flexibility(model):
    t1 = model.truncate(1)
    assert t1.n_modes == 1 and t1.modes["omega_n"].iloc[0] == pytest.approx(10.0)
    t1r = model.truncate(1, residual=True)
    assert t1r.static_flexibility() == pytest.approx(model.static_flexibility(), rel=1e-14)
    assert t1r.inverse_mass == model.inverse_mass
    assert model.truncate(10) == model or model.truncate(10).n_modes == 3


def test_passivity_and_stability_flags():
    negative = ModalModel.from_modes([10.0, 20.0], 0.01, [1.0, -2.0])
    assert negative.is_stable() and not negative.is_passive()
    unstable = ModalModel(poles=[0.1 + 5j], residues=[-0.1j])
    assert not unstable.is_stable() and not unstable.is_passive()


def test_immutable(model):
    with pytest.raises(AttributeError):
        model.inverse_mass = 2.0
    with pytest.raises(ValueError):
        model.poles[0] = 1j


@pytest.mark.parametrize("kwargs, match", [
    (dict(poles=[1j, 2j], residues=[1.0]), "same shape"),
    (dict(poles=[-1.0 + 0j], residues=[1.0]), "Im p > 0"),
    (dict(poles=[np.nan + 1j], residues=[1.0]), "finite"),
    (dict(inverse_mass=float("nan")), "inverse_mass"),
    (dict(real_poles=[0.0], real_residues=[1.0]), "real_poles"),
    (dict(flexibility=float("inf")), "flexibility"),
])
def test_constructor_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ModalModel(**kwargs)


def test_constructor_rejects_wrong_types():
    with pytest.raises(TypeError, match="poles"):
        ModalModel(poles="abc", residues=[1.0])
    with pytest.raises(TypeError, match="inverse_mass"):
        ModalModel(inverse_mass="heavy")


@pytest.mark.parametrize("args, match", [
    (([0.0], 0.0, 1.0), "omega_n"),
    (([1.0], 1.0, 1.0), "damping_ratio"),
    (([1.0], 0.0, 0.0), "modal_mass"),
    (([1.0, 2.0], [0.0, 0.1, 0.2], 1.0), "matching shapes"),
])
def test_from_modes_rejects_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        ModalModel.from_modes(*args)


def test_from_control_keeps_a_repeated_pole_that_is_not_defective():
    # two uncoupled equal modes: one pole, residues that add up (1 + 2)
    sys = control.ss(np.diag([-1.0, -1.0]), [[1.0], [1.0]], [[1.0, 2.0]], 0.0)
    model = ModalModel.from_control(sys)
    s = np.array([0.5j, 3.0j])
    np.testing.assert_allclose(model.receptance(s), 3.0 / (s + 1.0), rtol=1e-12)


@pytest.mark.parametrize("sys, match", [
    (control.tf([1, 0, 0], [1, 1]), "improper"),
    (control.tf([1], [1, 0]), "simple pole at s = 0"),
    (control.tf([1], [1, 0, 0, 0]), r"order 3 at s = 0 \(coefficient 1 of 1/s\^3\)"),
    # 1/s^4 had become a zero receptance (a wall), beside a mode the mode alone
    (control.tf([1], [3, 0, 0, 0, 0]), r"order 4 at s = 0 \(coefficient 0.333333 of 1/s\^4"),
    (control.tf([1], [1, 0, 0, 0, 0]) + control.tf([1], [1, 0, 100]), "order 4 at s = 0"),
    (control.tf([1, 0, 1], [1, 0, 0, 0, 0, 0]), "order 5 at s = 0"),
    (control.tf([1], [1, 1, 0, 0, 0]), "order 3 at s = 0"),     # 1/(s^3 (s + 1)), not "simple"
    (control.tf([1], [2, 0]), r"simple pole .* mobility is 1/\(m s\)"),
    (control.ss([[np.nan]], [[1.0]], [[1.0]], 0.0), "NaN or infinite entries"),
    # (s^2 + 100)^2: split by rounding into modes 6e-8 apart with residues +-4e4 i
    (control.tf([1], [1, 0, 200, 0, 1e4]), "repeated pole near s = .*10j"),
    (control.tf([1], [1, 4, 204, 400, 1e4]) + control.tf([1], [1, 0, 4e4]), "repeated pole"),
    (control.tf([1], [1, -1]), "unstable"),
    (control.ss(-np.eye(2), np.ones((2, 2)), np.ones((2, 2)), 0), "SISO"),
    (control.tf([1], [1, 1], dt=0.1), "continuous"),
])
def test_from_control_rejects_bad_systems(sys, match):
    with pytest.raises(ValueError, match=match):
        ModalModel.from_control(sys)
    with pytest.raises(TypeError, match="StateSpace"):
        ModalModel.from_control([1, 2, 3])


def test_frf_rejects_unknown_quantity(model):
    with pytest.raises(ValueError, match="inertance"):
        model.frf([1.0], quantity="inertance")


def test_json_round_trip_is_exact(model, tmp_path):
    m = ModalModel(poles=[-0.3 + 7j, -1.0 + 40j], residues=[0.01 - 0.2j, -0.05j],
                   real_poles=[-12.0], real_residues=[0.4], inverse_mass=0.25, flexibility=2e-3)
    back = ModalModel.from_json(m.to_json())
    assert back == m
    path = tmp_path / "model.json"
    model.to_json(path)
    assert ModalModel.from_json(path) == model
    assert ModalModel.from_json(str(path)) == model


@pytest.mark.parametrize("text, match", [
    ('{"format": "something else"}', "format"),
    ("{not json", "not a ModalModel JSON"),
    ('{"format": "modalid.ModalModel", "poles": [[0.0, -1.0]], "residues": [[0, 1]]}',
     "Im p > 0"),
])
def test_from_json_rejects_bad_text(text, match):
    with pytest.raises(ValueError, match=match):
        ModalModel.from_json(text)


def test_transfer_receptance_may_have_a_negative_rigid_term():
    """A transfer row of a free body (rigid rotation) has 1/s^2 coefficient < 0."""
    model = ModalModel(poles=[-0.1 + 10j], residues=[0.02j], inverse_mass=-0.3)
    assert not model.is_passive()
    back = ModalModel.from_control(model.to_statespace())
    assert back.inverse_mass == pytest.approx(-0.3, rel=1e-12)
    s = 1j * np.array([0.5, 3.0, 40.0])
    np.testing.assert_allclose(back.receptance(s), model.receptance(s), rtol=1e-12)


def test_pickle_round_trip_is_exact(model):
    """Process pools (sweeps) send models to workers by pickling."""
    import pickle

    back = pickle.loads(pickle.dumps(model))
    assert back == model and back.poles.flags.writeable is False


def test_transfer_function_export_says_when_polynomials_lose_the_model():
    import warnings

    from data_synth import Rod

    with warnings.catch_warnings():
        warnings.simplefilter("error")          # a low order: exact, said nothing
        small = Rod(1.0, 1.0, support="fixed").modal_model(5)
        tf = small.to_transfer_function()
    w = np.array([0.3, 7.0, 40.0])
    np.testing.assert_allclose(tf(1j * w), small.receptance(1j * w), rtol=1e-9)
    with warnings.catch_warnings():          # exact, though H = 0 at a point compared
        warnings.simplefilter("error")
        ModalModel(poles=[10j, 40j], residues=[-1j / 20, -4j / 80]).to_transfer_function()
    big = Rod(1.0, 1.0, support="fixed").modal_model(30)     # error 1 of the terms' sum
    with pytest.warns(UserWarning, match=r"60 poles lose its receptance .* to_statespace"):
        big.to_transfer_function()
