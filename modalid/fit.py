"""``ModalFit``: identify a driving-point ``ModalModel`` from an FRF or impulse response.

A scikit-learn style estimator (settings in ``__init__``, ``fit`` returns self, learned
attributes end in ``_``). Pipeline:

1. poles of every order: LSCF on the band and on nested low sub-bands, merged in one
   stabilization diagram (``"lscf"``); vector fitting from the resonance peaks
   (``"vf"``); python-control's ERA on an impulse response (``"era"``);
2. the clusters that persist over the orders (DBSCAN), as many as the Bayesian
   information criterion supports; or ``n_modes``;
3. the low end from the lowest lines (a free body's receptance is a mass line
   ``-1/(M omega^2)`` there, a grounded one's a positive static flexibility); above the
   band a constant and two pseudo-modes (one free, one held unless the data move it);
4. variable-projection refinement of all poles (residues eliminated), weighted ``1/|H|``
   then ``1/|H_model|`` (maximum likelihood for noise proportional to the FRF); modes the
   estimator missed are added where the residual peaks, poles that are not significant,
   not passive or duplicated are dropped one at a time.
"""

from __future__ import annotations

import contextlib
import warnings

import numpy as np
from sklearn.base import BaseEstimator
from sklearn.exceptions import NotFittedError
from threadpoolctl import threadpool_limits

from ._checks import (as_choice, as_count, as_nonnegative_scalar, as_positive_scalar,
                      as_real_array)
from ._band import choose_weighting
from ._era import fit_impulse
from ._fit_lines import FitLines
from ._fit_one import FitOne
from ._frf_pipeline import FRFPipeline, ModalFitWarning
from ._record_end import refit_without_record_end
from ._verdict import driving_point_decision
from ._window import MOST_WINDOW_DECAY, windowed_receptance
from .frf import FRFData, check_fittable
from .frf_set import FRFSet
from .model import ModalModel
from .quantities import receptance_to
from .stabilization import plot_fit, plot_stabilization

__all__ = ["ModalFit", "ModalFitWarning"]


def _finite_record(length):
    """A record length (s) as modelled: None for none, or for an endless record (inf)."""
    return None if length is None or np.isposinf(length) else float(length)


