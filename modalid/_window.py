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
* ``A_j = sum_k 2 Re(r_k p_k^(j-1) exp((p_k - sigma) T)) + sum_real a p^(j-1) exp((p -
  sigma) T)`` (each real pole once): what the cut removes from the instantaneous terms of
  the derivatives, of the order ``exp(-sigma T)`` of the first modes' residues. ``A_2``
  and an acceleration's rigid line are both ``1/x^2``: a fit reads ``u + A_2``.

All of it is exact for an impulse at ``t = 0``; a hit at ``t_0`` with a pulse short
against the modes' periods multiplies the second term of ``c_k`` by
``exp(-Re(p_k - sigma) t_0)`` (``1 + 0.035`` for a hit at 1 % of a 1 %-window record:
``3.5e-4`` of that mode's residue), and turns the terms below by ``omega t_0``
(:func:`modalid.frf_from_hammer` therefore cuts an unwindowed hit's records five pulse
widths before it: a hit at 5 % of such a record put a fixed rod's predicted restitution
0.03-0.06 too high, cut 0.006-0.010). :class:`modalid.ModalFit` (``window_decay_rate``,
``record_length``) fits the poles, ``c_k r_k``, ``c_0 u`` and ``D``, divides the factors
out and takes ``A_2`` out of an acceleration's mass line; the other ``A_j`` it computes
from a first fit's modes, takes out of the data and fits again where they are more than
1 % of the band's lowest lines (:mod:`modalid._record_end`); it neglects the displacement
ramp's term.

A fit's pseudo-modes (the band's lower and upper residual poles) describe the windowed
data over the band, not free decays the record's end cut: the record-end transforms take
a mask ``cut`` of the poles they act on (``None``: all), and :func:`structure_model`
leaves the pseudo-modes out (only the window's shift is undone on them). Dividing by
``c_k`` a pseudo-mode that sat near 0 Hz or on a DFT line, all but undamped, turned it into
a term 80 times the fit's (a real one-hit record fitted from 3 Hz with its record length:
a residue of 939 at 0.002 Hz and an FRF error of 3e8 %).
"""

from __future__ import annotations

import numpy as np

from ._checks import as_choice, as_nonnegative_scalar, as_positive_scalar
from ._lsfd import evaluate
from .model import ModalModel

__all__ = ["a2_unmodelled", "check_record_lines", "nonnegative_mass_line", "record_end_terms",
           "rigid_factor",
           "structure_model", "truncation_factors", "unmodelled_record_end", "unwindow",
           "windowed_receptance"]

#: the most ``sigma T`` an exponential window can have: ``exp(-700)`` is near the end of
#: double precision (``exp(-745)`` is 0), nothing of the record is left; a rate in the
#: wrong unit (1/ms for 1/s: a thousand times), not a window
MOST_WINDOW_DECAY = 700.0

#: the share of the data at the band's lowest lines above which the record end's terms
#: a fit does not model make it "suspect" (:func:`unmodelled_record_end`)
UNMODELLED_LIMIT = 0.2


def check_record_lines(freq_hz, record_length) -> None:
    """Refuse a ``record_length`` ``T`` (s) whose DFT lines ``k / T`` the data's lines
    (``freq_hz``, Hz, > 0) are not on, to 1e-3 of a line: the record-end model holds on
    those lines only (module docstring). A zero-padded FFT's lines, or a mistyped ``T``
    (1e-9 s for lines 0.01 Hz apart), were fitted with it silently."""
    k = np.asarray(freq_hz, dtype=float) * record_length
    off = np.where(np.round(k) >= 1, np.abs(k - np.round(k)), 1.0)   # below line 1: off
    if np.max(off) > 1e-3:
        i = int(np.argmax(off))
        raise ValueError(f"record_length={record_length!r} s puts the DFT lines at multiples "
                         f"of {1 / record_length:.6g} Hz, and the data's line "
                         f"{float(np.ravel(freq_hz)[i]):.6g} Hz is not on one: give the "
                         "length of the record the FFT took (not zero-padded), or leave "
                         "record_length out")


def truncation_factors(windowed_poles, record_length):
    """``1 - exp(p_w T)`` for windowed poles ``p_w`` (rad/s) and record length ``T`` (s)."""
    return 1.0 - np.exp(np.asarray(windowed_poles) * record_length)


#: power ``k`` of ``s`` in each measured quantity ``Q = s^k H``
_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}


def _checked(decay_rate, record_length, quantity):
    as_choice("quantity", quantity, tuple(_POWER))
    decay_rate = as_nonnegative_scalar("decay_rate", decay_rate)
    if record_length is not None:
        record_length = as_positive_scalar("record_length", record_length)
    return decay_rate, record_length


def _cut_mask(model: ModalModel, cut):
    """``cut`` as a boolean mask over ``model``'s complex poles (``None``: all)."""
    if cut is None:
        return np.ones(model.poles.size, bool)
    cut = np.asarray(cut)
    if cut.dtype != bool or cut.shape != model.poles.shape:
        raise ValueError(f"cut must be a boolean mask of shape {model.poles.shape} (one per "
                         f"complex pole), got dtype {cut.dtype} and shape {cut.shape}")
    return cut


