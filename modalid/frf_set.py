"""``FRFSet``: several FRFs of one structure from one input, on a common frequency grid.

A test engineer measures one driving-point FRF and several transfer FRFs (a roving hammer,
or several accelerometers); identified together they share their poles
(:meth:`modalid.ModalFit.fit` with an ``FRFSet``) and their residue rows give the mode
shapes. The rows share one frequency grid: FRFs on different grids are refused, never
silently resampled.
"""

from __future__ import annotations

import warnings

import numpy as np

from ._checks import as_choice, as_complex_array, as_line_selection, as_real_array
from .frf import FRFData
from .model import _rebuild
from .quantities import QUANTITIES, receptance_to, to_receptance

__all__ = ["FRFSet"]


def _labels(outputs, n_outputs):
    """Output labels: ``"0"``, ``"1"``, ... by default; unique strings otherwise."""
    if outputs is None:
        return tuple(str(i) for i in range(n_outputs))
    if isinstance(outputs, str) or not hasattr(outputs, "__len__"):
        raise TypeError(f"outputs must be a sequence of {n_outputs} str labels, got {outputs!r}")
    if len(outputs) != n_outputs:
        raise ValueError(f"outputs must hold {n_outputs} labels (one per row), got "
                         f"{len(outputs)}: {list(outputs)!r}")
    if not all(isinstance(label, str) for label in outputs):
        raise TypeError(f"outputs must be str labels, got {list(outputs)!r}")
    if len(set(outputs)) != n_outputs:
        raise ValueError(f"outputs labels must be unique, got {list(outputs)!r}")
    return tuple(outputs)


def _row_index(output, labels) -> int:
    """Row index of ``output`` (an int index, negative counting from the end, or a label)."""
    n = len(labels)
    if isinstance(output, str):
        if output not in labels:
            raise ValueError(f"no output labelled {output!r}; outputs are {list(labels)}")
        return labels.index(output)
    if isinstance(output, bool) or not isinstance(output, (int, np.integer)):
        raise TypeError(f"output must be an int row index or a str label, got {output!r}")
    if not -n <= output < n:
        raise ValueError(f"output index {int(output)} is out of range for {n} outputs "
                         f"(valid: {-n} to {n - 1}, or a label of {list(labels)})")
    return int(output) % n


