"""MultiOutputModalModel: shared poles, one residue row per output, exact conversions."""

import control
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from modalid import ModalModel, MultiOutputModalModel


def _beam_like(rng, n_modes=4, n_out=3, rigid=True):
    """Real normal modes with random shapes; row 0 is the driving point."""
    omega = 10.0 * np.arange(1, n_modes + 1) ** 1.5
    zeta = 0.02
    wd = omega * np.sqrt(1 - zeta**2)
    poles = -zeta * omega + 1j * wd
    shapes = rng.normal(size=(n_out, n_modes))
    shapes[0] = np.abs(shapes[0]) + 0.2
    residues = shapes * shapes[0] / (2j * wd)
    inverse_mass = shapes[0, 0] * np.array([0.5, -0.3, 0.2][:n_out]) if rigid else 0.0
    if rigid:
        inverse_mass = np.abs(inverse_mass) * np.sign([1, -1, 1][:n_out])
    return MultiOutputModalModel(poles=poles, residues=residues, inverse_mass=inverse_mass,
                                 flexibility=[1e-4, -2e-5, 3e-5][:n_out],
                                 outputs=("tip", "mid", "root")[:n_out]), shapes


@pytest.fixture
def model():
    return _beam_like(np.random.default_rng(1))[0]


def test_rows_are_modal_models_and_agree_with_the_matrix_evaluation(model):
    s = 1j * np.linspace(0.5, 120.0, 50) - 0.3
    H = model.receptance(s)
    assert H.shape == (3, 50)
    for i, label in enumerate(model.outputs):
        np.testing.assert_allclose(H[i], model.row(label).receptance(s), rtol=1e-13)
    assert model.driving == model.row(0)
    assert model.row("mid").inverse_mass < 0 and not model.row("mid").is_passive()


def test_rigid_rows_are_infinite_at_zero_never_nan(model):
    H = model.receptance(np.array([0.0, 1j]))
    assert np.all(np.isinf(H[:, 0])) and np.all(np.isfinite(H[:, 1]))
    acc = model.frf(np.array([0.0]), quantity="accelerance")
    np.testing.assert_allclose(acc[:, 0], model.inverse_mass, rtol=1e-15)


def test_statespace_has_one_output_per_row_and_round_trips(model):
    sys = model.to_statespace()
    assert (sys.ninputs, sys.noutputs) == (1, 3)
    assert list(sys.output_labels) == list(model.outputs)
    omega = np.linspace(0.7, 150.0, 40)
    response = np.squeeze(control.frequency_response(sys, omega).complex)
    np.testing.assert_allclose(response, model.frf(omega), rtol=1e-12)
    back = MultiOutputModalModel.from_control(sys, driving_point=0)
    np.testing.assert_allclose(back.receptance(1j * omega), model.receptance(1j * omega),
                               rtol=1e-10)
    np.testing.assert_allclose(back.inverse_mass, model.inverse_mass, rtol=1e-10)
    assert back.outputs == model.outputs


@settings(max_examples=25, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1), n_modes=st.integers(1, 6), n_out=st.integers(1, 3))
def test_statespace_round_trip_property(seed, n_modes, n_out):
    truth, _ = _beam_like(np.random.default_rng(seed), n_modes, n_out, rigid=seed % 2 == 0)
    back = MultiOutputModalModel.from_control(truth.to_statespace())
    s = 1j * np.geomspace(1.0, 500.0, 30)
    np.testing.assert_allclose(back.receptance(s), truth.receptance(s), rtol=1e-9,
                               atol=1e-12 * np.max(np.abs(truth.receptance(s))))


def test_step_and_impulse_responses_are_the_rows_closed_forms(model):
    t = np.linspace(-0.1, 2.0, 300)
    S, h = model.step_response(t), model.impulse_response(t)
    for i in range(model.n_outputs):
        np.testing.assert_array_equal(S[i], model.row(i).step_response(t))
        np.testing.assert_array_equal(h[i], model.row(i).impulse_response(t))
    # h is the derivative of S (central differences, away from t = 0)
    tt = np.linspace(0.2, 1.5, 200)
    dt = 1e-6
    dS = (model.step_response(tt + dt) - model.step_response(tt - dt)) / (2 * dt)
    np.testing.assert_allclose(dS, model.impulse_response(tt), rtol=1e-6, atol=1e-9)


