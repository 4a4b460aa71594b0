"""Residues for given poles (LSFD) and the joint nonlinear refinement: pure array kernels.

The receptance model, ``s = i omega``:

    H(s) = sum_k [ r_k/(s - p_k) + conj(r_k)/(s - conj p_k) ]
         + sum_j c_j/(s - sigma_j) + u/s^2 + d

with real unknowns ``Re r_k, Im r_k, c_j, u, d``. Passivity of a driving point (positive
modal mass ``-1/(2 Im p Im r)``) is ``Im r_k <= 0``; with ``u, d, c_j >= 0`` it makes a
bound-constrained linear least-squares problem (solved by an active set on the Gram
matrix). On request (``zero_start``) it also holds ``sum_k 2 Re r_k + sum_j c_j = 0``:
the impulse response of a receptance starts at 0 (a displacement does not jump under an
impulse), exact for every mechanical system, normal or complex modes (a driving point's
fit holds it where its ``h(0)`` came out negative: :mod:`modalid._zero_start`). Columns
are scaled to unit
norm, so the solve does not depend on the frequency units.

The refinement (:func:`refine_varpro`) is a Levenberg-Marquardt iteration on the poles
alone with the residues eliminated (variable projection, Golub and Pereyra 1973, with
Kaufman's Jacobian): the residues are linear, so for given poles they are the least-squares
solution, and only ``2 n`` nonlinear unknowns remain. Passivity bounds on the linear
unknowns are kept by a bounded linear solve inside the projection.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dpotrf as _potrf, dpotrs as _potrs

from ._lm import bounded_lm, pole_limits
from ._vp_kernels import fill_columns, fill_derivative, sum_modes

__all__ = ["Terms", "design_matrix", "refine_varpro", "evaluate", "split_coefficients",
           "place_upper_modes", "release_gain", "removal_cost", "mass_line_significant"]


@dataclass(frozen=True)
class Terms:
    """Which terms the model has besides the complex modes.

    ``rigid_shift`` (1/s, >= 0): the rigid-body column is ``1/(s + rigid_shift)**2``, the
    mass line of data that carry an exponential window of that decay rate (0: ``1/s**2``).
    """

    real_poles: np.ndarray
    rigid: bool
    upper: bool
    rigid_shift: float = 0.0

    @property
    def n_extra(self) -> int:
        return len(self.real_poles) + int(self.rigid) + int(self.upper)


def design_matrix(s, poles, terms: Terms):
    """Complex columns (lines x unknowns) in the order Re r, Im r per mode, c_j, u, d."""
    poles = np.asarray(poles, dtype=complex)
    n = poles.size
    out = np.empty((s.size, 2 * n + terms.n_extra), dtype=complex)
    if n:
        a = 1.0 / (s[:, None] - poles)
        b = 1.0 / (s[:, None] - poles.conj())
        out[:, 0:2 * n:2] = a + b
        out[:, 1:2 * n:2] = 1j * (a - b)
    k = 2 * n
    for sig in terms.real_poles:
        out[:, k] = 1.0 / (s - sig)
        k += 1
    if terms.rigid:
        out[:, k] = 1.0 / (s + terms.rigid_shift)**2
        k += 1
    if terms.upper:
        out[:, k] = 1.0
    return out


def _realify(m):
    return np.concatenate([m.real, m.imag])


def _bounds(n_modes, terms: Terms, passive, zero_start=False):
    """``(lo, hi, start)``: bounds on the linear unknowns (passivity) and, with
    ``zero_start``, the row ``e`` of the equality ``e @ x = 0`` that makes the impulse
    response start at 0, ``h(0) = sum 2 Re r_k + sum c_j = 0`` (else None)."""
    n = 2 * n_modes + terms.n_extra
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    if passive:
        hi[1:2 * n_modes:2] = 0.0                    # Im r <= 0
        lo[2 * n_modes:] = 0.0                       # c_j, u, d >= 0
    start = None
    if zero_start:
        start = np.zeros(n)
        start[0:2 * n_modes:2] = 2.0
        start[2 * n_modes:2 * n_modes + len(terms.real_poles)] = 1.0
    return lo, hi, start


def split_coefficients(x, n_modes, terms: Terms):
    """``(residues, real_residues, inverse_mass, flexibility)`` from the real unknowns."""
    r = x[0:2 * n_modes:2] + 1j * x[1:2 * n_modes:2]
    k = 2 * n_modes
    c = x[k:k + len(terms.real_poles)]
    k += len(terms.real_poles)
    u = float(x[k]) if terms.rigid else 0.0
    k += int(terms.rigid)
    d = float(x[k]) if terms.upper else 0.0
    return r, c, u, d


def evaluate(omega, poles, residues, real_poles, real_residues, inverse_mass, flexibility,
             rigid_shift=0.0):
    """The receptance model at ``s = i omega``, mass line ``inverse_mass/(s + rigid_shift)^2``
    (the modes' pairs summed by the compiled :func:`modalid._vp_kernels.sum_modes`)."""
    s = 1j * omega
    out = np.full(s.shape, flexibility, dtype=complex)
    if len(poles):
        poles, residues = np.asarray(poles, complex), np.asarray(residues, complex)
        parts = (poles.real, poles.imag, residues.real, residues.imag)
        sum_modes(np.ascontiguousarray(omega, dtype=float).ravel(),
                  *(np.ascontiguousarray(z) for z in parts), out.reshape(-1))   # a view
    if len(real_poles):
        out += np.sum(real_residues / (s[:, None] - real_poles), axis=1)
    if inverse_mass:
        out += inverse_mass / (s + rigid_shift)**2
    return out


# ------------------------------------------------------------------ variable projection
def _cholesky(a):
    """Lower Cholesky factor of the symmetric positive definite ``a`` (LAPACK ``potrf``
    called directly: scipy's checking wrapper costs more than the factorisation of the
    small Gram matrices here); ``None`` when ``a`` is not positive definite or not finite."""
    if a.size == 0:
        return a
    factor, info = _potrf(a, lower=1, clean=1, overwrite_a=0)
    return factor if info == 0 and np.isfinite(factor).all() else None


def _cho_solve(factor, rhs):
    """``a^-1 rhs`` from :func:`_cholesky`'s factor (LAPACK ``potrs``)."""
    if factor.size == 0:                                   # no unknowns left
        return np.zeros(rhs.shape)
    x, info = _potrs(factor, rhs, lower=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"potrs failed (info={info})")
    return x


class _Workspace:
    """Buffers of one projection, reused from one set of poles to the next.

    A fresh large temporary costs page faults on first touch, which on some machines
    cost more than the arithmetic; the projection therefore writes into these.
    """

    def __init__(self, m, n, k):
        self.mat = np.empty((2 * m, k))
        self.wd, self.a, self.b = (np.empty((m, n)) for _ in range(3))


class _Projection:
    """Weighted linear least squares for fixed poles, in real form.

    Solved through the Gram matrix (columns scaled to unit norm inside the Cholesky
    factorisation, one step of iterative refinement against the explicit residual): a
    tenth of the cost of a QR factorisation of the tall matrix, and accurate to the level
    the fit needs. With ``bounds`` (passivity: :func:`_bounds`) a violated unconstrained
    solution is replaced by the bounded one (an active set); the columns held at 0 then
    drop out of the projection. The equality ``e @ x = 0`` of the bounds is kept by its
    Lagrange multiplier: ``x = x_u - G^-1 e (e^T x_u)/(e^T G^-1 e)`` on the free columns,
    and the projection is the one onto the columns restricted to that plane.

    The partial-fraction columns and their derivatives are written by the compiled
    kernels of :mod:`modalid._vp_kernels` (real arithmetic, formulas there).
    """

    def __init__(self, omega, w, y, poles, extra, bounds=None, ws=None, held=None):
        self.poles, self.omega = poles, omega
        m, n = omega.size, poles.size
        ws = ws or _Workspace(m, n, 2 * n + extra.shape[1])
        self.ws = ws
        mat = ws.mat
        # held poles: their columns and the extra terms' stay in a workspace once written
        refill = held is None or id(ws) not in held.workspaces
        fill_columns(omega, w, np.ascontiguousarray(poles.real),
                     np.ascontiguousarray(poles.imag), mat, ws.wd, ws.a, ws.b,
                     np.arange(n) if refill else held.moving)
        if refill:
            mat[:, 2 * n:] = extra
        self.mat = mat
        self.held = held
        # the columns that move, gathered once for the Gram rows and the right-hand side
        moving = None if held is None or held.block is None else mat[:, held.varying]
        self.gram = self._gram(held, moving)
        scale = np.sqrt(np.diag(self.gram))
        scale[scale == 0] = 1.0
        self.scale = scale
        rhs = self._rhs(y, held, moving)
        if held is not None:
            held.workspaces.add(id(ws))
        self.free = np.ones(mat.shape[1], bool)
        self.equality = None if bounds is None else bounds[2]
        x = self._lstsq(rhs, y)
        if bounds is not None and (np.any(x < bounds[0]) or np.any(x > bounds[1])):
            x = self._bounded(rhs, y, bounds)
        self.residual = y - mat @ x
        self.cost = float(self.residual @ self.residual)
        self.x = x

    def _gram(self, held, moving):
        """``M^T M``; with ``held`` (:class:`_HeldColumns`) whose block is known only the
        rows of the columns that move (``moving``: those columns) are computed,
        ``O(rows x columns x moving)`` in place of ``O(rows x columns^2)``."""
        if moving is None:
            gram = self.mat.T @ self.mat
            if held is not None:
                held.block = gram[np.ix_(held.fixed, held.fixed)]
            return gram
        gram = np.empty((self.mat.shape[1],) * 2)
        gram[np.ix_(held.fixed, held.fixed)] = held.block
        rows = moving.T @ self.mat
        gram[held.varying, :] = rows
        gram[:, held.varying] = rows.T
        return gram

    def _rhs(self, y, held, moving):
        """``M^T y``; with ``held`` (:class:`_HeldColumns`) the fixed columns' part once,
        then only the ``moving`` columns'."""
        if moving is None:
            rhs = self.mat.T @ y
            if held is not None:
                held.rhs = rhs[held.fixed]
            return rhs
        rhs = np.empty(self.mat.shape[1])
        rhs[held.fixed] = held.rhs
        rhs[held.varying] = moving.T @ y
        return rhs

    def _gram_solve(self, rhs, cols=None):
        """``G^-1 rhs`` for the Gram matrix of ``cols`` (default: the free columns), from
        the factor of the last :meth:`_lstsq`."""
        cols = self.free if cols is None else cols
        d = self.scale[cols][:, None] if rhs.ndim == 2 else self.scale[cols]
        if self.factor is not None:
            return _cho_solve(self.factor, rhs / d) / d
        return np.linalg.lstsq(self.gram[np.ix_(cols, cols)], rhs, rcond=None)[0]

    def _lstsq(self, rhs, y, cols=None):
        d = self.scale if cols is None else self.scale[cols]
        gram = self.gram if cols is None else self.gram[np.ix_(cols, cols)]
        self.factor = _cholesky(gram / np.outer(d, d))
        cols = np.ones(d.size, bool) if cols is None else cols
        self.multiplier = 0.0
        if self.factor is None:
            x = np.linalg.lstsq(self.mat[:, cols], y, rcond=None)[0]
        else:
            x = _cho_solve(self.factor, rhs / d) / d
            # one step of iterative refinement, on the whole matrix with the bound
            # columns at 0 (no copy of the free columns: the active-set loop of
            # :meth:`_bounded` calls this a hundred times on a 50-mode band)
            full = np.zeros(self.mat.shape[1])
            full[cols] = x
            x += _cho_solve(self.factor, (self.mat.T @ (y - self.mat @ full))[cols] / d) / d
        self._plane = None
        if self.equality is not None and np.any(self.equality[cols]):
            e = self.equality[cols]
            v = self._gram_solve(e, cols)
            self._plane = (e, v, float(e @ v))
            self.multiplier = float(e @ x) / self._plane[2]
            x = x - self.multiplier * v
        return x

    def _bounded(self, rhs, y, bounds):
        """Least squares with each unknown at a bound of 0 or free (active set: the most
        violated unknown goes to its bound, a bound whose gradient points inwards is
        released; a few small Cholesky solves)."""
        lo, hi, _ = bounds
        at_bound = np.zeros(rhs.size, bool)
        x = np.zeros(rhs.size)
        for _ in range(3 * rhs.size):
            self.free = ~at_bound
            x[:] = 0.0
            x[self.free] = self._lstsq(rhs[self.free], y, self.free)
            excess = np.maximum(lo - x, x - hi)
            if np.any(excess > 0):
                at_bound[int(np.argmax(excess))] = True
                continue
            grad = rhs - self.gram @ x                     # -d(cost/2)/dx
            if self.equality is not None:
                grad -= self.multiplier * self.equality    # ... of the Lagrangian
            wrong = at_bound & (((lo == 0) & (grad > 0)) | ((hi == 0) & (grad < 0)))
            if not np.any(wrong):
                break
            at_bound[int(np.argmax(np.where(wrong, np.abs(grad), -1.0)))] = False
        return np.clip(x, lo, hi)

    def _solve(self, rhs):
        """``S rhs`` with ``S`` the inverse Gram matrix of the free columns restricted to
        the equality's plane (``P = M S M^T`` projects onto the model's columns)."""
        out = self._gram_solve(rhs)
        if self._plane is not None:
            e, v, evv = self._plane
            out = out - np.multiply.outer(v, e @ out) / evv
        return out

    def derivative(self, out=None, poles=None):
        """Columns ``d(Phi x)/d(Re p, Im p)`` of each pole (weighted, real form), shape
        ``(2 m, 2 n)`` (:func:`modalid._vp_kernels.fill_derivative`); of the ``poles``
        (bool, shape (n,)) only, shape ``(2 m, 2 k)``, if given."""
        m, n = self.omega.size, self.poles.size
        ws = self.ws
        wd, a, b = ws.wd, ws.a, ws.b
        p, x = self.poles, self.x[:2 * n]
        if poles is not None:
            wd, a, b = (np.ascontiguousarray(z[:, poles]) for z in (wd, a, b))
            p, x = p[poles], x.reshape(n, 2)[poles].ravel()
        k = p.size
        out = np.empty((2 * m, 2 * k)) if out is None else out[:, :2 * k]
        fill_derivative(self.omega, np.ascontiguousarray(p.real), np.ascontiguousarray(p.imag),
                        np.ascontiguousarray(x[0::2]), np.ascontiguousarray(x[1::2]),
                        wd, a, b, out)
        return out

    def normal_equations(self, out=None):
        """``J^T J`` and ``J^T r`` of Kaufman's Jacobian ``J = (I - P) G``; with held
        poles, their rows and columns are 0 (they do not move)."""
        moving = None
        if self.held is None:
            g = self.derivative(out)
        else:
            moving = np.repeat(~self.held.poles, 2)
            g = self.derivative(out, ~self.held.poles)
        cross = (self.mat.T @ g)[self.free]
        jtj = g.T @ g - cross.T @ self._solve(cross)
        jtj, jtr = 0.5 * (jtj + jtj.T), g.T @ self.residual
        if moving is None:
            return jtj, jtr
        full, full_r = np.zeros((moving.size,) * 2), np.zeros(moving.size)
        full[np.ix_(moving, moving)], full_r[moving] = jtj, jtr
        return full, full_r


class _HeldColumns:
    """The poles a refinement holds and what does not move with them (their residue
    columns and the extra terms): their Gram block and right-hand side, computed once
    (:meth:`_Projection._gram`, :meth:`_Projection._rhs`), and the workspaces that hold
    their columns already (only the moving poles' are written again). One per
    refinement: the weights, data and extra terms stay the same."""

    def __init__(self, hold, n_extra):
        self.poles = np.asarray(hold, bool)
        self.moving = np.flatnonzero(~self.poles)
        self.fixed = np.concatenate([np.repeat(self.poles, 2), np.ones(n_extra, bool)])
        self.varying = ~self.fixed
        self.block = self.rhs = None
        self.workspaces = set()


def refine_varpro(omega, values, weights, poles, terms: Terms, *, imag_lo=None, imag_hi=None,
                  hold=None, passive=False, zero_start=False, max_iter=50, xtol=1e-12,
                  stat_tol=1e-4, stall_tol=1e-3, with_std=True, buffers=None, max_real=None,
                  held_gram=False):
    """Weighted nonlinear least squares of poles and residues by variable projection.

    Parameters
    ----------
    omega, values, weights : ndarray, shape (n_lines,)
    poles : ndarray of complex, shape (n,)
        Starting poles, ``Im p > 0``.
    terms : Terms
        Extra linear terms (real poles held fixed, rigid body, constant).
    imag_lo, imag_hi : ndarray, shape (n,), optional
        Bounds on each ``Im p`` (e.g. a residual pseudo-mode kept outside the band);
        ``Re p < 0`` always. A parameter that reaches a bound is held there (active set)
        while the gradient pushes it outwards.
    hold : ndarray of bool, shape (n,), optional
        Poles held fixed (their residues are still fitted).
    passive : bool
        Passivity bounds on the linear unknowns (``Im r <= 0``; ``c_j, u, d >= 0``).
    zero_start : bool
        Hold ``sum 2 Re r_k + sum c_j = 0``: an impulse response that starts at 0.
    buffers : dict, optional
        Work arrays kept between calls (pass the same empty dict to a series of calls on
        one data set: a fresh large array costs page faults on first use).
    max_real : float, optional
        Upper bound on every ``Re p`` (rad/s, < 0), besides ``Re p < 0`` (see
        :func:`modalid._lm.pole_limits`): e.g. ``-decay_rate`` of an exponential window,
        so that the poles stay stable once the window is undone. ``None`` (default): none.
    held_gram : bool
        Keep the Gram block of the ``hold`` poles' columns and the extra terms from the
        first step and compute only the moving columns' part in the others (and the
        moving poles' derivatives): ``O(lines x columns x moving)`` a step instead of
        ``O(lines x columns^2)``, the same normal equations to rounding (their order of
        summation differs: an ill-conditioned fit may then step otherwise). For many
        poles held and a few moving (a segmented fit's pseudo-modes).

    Returns
    -------
    poles : ndarray of complex
    coefficients : ndarray of float
        The linear unknowns (see :func:`split_coefficients`).
    info : dict
        ``n_iter``, ``converged``, ``message``, ``cost`` (weighted SSE), ``std``
        (standard deviations of ``Re p, Im p, Re r, Im r`` per pole, shape (n, 4), and of
        the extra terms; None unless ``with_std``), ``at_bound`` (bool per pole).
    """
    omega = np.asarray(omega, dtype=float)
    w = np.asarray(weights, dtype=float)
    y = _realify(values * w)
    p = np.asarray(poles, dtype=complex).copy()
    n = p.size
    extra = _realify(design_matrix(1j * omega, np.zeros(0), terms) * w[:, None])
    bounds = _bounds(n, terms, passive, zero_start) if passive or zero_start else None
    key = (omega.size, n, 2 * n + extra.shape[1])
    buffers = {} if buffers is None else buffers
    if key not in buffers:
        buffers[key] = (_Workspace(*key), _Workspace(*key), np.empty((2 * omega.size, 2 * n)))
    first, spare, g_buffer = buffers[key]
    lo = np.zeros(n) if imag_lo is None else np.asarray(imag_lo, dtype=float)
    hi = np.full(n, np.inf) if imag_hi is None else np.asarray(imag_hi, dtype=float)
    limits = pole_limits(lo, hi, max_real)
    free_workspaces = [spare, first]   # two projections alive at once: recycle their arrays
    held = _HeldColumns(hold, extra.shape[1]) if held_gram and hold is not None else None

    def project(v):
        ws = free_workspaces.pop()
        try:
            projection = _Projection(omega, w, y, v[0::2] + 1j * v[1::2], extra, bounds, ws,
                                     held)
        except np.linalg.LinAlgError:     # a rejected step: its workspace is free again
            free_workspaces.append(ws)
            raise
        projection.normal_equations = functools.partial(projection.normal_equations, g_buffer)
        return projection

    x = np.empty(2 * n)
    x[0::2], x[1::2] = p.real, p.imag
    x, cur, info = bounded_lm(np.clip(x, *limits(x)), project=project, limits=limits,
                              n_data=y.size, hold=hold, max_iter=max_iter, stat_tol=stat_tol,
                              stall_tol=stall_tol, xtol=xtol,
                              release=lambda old: free_workspaces.append(old.ws))
    it, converged, message = info["n_iter"], info["converged"], info["message"]
    p = x[0::2] + 1j * x[1::2]
    low, high = limits(x)
    at_bound = (x[1::2] - low[1::2] <= 1e-9 * x[1::2]) | (high[1::2] - x[1::2] <= 1e-9 * x[1::2])
    info = {"n_iter": it, "converged": converged, "message": message, "cost": cur.cost,
            "std": _std(cur, n, y.size) if with_std else None, "at_bound": at_bound}
    return p, cur.x, info


def release_gain(omega, values, weights, poles, terms: Terms, hold, *, passive=False,
                 held=None):
    """What releasing the ``hold`` poles would gain: the Gauss-Newton decrease of the
    weighted cost with every pole free (but the ``held`` ones, held either way), in units
    of the residual variance.

    At a minimum with ``hold`` fixed, compare it with ``ln(n)`` per released parameter
    (information criterion) to decide whether the data support moving them.
    """
    omega = np.asarray(omega, dtype=float)
    w = np.asarray(weights, dtype=float)
    y = _realify(values * w)
    poles = np.asarray(poles, complex)
    extra = _realify(design_matrix(1j * omega, np.zeros(0), terms) * w[:, None])
    bounds = _bounds(poles.size, terms, True) if passive else None
    # the held poles' derivatives are not needed: their rows of J^T J stay 0
    proj = _Projection(omega, w, y, poles, extra, bounds,
                       held=None if held is None else _HeldColumns(held, extra.shape[1]))
    jtj, jtr = proj.normal_equations()
    norms = np.sqrt(np.maximum(np.diag(jtj), 1e-300))
    a_s, g_s = jtj / np.outer(norms, norms), jtr / norms
    free = ~np.repeat(np.asarray(hold, bool), 2)
    movable = np.ones(free.size, bool) if held is None else ~np.repeat(np.asarray(held, bool), 2)

    def gain(mask):
        try:
            return float(g_s[mask] @ np.linalg.solve(a_s[np.ix_(mask, mask)], g_s[mask]))
        except np.linalg.LinAlgError:
            return 0.0

    if not proj.cost > 0.0:      # the fit is exact (noise-free data): nothing to gain
        return 0.0
    sigma2 = proj.cost / max(y.size - proj.mat.shape[1] - 2 * poles.size, 1)
    return (gain(movable) - gain(free & movable)) / sigma2


def _std(proj, n, n_data):
    """Standard deviations from the full (poles and linear unknowns) Jacobian
    ``[G, Phi]``, its normal matrix assembled from blocks (no tall copy)."""
    mat = proj.mat
    if n:
        g = proj.derivative()
        cross = mat.T @ g
        normal = np.block([[g.T @ g, cross.T], [cross, proj.gram]])
    else:
        normal = proj.gram
    dof = max(n_data - normal.shape[0], 1)
    sigma2 = proj.cost / dof
    norms = np.sqrt(np.maximum(np.diag(normal), 1e-300))
    cov = np.linalg.pinv(normal / np.outer(norms, norms), hermitian=True) * sigma2
    std = np.sqrt(np.clip(np.diag(cov), 0.0, None)) / norms
    pole_std, lin_std = std[:2 * n], std[2 * n:]
    per_mode = np.column_stack([pole_std[0::2], pole_std[1::2],
                                lin_std[0:2 * n:2], lin_std[1:2 * n:2]])
    return {"modes": per_mode, "extra": lin_std[2 * n:]}


def place_upper_modes(omega, values, weights, poles, terms: Terms, *, n_upper=1,
                      ratios=(1.02, 1.05, 1.1, 1.2, 1.35, 1.6, 2.0, 2.8, 4.0),
                      damping=(0.02,)):
    """Starting poles of ``n_upper`` residual pseudo-modes above the band (grid search).

    With ``poles`` and ``terms`` fixed, every combination of ``n_upper`` poles at
    ``ratios * omega_max`` with each ``damping`` is scored by its linear least-squares
    cost; the best wins. The fixed columns are projected out once, so each combination
    costs a ``2 n_upper`` square solve. Returns the poles and the weighted costs without
    and with them.
    """
    from itertools import combinations

    s = 1j * omega
    w = weights
    y = _realify(values * w)
    base = _Projection(np.asarray(omega, float), w, y, np.asarray(poles, complex),
                       _realify(design_matrix(s, np.zeros(0), terms) * w[:, None]))
    wmax = float(np.max(omega))
    zeta = np.asarray(damping)[:, None]
    cand = (wmax * np.asarray(ratios) * (-zeta + 1j * np.sqrt(1 - zeta**2))).ravel()
    cols = _realify(design_matrix(s, cand, Terms(np.zeros(0), False, False)) * w[:, None])
    cols /= np.linalg.norm(cols, axis=0)
    # the candidates' columns with the fixed ones projected out, through small products
    # only: (I - P) C has the Gram matrix C^T C - (M^T C)^T G^-1 (M^T C), and the
    # residual is already orthogonal to M
    fixed = base.mat if base.free.all() else base.mat[:, base.free]
    cross = fixed.T @ cols
    gram = cols.T @ cols - cross.T @ base._solve(cross)
    rhs = cols.T @ base.residual
    best, best_cost = None, np.inf
    for combo in combinations(range(cand.size), n_upper):
        if len({round(abs(cand[k]), 9) for k in combo}) < n_upper:
            continue
        idx = np.ravel([[2 * k, 2 * k + 1] for k in combo])
        try:
            gain = rhs[idx] @ np.linalg.solve(gram[np.ix_(idx, idx)], rhs[idx])
        except np.linalg.LinAlgError:
            continue
        if base.cost - gain < best_cost:
            best, best_cost = combo, base.cost - gain
    if best is None:
        return cand[:n_upper], base.cost, base.cost
    return cand[list(best)], base.cost, best_cost


def mass_line_significant(omega, values, weights, poles, rigid_shift=0.0):
    """Does a ``u/(s + rigid_shift)^2`` term with ``u > 0`` lower the weighted residual of
    the linear fit (``poles``, a constant and two pseudo-modes above the band) by more
    than ``ln(n)`` residual variances (information criterion, one parameter)?"""
    upper = omega[-1] * np.array([1.1, 1.6]) * (-0.02 + 1j * np.sqrt(1 - 4e-4))
    cols = design_matrix(1j * omega, np.concatenate([poles, upper]),
                         Terms(np.zeros(0), True, True, rigid_shift)) * weights[:, None]
    mat = _realify(cols)
    y = _realify(values * weights)
    mat /= np.linalg.norm(mat, axis=0)
    k = mat.shape[1] - 2                                   # the 1/s^2 column
    x1, sse1 = np.linalg.lstsq(mat, y, rcond=None)[:2]
    sse0 = np.linalg.lstsq(np.delete(mat, k, axis=1), y, rcond=None)[1]
    if sse1.size == 0 or sse0.size == 0 or x1[k] <= 0:
        return False
    n = y.size
    return bool(n * np.log(sse0[0] / max(sse1[0], 1e-300)) > np.log(n))


def removal_cost(omega, values, weights, poles, terms: Terms, indices, *, passive=False,
                 buffers=None):
    """The rise of the weighted cost when each pole in ``indices`` is removed and the
    rest refitted linearly (poles held), in units of the residual variance: a
    likelihood-ratio measure of each pole's significance."""
    kw = dict(passive=passive, max_iter=0, with_std=False, buffers=buffers)
    cost = refine_varpro(omega, values, weights, poles, terms, **kw)[2]["cost"]
    sigma2 = cost / max(2 * np.size(omega) - 4 * len(poles) - terms.n_extra, 1)
    return np.array([refine_varpro(omega, values, weights, np.delete(poles, k), terms,
                                   **kw)[2]["cost"] - cost for k in indices]) / sigma2
