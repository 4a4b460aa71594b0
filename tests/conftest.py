"""Fixtures shared by several test files."""

import math

import pytest


@pytest.fixture
def windowed_free_rod_csv(tmp_path):
    """A free rod's (1 kg, transit time 1 s) mobility from an exponentially windowed
    synthetic hammer test (5 elastic modes in band, window ending at 1 %), written as a
    CSV file: ``(path, fit_options)`` with the ``ModalFit`` options of its window."""
    from data_synth import Rod, lightly_damped, synthetic_hammer_test
    from modalid import frf_from_hammer, write_frf

    truth = lightly_damped(Rod(1.0, 1.0), 15, 0.001)
    top, duration = 2.75, 100.0
    test = synthetic_hammer_test(truth, 5 * top, duration, pulse_width=0.5 / top,
                                 response="velocity", anti_alias=True)
    est = frf_from_hammer(test.force, test.response, 5 * top, response_type="velocity",
                          exponential_decay=-math.log(0.01) / duration)
    path = tmp_path / "free_rod.csv"
    write_frf(path, est.frf.band((1 / duration, top)))
    return path, est.fit_options()
