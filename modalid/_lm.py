"""Bounded Levenberg-Marquardt on the poles, the driver shared by the variable projections.

The unknowns are the poles as ``x = [Re p_1, Im p_1, Re p_2, ...]``; the residues and other
linear terms are projected out by the caller's ``project(x)``, which returns an object with
``cost`` (weighted sum of squared residuals) and ``normal_equations()`` (``J^T J`` and
``J^T r`` of the reduced problem). Used by :func:`modalid._lsfd.refine_varpro` (one FRF)
and :func:`modalid._global.refine_joint` (several FRFs sharing their poles).
"""

from __future__ import annotations

import numpy as np

__all__ = ["pole_limits", "bounded_lm"]


def pole_limits(lo, hi, max_real=None):
    """``limits(x)``: effective bounds at ``x``, ``Im p`` in ``[lo, hi]`` and then
    ``Re p`` in ``[-Im p, -1e-9 Im p]`` (stable, damping ratio below about 0.7).

    Parameters
    ----------
    lo, hi : ndarray of float, shape (n,)
        Bounds on each pole's imaginary part (rad/s).
    max_real : float, optional
        A further upper bound on every ``Re p`` (rad/s, < 0), e.g. minus the decay rate
        of an exponential window, so that the poles stay stable once it is removed; the
        bound used is ``min(-1e-9 Im p, max_real)`` (and ``-Im p`` stays the lower one,
        lowered to ``max_real`` when that is below it). ``None`` (default): no further
        bound.
    """
    n = lo.size

    def limits(x):
        im = np.clip(x[1::2], np.maximum(lo, 1e-9), hi)
        low, high = np.empty(2 * n), np.empty(2 * n)
        low[0::2], high[0::2] = -im, -1e-9 * im
        if max_real is not None:
            high[0::2] = np.minimum(high[0::2], max_real)
            low[0::2] = np.minimum(low[0::2], max_real)
        low[1::2], high[1::2] = np.maximum(lo, 1e-9), hi
        return low, high

    return limits


