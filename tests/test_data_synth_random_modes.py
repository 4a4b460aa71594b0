"""data_synth.random_modal_model: the modes where, as far apart and as damped as it
says, one model per seed, bad input refused."""

import numpy as np
import pytest

from data_synth import random_modal_model


@pytest.mark.parametrize("zeta", [1e-4, 1e-2])
def test_modes_lie_in_the_band_apart_by_two_bandwidths(zeta):
    model = random_modal_model(50, (200.0, 19800.0), zeta, seed=7)
    modes = model.modes
    freq = modes["frequency_hz"].to_numpy(float)
    f_n = modes["omega_n"].to_numpy(float) / (2 * np.pi)
    assert freq.size == 50 and np.all(np.diff(f_n) > 0)
    assert f_n.min() >= 200.0 and f_n.max() <= 19800.0
    assert np.all(f_n[1:] / f_n[:-1] >= 1.0 + max(0.005, 4 * zeta))
    damping = modes["damping_ratio"].to_numpy(float)
    assert np.all((damping >= zeta / 2 * (1 - 1e-12)) & (damping <= 2 * zeta * (1 + 1e-12)))
    mass = modes["modal_mass"].to_numpy(float)
    assert np.all((mass >= 0.5 - 1e-9) & (mass <= 5.0 + 1e-9))


def test_a_seed_gives_one_model_and_bad_input_is_refused():
    a = random_modal_model(5, (10.0, 100.0), 0.01, seed=3)
    b = random_modal_model(5, (10.0, 100.0), 0.01, seed=3)
    np.testing.assert_array_equal(a.poles, b.poles)
    with pytest.raises(ValueError, match="low < high"):
        random_modal_model(5, (100.0, 10.0), 0.01)
    with pytest.raises(ValueError, match="could place only"):
        random_modal_model(500, (100.0, 101.0), 0.01, seed=0)
    with pytest.raises(ValueError, match="damping_ratio"):
        random_modal_model(5, (10.0, 100.0), 0.0)
    with pytest.raises(TypeError, match=r"freq_range_hz must be a pair \(low, high\) in Hz, "
                                        "got 5"):        # "'int' object is not iterable"
        random_modal_model(3, 5, 0.01)
