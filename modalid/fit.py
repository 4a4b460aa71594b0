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

import warnings

import numpy as np
from scipy.signal import find_peaks
from sklearn.base import BaseEstimator
from threadpoolctl import threadpool_limits

from ._checks import as_choice, as_count, as_real_array
from ._era import identify_impulse, impulse_samples
from ._lscf import lscf_subbands
from ._lsfd import (Terms, evaluate, mass_line_significant, noise_level, place_upper_modes,
                    refine_varpro, release_gain, removal_cost, split_coefficients)
from ._vf import vector_fit_poles
from .frf import FRFData
from .frf_set import FRFSet
from .model import ModalModel
from .quantities import receptance_to
from .stabilization import (cluster_poles, plot_fit, plot_stabilization,
                            select_by_information, select_poles, stabilization_table)

__all__ = ["ModalFit", "ModalFitWarning"]

_FAR = 2.0          # the held upper pseudo-mode sits at twice the top of the band


class ModalFitWarning(UserWarning):
    """The identification did not converge or found nothing; ``report_`` says what."""


class ModalFit(BaseEstimator):
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
        resonance peaks (``4 n_peaks + 16``, at most 120); for ERA from the rank of the
        Hankel matrix (its singular values above the noise, plus 12).
    freq_range : (float, float), optional
        Band (Hz) to fit; default: all lines above 0 Hz.
    rigid_body : {"auto", True, False}
        Fit a rigid-body mass line ``1/(M s^2)``; ``"auto"`` keeps it when the lines well
        below the first resonance show one (negative real receptance falling like
        ``omega^-2``) and ``freq_range`` did not cut the data there.
    residuals : tuple of {"lower", "upper"}
        ``"upper"``: a constant flexibility and two pseudo-modes above the band for the
        modes there. ``"lower"``: a pseudo-mode below the band for the modes there, used
        when the data show a mass line that is not a rigid body (``freq_range`` cut the
        data above the first modes, the data start too close to the first resonance to
        tell, or ``rigid_body=False``).
    passive : bool
        Keep modal masses, the rigid mass and the residual flexibility positive.
    refine : bool
        Run the nonlinear refinement (else: residues of the estimated poles only).
    weighting : {"relative", "noise", "uniform"}
        ``"relative"``: weights ``1/|H|`` (times the square root of the coherence when
        given), then ``1/|H_model|``: maximum likelihood for noise proportional to the
        FRF. ``"noise"``: one over the noise level estimated from the data's own scatter
        (a running median of second differences), for measured FRFs whose noise is not
        proportional (a noise floor). ``"uniform"``: equal weights.
    weights : array_like of float, optional
        Weights of the data's lines (one per line of the ``FRFData`` given to ``fit``, all
        lines, >= 0), for the error in the data's own quantity; they replace
        ``weighting`` (no reweighting by the model). For example the error of a predicted
        response spectrum: ``sqrt(S_ff * coherence)`` for an H1 estimate. ``None``
        (default): ``weighting`` decides. FRFData and ``method`` "lscf" or "vf" only.
    max_real : float, optional
        Upper bound (rad/s, < 0) on the real part of every pole in the refinement, e.g.
        ``-(decay_rate + margin)`` for an FRF with an exponential window, so that the
        poles stay stable once :func:`correct_exponential_window` has removed it.
        ``None`` (default): only ``Re p < 0``. FRFData and "lscf" or "vf" only.

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
    report_ : dict
        ``converged``, ``message``, ``n_iterations``; ``n_modes`` and ``modes`` (the
        physical modes: frequency, damping, residue, modal mass and their standard
        deviations); ``rigid_body``, ``rigid_mass``, ``inverse_mass``;
        ``lower_residual_mode``, ``upper_residual_modes``; the high-frequency behaviour:
        ``effective_mass`` ``1/(sum 1/m_k + 1/M)`` over the model's modes (pseudo-modes
        included), ``effective_mass_physical`` (physical modes only) and
        ``residual_flexibility``; ``frf_nrmse`` (against the receptance),
        ``frf_nrmse_data`` (in the data's own quantity, ``data_quantity``), ``band_hz``,
        ``max_order``, ``notes`` (modes added or dropped, with why).

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
                 rigid_body="auto", residuals=("lower", "upper"), passive=True, refine=True,
                 weighting="relative", weights=None, max_real=None):
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

    # ------------------------------------------------------------------ fitting
    def fit(self, data):
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
        """
        as_choice("method", self.method, ("lscf", "vf", "era"))
        as_choice("weighting", self.weighting, ("relative", "noise", "uniform"))
        if not (isinstance(self.rigid_body, str) and self.rigid_body == "auto"
                or isinstance(self.rigid_body, (bool, np.bool_))):
            raise ValueError(f"rigid_body must be 'auto', True or False, got {self.rigid_body!r}")
        bad = set(self.residuals) - {"lower", "upper"}
        if bad:
            raise ValueError(f"residuals must be a subset of ('lower', 'upper'), got {bad}")
        self._selection()                        # validates n_modes
        for name in ("model_", "poles_", "stabilization_", "clusters_", "report_", "frf_",
                     "impulse_", "mode_shapes_"):
            self.__dict__.pop(name, None)         # a second fit starts afresh
        if isinstance(data, FRFSet) and (self.weights is not None
                                         or self.max_real is not None):
            raise ValueError("weights and max_real apply to an FRFData fit only")
        if self.method == "era" and (self.weights is not None or self.max_real is not None):
            raise ValueError("weights and max_real apply to method 'lscf' or 'vf' only")
        if self.max_real is not None and not float(self.max_real) < 0:
            raise ValueError(f"max_real must be negative, got {self.max_real!r}")
        if isinstance(data, FRFSet):              # common poles: see modalid._global
            from ._global import fit_set
            with threadpool_limits(limits=1, user_api="blas"):
                return fit_set(self, data)
        if self.method != "era" and not isinstance(data, FRFData):
            raise TypeError(f"data must be an FRFData or FRFSet for method={self.method!r}, "
                            f"got {type(data).__name__}")
        # small dense algebra: BLAS threads only add overhead (restored on exit)
        with threadpool_limits(limits=1, user_api="blas"):
            return self._fit_impulse(data) if self.method == "era" else self._fit_frf(data)

    def _selection(self):
        if self.n_modes is None:
            return {}
        if np.ndim(self.n_modes) == 0:
            return {"n_modes": as_count("n_modes", self.n_modes, minimum=1)}
        freqs = as_real_array("n_modes", self.n_modes, ndim=1)
        if freqs.size == 0 or np.any(freqs <= 0):
            raise ValueError(f"n_modes as frequencies must be positive Hz, got {freqs!r}")
        return {"frequencies_hz": freqs}

    def _relative(self):
        return self.weighting == "relative" and self.weights is None

    def _prepare(self, data: FRFData):
        given = None
        if self.weights is not None:
            given = as_real_array("weights", self.weights, ndim=1)
            if given.shape != data.freq_hz.shape or np.any(given < 0):
                raise ValueError(f"weights must be {data.freq_hz.size} values >= 0 (one per "
                                 f"line of the data), got shape {given.shape}")
            given = given[data.freq_hz > 0]
        data = data.select(data.freq_hz > 0)
        first = data.freq_hz[0]
        if self.freq_range is not None:
            if given is not None:
                lo, hi = self.freq_range
                given = given[(data.freq_hz >= lo) & (data.freq_hz <= hi)]
            data = data.band(self.freq_range)
        cut = bool(data.freq_hz[0] > first)          # lines below the band were dropped
        self._data_band = data                        # in the data's own quantity
        frf = data.to_receptance()
        mag = np.abs(frf.values)
        if self.weighting == "relative":
            w = 1.0 / np.maximum(mag, 1e-12 * mag.max())
        elif self.weighting == "noise":
            w = 1.0 / noise_level(frf.values)
        else:
            w = np.full(mag.size, 1.0 / np.sqrt(np.mean(mag**2)))
        self._coherence_weight = (1.0 if frf.coherence is None
                                  else np.sqrt(np.clip(frf.coherence, 1e-3, 1.0)))
        if given is not None:      # error in the data's quantity -> in receptance
            w = given * np.abs(receptance_to(data.quantity, np.ones(frf.omega.size),
                                             frf.omega))
            scale = np.sqrt(np.mean((w * mag) ** 2))
            return frf, w / (scale if scale > 0 else 1.0), cut
        return frf, w * self._coherence_weight, cut

    def _fit_frf(self, data: FRFData):
        frf, w, cut = self._prepare(data)
        self.frf_ = frf
        omega, h = frf.omega, frf.values
        peaks, _ = find_peaks(np.log10(np.abs(h)), prominence=0.3)
        max_order = (as_count("max_order", self.max_order, minimum=2) if self.max_order
                     else int(min(120, 4 * max(peaks.size, 2) + 16)))
        bands = lscf_subbands(omega, h, w, max_order, peaks=omega[peaks])
        f0 = frf.freq_hz[0]
        # a sub-band's top edge is where its basis wraps (z = -1): its poles there are not
        tops = [(1.0 if k == 0 else 0.9) * top / (2 * np.pi) for k, (top, _) in enumerate(bands)]
        self.stabilization_ = stabilization_table([p for _, p in bands],
                                                  [(f0, top) for top in tops])
        clusters = cluster_poles(self.stabilization_)
        if self._selection():
            poles, selected = select_poles(clusters, **self._selection())
        else:
            poles, selected = self._select_by_information(omega, h, w, clusters, cut)
        self.clusters_ = clusters.assign(selected=selected)
        iterations = None
        if self.method == "vf":
            n_pairs = max(poles.size, 1)
            mass_line = any(self._low_end(omega, h, w, poles, cut))
            poles, iterations = vector_fit_poles(omega, h, w, n_pairs + 2, start=omega[peaks],
                                                 rigid=mass_line)
            poles = poles[(np.abs(poles) >= omega[0]) & (np.abs(poles) <= omega[-1])]
            poles = self._screen(omega, h, w, poles, cut)
        return self._identify(frf, w, poles, cut, max_order, iterations)

    def _select_by_information(self, omega, h, w, clusters, cut, min_share=0.5):
        """Clusters in ``min_share`` of their band's orders, ranked by persistence; the
        information criterion decides how many are physical. (Noise and antiresonance
        poles persist over at most two fifths of the orders, physical ones two thirds; a
        less persistent mode is left to :meth:`_missed_mode`.)"""
        share = clusters["share"].to_numpy(float)
        cand = clusters["pole"].to_numpy(complex)[share >= min_share]
        selected = np.zeros(len(clusters), bool)
        if cand.size:
            keep, _, negative = select_by_information(
                omega, h, w, cand, *self._linear_terms(omega, h, w, cand, cut),
                passive=self.passive)
            self._warn_negative(cand[negative])
            selected[np.flatnonzero(share >= min_share)[keep]] = True
            cand = cand[keep]
        return cand[np.argsort(np.abs(cand))], selected

    def _warn_negative(self, poles):
        """Resonances the data support but with a negative modal mass: not a passive
        driving point (a transfer FRF, or the response sign reversed)."""
        if self.passive and poles.size:
            freqs = ", ".join(f"{abs(p) / (2 * np.pi):.4g}" for p in np.sort(np.abs(poles)))
            warnings.warn(f"resonances at {freqs} Hz have a negative modal mass and are left "
                          "out (passive=True): is this a transfer FRF, or is the sign "
                          "reversed? Fit with passive=False", ModalFitWarning, stacklevel=5)

    def _screen(self, omega, h, w, poles, cut):
        """Vector-fitting poles the data support (greedy forward selection, BIC)."""
        keep, _, negative = select_by_information(
            omega, h, w, poles, *self._linear_terms(omega, h, w, poles, cut), greedy=True,
            passive=self.passive)
        self._warn_negative(poles[negative])
        return poles[keep][np.argsort(np.abs(poles[keep]))]

    def _linear_terms(self, omega, h, w, poles, cut):
        """Terms and fixed pseudo-modes of the linear fits that select the poles."""
        terms = Terms(np.zeros(0), any(self._low_end(omega, h, w, poles, cut)),
                      "upper" in self.residuals)
        fixed = np.zeros(0, complex)
        if "upper" in self.residuals:
            fixed = omega[-1] * np.array([1.1, 1.6]) * (-0.02 + 1j * np.sqrt(1 - 4e-4))
        return terms, fixed

    # ----------------------------------------------------------- low end, residuals
    def _low_end(self, omega, h, w, poles, cut):
        """``(rigid, lower)``: is there a mass line, and is it a rigid body or the lower
        residual of modes below the band?

        With lines well below the first pole, their phase and slope decide (a free body's
        receptance there is ``-1/(M omega^2)``, a grounded one's a positive static
        flexibility); otherwise a ``1/s^2`` term must lower the weighted residual by more
        than its information cost, with a positive mass. A mass line is a rigid body when
        the data reach well below the first pole and ``freq_range`` did not cut them;
        else (and with ``rigid_body=False``) it is the lower residual.
        """
        if self.rigid_body is True:
            return True, False
        first = np.min(np.abs(poles)) if poles.size else omega[-1]
        below = np.flatnonzero(omega < 0.5 * first)[:20]
        if below.size >= 3:
            slope = np.polyfit(np.log(omega[below]), np.log(np.abs(h[below])), 1)[0]
            mass_line = bool(np.median(h[below].real) < 0 and slope < -1.0)
            if not self.passive and slope < -1.5 and np.median(h[below].real) > 0:
                return False, "lower" in self.residuals    # negative mass line: transfer
        else:
            mass_line = mass_line_significant(omega, h, w, poles)
        if not mass_line:
            return False, False
        lower = "lower" in self.residuals
        if self.rigid_body is False:
            return False, lower
        if below.size >= 3 and not cut:
            return True, False
        return not lower, lower

    def _start(self, omega, h, w, poles, cut):
        """Starting poles with their kinds and the linear terms."""
        rigid, lower = self._low_end(omega, h, w, poles, cut)
        upper = "upper" in self.residuals
        terms = Terms(np.zeros(0), rigid, upper)
        kinds = ["mode"] * poles.size
        if lower:
            wl = 0.5 * omega[0]
            poles = np.concatenate([[complex(-0.01 * wl, wl)], poles])
            kinds = ["lower"] + kinds
        if upper:
            ups, _, _ = place_upper_modes(omega, h, w, poles, terms, n_upper=1)
            far = _FAR * omega[-1] * complex(-0.05, np.sqrt(1 - 0.05**2))
            poles = np.concatenate([poles, ups, [far]])
            kinds = kinds + ["upper"] * ups.size + ["far"]
        return poles, np.array(kinds), terms

    def _release_far(self, omega, h, w, poles, kinds, x, info, terms):
        """Free the held far pseudo-mode when the data support moving it: its two
        parameters must lower the cost by more than ``2 ln(n)`` residual variances
        (Gauss-Newton prediction). Clean data do; at a few percent noise it stays put
        (a fixed shape for the distant modes costs less variance than a free one)."""
        hold = kinds == "far"
        wm = self._model_weights(omega, poles, x, terms, w)
        gain = release_gain(omega, h, wm, poles, terms, hold, passive=self.passive)
        if gain < 2 * np.log(2 * omega.size):
            return poles, kinds, x, info
        kinds = np.where(hold, "upper", kinds)
        poles, x, info = self._refine(omega, h, w, poles, kinds, terms)
        return poles, kinds, x, info

    # -------------------------------------------------------------- identification
    def _identify(self, frf, w, poles, cut, max_order, vf_iterations):
        omega, h = frf.omega, frf.values
        poles = poles[np.argsort(np.abs(poles))]
        poles, kinds, terms = self._start(omega, h, w, poles, cut)
        notes = []
        self._iterations, self._buffers = 0, {}
        if self.refine:
            start = poles
            # a quick first pass (a mode missing makes the refinement crawl), then modes
            # the estimator missed, where the residual peaks
            poles, x, info = self._refine(omega, h, w, start, kinds, terms, quick=True)
            tried = []
            for stage in range(2):
                for _ in range(0 if self._selection() else 4):
                    poles, kinds, x, info, found = self._missed_mode(
                        omega, h, w, poles, kinds, x, info, terms, tried)
                    if not found:
                        break
                    notes += found
                    start = poles
                if stage == 0 and info.get("quick"):
                    poles, x, info = self._refine(omega, h, w, poles, kinds, terms)
                else:
                    break
            # drop the worst non-physical pole, refine again from the start without it
            for _ in range(0 if self._selection() else 4):
                k, why = self._worst_pole(omega, h, w, poles, x, info, kinds, terms)
                if k is None:
                    break
                notes.append(why)
                start, kinds = np.delete(start, k), np.delete(kinds, k)
                poles, x, info = self._refine(omega, h, w, start, kinds, terms)
            if np.any(kinds == "far"):
                poles, kinds, x, info = self._release_far(omega, h, w, poles, kinds, x,
                                                          info, terms)
            # a pseudo-mode held at zero modal mass by passivity carries nothing physical
            for _ in range(2 if self.passive else 0):
                idle = (kinds != "mode") & (split_coefficients(x, poles.size, terms)[0].imag >= 0)
                if not idle.any():
                    break
                poles, x, info = self._refine(omega, h, w, poles[~idle], kinds[~idle], terms)
                kinds = kinds[~idle]
        else:
            poles, x, info = refine_varpro(omega, h, w, poles, terms, passive=self.passive,
                                           max_iter=0, max_real=self.max_real)
            info.update(converged=True, message="linear least squares (refine=False)")
        residues, _, u, d = split_coefficients(x, poles.size, terms)
        info["n_iter_total"] = self._iterations
        if not info["converged"]:
            warnings.warn(f"the refinement did not converge: {info['message']}",
                          ModalFitWarning, stacklevel=4)
        if not np.any(kinds == "mode"):
            warnings.warn("no resonance found in the band: the model holds only residual "
                          "terms; see stabilization_", ModalFitWarning, stacklevel=4)
        self._store(frf, poles, kinds, residues, u, d, info, notes, max_order, vf_iterations)
        del self._buffers
        return self

    def _imag_bounds(self, kinds, omega, poles):
        """Bounds on ``Im p``: pseudo-modes stay outside the band, a physical pole within
        10 % of where it started; with ``n_modes`` as frequencies, within 5 % of its own
        and short of half-way to the next (one pole per requested frequency)."""
        upper = (kinds == "upper") | (kinds == "far")
        lo = np.where(upper, omega[-1], np.where(kinds == "mode", 0.9 * poles.imag, 0.0))
        hi = np.where(upper, 4.0 * omega[-1],
                      np.where(kinds == "lower", omega[0],
                               np.where(kinds == "mode", 1.1 * poles.imag, np.inf)))
        freqs, mode = self._selection().get("frequencies_hz"), kinds == "mode"
        if freqs is not None and mode.sum() == freqs.size:
            wf = 2 * np.pi * np.sort(freqs)
            mid = 0.5 * (wf[1:] + wf[:-1])
            lo[mode], hi[mode] = (np.maximum(wf / 1.05, np.insert(mid, 0, 0.0)),
                                  np.minimum(wf * 1.05, np.append(mid, np.inf)))
        return lo, hi

    def _model_weights(self, omega, poles, x, terms, w0):
        if not self._relative():
            return w0
        r, _, u, d = split_coefficients(x, poles.size, terms)
        mag = np.abs(evaluate(omega, poles, r, (), (), u, d))
        if not np.all(np.isfinite(mag)) or mag.max() <= 0:
            return w0                                     # no model to weigh by
        return self._coherence_weight / np.maximum(mag, 1e-12 * mag.max())

    def _refine(self, omega, h, w, poles, kinds, terms, quick=False):
        """Variable projection with the data's weights (to within about a standard
        deviation), then reweighted by the model ``1/|H_model|`` and converged; once more
        if that moved the poles much. ``quick``: the first stage only, 15 steps at most."""
        lo, hi = self._imag_bounds(kinds, omega, poles)
        kw = dict(imag_lo=lo, imag_hi=hi, passive=self.passive, hold=kinds == "far",
                  buffers=self._buffers)
        if self.max_real is not None:
            kw["max_real"] = self.max_real
        relative = self._relative()
        poles, x, info = refine_varpro(omega, h, w, poles, terms, with_std=not relative,
                                       stat_tol=0.1 if relative else 1e-4,
                                       max_iter=15 if quick else 50, **kw)
        n_iter = info["n_iter"]
        for _ in range(0 if quick or not relative else 2):
            wm = self._model_weights(omega, poles, x, terms, w)
            poles, x, info = refine_varpro(omega, h, wm, poles, terms, **kw)
            n_iter += info["n_iter"]
            if info["n_iter"] <= 3:
                break
        info["n_iter"] = n_iter
        info["quick"] = quick and relative
        self._iterations += n_iter
        return poles, x, info

    def _missed_mode(self, omega, h, w, poles, kinds, x, info, terms, tried):
        """Add a mode the pole estimator missed, where the weighted residual has a peak.

        The residual power, averaged over 3 lines, must exceed 14 times its median (for
        noise alone a 1e-9 event) at a frequency not ``tried`` before; a pole of 1 %
        damping is placed there and kept when a quick refinement halves the cost (the
        data's weights) and the new pole passes :meth:`_worst_pole`.
        """
        r, _, u, d = split_coefficients(x, poles.size, terms)
        resid = h - evaluate(omega, poles, r, (), (), u, d)
        wm = self._model_weights(omega, poles, x, terms, w)
        e2 = np.convolve(np.abs(resid * wm) ** 2, np.ones(3) / 3, mode="same")
        e2 /= np.median(e2)
        e2[int(0.98 * e2.size):] = 0.0
        for wt in tried:
            e2[np.abs(omega - wt) < 0.02 * wt] = 0.0
        k = int(np.argmax(e2))
        if e2[k] < 14.0:
            return poles, kinds, x, info, []
        wk = omega[k]
        tried.append(wk)
        trial = np.append(poles, complex(-0.01 * wk, wk))
        kinds_t = np.append(kinds, "mode")
        order = np.argsort(np.where(kinds_t == "mode", np.abs(trial), np.inf), kind="stable")
        trial, kinds_t = trial[order], kinds_t[order]
        poles_t, x_t, info_t = self._refine(omega, h, w, trial, kinds_t, terms, quick=True)
        new = int(np.flatnonzero(order == trial.size - 1)[0])
        worst, _ = self._worst_pole(omega, h, w, poles_t, x_t, info_t, kinds_t, terms, only=new)
        if info_t["cost"] > 0.5 * np.sum(np.abs(resid * w) ** 2) or worst is not None:
            return poles, kinds, x, info, []
        note = f"added a mode the pole estimator missed, at {wk / (2 * np.pi):.6g} Hz"
        return poles_t, kinds_t, x_t, info_t, [note]

    def _worst_pole(self, omega, h, w, poles, x, info, kinds, terms, only=None):
        """The physical pole to drop first, and why (``(None, None)``: all are fine).

        A physical pole must have a positive modal mass, stay in the band, not duplicate a
        stronger one (half-power bands overlapping) and be significant, checked in that
        order; the weakest offender goes. Significant: damping < 0.3 and ``|r| > 6 std``,
        or else removing the mode (the rest refitted linearly) raises the cost by more
        than ``4 ln(n)`` residual variances (a sharp resonance on few lines has a poorly
        determined residue but is plainly there).
        """
        r, *_ = split_coefficients(x, poles.size, terms)
        std = info["std"]["modes"] if info["std"] is not None else np.zeros((poles.size, 4))
        t = np.abs(r) / np.maximum(np.hypot(std[:, 2], std[:, 3]), 1e-300)
        wn, zeta = np.abs(poles), -poles.real / np.abs(poles)
        mode = kinds == "mode"
        if only is not None:
            mode = mode & (np.arange(poles.size) == only)
        overlap = np.abs(wn[:, None] - wn[None, :]) < zeta[:, None] * wn[:, None] + zeta * wn
        weaker = overlap & mode[None, :] & (t[None, :] > t[:, None])
        weak = mode & (t < 6.0) & (zeta <= 0.3)
        if weak.any():
            gain = removal_cost(omega, h, self._model_weights(omega, poles, x, terms, w),
                                poles, terms, np.flatnonzero(weak), passive=self.passive,
                                buffers=self._buffers)
            weak[weak] = gain < 4 * np.log(2 * omega.size)
        tests = [(self.passive & (r.imag >= 0), "no positive modal mass"),
                 ((wn < omega[0]) | (wn > omega[-1]), "it left the band"),
                 (weaker.any(axis=1), "it duplicates a stronger pole"),
                 (weak | (zeta > 0.3), "not significant")]
        for bad, reason in tests:
            bad = bad & mode
            if bad.any():
                k = int(np.flatnonzero(bad)[np.argmin(t[bad])])
                detail = f" (|r|/std = {t[k]:.3g}, damping {zeta[k]:.3g})"
                return k, f"dropped the pole at {wn[k] / (2 * np.pi):.6g} Hz: {reason}{detail}"
        return None, None

    # ------------------------------------------------------------------ results
    def _store(self, frf, poles, kinds, residues, u, d, info, notes, max_order,
               vf_iterations):
        omega, h = frf.omega, frf.values
        self.model_ = ModalModel(poles=poles, residues=residues, inverse_mass=max(u, 0.0),
                                 flexibility=d)
        physical = kinds == "mode"
        self.poles_ = poles[physical][np.argsort(np.abs(poles[physical]))]
        fitted, band = self.model_.frf(omega), self._data_band
        own = self.model_.frf(band.omega, quantity=band.quantity) - band.values
        modes = ModalModel(poles=poles[physical], residues=residues[physical]).modes
        std = info.get("std")
        for name in ("frequency_hz_std", "damping_ratio_std", "residue_std"):
            modes[name] = np.nan
        if std is not None:
            # first-order propagation from (Re p, Im p) to |p| and -Re p/|p|
            order = np.argsort(np.abs(poles[physical]), kind="stable")
            s4, p = std["modes"][physical][order], poles[physical][order]
            wn, sig, nu = np.abs(p), p.real, p.imag
            modes["frequency_hz_std"] = np.hypot(sig * s4[:, 0], nu * s4[:, 1]) / wn / (2 * np.pi)
            modes["damping_ratio_std"] = np.hypot(nu**2 * s4[:, 0], sig * nu * s4[:, 1]) / wn**3
            modes["residue_std"] = np.hypot(s4[:, 2], s4[:, 3])
        self.report_ = _report(
            self.model_, kinds, info, notes, method=self.method, max_order=max_order,
            frf_nrmse=float(np.linalg.norm(fitted - h) / np.linalg.norm(h)),
            frf_nrmse_data=float(np.linalg.norm(own) / np.linalg.norm(band.values)),
            data_quantity=band.quantity,
            band_hz=(float(frf.freq_hz[0]), float(frf.freq_hz[-1])),
            vf_iterations=vf_iterations, modes=modes)

    # ------------------------------------------------------------------ ERA
    def _fit_impulse(self, data):
        t, h = impulse_samples(data)
        max_order = as_count("max_order", self.max_order, minimum=2) if self.max_order else None
        out = identify_impulse(t, h, max_order=max_order, selection=self._selection(),
                               rigid_body=self.rigid_body, passive=self.passive)
        self.stabilization_, self.clusters_ = out["stabilization"], out["clusters"]
        self.impulse_ = (t, h)
        poles, notes = out["poles"], []
        if poles.size == 0:
            warnings.warn("no resonance found in the impulse response", ModalFitWarning,
                          stacklevel=3)
        model = ModalModel(poles=poles, residues=out["residues"],
                           inverse_mass=out["inverse_mass"])
        self.model_, self.poles_ = model, poles
        info = {"converged": True, "message": "ERA poles, residues by linear least squares"}
        self.report_ = _report(model, np.full(poles.size, "mode"), info, notes,
                               method="era", max_order=out["max_order"],
                               impulse_nrmse=out["nrmse"],
                               hankel_singular_values=out["singular_values"],
                               modes=model.modes)
        return self

    # ------------------------------------------------------------------ use
    def _check_fitted(self):
        if not hasattr(self, "model_"):
            raise ValueError("this ModalFit is not fitted yet: call fit(data) first")

    def predict(self, omega) -> np.ndarray:
        """Receptance (m/N) of the identified model at ``omega`` (rad/s); shape
        ``(n_outputs,) + omega.shape`` after fitting an FRFSet."""
        self._check_fitted()
        return self.model_.frf(omega)

    def score(self, data) -> float:
        """``1 - ||H - H_model||^2 / ||H - mean H||^2`` in the data's own quantity (for an
        FRFSet: the mean over its rows, each against its own mean)."""
        self._check_fitted()
        data = data.select(data.freq_hz > 0)
        fitted = self.model_.frf(data.omega, quantity=data.quantity)
        h = data.values
        mean = h.mean(axis=-1, keepdims=True)
        scores = 1 - np.sum(np.abs(h - fitted) ** 2, axis=-1) / np.sum(np.abs(h - mean) ** 2,
                                                                      axis=-1)
        return float(np.mean(scores))

    def plot_stabilization(self, ax=None):
        """Stabilization diagram with the selected poles; returns the Axes."""
        self._check_fitted()
        return plot_stabilization(self.stabilization_, selected=self.poles_, ax=ax)

    def plot_fit(self, ax=None, *, data=None, output=None):
        """The data fitted (or ``data``) and the model; returns the Axes.

        FRF fits: magnitudes against frequency (Hz); ERA: impulse responses against time.
        After fitting an FRFSet: the row ``output`` (index or label; default the driving
        point).
        """
        self._check_fitted()
        if data is None and self.method == "era":
            return plot_fit(self.model_, impulse=self.impulse_, ax=ax)
        data = self.frf_ if data is None else data
        if isinstance(self.model_, ModalModel):
            if output is not None:
                raise ValueError(f"output={output!r} applies to a fit of an FRFSet only")
            return plot_fit(self.model_, frf=data, ax=ax)
        i = self.model_.index(self.model_.driving_point if output is None else output)
        row = data.row(i) if isinstance(data, FRFSet) else data
        return plot_fit(self.model_.row(i), frf=row, ax=ax)


def _high_frequency(model, physical):
    """Effective mass ``1/(sum 1/m_k + 1/M)`` and residual flexibility of a model."""
    masses = model.modes["modal_mass"].to_numpy()
    inv_all = model.inverse_mass + float(np.sum(1.0 / masses[masses > 0]))
    order = np.argsort(np.abs(model.poles), kind="stable")
    phys = masses[physical[order]]
    inv_band = model.inverse_mass + float(np.sum(1.0 / phys[phys > 0]))
    return {"effective_mass": 1.0 / inv_all if inv_all > 0 else np.inf,
            "effective_mass_physical": 1.0 / inv_band if inv_band > 0 else np.inf,
            "residual_flexibility": model.flexibility}


def _report(model, kinds, info, notes, *, method, max_order, **extra):
    """The report common to every method, plus ``extra`` entries."""
    n_modes = int(np.sum(kinds == "mode"))
    if n_modes == 0:
        notes = notes + ["no resonance in the band: the model holds only residual terms"]
    return {"method": method, "converged": bool(info["converged"]),
            "message": str(info["message"]), "n_iterations": int(info.get("n_iter_total", 0)),
            "max_order": int(max_order), "n_modes": n_modes,
            "lower_residual_mode": bool(np.any(kinds == "lower")),
            "upper_residual_modes": int(np.sum((kinds == "upper") | (kinds == "far"))),
            "rigid_body": model.inverse_mass > 0, "inverse_mass": model.inverse_mass,
            "rigid_mass": 1.0 / model.inverse_mass if model.inverse_mass > 0 else np.inf,
            **_high_frequency(model, kinds == "mode"), "notes": notes, **extra}