def test_mode_shapes_recover_the_generating_shapes():
    truth, shapes = _beam_like(np.random.default_rng(7), rigid=False)
    np.testing.assert_allclose(truth.mode_shapes(scaling="mass").real, shapes, rtol=1e-12)
    np.testing.assert_allclose(truth.mode_shapes(scaling="mass").imag, 0.0, atol=1e-12)
    np.testing.assert_allclose(truth.mode_shapes(), shapes / shapes[0], rtol=1e-12)


def test_from_rows_matches_poles_in_any_order(model):
    rows = [model.row(i) for i in range(model.n_outputs)]
    shuffled = rows[1].replace(poles=rows[1].poles[::-1], residues=rows[1].residues[::-1])
    again = MultiOutputModalModel.from_rows([rows[0], shuffled, rows[2]],
                                            outputs=model.outputs)
    assert again == model
    other = rows[1].replace(poles=rows[1].poles * 1.01)
    with pytest.raises(ValueError, match="row 1 does not share the poles"):
        MultiOutputModalModel.from_rows([rows[0], other])


def test_json_round_trip_is_exact(model, tmp_path):
    path = tmp_path / "m.json"
    text = model.to_json(path)
    assert MultiOutputModalModel.from_json(text) == model
    assert MultiOutputModalModel.from_json(path) == model
    with pytest.raises(ValueError, match="format"):
        MultiOutputModalModel.from_json(ModalModel().to_json())


def test_immutable(model):
    with pytest.raises(AttributeError):
        model.driving_point = 1
    with pytest.raises(ValueError):
        model.residues[0, 0] = 1.0


@pytest.mark.parametrize("changes, error, match", [
    (dict(residues=np.ones((2, 3))), ValueError, "residues must have shape"),
    (dict(driving_point=3), ValueError, "driving_point"),
    (dict(driving_point=1.0), TypeError, "driving_point"),
    (dict(outputs=("a", "a", "b")), ValueError, "unique"),
    (dict(outputs=("a", "b")), ValueError, "3 labels"),
    (dict(inverse_mass=[1.0, 2.0]), ValueError, "inverse_mass"),
    (dict(flexibility=[np.nan, 0.0, 0.0]), ValueError, "flexibility"),
    (dict(driving_point=1), ValueError, "driving point's inverse_mass"),
])
def test_bad_input_is_named(model, changes, error, match):
    with pytest.raises(error, match=match):
        model.replace(**changes)


def test_output_lookup_errors(model):
    with pytest.raises(ValueError, match="out of range"):
        model.row(5)
    with pytest.raises(ValueError, match="no output labelled 'foo'"):
        model.row("foo")
    with pytest.raises(TypeError, match="row index or a label"):
        model.row(1.5)


def test_pickle_round_trip_is_exact(model):
    import pickle

    back = pickle.loads(pickle.dumps(model))
    assert back == model and back.outputs == model.outputs


def test_close_modes_survive_the_state_space_round_trip_and_a_repeat_is_named():
    """Two genuine modes 1e-7 apart (a symmetric structure's pair: an antisymmetric cross
    row) keep their independent eigenvectors and come back; two identical uncoupled
    oscillators (one pole twice) are refused naming the repeat, not as 'relative
    difference 0 > 1e-08'."""
    p1, p2 = -0.01 + 100j, -0.01 + 100j * (1 + 1e-7)
    rows = [ModalModel(poles=[p1, p2], residues=[-0.005j, -0.005j]),
            ModalModel(poles=[p1, p2], residues=[-0.005j, 0.005j])]
    model = MultiOutputModalModel.from_rows(rows, driving_point=0, outputs=["a", "b"])
    back = MultiOutputModalModel.from_control(model.to_statespace())
    s = 1j * np.array([99.0, 100.0, 101.0])
    np.testing.assert_allclose(back.receptance(s), model.receptance(s), rtol=1e-6)
    one = np.array([[0.0, 1.0], [-1e4, -0.2]])
    twice = control.ss(np.block([[one, np.zeros((2, 2))], [np.zeros((2, 2)), one]]),
                       [[0.0], [1.0], [0.0], [1.0]], [[1.0, 0, 1, 0], [1.0, 0, -1, 0]],
                       np.zeros((2, 1)))
    with pytest.raises(ValueError, match="repeated pole near .* two identical uncoupled"):
        MultiOutputModalModel.from_control(twice, driving_point=0)