class FRFSet:
    """FRFs from one input (the driving point) to several outputs, one grid; immutable.

    Parameters
    ----------
    freq_hz : array_like of float, shape (n_freq,)
        Frequencies in Hz, finite, non-negative and strictly increasing; shared by all rows.
    values : array_like of complex, shape (n_outputs, n_freq)
        The FRFs, in SI units of ``quantity``: receptance m/N, mobility (m/s)/N,
        accelerance (m/s^2)/N.
    quantity : {"receptance", "mobility", "accelerance"}, keyword-only
    coherence : array_like of float, shape (n_outputs, n_freq), optional
        Ordinary coherence in [0, 1] of each row, if measured.
    outputs : sequence of str, optional
        One unique label per row (default ``"0"``, ``"1"``, ...).
    driving_point : int, str or None
        The row (index or label) whose response point is the excitation point; ``None``
        when none of the rows is (then fitting, which needs one, refuses the set).

    Attributes
    ----------
    freq_hz, values, coherence : ndarray (read-only)
    omega : ndarray, shape (n_freq,)
        Angular frequencies (rad/s).
    outputs : tuple of str
    driving_point : int or None
        Row index of the driving point.
    """

    __slots__ = ("_freq_hz", "_values", "_quantity", "_coherence", "_outputs",
                 "_driving_point")
    _freq_hz: np.ndarray
    _values: np.ndarray
    _quantity: str
    _coherence: np.ndarray | None
    _outputs: tuple
    _driving_point: int | None

    def __init__(self, freq_hz, values, *, quantity="receptance", coherence=None,
                 outputs=None, driving_point=0):
        freq_hz = as_real_array("freq_hz", freq_hz, ndim=1)
        values = as_complex_array("values", values)
        as_choice("quantity", quantity, QUANTITIES)
        if values.ndim != 2:
            raise ValueError(f"values must be 2-D, shape (n_outputs, n_freq), got shape "
                             f"{values.shape}")
        if values.shape[0] == 0:
            raise ValueError("an FRFSet needs at least one output row, got 0")
        if values.shape[1] != freq_hz.size:
            raise ValueError(f"values must have one column per frequency line "
                             f"({freq_hz.size}), got shape {values.shape}")
        # the grid is validated once, by FRFData (length, order, sign)
        FRFData(freq_hz, values[0], quantity=quantity)
        if coherence is not None:
            coherence = as_real_array("coherence", coherence)
            if coherence.shape != values.shape:
                raise ValueError(f"coherence must have the shape of values {values.shape}, "
                                 f"got {coherence.shape}")
            bad = (coherence < 0) | (coherence > 1 + 1e-9)
            if np.any(bad):
                i, k = np.argwhere(bad)[0]
                raise ValueError(f"coherence must lie in [0, 1], got {float(coherence[i, k])!r} "
                                 f"(row {i}, {freq_hz[k]:g} Hz)")
            coherence = np.clip(coherence, 0.0, 1.0)
        outputs = _labels(outputs, values.shape[0])
        if driving_point is not None:
            driving_point = _row_index(driving_point, outputs)
        for name, arr in (("_freq_hz", freq_hz), ("_values", values), ("_coherence", coherence)):
            if arr is not None:
                arr = np.array(arr)
                arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "_quantity", quantity)
        object.__setattr__(self, "_outputs", outputs)
        object.__setattr__(self, "_driving_point", driving_point)

    def __setattr__(self, name, value):
        raise AttributeError(f"FRFSet is immutable: cannot set {name!r}")

    def __reduce__(self):
        """Pickle through the constructor (fitted estimators keep their data)."""
        return (_rebuild, (FRFSet, dict(freq_hz=self._freq_hz, values=self._values,
                                        quantity=self._quantity, coherence=self._coherence,
                                        outputs=self._outputs,
                                        driving_point=self._driving_point)))

    freq_hz = property(lambda self: self._freq_hz, doc="Frequencies (Hz), shape (n_freq,).")
    values = property(lambda self: self._values, doc="FRFs, shape (n_outputs, n_freq).")
    quantity = property(lambda self: self._quantity, doc="receptance, mobility or accelerance.")
    coherence = property(lambda self: self._coherence,
                         doc="Coherence (n_outputs, n_freq) or None.")
    outputs = property(lambda self: self._outputs, doc="Output labels, one per row.")
    driving_point = property(lambda self: self._driving_point,
                             doc="Row index of the driving point, or None.")

    @property
    def omega(self) -> np.ndarray:
        """Angular frequencies (rad/s), shape (n_freq,)."""
        return 2.0 * np.pi * self._freq_hz

    @property
    def n_outputs(self) -> int:
        """Number of rows."""
        return int(self._values.shape[0])

    def __len__(self) -> int:
        return int(self._freq_hz.size)

    def __repr__(self) -> str:
        dp = "None" if self._driving_point is None else repr(self._outputs[self._driving_point])
        return (f"FRFSet({self.n_outputs} outputs, {len(self)} lines, "
                f"{self._freq_hz[0]:.6g}-{self._freq_hz[-1]:.6g} Hz, {self._quantity}, "
                f"driving_point={dp})")

    # ------------------------------------------------------------------ rows
    def index(self, output) -> int:
        """Row index of ``output`` (int index or label); ``ValueError`` if out of range.

        Parameters
        ----------
        output : int or str
            Row index or output label.

        Returns
        -------
        int
        """
        return _row_index(output, self._outputs)

    def row(self, output) -> FRFData:
        """One row (index or label) as an :class:`FRFData`.

        Parameters
        ----------
        output : int or str
            Row index or output label.

        Returns
        -------
        FRFData
        """
        i = self.index(output)
        coherence = None if self._coherence is None else self._coherence[i]
        return FRFData(self._freq_hz, self._values[i], quantity=self._quantity,
                       coherence=coherence)

    def require_driving_point(self, purpose="this") -> int:
        """The driving point's row index; ``ValueError`` saying why when it is None.

        Parameters
        ----------
        purpose : str
            What needs the driving point, for the message.

        Returns
        -------
        int
        """
        if self._driving_point is None:
            raise ValueError(f"{purpose} needs a driving point (the row measured at the "
                             f"excitation point) but this FRFSet has driving_point=None; its "
                             f"outputs are {list(self._outputs)}: pass driving_point= (a row "
                             "index or label) when building or reading the set")
        return self._driving_point

    @property
    def driving(self) -> FRFData:
        """The driving-point FRF (``ValueError`` when ``driving_point`` is None)."""
        return self.row(self.require_driving_point("FRFSet.driving"))

    @classmethod
    def from_frfs(cls, frfs, *, driving_point=0, outputs=None) -> FRFSet:
        """Stack :class:`FRFData` of one quantity on one frequency grid.

        Different grids are refused (``ValueError`` naming the rows and how they differ):
        resample them yourself if that is what you mean, this never interpolates.
        Coherence is kept when every row has it; an excitation spectrum
        (``FRFData.excitation``) is not (a set's band comes from its rows' coherence or
        scatter), nor how the rows were measured: a row with an exponential window
        (``FRFData.window_decay_rate``) gets a ``UserWarning``, since the common-pole fit
        does not model it (its poles' decay rates include the window's).

        Parameters
        ----------
        frfs : sequence of FRFData
            One FRF per output, same quantity and frequency lines.
        driving_point : int or None, keyword-only
            Row of the driving point (None: no row is).
        outputs : sequence of str, optional, keyword-only
            One label per row (default ``"0"``, ``"1"``, ...).

        Returns
        -------
        FRFSet
        """
        if not isinstance(frfs, FRFData) and (isinstance(frfs, (str, bytes))
                                              or not hasattr(frfs, "__iter__")):
            raise TypeError(f"frfs must be an FRFData or a list of them, got "
                            f"{type(frfs).__name__}")
        frfs = list(frfs) if not isinstance(frfs, FRFData) else [frfs]
        if not frfs:
            raise ValueError("frfs must hold at least one FRFData, got none")
        for i, frf in enumerate(frfs):
            if not isinstance(frf, FRFData):
                raise TypeError(f"frfs[{i}] must be an FRFData, got {type(frf).__name__}")
        ref = frfs[0]
        for i, frf in enumerate(frfs[1:], start=1):
            if frf.quantity != ref.quantity:
                raise ValueError(f"row {i} is {frf.quantity}, row 0 is {ref.quantity}: "
                                 "convert them to one quantity first (FRFData.convert)")
            why = grid_difference(ref.freq_hz, frf.freq_hz)
            if why:
                raise ValueError(f"rows 0 and {i} are on different frequency grids: {why}. "
                                 "An FRFSet needs one grid; resample or cut the FRFs "
                                 "yourself (FRFData.band/select), nothing is interpolated")
        windowed = sorted({frf.window_decay_rate for frf in frfs if frf.window_decay_rate})
        if windowed:
            warnings.warn(f"the FRFs were measured with an exponential window (decay "
                          f"{', '.join(f'{d:.6g}' for d in windowed)} 1/s): an FRFSet does not "
                          "keep it and its common-pole fit does not model it (every pole's "
                          "decay rate includes the window's: correct_exponential_window "
                          "removes it)", UserWarning, stacklevel=2)
        coherence = None
        if all(frf.coherence is not None for frf in frfs):
            coherence = np.stack([frf.coherence for frf in frfs])
        return cls(ref.freq_hz, np.stack([frf.values for frf in frfs]), quantity=ref.quantity,
                   coherence=coherence, outputs=outputs, driving_point=driving_point)

    # ------------------------------------------------------------------ conversions
    def _new(self, freq_hz, values, quantity, coherence):
        return FRFSet(freq_hz, values, quantity=quantity, coherence=coherence,
                      outputs=self._outputs, driving_point=self._driving_point)

    def convert(self, quantity: str) -> FRFSet:
        """The same FRFs as another quantity (a 0 Hz line is dropped towards receptance,
        with a ``UserWarning``, as :meth:`FRFData.convert`).

        Parameters
        ----------
        quantity : {"receptance", "mobility", "accelerance"}
            The quantity to convert to.

        Returns
        -------
        FRFSet
        """
        as_choice("quantity", quantity, QUANTITIES)
        if quantity == self._quantity:
            return self
        data = self
        if (QUANTITIES.index(quantity) < QUANTITIES.index(self._quantity)
                and self._freq_hz[0] == 0.0):
            warnings.warn(f"dropped the 0 Hz line converting {self._quantity} to {quantity}: "
                          "it does not determine the value there", UserWarning, stacklevel=2)
            data = self.select(slice(1, None))
        receptance = to_receptance(data._quantity, data._values, data.omega)
        return self._new(data._freq_hz, receptance_to(quantity, receptance, data.omega),
                         quantity, data._coherence)

    def to_receptance(self) -> FRFSet:
        """The FRFs as receptance (m/N); see :meth:`convert` for the 0 Hz line.

        Returns
        -------
        FRFSet
        """
        return self.convert("receptance")

    def select(self, index) -> FRFSet:
        """A subset of the frequency lines (slice, boolean mask or indices), all rows.

        Parameters
        ----------
        index : slice, array_like of bool or array_like of int
            The lines to keep.

        Returns
        -------
        FRFSet
        """
        index = as_line_selection("index", index, self._freq_hz.size)
        coherence = None if self._coherence is None else self._coherence[:, index]
        return self._new(self._freq_hz[index], self._values[:, index], self._quantity,
                         coherence)

    def band(self, freq_range) -> FRFSet:
        """The lines with ``fmin <= freq_hz <= fmax`` (Hz), all rows.

        Parameters
        ----------
        freq_range : tuple of float
            ``(fmin, fmax)`` (Hz).

        Returns
        -------
        FRFSet
        """
        mask = np.isin(self._freq_hz, self.row(0).band(freq_range).freq_hz)
        return self.select(mask)

    # ---------------------------------------------------------------------- plots
    def plot(self, ax=None, *, outputs=None, **kwargs):
        """Magnitudes against frequency (Hz), one line per row (or the ``outputs`` given);
        returns the Axes. The driving point is drawn thicker.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).
        outputs : sequence of int or str, optional, keyword-only
            The rows to draw (all when None).
        **kwargs
            Passed to ``ax.plot``.

        Returns
        -------
        matplotlib.axes.Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        rows = range(self.n_outputs) if outputs is None else [self.index(o) for o in outputs]
        for i in rows:
            label = self._outputs[i] + (" (driving point)" if i == self._driving_point else "")
            lw = 1.6 if i == self._driving_point else 1.0
            self.row(i).plot(ax=ax, label=label, lw=lw, **kwargs)
        ax.legend(fontsize=8)
        return ax


def grid_difference(reference, other) -> str:
    """How two frequency grids (Hz) differ, in words; ``""`` when they are identical
    (to 1e-9 of the larger spacing)."""
    reference, other = np.asarray(reference, float), np.asarray(other, float)
    if reference.size != other.size:
        return (f"{reference.size} lines {reference[0]:g}-{reference[-1]:g} Hz against "
                f"{other.size} lines {other[0]:g}-{other[-1]:g} Hz")
    step = max(np.max(np.diff(reference)), np.max(np.diff(other)))
    diff = np.abs(reference - other)
    if np.all(diff <= 1e-9 * step):
        return ""
    k = int(np.argmax(diff > 1e-9 * step))
    return (f"line {k} is at {float(reference[k])!r} Hz in one and {float(other[k])!r} Hz in "
            f"the other "
            f"({np.count_nonzero(diff > 1e-9 * step)} of {reference.size} lines differ)")
