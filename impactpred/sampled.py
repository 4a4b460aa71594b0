"""A driving-point impulse response known only by samples (a measured one)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from modalid.receptance import TimeScale
from modalid.validation import as_real_array, as_real_scalar

from .result import ReadOnlyArrays

__all__ = ["SampledResponse"]

#: a record's second half whose straight-line trend rises by more than this many times
#: the scatter about it drifts (a free body's rigid motion, ``h -> t / M``)
DRIFT_OVER_SCATTER = 4.0


@dataclass(frozen=True, eq=False, repr=False)
class SampledResponse(ReadOnlyArrays):
    """A driving-point impulse response known only by samples (e.g. measured).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times (s), strictly increasing, starting at 0.
    impulse_response : array_like, shape (n,)
        ``h(t)`` in m/(N s): the complete response, rigid-body drift included.
    inverse_mass : float, optional
        ``1/M`` (1/kg) of the rigid-body part already contained in ``h`` (0 for a
        grounded body); used for restitution and energy bookkeeping only.

    Notes
    -----
    The step response is the trapezoidal integral of the samples, linear between them;
    it is exact for a piecewise-linear ``h``. The record must cover the whole solve:
    nothing is extrapolated beyond ``t[-1]``.
    """

    t: Any
    impulse_response: Any
    inverse_mass: float = 0.0

    def __post_init__(self):
        t = as_real_array("t", self.t, ndim=1)
        h = as_real_array("impulse_response", self.impulse_response, ndim=1)
        if t.shape != h.shape:
            raise ValueError(f"t and impulse_response must have the same shape, got "
                             f"{t.shape} and {h.shape}")
        if t.size < 2 or t[0] != 0.0:
            raise ValueError(f"t must start at 0 and hold at least 2 samples, got "
                             f"{t.size} samples starting at {t[0] if t.size else None!r}")
        if np.any(np.diff(t) <= 0):
            raise ValueError("t must be strictly increasing")
        step = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (h[1:] + h[:-1]))])
        for name, value in (("t", t), ("impulse_response", h), ("_step", step)):
            value = np.array(value)
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "inverse_mass", as_real_scalar("inverse_mass", self.inverse_mass))
        if self.inverse_mass < 0:
            raise ValueError(f"inverse_mass must be non-negative, got {self.inverse_mass!r}")
        _warn_of_drift(t, h, self.inverse_mass)

    @property
    def duration(self) -> float:
        """Length of the record (s)."""
        return float(self.t[-1])

    # ----------------------------------------- receptance interface (modalid.receptance)
    is_rational = property(lambda self: False, doc="Always False: no poles are known.")

    def elastic_flexibility(self) -> float:
        """Not known from a finite record: raises ``ValueError``."""
        raise ValueError("a SampledResponse has no static flexibility: the record does not "
                         "reach s = 0")

    def time_scales(self) -> tuple:
        """``(TimeScale(smallest sample step, "sample"),)`` (s).

        Returns
        -------
        tuple of modalid.receptance.TimeScale
        """
        return (TimeScale(float(np.min(np.diff(self.t))), "sample"),)

    def modal_form(self, n_modes=None):
        """Raises ``ValueError``: a sampled response has no pole-residue form.

        Parameters
        ----------
        n_modes : int, optional
            Ignored.
        """
        raise ValueError("a SampledResponse has no modal model: identify one with modalid")

    def step_response(self, t) -> np.ndarray:
        """Trapezoidal step response (m/N) at ``t`` (s); 0 before 0, error past the record.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = as_real_array("t", t)
        if np.any(t > self.t[-1] * (1 + 1e-12)):
            raise ValueError(f"the sampled response covers 0 to {self.t[-1]:.6g} s, asked for "
                             f"t = {float(np.max(t)):.6g} s: give a longer record or a shorter "
                             "t_end")
        tc = np.clip(t, 0.0, self.t[-1])
        i = np.clip(np.searchsorted(self.t, tc, side="right") - 1, 0, self.t.size - 2)
        tau = tc - self.t[i]
        dt = self.t[i + 1] - self.t[i]
        slope = (self.impulse_response[i + 1] - self.impulse_response[i]) / dt
        out = self._step[i] + tau * (self.impulse_response[i] + 0.5 * slope * tau)  # type: ignore[attr-defined]
        return np.where(t > 0, out, 0.0)


def _warn_of_drift(t, h, inverse_mass) -> None:
    """Warn where ``h`` drifts at the record's end at a rate other than ``inverse_mass``.

    A free body's impulse response tends to ``t / M`` (its rigid motion) while its
    vibration dies out; over the record's second half its straight-line trend then rises
    by more than :data:`DRIFT_OVER_SCATTER` times the scatter about it, at the slope
    ``1/M``. Given ``inverse_mass=0`` (the default), the motion is solved right but the
    restitution and the energies are booked as for a grounded body (a 2 kg free mass
    struck by 1 kg at 1 m/s through a spring: restitution 0.33 for 1.0). A grounded body
    whose slowest mode is longer than the record looks alike: hence a warning.
    """
    late = t >= 0.5 * t[-1]
    if np.count_nonzero(late) < 8:
        return
    span = t[late] - t[late].mean()
    slope = float(span @ h[late] / (span @ span))
    scatter = float(np.std(h[late] - h[late].mean() - slope * span))
    rise = slope * (span[-1] - span[0])
    if rise > DRIFT_OVER_SCATTER * scatter and abs(slope - inverse_mass) > 0.1 * slope:
        warnings.warn(f"impulse_response drifts at the record's end at {slope:.4g} m/(N s^2) "
                      f"(a free body's rigid motion, 1/M), inverse_mass is {inverse_mass:.4g} "
                      f"1/kg: give inverse_mass={slope:.4g} for a free body (restitution and "
                      "energies are booked with it), or a longer record if its slowest mode "
                      "is longer than this one", UserWarning, stacklevel=4)
