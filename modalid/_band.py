"""The automatic band of :class:`modalid.ModalFit`: the lines a measured FRF can vouch for.

A measured FRF is not equally informative everywhere. Below the first trustworthy line
sit DC leakage and the analyzer's or window's low end (random phase, |H| jumping from
line to line); above the excitation's reach the coherence falls and the lines become
noise. Fitting those lines costs time and, under relative weights, drags the poles. The
band is chosen from the data alone:

* **low end** -- the *roughness* of line ``k``, ``|H[k-1] - 2 H[k] + H[k+1]| / |H[k]|``
  (a smooth FRF's second difference is small against its value; noise's is of order
  one), is smoothed by a running median of 5 lines; the lowest lines are dropped while it
  stays above ``max(0.3, 2 x`` the file's median roughness), or (with coherence) while
  the coherence (running median of 3 lines) is under 0.5, whichever drops more; at most
  5 % of the lines, and (by roughness) never through a resonance (a peak standing half a
  decade above its surroundings);
* **high end** -- with coherence: the noise-to-signal ratio ``(1 - g)/g`` of the smoothed
  coherence ``g`` (running median of about 1 % of the lines), compared with the file's
  best tenth: the band ends where, above the middle of the file, a run of 2 % of the lines
  or more has a ratio above ``max(1, 100 x`` the best) (the noise as strong as the signal,
  or a hundred times the file's best) and the lines do not recover for good. Without
  coherence the smoothed roughness plays the same part (above ``max(0.3, 4 x`` its
  median). Where the data carry the excitation's autospectrum (a hammer test's:
  ``FRFData.excitation``) so does its fall to 20 dB below its peak (smoothed the same
  way), whichever ends the band first; with coherence too, the lines above that reach
  count while the smoothed coherence stays at 0.9 or more (a run of 2 % of the lines
  under it, not recovering, ends the band): averaged hits keep the coherence fair past a
  null of the pulse's spectrum, where the lines misled the fit (a false mass line on a
  grounded rod, its restitution 13 % off), while a clean test's lines above its reach
  (coherence 0.99) hold what a response prediction needs.

Which lines were dropped, and why, is returned as a sentence for ``report_``.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import median_filter
from scipy.signal import find_peaks, peak_widths

from ._noise import noise_level, running_percentile
from ._segments import resonance_peaks
from .frf import FRFData

__all__ = ["choose_band", "choose_weighting", "decimation", "noise_model", "roughness"]

_LOW_MAX_SHARE = 0.05        # the low-end cut takes at most this share of the lines
_RUN_SHARE = 0.02            # a bad run at the top must span this share of the lines
_MIN_COHERENCE = 0.1         # below this everywhere the lines hold no information
#: with coherence, the band ends where the smoothed noise-to-signal ratio ``(1 - g)/g``
#: exceeds this many times its best lines' (10th percentile), or 1 (coherence 0.5)
_NSR_SPAN = 10.0
#: ... at the end of the good lines, if this share of the lines above them is bad
_TAIL_BAD = 0.75
#: without coherence, the band ends where the excitation's autospectrum has fallen this
#: far below its peak (a hammer's usable band: 10-20 dB is the textbook range)
_REACH_DB = 20.0
#: above that reach, lines of a coherence under this one do not count (with coherence)
_ABOVE_REACH_COHERENCE = 0.9
#: ... nor lines where the excitation has fallen this far below its peak
_ABOVE_REACH_DB = 40.0
MANY_LINES = 50_000          # bands of more lines than this are decimated where they can be
_TARGET_LINES = 20_000       # ... towards this many lines
_LINES_PER_WIDTH = 4         # ... keeping at least this many lines in a half-power band


def roughness(values) -> np.ndarray:
    """Relative second difference of each line, shape ``values.shape`` (the end lines
    copy their neighbours'); about 0 for a smooth FRF, of order 1 for noise."""
    h = np.asarray(values, dtype=complex)
    if h.size < 3:
        return np.zeros(h.size)
    mag = np.maximum(np.abs(h[1:-1]), 1e-300)
    inner = np.abs(h[2:] - 2.0 * h[1:-1] + h[:-2]) / mag
    return np.concatenate([inner[:1], inner, inner[-1:]])


def _low_cut(h, rough, coherence=None) -> tuple[int, str]:
    """How many of the lowest lines to drop, and what said so (``"roughness"`` or
    ``"coherence"``): the larger of the two cuts that stand (``rough=None``: by
    coherence only)."""
    n = h.size
    by_roughness = 0 if rough is None else _rough_low_cut(h, rough)
    by_coherence = 0
    if coherence is not None:
        # the noise as strong as the signal: coherence under 1/2 (running median of 3);
        # such lines show no resonance, so no guard is needed. Not a median of 11: five
        # hits' coherence scatters 0.05-0.7 where it is 0.3, yet such lines inform (a
        # fixed rod's lines below its first mode, 1 % noise, cut from 11 to 200 Hz:
        # restitution 0.694 -> 0.421 for the exact 0.690; an aliased test's lowest lines
        # are biased, not noisy, and the driving-point decision says what they did)
        trusted = np.flatnonzero(median_filter(coherence, size=3, mode="nearest") >= 0.5)
        by_coherence = int(trusted[0]) if trusted.size else 0
        if by_coherence > _LOW_MAX_SHARE * n:
            by_coherence = 0
    if by_coherence > by_roughness:
        return by_coherence, "coherence"
    return by_roughness, "roughness"


def _rough_low_cut(h, rough) -> int:
    """How many of the lowest lines the roughness says to drop (0: none, or a cut the
    guards refuse)."""
    n = h.size
    threshold = max(0.3, 2.0 * float(np.median(rough)))
    smooth = median_filter(rough, size=5, mode="nearest")
    good = np.flatnonzero(smooth < threshold)
    cut = int(good[0]) if good.size else 0
    if cut == 0 or cut > _LOW_MAX_SHARE * n:
        return 0
    # never through a resonance: a peak half a decade above its surroundings there, or
    # closer than a quarter of the way to the first clear peak above
    logmag = np.log10(np.maximum(np.abs(h), 1e-300))
    if find_peaks(logmag[:cut + 3], prominence=0.5)[0].size:
        return 0
    above = find_peaks(logmag[cut:], prominence=0.3)[0]
    if above.size and cut > 0.25 * (cut + above[0]):
        return 0
    return cut


def _top_run(bad, n, *, upper_half=True) -> int | None:
    """Index where the band ends: the start of the lowest run of ``bad`` lines of at
    least ``_RUN_SHARE`` of ``n`` (in the upper half, with ``upper_half``) after which
    fewer than half of the lines recover; ``None`` when there is none."""
    run = max(3, int(_RUN_SHARE * n))
    edges = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(np.int8), [0]])))
    starts, stops = edges[::2], edges[1::2]
    first = n // 2 if upper_half else 0
    long_runs = [(a, b) for a, b in zip(starts, stops) if b - a >= run and a >= first]
    for a, _ in long_runs:
        if np.mean(bad[a:]) >= 0.5:          # the lines above do not recover for good
            return int(a)
    return None


