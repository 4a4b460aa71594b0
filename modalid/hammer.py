"""Impact-hammer FRF estimation: H1 over hits, force and exponential windows, double hits.

The workflow of a roving- or fixed-hammer test, one excitation/response pair::

    est = frf_from_hammer(force, acceleration, fs, response_type="acceleration",
                          exponential_decay=4.6)      # records: (n_hits, n_samples)
    est.frf                      # FRFData (accelerance), with coherence for >= 2 hits,
                                 # stating its window and record length
    fit = ModalFit().fit(est.frf)      # models what est.frf states: fit.model_ is the
                                       # structure's, the window's damping undone
    # est.correct(model) is for a model fitted to the windowed FRF as it is (another
    # tool's, or ModalFit(window_decay_rate=0, record_length=numpy.inf)): never for
    # fit.model_ above, whose window is already undone

Conventions: time records start at ``t = 0`` (the first sample), sampled at ``fs`` Hz;
force in N, response in m, m/s or m/s^2 (``response_type``); spectra are one-sided
(``scipy.fft.rfft``), frequency lines ``k fs / n_fft``, 0 Hz included.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.fft
import scipy.ndimage
import scipy.signal

from ._checks import (as_choice, as_complex_array, as_count, as_nonnegative_scalar,
                      as_positive_scalar, as_real_array, as_real_scalar)
from ._pulses import (double_hits_in, hit_start, main_pulse, pretrigger_offsets,
                      swapped_channels, warn_of_aliasing)
from ._window import MOST_WINDOW_DECAY
from .frf import FRFData
from .model import ModalModel

__all__ = ["RESPONSE_TYPES", "DoubleHitWarning", "HammerFRF", "frf_from_hammer",
           "find_double_hits", "correct_exponential_window"]

#: Response signal -> FRF quantity it measures (with a force input).
RESPONSE_TYPES = {"displacement": "receptance", "velocity": "mobility",
                  "acceleration": "accelerance"}

#: Power of ``s`` relating each quantity to the receptance (``Q(s) = s**k H(s)``).
_S_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}

FORCE_WINDOWS = ("force", "none")
BASELINES = ("pretrigger", "none")
PRETRIGGERS = ("auto", "cut", "keep")
#: the longest pulse (s, width at half height) a hammer gives before ``fs`` is doubted
_LONGEST_PULSE = 0.05
#: the share of the records a pre-trigger cut may drop before it is said
_MOST_CUT = 0.2


class DoubleHitWarning(UserWarning):
    """A force record holds a second hammer pulse after the main one (a double hit)."""


# ----------------------------------------------------------------------- result
@dataclass(frozen=True, repr=False, eq=False)
class HammerFRF:
    """Result of :func:`frf_from_hammer`; immutable.

    Attributes
    ----------
    frf : FRFData
        The H1 estimate in the quantity measured by the response (receptance, mobility
        or accelerance), with ``coherence`` when at least two hits were averaged.
        With an exponential window it is the FRF of the damped-by-the-window system:
        see :func:`frf_from_hammer` (Notes) and :meth:`correct`.
    window_decay_rate : float
        Decay rate ``sigma_w = 1/tau`` (1/s) of the exponential window applied, 0.0 for
        none. Every pole of ``frf`` sits ``sigma_w`` further left than the structure's.
    n_hits : int
        Number of hits averaged.
    double_hits : tuple of int
        Indices of the hits in which :func:`find_double_hits` found a second pulse (each
        also reported by a :class:`DoubleHitWarning`); they are still averaged.
    force_spectrum : ndarray of float, shape (n_lines,)
        Averaged force autospectrum ``mean_i |F_i|^2`` (N^2, unscaled DFT) on the lines
        of ``frf``, after the windows: the band where it is within, say, 20 dB of its
        maximum is the band the hammer excited.
    force_window_length : float or None
        Length (s, from the record start) of the force window applied, ``None`` without.
    force_window_starts : tuple of float or None
        Where the automatic force window starts in each hit (s): the force before it,
        the pre-trigger's noise, is set to zero; ``None`` where the window starts at the
        record start (a ``force_window_length`` given, or no force window).
    offsets : tuple of float or None
        ``(force, response)`` offsets removed from every record before the windows (N,
        and the response's unit): each channel's mean over the hits' pre-trigger samples
        where it is significant, else 0.0 (:func:`frf_from_hammer`, ``baseline``);
        ``None`` where none was measured (``baseline="none"``, one hit, no pre-trigger).
    record_length : float or None
        Length ``T = n_samples / fs`` (s) of the records, when their DFT was not
        zero-padded (``n_fft == n_samples``): the lines are then ``j / T`` and the
        record's end scales each windowed mode's residue by a known constant
        (:mod:`modalid._window`), which :meth:`fit_options` lets ``ModalFit`` undo.
        ``None`` for zero-padded records (the end's effect is then spread over the lines).
    record_starts : tuple of float or None
        Where each hit's records were cut (s, in the records given: its force window's
        start), the pre-trigger before it dropped (:func:`frf_from_hammer`,
        ``pretrigger``); ``None`` where they were used whole. ``record_length``
        and ``force_window_length`` then count from the cut.
    """

    frf: FRFData
    window_decay_rate: float
    n_hits: int
    double_hits: tuple
    force_spectrum: np.ndarray
    force_window_length: float | None
    record_length: float | None = None
    offsets: tuple | None = None
    force_window_starts: tuple | None = None
    record_starts: tuple | None = None

    @property
    def coherence(self):
        """Ordinary coherence of the estimate (``frf.coherence``), None for one hit."""
        return self.frf.coherence

    def correct(self, model_or_poles):
        """Undo this estimate's exponential window: :func:`correct_exponential_window`
        with ``decay_rate = window_decay_rate`` (poles only: for a model fitted with the
        rigid line ``1/(M s^2)`` and no truncation correction).

        Not for ``ModalFit().fit(est.frf).model_``: :attr:`frf` states its window, which
        that fit models, so its model is the structure's already (correcting it again
        moves every pole by twice the window's decay).

        Parameters
        ----------
        model_or_poles : ModalModel or array_like of complex
            A model fitted to :attr:`frf` as it is, without the window modelled (another
            tool's, or ``ModalFit(window_decay_rate=0, record_length=numpy.inf)``'s), or
            its poles (rad/s).

        Returns
        -------
        ModalModel or numpy.ndarray
            The same with the window's damping removed.
        """
        return correct_exponential_window(model_or_poles, self.window_decay_rate)

    def fit_options(self, *, weighted: bool = False) -> dict:
        """Options for :class:`modalid.ModalFit`, which then fits this windowed FRF
        exactly and returns the structure's model::

            ModalFit(**est.fit_options()).fit(est.frf)

        ``window_decay_rate`` and ``record_length``; with ``weighted=True`` also
        ``weights = sqrt(force_spectrum * coherence)`` (coherence clipped to
        ``[1e-3, 1]``; the force spectrum alone for one hit), one per line of ``frf``
        (fit ``est.frf`` itself, not a band of it): the fit's weighted error is then the
        error of the response it predicts for the average hit, the lines the hammer did
        not excite or the noise covered counting for little. That is the objective of a
        response prediction. On a real hammer test (its fifth hit predicted from the
        first four, ``benchmarks/hammer_hit5.py``) the unweighted default predicts as well
        or better, and it suits the modal parameters of weak modes better.

        Parameters
        ----------
        weighted : bool, keyword-only
            Add the response weights.

        Returns
        -------
        dict
            Keyword arguments of :class:`modalid.ModalFit`.
        """
        options = {"window_decay_rate": self.window_decay_rate,
                   "record_length": self.record_length}
        if weighted:
            share = 1.0 if self.coherence is None else np.clip(self.coherence, 1e-3, 1.0)
            options["weights"] = np.sqrt(self.force_spectrum * share)  # type: ignore[assignment]
        return options

    def __repr__(self) -> str:
        return (f"HammerFRF({self.frf!r}, n_hits={self.n_hits}, window_decay_rate="
                f"{self.window_decay_rate:.6g}, double_hits={self.double_hits})")


# ---------------------------------------------------------------------- helpers
def _as_records(name: str, value) -> np.ndarray:
    arr = as_real_array(name, value)
    if arr.ndim not in (1, 2):
        raise ValueError(f"{name} must be 1-D (one hit) or 2-D (hits x samples), got shape "
                         f"{arr.shape}")
    arr = np.atleast_2d(arr)
    if arr.shape[0] < 1 or arr.shape[1] < 4:
        raise ValueError(f"{name} must hold at least one hit of at least 4 samples, got "
                         f"shape {arr.shape}")
    return arr


# ------------------------------------------------------------------- functions
def find_double_hits(force, fs, *, threshold=0.1):
    """Second hammer pulses after the main one, in each force record.

    The main pulse is the sample of largest ``|force|`` (the record's sign is taken from
    it). The record is averaged over the main pulse's width at half maximum, so that
    noise spikes (one sample wide) do not count while a pulse as wide as the main one
    does. A double hit is a local maximum of that average above ``threshold`` times the
    average's main peak and above six robust standard deviations of the average's noise
    after the pulse, coming after the average has first fallen below that level and more
    than one pulse width after the main peak; its time and height are those of the raw
    record's largest sample within one pulse width.

    Parameters
    ----------
    force : array_like of float, shape (n_samples,) or (n_hits, n_samples)
        Force records (N), one row per hit.
    fs : float
        Sampling frequency (Hz), > 0.
    threshold : float, optional
        Level, as a fraction of the main peak in (0, 1), above which a later pulse counts.

    Returns
    -------
    list of tuple (hit, time_s, relative_height)
        One entry per record with a double hit: the hit index, the time (s, from the
        record start) of the largest second pulse, and its height over the main peak.
    """
    fs = as_positive_scalar("fs", fs)
    threshold = _as_threshold(threshold)
    forces = _as_records("force", force)
    return [(i, t, r) for i, t, r, _ in double_hits_in(forces, fs, threshold)]


def _as_threshold(value) -> float:
    out = as_real_scalar("double_hit_threshold", value)
    if not 0.0 < out < 1.0:
        raise ValueError(f"double_hit_threshold must lie in (0, 1), got {out!r}")
    return out


#: the largest ``n_fft`` frf_from_hammer accepts: 64 times the record, or 2**24 lines
#: for a short one (1e11 was a MemoryError)
_MAX_PAD, _MAX_FFT = 64, 2**24


def frf_from_hammer(force, response, fs, *, response_type="acceleration",
                    force_window="force", force_window_length=None, exponential_decay=0.0,
                    n_fft=None, double_hit_threshold=0.1,
                    baseline="pretrigger", pretrigger="auto", max_freq_hz=None) -> HammerFRF:
    """H1 estimate of the FRF from impact-hammer records, averaged over hits.

    Parameters
    ----------
    force : array_like of float, shape (n_samples,) or (n_hits, n_samples)
        Hammer force (N), one row per hit, each record starting at ``t = 0``.
    response : array_like of float, same shape as ``force``
        Response recorded with each hit.
    fs : float
        Sampling frequency (Hz), > 0.
    response_type : {"acceleration", "velocity", "displacement"}
        What ``response`` is; the FRF is then accelerance, mobility or receptance.
    force_window : {"force", "none"}
        ``"force"`` keeps each force record from ``t = 0`` to ``force_window_length``
        and sets the rest to zero (it removes the noise recorded on the force channel
        after the pulse); ``"none"`` leaves the force as recorded.
    force_window_length : float or None
        Length (s) of the force window, at most the record length ``n_samples / fs``.
        ``None``: the latest main peak of all hits plus five times its width at half
        maximum (the whole half-sine and a margin; the second pulse of a double hit
        likewise: it is force the response holds), and each hit's force is set to zero
        before its hit too, from five such widths before the hit's start (its first
        sample 5 % of its peak away from its median): the pre-trigger's force is noise
        (the structure is at rest), which held the force spectrum up past the hammer's
        reach (a 5 % pre-trigger at 1 % noise: the automatic band went on to the Nyquist
        line, with 43 modes for the rod's 13 there). ``HammerFRF.force_window_starts``
        says where.
    exponential_decay : float
        Decay rate ``sigma_w = 1/tau`` (1/s) of the exponential window
        ``w(t) = exp(-sigma_w t)`` applied to both channels; 0 (default) for none. For a
        window that ends at the value ``e`` use ``-log(e) / (n_samples / fs)``.
    n_fft : int or None
        FFT length, ``>= n_samples`` (the records are zero-padded) and at most 64 times
        it or ``2**24``, the larger; ``None`` for ``n_samples``. The frequency lines are
        ``k fs / n_fft``, ``k = 0 ..`` up to ``max_freq_hz``.
    double_hit_threshold : float
        Fraction of the main force peak above which a later pulse is a double hit
        (:func:`find_double_hits`).
    baseline : {"pretrigger", "none"}
        ``"pretrigger"`` (default): the structure is at rest before the hit, so a
        channel's mean over the pre-trigger samples (before each force first reaches 5 %
        of its peak above its median, less 2 samples; pooled over the hits) is a sensor
        offset, removed from every record of that channel where it exceeds 4 standard
        errors, white-noise and hit-to-hit (:attr:`HammerFRF.offsets`; two hits at least
        and 8 pre-trigger samples in all, else none is measured). An exponential window
        turns an offset into a false low-frequency term: a real accelerometer's 0.27
        m/s^2 made the lowest lines of a windowed H1 several times the FRF and its fit
        "suspect". ``"none"``: the records as they are.
    pretrigger : {"auto", "cut", "keep"}
        ``"cut"``: with the automatic force window and no ``n_fft``, each hit's records
        start where its force window starts (five pulse widths before the hit; the
        samples before it, the structure at rest, are dropped) and all keep the length
        the latest start leaves: ``HammerFRF.record_starts`` says where, the lines are
        ``k / T'`` for that length ``T'`` and ``record_length`` is ``T'``. The record's
        end is modelled for a hit at ``t = 0`` (:mod:`modalid._window`): a hit at ``t_0``
        turns the end's terms by ``omega t_0``, which matters where the modes ring to the
        record's end. A fixed rod's five hits at 1e-3 noise (seeds 1-4, zeta 1e-3, 1 s
        records), restitution of a 1 kg mass at 1 m/s (0.690): unwindowed, hits at 1 %
        and 5 % of the record predicted it 0.020-0.062 too high kept, 0.006-0.010 cut;
        with a window to 1 %, 0.003-0.012 kept and 0.003-0.010 cut (one -0.028, which
        the band check warns of). ``"auto"`` (default): cut without an exponential
        window, keep with one. ``"keep"``: the records as given, on the lines of their
        full length (an ASCII UFF file holds lines on a round spacing only). A given
        ``n_fft`` (even ``n_samples``) or force window keeps them; ``"cut"`` with one is
        refused. A cut of more than 20 % of the records (a late hit) is warned of.

    max_freq_hz : float or None
        The highest line kept (Hz), at most ``fs / 2`` (``None``, the default): an
        analyzer shows its lines up to ``fs / 2.56``, where its anti-aliasing filter rolls
        off. Without a limit the automatic band of :class:`ModalFit` ends where the force
        has fallen 40 dB above the hammer's reach (:mod:`modalid._band`).

    Returns
    -------
    HammerFRF
        The estimate (``.frf``, an :class:`FRFData`), the window decay rate, the hits
        with double hits, the force autospectrum and the offsets removed.

    Warns
    -----
    DoubleHitWarning
        For each hit whose force holds a second pulse, naming the hit index and time.
    UserWarning
        The response holds four times more of its energy around its peak than the force
        (a hammer's force lies in its pulse, a response rings on): channels swapped?
        The force pulse lasts more than 50 ms at half its height (a hammer's: 0.05-20
        ms): ``fs`` in kHz?

    Notes
    -----
    With ``X_i``, ``F_i`` the DFTs of the windowed response and force of hit ``i``,
    ``H1 = sum_i X_i conj(F_i) / sum_i |F_i|^2`` and the ordinary coherence is
    ``|sum X_i conj(F_i)|^2 / (sum |X_i|^2 sum |F_i|^2)`` (only for two or more hits:
    for one it is identically 1). H1 is unbiased by noise on the response channel.

    Exponential window: the windowed impulse response ``h(t) exp(-sigma_w t)`` has the
    Laplace transform ``H(s + sigma_w)``, whose poles are ``p_k - sigma_w`` with the
    residues unchanged; both channels are windowed, so the ratio of their spectra is
    ``Q(i omega + sigma_w)`` for the measured quantity ``Q(s) = s**k H(s)``
    (``k = 0, 1, 2`` for receptance, mobility, accelerance). It is reported multiplied by
    ``(i omega / (i omega + sigma_w))**k``, i.e. as ``(i omega)**k H(i omega + sigma_w)``:
    the quantity-``Q`` FRF of the receptance whose every pole moved by ``-sigma_w``, with
    the same residues and constant term. A :class:`ModalModel` fitted to it is therefore
    turned into the structure's model exactly by :func:`correct_exponential_window`,
    for any quantity (the factor is 1 for receptance and differs from 1 by about
    ``k sigma_w / omega`` otherwise), up to the record's end: it cuts each windowed free
    decay, which on the DFT lines scales mode ``k``'s residue by
    ``1 - exp((p_k - sigma_w) T)`` (up to 1 % with a window ending at 1 %) and a free
    body's rigid line by ``1 - exp(-sigma_w T)``, whose windowed form is
    ``1/(M (s + sigma_w)^2)``. ``ModalFit(**est.fit_options())`` models all of this
    exactly (:mod:`modalid._window`), and ``ModalFit()`` does it unasked: ``frf`` states
    ``window_decay_rate`` and ``record_length``.

    Raises
    ------
    ValueError
        For non-finite samples, records of different shapes, ``fs <= 0``, a force window
        longer than the record or ending before a force peak, ``n_fft < n_samples``, a
        zero force record, or a frequency line where the force spectrum vanishes.
    """
    fs = as_positive_scalar("fs", fs)
    as_choice("response_type", response_type, tuple(RESPONSE_TYPES))
    quantity = RESPONSE_TYPES[response_type]
    as_choice("force_window", force_window, FORCE_WINDOWS)
    as_choice("baseline", baseline, BASELINES)
    decay = as_nonnegative_scalar("exponential_decay", exponential_decay)
    as_choice("pretrigger", pretrigger, PRETRIGGERS)
    threshold = _as_threshold(double_hit_threshold)
    forces = _as_records("force", force)
    responses = _as_records("response", response)
    if forces.shape != responses.shape:
        raise ValueError(f"force and response must have the same shape, got {forces.shape} "
                         f"and {responses.shape}")
    n_hits, n_samples = forces.shape
    duration = n_samples / fs
    if decay * duration > MOST_WINDOW_DECAY:      # nothing left: a rate in the wrong unit
        raise ValueError(f"exponential_decay={decay:g} 1/s ends the window at "
                         f"exp(-{decay * duration:.3g}) over the {duration:.4g} s records: "
                         "nothing of them would be left; give it in 1/s (a window ending at "
                         "a fraction r of its start: -ln(r)/T)")
    cut = (pretrigger == "cut" or pretrigger == "auto" and not decay) and n_fft is None \
        and force_window == "force" and force_window_length is None
    if pretrigger == "cut" and not cut:           # asked for, and not possible: said
        raise ValueError("pretrigger='cut' needs the automatic force window "
                         "(force_window='force', no force_window_length) and no n_fft, got "
                         f"force_window={force_window!r}, force_window_length="
                         f"{force_window_length!r}, n_fft={n_fft!r}")
    if n_fft is None:
        n_fft = n_samples
    n_fft = as_count("n_fft", n_fft, minimum=1)
    top = fs / 2 if max_freq_hz is None else as_positive_scalar("max_freq_hz", max_freq_hz)
    if top > fs / 2 * (1 + 1e-12):
        raise ValueError(f"max_freq_hz must be at most the Nyquist frequency fs / 2 = "
                         f"{fs / 2:.6g} Hz, got {max_freq_hz!r}")
    if n_fft < n_samples:
        raise ValueError(f"n_fft must be >= the record length {n_samples} (records are "
                         f"zero-padded, never cut), got {n_fft}")
    if n_fft > max(_MAX_PAD * n_samples, _MAX_FFT):   # 1e11: a MemoryError, or swap
        raise ValueError(f"n_fft must be at most {max(_MAX_PAD * n_samples, _MAX_FFT)} (64 "
                         f"times the record length {n_samples}, or 2**24; zero padding "
                         f"only interpolates the FRF), got {n_fft}")

    swapped = swapped_channels(forces, responses)
    if swapped is not None:
        warnings.warn(f"the force record does not look like a hammer's: {swapped[0]:.0%} of "
                      "its energy lies within five half-widths of its peak, and "
                      f"{swapped[1]:.0%} of the response's: are the force and response "
                      "channels swapped?", UserWarning, stacklevel=2)
    found = double_hits_in(forces, fs, threshold)
    for i, t_second, ratio, t_main in found:
        warnings.warn(f"double hit in hit {i}: a second force pulse of {ratio:.0%} of the "
                      f"main peak at t = {t_second:.6g} s, {(t_second - t_main) * 1e3:.3g} ms "
                      f"after the main peak; it biases the FRF, consider rejecting hit {i}",
                      DoubleHitWarning, stacklevel=2)

    offsets = pretrigger_offsets(forces, responses) if baseline == "pretrigger" else None
    if offsets is not None:
        forces, responses = forces - offsets[0], responses - offsets[1]
    t = np.arange(n_samples) / fs
    peaks = [main_pulse(f)[1:] for f in forces]  # (k0, peak, fwhm) of each hit
    width = float(np.median([fwhm for _, _, fwhm in peaks])) / fs
    if width > _LONGEST_PULSE:                    # 25.6 for 25.6 kHz: a 500 s record
        warnings.warn(f"the force pulse lasts {1e3 * width:.3g} ms at half its height, a "
                      f"hammer's 0.05-20 ms: is fs={fs!r} in Hz (not kHz)?", UserWarning,
                      stacklevel=2)
    window_length, starts, record_starts = None, None, None
    if force_window == "force":
        if force_window_length is None:
            starts = np.array([max(hit_start(f) - 5 * fwhm, 0)
                               for f, (_, _, fwhm) in zip(forces, peaks)])
            shift = np.zeros_like(starts)     # where each record now starts
            if cut and starts.any():      # each hit from its window's start: t_0 ~ 0
                record_starts = shift = starts
                if starts.max() > _MOST_CUT * n_samples:
                    warnings.warn(f"the pre-trigger cut keeps {n_samples - starts.max()} of "
                                  f"{n_samples} samples of every record (the latest hit "
                                  f"starts at {starts.max() / fs:.6g} s): the lines are "
                                  "that much coarser; pretrigger='keep' keeps them whole",
                                  UserWarning, stacklevel=2)
                n_samples = n_fft = n_samples - int(starts.max())
                duration, t = n_samples / fs, t[:n_samples]
                forces, responses = (np.array([r[k:k + n_samples] for r, k in
                                               zip(records, starts)])
                                     for records in (forces, responses))
                peaks = [(k0 - k, peak, fwhm) for (k0, peak, fwhm), k in zip(peaks, starts)]
            ends = [k0 + 5 * fwhm for k0, _, fwhm in peaks]
            for i, t_second, _, _ in found:   # a double hit's second pulse is force too
                ends[i] = max(ends[i], round(t_second * fs) - shift[i] + 5 * peaks[i][2])
            window_length = min(max(ends), n_samples - 1) / fs
        else:
            window_length = as_positive_scalar("force_window_length", force_window_length)
            if window_length > duration:
                raise ValueError(f"force_window_length must not exceed the record length "
                                 f"{duration:.6g} s ({n_samples} samples at {fs:g} Hz), got "
                                 f"{window_length!r}")
            for i, (k0, _, _) in enumerate(peaks):
                if t[k0] > window_length:
                    raise ValueError(f"force_window_length {window_length!r} s ends before "
                                     f"the force peak of hit {i} at t = {t[k0]:.6g} s")
        keep = t <= window_length * (1 + 1e-12)
        if starts is not None:
            keep = keep & (np.arange(n_samples) >= (starts - shift)[:, None])
        forces = np.where(keep, forces, 0.0)
    elif force_window_length is not None:
        raise ValueError(f"force_window_length is used only with force_window='force', got "
                         f"{force_window_length!r} with force_window='none'")

    if decay:
        w = np.exp(-decay * t)
        forces = forces * w
        responses = responses * w
    F = scipy.fft.rfft(forces, n=n_fft, axis=-1)
    X = scipy.fft.rfft(responses, n=n_fft, axis=-1)
    freq = scipy.fft.rfftfreq(n_fft, 1.0 / fs)
    sff = np.mean(np.abs(F) ** 2, axis=0)
    sxx = np.mean(np.abs(X) ** 2, axis=0)
    sxf = np.mean(X * F.conj(), axis=0)
    if np.any(sff == 0.0):
        k = int(np.flatnonzero(sff == 0.0)[0])
        raise ValueError(f"the force spectrum vanishes at {freq[k]:.6g} Hz: the FRF is "
                         "undefined there")
    warn_of_aliasing(freq, sff, fs)
    keep = freq <= top * (1 + 1e-12)
    freq, sff, sxx, sxf = freq[keep], sff[keep], sxx[keep], sxf[keep]
    h1 = sxf / sff
    coherence = None
    if n_hits >= 2:
        with np.errstate(invalid="ignore", divide="ignore"):
            coherence = np.abs(sxf) ** 2 / (sxx * sff)
        coherence = np.clip(np.nan_to_num(coherence, nan=0.0), 0.0, 1.0)
    k = _S_POWER[quantity]
    if decay and k:
        iw = 2j * np.pi * freq
        h1 = h1 * (iw / (iw + decay)) ** k
    sff = np.array(sff)
    sff.setflags(write=False)
    record_length = duration if n_fft == n_samples else None
    # how it was measured travels with the FRF (and its files): a fit models it unasked
    frf = FRFData(freq, h1, quantity=quantity, coherence=coherence, excitation=sff,
                  window_decay_rate=decay, record_length=record_length)
    return HammerFRF(frf=frf, window_decay_rate=decay, n_hits=n_hits,
                     double_hits=tuple(i for i, *_ in found), force_spectrum=sff,
                     force_window_length=window_length, record_length=record_length,
                     force_window_starts=(None if starts is None
                                          else tuple(float(k / fs) for k in starts)),
                     record_starts=(None if record_starts is None
                                    else tuple(float(k / fs) for k in record_starts)),
                     offsets=offsets)


def correct_exponential_window(model_or_poles, decay_rate):
    """Remove the damping added by an exponential window ``exp(-decay_rate t)``.

    Parameters
    ----------
    model_or_poles : ModalModel or array_like of complex
        A model (or poles, rad/s) identified from an exponentially windowed FRF.
    decay_rate : float
        The window's decay rate ``1/tau`` (1/s), >= 0 (``HammerFRF.window_decay_rate``).

    Returns
    -------
    ModalModel or ndarray of complex
        Of the input's kind: every pole (complex and real) moved right by ``decay_rate``,
        ``p = p_w + decay_rate``; residues, ``flexibility`` and ``inverse_mass`` unchanged.

    Raises
    ------
    ValueError
        A pole the move would leave at ``Re p >= 0`` (not damped by the window alone).

    Notes
    -----
    The window multiplies the impulse response: ``h_w(t) = h(t) exp(-t/tau)``. By the
    shift theorem its Laplace transform is ``H_w(s) = H(s + 1/tau)``, and for
    ``H(s) = sum r_k/(s - p_k) + D``, ``H_w(s) = sum r_k/(s - (p_k - 1/tau)) + D``: each
    pole moves by ``-1/tau`` and each residue is unchanged, exactly (not merely to first
    order), because the window is an exact exponential acting on every exponential mode
    ``r_k exp(p_k t)`` alike. (A free body's rigid term ``1/(M s^2)`` becomes a double
    pole at ``-1/tau``, which a ModalModel cannot hold: ``inverse_mass`` is passed
    through unchanged.) :func:`frf_from_hammer` reports windowed mobilities and
    accelerances so that this holds for them too.
    """
    decay_rate = as_nonnegative_scalar("decay_rate", decay_rate)

    def stable(windowed, kind):
        moved = windowed + decay_rate
        if decay_rate > 0 and np.any(moved.real >= 0):     # at 0 nothing moves
            bad = windowed[moved.real >= 0][0]
            bad = f"{float(bad)!r}" if np.isrealobj(windowed) else f"{complex(bad):.6g}"
            raise ValueError(f"decay_rate {decay_rate!r} moves the {kind} {bad} to Re p >= "
                             f"0: it was not damped by the window alone (a model whose "
                             "window a fit undid already, as ModalFit() does for an FRF "
                             "that states its window, is the structure's: do not correct "
                             "it; else fit the windowed FRF with ModalFit(), which models "
                             "the window, or bound its poles: max_real=-(decay_rate + "
                             "margin))")
        return moved

    if isinstance(model_or_poles, ModalModel):
        m = model_or_poles
        real_poles = stable(m.real_poles, "real pole")
        return m.replace(poles=stable(m.poles, "pole"), real_poles=real_poles)
    poles = as_complex_array("model_or_poles", model_or_poles)
    return stable(poles, "pole")
