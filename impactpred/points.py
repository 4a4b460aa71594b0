"""``PointResponse``: displacement, velocity and acceleration histories at a body's output points.

A body given with outputs (``Body(MultiOutputModalModel)`` or ``Body(Rod(...),
outputs=xi)``) gets one :class:`PointResponse` in :attr:`ImpactResult.points`. Every
output is the displacement of its point along the same axis and sign as that body's
contact displacement (``y1`` for body 1, ``y2`` for body 2, method.md): at the driving point
the output equals ``y1`` (``y2``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from .result import ReadOnlyArrays

__all__ = ["PointResponse", "QUANTITIES"]

#: the three histories of a :class:`PointResponse`, with their units
QUANTITIES = {"displacement": "m", "velocity": "m/s", "acceleration": "m/s^2"}


def _frozen_2d(name, a, shape):
    a = np.array(a, dtype=float, copy=True)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape} (n_points, n_t), got {a.shape}")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False, repr=False)
class PointResponse(ReadOnlyArrays):
    """Motion of one body's output points during and after the impact; immutable.

    Attributes
    ----------
    labels : tuple of str
        One label per output point (the multi-output model's ``outputs``, or
        ``"xi=..."`` for positions on a continuum).
    t : ndarray, shape (n_t,)
        Times (s): the :class:`ImpactResult`'s own ``t``.
    displacement, velocity, acceleration : ndarray, shape (n_points, n_t)
        Histories (m, m/s, m/s^2) of each point along the body's contact axis ``y``.
        Where the contact force has a Dirac impulse the velocity jumps and the
        acceleration has a Dirac part: the samples hold the regular part only (the exact
        solver samples both one-sided limits at its event times, except at ``t = 0`` when
        the contact starts there: then only the state after any impulse). The time-stepping
        solvers sample left limits at ``t_n`` (the force of step ``n - 1`` acting), like
        ``y1`` and ``y2``; see ``method``.
    method : str
        How the histories were obtained and how exact they are.
    """

    labels: tuple
    t: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    method: str = ""

    def __post_init__(self):
        labels = tuple(str(x) for x in self.labels)
        t = np.array(self.t, dtype=float, copy=True)
        if t.ndim != 1:
            raise ValueError(f"t must be 1-D, got shape {t.shape}")
        t.setflags(write=False)
        shape = (len(labels), t.size)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "t", t)
        for name in QUANTITIES:
            object.__setattr__(self, name, _frozen_2d(name, getattr(self, name), shape))

    @property
    def n_points(self) -> int:
        """Number of output points."""
        return len(self.labels)

    def __getitem__(self, label) -> pd.DataFrame:
        """One point's histories (a label or a row index) as a DataFrame indexed by time."""
        i = self._index(label)
        return pd.DataFrame({q: getattr(self, q)[i] for q in QUANTITIES},
                            index=pd.Index(self.t, name="t"))

    def _index(self, label) -> int:
        if isinstance(label, str):
            if label not in self.labels:
                raise KeyError(f"no output point {label!r}; points are {self.labels}")
            return self.labels.index(label)
        if isinstance(label, (int, np.integer)) and not isinstance(label, bool):
            if not -self.n_points <= label < self.n_points:
                raise IndexError(f"point index {label} out of range for {self.n_points} points")
            return int(label) % self.n_points
        raise TypeError(f"a point is a label or an int index, got {label!r}")

    def peaks(self) -> pd.DataFrame:
        """Peak absolute displacement, velocity and acceleration of each point, with times.

        One row per point (index ``point``); columns ``peak_displacement`` (m),
        ``t_peak_displacement`` (s), and likewise for velocity (m/s) and acceleration
        (m/s^2). Sampled values: Dirac parts of the acceleration are not in them.

        Returns
        -------
        pandas.DataFrame
        """
        rows = {}
        for i, label in enumerate(self.labels):
            row = {}
            for q in QUANTITIES:
                values = np.abs(getattr(self, q)[i])
                k = int(np.argmax(values)) if values.size else 0
                row[f"peak_{q}"] = float(values[k]) if values.size else 0.0
                row[f"t_peak_{q}"] = float(self.t[k]) if values.size else 0.0
            rows[label] = row
        table = pd.DataFrame.from_dict(rows, orient="index")
        table.index.name = "point"
        return table

    def to_pandas(self) -> pd.DataFrame:
        """All histories, indexed by time (s), columns ``(quantity, point)`` (a MultiIndex).

        Returns
        -------
        pandas.DataFrame
        """
        data = {(q, label): getattr(self, q)[i]
                for q in QUANTITIES for i, label in enumerate(self.labels)}
        frame = pd.DataFrame(data, index=pd.Index(self.t, name="t"))
        frame.columns = pd.MultiIndex.from_tuples(frame.columns, names=["quantity", "point"])
        return frame

    def plot(self, ax=None, quantity: str = "acceleration"):
        """One quantity of every point against time; returns the Axes.

        In SI units (the axis label says which); the legend in a band above the curves,
        clear of them.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).
        quantity : {"displacement", "velocity", "acceleration"}
            What to draw.

        Returns
        -------
        matplotlib.axes.Axes
        """
        import matplotlib.pyplot as plt

        if quantity not in QUANTITIES:
            raise ValueError(f"quantity must be one of {tuple(QUANTITIES)}, got {quantity!r}")
        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        from ._plot_axes import legend_above_data

        values = getattr(self, quantity)
        for i, label in enumerate(self.labels):
            ax.plot(self.t, values[i], lw=1, label=label)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"{quantity} ({QUANTITIES[quantity]})")
        legend_above_data(ax, *ax.get_legend_handles_labels())
        return ax