def _cut_sums(model: ModalModel, decay_rate, record_length, j, cut):
    """``A_j`` of the module docstring for the structure ``model``, over the complex poles
    ``cut`` (boolean mask) and every real pole."""
    decays = np.where(cut, np.exp((model.poles - decay_rate) * record_length), 0.0)
    cut_real = np.exp((model.real_poles - decay_rate) * record_length)
    return float(2.0 * np.sum((model.residues * model.poles ** (j - 1) * decays).real)
                 + np.sum(model.real_residues * model.real_poles ** (j - 1) * cut_real))


def rigid_factor(decay_rate, record_length, quantity):
    """``c_0``: the record's end's factor on the rigid line (module docstring)."""
    if record_length is None or _POWER[quantity] == 2:
        return 1.0
    c0 = float(-np.expm1(-decay_rate * record_length))
    if c0 <= 0.0:
        raise ValueError("a rigid-body line cannot be measured without an exponential window "
                         "(decay_rate 0): the constant velocity after the hit has no content "
                         "on the DFT lines above 0 Hz")
    return c0


def unwindow(model: ModalModel, decay_rate: float, record_length=None, *,
             quantity: str = "mobility", cut=None, a2_removed=False) -> ModalModel:
    """The structure's model from ``model`` fitted to a windowed, truncated FRF.

    ``model`` holds the windowed poles ``p_w`` and residues (its rigid term meaning
    ``inverse_mass/(s + decay_rate)^2``); the result has the poles ``p_w + decay_rate``,
    and, with ``record_length``, the residues divided by :func:`truncation_factors` and
    the inverse mass by the rigid line's factor for the measured ``quantity`` (module
    docstring). ``flexibility`` is unchanged (an instantaneous term is neither shifted
    nor cut). ``cut`` (boolean, one per complex pole; default all): the poles the record's
    end acts on; the others (pseudo-modes) are only shifted. ``a2_removed``: an
    acceleration's ``A_2`` was taken out of the data, so the mass line does not hold it.
    """
    decay_rate, record_length = _checked(decay_rate, record_length, quantity)
    cut = _cut_mask(model, cut)
    residues, real_residues = model.residues, model.real_residues
    inverse_mass = model.inverse_mass
    if record_length is not None:
        residues = residues / np.where(cut, truncation_factors(model.poles, record_length),
                                       1.0)
        real_residues = real_residues / truncation_factors(model.real_poles, record_length)
    out = ModalModel(poles=model.poles + decay_rate, residues=residues,
                     real_poles=model.real_poles + decay_rate, real_residues=real_residues,
                     flexibility=model.flexibility)
    if record_length is not None and inverse_mass:
        if _POWER[quantity] == 2 and not a2_removed:   # the fit read u + A_2 (docstring)
            inverse_mass -= _cut_sums(out, decay_rate, record_length, 2, cut)
        inverse_mass /= rigid_factor(decay_rate, record_length, quantity)
    return out.replace(inverse_mass=inverse_mass)


