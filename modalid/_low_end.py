"""The low end of an FRF's fit: a mass line (rigid body or the lower residual of modes
below the band) and a resonance the pole estimator missed below the first pole (a mixin
of :class:`modalid._frf_pipeline.FRFPipeline`).

The methods read the estimator's settings (``self.rigid_body``, ``self.residuals``,
``self._passive_on``) and the window's decay ``self._shift`` (rad/s), which
:class:`modalid.fit.ModalFit` and the pipeline set.
"""

from __future__ import annotations

import numpy as np

from ._lsfd import mass_line_significant
from ._segments import resonance_peaks

__all__ = ["LowEnd"]

#: the lines that judge the low end lie more than this many lines below the data's first
#: resonance peak
_PEAK_LINES = 3

#: the log-log slope of ``|h|`` over the lowest lines under which a mass line that
#: steepens towards them is the lower residual of a resonance below them
#: (:func:`_resonance_below`)
_STEEPER_THAN_MASS_LINE = -2.2


def _resonance_below(omega, h, slope) -> bool:
    """Do the lowest lines ``omega`` (rad/s, ascending, 3 or more), receptance ``h``
    and log-log slope ``slope`` of ``|h|``, a mass-line-like ``-1/(m omega^2)``, lie just
    above a resonance rather than below the first mode of a free body?

    Above a mode ``|h| = 1/(m (omega^2 - omega_n^2))`` falls faster than ``omega^-2``,
    the more so the nearer the mode: its slope rises towards ``-2`` with frequency. A
    free body's mass line ``1/(M omega^2) - C`` (modes above) steepens with frequency
    instead, and a windowed one ``1/(M (omega^2 + sigma^2))`` is flatter than ``-2``. A
    spring-mass's receptance on 15-40 Hz, its 10 Hz mode below the band, had been fitted
    as a 1.6 kg rigid body and a constant, 32 % off at the band's start."""
    if slope >= _STEEPER_THAN_MASS_LINE:
        return False
    half = omega.size // 2
    x, y = np.log(omega), np.log(np.abs(h))
    lower = np.polyfit(x[:half + 1], y[:half + 1], 1)[0]
    upper = np.polyfit(x[half:], y[half:], 1)[0]
    return bool(lower < upper)


class LowEnd:
    """The mass line and the missed low resonance (see the module docstring)."""

    def _low_end(self, omega, h, w, poles, cut):
        """``(rigid, lower)``: is there a mass line, and is it a rigid body or the lower
        residual of modes below the band?

        With three lines or more well below the first pole (and above twice the window's
        decay, where a windowed mass line ``1/(M (s + sigma)^2)`` is negative like
        ``1/(M s^2)``), their phase and slope decide: a free body's receptance there is
        ``-1/(M omega^2)``, a grounded one's a positive static flexibility, and a mass
        line keeps its sign down to the lowest of them (a resonance the poles missed turns
        its static side, the lowest lines, positive). Otherwise a ``1/s^2`` term must lower
        the weighted residual by more than its information cost, with a positive mass. A
        mass line is a rigid body when the data reach well below the first pole and
        ``freq_range`` did not cut them; else (and with ``rigid_body=False``) it is the
        lower residual.
        """
        if self.rigid_body is True:
            return True, False
        if self.__dict__.get("_lower_forced"):    # a refit for a missed low end (FitOne)
            return False, True
        below = self._below_first(omega, poles)
        # and below the data's first resonance: a sharp mode the poles miss is no mass
        # line (a cantilever's accelerance from 3.5 times its first mode, its second at
        # 0.93 Hz missed: the lines up to 1.3 Hz, its resonance among them, were taken
        # for no mass line and the fit lost its low end)
        peaks = resonance_peaks(h)
        if peaks.size:
            below = below[below < peaks[0] - _PEAK_LINES]
        below = below[omega[below] > 2.0 * self._shift]
        hb = h[below]
        level = np.median(hb.real) if below.size else 0.0
        steady = below.size >= 3 and bool(np.all(np.sign(hb[:3].real) == np.sign(level)))
        if steady:
            slope = np.polyfit(np.log(omega[below]), np.log(np.abs(hb)), 1)[0]
            mass_line = bool(level < 0 and slope < -1.0)
            if not self._passive_on and slope < -1.5 and level > 0:
                return False, "lower" in self.residuals    # negative mass line: transfer
        else:
            mass_line = mass_line_significant(omega, h, w, poles, self._shift)
        if not mass_line:
            return False, False
        lower = "lower" in self.residuals
        if self.rigid_body is False:
            return False, lower
        if steady and not cut and not _resonance_below(omega[below], hb, slope):
            return True, False
        return not lower, lower

    @staticmethod
    def _below_first(omega, poles):
        """Indices of the (at most 20) lowest lines below half the first pole."""
        first = np.min(np.abs(poles)) if poles.size else omega[-1]
        return np.flatnonzero(omega < 0.5 * first)[:20]

    def _low_resonance(self, omega, h, poles):
        """A resonance the pole estimator missed among the lines below the first pole.

        Near a resonance of positive modal mass a receptance's real part is positive below
        it and negative above; a mass line's is negative throughout (a windowed one's
        positive below the window's decay, but with ``|h|`` falling all the way). When the
        lowest lines' real parts go from positive to negative and ``|h|`` rises to its
        largest (by 10 % or more over the lowest line) within a line of the change, a
        pole is placed there (1 % damping plus the window's decay) and returned. ``None``
        otherwise (resonances of negative modal mass, allowed by ``passive=False``, are
        left to the residual's peaks).
        """
        below = self._below_first(omega, poles)
        hb = h[below]
        if below.size < 3 or hb[0].real <= 0:
            return None
        negative = np.flatnonzero(hb.real < 0)
        if negative.size == 0:
            return None
        c = int(negative[0])
        peak = int(np.argmax(np.abs(hb)))
        if abs(peak - c) > 1 or np.abs(hb[peak]) < 1.1 * np.abs(hb[0]):
            return None
        lo, hi = omega[below[c - 1]], omega[below[c]]
        wk = lo + (hi - lo) * hb[c - 1].real / (hb[c - 1].real - hb[c].real)
        return complex(-0.01 * wk - self._shift, wk)
