"""Synthetic measurements with an exact truth: noisy FRFs, impulse responses, hammer tests.

Every function draws its noise from ``numpy.random.default_rng(seed)``, so a fixed seed
gives the same data on every run, and returns data whose noise-free part is exact (closed
form, to rounding): the truth to test identification against.

* :func:`synthetic_frf` - the exact FRF of a model plus complex Gaussian noise;
* :func:`lightly_damped` - the damped, truncated :class:`modalid.ModalModel` used as the
  truth for the (undamped) exact continua;
* :func:`synthetic_impulse_response` - sampled ``h(t)`` plus Gaussian noise;
* :func:`synthetic_hammer_test` - half-sine hammer hits and their exact responses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalid import FRFData, ModalModel
from modalid.validation import (as_choice, as_count, as_nonnegative_scalar, as_positive_scalar,
                             as_real_array)
from modalid.hammer import RESPONSE_TYPES
from modalid.quantities import QUANTITIES

from ._base import ExactModel

__all__ = ["synthetic_frf", "lightly_damped", "synthetic_impulse_response",
           "synthetic_hammer_test", "HammerTest"]


def _check_model(model, allowed=(ExactModel, ModalModel)):
    if not isinstance(model, allowed):
        names = " or ".join(c.__name__ for c in allowed)
        raise TypeError(f"model must be a {names}, got {type(model).__name__}")
    return model


def _frozen(a) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a


def _complex_gaussian(rng, shape) -> np.ndarray:
    """Circular complex Gaussian of unit variance: real and imaginary std 1/sqrt(2)."""
    g = rng.standard_normal((2,) + tuple(shape))
    return (g[0] + 1j * g[1]) / math.sqrt(2.0)


# --------------------------------------------------------------------------- FRF
def synthetic_frf(model, freq_hz, *, quantity="receptance", noise=0.0, seed=None,
                  noise_floor=0.0) -> FRFData:
    """Exact FRF of ``model`` on ``freq_hz`` plus complex Gaussian noise.

    Parameters
    ----------
    model : ExactModel or ModalModel
        The truth: any ``data_synth`` model or a :class:`modalid.ModalModel`.
    freq_hz : array_like of float, shape (n,)
        Frequency lines (Hz), non-negative and strictly increasing.
    quantity : {"receptance", "mobility", "accelerance"}
    noise : float
        Proportional noise level ``eta >= 0``: at each line the noise has standard
        deviation ``eta |H(omega)|`` (so "5 % noise" is ``noise=0.05``).
    seed : int, numpy.random.Generator or None
        Seed of ``numpy.random.default_rng``.
    noise_floor : float
        Additive floor ``phi >= 0``, relative to ``rms(|H|)`` over the given lines: an
        extra noise of standard deviation ``phi * sqrt(mean |H|^2)`` at every line (it
        dominates at antiresonances, as the noise floor of a real measurement does).

    Returns
    -------
    FRFData
        ``Hn = H + eta |H| e1 + phi rms(|H|) e2`` in the SI units of ``quantity``, with
        ``e1``, ``e2`` independent circular complex Gaussian (real and imaginary parts
        independent, each of standard deviation ``1/sqrt(2)``, so ``E|e|^2 = 1``); no
        coherence. ``e1`` is drawn first, so the proportional noise for a given seed does
        not depend on ``noise_floor``. With ``noise = noise_floor = 0`` the values equal
        ``model.frf(2 pi freq_hz, quantity=quantity)`` exactly.

    Raises
    ------
    ValueError
        If the FRF is infinite at a line (the receptance or mobility of a free body at
        0 Hz, an undamped model exactly at resonance).
    """
    _check_model(model)
    as_choice("quantity", quantity, QUANTITIES)
    freq_hz = as_real_array("freq_hz", freq_hz, ndim=1)
    noise = as_nonnegative_scalar("noise", noise)
    noise_floor = as_nonnegative_scalar("noise_floor", noise_floor)
    values = model.frf(2.0 * np.pi * freq_hz, quantity=quantity)
    if not np.all(np.isfinite(values)):
        k = int(np.flatnonzero(~np.isfinite(values))[0])
        raise ValueError(f"the {quantity} of {type(model).__name__} is infinite at "
                         f"freq_hz = {float(freq_hz[k])!r}: drop that line")
    if noise or noise_floor:
        rng = np.random.default_rng(seed)
        magnitude = np.abs(values)
        e1 = _complex_gaussian(rng, values.shape)
        values = values + noise * magnitude * e1
        if noise_floor:
            rms = math.sqrt(float(np.mean(magnitude**2)))
            values = values + noise_floor * rms * _complex_gaussian(rng, values.shape)
    return FRFData(freq_hz, values, quantity=quantity)


def lightly_damped(model, n_modes, damping_ratio, *, residual=True) -> ModalModel:
    """The damped, truncated truth of an exact model: ``model.modal_model(...)``.

    The exact continua (:class:`~data_synth.Rod`, :class:`~data_synth.CantileverBeam`)
    are undamped: their responses never decay, so a finite record of them has leakage
    and no identification method can recover a damping. This returns their first
    ``n_modes`` modes, each with viscous ``damping_ratio``, plus (``residual=True``) the
    exact static flexibility of the omitted modes, as a :class:`modalid.ModalModel` to
    use as the truth of damped synthetic data (:func:`synthetic_frf`,
    :func:`synthetic_hammer_test`). ``synthetic_frf`` itself never adds damping: pass it
    this model.

    Parameters
    ----------
    model : ExactModel
    n_modes : int
        Number of elastic modes kept.
    damping_ratio : float
        Viscous damping ratio in ``[0, 1)`` of every kept mode.
    residual : bool, keyword-only
        Keep the omitted modes' static flexibility as the model's ``flexibility``
        (default True). An accelerance hammer test needs ``residual=False`` (see
        :func:`synthetic_hammer_test`).

    Returns
    -------
    modalid.ModalModel
        ``n_modes`` damped modes (and the residual flexibility with ``residual``).
    """
    _check_model(model, (ExactModel,))
    return model.modal_model(n_modes, damping_ratio=damping_ratio, residual=residual)


def synthetic_impulse_response(model, fs, n_samples, *, noise=0.0, seed=None):
    """Sampled impulse response ``h(t)`` (m/(N s)) of ``model`` plus Gaussian noise.

    Parameters
    ----------
    model : ExactModel or ModalModel
    fs : float
        Sampling frequency (Hz), > 0; ``t = arange(n_samples) / fs``.
    n_samples : int
        Number of samples, >= 1.
    noise : float
        Noise level ``eta >= 0``: white Gaussian noise of standard deviation
        ``eta * rms(h)`` (``sqrt(mean h^2)`` over the record) is added to every sample.
    seed : int, numpy.random.Generator or None
        Seed of ``numpy.random.default_rng``.

    Returns
    -------
    t, h : ndarray of float, shape (n_samples,)
        Times (s) and samples. A ModalModel's ``flexibility * delta(t)`` is not in ``h``
        (see :meth:`modalid.ModalModel.impulse_response`).
    """
    _check_model(model)
    fs = as_positive_scalar("fs", fs)
    n_samples = as_count("n_samples", n_samples, minimum=1)
    noise = as_nonnegative_scalar("noise", noise)
    t = np.arange(n_samples) / fs
    h = np.asarray(model.impulse_response(t), dtype=float)
    if noise:
        rng = np.random.default_rng(seed)
        h = h + noise * math.sqrt(float(np.mean(h**2))) * rng.standard_normal(n_samples)
    return t, h


# --------------------------------------------------------------------- hammer test
@dataclass(frozen=True, repr=False, eq=False)
class HammerTest:
    """Records of a synthetic hammer test (:func:`synthetic_hammer_test`); immutable.

    Attributes
    ----------
    t : ndarray, shape (n_samples,)
        Sample times (s), ``arange(n_samples) / fs``, the same for every hit.
    force : ndarray, shape (n_hits, n_samples)
        Hammer force (N), one row per hit (each hit is its own record).
    response : ndarray, shape (n_hits, n_samples)
        Response (m, m/s or m/s^2 by ``response_type``).
    fs : float
        Sampling frequency (Hz).
    response_type : str
        ``"displacement"``, ``"velocity"`` or ``"acceleration"``.
    model : modalid.ModalModel
        The true model: ``model.frf(omega, quantity=quantity)`` is the exact FRF.
    hit_times : ndarray, shape (n_hits,)
        Start of the main half-sine pulse in each record (s).
    force_peaks : ndarray, shape (n_hits,)
        Peak of each main pulse (N).
    pulse_width : float
        Duration of each half-sine (s).
    double_hits : tuple of int
        Records holding a second, smaller pulse.
    noise : tuple of float
        ``(force_noise, response_noise)`` levels.
    anti_alias : bool
        Whether both channels passed the anti-aliasing filter (then ``force`` is the
        filtered half-sine).
    noise_reference : str
        What the noise levels are relative to: ``"max"`` or ``"rms"`` of each record.
    """

    t: np.ndarray
    force: np.ndarray
    response: np.ndarray
    fs: float
    response_type: str
    model: ModalModel
    hit_times: np.ndarray
    force_peaks: np.ndarray
    pulse_width: float
    double_hits: tuple
    noise: tuple
    anti_alias: bool
    noise_reference: str = "max"

    @property
    def quantity(self) -> str:
        """FRF quantity measured: receptance, mobility or accelerance."""
        return RESPONSE_TYPES[self.response_type]

    def true_frf(self, freq_hz) -> FRFData:
        """Exact FRF of :attr:`model` in :attr:`quantity` at ``freq_hz`` (Hz).

        Parameters
        ----------
        freq_hz : array_like of float
            Frequency lines (Hz).

        Returns
        -------
        modalid.FRFData
        """
        return synthetic_frf(self.model, freq_hz, quantity=self.quantity)

    def __repr__(self) -> str:
        return (f"HammerTest({self.force.shape[0]} hits x {self.t.size} samples at "
                f"{self.fs:g} Hz, {self.response_type}, {self.model!r})")


def _half_sine_state(p: complex, u: np.ndarray, wc: float) -> np.ndarray:
    """``I(u) = int_0^u exp(p (u - tau)) sin(wc tau) dtau`` for ``0 <= u``, in closed form.

    ``I = (wc e^{pu} - wc cos(wc u) - p sin(wc u)) / (p^2 + wc^2)``; near resonance
    (``p -> +-i wc``, a removable 0/0) ``I = (E(i wc) - E(-i wc)) / (2i)`` with
    ``E(q) = u e^{pu} phi1((q - p) u)``, ``phi1(z) = expm1(z)/z``, free of cancellation.
    """
    d = p * p + wc * wc
    if abs(d) >= 1e-2 * (abs(p) ** 2 + wc * wc):
        return (wc * np.exp(p * u) - wc * np.cos(wc * u) - p * np.sin(wc * u)) / d

    def e(q):
        z = (q - p) * u
        safe = np.where(z == 0, 1.0, z)
        phi1 = np.where(z == 0, 1.0, np.expm1(safe) / safe)
        return u * np.exp(p * u) * phi1

    return (e(1j * wc) - e(-1j * wc)) / 2j


def _pulse_response(model: ModalModel, u: np.ndarray, amplitude: float, width: float,
                    kind: str) -> np.ndarray:
    """Exact response of ``model`` to ``amplitude * sin(pi u / width)`` on ``[0, width]``.

    Each pole ``p`` (residue ``c``) has the state ``z' = p z + f``: ``z`` is
    :func:`_half_sine_state` during the pulse and decays freely, ``z(width)
    exp(p (u - width))``, after it. Its displacement is ``c z``, velocity ``c (p z + f)``
    and acceleration ``c (p^2 z + p f + f')``. ``f'`` jumps at both ends of the pulse
    and takes its mid value there.
    """
    wc = math.pi / width
    started = u >= 0.0
    ui = np.clip(u, 0.0, width)
    after = np.maximum(u - width, 0.0)
    f = np.where(started & (u <= width), amplitude * np.sin(wc * ui), 0.0)
    df = np.where(started & (u <= width), amplitude * wc * np.cos(wc * ui), 0.0)
    df = np.where((u == 0.0) | (u == width), 0.5 * df, df)
    out = np.zeros(u.shape)
    terms = [(p, c, 2.0) for p, c in zip(model.poles, model.residues)]
    terms += [(complex(p), complex(a), 1.0) for p, a in zip(model.real_poles,
                                                             model.real_residues)]
    for p, c, factor in terms:
        z_end = amplitude * _half_sine_state(p, np.array([width]), wc)[0]
        z = np.where(u <= width, amplitude * _half_sine_state(p, ui, wc),
                     z_end * np.exp(p * after))
        z = np.where(started, z, 0.0)
        if kind == "displacement":
            y = c * z
        elif kind == "velocity":
            y = c * (p * z + f)
        else:
            y = c * (p * p * z + p * f + df)
        out += factor * y.real
    if model.inverse_mass:
        # integrals of the pulse: int f and int int f, closed form
        i1 = np.where(started, amplitude / wc * (1.0 - np.cos(wc * ui)), 0.0)
        i2 = np.where(started, amplitude / wc * (ui - np.sin(wc * ui) / wc)
                      + 2.0 * amplitude / wc * after, 0.0)
        out += model.inverse_mass * {"displacement": i2, "velocity": i1,
                                     "acceleration": f}[kind]
    if model.flexibility:
        out += model.flexibility * {"displacement": f, "velocity": df}[kind]
    return out


#: most samples one synthetic hammer test computes (n_hits x duration x fs)
MAX_RECORD_SAMPLES = 2**25
#: Anti-aliasing filter of :func:`synthetic_hammer_test`: Butterworth order, cutoff / fs.
ANTI_ALIAS_ORDER = 8
ANTI_ALIAS_CUTOFF = 0.4


def _butterworth_terms(fs: float):
    """Poles and residues of the analog low-pass ``G(s) = sum rho_j / (s - g_j)``, G(0) = 1."""
    import scipy.signal

    _, g, gain = scipy.signal.butter(ANTI_ALIAS_ORDER, 2.0 * np.pi * ANTI_ALIAS_CUTOFF * fs,
                                     analog=True, output="zpk")
    rho = np.array([gain / np.prod(gj - np.delete(g, j)) for j, gj in enumerate(g)])
    return g, rho


def _filtered_terms(model: ModalModel, kind: str, g: np.ndarray, rho: np.ndarray):
    """Partial fractions of ``G(s) s^k H(s)``: ``(poles, residues, double_pole_at_0)``.

    ``k = 0, 1, 2`` for displacement, velocity, acceleration. With the model's terms
    ``s^k r/(s - p) = r p^k/(s - p) + P(s)`` (``P`` a polynomial of degree < k) and ``G``
    strictly proper of relative degree > k, every product has simple poles: at a model
    pole ``p`` the residue ``r p^k G(p)``, at a filter pole ``g_j`` the residue
    ``rho_j g_j^k H(g_j)``. The rigid term ``mu s^(k-2)`` adds a pole at 0 (k = 1: residue
    ``mu``; k = 0: a double pole ``mu/s^2`` plus ``mu G'(0)/s``, returned separately).
    """
    k = ("displacement", "velocity", "acceleration").index(kind)
    poles = np.concatenate([model.poles, model.poles.conj(), model.real_poles])
    residues = np.concatenate([model.residues, model.residues.conj(), model.real_residues])

    def gain(s):
        return np.sum(rho / (s[..., None] - g), axis=-1)

    out_p = [poles, g]
    out_r = [residues * poles**k * gain(poles),
             rho * g**k * model.without_rigid_body().receptance(g)]
    mu = model.inverse_mass
    double = 0.0
    if mu:
        out_r[1] = out_r[1] + rho * mu * g ** (k - 2)
        if k == 1:
            out_p.append(np.zeros(1))
            out_r.append(np.array([mu + 0j]))
        elif k == 0:
            out_p.append(np.zeros(1))
            out_r.append(np.array([-mu * np.sum(rho / g**2)]))
            double = mu
    return np.concatenate(out_p), np.concatenate(out_r), double


def _filtered_pulse(terms, u: np.ndarray, amplitude: float, width: float) -> np.ndarray:
    """``sum_j c_j z_j(u)`` (real part) for the half-sine: each pole's exact state."""
    poles, residues, double = terms
    wc = math.pi / width
    started = u >= 0.0
    ui = np.clip(u, 0.0, width)
    after = np.maximum(u - width, 0.0)
    out = np.zeros(u.shape, dtype=complex)
    for p, c in zip(poles, residues):
        z_end = amplitude * _half_sine_state(p, np.array([width]), wc)[0]
        z = np.where(u <= width, amplitude * _half_sine_state(p, ui, wc),
                     z_end * np.exp(p * after))
        out += c * np.where(started, z, 0.0)
    if double:
        out += double * np.where(started, amplitude / wc * (ui - np.sin(wc * ui) / wc)
                                 + 2.0 * amplitude / wc * after, 0.0)
    return out.real


def _as_truth(model) -> ModalModel:
    _check_model(model)
    if isinstance(model, ModalModel):
        return model
    if not model.is_rational:
        raise ValueError(f"{type(model).__name__} is not rational (infinitely many undamped "
                         "modes): pass lightly_damped(model, n_modes, damping_ratio) as the "
                         "truth of a hammer test")
    return model.modal_model(model._mode_count())


def _per_hit(name: str, value, n_hits: int, check) -> np.ndarray:
    arr = np.atleast_1d(as_real_array(name, value))
    if arr.ndim != 1 or arr.size not in (1, n_hits):
        raise ValueError(f"{name} must be a scalar or have n_hits = {n_hits} values, got "
                         f"shape {np.shape(value)}")
    for v in arr:
        check(name, float(v))
    return np.broadcast_to(arr, (n_hits,)).astype(float)


def _double_hit_records(double_hit, n_hits: int) -> tuple:
    if isinstance(double_hit, (bool, np.bool_)):
        return tuple(range(n_hits)) if double_hit else ()
    try:
        indices = [as_count("double_hit", i) for i in double_hit]
    except TypeError as exc:
        raise TypeError(f"double_hit must be True, False or a sequence of hit indices, got "
                        f"{double_hit!r}") from exc
    for i in indices:
        if i >= n_hits:
            raise ValueError(f"double_hit index {i} is out of range for n_hits = {n_hits}")
    return tuple(sorted(set(indices)))


def synthetic_hammer_test(model, fs, duration, *, n_hits=1, hit_times=None, pulse_width=None,
                          force_peak=100.0, noise=0.0, response="acceleration", seed=None,
                          double_hit=False, double_hit_delay=None, double_hit_ratio=0.3,
                          anti_alias=False, noise_reference="max") -> HammerTest:
    """Force and response records of half-sine hammer hits on ``model``, exact.

    Each hit is its own record of ``duration`` seconds starting at ``t = 0``: the force
    is the half-sine ``force_peak * sin(pi (t - t0) / pulse_width)`` for
    ``t0 <= t <= t0 + pulse_width`` (``t0`` = the hit time), zero elsewhere, and the
    response is the model's exact response to it, sampled at ``fs`` (an ideal sampler:
    no anti-aliasing filter, so the sampled spectra alias what the force puts above
    ``fs / 2``; keep ``pulse_width`` several samples long).

    Parameters
    ----------
    model : ModalModel or ExactModel
        The truth. A ModalModel is used as is; a rational exact model
        (:class:`~data_synth.SpringMass`, :class:`~data_synth.LumpedMass`) through its
        exact modal model. The continua are not rational: pass
        :func:`lightly_damped` of them.
    fs : float
        Sampling frequency (Hz), > 0.
    duration : float
        Record length (s); ``n_samples = round(duration * fs)``, at least 4.
    n_hits : int
        Number of hits (records), >= 1; ``n_hits * duration * fs`` at most
        ``MAX_RECORD_SAMPLES`` (2**25).
    hit_times : float or array_like, shape (n_hits,), optional
        Start of each main pulse (s, from the record start); default 20 samples
        (``20 / fs``), a pre-trigger as an analyser records.
    pulse_width : float, optional
        Duration ``Tc`` (s) of the half-sine, at least ``2 / fs``; default ``10 / fs``.
        Its spectrum ``|F(f)| = 2 A Tc / pi |cos(pi f Tc) / (1 - (2 f Tc)^2)|`` falls by
        3 dB near ``f = 0.6 / Tc`` and has its first zero at ``f = 1.5 / Tc``.
    force_peak : float or array_like, shape (n_hits,)
        Peak force ``A`` (N) of each main pulse, > 0.
    noise : float or (float, float)
        Noise level, or ``(force_noise, response_noise)``: white Gaussian noise of
        standard deviation ``level`` times the reference (``noise_reference``) of the
        noise-free record of that channel and hit is added to the force and the response.
    response : {"acceleration", "velocity", "displacement"}
        Response recorded; the FRF is then accelerance, mobility or receptance.
    seed : int, numpy.random.Generator or None
        Seed of ``numpy.random.default_rng``; for each hit in turn two standard normal
        sequences are drawn, force then response (whatever the levels, when any is > 0).
    double_hit : bool or sequence of int
        Records that get a double hit (True: all, False: none): a second half-sine of
        the same width and ``double_hit_ratio`` times the peak, starting
        ``double_hit_delay`` after the main pulse starts (the hammer bouncing back).
    double_hit_delay : float, optional
        Default ``3 * pulse_width``; at least ``pulse_width`` (the pulses do not overlap).
    double_hit_ratio : float
        Peak of the second pulse over the first, in (0, 1].
    noise_reference : {"max", "rms"}
        What ``noise`` is relative to: ``"max"`` (default), ``max|signal|``; ``"rms"``,
        the record's root mean square (a signal-to-noise ratio of ``1/level^2`` in power,
        40 dB at 0.01). An impact record's peak is far above its RMS (the force's by
        30x for a pulse of 2.5 samples in 2600, a driving-point velocity's by 10x), so the
        same level gives about 10x less noise with ``"rms"``: at ``fs = 5 f_top`` with 5
        hits and a 1 % exponential window, ``"rms"`` gives H1 estimates whose median
        error per line is about ``level`` (0.7-1.3 ``level`` on rods and a cantilever),
        ``"max"`` about 8-9 ``level``.
    anti_alias : bool
        False (default): the exact signals are sampled as they are. True: both channels
        first pass through the same analog anti-aliasing filter, an order-8 Butterworth
        low-pass with cutoff ``0.4 fs`` (``ANTI_ALIAS_ORDER``, ``ANTI_ALIAS_CUTOFF``), as
        in an analyser; computed exactly too (partial fractions of ``G(s) s^k H(s)``,
        see :func:`_filtered_terms`). The filter's gain and phase are common to both
        channels and cancel in the FRF, while what lies above ``fs / 2`` (the half-sine's
        ``1/f^2`` tail times the mass line of an accelerance) no longer aliases onto
        the band. It also allows an acceleration response with a ``flexibility`` term.

    Returns
    -------
    HammerTest
        ``t``, ``force``, ``response`` (shape ``(n_hits, n_samples)``), the true
        ``model`` and the test's settings.

    Notes
    -----
    The response is exact to rounding (no time stepping): every pole's response to the
    half-sine is in closed form (:func:`_pulse_response`), and pulses add by
    superposition. A model with a ``flexibility`` term has, for an acceleration
    response, Dirac impulses ``flexibility * f''`` at both ends of each pulse that no
    sampled record can hold: that case raises ``ValueError`` (use
    ``lightly_damped(..., residual=False)`` or a displacement or velocity response).
    """
    truth = _as_truth(model)
    fs = as_positive_scalar("fs", fs)
    duration = as_positive_scalar("duration", duration)
    n_hits = as_count("n_hits", n_hits, minimum=1)
    as_choice("response", response, tuple(RESPONSE_TYPES))
    if not isinstance(anti_alias, (bool, np.bool_)):
        raise TypeError(f"anti_alias must be True or False, got {anti_alias!r}")
    if response == "acceleration" and truth.flexibility and not anti_alias:
        raise ValueError(f"an acceleration response of a model with flexibility = "
                         f"{truth.flexibility!r} m/N holds Dirac impulses at the pulse ends; "
                         "use anti_alias=True, a model without the residual term "
                         "(residual=False) or response='displacement'/'velocity'")
    if duration * fs * n_hits > MAX_RECORD_SAMPLES:     # before any work or allocation
        raise ValueError(f"n_hits * duration * fs = {n_hits} * {duration:.6g} s * {fs:.6g} Hz "
                         f"samples exceeds {MAX_RECORD_SAMPLES}: shorten the records, lower fs "
                         "or test fewer hits")
    n_samples = int(round(duration * fs))
    if n_samples < 4:
        raise ValueError(f"duration * fs must give at least 4 samples, got "
                         f"{duration!r} s * {fs!r} Hz = {n_samples}")
    integer = isinstance(seed, (int, np.integer)) and not isinstance(seed, bool)
    if not (seed is None or integer or isinstance(seed, np.random.Generator)):
        raise TypeError(f"seed must be None, an integer or a numpy.random.Generator, got "
                        f"{seed!r}")
    if integer and seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed!r}")
    t = np.arange(n_samples) / fs
    t_end = t[-1]
    width = 10.0 / fs if pulse_width is None else as_positive_scalar("pulse_width",
                                                                      pulse_width)
    if width < 2.0 / fs:
        raise ValueError(f"pulse_width must be at least 2 samples (2 / fs = {2.0 / fs:.6g} "
                         f"s) so that the force is sampled, got {width!r}")
    hits = _per_hit("hit_times", 20.0 / fs if hit_times is None else hit_times, n_hits,
                    as_nonnegative_scalar)
    peaks = _per_hit("force_peak", force_peak, n_hits, as_positive_scalar)
    doubles = _double_hit_records(double_hit, n_hits)
    delay = 3.0 * width if double_hit_delay is None else as_positive_scalar(
        "double_hit_delay", double_hit_delay)
    if delay < width:
        raise ValueError(f"double_hit_delay must be >= pulse_width ({width:.6g} s), got "
                         f"{delay!r}")
    ratio = as_positive_scalar("double_hit_ratio", double_hit_ratio)
    if ratio > 1.0:
        raise ValueError(f"double_hit_ratio must lie in (0, 1], got {ratio!r}")
    if isinstance(noise, (tuple, list)):
        if len(noise) != 2:
            raise ValueError(f"noise must be a level or a pair (force_noise, response_noise), "
                             f"got {noise!r}")
        noise = (as_nonnegative_scalar("noise[0]", noise[0]),
                 as_nonnegative_scalar("noise[1]", noise[1]))
    else:
        level = as_nonnegative_scalar("noise", noise)
        noise = (level, level)
    as_choice("noise_reference", noise_reference, ("max", "rms"))
    reference = ((lambda x: np.max(np.abs(x))) if noise_reference == "max"
                 else (lambda x: np.sqrt(np.mean(x**2))))

    if anti_alias:
        g, rho = _butterworth_terms(fs)
        force_terms = (g, rho, 0.0)
        response_terms = _filtered_terms(truth, response, g, rho)
    rng = np.random.default_rng(seed)
    force = np.zeros((n_hits, n_samples))
    resp = np.zeros((n_hits, n_samples))
    for i in range(n_hits):
        pulses = [(hits[i], peaks[i])]
        if i in doubles:
            pulses.append((hits[i] + delay, ratio * peaks[i]))
        for t0, amplitude in pulses:
            if t0 + width > t_end:
                raise ValueError(f"the pulse of hit {i} starting at {t0:.6g} s (width "
                                 f"{width:.6g} s) does not end within the record "
                                 f"(last sample at {t_end:.6g} s)")
            u = t - t0
            if anti_alias:
                force[i] += _filtered_pulse(force_terms, u, amplitude, width)
                resp[i] += _filtered_pulse(response_terms, u, amplitude, width)
                continue
            inside = (u >= 0.0) & (u <= width)
            force[i] += np.where(inside, amplitude * np.sin(np.pi * np.clip(u, 0, width)
                                                            / width), 0.0)
            resp[i] += _pulse_response(truth, u, amplitude, width, response)
        if noise[0] or noise[1]:
            g = rng.standard_normal((2, n_samples))
            force[i] += noise[0] * reference(force[i]) * g[0]
            resp[i] += noise[1] * reference(resp[i]) * g[1]
    return HammerTest(t=_frozen(t), force=_frozen(force), response=_frozen(resp), fs=fs,
                      response_type=response, model=truth, hit_times=_frozen(hits),
                      force_peaks=_frozen(peaks), pulse_width=width, double_hits=doubles,
                      noise=noise, anti_alias=bool(anti_alias),
                      noise_reference=noise_reference)
