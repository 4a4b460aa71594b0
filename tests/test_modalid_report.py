"""The fit's report (modalid._report.FitReport): read-only, by key and by attribute."""

import copy
import pickle

import numpy as np
import pytest
from sklearn.exceptions import NotFittedError

from modalid import FitReport, FRFData, ModalFit, ModalModel


@pytest.fixture(scope="module")
def fit():
    truth = ModalModel.from_modes(2 * np.pi * np.array([10.0, 25.0]), [0.01, 0.02], [1.0, 2.0])
    freq = np.linspace(1.0, 40.0, 400)
    return ModalFit().fit(FRFData(freq, truth.frf(2 * np.pi * freq)))


def test_entries_by_key_and_by_attribute(fit):
    report = fit.report_
    assert isinstance(report, FitReport)
    assert report.verdict == report["verdict"] == "ok"
    assert report.n_modes == 2 and len(report.modes) == 2
    assert {"band_hz", "frf_nrmse", "driving_point", "verdict_reasons"} <= set(report)
    with pytest.raises(AttributeError, match="no entry 'no_such_entry'"):
        _ = report.no_such_entry


def test_a_report_is_read_only_and_replace_makes_a_new_one(fit):
    report = fit.report_
    with pytest.raises(AttributeError, match="read-only"):
        report.verdict = "failed"
    with pytest.raises(TypeError):
        report["verdict"] = "failed"
    changed = report.replace(verdict="suspect", extra=1)
    assert changed.verdict == "suspect" and changed.extra == 1
    assert report.verdict == "ok" and "extra" not in report


def test_a_report_survives_pickle_and_deepcopy(fit):
    for copied in (pickle.loads(pickle.dumps(fit.report_)), copy.deepcopy(fit.report_)):
        assert isinstance(copied, FitReport) and copied.n_modes == 2
        np.testing.assert_array_equal(copied.modes["frequency_hz"],
                                      fit.report_.modes["frequency_hz"])


def test_an_unfitted_estimator_raises_sklearns_not_fitted_error():
    with pytest.raises(NotFittedError, match="not fitted yet"):
        ModalFit().predict([1.0])