def windowed_receptance(model: ModalModel, omega, decay_rate: float, record_length=None, *,
                        quantity: str = "mobility", cut=None):
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
    cut : array_like of bool, optional
        One per complex pole of ``model``: the free decays the record's end cuts (default
        all); the others (a fit's pseudo-modes, :func:`structure_model`) are only shifted.

    Returns
    -------
    ndarray of complex
        The FRF :func:`modalid.frf_from_hammer` reports, in receptance form (m/N): the
        module docstring's sum, exact for a hit at ``t = 0``.
    """
    decay_rate, record_length = _checked(decay_rate, record_length, quantity)
    cut = _cut_mask(model, cut)
    omega = np.asarray(omega, dtype=float)
    w = omega.ravel()
    x = 1j * w + decay_rate
    poles, real_poles = model.poles - decay_rate, model.real_poles - decay_rate
    residues, real_residues = model.residues, model.real_residues
    extra = np.zeros(w.shape, dtype=complex)
    if record_length is not None:
        for j in range(1, _POWER[quantity] + 1):
            extra += _cut_sums(model, decay_rate, record_length, j, cut) / x**j
        if quantity == "receptance" and model.inverse_mass:
            extra -= model.inverse_mass * record_length * np.exp(-decay_rate * record_length) / x
        residues = residues * np.where(cut, truncation_factors(poles, record_length), 1.0)
        real_residues = real_residues * truncation_factors(real_poles, record_length)
    rigid = (model.inverse_mass * rigid_factor(decay_rate, record_length, quantity)
             if model.inverse_mass else 0.0)
    out = evaluate(w, poles, residues, real_poles, real_residues, rigid, model.flexibility,
                   rigid_shift=decay_rate) + extra
    return out.reshape(omega.shape)


def structure_model(model, kinds, *, decay_rate, record_length, quantity, min_damping=1e-5,
                    data=None, removed=None):
    """The structure's model from a fit ``model`` of windowed data, and what was done.

    ``kinds``: each pole's kind (``"far"`` pseudo-modes are not held); ``decay_rate``
    (1/s), ``record_length`` (s, or None): the window's and the record's; ``quantity``:
    the data's. A pole whose damping the window's removal would leave under
    ``min_damping`` (noise in the windowed damping) is held at ``min_damping``: the
    structure is passive; ``window_clipped`` counts them. The hold is applied to the
    windowed pole before the record's end is divided out: a windowed pole that does not
    decay within the record and sits on a line (a pseudo-mode on its bound at a multiple
    of the band top) has a truncation factor ``1 - exp(p_w T)`` near 0 (1.4e-4 for the
    ball's cantilever at 20 modes, 5 % noise, run 16), and dividing by it turned the
    pseudo-mode into a static compliance of 1.5e-6 m/N where the omitted modes hold
    about 2e-10: a soft spring under the contact.

    Only the physical poles (kind ``"mode"``) are taken as free decays the record's end
    cut; the pseudo-modes keep their fitted residues (module docstring).

    Returns ``(model, info)``: ``info`` holds ``window_decay_rate``, ``record_length``,
    ``window_clipped``, ``truncation_factors`` (per pole, 1 for a pseudo-mode),
    ``rigid_factor`` and ``record_cut`` (the mask to re-window ``model`` with:
    :func:`windowed_receptance`'s ``cut``); with ``data`` (the band fitted, an ``FRFData``)
    ``record_end_unmodelled`` (:func:`unmodelled_record_end`). ``removed``: ``(freq_hz,
    terms, with_a2)``, the record end's terms taken out of the data before the fit
    (``record_end_gone``: those on the band's lines, with ``data``)
    (:func:`modalid._record_end.refit_without_record_end`; ``with_a2``: an acceleration's
    ``A_2`` among them, which a mass line then no longer holds).
    """
    sigma, length = decay_rate, record_length
    windowed = model.poles
    limit = -min_damping * np.abs(windowed + sigma)
    clipped = ((windowed + sigma).real > limit) & (kinds != "far")
    model = model.replace(poles=np.where(clipped, limit - sigma + 1j * windowed.imag,
                                         windowed))
    cut = np.asarray(kinds) == "mode"
    factors = (np.ones(model.poles.size) if length is None
               else np.where(cut, truncation_factors(model.poles, length), 1.0))
    try:
        out = unwindow(model, sigma, length, quantity=quantity, cut=cut,
                       a2_removed=bool(removed is not None and removed[2]))
    except ValueError as exc:        # a rigid line with record_length and no window
        raise ValueError(f"ModalFit(window_decay_rate={sigma!r}, record_length={length!r}) "
                         f"found a rigid body: {exc}") from None
    gone = (None if removed is None or data is None
            else removed[1][np.isin(removed[0], data.freq_hz)])
    info = {} if data is None else {"record_end_gone": 0.0 if gone is None else gone}
    unmodelled = None if data is None else unmodelled_record_end(
        out, data.omega, data.values, decay_rate=sigma, record_length=length,
        quantity=quantity, cut=cut, removed=gone)
    return out, {"window_decay_rate": sigma, "record_length": length,
                 "window_clipped": int(np.sum(clipped)), "truncation_factors": factors,
                 "record_cut": cut, "record_end_unmodelled": unmodelled, **info,
                 "rigid_factor": (rigid_factor(sigma, length, quantity)
                                  if model.inverse_mass else 1.0)}


def a2_unmodelled(model: ModalModel, quantity) -> bool:
    """Whether an acceleration record's ``A_2 / x^2`` is left to :func:`record_end_terms`:
    ``model`` has no mass line to take it (module docstring)."""
    return _POWER[quantity] == 2 and not model.inverse_mass


def record_end_terms(model: ModalModel, omega, *, decay_rate, record_length, quantity, cut):
    """The record end's terms a fit does not model (module docstring), in the data's own
    quantity on ``omega`` (rad/s; 0 at omega = 0): ``x^k A_1 / x`` of a velocity or
    acceleration record and, where ``model`` has no mass line to take it, an
    acceleration's ``A_2``; zeros for a displacement record.

    ``model``: the structure's (:func:`structure_model`), ``cut`` its physical poles.
    """
    omega = np.asarray(omega, dtype=float)
    k = _POWER[quantity]
    out = np.zeros(omega.shape, complex)
    if k == 0:
        return out
    x = 1j * omega[omega > 0] + decay_rate
    terms = _cut_sums(model, decay_rate, record_length, 1, cut) / x
    if a2_unmodelled(model, quantity):
        terms = terms + _cut_sums(model, decay_rate, record_length, 2, cut) / x**2
    out[omega > 0] = terms * x**k
    return out


def unmodelled_record_end(model: ModalModel, omega, values, *, decay_rate, record_length,
                          quantity, cut, removed=None):
    """How much of the data at the band's lowest lines are record-end terms a fit does
    not model (:func:`record_end_terms`, less ``removed``: those taken out of the data
    before the fit, on the same lines), over the data ``values`` (on ``omega``, rad/s):
    their median over the band's lines below its first physical mode (the five lowest at
    most; the five lowest lines where none lies below).

    They matter where a mode has not died out within the record: a fixed rod's 250 Hz
    mode at zeta 1e-3 in a 1 s unwindowed acceleration record puts 45-200 % of the data
    on the band's lowest lines (74 Hz and up), which a fit stands a 2.5 kg pseudo-mode at
    0.05 Hz in for: a free mass on a fixed rod, restitution 0.22 for 0.69. With a window
    ending at 1 %: 2-4 %; the real five hits unwindowed: 0.2-0.7 %.

    Returns
    -------
    float or None
        The share; ``None`` without ``record_length`` or for a displacement record.
    """
    if record_length is None or _POWER[quantity] == 0:
        return None
    omega = np.asarray(omega, dtype=float)
    terms = record_end_terms(model, omega, decay_rate=decay_rate, record_length=record_length,
                             quantity=quantity, cut=cut)
    if removed is not None:
        terms = terms - removed
    values = np.asarray(values)
    physical = np.abs(model.poles[cut])
    lines = np.flatnonzero((values != 0) & np.isfinite(values))  # a zero line says nothing
    if not lines.size:
        raise ValueError("the band's data are zero or not finite at every line")
    low = lines[omega[lines] < physical.min()][:5] if physical.size else lines[:0]
    if not low.size:
        low = lines[:5]
    return float(np.median(np.abs(terms[low]) / np.abs(values[low])))


def nonnegative_mass_line(model: ModalModel):
    """``(model, notes)``: a driving point's ``model`` with a negative mass line set to 0.

    An acceleration's mass line, less the record end's ``A_2`` computed from the modes
    (:func:`unwindow`), holds that estimate's error: a fixed rod's unwindowed hits at
    1e-3 noise left -0.048 +- 0.015 1/kg, and the fit of a driving point was refused as
    a transfer FRF (negative mass line). A driving point's mass line (a rigid body, or
    the modes below the band) is not negative.
    """
    if not model.inverse_mass < 0:
        return model, []
    return model.replace(inverse_mass=0.0), [
        f"the mass line less the record end's A_2 ({model.inverse_mass:.4g} 1/kg) set to 0: "
        "a driving point's is not negative"]
