"""Wide bands by segments: the poles of a long FRF from fits of overlapping pieces of it.

The refinement of :class:`modalid.ModalFit` costs ``O(lines x parameters^2)`` per step,
and a wide hammer FRF (10^4 lines, tens of modes) makes both large. A lightly damped
mode's information sits within a few half-power bandwidths of it, so the band is cut into
overlapping segments of :data:`SEGMENT_LINES` lines (half a segment apart; bands of
:data:`MIN_SEGMENTED` lines or more), each fitted on
its own by the same estimator (its out-of-segment modes standing in its lower and upper
pseudo-modes), and each segment contributes the poles of its middle half: every line of
the band lies in exactly one segment's middle, away from the segment's edges. The poles
then start one refinement of the whole band (:meth:`FRFPipeline._identify`), which fits
the residues, the mass line and the residual terms of the whole band jointly.

Cost: ``S`` segments of ``L`` lines and ``n/S`` modes cost ``O(n^2 L / S)`` a step where
one fit of the band costs ``O(n^2 L S)``.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.base import clone

__all__ = ["SEGMENT_LINES", "MIN_SEGMENTED", "segment_edges", "segment_poles"]

SEGMENT_LINES = 1600     # lines per segment
MIN_SEGMENTED = 8000     # bands of this many lines and more are fitted by segments


def segment_edges(n_lines: int, length: int = SEGMENT_LINES):
    """Overlapping segments of a band of ``n_lines`` lines.

    Returns
    -------
    list of (start, stop, keep_from, keep_to)
        Line indices: the segment is ``[start, stop)``, its poles are kept when their
        frequency lies in the lines ``[keep_from, keep_to)``; the kept ranges tile
        ``[0, n_lines)``.
    """
    step = length // 2
    edges = []
    start = 0
    while True:
        stop = min(start + length, n_lines)
        last = stop == n_lines
        keep_from = 0 if start == 0 else start + step // 2
        keep_to = n_lines if last else start + step + step // 2
        edges.append((start, stop, keep_from, keep_to))
        if last:
            return edges
        start += step


def segment_poles(estimator, band):
    """Poles of ``band`` (FRFData in its own quantity, the band fitted) from segment fits.

    Parameters
    ----------
    estimator : ModalFit
        Its settings, with the passivity and weighting it decided, are cloned for each
        segment (``freq_range`` set to the segment).
    band : FRFData

    Returns
    -------
    poles : ndarray of complex
        The physical poles in the data's domain (a window's decay put back), by frequency.
    fits : list of ModalFit
        The segment fits (their stabilization diagrams and reports).
    """
    f = band.freq_hz
    shift = float(estimator.window_decay_rate)
    poles, fits = [], []
    for start, stop, keep_from, keep_to in segment_edges(f.size):
        sub = clone(estimator).set_params(freq_range=(f[start], f[stop - 1]),
                                          passive=estimator._passive_on,
                                          weighting=estimator._weighting_on)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sub.fit(band)
        fits.append(sub)
        p = sub.poles_
        fp = np.abs(p) / (2 * np.pi)
        top = f[keep_to - 1] if keep_to == f.size else f[keep_to]
        kept = (fp >= f[keep_from]) & ((fp < top) if keep_to < f.size else (fp <= top))
        poles.append(p[kept] - shift)            # the windowed FRF's poles
    out = np.concatenate(poles) if poles else np.zeros(0, complex)
    return out[np.argsort(np.abs(out))], fits
