"""Mode-shape measures: the modal assurance criterion (MAC) between shapes, and each
shape's modal phase collinearity (MPC, :func:`mpc`).

    MAC_jk = |a_j^H b_k|^2 / ((a_j^H a_j) (b_k^H b_k))

for shape ``j`` of one set and ``k`` of another (Allemang and Brown, 1982): 1 for
proportional shapes (any complex scale), 0 for orthogonal ones. It does not depend on how
the shapes are scaled, so shapes scaled by the driving point compare directly with
mass-normalised analytic ones.
"""

from __future__ import annotations

import numpy as np

from ._checks import as_complex_array

__all__ = ["mac", "mpc"]


def _shapes(name, value):
    arr = as_complex_array(name, value)
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2:
        raise ValueError(f"{name} must have shape (n_points, n_modes), got shape {arr.shape}")
    if arr.shape[0] < 1 or arr.shape[1] < 1:
        raise ValueError(f"{name} must hold at least one point and one mode, got shape "
                         f"{arr.shape}")
    norms = np.sum(np.abs(arr) ** 2, axis=0)
    if np.any(norms == 0):
        raise ValueError(f"{name} has a zero shape vector (mode {int(np.argmax(norms == 0))}): "
                         "the criterion is undefined for it")
    return arr, norms


def mac(shapes_a, shapes_b) -> np.ndarray:
    """Modal assurance criterion matrix between two sets of shapes.

    Parameters
    ----------
    shapes_a : array_like of complex, shape (n_points, n_modes_a)
        One shape per column (a 1-D array is one shape), values at the same points and
        directions as ``shapes_b``, any scaling.
    shapes_b : array_like of complex, shape (n_points, n_modes_b)

    Returns
    -------
    ndarray of float, shape (n_modes_a, n_modes_b)
        Always a matrix (also for single shapes), each entry in [0, 1].

    Raises
    ------
    ValueError
        Different numbers of points, non-finite values or a zero shape vector.
    TypeError
        Non-numeric input.

    Examples
    --------
    >>> mac([[1.0], [2.0]], [[-2j, 1.0], [-4j, 0.0]]).round(3)
    array([[1. , 0.2]])
    """
    a, na = _shapes("shapes_a", shapes_a)
    b, nb = _shapes("shapes_b", shapes_b)
    if a.shape[0] != b.shape[0]:
        raise ValueError(f"shapes_a and shapes_b must have the same number of points (rows), "
                         f"got {a.shape[0]} and {b.shape[0]} (shapes {a.shape} and {b.shape})")
    cross = np.abs(a.conj().T @ b) ** 2
    return np.clip(cross / np.outer(na, nb), 0.0, 1.0)


def mpc(shapes) -> np.ndarray:
    """Modal phase collinearity of each shape: 1 for a real (normal) mode, whose points
    move in phase or in antiphase, towards 0 for a complex one.

        MPC = ((S_rr - S_ii)^2 + 4 S_ri^2) / (S_rr + S_ii)^2

    with ``S_rr = sum Re^2``, ``S_ii = sum Im^2``, ``S_ri = sum Re Im`` over the points
    (Pappa, Elliott and Schenk, 1993): the squared ratio of the two principal axes'
    difference to their sum, for the points of the shape in the complex plane. It does not
    depend on the shape's complex scale.

    Parameters
    ----------
    shapes : array_like of complex, shape (n_points, n_modes)
        One shape per column (a 1-D array is one shape).

    Returns
    -------
    ndarray of float, shape (n_modes,)
        Each in [0, 1].

    Raises
    ------
    ValueError
        Non-finite values or a zero shape vector.
    TypeError
        Non-numeric input.

    Examples
    --------
    >>> mpc([[1.0, 1.0], [-2.0, 1j]]).round(3)
    array([1., 0.])
    """
    arr, norms = _shapes("shapes", shapes)
    s_rr = np.sum(arr.real ** 2, axis=0)
    s_ii = np.sum(arr.imag ** 2, axis=0)
    s_ri = np.sum(arr.real * arr.imag, axis=0)
    return np.clip(((s_rr - s_ii) ** 2 + 4.0 * s_ri ** 2) / norms ** 2, 0.0, 1.0)
