"""The hammer's pulse in a force record, the pre-trigger before it, and whether the
channels look swapped.

:func:`main_pulse` finds a record's main pulse (:func:`modalid.frf_from_hammer`'s force
window and double-hit search use it); :func:`swapped_channels` compares how much of each
channel's energy lies around its own main peak: a hammer's force lies almost whole in
its pulse, a structure's response rings on after it. :func:`double_hits_in` finds second
pulses; :func:`warn_of_aliasing` says a force spectrum that reaches the Nyquist line.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.ndimage
import scipy.signal

__all__ = ["hit_start", "main_pulse", "pretrigger_offsets", "pulse_share", "swapped_channels",
           "double_hits_in", "warn_of_aliasing"]

#: how many times more of its energy the response may hold around its peak than the force
#: before the channels are said to be swapped (measured: pyFRF's real records, force
#: 99.9 % and response 2.4 %; a synthetic rod at zeta 0.3 and 3 % noise, 10 % and 12 %)
SWAP_RATIO = 4.0
#: a channel's pre-trigger mean is an offset to remove when it exceeds this many of its
#: standard errors (pure noise: 6e-5 of the time)
BASELINE_Z = 4.0
#: the pre-trigger ends this many samples before the force first reaches
#: ``PRETRIGGER_LEVEL`` of its peak; fewer than ``MIN_PRETRIGGER`` samples in all
#: hits say nothing
PRETRIGGER_MARGIN, PRETRIGGER_LEVEL, MIN_PRETRIGGER = 2, 0.05, 8
#: a force autospectrum within this many dB of its peak near the Nyquist frequency is
#: said (aliasing, :func:`warn_of_aliasing`)
ALIASING_DB = 30.0


def main_pulse(f: np.ndarray):
    """The record less its median, sign-normalised; its main peak's index, value and
    width at half maximum (samples).

    A hammer pulse is short: the record's median is its baseline. Measured from it, an
    offset does not widen the pulse (an offset of 60 % of the peak had every sample above
    half maximum: the force window took the whole record).
    """
    f = f - np.median(f)
    k0 = int(np.argmax(np.abs(f)))
    if f[k0] < 0:
        f = -f
    peak = float(f[k0])
    above = f >= 0.5 * peak
    left = k0
    while left > 0 and above[left - 1]:
        left -= 1
    right = k0
    while right < f.size - 1 and above[right + 1]:
        right += 1
    return f, k0, peak, right - left + 1


def pulse_share(records: np.ndarray) -> float:
    """The median over the records (rows) of the share of each one's energy (about its
    median) within five half-widths of its main peak."""
    shares = []
    for record in records:
        centred, k0, _, width = main_pulse(record)
        total = float(np.sum(centred ** 2))
        near = float(np.sum(centred[max(k0 - 5 * width, 0):k0 + 5 * width + 1] ** 2))
        shares.append(near / total if total > 0 else 1.0)
    return float(np.median(shares))


def swapped_channels(forces: np.ndarray, responses: np.ndarray):
    """``(force_share, response_share)`` when the response holds :data:`SWAP_RATIO` times
    more of its energy around its peak than the force does (the channels look swapped),
    else None."""
    force, response = pulse_share(forces), pulse_share(responses)
    return (force, response) if response > SWAP_RATIO * force else None


def hit_start(f: np.ndarray) -> int:
    """Index of the first sample of the force record ``f`` that departs from its median
    by ``PRETRIGGER_LEVEL`` of its largest departure: where the hit starts."""
    level = np.abs(f - np.median(f))
    return int(np.flatnonzero(level >= PRETRIGGER_LEVEL * level.max())[0])


def pretrigger_offsets(forces: np.ndarray, responses: np.ndarray):
    """``(force, response)`` offsets, or None where they cannot be measured.

    The pre-trigger of a hit: its samples before the force, less its median (an offset of
    its own), first reaches ``PRETRIGGER_LEVEL`` of its peak, less a margin. A channel's
    offset is the mean over the hits' pre-triggers where it exceeds ``BASELINE_Z``
    standard errors, the larger of the white-noise one (``std / sqrt(n)``) and the hits'
    (the spread of their own means over ``sqrt(n_hits)``): a slow disturbance, such as a
    50 Hz hum over a pre-trigger of 0.7 ms, is a constant within one hit but not from hit
    to hit. ``None`` for a single hit (a slow disturbance cannot be told from an offset)
    or fewer than ``MIN_PRETRIGGER`` pre-trigger samples in all.
    """
    if forces.shape[0] < 2:
        return None
    ends = [max(hit_start(f) - PRETRIGGER_MARGIN, 0) for f in forces]
    if sum(ends) < MIN_PRETRIGGER:
        return None
    offsets = []
    for records in (forces, responses):
        pre = np.concatenate([r[:end] for r, end in zip(records, ends)])
        means = np.array([np.mean(r[:end]) for r, end in zip(records, ends) if end])
        mean = float(np.mean(pre))
        error = float(np.std(pre, ddof=1)) / np.sqrt(pre.size)
        if means.size >= 2:
            error = max(error, float(np.std(means, ddof=1)) / np.sqrt(means.size))
        offsets.append(mean if abs(mean) > BASELINE_Z * error else 0.0)
    return offsets[0], offsets[1]


def double_hits_in(forces: np.ndarray, fs: float, threshold: float):
    """Second pulses, found on the record averaged over the main pulse's width.

    A hammer pulse lasts about as long as the main one; noise spikes last a sample. The
    search runs on the moving average over the main pulse's width at half maximum
    (``fwhm`` samples), where white noise is ``sqrt(fwhm)`` times smaller and a pulse as
    wide as the main one keeps its relative height; a second pulse must also stand six
    robust standard deviations (median absolute deviation) above the averaged record
    after the main pulse, so that noise never passes for one. The time and height
    reported are those of the raw record's largest sample within that width of the
    averaged peak.
    """
    found = []
    for i, record in enumerate(forces):
        f, k0, peak, fwhm = main_pulse(record)
        if peak == 0.0:
            what = "constant" if record.any() else "identically zero"
            raise ValueError(f"force of hit {i} is {what}: no hammer pulse")
        avg = scipy.ndimage.uniform_filter1d(f, size=fwhm, mode="constant")
        a0 = int(np.argmax(avg[max(k0 - fwhm, 0):k0 + fwhm + 1])) + max(k0 - fwhm, 0)
        level = threshold * float(avg[a0])
        below = np.flatnonzero(avg[a0:] < level)
        if below.size == 0:
            continue
        end = a0 + int(below[0])
        # and above the averaged noise: 6 robust standard deviations of the rest
        rest = avg[end:]
        noise = 1.4826 * float(np.median(np.abs(rest - np.median(rest)))) if rest.size else 0.0
        peaks, _ = scipy.signal.find_peaks(avg, height=max(level, 6.0 * noise))
        later = peaks[(peaks > end) & (peaks - k0 > fwhm)]
        if later.size:
            k_avg = int(later[np.argmax(avg[later])])
            lo, hi = max(k_avg - fwhm, 0), min(k_avg + fwhm + 1, f.size)
            k = lo + int(np.argmax(f[lo:hi]))
            found.append((i, k / fs, float(f[k] / peak), k0 / fs))
    return found


def warn_of_aliasing(freq, force_spectrum, fs):
    """A UserWarning when the force autospectrum on the lines above ``0.45 fs`` (median)
    is within :data:`ALIASING_DB` of its peak: the hammer put force above ``fs / 2`` too,
    which an ideal sampler folds onto the band (no anti-aliasing filter: a fixed rod's
    hits of 3-6 samples, -22 to -24 dB there, were then called a transfer FRF; through a
    filter, or with hits of 20 samples, -46 to -72 dB)."""
    near = freq >= 0.45 * fs
    if not near.any() or not force_spectrum.max() > 0:
        return
    level = 10.0 * np.log10(max(float(np.median(force_spectrum[near])), 1e-300)
                            / float(force_spectrum.max()))
    if level > -ALIASING_DB:
        warnings.warn(f"the force spectrum near the Nyquist frequency ({0.45 * fs:.6g}-"
                      f"{fs / 2:.6g} Hz) is only {-level:.3g} dB below its peak: the hits "
                      "hold force above fs / 2, which records sampled without an "
                      "anti-aliasing filter fold onto the band; use a softer hammer tip or "
                      "a higher sample rate (or check that the records were filtered)",
                      UserWarning, stacklevel=3)
