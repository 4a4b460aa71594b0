"""Common-pole identification of an :class:`~modalid.FRFSet`: the ``ModalFit`` pipeline for
several outputs of one input.

1. Global LSCF: the reduced normal equations of every output are summed (one common
   denominator), on the band and nested low sub-bands, into one stabilization diagram;
   the same clustering as a single FRF (:mod:`modalid.stabilization`).
2. How many clusters are physical: the Bayesian information criterion on the linear fits
   of all outputs together (residues per output, poles shared), each mode counting
   ``2 + 2 n_outputs`` real parameters.
3. The low end is judged at the driving point (rigid body or lower pseudo-mode); every
   output gets the same terms (a rigid ``u_i / s^2``, a constant ``d_i``, the shared
   pseudo-modes), with its own coefficients.
4. Joint variable projection: the poles are the only nonlinear unknowns; every output's
   residues are eliminated by its own weighted linear least squares, so the Gauss-Newton
   normal equations of the poles are the sum over outputs of Kaufman's single-output ones.
   ``passive=True`` bounds the driving-point row only (transfer rows take any sign).
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.linalg import cholesky, solve_triangular

from ._checks import as_count
from ._frf_pipeline import ModalFitWarning, reweighting_kept
from ._pole_checks import line_noise, local_evidence
from ._report import (fit_report, local_misfit_inflation, misfit_notes, mode_std_columns,
                      residual_correlation_inflation)
from ._lm import bounded_lm, pole_limits
from ._band import band_to_fit, choose_band, given_band, noise_model
from ._unresolved_damping import damping_off_bound
from ._zero_start import hold_at_zero
from ._lscf import lscf_subbands
from ._segments import default_order, resonance_peaks
from ._lsfd import (Terms, _bounds, _Projection, _realify, _std, design_matrix,
                    split_coefficients)
from ._noise import noise_level
from .frf_set import FRFSet
from .model import ModalModel
from .quantities import receptance_to
from .multi_output import MultiOutputModalModel
from .stabilization import cluster_poles, select_poles, stabilization_table
from ._verdict import missed_resonances

__all__ = ["fit_set", "refine_joint"]


# ----------------------------------------------------------------- the array kernels
def split_rows(xs, n_modes, terms):
    """Each row's :func:`~modalid._lsfd.split_coefficients`, stacked.

    Returns residues (n_outputs, n_modes), real residues (n_outputs, n_real), inverse
    masses and flexibilities (n_outputs,).
    """
    parts = [split_coefficients(x, n_modes, terms) for x in xs]
    return (np.array([p[0] for p in parts]).reshape(len(xs), n_modes),
            np.array([p[1] for p in parts]).reshape(len(xs), len(terms.real_poles)),
            np.array([p[2] for p in parts]), np.array([p[3] for p in parts]))


def evaluate_rows(omega, poles, xs, terms):
    """Receptance of every row, shape (n_outputs, n_lines)."""
    cols = design_matrix(1j * omega, poles, terms)
    return np.array([cols @ x for x in xs]).reshape(len(xs), omega.size)


class _Joint:
    """The projections of all rows for one set of shared poles."""

    def __init__(self, omega, ys, ws, extras, bounds, poles):
        self.rows = [_Projection(omega, w, y, poles, e, b)
                     for y, w, e, b in zip(ys, ws, extras, bounds)]
        self.cost = float(sum(p.cost for p in self.rows))
        self.xs = [p.x for p in self.rows]

    def normal_equations(self):
        parts = [p.normal_equations() for p in self.rows]
        return sum(a for a, _ in parts), sum(b for _, b in parts)


def refine_joint(omega, values, weights, poles, terms: Terms, *, passive_row=None,
                 zero_start=False, imag_lo=None, imag_hi=None, hold=None, max_iter=50,
                 stat_tol=1e-4, stall_tol=1e-3, xtol=1e-12, with_std=True):
    """Shared poles and per-row residues by variable projection (Levenberg-Marquardt).

    Parameters
    ----------
    omega : ndarray, shape (n_lines,)
        rad/s.
    values, weights : ndarray, shape (n_outputs, n_lines)
        Receptances and real weights per row.
    poles : ndarray of complex, shape (n,)
        Starting poles, ``Im p > 0``.
    terms : Terms
        The same extra terms for every row.
    passive_row : int, optional
        The row whose linear unknowns are bounded for passivity (the driving point).
    zero_start : bool
        Hold that row's impulse response at 0 at ``t = 0`` (``sum 2 Re r_k = 0``; see
        :func:`modalid._lsfd.refine_varpro`).
    imag_lo, imag_hi, hold, max_iter, stat_tol, stall_tol, xtol
        As :func:`modalid._lsfd.refine_varpro`.

    Returns
    -------
    poles : ndarray of complex, shape (n,)
    xs : list of ndarray
        Each row's linear unknowns (see :func:`split_rows`).
    info : dict
        ``n_iter``, ``converged``, ``message``, ``cost`` (weighted SSE, all rows),
        ``pole_std`` (shape (n, 2): std of Re p, Im p from the joint Jacobian) and
        ``residue_std`` (shape (n_outputs, n, 2): std of Re r, Im r), None unless
        ``with_std``.
    """
    omega = np.asarray(omega, float)
    n_out = values.shape[0]
    ys = [_realify(values[i] * weights[i]) for i in range(n_out)]
    base = design_matrix(1j * omega, np.zeros(0), terms)
    extras = [_realify(base * weights[i][:, None]) for i in range(n_out)]
    x = np.empty(2 * np.size(poles))
    n = x.size // 2
    bounds = [_bounds(n, terms, True, zero_start) if i == passive_row else None
              for i in range(n_out)]
    lo = np.zeros(n) if imag_lo is None else np.asarray(imag_lo, float)
    hi = np.full(n, np.inf) if imag_hi is None else np.asarray(imag_hi, float)
    limits = pole_limits(lo, hi)

    def project(v):
        return _Joint(omega, ys, weights, extras, bounds, v[0::2] + 1j * v[1::2])

    x[0::2], x[1::2] = np.real(poles), np.imag(poles)
    n_data = sum(y.size for y in ys)
    x, cur, lm_info = bounded_lm(np.clip(x, *limits(x)), project=project, limits=limits,
                                 n_data=n_data, hold=hold, max_iter=max_iter,
                                 stat_tol=stat_tol, stall_tol=stall_tol, xtol=xtol)
    it, converged, message = lm_info["n_iter"], lm_info["converged"], lm_info["message"]
    info = {"n_iter": it, "converged": converged, "message": message, "cost": cur.cost,
            "pole_std": None, "residue_std": None, "weights": weights}
    if with_std and n:
        s = _joint_pole_std(cur.rows, n_data)
        info["pole_std"] = np.column_stack([s[0::2], s[1::2]])
        info["residue_std"] = np.array([_std(p, n, y.size)["modes"][:, 2:4]
                                        for p, y in zip(cur.rows, ys)])
    return x[0::2] + 1j * x[1::2], cur.xs, info


def _joint_pole_std(rows, n_data):
    """Standard deviations (shape (2 n,): Re p, Im p interleaved) of the shared poles.

    From the full normal matrix of the poles and every row's free linear unknowns,
    assembled from blocks (``[[sum G_i^T G_i, C_1^T, ...], [C_1, Phi_1^T Phi_1, 0], ...]``
    with ``C_i = Phi_i^T G_i``), as :func:`modalid._lsfd._std` for one row. Its diagonal is
    a sum of squares; the variable-projection form ``sum (G_i^T G_i - C_i^T Gram_i^-1 C_i)``
    subtracts nearly equal terms for a pole the linear unknowns almost absorb (a residual
    pseudo-mode below the band: a diagonal of -1e-8 against +4.5e-8, pyuff's three points),
    and a negative diagonal there had made every pole's std 0.
    """
    gs = [p.derivative() for p in rows]
    crosses = [(p.mat.T @ g)[p.free] for p, g in zip(rows, gs)]
    grams = [p.gram[np.ix_(p.free, p.free)] for p in rows]
    n2 = gs[0].shape[1]
    size = n2 + sum(c.shape[0] for c in crosses)
    normal = np.zeros((size, size))
    normal[:n2, :n2] = sum(g.T @ g for g in gs)
    at = n2
    for c, gram in zip(crosses, grams):
        k = c.shape[0]
        normal[at:at + k, :n2] = c
        normal[:n2, at:at + k] = c.T
        normal[at:at + k, at:at + k] = gram
        at += k
    sigma2 = sum(p.cost for p in rows) / max(n_data - size, 1)
    norms = np.sqrt(np.maximum(np.diag(normal), 1e-300))
    cov = np.linalg.pinv(normal / np.outer(norms, norms), hermitian=True) * sigma2
    return np.sqrt(np.clip(np.diag(cov)[:n2], 0.0, None)) / norms[:n2]


def prefix_sse(omega, values, weights, candidates, terms: Terms, fixed=()):
    """Weighted SSE of every prefix ``0..n_candidates`` of ``candidates``: linear fits of
    every row (one Cholesky factorisation per row), summed over the rows."""
    s = 1j * omega
    head = design_matrix(s, np.asarray(fixed, complex), terms)
    cols = np.hstack([head, design_matrix(s, candidates, Terms(np.zeros(0), False, False))])
    sizes = head.shape[1] + 2 * np.arange(candidates.size + 1)
    total = np.zeros(candidates.size + 1)
    for h, w in zip(values, weights):
        mat, y = _realify(cols * w[:, None]), _realify(h * w)
        scale = np.linalg.norm(mat, axis=0)
        scale[scale == 0] = 1.0
        mat = mat / scale
        gram = mat.T @ mat
        gram[np.diag_indices_from(gram)] += 1e-10
        upper = cholesky(gram)
        z = solve_triangular(upper, mat.T @ y, trans="T")
        full = float(np.sum((y - mat @ solve_triangular(upper, z)) ** 2))
        tail = np.concatenate([np.cumsum((z**2)[::-1])[::-1], [0.0]])
        floor = 1e-24 * float(y @ y) + 1e-300
        total += np.maximum(full + tail[sizes], floor)
    return total


def select_joint(omega, values, weights, candidates, terms, fixed, *, driving_point,
                 passive):
    """Which of the ranked ``candidates`` the data of all rows support (BIC).

    ``BIC = n ln(SSE/n) + (2 + 2 n_outputs) k ln(n)``, ``n`` the real data of all rows.
    Returns ``(keep, negative)``: ``negative`` flags chosen candidates with a negative
    modal mass at the driving point (dropped from ``keep`` when ``passive``).
    """
    n_out = values.shape[0]
    sse = prefix_sse(omega, values, weights, candidates, terms, fixed)
    n = 2 * values.size
    bic = n * np.log(sse / n) + (2 + 2 * n_out) * np.arange(sse.size) * np.log(n)
    k = int(np.argmin(bic))
    keep = np.zeros(candidates.size, bool)
    keep[:k] = True
    negative = np.zeros(candidates.size, bool)
    if k:
        poles = np.concatenate([np.asarray(fixed, complex), candidates[:k]])
        w = weights[driving_point]
        mat = design_matrix(1j * omega, poles, terms) * w[:, None]
        x = np.linalg.lstsq(_realify(mat), _realify(values[driving_point] * w), rcond=None)[0]
        im_r = x[1:2 * poles.size:2][len(fixed):]
        negative[:k] = im_r > 0
    return (keep & ~negative if passive else keep), negative


# ----------------------------------------------------------------- the pipeline
def _fit_warning():

    return ModalFitWarning


def _row_weights(est, rec: FRFSet, data: FRFSet):
    """Weights per row as :meth:`ModalFit._prepare` (each row on its own scale; the
    noise estimated in the quantity of ``data``, measured, and carried to ``rec``)."""
    mag = np.abs(rec.values)
    if est._weighting_on == "relative":
        w = 1.0 / np.maximum(mag, 1e-12 * mag.max(axis=1, keepdims=True))
    elif est._weighting_on == "noise":
        to_data = np.abs(receptance_to(data.quantity, np.ones(rec.omega.size), rec.omega))
        w = to_data / np.array([noise_level(h) for h in data.values])
    else:
        w = np.ones_like(mag) / np.sqrt(np.mean(mag**2, axis=1, keepdims=True))
    coh = (np.ones_like(mag) if rec.coherence is None
           else np.sqrt(np.clip(rec.coherence, 1e-3, 1.0)))
    return w * coh, coh


def _model_weights(est, omega, poles, xs, terms, w0, coh):
    if est._weighting_on != "relative":
        return w0
    mag = np.abs(evaluate_rows(omega, poles, xs, terms))
    if not np.all(np.isfinite(mag)) or np.any(mag.max(axis=1) <= 0):
        return w0
    return coh / np.maximum(mag, 1e-12 * mag.max(axis=1, keepdims=True))


def _refine(est, omega, h, w, coh, poles, kinds, terms, dp):
    """Data weights, then (relative weighting) model weights, as ``ModalFit._refine``."""
    lo, hi = est._imag_bounds(kinds, omega, poles)
    kw = dict(imag_lo=lo, imag_hi=hi, hold=kinds == "far",
              passive_row=dp if est._passive_on else None, zero_start=est._zero_start)
    relative = est._weighting_on == "relative"
    poles, xs, info = refine_joint(omega, h, w, poles, terms, with_std=not relative,
                                   stat_tol=0.1 if relative else 1e-4, **kw)
    n_iter = info["n_iter"]
    cost = info["cost"]                           # weighted by the data
    for k in range(2 if relative else 0):
        wm = _model_weights(est, omega, poles, xs, terms, w, coh)
        new = refine_joint(omega, h, wm, poles, terms, **kw)
        n_iter += new[2]["n_iter"]
        if not reweighting_kept(evaluate_rows(omega, new[0], new[1], terms), h, w, cost):
            # the model's weights chased lines the data do not follow: keep the fit
            # weighted by the data, converged to the full tolerance (with its stds)
            if k == 0:
                poles, xs, info = refine_joint(omega, h, w, poles, terms, **kw)
                n_iter += info["n_iter"]
            break
        poles, xs, info = new
        if info["n_iter"] <= 3:
            break
    info["n_iter"] = n_iter
    return poles, xs, info


def _unresolved_damping(est, rec, poles, kinds, xs, info, terms, dp, notes):
    """Modes whose damping went to the refinement's bound, moved off it where the lines
    cannot tell, as ``ModalFit``'s for one FRF
    (:func:`modalid._unresolved_damping.damping_off_bound`). Returns ``(poles, xs, info,
    n_iter)``: the fit, and the refinement steps this took."""
    lo, hi = est._imag_bounds(kinds, rec.omega, poles)

    def refit(trial, hold):
        return refine_joint(rec.omega, rec.values, info["weights"], trial, terms,
                            imag_lo=lo, imag_hi=hi, hold=hold | (kinds == "far"),
                            passive_row=dp if est._passive_on else None,
                            zero_start=est._zero_start)

    n_params = 2 * poles.size + sum(x.size for x in xs)
    spacing = float(np.median(np.diff(rec.freq_hz)))
    fit, said, n_iter = damping_off_bound(2 * rec.values.size, n_params, spacing, poles, kinds,
                                          info["cost"], refit)
    notes += said
    return (poles, xs, info, n_iter) if fit is None else (*fit, n_iter)


def _worst_pole(est, omega, h, w, coh, poles, xs, info, kinds, terms, dp):
    """The physical pole to drop first and why, as ``ModalFit._worst_pole`` with every
    row: no positive modal mass at the driving point (``passive``), out of the band, a
    duplicate of a stronger pole, not significant (removing it, all rows refitted
    linearly, raises the cost by less than ``(2 + 2 n_outputs) ln(n)`` variances), or
    no more than the rows' noise on its lines (:func:`_joint_evidence` under 1)."""
    r = split_rows(xs, poles.size, terms)[0]
    std = info["residue_std"]
    std = np.ones(r.shape) * np.inf if std is None else np.hypot(std[..., 0], std[..., 1])
    t = np.sqrt(np.sum((np.abs(r) / np.maximum(std, 1e-300)) ** 2, axis=0))
    wn, zeta = np.abs(poles), -poles.real / np.abs(poles)
    mode = kinds == "mode"
    overlap = np.abs(wn[:, None] - wn[None, :]) < zeta[:, None] * wn[:, None] + zeta * wn
    weaker = overlap & mode[None, :] & (t[None, :] > t[:, None])
    weak = mode & (zeta > 0.3)
    candidates = np.flatnonzero(mode & (t < 6.0 * np.sqrt(h.shape[0])))
    wm = _model_weights(est, omega, poles, xs, terms, w, coh)
    if candidates.size:
        kw = dict(passive_row=dp if est._passive_on else None, max_iter=0, with_std=False)
        cost = refine_joint(omega, h, wm, poles, terms, **kw)[2]["cost"]
        n_data = 2 * h.size
        sigma2 = cost / max(n_data - h.shape[0] * (2 * poles.size + terms.n_extra)
                            - 2 * poles.size, 1)
        for k in candidates:
            rise = refine_joint(omega, h, wm, np.delete(poles, k), terms, **kw)[2]["cost"] - cost
            weak[k] |= rise / sigma2 < (2 + 2 * h.shape[0]) * np.log(n_data)
    evidence = _joint_evidence(omega, h, wm, coh, poles, xs, terms, r)
    tests = [(est._passive_on & (r[dp].imag >= 0), "no positive modal mass at the driving point"),
             ((wn < omega[0]) | (wn > omega[-1]), "it left the band"),
             (weaker.any(axis=1), "it duplicates a stronger pole"),
             (weak, "not significant"),
             (evidence < 1.0, "no more than the data's noise on its lines")]
    for i, (bad, reason) in enumerate(tests):
        bad = bad & mode
        if bad.any():
            last = i == len(tests) - 1
            k = int(np.flatnonzero(bad)[np.argmin((evidence if last else t)[bad])])
            figure = f"evidence {evidence[k]:.3g}" if last else f"joint |r|/std = {t[k]:.3g}"
            return k, (f"dropped the pole at {wn[k] / (2 * np.pi):.6g} Hz: {reason} "
                       f"({figure}, damping {zeta[k]:.3g})")
    return None, None


def _joint_evidence(omega, h, w, coh, poles, xs, terms, r):
    """Per pole, :func:`modalid._pole_checks.local_evidence` over the rows: each row's
    noise from :func:`modalid._band.noise_model` of that row (and its coherence, where
    the data carry it: ``coh`` is its square root, all ones without). ``w``: the weights
    the fit minimised (the model's, under relative weighting)."""
    coherence = None if np.all(coh == 1.0) else coh**2
    sigma = np.array([line_noise(row, noise_model(row),
                                 None if coherence is None else coherence[j])
                      for j, row in enumerate(h)])
    return local_evidence(omega, h, w, sigma, poles, r, evaluate_rows(omega, poles, xs, terms))


def _common_band(est, data: FRFSet):
    """The automatic band of a set (:func:`modalid._band.choose_band` per row): the lines
    every row vouches for (the highest low end, the lowest top); sets
    ``est._band_reason``."""
    bands, reasons = [], []
    for k, output in enumerate(data.outputs):
        band, why = choose_band(data.row(k), low_end=not est._windowed)
        bands.append(band)
        if why != "all lines":
            reasons.append(f"{output}: {why}")
    lo, hi = max(b[0] for b in bands), min(b[1] for b in bands)
    if hi <= lo:
        raise ValueError(f"the rows of the FRFSet share no usable band: {'; '.join(reasons)}")
    est._band_reason = "; ".join(reasons) or "all lines"
    return lo, hi


def _driving_row_poles(est, data: FRFSet, dp, stable):
    """The physical poles a single-FRF fit of the driving-point row finds on the set's
    band that no stable cluster of the global estimator lies near (0.5 % or three
    half-power half-widths).

    The single fit searches its residual for the modes its estimator missed (which the
    global estimator's clusters cannot: pyuff's 278.7 Hz on 100-800 Hz was a cluster of
    share 0.4, its 687 Hz 15 Hz below a 702 Hz band top none). They join the candidates
    after the stable clusters, and the joint selection keeps a prefix of that order
    (:func:`select_joint`, by the information criterion): a strong one is kept, a marginal
    one only with every cluster before it."""
    from sklearn.base import clone

    single = clone(est).set_params(freq_range=(float(data.freq_hz[0]),
                                               float(data.freq_hz[-1])),
                                   passive=bool(est._passive_on),
                                   weighting=est._weighting_on)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        poles = single.fit(data.row(dp)).poles_
    if stable.size == 0:
        return poles
    reach = np.maximum(0.005 * np.abs(poles), -3.0 * poles.real)
    near = np.abs(np.abs(poles)[:, None] - np.abs(stable)[None, :]) < reach[:, None]
    return poles[~near.any(axis=1)]


def fit_set(est, data: FRFSet):
    """``ModalFit.fit`` for an :class:`FRFSet`: common poles, residues per output."""
    dp = data.require_driving_point("ModalFit.fit with common poles")
    if est.method != "lscf":
        raise ValueError(f"method={est.method!r} does not fit an FRFSet: common poles come "
                         "from the global LSCF, use method='lscf'")
    data = data.select(data.freq_hz > 0)
    first = data.freq_hz[0]
    if est.freq_range is not None:
        band, est._band_reason = given_band(
            est.freq_range, lambda: (_common_band(est, data), est._band_reason))
        data = band_to_fit(data, band)
    else:
        data = data.band(_common_band(est, data))
    cut = (est.freq_range is not None and est.freq_range[0] is not None
           and bool(data.freq_hz[0] > first))
    est._data_band = est.data_ = data
    rec = data.to_receptance()
    omega, h = rec.omega, rec.values
    w, coh = _row_weights(est, rec, data)
    est.frf_ = rec
    level = np.sum(np.abs(h) / np.sqrt(np.mean(np.abs(h) ** 2, axis=1, keepdims=True)), axis=0)
    peaks = resonance_peaks(level)
    max_order = (as_count("max_order", est.max_order, minimum=2) if est.max_order
                 else default_order(peaks.size))
    bands = lscf_subbands(omega, h, w, max_order, peaks=omega[peaks])
    tops = [(1.0 if k == 0 else 0.9) * top / (2 * np.pi) for k, (top, _) in enumerate(bands)]
    est.stabilization_ = stabilization_table([p for _, p in bands],
                                             [(rec.freq_hz[0], t) for t in tops])
    clusters = cluster_poles(est.stabilization_)
    notes = []
    if est._selection():
        poles, selected = select_poles(clusters, **est._selection())
    else:
        share = clusters["share"].to_numpy(float)
        stable = clusters["pole"].to_numpy(complex)[share >= 0.5]
        found = _driving_row_poles(est, data, dp, stable)
        cand = np.concatenate([stable, found])
        selected = np.zeros(len(clusters), bool)
        if cand.size:
            terms, fixed = est._linear_terms(omega, h[dp], w[dp], cand, cut)
            keep, negative = select_joint(omega, h, w, cand, terms, fixed, driving_point=dp,
                                          passive=est._passive_on)
            est._warn_negative(cand[negative])
            selected[np.flatnonzero(share >= 0.5)[keep[:stable.size]]] = True
            for p_k in found[keep[stable.size:]]:
                notes.append(f"a mode the driving-point row's own fit found, at "
                             f"{abs(p_k) / (2 * np.pi):.6g} Hz, joined the candidates")
            cand = cand[keep]
        poles = cand[np.argsort(np.abs(cand))]
    est.clusters_ = clusters.assign(selected=selected)
    start, kinds, terms = est._start(omega, h[dp], w[dp], poles, cut)
    if est.refine:
        p, xs, info = _refine(est, omega, h, w, coh, start, kinds, terms, dp)
        n_iter = info["n_iter"]
        for _ in range(0 if est._selection() else 4):
            k, why = _worst_pole(est, omega, h, w, coh, p, xs, info, kinds, terms, dp)
            if k is None:
                break
            notes.append(why)
            start, kinds = np.delete(start, k), np.delete(kinds, k)
            p, xs, info = _refine(est, omega, h, w, coh, start, kinds, terms, dp)
            n_iter += info["n_iter"]
        if est._passive_on:
            p, xs, new = _start_at_zero(est, omega, h, w, coh, p, kinds, xs, info, terms,
                                        dp, notes)
            n_iter += new["n_iter"] if new is not info else 0
            info = new
        p, xs, info, spent = _unresolved_damping(est, rec, p, kinds, xs, info, terms, dp, notes)
        n_iter += spent
        info["n_iter_total"] = n_iter
    else:
        p, xs, info = refine_joint(omega, h, w, start, terms, max_iter=0,
                                   passive_row=dp if est._passive_on else None)
        info.update(converged=True, message="linear least squares (refine=False)",
                    n_iter_total=0)
    if not info["converged"]:
        warnings.warn(f"the refinement did not converge: {info['message']}",
                      _fit_warning(), stacklevel=4)
    if not np.any(kinds == "mode"):
        warnings.warn("no resonance found in the band: the model holds only residual terms; "
                      "see stabilization_", _fit_warning(), stacklevel=4)
    est.__dict__.pop("_zero_start", None)
    return _store(est, rec, p, kinds, xs, terms, info, notes, max_order, dp)


def _start_at_zero(est, omega, h, w, coh, poles, kinds, xs, info, terms, dp, notes):
    """The set refined again from its poles holding the driving-point row's ``h(0) = 0``,
    where that row's impulse response starts against the force (as for one FRF,
    :mod:`modalid._zero_start`; no pseudo-mode is dropped: the transfer rows may need
    it). Returns ``(poles, xs, info)``."""
    out = hold_at_zero(est, xs[dp], poles.size, terms,
                       lambda: _refine(est, omega, h, w, coh, poles, kinds, terms, dp), notes,
                       what="the driving point's impulse response")
    return (poles, xs, info) if out is None else out


def _store(est, rec, poles, kinds, xs, terms, info, notes, max_order, dp):

    r, c, u, d = split_rows(xs, poles.size, terms)
    if u[dp] <= 0.0 and np.any(u != 0.0):
        # the rigid-body mode is one mode: without it at the driving point, no row has it
        u[:] = 0.0
        notes.append("no positive rigid-body term at the driving point: the rigid-body "
                     "terms of every output were dropped")
    model = MultiOutputModalModel(poles=poles, residues=r, real_poles=terms.real_poles,
                                  real_residues=c, inverse_mass=u, flexibility=d,
                                  driving_point=dp, outputs=rec.outputs)
    est.model_ = model
    physical = kinds == "mode"
    order = np.argsort(np.abs(poles[physical]), kind="stable")
    est.poles_ = poles[physical][order]
    band = est._data_band
    fitted = model.frf(rec.omega)
    own = model.frf(band.omega, quantity=band.quantity)

    def nrmse(a, b):
        return np.linalg.norm(a - b, axis=1) / np.linalg.norm(b, axis=1)

    scatter = np.array([noise_level(v) for v in band.values])     # per row and line
    noise = np.sqrt(np.mean(scatter ** 2, axis=1) / np.mean(np.abs(band.values) ** 2, axis=1))
    magnitude = np.maximum(np.abs(band.values), 1e-300)
    shapes = model.mode_shapes()                   # sorted by |p|: pick the physical ones
    all_order = np.argsort(np.abs(poles), kind="stable")
    est.mode_shapes_ = shapes[:, physical[all_order]]
    modes = ModalModel(poles=poles[physical], residues=r[dp][physical]).modes
    # as a single FRF's (ModalFit._store): the formula assumes independent lines and the
    # band's mean residual; widen by Bartlett's factor of the rows' residuals and, per
    # pole, by the misfit on its own lines where noise does not explain it
    weighted = info["weights"] * (fitted - rec.values)
    inflation = residual_correlation_inflation(weighted)
    local = local_misfit_inflation(rec.omega, weighted, poles, correlation=inflation)
    if info.get("pole_std") is not None:
        widen = inflation * local[physical][order]
        s4 = np.hstack([info["pole_std"][physical][order],
                        info["residue_std"][dp][physical][order]]) * widen[:, None]
        p = poles[physical][order]
        modes = mode_std_columns(modes, s4, p, np.ones(p.size))
        notes += misfit_notes(p, local[physical][order])
    else:
        modes = mode_std_columns(modes)
    est.report_ = fit_report(
        model.driving, kinds, info, notes, method=est.method, max_order=max_order,
        outputs=list(rec.outputs), driving_point=dp,
        frf_nrmse=nrmse(fitted, rec.values).tolist(),
        frf_nrmse_data=nrmse(own, band.values).tolist(),
        noise_estimate_data=noise.tolist(), data_quantity=band.quantity,
        missed_resonances_hz=np.unique(np.concatenate([missed_resonances(
            band.freq_hz, h, m) for h, m in zip(band.values, own)])).tolist(),
        frf_median_relative_error=np.median(np.abs(own - band.values) / magnitude,
                                            axis=1).tolist(),
        noise_median_relative=np.median(scatter / magnitude, axis=1).tolist(),
        band_hz=(float(rec.freq_hz[0]), float(rec.freq_hz[-1])), modes=modes,
        std_inflation=inflation)
    return est
