"""``FRFData``: one measured (or synthetic) frequency-response function, validated."""

from __future__ import annotations

import warnings

import numpy as np

from ._checks import (as_choice, as_complex_array, as_line_selection, as_nonnegative_scalar,
                      as_positive_scalar, as_real_array, as_real_scalar)
from .model import _rebuild
from .quantities import QUANTITIES, receptance_to, to_receptance

__all__ = ["FRFData"]


def _wrapped_phase(freq_hz, values):
    """``(freq_hz, phase_deg)`` to plot: the phase in [-180, 180] degrees with a NaN
    between two lines where it wraps (a step over 180 degrees), so the plotted line
    breaks there instead of drawing a vertical stroke across the axes.

    Parameters
    ----------
    freq_hz : ndarray, shape (n,)
    values : ndarray of complex, shape (n,)

    Returns
    -------
    freq_hz, phase_deg : ndarray, shape (n + number of wraps,)
    """
    freq_hz = np.asarray(freq_hz, dtype=float)
    phase = np.degrees(np.angle(np.asarray(values)))
    wraps = np.flatnonzero(np.abs(np.diff(phase)) > 180.0) + 1
    return np.insert(freq_hz, wraps, np.nan), np.insert(phase, wraps, np.nan)


class FRFData:
    """A single FRF on a frequency grid; immutable.

    Parameters
    ----------
    freq_hz : array_like of float, shape (n,)
        Frequencies in Hz, finite, non-negative and strictly increasing.
    values : array_like of complex, shape (n,)
        The FRF at ``freq_hz``, in SI units of ``quantity``: receptance m/N,
        mobility (m/s)/N, accelerance (m/s^2)/N.
    quantity : {"receptance", "mobility", "accelerance"}, keyword-only
    coherence : array_like of float, shape (n,), optional
        Ordinary coherence in [0, 1], if measured.
    excitation : array_like of float, shape (n,), optional
        The excitation's autospectrum on the lines (any unit, e.g. a hammer's force
        autospectrum in N^2), finite and non-negative, if recorded. Without coherence
        (one hit) it tells the automatic band of :class:`modalid.ModalFit` where the
        excitation stopped reaching (:func:`modalid._band.choose_band`).
    window_decay_rate : float, optional, keyword-only
        How the FRF was measured: the decay rate ``sigma`` (1/s, finite, >= 0) of an
        exponential window on its records (:attr:`modalid.HammerFRF.window_decay_rate`).
        :class:`modalid.ModalFit` models it unless given its own. ``None`` (default):
        not stated.
    record_length : float, optional, keyword-only
        How the FRF was measured: the length ``T`` (s, finite, > 0) of the records whose
        DFT, without zero padding, gave it (:attr:`modalid.HammerFRF.record_length`);
        :class:`modalid.ModalFit` then takes the record end's effect out. ``None``
        (default): not stated.

    Both travel with the data through :meth:`convert`, :meth:`select`, :meth:`band`, and
    :func:`modalid.write_frf` / :func:`modalid.read_frf` (every format it writes).

    Attributes
    ----------
    freq_hz, values, coherence, excitation : ndarray (read-only)
    window_decay_rate, record_length : float or None
    omega : ndarray
        Angular frequency (rad/s).
    """

    __slots__ = ("_freq_hz", "_values", "_quantity", "_coherence", "_excitation",
                 "_window_decay_rate", "_record_length")
    _freq_hz: np.ndarray
    _values: np.ndarray
    _quantity: str
    _coherence: np.ndarray | None
    _excitation: np.ndarray | None
    _window_decay_rate: float | None
    _record_length: float | None

    def __init__(self, freq_hz, values, *, quantity="receptance", coherence=None,
                 excitation=None, window_decay_rate=None, record_length=None):
        freq_hz = as_real_array("freq_hz", freq_hz, ndim=1)
        values = as_complex_array("values", values, ndim=1)
        as_choice("quantity", quantity, QUANTITIES)
        if freq_hz.shape != values.shape:
            raise ValueError(f"freq_hz and values must have the same length, got "
                             f"{freq_hz.size} and {values.size}")
        if freq_hz.size < 2:
            raise ValueError(f"an FRF needs at least 2 frequency lines, got {freq_hz.size}")
        if freq_hz[0] < 0:
            raise ValueError(f"freq_hz must be non-negative, got {float(freq_hz[0])!r}")
        steps = np.diff(freq_hz)
        if np.any(steps <= 0):
            i = int(np.argmax(steps <= 0))
            raise ValueError(f"freq_hz must be strictly increasing, got {float(freq_hz[i])!r} "
                             f"then {float(freq_hz[i + 1])!r} at index {i}")
        if coherence is not None:
            coherence = as_real_array("coherence", coherence, ndim=1)
            if coherence.shape != freq_hz.shape:
                raise ValueError(f"coherence must have the length of freq_hz ({freq_hz.size}), "
                                 f"got {coherence.size}")
            if np.any((coherence < 0) | (coherence > 1 + 1e-9)):
                bad = coherence[(coherence < 0) | (coherence > 1 + 1e-9)][0]
                raise ValueError(f"coherence must lie in [0, 1], got {bad!r}")
            coherence = np.clip(coherence, 0.0, 1.0)
        if excitation is not None:
            excitation = as_real_array("excitation", excitation, ndim=1)
            if excitation.shape != freq_hz.shape:
                raise ValueError(f"excitation must have the length of freq_hz "
                                 f"({freq_hz.size}), got {excitation.size}")
            if np.any(excitation < 0):
                raise ValueError(f"excitation must be non-negative (an autospectrum), got "
                                 f"{excitation[excitation < 0][0]!r}")
        for name, arr in (("_freq_hz", freq_hz), ("_values", values), ("_coherence", coherence),
                          ("_excitation", excitation)):
            if arr is not None:
                arr = np.array(arr)
                arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "_quantity", quantity)
        if window_decay_rate is not None:
            window_decay_rate = as_nonnegative_scalar("window_decay_rate", window_decay_rate)
        if record_length is not None:
            record_length = as_positive_scalar("record_length", record_length)
        object.__setattr__(self, "_window_decay_rate", window_decay_rate)
        object.__setattr__(self, "_record_length", record_length)

    def __setattr__(self, name, value):
        raise AttributeError(f"FRFData is immutable: cannot set {name!r}")

    def __reduce__(self):
        """Pickle through the constructor (fitted estimators keep their data)."""
        return (_rebuild, (FRFData, self._fields()))

    def _fields(self) -> dict:
        """The constructor's arguments that give this FRF."""
        return dict(freq_hz=self._freq_hz, values=self._values, quantity=self._quantity,
                    coherence=self._coherence, excitation=self._excitation,
                    window_decay_rate=self._window_decay_rate,
                    record_length=self._record_length)

    def _replaced(self, **changes) -> FRFData:
        """This FRF with some of the constructor's arguments changed (the lines, values or
        quantity), the rest (coherence, excitation, how it was measured) kept."""
        return FRFData(**{**self._fields(), **changes})

    freq_hz = property(lambda self: self._freq_hz, doc="Frequencies (Hz).")
    values = property(lambda self: self._values, doc="FRF values (SI units of quantity).")
    quantity = property(lambda self: self._quantity, doc="receptance, mobility or accelerance.")
    coherence = property(lambda self: self._coherence, doc="Coherence, or None.")
    excitation = property(lambda self: self._excitation,
                          doc="The excitation's autospectrum on the lines, or None.")
    window_decay_rate = property(lambda self: self._window_decay_rate,
                                 doc="The records' exponential window (1/s), or None.")
    record_length = property(lambda self: self._record_length,
                             doc="The records' length (s) without zero padding, or None.")

    @property
    def omega(self) -> np.ndarray:
        """Angular frequencies (rad/s)."""
        return 2.0 * np.pi * self._freq_hz

    def __len__(self) -> int:
        return int(self._freq_hz.size)

    def __repr__(self) -> str:
        return (f"FRFData({len(self)} lines, {self._freq_hz[0]:.6g}-{self._freq_hz[-1]:.6g} Hz, "
                f"{self._quantity})")

    # ------------------------------------------------------------------ conversions
    def convert(self, quantity: str) -> FRFData:
        """The same FRF as another quantity.

        Dividing by ``i omega`` is undefined at 0 Hz: a 0 Hz line is dropped, with a
        ``UserWarning`` saying so, when converting towards receptance.

        Parameters
        ----------
        quantity : {"receptance", "mobility", "accelerance"}
            The quantity to convert to.

        Returns
        -------
        FRFData
        """
        as_choice("quantity", quantity, QUANTITIES)
        if quantity == self._quantity:
            return self
        order = {q: i for i, q in enumerate(QUANTITIES)}
        data = self
        if order[quantity] < order[self._quantity] and self._freq_hz[0] == 0.0:
            warnings.warn(f"dropped the 0 Hz line converting {self._quantity} to {quantity}: "
                          "it does not determine the value there", UserWarning, stacklevel=2)
            data = self.select(slice(1, None))
        receptance = to_receptance(data._quantity, data._values, data.omega)
        return data._replaced(values=receptance_to(quantity, receptance, data.omega),
                              quantity=quantity)

    def to_receptance(self) -> FRFData:
        """The FRF as receptance (m/N); see :meth:`convert` for the 0 Hz line.

        Returns
        -------
        FRFData
        """
        return self.convert("receptance")

    def with_measurement(self, *, window_decay_rate=None, record_length=None) -> FRFData:
        """The same FRF stating how it was measured as given (``None``: not stated).

        For an FRF from a file that does not say (another program's export), or to fit
        one as it is: ``frf.with_measurement()`` states nothing.

        Parameters
        ----------
        window_decay_rate : float, optional, keyword-only
            The exponential window's decay rate (1/s, >= 0).
        record_length : float, optional, keyword-only
            The records' length (s, > 0), their DFT not zero-padded.

        Returns
        -------
        FRFData
        """
        return self._replaced(window_decay_rate=window_decay_rate,
                              record_length=record_length)

    def select(self, index) -> FRFData:
        """A subset of the lines (slice, boolean mask or indices).

        Parameters
        ----------
        index : slice, array_like of bool or array_like of int
            The lines to keep.

        Returns
        -------
        FRFData
        """
        index = as_line_selection("index", index, self._freq_hz.size)
        coherence = None if self._coherence is None else self._coherence[index]
        excitation = None if self._excitation is None else self._excitation[index]
        return self._replaced(freq_hz=self._freq_hz[index], values=self._values[index],
                              coherence=coherence, excitation=excitation)

    def band(self, freq_range) -> FRFData:
        """The lines with ``fmin <= freq_hz <= fmax`` (Hz, to a relative 1e-9: the
        rounding of a line's frequency; ``fmax`` may be ``numpy.inf``); an empty band is
        an error.

        Parameters
        ----------
        freq_range : tuple of float
            ``(fmin, fmax)`` (Hz).

        Returns
        -------
        FRFData
        """
        try:
            fmin, fmax = freq_range
        except (TypeError, ValueError) as exc:
            raise TypeError(f"freq_range must be a pair (fmin, fmax) in Hz, got "
                            f"{freq_range!r}") from exc
        fmin = as_real_scalar("freq_range[0]", fmin)
        # an open top (numpy.inf) takes every line above fmin
        open_top = isinstance(fmax, (float, np.floating)) and np.isposinf(fmax)
        fmax = np.inf if open_top else as_real_scalar("freq_range[1]", fmax)
        if fmax <= fmin:
            raise ValueError(f"freq_range must have fmin < fmax, got ({fmin!r}, {fmax!r}) "
                             f"(the data span {self._freq_hz[0]:g}-{self._freq_hz[-1]:g} Hz)")
        # both ends included, to the rounding of a line's frequency (a hammer FRF's
        # 6.99999999999986 Hz line is the 7 Hz one a user names)
        mask = ((self._freq_hz >= fmin - 1e-9 * abs(fmin))
                & (self._freq_hz <= fmax + 1e-9 * abs(fmax)))
        if np.count_nonzero(mask) < 2:
            raise ValueError(f"freq_range ({fmin:g}, {fmax:g}) Hz holds "
                             f"{np.count_nonzero(mask)} lines of the data's "
                             f"{self._freq_hz[0]:g}-{self._freq_hz[-1]:g} Hz: empty band")
        return self.select(mask)

    # ---------------------------------------------------------------------- plots
    def plot(self, ax=None, *, label=None, **kwargs):
        """Magnitude against frequency (Hz) on a log axis; returns the Axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).
        label : str, optional, keyword-only
            Legend label.
        **kwargs
            Passed to ``ax.plot``.

        Returns
        -------
        matplotlib.axes.Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        ax.semilogy(self._freq_hz, np.abs(self._values), label=label, **kwargs)
        units = {"receptance": "m/N", "mobility": "m/s/N", "accelerance": "m/s²/N"}
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel(f"|{self._quantity}| ({units[self._quantity]})")
        return ax

    def plot_phase(self, ax=None, **kwargs):
        """Phase (degrees, in [-180, 180]) against frequency (Hz); returns the Axes.

        The line is broken where the phase wraps (a step over 180 degrees between two
        lines), so a phase near +-180 degrees does not draw vertical strokes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).
        **kwargs
            Passed to ``ax.plot``.

        Returns
        -------
        matplotlib.axes.Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 3))
        ax.plot(*_wrapped_phase(self._freq_hz, self._values), **kwargs)
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("phase (deg)")
        return ax


#: FRF values beyond these magnitudes (in the data's own units) are no measurement: the
#: fit's algebra would overflow or underflow on them
_LARGEST_VALUE, _SMALLEST_VALUE = 1e150, 1e-150


def check_fittable(data: FRFData) -> None:
    """Refuse an FRF whose values are all 0 or beyond any physical scale, naming them.

    Raises
    ------
    ValueError
        All values 0 (nothing to identify), or the largest beyond ``1e150`` or under
        ``1e-150`` (a unit or scaling error; the algebra would overflow).
    """
    peak = float(np.max(np.abs(data.values)))
    if peak == 0.0:
        raise ValueError(f"the FRF ({data.quantity}, {len(data)} lines) is 0 at every line: "
                         "nothing to identify")
    if not _SMALLEST_VALUE <= peak <= _LARGEST_VALUE:
        raise ValueError(f"the FRF's largest value is {peak:.3g} ({data.quantity}, in SI "
                         f"units): beyond any measured scale ({_SMALLEST_VALUE:g} to "
                         f"{_LARGEST_VALUE:g}); check the file's units or scaling")
