"""FRF quantities: receptance (m/N), mobility (m/s/N) and accelerance (m/s^2/N).

The project's internal form is receptance. For ``s = i*omega``:
mobility = ``i*omega * receptance``, accelerance = ``-omega**2 * receptance``.
"""

from __future__ import annotations

import numpy as np

from ._checks import as_choice

__all__ = ["QUANTITIES", "receptance_to", "to_receptance"]

QUANTITIES = ("receptance", "mobility", "accelerance")


def _operands(name, values, omega):
    """``(values, omega)`` as complex and float arrays that broadcast, ``omega`` finite;
    refused naming the argument otherwise (numpy's own message named neither)."""
    if omega is None:
        raise TypeError("omega must be an array of angular frequencies (rad/s), got None")
    try:
        omega = np.asarray(omega, dtype=float)
        values = np.asarray(values, dtype=complex)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} and omega must be numeric arrays: {exc}") from None
    if not np.all(np.isfinite(omega)):
        raise ValueError("omega must be finite (rad/s), got a NaN or infinite value")
    try:
        np.broadcast_shapes(values.shape, omega.shape)
    except ValueError:
        raise ValueError(f"{name} (shape {values.shape}) and omega (shape {omega.shape}) do "
                         "not broadcast: give one value per frequency") from None
    return values, omega


def receptance_to(quantity: str, receptance, omega) -> np.ndarray:
    """Convert receptance values (m/N) at angular frequencies ``omega`` (rad/s).

    Parameters
    ----------
    quantity : {"receptance", "mobility", "accelerance"}
    receptance : array_like of complex
        Receptance at ``omega``; broadcast against ``omega``.
    omega : array_like of float
        Angular frequency in rad/s.

    Returns
    -------
    numpy.ndarray of complex
        The values in ``quantity`` (m/N, m/(N s) or m/(N s^2)).
    """
    as_choice("quantity", quantity, QUANTITIES)
    receptance, omega = _operands("receptance", receptance, omega)
    iw = 1j * omega
    if quantity == "receptance":
        return receptance
    if quantity == "mobility":
        return iw * receptance
    return iw * iw * receptance


def to_receptance(quantity: str, values, omega) -> np.ndarray:
    """Convert mobility or accelerance values to receptance (m/N).

    At ``omega = 0`` a mobility or accelerance carries no information about the
    receptance (it is divided by zero): a ``ValueError`` names the case instead of
    returning ``inf``/``nan``. Drop the 0 Hz line or convert it by a model.

    Parameters
    ----------
    quantity : {"receptance", "mobility", "accelerance"}
        What ``values`` are.
    values : array_like of complex
        The FRF values (m/N, m/(N s) or m/(N s^2)); broadcast against ``omega``.
    omega : array_like of float
        Angular frequency (rad/s).

    Returns
    -------
    numpy.ndarray of complex
        Receptance (m/N).
    """
    as_choice("quantity", quantity, QUANTITIES)
    values, omega = _operands("values", values, omega)
    if quantity == "receptance":
        return values
    if np.any(omega == 0.0):
        raise ValueError(f"cannot convert {quantity} to receptance at omega = 0 rad/s: "
                         "the receptance there is not determined by the data")
    iw = 1j * omega
    return values / iw if quantity == "mobility" else values / (iw * iw)
