"""``ModalFit``: identify a driving-point ``ModalModel`` from an FRF or impulse response.

Pipeline (scikit-learn estimator conventions: settings in ``__init__``, ``fit`` returns
self, learned attributes end in ``_``):

1. poles of every order: LSCF (``"lscf"``), vector fitting (``"vf"``) or python-control's
   ERA on an impulse response (``"era"``);
2. a stabilization diagram and automatic selection of the physical poles (clustering);
3. residues by bounded least squares with the selected poles, rigid-body (mass-line)
   and residual terms; ``passive=True`` keeps every modal mass positive;
4. a joint weighted nonlinear least-squares refinement of all poles and residues
   (``scipy.optimize.least_squares``), with its own uncertainty estimate.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.signal import find_peaks
from sklearn.base import BaseEstimator

from ._checks import as_choice, as_count, as_real_array
from ._era import era_poles_all_orders, fit_residues_time
from ._lscf import lscf_poles_all_orders
from ._lsfd import Terms, evaluate, fit_residues, refine
from ._vf import vector_fit_poles
from .frf import FRFData
from .model import ModalModel
from .stabilization import plot_stabilization, select_poles, stabilization_table

__all__ = ["ModalFit", "ModalFitWarning"]


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
        resonance peaks (``4 n_peaks + 16``, at most 120).
    freq_range : (float, float), optional
        Band (Hz) to fit; default: all lines above 0 Hz.
    rigid_body : {"auto", True, False}
        Fit a rigid-body mass line ``1/(M s^2)``; ``"auto"`` keeps it when the data below
        the first resonance show one.
    residuals : tuple of {"lower", "upper"}
        ``"upper"``: a constant flexibility for the modes above the band. ``"lower"``:
        for a grounded structure whose band starts above its first modes, a pseudo-mode
        at a quarter of the lowest band frequency stands for them (reported).
    passive : bool
        Constrain modal masses, the rigid mass, residual flexibility to be positive.
    refine : bool
        Run the joint nonlinear refinement.
    weighting : {"relative", "uniform"}
        ``"relative"``: weights ``1/|H|`` (times coherence when given), the maximum-
        likelihood weighting for noise proportional to the FRF.

    Attributes
    ----------
    model_ : ModalModel
    poles_ : ndarray of complex (Im > 0)
    stabilization_ : pandas.DataFrame
    clusters_ : pandas.DataFrame
    report_ : dict
    """

    def __init__(self, *, method="lscf", n_modes=None, max_order=None, freq_range=None,
                 rigid_body="auto", residuals=("lower", "upper"), passive=True, refine=True,
                 weighting="relative"):
        self.method = method
        self.n_modes = n_modes
        self.max_order = max_order
        self.freq_range = freq_range
        self.rigid_body = rigid_body
        self.residuals = residuals
        self.passive = passive
        self.refine = refine
        self.weighting = weighting

    # ------------------------------------------------------------------ fitting
    def fit(self, data):
        """Identify the model from ``data``; returns ``self``."""
        as_choice("method", self.method, ("lscf", "vf", "era"))
        as_choice("weighting", self.weighting, ("relative", "uniform"))
        if self.rigid_body not in ("auto", True, False):
            raise ValueError(f"rigid_body must be 'auto', True or False, got {self.rigid_body!r}")
        bad = set(self.residuals) - {"lower", "upper"}
        if bad:
            raise ValueError(f"residuals must be a subset of ('lower', 'upper'), got {bad}")
        if self.method == "era":
            return self._fit_impulse(data)
        if not isinstance(data, FRFData):
            raise TypeError(f"data must be an FRFData for method={self.method!r}, got "
                            f"{type(data).__name__}")
        return self._fit_frf(data)

    def _prepare(self, data: FRFData):
        if self.freq_range is not None:
            data = data.band(self.freq_range)
        data = data.select(data.freq_hz > 0)
        frf = data.to_receptance()
        h = frf.values
        if self.weighting == "relative":
            mag = np.abs(h)
            w = 1.0 / np.maximum(mag, 1e-3 * np.median(mag))
        else:
            w = np.full(h.size, 1.0 / np.sqrt(np.mean(np.abs(h) ** 2)))
        if frf.coherence is not None:
            w = w * np.sqrt(np.clip(frf.coherence, 1e-3, 1.0))
        return data, frf, w

    def _default_order(self, h):
        logmag = np.log10(np.abs(h))
        peaks, _ = find_peaks(logmag, prominence=0.3)
        return int(min(120, 4 * max(peaks.size, 2) + 16))

    def _fit_frf(self, data: FRFData):
        data, frf, w = self._prepare(data)
        omega, h = frf.omega, frf.values
        band = (frf.freq_hz[0], frf.freq_hz[-1])
        max_order = (as_count("max_order", self.max_order, minimum=2) if self.max_order
                     else self._default_order(h))
        poles_by_order = lscf_poles_all_orders(omega, h, w, max_order)
        self.stabilization_ = stabilization_table(poles_by_order, band)
        poles, self.clusters_ = select_poles(self.stabilization_, **self._selection())
        if self.n_modes is None:
            poles = self._select_by_information(omega, h, w, poles)
        iterations = None
        if self.method == "vf":
            n_pairs = poles.size if poles.size else (self.n_modes if isinstance(
                self.n_modes, int) else 4)
            poles, iterations = vector_fit_poles(omega, h, w, n_pairs)
            inside = (np.abs(poles) >= omega[0]) & (np.abs(poles) <= omega[-1])
            poles = poles[inside]
        return self._finish(data, frf, w, poles, max_order, vf_iterations=iterations)

    def _selection(self):
        if self.n_modes is None:
            return {}
        if np.ndim(self.n_modes) == 0:
            return {"n_modes": as_count("n_modes", self.n_modes, minimum=1)}
        return {"frequencies_hz": as_real_array("n_modes", self.n_modes, ndim=1)}

    def _select_by_information(self, omega, h, w, candidates):
        """The persistent clusters that the data support, by the Bayesian information criterion.

        Clusters are added in order of persistence (orders in the stabilization diagram);
        for each count the residues are refitted and ``BIC = n ln(SSE/n) + k ln(n)``
        (``n`` real data, ``k`` real parameters) is computed; the count with the smallest
        BIC wins. A noise pole lowers the residual by about what its four parameters can
        fit in noise, far less than their ``4 ln(n)`` penalty; a physical pole lowers it by
        orders of magnitude.
        """
        clusters = self.clusters_
        if candidates.size <= 1:
            return candidates
        sel = clusters[clusters["selected"]].copy()
        sel["pole"] = -sel["damping_ratio"] * sel["omega_n"] + 1j * sel["omega_n"] * np.sqrt(
            1 - sel["damping_ratio"] ** 2)
        ranked = sel.sort_values(["size", "first_order"], ascending=[False, True])["pole"]
        ranked = ranked.to_numpy()
        terms = Terms(np.zeros(0), self.rigid_body is not False or "lower" in self.residuals,
                      "upper" in self.residuals)
        n = 2 * omega.size
        best_k, best_bic = 0, np.inf
        upper = self._upper_pole(omega)
        for k in range(1, ranked.size + 1):
            *_, sse = fit_residues(omega, h, w, _append(ranked[:k], upper), terms,
                                   passive=self.passive)
            n_par = 4 * k + int(terms.rigid) + int(terms.upper)
            bic = n * np.log(max(sse, 1e-300) / n) + n_par * np.log(n)
            if bic < best_bic:
                best_k, best_bic = k, bic
        keep = np.zeros(len(clusters), bool)
        chosen = set(np.round(ranked[:best_k], 12))
        for i, row in clusters.iterrows():
            if row["selected"]:
                pole = -row["damping_ratio"] * row["omega_n"] + 1j * row["omega_n"] * np.sqrt(
                    1 - row["damping_ratio"] ** 2)
                keep[i] = np.round(pole, 12) in chosen
        self.clusters_ = clusters.assign(selected=keep)
        return np.sort_complex(ranked[:best_k])

    def _upper_pole(self, omega):
        """Pseudo-mode standing for the modes above the band (None without "upper")."""
        if "upper" not in self.residuals:
            return None
        w_u = 1.25 * omega[-1]
        return -0.01 * w_u + 1j * w_u

    def _residual_terms(self, omega, h, w, poles):
        """Decide the rigid-body / lower-residual terms; returns (terms, lower_pole)."""
        upper = "upper" in self.residuals
        want_mass_line = self.rigid_body is not False or "lower" in self.residuals
        terms = Terms(np.zeros(0), bool(want_mass_line), upper)
        if not want_mass_line:
            return terms, None
        with_upper = _append(poles, self._upper_pole(omega))
        r, c, u, d, _, _ = fit_residues(omega, h, w, with_upper, terms, passive=self.passive)
        below_first = poles.size == 0 or omega[0] < 0.7 * np.min(np.abs(poles))
        significant = u / omega[0] ** 2 > 0.05 * np.abs(h[0])
        if self.rigid_body is True or (self.rigid_body == "auto" and significant
                                        and below_first):
            return terms, None
        terms = Terms(np.zeros(0), False, upper)
        if "lower" in self.residuals and significant and not below_first:
            w_l = omega[0] / 4
            return terms, -0.01 * w_l + 1j * w_l
        return terms, None

    def _finish(self, data, frf, w, poles, max_order, *, vf_iterations=None):
        omega, h = frf.omega, frf.values
        if poles.size == 0:
            warnings.warn("no stable physical pole found: the model holds only residual "
                          "terms; see stabilization_", ModalFitWarning, stacklevel=3)
        terms, lower_pole = self._residual_terms(omega, h, w, poles)
        upper_pole = self._upper_pole(omega)
        all_poles = _append(poles, upper_pole)
        bounds = [(0.0, np.inf)] * poles.size + ([(omega[-1], np.inf)] if upper_pole else [])
        if lower_pole is not None:
            all_poles = np.concatenate([[lower_pole], all_poles])
            bounds = [(0.0, omega[0])] + bounds
        r, c, u, d, cov, _ = fit_residues(omega, h, w, all_poles, terms, passive=self.passive)
        converged, message, nfev = True, "linear least squares", 0
        std = np.sqrt(np.clip(np.diag(cov), 0, None))
        if self.refine and all_poles.size:
            (p, r, _, _, u, d), result = refine(
                omega, h, w, all_poles, r, np.zeros(0), np.zeros(0), u, d,
                rigid=terms.rigid, upper=terms.upper, passive=self.passive,
                imag_bounds=bounds)
            all_poles = p
            converged, message, nfev = result.status > 0, result.message, result.nfev
            std = _parameter_std(result)
            if not converged:
                warnings.warn(f"the refinement did not converge: {message}", ModalFitWarning,
                              stacklevel=3)
        model = ModalModel(poles=all_poles, residues=r, inverse_mass=max(u, 0.0),
                           flexibility=d)
        self.model_ = model
        physical = slice(int(lower_pole is not None),
                         all_poles.size - int(upper_pole is not None))
        self.poles_ = np.sort_complex(all_poles[physical])
        fitted = evaluate(omega, all_poles, r, np.zeros(0), np.zeros(0), u, d)
        self.report_ = self._report(frf, fitted, model, converged, message, nfev, max_order,
                                    lower_pole is not None, upper_pole is not None, std,
                                    all_poles.size, vf_iterations)
        return self

    def _report(self, frf, fitted, model, converged, message, nfev, max_order, lower, upper,
                std, n_poles, vf_iterations):
        h = frf.values
        nrmse = float(np.linalg.norm(fitted - h) / np.linalg.norm(h))
        modal_mass = model.modes["modal_mass"].to_numpy()
        inv_sum = model.inverse_mass + float(np.sum(1.0 / modal_mass[modal_mass > 0]))
        table = model.modes.copy()
        order = np.argsort(np.abs(model.poles), kind="stable")
        if std is not None and std.size >= 4 * n_poles:
            s4 = std[:4 * n_poles].reshape(n_poles, 4)[order]
            table["damping_std"] = s4[:, 0] / table["omega_n"]
            table["frequency_hz_std"] = s4[:, 1] / (2 * np.pi)
            table["residue_std"] = np.hypot(s4[:, 2], s4[:, 3])
        return {"method": self.method, "converged": bool(converged), "message": str(message),
                "n_function_evaluations": int(nfev), "max_order": int(max_order),
                "n_modes": model.n_modes - int(lower) - int(upper),
                "lower_residual_mode": bool(lower), "upper_residual_mode": bool(upper),
                "rigid_body": model.inverse_mass > 0, "inverse_mass": model.inverse_mass,
                "flexibility": model.flexibility,
                "effective_mass": (1.0 / inv_sum) if inv_sum > 0 else np.inf,
                "frf_nrmse": nrmse, "band_hz": (float(frf.freq_hz[0]), float(frf.freq_hz[-1])),
                "vf_iterations": vf_iterations, "modes": table}

    def _fit_impulse(self, data):
        try:
            t, h = data
        except (TypeError, ValueError) as exc:
            raise TypeError("method='era' takes an impulse response (t, h)") from exc
        t = as_real_array("t", t, ndim=1)
        h = as_real_array("h", h, ndim=1)
        if t.shape != h.shape or t.size < 16:
            raise ValueError(f"t and h must have equal lengths of at least 16, got {t.size} "
                             f"and {h.size}")
        dt = float(t[1] - t[0])
        if dt <= 0 or not np.allclose(np.diff(t), dt, rtol=1e-6):
            raise ValueError("t must be uniformly spaced and increasing for ERA")
        max_order = as_count("max_order", self.max_order, minimum=2) if self.max_order else 40
        poles_by_order = era_poles_all_orders(h, dt, max_order)
        band = (1e-12, 0.5 / dt)
        self.stabilization_ = stabilization_table(poles_by_order, band)
        poles, self.clusters_ = select_poles(self.stabilization_, **self._selection())
        rigid = self.rigid_body is True
        r, c, u = fit_residues_time(t, h, poles, np.zeros(0), rigid=rigid, passive=self.passive)
        model = ModalModel(poles=poles, residues=r, inverse_mass=max(u, 0.0))
        fitted = model.impulse_response(t)
        self.model_ = model
        self.poles_ = np.sort_complex(poles)
        nrmse = float(np.linalg.norm(fitted - h) / np.linalg.norm(h))
        self.report_ = {"method": "era", "converged": True, "message": "linear least squares",
                        "max_order": max_order, "n_modes": model.n_modes,
                        "rigid_body": rigid, "impulse_nrmse": nrmse, "modes": model.modes}
        return self

    # ------------------------------------------------------------------ use
    def _check_fitted(self):
        if not hasattr(self, "model_"):
            raise ValueError("this ModalFit is not fitted yet: call fit(data) first")

    def predict(self, omega) -> np.ndarray:
        """Receptance (m/N) of the identified model at ``omega`` (rad/s)."""
        self._check_fitted()
        return self.model_.frf(omega)

    def score(self, data: FRFData) -> float:
        """``1 - ||H - H_model||^2 / ||H - mean H||^2`` in the data's own quantity."""
        self._check_fitted()
        data = data.select(data.freq_hz > 0)
        fitted = self.model_.frf(data.omega, quantity=data.quantity)
        h = data.values
        return float(1 - np.sum(np.abs(h - fitted) ** 2) / np.sum(np.abs(h - h.mean()) ** 2))

    def plot_stabilization(self, ax=None):
        """Stabilization diagram with the selected poles; returns the Axes."""
        self._check_fitted()
        return plot_stabilization(self.stabilization_, selected=self.poles_, ax=ax)

    def plot_fit(self, data: FRFData, ax=None):
        """Measured and identified FRF magnitude; returns the Axes."""
        self._check_fitted()
        data = data.select(data.freq_hz > 0)
        ax = data.plot(ax=ax, label="data", color="0.6")
        fitted = self.model_.frf(data.omega, quantity=data.quantity)
        ax.semilogy(data.freq_hz, np.abs(fitted), "C3", lw=1, label="ModalFit")
        ax.legend(fontsize=8)
        return ax


def _append(poles, extra):
    return poles if extra is None else np.concatenate([poles, [extra]])


def _parameter_std(result):
    """Standard deviations of the refined parameters from ``J^T J`` and the residual."""
    jac = result.jac
    dof = max(jac.shape[0] - jac.shape[1], 1)
    sigma2 = 2 * result.cost / dof
    try:
        cov = np.linalg.pinv(jac.T @ jac) * sigma2
    except np.linalg.LinAlgError:
        return None
    return np.sqrt(np.clip(np.diag(cov), 0, None))