def _best_top(bad, n, peak_bad) -> int | None:
    """Index where the band ends by the mask ``bad`` (lines from the band's start): the
    end of the start's run of lines in which the good ones most outnumber the bad (the
    maximum of the running sum of +1 per good line, -1 per bad one), so that at least
    half the lines above it are bad; ``None`` where fewer than ``_RUN_SHARE`` of ``n``
    lines lie above it or fewer than :data:`_TAIL_BAD` of them are bad. Where most of
    the resonance peaks above it are good by their own lines' coherence (``peak_bad``:
    1 or 0 at a peak line, NaN elsewhere), it moves up past the last good one: valleys
    between modes on half the lines or more drag the sum down from the first good
    stretch on, and the band had collapsed to a cantilever's first 4 modes of 8, its
    peaks' coherence 0.93-0.99 (review). Not the first long bad run: a fixed rod's
    antiresonance valleys (coherence under 0.5 over 250 Hz at a time, between its modes
    every 500 Hz) would end the band above its first mode, as the lines above its
    hammer's reach (half the file) are bad too."""
    score = np.cumsum(np.where(bad, -1, 1))
    top = int(np.argmax(score)) + 1
    # the resonance peaks above it, by their own lines' coherence (``peak_bad``; NaN off
    # the peaks): mostly good, the valleys alone are bad and the peaks still inform, and
    # the band goes on to the good stretch of its last good peak
    above = peak_bad[top:]
    above = above[np.isfinite(above)]
    if above.size and np.mean(above) < 0.5:
        start = int(np.flatnonzero(peak_bad == 0)[-1])
        top = start + int(np.argmax(score[start:])) + 1
    if bad.size - top < max(3, int(_RUN_SHARE * n)) or np.mean(bad[top:]) < _TAIL_BAD:
        return None
    return top


