"""The noise of measured FRF data estimated from the data themselves: a running
percentile that stays inside the data (:func:`running_percentile`) and the noise's
standard deviation per line from second differences (:func:`noise_level`)."""

from __future__ import annotations

import numpy as np
from scipy.ndimage import percentile_filter

__all__ = ["noise_level", "running_percentile"]


def running_percentile(x, q, size):
    """The ``q``-th percentile of ``x`` over a running window of ``size`` lines that
    stays inside the data: centred, and shifted inwards within ``size // 2`` lines of
    either end (the first lines take the window of the first ``size`` lines).

    Padding the ends instead (``mode="nearest"``) repeats the end value ``size // 2``
    times: where a resonance sits at the band's edge, its curvature then fills the
    window and a median reads it as the level of the noise.

    Parameters
    ----------
    x : ndarray of float, shape (n,)
    q : float
        Percentile, 0-100 (50: the running median).
    size : int
        Window length (lines); the whole array when ``n <= size``.
    """
    x = np.asarray(x, dtype=float)
    if x.size <= size:
        return np.full(x.size, np.percentile(x, q))
    out = percentile_filter(x, q, size=size, mode="nearest")
    half = size // 2
    out[:half] = np.percentile(x[:size], q)
    out[x.size - half:] = np.percentile(x[-size:], q)
    return out


def noise_level(h, window=31):
    """Standard deviation of the noise at each line, estimated from the data themselves.

    The second difference ``h[l+1] - 2 h[l] + h[l-1]`` of white noise of variance
    ``sigma^2`` has variance ``6 sigma^2``; its squared modulus is exponential, with median
    ``6 sigma^2 ln 2``. A running median over ``window`` lines
    (:func:`running_percentile`, inside the data at the ends) ignores the few lines of a
    sharp resonance, where the curvature is the FRF's own.
    """
    d2 = np.abs(np.diff(h, 2)) ** 2
    d2 = np.concatenate([d2[:1], d2, d2[-1:]])
    level = np.sqrt(running_percentile(d2, 50, window) / (6 * np.log(2)))
    return np.maximum(level, 1e-12 * np.max(np.abs(h)))
