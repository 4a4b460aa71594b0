"""modalid.SavedFit: a fit's model and report in one JSON file; the model read back exactly,
the report as JSON holds it."""

import json
import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.exceptions import NotFittedError

from data_synth import CantileverBeam, Rod, lightly_damped, synthetic_frf
from modalid import FRFSet, ModalFit, ModalModel, MultiOutputModalModel, SavedFit


@pytest.fixture(scope="module")
def rod_fit():
    """A fixed rod's accelerance (12 modes in band, 1 % noise), fitted with no options."""
    truth = lightly_damped(Rod(1.0, 1e-3, support="fixed"), 20, 1e-3)
    frf = synthetic_frf(truth, np.arange(1.0, 6000.0, 2.0), quantity="accelerance",
                        noise=0.01, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ModalFit().fit(frf)


def assert_same_report(saved, fit):
    """Every entry JSON can hold comes back equal (the modes table column by column)."""
    for name, value in fit.report_.items():
        if name == "modes":
            pd.testing.assert_frame_equal(saved.report_["modes"], value)
        elif isinstance(value, float) and np.isnan(value):
            assert np.isnan(saved.report_[name]), name
        else:
            assert saved.report_[name] == value, name


def test_round_trip_is_exact_and_the_file_is_still_a_model(rod_fit, tmp_path):
    path = tmp_path / "rod_model.json"
    SavedFit.from_fit(rod_fit, source="rod.csv").to_json(path)
    saved = SavedFit.from_json(path)
    np.testing.assert_array_equal(saved.model_.poles, rod_fit.model_.poles)
    np.testing.assert_array_equal(saved.model_.residues, rod_fit.model_.residues)
    assert saved.model_.flexibility == rod_fit.model_.flexibility
    assert saved.source == "rod.csv"
    assert saved.report_["band_hz"] == rod_fit.report_["band_hz"] == (7.0, 5999.0)
    assert saved.report_.verdict == "ok" and saved.report_["n_modes"] == 12
    assert saved.report_["modes"]["residue"].dtype == complex
    assert saved.report_["modes"]["damping_resolved"].dtype == bool
    assert_same_report(saved, rod_fit)
    # the same file read as a bare model: the model alone, exactly
    bare = ModalModel.from_json(path)
    np.testing.assert_array_equal(bare.residues, rod_fit.model_.residues)
    # a copy: the saved fit does not share the fit's objects
    assert saved.model_ is not rod_fit.model_


def test_entries_json_cannot_hold_are_left_out(rod_fit):
    saved = SavedFit.from_fit(rod_fit)
    odd = SavedFit(model_=saved.model_, report_=saved.report_.replace(callback=print))
    again = SavedFit.from_json(odd.to_json())
    assert "callback" not in again.report_ and again.report_["n_modes"] == 12
    assert again.source is None


@pytest.fixture(scope="module")
def beam_set_fit():
    """A cantilever at three points (18 modes, 1 % noise), struck at its last point (the
    driving point is row 2: the report holds the row index), fitted with common poles."""
    beam = CantileverBeam(1.0, 1.0)
    truth = beam.multi_output_model([0.8, 0.5, 0.0], 18, damping_ratio=0.01, residual=True)
    freq_hz = np.linspace(0.05, 80.0, 3000)
    frfs = [synthetic_frf(truth.row(i), freq_hz, noise=0.01, seed=i) for i in range(3)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ModalFit().fit(FRFSet.from_frfs(frfs, driving_point=2, outputs=truth.outputs))


def test_a_multi_output_fit_round_trips(beam_set_fit):
    fit = beam_set_fit
    assert fit.report_["driving_point"] == 2
    saved = SavedFit.from_json(SavedFit.from_fit(fit).to_json())
    assert isinstance(saved.model_, MultiOutputModalModel)
    np.testing.assert_array_equal(saved.model_.residues, fit.model_.residues)
    assert saved.model_.outputs == fit.model_.outputs
    for name, value in fit.report_.items():      # lists where the fit has tuples or arrays
        if name == "modes":
            pd.testing.assert_frame_equal(saved.report_["modes"], value)
        elif isinstance(value, (tuple, list, np.ndarray)) and name != "band_hz":
            np.testing.assert_array_equal(saved.report_[name], value, err_msg=name)
        elif name in saved.report_:
            assert (saved.report_[name] == value
                    or (np.isnan(value) and np.isnan(saved.report_[name]))), name
    assert saved.report_["band_hz"] == fit.report_["band_hz"]
    with pytest.raises(ValueError, match=r"driving_point must be true, false or null, or a "
                                         r"row index < 3, got 3"):
        SavedFit(model_=saved.model_, report_=saved.report_.replace(driving_point=3))


def test_what_json_holds_comes_back_as_json_holds_it(rod_fit):
    """A band given as an array is kept as a tuple; an empty modes table keeps its
    dtypes; two saved fits compare by identity."""
    saved = SavedFit.from_fit(rod_fit)
    as_array = SavedFit(model_=saved.model_,
                        report_=saved.report_.replace(band_hz=np.array([7.0, 5999.0]),
                                                      modes=saved.report_["modes"].iloc[:0]))
    assert as_array.report_["band_hz"] == (7.0, 5999.0)
    again = SavedFit.from_json(as_array.to_json())
    assert again.report_["band_hz"] == (7.0, 5999.0)
    assert again.report_["modes"].empty
    assert again.report_["modes"].dtypes.to_dict() == saved.report_["modes"].dtypes.to_dict()
    assert again == again and again != as_array
    # the modes table is the saved fit's own copy
    assert saved.report_["modes"] is not rod_fit.report_["modes"]


def test_bad_input_is_named(rod_fit, tmp_path):
    with pytest.raises(NotFittedError, match="not fitted"):
        SavedFit.from_fit(ModalFit())
    bare = tmp_path / "bare.json"
    rod_fit.model_.to_json(bare)
    with pytest.raises(ValueError, match=r"bare\.json holds a bare model, not a saved fit .*"
                                         r"ModalModel\.from_json"):
        SavedFit.from_json(bare)
    payload = json.loads(SavedFit.from_fit(rod_fit).to_json())
    for field, value, message in [("band_hz", [10.0, 5.0], "band_hz must be finite with"),
                                  ("band_hz", "7-5999", "band_hz must be two frequencies"),
                                  ("n_modes", 2.5, "n_modes must be an integer"),
                                  ("verdict", "great", "verdict must be one of"),
                                  ("driving_point", "yes", "driving_point must be")]:
        broken = json.loads(json.dumps(payload))
        broken["identification"]["report"][field] = value
        path = tmp_path / f"broken_{field}.json"
        path.write_text(json.dumps(broken))
        with pytest.raises(ValueError, match=rf"broken_{field}\.json: .*{message}"):
            SavedFit.from_json(path)
    with pytest.raises(TypeError, match="model_ must be a ModalModel"):
        SavedFit(model_="rod", report_=SavedFit.from_fit(rod_fit).report_)
    # a block that is not a report is named as such, not taken for a bare model
    malformed = json.loads(json.dumps(payload))
    malformed["identification"] = "fitted on Tuesday"
    path = tmp_path / "malformed.json"
    path.write_text(json.dumps(malformed))
    with pytest.raises(ValueError, match=r"malformed\.json: its 'identification' must be an "
                                         r"object holding a 'report' object"):
        SavedFit.from_json(path)
    # the report is in SI units: a model stated in other units is refused
    scaled = json.loads(json.dumps(payload))
    scaled["units"]["receptance"] = "mm/N"
    path = tmp_path / "mm.json"
    path.write_text(json.dumps(scaled))
    with pytest.raises(ValueError, match=r"mm\.json: a saved fit's report is in SI units"):
        SavedFit.from_json(path)


def test_a_uff_record_s_dofs_go_with_the_fit(rod_fit, tmp_path):
    """``record_dofs`` (what ``modalid fit --out`` keeps of a UFF record) round-trip
    through JSON; where they say a transfer FRF ``dofs_say_transfer`` is True (a driving
    point along the opposite direction, a scalar direction at the reference's node and no
    DOFs at all are not); malformed ones are refused, naming them."""
    for dofs, transfer in [((2, 3, 1, 3), True), ((1, 2, 1, 3), True), ((1, -3, 1, 3), False),
                           ((1, 0, 1, 3), False), (None, False)]:
        saved = SavedFit.from_fit(rod_fit, source="rod.uff", record_dofs=dofs)
        again = SavedFit.from_json(saved.to_json())
        assert again.record_dofs == dofs and again.dofs_say_transfer is transfer
    with pytest.raises(ValueError, match=r"record_dofs must be None or 4 integers .* got "
                                         r"\(2, 3, 1\)"):
        SavedFit.from_fit(rod_fit, record_dofs=(2, 3, 1))
    payload = json.loads(SavedFit.from_fit(rod_fit, record_dofs=(2, 3, 1, 3)).to_json())
    payload["identification"]["record_dofs"] = ["2", 3, 1, 3]
    path = tmp_path / "dofs.json"
    path.write_text(json.dumps(payload))
    with pytest.raises(ValueError, match=r"dofs\.json: its identification's record_dofs must "
                                         r"be 4 integers or absent"):
        SavedFit.from_json(path)