def bounded_lm(x, *, project, limits, n_data, hold=None, max_iter=50, stat_tol=1e-4,
               stall_tol=1e-3, xtol=1e-12, release=None):
    """Minimise ``project(x).cost`` over the poles ``x`` within ``limits``.

    Scaled Levenberg-Marquardt with an active set (a parameter on a bound whose gradient
    points outwards is held there), a trust region (no pole moves by more than a tenth of
    its modulus per step, each pole's step shortened on its own) and three statistical
    stops, in units of one residual variance ``cost / (n_data - n_par)``: the full
    Gauss-Newton step would gain less than ``stat_tol`` of it; two steps in a row gained
    less than ``stall_tol`` of it; or the relative step is below ``xtol``.

    Parameters
    ----------
    x : ndarray of float, shape (2 n,)
        Starting poles, clipped to ``limits`` by the caller.
    project : callable
        ``project(x)`` -> object with ``cost`` and ``normal_equations()``.
    limits : callable
        ``limits(x)`` -> ``(low, high)`` arrays of shape (2 n,), e.g. :func:`pole_limits`.
    n_data : int
        Number of real residuals (for the residual variance).
    hold : ndarray of bool, shape (n,), optional
        Poles held fixed.
    release : callable, optional
        ``release(obj)`` is called with every projection the driver discards (a rejected
        trial, or the previous iterate once a step is accepted), so that the caller can
        recycle its work arrays.

    Returns
    -------
    x : ndarray, shape (2 n,)
    cur : the projection at ``x``
    info : dict
        ``n_iter``, ``converged``, ``message``.
    """
    n = x.size // 2
    cur = project(x)
    variance_dof = max(n_data - 2 * n, 1)
    lam, nu, n_small, it = 1e-3, 2.0, 0, 0
    converged = n == 0
    message = ("linear least squares (no poles)" if n == 0
               else "maximum number of iterations reached")
    while not converged and it < max_iter:
        jtj, jtr = cur.normal_equations()
        norms = np.sqrt(np.maximum(np.diag(jtj), 1e-300))
        # where coinciding poles make Kaufman's normal matrix singular, its rounding can
        # turn a diagonal negative (-1.9e11 beside +8e4 on a measured beam) and the scaled
        # system overflow: the steps it gives are not finite, and are rejected below
        with np.errstate(over="ignore", invalid="ignore"):
            a_s, g_s = jtj / np.outer(norms, norms), jtr / norms
        # active set: parameters on a bound whose gradient step points outwards
        low, high = limits(x)
        tol_b = 1e-12 * np.repeat(np.hypot(x[0::2], x[1::2]), 2)
        free = ~(((x - low <= tol_b) & (g_s < 0)) | ((high - x <= tol_b) & (g_s > 0)))
        if hold is not None:
            free &= ~np.repeat(np.asarray(hold, bool), 2)
        idx = np.flatnonzero(free)
        if idx.size == 0:
            converged, message = True, "converged (all poles on bounds)"
            break
        a_f, g_f = a_s[np.ix_(idx, idx)], g_s[idx]
        # statistical stop: the full Gauss-Newton step would lower the cost by less than
        # ``stat_tol`` of one residual variance (a step far below one standard deviation)
        try:
            gain = float(g_f @ np.linalg.solve(a_f, g_f))
        except np.linalg.LinAlgError:
            gain = np.inf
        if gain < stat_tol * cur.cost / variance_dof:
            converged, message = True, "converged"
            break
        it += 1
        accepted = singular = False
        while lam < 1e12:
            step = np.zeros(2 * n)
            try:
                step[idx] = np.linalg.solve(a_f + lam * np.eye(idx.size), g_f)
            except np.linalg.LinAlgError:
                lam, nu = lam * nu, nu * 2.0
                continue
            step /= norms
            # trust region: no pole moves by more than a tenth of its modulus at once,
            # each pole's step shortened on its own (shortening the whole step let one
            # pole near 0 Hz, a lower pseudo-mode standing in for a mass line, hold every
            # other pole to tiny steps: the fit stalled with resonances 10x too damped)
            move = np.hypot(step[0::2], step[1::2]) / np.hypot(x[0::2], x[1::2])
            if move.max() > 0.1:
                step *= np.repeat(np.minimum(1.0, 0.1 / np.maximum(move, 1e-300)), 2)
            if not np.all(np.isfinite(step)):     # a singular system's overflow
                lam, nu, singular = lam * nu, nu * 2.0, True
                continue
            x_new = np.clip(x + step, *limits(x + step))
            try:
                trial = project(x_new)
            except np.linalg.LinAlgError:         # no projection there: a rejected step
                lam, nu = lam * nu, nu * 2.0
                continue
            actual = cur.cost - trial.cost
            if actual >= 0.0:
                taken = (x_new - x) * norms
                predicted = taken @ (2 * g_s - a_s @ taken)
                rho = actual / predicted if predicted > 0 else 1.0
                lam *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                nu, accepted = 2.0, True
                break
            if release is not None:
                release(trial)
            lam, nu = lam * nu, nu * 2.0
        if not accepted and singular:
            converged, message = False, ("stopped: the normal matrix is singular (poles "
                                         "that coincide?)")
            break
        if not accepted:
            converged, message = True, "no further decrease of the cost"
            break
        change = np.max(np.abs(x_new - x) / np.repeat(np.hypot(x_new[0::2], x_new[1::2]), 2))
        if release is not None:
            release(cur)
        x, cur = x_new, trial
        # stalled: two steps in a row that lower the cost by less than ``stall_tol`` of one
        # residual variance (a flat valley, e.g. of pseudo-modes, statistically settled)
        small = actual < stall_tol * cur.cost / variance_dof
        n_small = n_small + 1 if small else 0
        if change < xtol:
            converged, message = True, "converged (step below xtol)"
        elif n_small >= 2:
            converged, message = True, "converged (cost settled)"
    return x, cur, {"n_iter": it, "converged": converged, "message": message}
