"""Poles from impulse responses by python-control's eigensystem realization (ERA).

ERA's balanced realization of order ``r`` is the leading ``r x r`` block of the one of
the largest order (its state basis is the leading singular vectors of the Hankel
matrix), so one call to :func:`control.eigensys_realization` gives every order: the
eigenvalues ``z`` of the leading blocks become continuous poles ``s = log(z) / dt``.
Residues then follow from a bounded linear least-squares fit of the samples
``h(t_k) = sum 2 Re(r e^{p t}) + sum c e^{sigma t} + u t`` (time-domain LSFD).
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.optimize import lsq_linear

from ._checks import as_count, as_real_array
from ._frf_pipeline import ModalFitWarning
from ._report import fit_report
from .model import ModalModel

__all__ = ["era_realization", "era_poles_all_orders", "fit_residues_time", "time_columns",
           "select_by_information_time", "identify_impulse", "impulse_samples",
           "fit_impulse"]


def era_realization(h, dt, max_order, *, hankel_size=None):
    """ERA state matrix of order ``max_order`` and the Hankel singular values.

    ``h`` are samples of the impulse response at ``t = k dt`` (m/(N s)); the Markov
    parameters are ``h dt`` (the response to a unit-area discrete impulse).
    """
    import control

    h = np.asarray(h, dtype=float)
    size = hankel_size or int(min((h.size - 2) // 2, max(4 * max_order, 200)))
    if size < max_order:
        raise ValueError(f"the impulse response ({h.size} samples) is too short for "
                         f"max_order={max_order}: at least {2 * max_order + 2} are needed")
    sysd, sv = control.eigensys_realization(h * dt, max_order, m=size, n=size, dt=dt)
    return np.asarray(sysd.A), np.asarray(sv)


def era_poles_all_orders(a, dt, max_order):
    """Poles (rad/s) of the ERA realizations of orders 2, 4, ..., ``max_order``.

    ``a`` is the state matrix of :func:`era_realization`. Returns a list indexed like the
    LSCF one (entry ``k`` holds the poles of order ``k + 1``; odd orders are empty).
    """
    out = []
    for order in range(1, max_order + 1):
        if order % 2:
            out.append(np.zeros(0, complex))
            continue
        z = np.linalg.eigvals(a[:order, :order]).astype(complex)
        z = z[np.abs(z) > 1e-300]
        out.append(np.log(z) / dt)
    return out


def time_columns(t, poles, real_poles=(), *, rigid=False):
    """Columns of ``Re r, Im r`` per pole (``2 Re(r e^{p t})``), ``c_j``, ``u`` (``u t``)."""
    poles = np.asarray(poles, complex)
    e = np.exp(np.outer(t, poles))
    cols = np.empty((t.size, 2 * poles.size + len(real_poles) + int(rigid)))
    cols[:, 0:2 * poles.size:2] = 2 * e.real    # 2 Re(r e) = 2 (Re r Re e - Im r Im e)
    cols[:, 1:2 * poles.size:2] = -2 * e.imag
    for k, sig in enumerate(real_poles):
        cols[:, 2 * poles.size + k] = np.exp(sig * t)
    if rigid:
        cols[:, -1] = t
    return cols


def select_by_information_time(t, h, candidates, *, rigid, passive=True):
    """How many of the ranked ``candidates`` the samples support (see
    :func:`modalid._information.prefix_information`)."""
    from ._information import prefix_information

    candidates = np.asarray(candidates, complex)
    head = time_columns(t, np.zeros(0), rigid=rigid)
    mat = np.hstack([head, time_columns(t, candidates)])
    return prefix_information(mat, np.asarray(h, float), head.shape[1], candidates.size,
                              passive=passive)


def fit_residues_time(t, h, poles, real_poles=(), *, rigid, passive=True):
    """Residues of fixed poles from impulse-response samples (bounded least squares).

    Returns ``(residues, real_residues, inverse_mass, nrmse)``.
    """
    poles = np.asarray(poles, complex)
    if poles.size + len(real_poles) + int(rigid) == 0:
        return np.zeros(0, complex), np.zeros(0), 0.0, 1.0
    a = time_columns(t, poles, real_poles, rigid=rigid)
    scale = np.linalg.norm(a, axis=0)
    scale[scale == 0] = 1.0
    n_c = len(poles)
    lo, hi = np.full(a.shape[1], -np.inf), np.full(a.shape[1], np.inf)
    if passive:
        hi[1:2 * n_c:2] = 0.0
        lo[2 * n_c:] = 0.0
    x = np.linalg.lstsq(a / scale, h, rcond=None)[0]
    if np.any(x < lo) or np.any(x > hi):
        x = lsq_linear(a / scale, h, bounds=(lo, hi), method="bvls").x
    nrmse = float(np.linalg.norm(a / scale @ x - h) / np.linalg.norm(h))
    x = x / scale
    r = x[0:2 * n_c:2] + 1j * x[1:2 * n_c:2]
    c = x[2 * n_c:2 * n_c + len(real_poles)]
    u = float(x[-1]) if rigid else 0.0
    return r, c, u, nrmse


def identify_impulse(t, h, *, max_order=None, selection=None, rigid_body="auto",
                     passive=True):
    """Modes of a sampled impulse response: ERA poles, stabilization, residues.

    ``max_order`` defaults to the rank of the Hankel matrix (its singular values above
    the noise floor) plus 12. A rigid body shows as ERA eigenvalues at ``z = 1`` (within
    one cycle per record). Without ``selection`` (the ``n_modes`` keywords of
    :func:`~modalid.stabilization.select_poles`) the clusters are ranked by persistence
    and the information criterion on the samples picks how many are physical.

    Returns
    -------
    dict
        ``poles``, ``residues``, ``inverse_mass``, ``nrmse`` (of the samples),
        ``stabilization``, ``clusters`` (with ``selected``), ``max_order``,
        ``singular_values``.
    """
    from .stabilization import cluster_poles, select_poles, stabilization_table

    dt = float(t[1] - t[0])
    t = t - t[0]
    cap = int(min(120, (h.size - 2) // 4))
    a, sv = era_realization(h, dt, cap)
    if max_order:
        max_order = min(max_order, cap)
    else:
        floor = max(float(np.median(sv[sv.size // 2:])), 1e-13 * sv[0])
        max_order = int(min(cap, max(2 * (np.count_nonzero(sv > 10 * floor) // 2) + 12, 40)))
    f_low = 1.0 / t[-1]                            # one cycle over the record
    table = stabilization_table(era_poles_all_orders(a, dt, max_order), (f_low, 0.5 / dt))
    clusters = cluster_poles(table, representative="last")
    z = np.linalg.eigvals(a[:max_order, :max_order]).astype(complex)
    near_zero = np.abs(np.log(z[np.abs(z) > 0])) / dt < 2 * np.pi * f_low
    rigid = rigid_body is True or (rigid_body == "auto" and np.count_nonzero(near_zero) >= 2)
    if selection:
        poles, selected = select_poles(clusters, **selection)
    else:
        share = clusters["share"].to_numpy(float)
        cand = clusters["pole"].to_numpy(complex)[share >= 0.1]
        keep = select_by_information_time(t, h, cand, rigid=rigid, passive=passive)[0]
        selected = np.zeros(len(clusters), bool)
        selected[np.flatnonzero(share >= 0.1)[keep]] = True
        poles = cand[keep][np.argsort(np.abs(cand[keep]))]
    residues, _, u, nrmse = fit_residues_time(t, h, poles, rigid=rigid, passive=passive)
    return {"poles": poles, "residues": residues, "inverse_mass": max(u, 0.0),
            "nrmse": nrmse, "stabilization": table,
            "clusters": clusters.assign(selected=selected), "max_order": max_order,
            "singular_values": sv}


def impulse_samples(data):
    """``(t, h)`` checked: equal lengths of at least 16, ``t`` uniform and increasing."""
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
    if dt <= 0 or not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0):
        raise ValueError("t must be uniformly spaced and increasing for ERA")
    return t, h


def fit_impulse(estimator, data):
    """The ERA fit of :class:`modalid.ModalFit` (``method="era"``) on an impulse response.

    Sets ``stabilization_``, ``clusters_``, ``impulse_``, ``model_``, ``poles_`` and
    ``report_`` on ``estimator`` (its ``max_order``, ``n_modes``, ``rigid_body`` and
    passivity in effect decide the fit) and returns it; warns
    (:class:`modalid.ModalFitWarning`) when no resonance is found.
    """
    t, h = impulse_samples(data)
    max_order = (as_count("max_order", estimator.max_order, minimum=2)
                 if estimator.max_order else None)
    out = identify_impulse(t, h, max_order=max_order, selection=estimator._selection(),
                           rigid_body=estimator.rigid_body, passive=estimator._passive_on)
    estimator.stabilization_, estimator.clusters_ = out["stabilization"], out["clusters"]
    estimator.impulse_ = (t, h)
    poles = out["poles"]
    if poles.size == 0:
        warnings.warn("no resonance found in the impulse response", ModalFitWarning,
                      stacklevel=3)
    model = ModalModel(poles=poles, residues=out["residues"],
                       inverse_mass=out["inverse_mass"])
    estimator.model_, estimator.poles_ = model, poles
    info = {"converged": True, "message": "ERA poles, residues by linear least squares"}
    estimator.report_ = fit_report(model, np.full(poles.size, "mode"), info, [],
                                   method="era", max_order=out["max_order"],
                                   impulse_nrmse=out["nrmse"],
                                   hankel_singular_values=out["singular_values"],
                                   modes=model.modes)
    return estimator