def _excitation_reach(excitation, window, db=_REACH_DB) -> int | None:
    """Index where the excitation stops reaching: the start of the lowest run (as
    :func:`_top_run`) above its peak of lines whose autospectrum (running median of
    ``window`` lines) is ``db`` (:data:`_REACH_DB`) dB or more below that peak; ``None``
    when there is none (or no excitation at all). Below the peak it is not looked for: a
    shaker's band-limited drive, or a hammer's low end, rises there."""
    smooth = median_filter(np.asarray(excitation, float), size=window, mode="nearest")
    top = int(np.argmax(smooth))
    if not smooth[top] > 0.0:
        return None
    # anywhere above the peak: an autospectrum's fall is no resonance's trough
    start = _top_run(smooth[top:] < smooth[top] * 10.0 ** (-db / 10.0), smooth.size,
                     upper_half=False)
    return None if start is None else top + start


#: the fewest lines a band given by the user may hold: with 2 the fit crashed in numpy,
#: with 3 it put a mode and two pseudo-modes through them, "ok" (with 5 it fits the
#: residual terms alone and says the band holds no resonance)
MIN_BAND_LINES = 4
#: the fewest informative lines the automatic band must find
_MIN_AUTOMATIC_LINES = 8


def band_to_fit(data, band):
    """``data.band(band)`` (an FRFData or FRFSet), refused naming the band when it holds
    fewer than :data:`MIN_BAND_LINES` lines."""
    out = data.band(band)
    n = out.freq_hz.size
    if n < MIN_BAND_LINES:
        raise ValueError(f"freq_range ({band[0]:g}, {band[1]:g}) Hz holds {n} lines of the "
                         f"data; a fit needs at least {MIN_BAND_LINES}: widen it")
    return out


def given_band(freq_range, automatic) -> tuple[tuple[float, float], str]:
    """The band (Hz) a user's ``freq_range`` asks for and a sentence saying why: an end
    given as None is the automatic band's (``automatic()``, returning ``((fmin, fmax),
    reason)`` like :func:`choose_band`), so that ``--fmax`` alone keeps the automatic low
    end (on a real hammer record the noisy lines under 7 Hz made the fit "suspect").

    Parameters
    ----------
    freq_range : pair of (float or None)
        ``(fmin, fmax)`` (Hz).
    automatic : callable
        The automatic band, called only when an end is None.

    Returns
    -------
    (fmin, fmax) : tuple of float
    reason : str
    """
    try:
        lo, hi = freq_range
    except (TypeError, ValueError) as exc:
        raise TypeError(f"freq_range must be a pair (fmin, fmax) in Hz, got "
                        f"{freq_range!r}") from exc
    if lo is not None and hi is not None:
        return (lo, hi), "freq_range"
    (auto_lo, auto_hi), why = automatic()
    ends = "both ends" if lo is None and hi is None else ("the low end" if lo is None
                                                          else "the top")
    if (lo is None) != (hi is None):   # what the automatic band dropped at the end chosen
        parts = [p for p in why.split("; ") if p.startswith("dropped the") == (lo is not None)]
        why = "; ".join(parts) or "all lines"
    return ((auto_lo if lo is None else lo, auto_hi if hi is None else hi),
            f"freq_range, {ends} chosen from the data ({why})")


