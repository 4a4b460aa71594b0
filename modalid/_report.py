"""The report of a modal fit: the figures every method shares, and the widening of its
standard deviations for correlated residuals."""

from __future__ import annotations

import numpy as np

__all__ = ["fit_report", "residual_correlation_inflation"]


def residual_correlation_inflation(residual) -> float:
    """Factor (>= 1) widening standard deviations computed as if the lines' errors were
    independent, from the lag-one correlation ``rho`` of the weighted residual (complex,
    shape (n,)): ``sqrt((1 + rho) / (1 - rho))``, the ratio of the line count to the
    effective count of independent lines for AR(1) errors (Bartlett). White residuals
    (noise alone) give 1; a residual that is model error, smooth over the lines, more.
    ``rho`` is taken in [0, 0.99]."""
    r = np.asarray(residual, dtype=complex)
    power = float(np.sum(np.abs(r) ** 2))
    if r.size < 3 or power <= 0:
        return 1.0
    rho = float(np.real(np.sum(r[1:] * np.conj(r[:-1])))) / power
    rho = min(max(rho, 0.0), 0.99)
    return float(np.sqrt((1.0 + rho) / (1.0 - rho)))


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


def fit_report(model, kinds, info, notes, *, method, max_order, **extra):
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
