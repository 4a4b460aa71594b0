"""The report of a modal fit: the figures every method shares, held in a read-only
:class:`FitReport`, and the widening of its standard deviations for correlated
residuals and for a mode whose lines the model misses."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ._pole_checks import pole_lines

__all__ = ["FitReport", "fit_report", "local_misfit_inflation", "misfit_notes",
           "mode_std_columns", "residual_correlation_inflation"]

#: the modes table's standard deviations (NaN where a fit has none)
STD_COLUMNS = ("frequency_hz_std", "damping_ratio_std", "residue_std", "residue_real_std",
               "residue_imag_std")


class FitReport(Mapping):
    """What a fit found and decided: read-only, by key or by attribute.

    ``report["verdict"]`` and ``report.verdict`` are the same entry; ``list(report)``
    names them all. The entries every fit has: ``method``, ``converged``, ``message``,
    ``n_iterations``, ``max_order``, ``n_modes``, ``modes`` (a DataFrame, one row per
    physical mode: frequency, damping, residue, modal mass, their standard deviations,
    ``damping_resolved``), ``lower_residual_mode``, ``upper_residual_modes``,
    ``rigid_body``, ``inverse_mass`` (1/kg), ``rigid_mass`` (kg; ``rigid_body`` and
    ``rigid_mass`` speak of a positive mass line, a transfer FRF's negative one is in
    ``inverse_mass`` alone), ``effective_mass``,
    ``effective_mass_physical`` (kg), ``residual_flexibility`` (m/N), ``notes``,
    ``verdict`` (``"ok"``, ``"suspect"`` or ``"failed"``) and ``verdict_reasons``; an FRF
    fit adds its band (``band_hz``, ``band_reason``), weighting, driving-point decision
    and errors (``frf_nrmse`` in the data's own quantity, ...). The ``modes`` table is a
    copy per report; changing it changes nothing else.

    Parameters
    ----------
    entries : mapping
        The entries, by name.
    """

    __slots__ = ("_entries",)

    def __init__(self, entries):
        object.__setattr__(self, "_entries", dict(entries))

    def __getitem__(self, key):
        return self._entries[key]

    def __iter__(self):
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __getattr__(self, name):
        if name.startswith("_"):                  # not an entry (copy, pickle, ...)
            raise AttributeError(name)
        try:
            return self._entries[name]
        except KeyError:
            raise AttributeError(f"FitReport has no entry {name!r}") from None

    def __reduce__(self):
        return FitReport, (self._entries,)

    def __setattr__(self, name, value):
        raise AttributeError("a FitReport is read-only; FitReport.replace makes a new one")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._entries))

    def replace(self, **changes) -> FitReport:
        """A new report with ``changes`` (entries added or replaced).

        Parameters
        ----------
        **changes
            Entries by name.

        Returns
        -------
        FitReport
        """
        return FitReport({**self._entries, **changes})

    def __repr__(self) -> str:
        shown = ", ".join(f"{k}={self._entries[k]!r}" for k in
                          ("method", "n_modes", "verdict") if k in self._entries)
        return f"FitReport({shown}; {len(self)} entries)"


def residual_correlation_inflation(residual) -> float:
    """Factor (>= 1) widening standard deviations computed as if the lines' errors were
    independent, from the lag-one correlation ``rho`` of the weighted residual (complex,
    shape (n,), or (n_outputs, n) pooled over the rows): ``sqrt((1 + rho) / (1 - rho))``,
    the ratio of the line count to the effective count of independent lines for AR(1)
    errors (Bartlett). White residuals (noise alone) give 1; a residual that is model
    error, smooth over the lines, more. ``rho`` is taken in [0, 0.99]."""
    r = np.atleast_2d(np.asarray(residual, dtype=complex))
    power = float(np.sum(np.abs(r) ** 2))
    if r.shape[1] < 3 or power <= 0:
        return 1.0
    rho = float(np.real(np.sum(r[:, 1:] * np.conj(r[:, :-1])))) / power
    rho = min(max(rho, 0.0), 0.99)
    return float(np.sqrt((1.0 + rho) / (1.0 - rho)))


def local_misfit_inflation(omega, residual, poles, *, correlation=1.0, quantile=0.99):
    """Per pole, a factor (>= 1) widening its standard deviations where the fit misses the
    lines it acts on by more than noise explains.

    The formula's variance is the band's mean squared weighted residual. Where the model
    cannot follow a mode's own lines (a peak narrower than the lines, smeared by the
    analyzer's window: vtb case2's 192.4 Hz, 100 times the band's mean there) its
    parameters are as uncertain as that misfit says, not as the band's mean does. Over
    the lines the pole acts on (:func:`modalid._pole_checks.pole_lines`), the mean
    ``|r|^2`` over the band's,
    ``ratio``; the factor is ``sqrt(ratio)`` where ``ratio`` exceeds its ``quantile``
    under the noise model (a chi-square with two degrees of freedom per line, over them;
    per ``correlation**2`` lines where the residual is correlated, Bartlett's factor of
    :func:`residual_correlation_inflation`), else 1: a model that fits leaves about one
    mode in a hundred widened.

    Parameters
    ----------
    omega : ndarray, shape (n,)
        Lines (rad/s).
    residual : ndarray of complex, shape (n,) or (n_outputs, n)
        Weighted residual ``w (model - data)``; with several rows (common poles) the
        means are over every row's lines.
    poles : ndarray of complex, shape (m,)
    correlation : float, keyword-only
        Bartlett's factor of the residual (>= 1): its lines count ``1/correlation**2``.
    quantile : float, keyword-only

    Returns
    -------
    ndarray, shape (m,)
    """
    from scipy.stats import chi2

    power = np.abs(np.atleast_2d(np.asarray(residual, dtype=complex))) ** 2
    mean = float(np.mean(power)) if power.size else 0.0
    factors = np.ones(len(poles))
    n_rows, n_lines = power.shape
    if mean <= 0.0 or n_lines < 3:
        return factors
    spacing = float(np.median(np.diff(omega)))
    ratio, dof = np.zeros(len(poles)), np.ones(len(poles))
    for k, p in enumerate(poles):
        near = pole_lines(omega, p, spacing)
        n = int(np.count_nonzero(near))
        if 0 < n < n_lines:
            ratio[k] = float(np.mean(power[:, near])) / mean
            dof[k] = max(2.0 * n * n_rows / correlation ** 2, 1.0)
    # one call for every pole (scipy's distribution call costs 0.1 ms each)
    wide = ratio > chi2.ppf(quantile, dof) / dof
    factors[wide] = np.sqrt(ratio[wide])
    return factors


def mode_std_columns(modes, s4=None, poles=None, scale=None):
    """``modes`` (a DataFrame, one row per physical mode by frequency) with the standard
    deviations of :data:`STD_COLUMNS` from those of the fitted parameters.

    First-order propagation: ``s4`` (shape (n, 4)) holds the stds of ``Re p``, ``Im p``
    (rad/s), ``Re r`` and ``Im r`` of each mode's pole ``p`` (``poles``) and of its
    residue as fitted; the structure's residue is the fitted one divided by ``scale`` (the
    record's truncation factors, complex, shape (n,); ones without a window), so that its
    real and imaginary parts' stds mix the fitted parts' by the factor's phase. The
    fitted parts' errors are taken as independent. ``residue_std`` is the complex
    residue's (``hypot`` of the two parts). ``s4`` None: every column NaN.
    """
    columns = dict.fromkeys(STD_COLUMNS, np.nan)
    if s4 is not None:
        wn, sig, nu = np.abs(poles), poles.real, poles.imag
        scale = np.asarray(scale, complex)
        size = np.abs(scale) ** 2
        # r = r_f / c: Re r = (Re r_f Re c + Im r_f Im c) / |c|^2,
        #              Im r = (Im r_f Re c - Re r_f Im c) / |c|^2
        columns.update(
            frequency_hz_std=np.hypot(sig * s4[:, 0], nu * s4[:, 1]) / wn / (2 * np.pi),
            damping_ratio_std=np.hypot(nu**2 * s4[:, 0], sig * nu * s4[:, 1]) / wn**3,
            residue_real_std=np.hypot(s4[:, 2] * scale.real, s4[:, 3] * scale.imag) / size,
            residue_imag_std=np.hypot(s4[:, 3] * scale.real, s4[:, 2] * scale.imag) / size,
            residue_std=np.hypot(s4[:, 2], s4[:, 3]) / np.abs(scale))
    return modes.assign(**columns)       # one new frame (a column at a time cost 10x)


def misfit_notes(poles, factors):
    """The report's notes on the modes :func:`local_misfit_inflation` widened by 2 or more:
    ``poles`` (complex, rad/s) and their ``factors``, in the order given."""
    return [f"mode at {abs(p) / (2 * np.pi):.6g} Hz: the model misses its lines by "
            f"{f ** 2:.3g} times the band's mean residual; its standard deviations are "
            f"widened {f:.3g} times" for p, f in zip(poles, factors) if f >= 2.0]


def _high_frequency(model, physical):
    """Effective mass ``1/(sum 1/m_k + 1/M)`` over the positive masses (a driving point's)
    and residual flexibility of a model."""
    masses = model.modes["modal_mass"].to_numpy()
    rigid = max(model.inverse_mass, 0.0)
    inv_all = rigid + float(np.sum(1.0 / masses[masses > 0]))
    order = np.argsort(np.abs(model.poles), kind="stable")
    phys = masses[physical[order]]
    inv_band = rigid + float(np.sum(1.0 / phys[phys > 0]))
    return {"effective_mass": 1.0 / inv_all if inv_all > 0 else np.inf,
            "effective_mass_physical": 1.0 / inv_band if inv_band > 0 else np.inf,
            "residual_flexibility": model.flexibility}


def fit_report(model, kinds, info, notes, *, method, max_order, **extra):
    """The report common to every method, plus ``extra`` entries."""
    n_modes = int(np.sum(kinds == "mode"))
    if n_modes == 0:
        notes = notes + ["no resonance in the band: the model holds only residual terms"]
    return FitReport({"method": method, "converged": bool(info["converged"]),
            "message": str(info["message"]), "n_iterations": int(info.get("n_iter_total", 0)),
            "max_order": int(max_order), "n_modes": n_modes,
            "lower_residual_mode": bool(np.any(kinds == "lower")),
            "upper_residual_modes": int(np.sum((kinds == "upper") | (kinds == "far"))),
            "rigid_body": model.inverse_mass > 0, "inverse_mass": model.inverse_mass,
            "rigid_mass": 1.0 / model.inverse_mass if model.inverse_mass > 0 else np.inf,
            **_high_frequency(model, kinds == "mode"), "notes": notes, **extra})
