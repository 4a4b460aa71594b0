"""The exact effect of an exponential window and of the record's end on a pole-residue FRF.

An impact test records the response for a time ``T`` (the record length) and usually
multiplies both channels by ``w(t) = exp(-sigma t)``; :func:`modalid.frf_from_hammer`
reports the windowed quantity ``Q = s^k H`` (``k = 0, 1, 2``: displacement, velocity,
acceleration) times ``(i omega / (i omega + sigma))^k``, whose receptance form is
``Q_w / x^k`` with ``x = i omega + sigma``. For ``H(s) = sum_k r_k/(s - p_k) + conj.
+ u/s^2 + D`` hit at ``t = 0``, on the DFT lines ``omega_j = 2 pi j / T`` (no zero
padding, so ``exp(-i omega_j T) = 1``), that receptance form is exactly::

    sum_k c_k r_k / (x - p_k) + conj.  +  c_0 u / x^2  +  D  +  sum_{j=1..k} A_j / x^j

* every pole moves to ``p_k - sigma`` (the shift theorem) and the record's end cuts each
  windowed free decay, scaling its residue by ``c_k = 1 - exp((p_k - sigma) T)``;
* the rigid line's cut: ``c_0 = 1 - exp(-sigma T)`` for a velocity (a constant cut at
  ``T``) or displacement record, 1 for an acceleration (zero after the hit); a
  displacement record's cut ramp adds ``-u T exp(-sigma T) / x`` too;
* ``A_j = sum 2 Re(r_k p_k^(j-1) exp((p_k - sigma) T))`` (real poles alike): what the cut
  removes from the instantaneous terms of the derivatives, of the order ``exp(-sigma T)``
  of the first modes' residues.

All of it is exact for an impulse at ``t = 0``; a hit at ``t_0`` with a pulse short
against the modes' periods multiplies the second term of ``c_k`` by
``exp(-Re(p_k - sigma) t_0)`` (``1 + 0.035`` for a hit at 1 % of a 1 %-window record:
``3.5e-4`` of that mode's residue). :class:`modalid.ModalFit` (``window_decay_rate``,
``record_length``) fits the poles, ``c_k r_k``, ``c_0 u`` and ``D`` and divides the
factors out; it neglects the ``A_j`` and the displacement ramp's term.
"""

from __future__ import annotations

import numpy as np

from .model import ModalModel

__all__ = ["truncation_factors", "unwindow", "windowed_receptance"]


def truncation_factors(windowed_poles, record_length):
    """``1 - exp(p_w T)`` for windowed poles ``p_w`` (rad/s) and record length ``T`` (s)."""
    return 1.0 - np.exp(np.asarray(windowed_poles) * record_length)


#: power ``k`` of ``s`` in each measured quantity ``Q = s^k H``
_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}


def _rigid_factor(decay_rate, record_length, quantity):
    if record_length is None or _POWER[quantity] == 2:
        return 1.0
    c0 = float(-np.expm1(-decay_rate * record_length))
    if c0 <= 0.0:
        raise ValueError("a rigid-body line cannot be measured without an exponential window "
                         "(decay_rate 0): the constant velocity after the hit has no content "
                         "on the DFT lines above 0 Hz")
    return c0


def unwindow(model: ModalModel, decay_rate: float, record_length=None, *,
             quantity: str = "mobility") -> ModalModel:
    """The structure's model from ``model`` fitted to a windowed, truncated FRF.

    ``model`` holds the windowed poles ``p_w`` and residues (its rigid term meaning
    ``inverse_mass/(s + decay_rate)^2``); the result has the poles ``p_w + decay_rate``,
    and, with ``record_length``, the residues divided by :func:`truncation_factors` and
    the inverse mass by the rigid line's factor for the measured ``quantity`` (module
    docstring). ``flexibility`` is unchanged (an instantaneous term is neither shifted
    nor cut).
    """
    residues, real_residues = model.residues, model.real_residues
    inverse_mass = model.inverse_mass
    if record_length is not None:
        residues = residues / truncation_factors(model.poles, record_length)
        real_residues = real_residues / truncation_factors(model.real_poles, record_length)
        if inverse_mass:
            inverse_mass = inverse_mass / _rigid_factor(decay_rate, record_length, quantity)
    return ModalModel(poles=model.poles + decay_rate, residues=residues,
                      real_poles=model.real_poles + decay_rate, real_residues=real_residues,
                      inverse_mass=inverse_mass, flexibility=model.flexibility)


def windowed_receptance(model: ModalModel, omega, decay_rate: float, record_length=None, *,
                        quantity: str = "mobility"):
    """The receptance form of what an exponentially windowed test of ``model`` measures.

    Parameters
    ----------
    model : ModalModel
        The structure (receptance, m/N).
    omega : array_like of float
        Angular frequencies (rad/s), DFT lines ``2 pi j / T`` when ``record_length`` is
        given (the record's end acts as the module docstring says there only).
    decay_rate : float
        The window's decay rate ``sigma`` (1/s), >= 0.
    record_length : float, optional
        ``T`` (s); ``None`` for an untruncated record (then ``H(i omega + sigma)``).
    quantity : {"receptance", "mobility", "accelerance"}
        What was recorded: displacement, velocity or acceleration.

    Returns
    -------
    ndarray of complex
        The FRF :func:`modalid.frf_from_hammer` reports, in receptance form (m/N): the
        module docstring's sum, exact for a hit at ``t = 0``.
    """
    iw = 1j * np.asarray(omega, dtype=float)
    x = iw + decay_rate
    poles, real_poles = model.poles - decay_rate, model.real_poles - decay_rate
    residues, real_residues = model.residues, model.real_residues
    extra = np.zeros(iw.shape, dtype=complex)
    if record_length is not None:
        cut, cut_real = (1.0 - truncation_factors(poles, record_length),
                         1.0 - truncation_factors(real_poles, record_length))
        for j in range(1, _POWER[quantity] + 1):
            a_j = (2.0 * np.sum((residues * model.poles ** (j - 1) * cut).real)
                   + np.sum(real_residues * model.real_poles ** (j - 1) * cut_real))
            extra += a_j / x**j
        if quantity == "receptance" and model.inverse_mass:
            extra -= model.inverse_mass * record_length * np.exp(-decay_rate * record_length) / x
        residues, real_residues = residues * (1.0 - cut), real_residues * (1.0 - cut_real)
    col = iw[..., None]
    out = np.full(iw.shape, model.flexibility, dtype=complex) + extra
    if poles.size:
        out += np.sum(residues / (col - poles) + residues.conj() / (col - poles.conj()),
                      axis=-1)
    if real_poles.size:
        out += np.sum(real_residues / (col - real_poles), axis=-1)
    if model.inverse_mass:
        out += model.inverse_mass * _rigid_factor(decay_rate, record_length, quantity) / x**2
    return out
