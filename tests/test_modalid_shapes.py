"""modalid.mac: exact values, invariance to scaling, refused inputs."""

import numpy as np
import pytest

from modalid import mac


def test_identical_and_scaled_shapes_give_one():
    rng = np.random.default_rng(0)
    a = rng.normal(size=(5, 3)) + 1j * rng.normal(size=(5, 3))
    scaled = a * np.array([2.0, -3j, 0.5 - 0.5j])       # any complex scale per mode
    m = mac(a, scaled)
    assert m.shape == (3, 3) and m.dtype == float
    np.testing.assert_allclose(np.diag(m), 1.0, rtol=0, atol=1e-14)


def test_exact_values():
    # orthogonal shapes: 0; a known angle: cos^2
    np.testing.assert_allclose(mac(np.eye(3), np.eye(3)), np.eye(3), atol=0)
    theta = 0.3
    m = mac([[1.0], [0.0]], [[np.cos(theta)], [np.sin(theta)]])
    np.testing.assert_allclose(m, [[np.cos(theta) ** 2]], rtol=1e-14)
    # the docstring example, and a 1-D input is one shape (the result is always 2-D)
    np.testing.assert_allclose(mac([[1.0], [2.0]], [[-2j, 1.0], [-4j, 0.0]]), [[1.0, 0.2]])
    assert mac([1.0, 2.0], [2.0, 4.0]).shape == (1, 1)


def test_rectangular_sets_lie_in_unit_interval():
    rng = np.random.default_rng(1)
    m = mac(rng.normal(size=(6, 4)), rng.normal(size=(6, 2)) + 1j * rng.normal(size=(6, 2)))
    assert m.shape == (4, 2) and np.all((m >= 0) & (m <= 1))


@pytest.mark.parametrize("a, b, match", [
    (np.ones((3, 2)), np.ones((4, 2)), "same number of points.*3 and 4"),
    (np.array([[1.0, np.nan], [1.0, 2.0]]), np.ones((2, 1)), "shapes_a must be finite, got .*nan"),
    (np.array([[1.0, 0.0], [1.0, 0.0]]), np.ones((2, 1)), "zero shape vector \\(mode 1\\)"),
    (np.ones((2, 1)), np.zeros((2, 1)), "shapes_b has a zero shape vector"),
    (np.ones((2, 2, 2)), np.ones((2, 1)), "shape \\(n_points, n_modes\\)"),
    (np.ones((0, 2)), np.ones((0, 1)), "at least one point"),
])
def test_bad_shapes_are_refused(a, b, match):
    with pytest.raises(ValueError, match=match):
        mac(a, b)


def test_non_numeric_is_a_type_error():
    with pytest.raises(TypeError, match="shapes_a"):
        mac("abc", np.ones((3, 1)))


def test_phase_collinearity_of_real_complex_and_scaled_shapes():
    """modalid.mpc: 1 for a real shape under any complex scale, 0 for points on a circle
    (a travelling wave), the closed form for one point off the line, and the refusals of
    the shared checks."""
    from modalid import mpc

    real = np.array([1.0, -0.5, 0.3, 2.0])
    np.testing.assert_allclose(mpc(np.outer(real, [1.0, np.exp(0.7j), -3j])), 1.0,
                               atol=1e-15)
    circle = np.exp(2j * np.pi * np.arange(4) / 4)
    np.testing.assert_allclose(mpc(circle), 0.0, atol=1e-15)
    # (1, i a): S_rr = 1, S_ii = a^2, S_ri = 0 -> ((1 - a^2) / (1 + a^2))^2
    a = 0.3
    np.testing.assert_allclose(mpc([1.0, 1j * a]), ((1 - a**2) / (1 + a**2)) ** 2,
                               rtol=1e-14)
    with pytest.raises(ValueError, match="zero shape vector"):
        mpc([[0.0], [0.0]])
