"""The receptance interface (``modalid.receptance``): every model kind implements it, and
the impact solvers read time scales and modal forms through it, not by class."""

import numpy as np
import pytest

import modalid.validation as validation
from data_synth import CantileverBeam, LumpedMass, Rod, SpringMass
from impactpred import Body, SampledResponse, choose_dt
from impactpred.contact import Rigid
from modalid import ModalModel, MultiOutputModalModel
from modalid import _checks
from modalid.receptance import TIME_SCALE_KINDS, Receptance, TimeScale


def _kinds():
    t = np.linspace(0.0, 0.1, 101)
    return {
        "modal": ModalModel.from_modes([100.0, 400.0], 0.02, [1.0, 2.0], inverse_mass=0.25),
        "rod": Rod(2.0, 1e-3),
        "beam": CantileverBeam(1.0, 0.05),
        "mass": LumpedMass(2.0),
        "spring-mass": SpringMass(1.0, 1e4),
        "sampled": SampledResponse(t, np.full_like(t, 0.5), inverse_mass=0.5),
    }


@pytest.mark.parametrize("name", list(_kinds()))
def test_every_model_kind_implements_the_interface(name):
    model = _kinds()[name]
    assert isinstance(model, Receptance)
    scales = model.time_scales()
    assert all(isinstance(s, TimeScale) and s.seconds > 0 and s.kind in TIME_SCALE_KINDS
               for s in scales)
    assert np.all(np.isfinite(model.step_response(np.array([0.0, 1e-3]))))
    if name == "sampled":
        assert not model.is_rational
        with pytest.raises(ValueError, match="no modal model"):
            model.modal_form(10)
        with pytest.raises(ValueError, match="static flexibility"):
            model.elastic_flexibility()
        return
    form = model.modal_form(30)
    assert isinstance(form, ModalModel)
    assert form.inverse_mass == pytest.approx(model.inverse_mass, rel=1e-15)
    # the modal form keeps the static flexibility (omitted modes' included)
    assert form.static_flexibility() == pytest.approx(model.elastic_flexibility(),
                                                      rel=1e-12, abs=1e-300)


def test_time_scales_say_what_they_resolve():
    k = _kinds()
    assert k["rod"].time_scales() == (TimeScale(1e-3, "transit"),)
    (beam,) = k["beam"].time_scales()
    assert beam.kind == "continuum"
    assert beam.seconds == pytest.approx(1.0 / k["beam"].natural_frequencies(1)[0])
    assert k["spring-mass"].time_scales()[0].kind == "modal"
    assert k["mass"].time_scales() == ()
    (modal,) = k["modal"].time_scales()
    assert modal == TimeScale(1.0 / np.max(np.abs(k["modal"].poles)), "modal")
    assert k["sampled"].time_scales() == (TimeScale(pytest.approx(1e-3), "sample"),)


def test_rational_models_give_their_exact_form_and_others_need_a_mode_count():
    k = _kinds()
    assert k["modal"].modal_form() is k["modal"]
    assert k["spring-mass"].modal_form().n_modes == 1
    assert k["mass"].modal_form().n_modes == 0
    with pytest.raises(ValueError, match="needs n_modes"):
        k["beam"].modal_form()
    assert k["beam"].modal_form(5).n_modes == 5


def test_a_multi_output_model_offers_its_driving_row():
    row = ModalModel.from_modes([100.0], 0.02, [1.0])
    other = row.replace(residues=0.5 * row.residues)
    multi = MultiOutputModalModel.from_rows([other, row], driving_point=1)
    assert multi.modal_form() == multi.driving == row
    assert multi.time_scales() == row.time_scales()
    assert multi.elastic_flexibility() == pytest.approx(row.static_flexibility())
    assert multi.is_rational


def test_any_model_implementing_the_interface_is_a_body_and_choose_dt_reads_its_scales():
    class Slow:
        """A user's own model: a lumped mass with a 2 ms wave transit."""

        inverse_mass, is_rational = 0.5, False

        def step_response(self, t):
            t = np.asarray(t, float)
            return np.where(t > 0, 0.25 * t**2, 0.0)

        def elastic_flexibility(self):
            return 0.0

        def time_scales(self):
            return (TimeScale(2e-3, "transit"),)

        def modal_form(self, n_modes=None):
            return ModalModel(inverse_mass=0.5)

    assert isinstance(Slow(), Receptance)
    bodies = (Body(Slow(), velocity=1.0), Body(LumpedMass(1.0)))
    # a transit time gets 1000 steps and the step divides it (wave reflections on the grid)
    assert choose_dt(bodies, Rigid(), t_end=0.1) == pytest.approx(2e-6, rel=1e-12)
    # the same as a rod of that transit time
    rod = (Body(Rod(2.0, 2e-3), velocity=1.0), Body(LumpedMass(1.0)))
    assert choose_dt(rod, Rigid(), t_end=0.1) == choose_dt(bodies, Rigid(), t_end=0.1)
    with pytest.raises(TypeError, match="Receptance"):
        Body(object())

    class Odd(Slow):
        def time_scales(self):
            return (TimeScale(1e-3, "geological"),)

    with pytest.raises(ValueError, match="kind 'geological'"):
        choose_dt((Body(Odd(), velocity=1.0), Body(LumpedMass(1.0))), Rigid(), t_end=0.1)


def test_the_public_validation_module_is_the_shared_one():
    for name in validation.__all__:
        assert getattr(validation, name) is getattr(_checks, name)
    with pytest.raises(ValueError, match="clearance must be positive, got -1.0"):
        validation.as_positive_scalar("clearance", -1)


def test_quantity_conversions_name_bad_operands():
    """``to_receptance(q, values, None)`` returned NaN; mismatched lengths gave numpy's
    broadcast message naming neither argument."""
    from modalid import receptance_to, to_receptance

    with pytest.raises(TypeError, match="omega must be an array .* got None"):
        to_receptance("mobility", [1 + 1j], None)
    with pytest.raises(ValueError, match=r"values \(shape \(2,\)\) and omega \(shape "
                                         r"\(3,\)\) do not broadcast"):
        to_receptance("mobility", [1 + 1j, 2], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="omega must be finite"):
        receptance_to("accelerance", [1.0], [np.nan])
    np.testing.assert_array_equal(receptance_to("accelerance", [1, 2], [1, 2]), [-1, -8])