def choose_band(data: FRFData, *, low_end=True) -> tuple[tuple[float, float], str]:
    """The band (Hz) to fit and a sentence saying why.

    Parameters
    ----------
    data : FRFData
        The measured FRF, lines above 0 Hz (any quantity; roughness is scale-free).
    low_end : bool
        Whether the lowest lines may be dropped for their roughness (not for data whose
        low end a model describes, e.g. an exponential window's). Lines of coherence
        under 0.5 are dropped either way: they hold no information.

    Returns
    -------
    (fmin, fmax) : tuple of float
        The band, both ends included (Hz).
    reason : str
        What was dropped at each end and why ("all lines" when nothing was).

    Raises
    ------
    ValueError
        When fewer than 8 lines would remain, or the smoothed coherence is under 0.1 on
        all but 8 lines (no usable band).
    """
    f, h, n = data.freq_hz, data.values, len(data)
    rough = roughness(h)
    lo, why = _low_cut(h, rough if low_end else None, data.coherence)
    reasons = []
    if lo and why == "coherence":
        reasons.append(f"dropped {lo} line{'s' * (lo > 1)} below {f[lo]:.6g} Hz (the "
                       "coherence of the lowest lines is under 0.5: median "
                       f"{np.median(data.coherence[:lo]):.2g})")
    elif lo:
        reasons.append(f"dropped {lo} line{'s' * (lo > 1)} below {f[lo]:.6g} Hz (the "
                       "lowest lines scatter like noise: relative second difference "
                       f"{np.median(rough[:lo]):.2g} against {np.median(rough):.2g})")
    hi, why_top = None, None
    window = max(11, (n // 100) | 1)
    if data.coherence is not None:
        g = np.clip(median_filter(data.coherence, size=window, mode="nearest"), 1e-6, 1.0)
        nsr = (1.0 - g) / g
        limit = max(1.0, _NSR_SPAN * float(np.quantile(nsr, 0.1)))
        if np.count_nonzero(g >= _MIN_COHERENCE) < _MIN_AUTOMATIC_LINES:
            raise ValueError(f"the FRF holds no usable band: the smoothed coherence is below "
                             f"{_MIN_COHERENCE} on {np.count_nonzero(g < _MIN_COHERENCE)} of "
                             f"its {n} lines")
        # anywhere above the low cut: the coherence of a noisy hammer test (best lines
        # 0.89) fell to 0.15-0.4 from 2.6 kHz of 10 kHz, and a cut in the upper half
        # only kept it all (FRF error 84 %, "suspect"; its force spectrum cut 2.8 kHz)
        own = np.clip(median_filter(data.coherence, size=3, mode="nearest"), 1e-6, 1.0)
        peak_bad = np.full(n, np.nan)
        peaks = resonance_peaks(h)
        peak_bad[peaks] = (1.0 - own[peaks]) / own[peaks] > limit
        hi = _best_top(nsr[lo:] > limit, n, peak_bad[lo:])
        if hi is None:    # as before: a run in the upper half the lines above do not
            # recover from, at 100 times the best lines' noise-to-signal ratio
            worst = max(1.0, 100.0 * float(np.quantile(nsr, 0.1)))
            hi = _top_run(nsr > worst, n)
            limit = worst if hi is not None else limit
        else:
            hi += lo
        why_top = f"the smoothed coherence falls below {1 / (1 + limit):.3g}"
    else:
        smooth = median_filter(rough, size=window, mode="nearest")
        limit = max(0.3, 4.0 * float(np.median(rough)))
        hi = _top_run(smooth > limit, n)
        why_top = "the lines scatter like noise there"
    reach = None if data.excitation is None else _excitation_reach(data.excitation, window)
    if reach is not None and data.coherence is not None:
        # averaged hits keep the coherence fair above the hammer's reach, and past a null
        # of its pulse's spectrum: there only lines of high coherence inform (a rod's
        # restitution came out 13 % off from lines to 21.5 kHz over a 15 kHz null, where
        # the fit put a false mass line; a real test's lines above its reach at coherence
        # 0.99 predict its responses 2.4 times better than a band cut at the reach)
        # ... and while the force stays within _ABOVE_REACH_DB of its peak: an analyzer's
        # anti-aliasing filter cuts it near fs / 2, and there a fixed rod's H1 was 30-436 %
        # off at a coherence of 0.99 (the force 40-50 dB down; a real test's 26-32 dB at
        # 10-12 kHz informs)
        weak = _top_run(g[reach:] < _ABOVE_REACH_COHERENCE, n, upper_half=False)
        floor = _excitation_reach(data.excitation, window, db=_ABOVE_REACH_DB)
        ends = [end for end in (None if weak is None else reach + weak, floor)
                if end is not None]
        reach = min(ends) if ends else None
        above = (f"above the excitation's reach ({_REACH_DB:g} dB below its peak) the "
                 f"smoothed coherence falls below {_ABOVE_REACH_COHERENCE:g}, or the "
                 f"excitation {_ABOVE_REACH_DB:g} dB below its peak")
    else:
        above = f"the excitation's spectrum is {_REACH_DB:g} dB or more below its peak there"
    if reach is not None and reach > lo and (hi is None or reach < hi):
        hi, why_top = reach, above
    if hi is not None:
        reasons.append(f"dropped the {n - hi} lines above {f[hi - 1]:.6g} Hz ({why_top})")
    hi = n if hi is None else hi
    if hi - lo < _MIN_AUTOMATIC_LINES:
        raise ValueError(f"the FRF holds no usable band: {hi - lo} informative lines of "
                         f"{n} ({'; '.join(reasons)})")
    return (float(f[lo]), float(f[hi - 1])), "; ".join(reasons) or "all lines"


def choose_weighting(values) -> tuple[str, str]:
    """``("relative" | "mixed" | "noise", reason)``: the weighting the data's noise calls for.

    The data's own scatter (:func:`modalid._lsfd.noise_level`) relative to ``|H|`` is
    compared on the weakest and the strongest quarter of the lines: noise proportional to
    the FRF gives a ratio near 1, a noise floor (an analyzer's, a hammer test's) one of
    ``|H|``'s spread. Without a floor (ratio up to 2.5): ``1/|H|`` ("relative", maximum
    likelihood for proportional noise). With one: where it dominates (median relative
    scatter above 5 %) one over the local noise level ("noise"), else one over the
    modelled ``sqrt((sigma_rel |H|)^2 + floor^2)`` of :func:`noise_model` ("mixed": the
    antiresonances' floor does not take over the weights).

    Parameters
    ----------
    values : ndarray of complex, shape (n,)
        The FRF in the quantity measured.
    """
    h = np.asarray(values, dtype=complex)
    mag = np.abs(h)
    relative = noise_level(h) / np.maximum(mag, 1e-300)
    lo, hi = np.quantile(mag, [0.25, 0.75])
    ratio = float(np.median(relative[mag <= lo]) / np.median(relative[mag >= hi]))
    scatter = float(np.median(relative))
    floor = (f"a noise floor: the lines scatter by {100 * scatter:.2g} % (median), "
             f"{ratio:.2g} times more on the weakest quarter than the strongest")
    if ratio > 2.5:
        return ("noise" if scatter > 0.05 else "mixed"), floor
    return "relative", (f"noise proportional to the FRF or small (scatter {100 * scatter:.2g} "
                        f"%, weak/strong ratio {ratio:.2g})")


def noise_model(values):
    """``(sigma_rel, floor)``: the data's noise as a part proportional to ``|H|`` and a
    floor, per line.

    ``floor`` (shape ``values.shape``, units of ``values``) is the 20th percentile of the
    local noise level (:func:`modalid._lsfd.noise_level`) over about 2 % of the lines (at
    least 51): the scatter where the FRF is weak, not raised by the curvature of the
    resonances. ``sigma_rel`` is the median relative scatter of the strongest quarter of
    the lines. The standard deviation of line ``k`` is then modelled as
    ``sqrt((sigma_rel |H_k|)^2 + floor_k^2)``.
    """
    h = np.asarray(values, dtype=complex)
    mag = np.abs(h)
    level = noise_level(h)
    window = max(51, (h.size // 50) | 1)
    floor = running_percentile(level, 20, window)
    strong = mag >= np.quantile(mag, 0.75)
    sigma_rel = float(np.median(level[strong] / mag[strong]))
    return sigma_rel, np.maximum(floor, 1e-12 * mag.max())


def decimation(values) -> tuple[int, str]:
    """``(k, reason)``: keep every ``k``-th line of a band of more than
    :data:`MANY_LINES` lines (``k = 1``: all).

    Every line of a very fine FRF (10^5-10^6 lines) is not needed to find its poles: a
    lightly damped mode is determined by the lines within a few half-power bandwidths of
    it. The half-power widths (lines) of the clear peaks (``|H|`` standing a factor 3 over
    their surroundings) are measured, and ``k`` is the largest step that keeps
    :data:`_LINES_PER_WIDTH` lines across the 10th percentile of them, but no larger than
    needed to bring the band to about :data:`_TARGET_LINES` lines. The lines kept are
    the measured ones (no averaging, no bias on a peak); a file whose peaks are too sharp
    to decimate keeps all its lines.

    Parameters
    ----------
    values : ndarray of complex, shape (n,)
        The band's FRF (any quantity).
    """
    h = np.asarray(values, dtype=complex)
    n = h.size
    if n <= MANY_LINES:
        return 1, ""
    mag = np.abs(h)
    peaks = find_peaks(np.log10(np.maximum(mag, 1e-300)), prominence=0.5)[0]
    if peaks.size == 0:
        return 1, f"all {n} lines kept (no clear peak to size a decimation by)"
    widths = peak_widths(mag**2, peaks, rel_height=0.5)[0]
    narrow = float(np.quantile(widths, 0.1))
    k = int(min(narrow // _LINES_PER_WIDTH, -(-n // _TARGET_LINES)))
    if k <= 1:
        return 1, (f"all {n} lines kept (the sharpest peaks are {narrow:.3g} lines wide at "
                   "half power)")
    return k, (f"every {k}th of {n} lines kept (the sharpest peaks are {narrow:.3g} lines "
               f"wide at half power: {narrow / k:.2g} lines of {k} across each)")