class ModalFit(FitOne, FRFPipeline, FitLines, BaseEstimator):
    """Identify a pole-residue driving-point receptance.

    Parameters
    ----------
    method : {"lscf", "vf", "era"}
        Pole estimator. ``"era"`` takes an impulse response ``(t, h)``; the others an
        :class:`~modalid.FRFData`.
    n_modes : int or sequence of float, optional
        Number of modes, or their approximate frequencies (Hz); default: automatic.
    max_order : int, optional
        Largest model order of the stabilization diagram; default from the number of
        resonance peaks (``4 n_peaks + 16``, at most 120; an FRF fitted by LSCF with the
        mode count left to the data is fitted by segments, :mod:`modalid._segments`,
        from 8000 lines or from 27 distinct peaks, those that noise does not make); for
        ERA from the rank of the Hankel matrix (its singular values above the noise,
        plus 12). Given, a band of under 8000 lines is fitted whole, up to that order.
    freq_range : (float or None, float or None), optional
        Band (Hz) to fit; an end given as None is the automatic band's (``(None, 7000)``
        keeps the automatic low end). Default: chosen from the data
        (:func:`modalid._band.choose_band`):
        the lowest lines are dropped while they scatter like noise, the top ones where the
        coherence (or, without it, the lines' scatter, or the fall of the excitation's
        spectrum the data carry, ``FRFData.excitation``, 20 dB below its peak) says the
        data stop being informative; ``report_["band_hz"]`` and ``report_["band_reason"]``
        say which and why. ``(0, numpy.inf)`` fits every line above 0 Hz.
    rigid_body : {"auto", True, False}
        Fit a rigid-body mass line ``1/(M s^2)``; ``"auto"`` keeps it when the lines well
        below the first resonance show one (negative real receptance falling like
        ``omega^-2``) and ``freq_range`` did not cut the data there.
    residuals : tuple of {"lower", "upper"}
        ``"upper"``: a constant flexibility and two pseudo-modes above the band for the
        modes there. ``"lower"``: a pseudo-mode below the band for the modes there, used
        when the data show a mass line that is not a rigid body (``freq_range`` cut the
        data above the first modes, the data start too close to the first resonance to
        tell, their lowest lines fall faster than ``omega^-2`` and flatten towards it, as
        just above a resonance, or ``rigid_body=False``), and in a refit of a fit with
        no term there whose model misses the band's lowest lines
        (``report_["missed_low_end_hz"]``).
    passive : {"auto", True, False}
        Keep modal masses, the rigid mass and the residual flexibility positive (a passive
        driving point). ``"auto"`` (default): fit without the constraint, decide from the
        signs of the modal constants whether the FRF is a driving point (modes of
        positive modal mass carry 90 % of the modes' strength ``1/|m|`` and the mass line
        is not negative; :func:`modalid._verdict.driving_point_decision`) and, where it
        is, identify with it (a quick unconstrained refinement decides, or the full
        unconstrained identification where the quick one finds no resonance, misses
        lines by more than the verdict allows or calls it a transfer FRF that the full
        one does not; the full identification follows with the
        constraint, and stays unconstrained when the constraint raises the median error
        per line by half); ``report_["driving_point"]``
        and ``report_["driving_point_reason"]`` say what was decided. An FRFSet's
        driving-point row is decided the same way (``report_["driving_point"]`` stays its
        index, the decision is ``["driving_row_is_driving_point"]``). An impulse response
        (``"era"``) is taken as a driving point.
    refine : bool
        Run the nonlinear refinement (else: residues of the estimated poles only).
    weighting : {"auto", "relative", "mixed", "noise", "uniform"}
        ``"auto"`` (default): ``"relative"`` for noise proportional to the FRF, ``"mixed"``
        for a noise floor under it, ``"noise"`` where the floor dominates
        (:func:`modalid._band.choose_weighting`; an FRFSet: ``"relative"``); a fit
        weighted ``"relative"`` whose verdict is ``"failed"``, that ``passive="auto"``
        found no passive driving point for want of a passive fit, that misses a resonance
        of the data (``report_["missed_resonances_hz"]``) or is ``"suspect"`` for its
        error, is refitted ``"noise"``, which stands where it does better (an FRF's fit,
        not an FRFSet's;
        :meth:`modalid._fit_one.FitOne._fit_weighted`);
        ``report_["weighting"]`` says which and why. ``"mixed"``: one over the modelled
        noise ``sqrt((sigma_rel |H|)^2 + floor^2)`` (:func:`modalid._band.noise_model`),
        then with the model's ``|H|``.
        ``"relative"``: weights ``1/|H|`` (times the square root of the coherence when
        given), then ``1/|H_model|``: maximum likelihood for noise proportional to the
        FRF. ``"noise"``: one over the noise level estimated from the data's own scatter
        (a running median of second differences), for measured FRFs whose noise is not
        proportional (a noise floor). The scatter and the floor are estimated in the
        quantity measured (``FRFData.quantity``), where a sensor's floor is flat, and
        carried to receptance. ``"uniform"``: equal weights.
    weights : array_like of float, optional
        Per-line weights as a setting; they belong to the data, so prefer
        ``fit(data, weights=...)`` (the same meaning; see :meth:`fit`), which this
        route is kept beside for the settings of :meth:`modalid.HammerFRF.fit_options`
        (``weighted=True``). Giving both is an error. ``None`` (default): none.
    max_real : float, optional
        Upper bound (rad/s, < 0) on the real part of every pole in the refinement, e.g.
        ``-(decay_rate + margin)`` for an FRF with an exponential window, so that the
        poles stay stable once :func:`correct_exponential_window` has removed it.
        ``None`` (default): only ``Re p < 0``. FRFData and "lscf" or "vf" only.
    window_decay_rate : float, optional
        Decay rate ``sigma`` (1/s, >= 0) of an exponential window the data carry
        (:attr:`~modalid.hammer.HammerFRF.window_decay_rate`). ``None`` (default): the
        data's own statement (:attr:`FRFData.window_decay_rate`, which
        :func:`modalid.frf_from_hammer` and its files keep), else 0 (none); a value given
        here wins, with a warning where the data state another. The fit then models the
        windowed FRF exactly (poles moved by ``-sigma``, residues kept, the rigid line
        ``1/(M (s + sigma)^2)``) and ``model_``, ``poles_`` and the modal table of
        ``report_`` are the structure's, with the window removed (a pole the removal would
        leave with damping under ``1e-5`` is held there: ``report_["window_clipped"]``).
        FRFData and "lscf" or "vf" only.
    record_length : float, optional
        Length ``T`` (s) of the records whose DFT gave the data, when it was not
        zero-padded (:attr:`~modalid.hammer.HammerFRF.record_length`). The record's end
        cuts each windowed free decay, which on the DFT lines scales mode ``k``'s residue
        by ``1 - exp((p_k - sigma) T)`` and the rigid line by ``1 - exp(-sigma T)`` (exact
        for a hit at the record's start, :mod:`modalid._window`); the fit divides them out
        of the physical modes (its pseudo-modes describe the band's data, not free decays:
        they keep their fitted residues). ``None`` (default): the data's own statement
        (:attr:`FRFData.record_length`), else no correction (an untruncated FRF);
        ``numpy.inf``: no correction whatever the data say. Needs ``window_decay_rate > 0``
        for a rigid body. The rigid line's factor depends on what was recorded (the data's
        ``quantity``); for an acceleration the record's end also adds ``A_2/(s + sigma)^2``
        to the mass line, which is taken out; the other ``A_j`` terms (what is left of each
        mode at the record's end: large where a mode has not died out within it) are
        computed from a first fit's modes, taken out of the data and the fit repeated where
        they exceed 1 % of the band's lowest lines (:mod:`modalid._record_end`,
        ``report_["record_end_removed"]``); a displacement record of a free body adds a
        term the model lacks (prefer velocity or acceleration there).
    missed_modes : {"strict", "dense"}
        How readily a peak of the fit's residual becomes a mode the pole estimator
        missed. ``"strict"`` (default): when the mode halves the weighted residual on the
        lines around it, by much more than the data's noise there (mains-hum lines, steps
        in the data and broad residual trends stay out); up to six modes per pass, or
        half the band's peaks (at most 30) where it has more.
        ``"dense"``: when the information criterion supports it (the cost drops by more
        than ``4 ln(n)`` residual variances), the mode lies two lines or more from every
        other and its damping ratio (window removed) is under 0.1; up to 60 modes per
        pass, three rejected peaks in a row end the search. For measured bands with many
        weakly excited or close modes: on the real hammer test of
        ``benchmarks/hammer_hit5.py`` it adds 9 modes to the 47 of ``"strict"``;
        the run time grows with the modes found. FRFData and "lscf" or "vf" only.
    progress : bool
        Print one line per segment of a wide band (:mod:`modalid._segments`) to stderr:
        the segment, its band and the time so far. Default False (the command line
        turns it on).

    Attributes
    ----------
    model_ : ModalModel
        The identified model, pseudo-modes included (they stand for out-of-band modes).
    poles_ : ndarray of complex (Im > 0)
        The physical poles, by frequency.
    stabilization_ : pandas.DataFrame
        Every candidate pole of every order and band (:func:`stabilization_table`).
    clusters_ : pandas.DataFrame
        The pole clusters and which were selected.
    frf_ : FRFData
        The receptance fitted (the band, lines above 0 Hz); ``impulse_`` ``(t, h)`` for
        ERA.
    data_ : FRFData
        The same band in the data's own quantity (what a re-fit with the same settings
        takes: a windowed fit's terms depend on what was recorded).
    weights_ : ndarray or None
        The per-line weights given, on ``data_``'s lines (what that re-fit takes as
        ``fit(data_, weights=weights_)``); None without.
    window_decay_rate_, record_length_ : float, float or None
        The window (1/s) and record length (s) the fit modelled: the settings, else the
        data's statement (0 and None: none).
    report_ : FitReport
        Read-only, by key or attribute (:class:`modalid.FitReport`): ``converged``,
        ``message``, ``n_iterations``; ``n_modes`` and ``modes`` (the physical modes:
        frequency, damping, residue, modal mass and their standard deviations);
        ``rigid_body``, ``rigid_mass``, ``inverse_mass`` and the standard deviations
        ``inverse_mass_std`` and ``flexibility_std`` (of the constant term;
        NaN when not estimated, or when a lower or upper pseudo-mode trades against the
        term: its marginal std is then meaningless);
        ``lower_residual_mode``, ``upper_residual_modes``; the high-frequency behaviour:
        ``effective_mass`` ``1/(sum 1/m_k + 1/M)`` over the model's modes (pseudo-modes
        included), ``effective_mass_physical`` (physical modes only) and
        ``residual_flexibility``; ``frf_nrmse`` (against the receptance),
        ``frf_nrmse_data`` (in the data's own quantity, ``data_quantity``), ``band_hz``,
        ``max_order``, ``notes`` (modes added or dropped, with why);
        ``missed_resonances_hz`` and ``missed_low_end_hz`` (the band's lowest lines the
        model misses, ``(first, last)`` Hz, or None), which make the verdict "suspect".

    Warns
    -----
    ModalFitWarning
        When the refinement did not converge or the band holds no resonance
        (``report_`` says so too).

    Examples
    --------
    >>> from data_synth import Rod
    >>> truth = Rod(1.0, 1.0, support="fixed").modal_model(18, damping_ratio=0.01,
    ...                                                     residual=True)
    >>> freq = np.linspace(0.001, 4.0, 4000)
    >>> fit = ModalFit().fit(FRFData(freq, truth.frf(2 * np.pi * freq)))
    >>> fit.report_["n_modes"], bool(fit.report_["rigid_body"])
    (8, False)
    >>> np.round(np.abs(fit.poles_[:3]) / (2 * np.pi), 4)
    array([0.25, 0.75, 1.25])
    """

    def __init__(self, *, method="lscf", n_modes=None, max_order=None, freq_range=None,
                 rigid_body="auto", residuals=("lower", "upper"), passive="auto", refine=True,
                 weighting="auto", weights=None, max_real=None, window_decay_rate=None,
                 record_length=None, missed_modes="strict", progress=False):
        self.method = method
        self.n_modes = n_modes
        self.max_order = max_order
        self.freq_range = freq_range
        self.rigid_body = rigid_body
        self.residuals = residuals
        self.passive = passive
        self.refine = refine
        self.weighting = weighting
        self.weights = weights
        self.max_real = max_real
        self.window_decay_rate = window_decay_rate
        self.record_length = record_length
        self.missed_modes = missed_modes
        self.progress = progress

    # ------------------------------------------------------------------ fitting
    def fit(self, data, weights=None):
        """Identify the model from ``data``; returns ``self``.

        Parameters
        ----------
        data : FRFData, FRFSet, or (t, h) for ``method="era"``
            Any FRF quantity (converted to receptance); the impulse response in m/(N s)
            on a uniform time grid. An :class:`FRFSet` (one driving point required) is
            fitted with common poles (global LSCF, residues per output, joint refinement;
            ``passive`` constrains the driving-point row only): ``model_`` is then a
            :class:`MultiOutputModalModel`, ``mode_shapes_`` (n_outputs, n_modes) its
            physical modes' residue rows divided by the driving point's, and ``report_``
            gives ``frf_nrmse``, ``frf_nrmse_data`` and ``noise_estimate_data`` (the
            data's own scatter, relative) per output.
        weights : array_like of float, shape (n_lines,), optional
            Weights of the data's lines, one per line of the ``FRFData`` (all its lines,
            the band is cut from them with the data), finite, >= 0 and not all 0: the
            error is weighted in the data's own quantity and they replace ``weighting``
            (no reweighting by the model). A weight of 0 leaves its line out of the fit.
            For example the error of a predicted response spectrum:
            ``sqrt(S_ff * coherence)`` for an H1 estimate. ``None`` (default):
            ``weighting`` decides. FRFData and ``method`` "lscf" or "vf" only.

        Returns
        -------
        ModalFit
            ``self``, fitted.

        Raises
        ------
        ValueError
            Bad settings, or ``weights`` of the wrong length, not finite, negative, all 0
            (on the data or on the band fitted), given with an FRFSet or ERA, or given
            both here and as the estimator's setting.
        """
        as_choice("method", self.method, ("lscf", "vf", "era"))
        as_choice("weighting", self.weighting, ("auto", "relative", "mixed", "noise", "uniform"))
        self._weighting_on = "relative" if self.weighting == "auto" else self.weighting
        self._weighting_reason = "given" if self.weighting != "auto" else "an FRFSet or ERA"
        as_choice("missed_modes", self.missed_modes, ("strict", "dense"))
        if not (isinstance(self.passive, str) and self.passive == "auto"
                or isinstance(self.passive, (bool, np.bool_))):
            raise ValueError(f"passive must be 'auto', True or False, got {self.passive!r}")
        if not (isinstance(self.rigid_body, str) and self.rigid_body == "auto"
                or isinstance(self.rigid_body, (bool, np.bool_))):
            raise ValueError(f"rigid_body must be 'auto', True or False, got {self.rigid_body!r}")
        if isinstance(self.residuals, str) or not hasattr(self.residuals, "__iter__"):
            raise TypeError(f"residuals must be a tuple of 'lower' and/or 'upper', got "
                            f"{self.residuals!r}")
        bad = set(self.residuals) - {"lower", "upper"}
        if bad:
            raise ValueError(f"residuals must be a subset of ('lower', 'upper'), got {bad}")
        self._selection()                        # validates n_modes
        for name in ("model_", "poles_", "stabilization_", "clusters_", "report_", "frf_",
                     "data_", "weights_", "impulse_", "mode_shapes_", "_stabilization_cache",
                     "_probe", "_probe_assembly", "_zero_start", "_passive_stalled",
                     "_weighting_forced", "_record_cut", "window_decay_rate_", "record_length_"):
            self.__dict__.pop(name, None)         # a second fit starts afresh
        self._resolve_window(data)
        # asked for by the settings (an FRFSet or ERA fit cannot model them)
        windowed = bool(self.window_decay_rate) or _finite_record(self.record_length) is not None
        self._line_weights = self._given_weights(weights)
        weighted = self._line_weights is not None
        if isinstance(data, FRFSet) and (weighted or self.max_real is not None or windowed):
            raise ValueError("weights, max_real, window_decay_rate and record_length apply "
                             "to an FRFData fit only")
        if self.method == "era" and (weighted or self.max_real is not None or windowed):
            raise ValueError("weights, max_real, window_decay_rate and record_length apply "
                             "to method 'lscf' or 'vf' only")
        if self.max_real is not None and not float(self.max_real) < 0:
            raise ValueError(f"max_real must be negative, got {self.max_real!r}")
        auto = isinstance(self.passive, str)
        self._passive_on = bool(self.passive) if not auto else True
        if isinstance(data, FRFSet):              # common poles: see modalid._global
            return self._fit_set(data, auto)
        if self.method != "era" and not isinstance(data, FRFData):
            raise TypeError(f"data must be an FRFData or FRFSet for method={self.method!r}, "
                            f"got {type(data).__name__}")
        if isinstance(data, FRFData):
            check_fittable(data)
        # small dense algebra: BLAS threads only add overhead (restored on exit); a
        # segment's fit runs inside its parent's limit (finding the libraries again
        # costs ~6 ms a call)
        inside = bool(self.__dict__.get("_segment_of"))
        with contextlib.nullcontext() if inside else threadpool_limits(limits=1,
                                                                        user_api="blas"):
            if self.method == "era":
                fit_impulse(self, data)
                return self._judge(driving_point=None, reason="an impulse response: not "
                                   "decided (taken as a driving point)")
            return refit_without_record_end(self, data, auto)

    def _fit_set(self, data: FRFSet, auto: bool):
        """Common poles (:func:`modalid._global.fit_set`). ``weighting="auto"``: the
        driving-point row's noise decides (:func:`modalid._band.choose_weighting`; a noise
        floor calls for ``"noise"``, a set has no ``"mixed"``). ``passive="auto"``: an
        unconstrained fit first; the passivity constraint on the driving-point row only
        when its modes say it is one (:func:`modalid._verdict.driving_point_decision`)."""
        from ._global import fit_set

        dp = data.require_driving_point("ModalFit.fit with common poles")
        if self.weighting == "auto":
            row = data.row(dp).select(data.freq_hz > 0)
            chosen, self._weighting_reason = choose_weighting(row.values)
            self._weighting_on = "relative" if chosen == "relative" else "noise"
        with threadpool_limits(limits=1, user_api="blas"):
            if not auto:
                fit_set(self, data)
                return self._judge(driving_point=bool(self.passive),
                                   reason=f"passive={self.passive!r} given")
            self._passive_on = False
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                fit_set(self, data)
            driving, reason = driving_point_decision(
                self.report_["modes"], float(self.model_.inverse_mass[dp]))
            if driving:
                self._passive_on = True
                fit_set(self, data)
            else:
                for w in caught:                  # the unconstrained fit stands
                    warnings.warn(w.message, w.category, stacklevel=3)
                warnings.warn(f"the set's driving-point row {data.outputs[dp]!r} is not a "
                              f"driving point ({reason}): the fit stands as a set of transfer "
                              "FRFs, and its model cannot be an impact body; give the row "
                              "measured at the excitation", ModalFitWarning, stacklevel=3)
        return self._judge(driving_point=driving, reason=f"row {data.outputs[dp]!r}: {reason}")

    def _resolve_window(self, data):
        """Set ``window_decay_rate_`` and ``record_length_``, what the fit models: the
        estimator's settings, else what ``data`` (an FRFData) states; a setting that
        contradicts the data's statement wins with a ``UserWarning``."""
        decay, length = self.window_decay_rate, self.record_length
        if decay is not None:
            decay = as_nonnegative_scalar("window_decay_rate", decay)
        if length is not None and not (isinstance(length, (float, np.floating))
                                       and np.isposinf(length)):
            length = as_positive_scalar("record_length", length)
        modelled = {}
        for name, mine in (("window_decay_rate", decay), ("record_length", length)):
            stated = getattr(data, name, None) if isinstance(data, FRFData) else None
            # to the 9 digits a command line's flags print
            if stated is not None and mine is not None and not np.isclose(
                    mine, stated, rtol=1e-8, atol=0.0) and not self.__dict__.get("_segment_of"):
                models = "no record end" if np.isposinf(mine) else f"{mine:.9g}"
                warnings.warn(f"{name}={mine:.9g} given, but the data state {stated:.9g} (how "
                              f"they were measured, FRFData.{name}): the fit models "
                              f"{models}", UserWarning, stacklevel=3)
            modelled[name] = stated if mine is None else mine
        self.window_decay_rate_ = float(modelled["window_decay_rate"] or 0.0)
        self.record_length_ = _finite_record(modelled["record_length"])
        # (the record's length only: the line spacing of a zero-padded FFT is not it)
        span = self.record_length_
        if span is not None and self.window_decay_rate_ * span > MOST_WINDOW_DECAY:
            whose = ("window_decay_rate=" if decay is not None
                     else "the data's FRFData.window_decay_rate, ")
            raise ValueError(
                f"{whose}{self.window_decay_rate_:g} 1/s, ends the window at "
                f"exp(-{self.window_decay_rate_ * span:.3g}) over the record ({span:.4g} s): "
                "nothing of the record would be left; give the decay rate in 1/s (for a "
                "window ending at a fraction r of its start: -ln(r)/T)")

    @property
    def _passive_on(self) -> bool:
        """The passivity constraint in effect (``passive="auto"`` sets it per pass)."""
        if "_passive_now" in self.__dict__:
            return self.__dict__["_passive_now"]
        return True if isinstance(self.passive, str) else bool(self.passive)

    @_passive_on.setter
    def _passive_on(self, value):
        self.__dict__["_passive_now"] = bool(value)

    @property
    def _windowed(self) -> bool:
        """An exponential window or a record's end to model (``window_decay_rate_``,
        ``record_length_``; before a fit, the settings)."""
        return bool(self._shift) or self._record is not None

    @property
    def _record(self):
        """The record length modelled (``record_length_``; before a fit, or for a fit
        pickled before it existed, the setting), None for none."""
        return _finite_record(self.__dict__.get("record_length_", self.record_length))

    @property
    def _shift(self) -> float:
        """The window's decay rate (``window_decay_rate_``; before a fit, the setting): the
        rigid line is ``1/(s + _shift)^2``."""
        return float(self.__dict__.get("window_decay_rate_", self.window_decay_rate) or 0.0)

    def _selection(self):
        if self.n_modes is None:
            return {}
        if np.ndim(self.n_modes) == 0:
            return {"n_modes": as_count("n_modes", self.n_modes, minimum=1)}
        freqs = as_real_array("n_modes", self.n_modes, ndim=1)
        if freqs.size == 0 or np.any(freqs <= 0):
            raise ValueError(f"n_modes as frequencies must be positive Hz, got {freqs!r}")
        return {"frequencies_hz": freqs}

    # ------------------------------------------------------------------ use
    def _check_fitted(self):
        if not hasattr(self, "model_"):
            raise NotFittedError("this ModalFit is not fitted yet: call fit(data) first")

    def predict(self, omega) -> np.ndarray:
        """Receptance (m/N) of the identified model at ``omega`` (rad/s); shape
        ``(n_outputs,) + omega.shape`` after fitting an FRFSet.

        Parameters
        ----------
        omega : array_like of float
            Angular frequencies (rad/s).

        Returns
        -------
        numpy.ndarray of complex
        """
        self._check_fitted()
        return self.model_.frf(omega)

    def score(self, data) -> float:
        """``1 - ||H - H_model||^2 / ||H - mean H||^2`` in the data's own quantity (for an
        FRFSet: the mean over its rows, each against its own mean).

        Parameters
        ----------
        data : FRFData or FRFSet
            The data to score the model on.

        Returns
        -------
        float
            1 for a perfect fit.
        """
        self._check_fitted()
        _check_data("data", data)
        data = data.select(data.freq_hz > 0)
        fitted = self._fitted_values(data)
        h = data.values
        mean = h.mean(axis=-1, keepdims=True)
        scores = 1 - np.sum(np.abs(h - fitted) ** 2, axis=-1) / np.sum(np.abs(h - mean) ** 2,
                                                                      axis=-1)
        return float(np.mean(scores))

    def _fitted_values(self, data):
        """The model on ``data``'s lines in its quantity; windowed like the data fitted
        (what was recorded: ``data_.quantity``) when the fit had ``window_decay_rate`` or
        ``record_length``."""
        if self.method == "era" or not self._windowed:
            return self.model_.frf(data.omega, quantity=data.quantity)
        h = windowed_receptance(self.model_, data.omega, self._shift,
                                self._record, quantity=self.data_.quantity,
                                cut=getattr(self, "_record_cut", None))
        return receptance_to(data.quantity, h, data.omega)

    def plot_stabilization(self, ax=None):
        """Stabilization diagram with the selected poles and the magnitude of the band
        fitted (:func:`modalid.stabilization.plot_stabilization`); returns the Axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (a new figure when None).

        Returns
        -------
        matplotlib.axes.Axes
        """
        self._check_fitted()
        data = getattr(self, "data_", None)                   # the band fitted, if an FRF
        frf = data if getattr(data, "freq_hz", None) is not None else None
        return plot_stabilization(self.stabilization_, frf=frf, selected=self.poles_, ax=ax)

    def plot_fit(self, ax=None, *, data=None, output=None):
        """The data fitted (or ``data``) and the model; returns the Axes.

        FRF fits: in the quantity measured (``data_``), magnitude, phase and, where
        measured, coherence against frequency (Hz) (:func:`modalid.stabilization.plot_fit`);
        ERA: impulse responses against time. After fitting an FRFSet: the row ``output``
        (index or label; default the driving point), in receptance.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or sequence of Axes, optional
            One Axes: the magnitude only; a sequence: magnitude, phase, coherence; None: a
            new figure with all of them.
        data : FRFData, optional, keyword-only
            Other data to draw the model against.
        output : int or str, optional, keyword-only
            The row of an FRFSet fit.

        Returns
        -------
        matplotlib.axes.Axes or sequence of Axes
            ``ax`` as given; with ``ax=None`` the magnitude's (the others are
            ``ax.figure.axes[1:]``).
        """
        self._check_fitted()
        if data is None and self.method == "era":
            return plot_fit(self.model_, impulse=self.impulse_, ax=ax)
        if data is None:
            data = self.data_ if isinstance(self.model_, ModalModel) else self.frf_
        _check_data("data", data)
        if isinstance(self.model_, ModalModel):
            if output is not None:
                raise ValueError(f"output={output!r} applies to a fit of an FRFSet only")
            row = data.select(data.freq_hz > 0)
            return plot_fit(self.model_, frf=data, ax=ax, fitted=self._fitted_values(row))
        i = self.model_.index(self.model_.driving_point if output is None else output)
        row = data.row(i) if isinstance(data, FRFSet) else data
        return plot_fit(self.model_.row(i), frf=row, ax=ax)


def _check_data(name, data):
    """Refuse ``data`` that is not an FRFData or FRFSet, naming ``name``."""
    if not isinstance(data, (FRFData, FRFSet)):
        raise TypeError(f"{name} must be an FRFData or an FRFSet, got "
                        f"{type(data).__name__}")
