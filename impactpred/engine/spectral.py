"""Closed-form propagation of a linear autonomous phase ``x' = M x``.

``M`` is split once by an ordered real Schur form and a Sylvester solve into a block
with eigenvalues at 0 (nilpotent: rigid-body motion, constants, integrators) and the
rest, which is diagonalised:

    x(t) = S0 exp(N t) c0 + S1 V exp(Lambda t) c1,     exp(N t) = sum_{j<k} N^j t^j / j!

so any output ``r x(t)`` is a polynomial plus a sum of exponentials ``sum b_j e^{l_j t}``:
coefficient arithmetic, exact to rounding, and evaluated at a whole vector of times in
one numpy call. This is the paper's pole-residue form of the phase's response.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from numba import njit

from .product_integrals import product_integrals
from .rank_one import rank_one_split

__all__ = ["SpectralPhase", "DefectiveSpectrum"]


#: zero eigenvalues are cut at this many times the rounding split of a Jordan pair
_CHAIN_FACTOR = 10.0


class DefectiveSpectrum(ValueError):
    """The non-zero part of ``M`` is not safely diagonalisable."""


@njit(cache=True)
def _components(adjacency):  # pragma: no cover - compiled
    """``(count, labels)`` of the connected components of a symmetric boolean matrix
    (depth-first search, O(n^2))."""
    n = adjacency.shape[0]
    labels = np.full(n, -1, np.int64)
    stack = np.empty(n, np.int64)
    count = 0
    for start in range(n):
        if labels[start] >= 0:
            continue
        labels[start] = count
        top = 0
        stack[0] = start
        while top >= 0:
            i = stack[top]
            top -= 1
            for j in range(n):
                if adjacency[i, j] and labels[j] < 0:
                    labels[j] = count
                    top += 1
                    stack[top] = j
        count += 1
    return count, labels


def _decoupling(t11, t22, t12):
    """``X`` with ``T11 X - X T22 = -T12`` for the quasi-triangular Schur blocks (LAPACK trsyl)."""
    x, scale, info = scipy.linalg.lapack.dtrsyl(t11, t22, -t12, isgn=-1)
    if info < 0:
        raise ValueError(f"dtrsyl: argument {-info} is invalid")
    return x / scale


def _ordered_schur(M, tol):
    """Real Schur form ``M = Z T Z^T`` with the eigenvalues ``|lambda| <= tol`` first.

    LAPACK ``dgees`` then ``dtrsen`` on a selection computed at once (the same result as
    ``scipy.linalg.schur(..., sort=...)`` without a Python callback per eigenvalue).
    Returns ``(T, Z, k)``, ``k`` the number of selected eigenvalues.
    """
    t, _, wr, wi, z, _, info = scipy.linalg.lapack.dgees(lambda re, im: None, M,
                                                          compute_v=1, sort_t=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"the Schur decomposition failed (dgees info {info})")
    select = np.hypot(wr, wi) <= tol
    k = int(np.count_nonzero(select))
    if 0 < k < M.shape[0]:
        t, z, _, _, k, _, _, info = scipy.linalg.lapack.dtrsen(select.astype(np.int32), t, z,
                                                               job="N")
        if info != 0:
            raise np.linalg.LinAlgError(f"reordering the Schur form failed (dtrsen info "
                                        f"{info}): eigenvalues too close to separate")
    return t, z, k


def _split(M, tol, max_cond):
    """``(nil, lam, s0, s1v, in0, in1)`` of ``M`` (n x n): ordered real Schur form, Sylvester
    decoupling, eigendecomposition of the part with ``|lambda| > tol``."""
    n = M.shape[0]
    t, z, k = _ordered_schur(M, tol)
    t11, t12, t22 = t[:k, :k], t[:k, k:], t[k:, k:]
    x = _decoupling(t11, t22, t12) if 0 < k < n else np.zeros((k, n - k))
    # x_orig = Z [[I, X], [0, I]] [xi0; xi1];  [[I, X], [0, I]]^-1 = [[I, -X], [0, I]]
    upper = np.eye(n)
    upper[:k, k:] = x
    s = z @ upper
    upper[:k, k:] = -x
    s_inv = upper @ z.T
    if k == n:
        return t11, np.zeros(0, complex), s, np.zeros((n, 0), complex), s_inv, \
            np.zeros((0, n), complex)
    lam, v = np.linalg.eig(t22)
    lu = scipy.linalg.lu_factor(v, check_finite=False)
    rcond, _ = scipy.linalg.lapack.zgecon(lu[0], np.linalg.norm(v, 1), norm="1")
    if not rcond * max_cond > 1.0:      # 1-norm condition number estimate
        raise DefectiveSpectrum(f"eigenvector condition number {1 / rcond:.3g} "
                                f"(1-norm estimate) exceeds {max_cond:.3g}")
    in1 = scipy.linalg.lu_solve(lu, s_inv[k:].astype(complex), check_finite=False)
    return t11, lam, s[:, :k], s[:, k:] @ v, s_inv[:k], in1


def _split_blocks(M, tol, max_cond, labels):
    """:func:`_split` of a block-diagonal ``M`` (up to a permutation), block by block.

    ``labels``: the component of each state. Blocks of one and two states (free modes,
    rigid bodies, constants) are decomposed together, in closed form or by one batched
    2 x 2 eigensolve; larger ones, or 2 x 2 blocks with one zero eigenvalue, by
    :func:`_split`.
    """
    n = M.shape[0]
    order = np.argsort(labels, kind="stable")
    sizes = np.bincount(labels)
    groups = np.split(order, np.cumsum(sizes)[:-1])
    # (idx, s0, in0, nil) and (idx, lam, v, vinv); idx of shape (N, 2) for a batch of 2 x 2
    nil_parts, mode_parts = [], []
    ones = [g[0] for g in groups if g.size == 1]
    if ones:
        i1 = np.array(ones)
        a = M[i1, i1]
        for i, ai in zip(i1[np.abs(a) <= tol], a[np.abs(a) <= tol]):
            nil_parts.append((np.array([i]), np.ones((1, 1)), np.ones((1, 1)), np.array([[ai]])))
        live = np.abs(a) > tol
        if live.any():
            mode_parts.append((i1[live], a[live].astype(complex), None, None))
    general = [g for g in groups if g.size > 2]
    twos = [g for g in groups if g.size == 2]
    if twos:
        i2 = np.array(twos)
        blocks = M[i2[:, :, None], i2[:, None, :]]
        lam2, v2 = np.linalg.eig(blocks)
        small = np.abs(lam2) <= tol
        for g, blk in zip(i2[small.all(axis=1)], blocks[small.all(axis=1)]):
            nil_parts.append((g, np.eye(2), np.eye(2), blk))
        live = ~small.any(axis=1)
        if live.any():
            cond = np.linalg.cond(v2[live])
            if np.any(~(cond <= max_cond)):
                raise DefectiveSpectrum(f"eigenvector condition number {np.max(cond):.3g} "
                                        f"of a 2 x 2 block exceeds {max_cond:.3g}")
            mode_parts.append((i2[live], lam2[live], v2[live], np.linalg.inv(v2[live])))
        general += [g for g, mixed in zip(twos, small.any(axis=1) & ~small.all(axis=1))
                    if mixed]
    for g in general:
        nil, lam, s0, s1v, in0, in1 = _split(M[np.ix_(g, g)], tol, max_cond)
        if nil.size:
            nil_parts.append((g, s0, in0, nil))
        if lam.size:
            mode_parts.append((g, lam, s1v, in1))
    k = sum(p[3].shape[0] for p in nil_parts)
    m = sum(p[1].size for p in mode_parts)
    nil, s0, in0 = np.zeros((k, k)), np.zeros((n, k)), np.zeros((k, n))
    lam = np.zeros(m, complex)
    s1v, in1 = np.zeros((n, m), complex), np.zeros((m, n), complex)
    c = 0
    for g, s0_b, in0_b, nil_b in nil_parts:
        kb = nil_b.shape[0]
        nil[c:c + kb, c:c + kb] = nil_b
        s0[g, c:c + kb] = s0_b
        in0[c:c + kb, g] = in0_b
        c += kb
    c = 0
    for g, lam_b, v_b, w_b in mode_parts:
        mb = lam_b.size
        lam[c:c + mb] = lam_b.ravel()
        if v_b is None:                 # 1 x 1 blocks: unit eigenvectors
            s1v[g, np.arange(c, c + mb)] = 1.0
            in1[np.arange(c, c + mb), g] = 1.0
        elif g.ndim == 2:               # a batch of 2 x 2 blocks, two columns each
            cols = c + np.arange(mb).reshape(-1, 2)
            s1v[g[:, :, None], cols[:, None, :]] = v_b
            in1[cols[:, :, None], g[:, None, :]] = w_b
        else:
            s1v[np.ix_(g, np.arange(c, c + mb))] = v_b
            in1[np.ix_(np.arange(c, c + mb), g)] = w_b
        c += mb
    return nil, lam, s0, s1v, in0, in1


def _checked_update(M, update_of):
    """``(free, b, r)`` of ``update_of`` after checking that ``M = free.M + outer(b, r)``."""
    if not (isinstance(update_of, tuple) and len(update_of) == 3):
        raise TypeError(f"update_of must be a tuple (free, b, r), got {update_of!r}")
    free, b, r = update_of
    if not isinstance(free, SpectralPhase):
        raise TypeError(f"update_of[0] must be a SpectralPhase, got {type(free).__name__}")
    b, r = np.asarray(b, dtype=float), np.asarray(r, dtype=float)
    n = M.shape[0]
    for name, v in (("b", b), ("r", r)):
        if v.shape != (n,):
            raise ValueError(f"update_of's {name} must have shape ({n},), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"update_of's {name} has non-finite entries")
    if free.M.shape != M.shape:
        raise ValueError(f"update_of's phase is {free.M.shape[0]} x {free.M.shape[0]}, M is "
                         f"{n} x {n}")
    mismatch = float(np.max(np.abs(M - (free.M + np.outer(b, r))), initial=0.0))
    if mismatch > 1e-12 * max(float(np.max(np.abs(M), initial=0.0)), 1e-300):
        raise ValueError(f"M is not update_of's matrix + outer(b, r) (largest difference "
                         f"{mismatch:.3g})")
    return free, b, r


class SpectralPhase:
    """Spectral form of ``x' = M x`` with fast evaluation of outputs over many times.

    A block-diagonal ``M`` (up to a permutation of the states: uncoupled modes, the free
    flight of two bodies) is decomposed block by block, which gives the same form.
    ``update_of=(free, b, r)``: ``M = free's matrix + outer(b, r)`` (a contact phase), split
    through ``free``'s form in O(n^2 m) (:mod:`.rank_one`) when its checks pass, else by
    the general route. :attr:`route` says which was taken.
    """

    def __init__(self, M, *, max_cond=1e8, update_of=None):
        M = np.asarray(M, dtype=float)
        n = M.shape[0]
        norm = np.linalg.norm(M, 1) or 1.0
        # zero eigenvalues: a Jordan pair (a rigid body, a rigid contact's held gap)
        # splits by ~sqrt(eps |M|) in rounding: the cut is a multiple of that. (It was
        # the smaller of that and 1e-9 |M|, which below |M| ~ 2e4 /s missed the split
        # pair: at |M| = 352 /s a held gap's pair at +-5e-7 /s, above 3.5e-7, was kept as
        # a mode of period 1e7 s with nearly parallel eigenvectors, and the impulse
        # integral J came out 1-3 % off. Eigenvalues under the cut, 1.5e-5 /s at |M| = 1e4,
        # are taken with the polynomial part: exact to O((lambda t)^k) there.)
        tol = _CHAIN_FACTOR * math.sqrt(np.finfo(float).eps * norm)
        split = None
        if update_of is not None:
            free, b, r = _checked_update(M, update_of)
            split = rank_one_split(M, free, b, r, tol=tol, max_cond=max_cond)
            self.route = "rank-one update"
        if split is None:
            n_comp, labels = _components((M != 0) | (M.T != 0)) if n > 2 else (1, None)
            split = (_split_blocks(M, tol, max_cond, labels) if n_comp > 1
                     else _split(M, tol, max_cond))
            self.route = "blocks" if n_comp > 1 else "schur"
        nil, lam, s0, s1v, in0, in1 = split
        self.M = M.copy()
        k = nil.shape[0]
        self.n, self.k = n, k
        self.nil = nil
        self.lam = lam
        self.s0 = s0
        self.s1v = s1v
        self.in0 = in0
        self.in1 = in1
        # powers N^j / j! for the polynomial part (N nilpotent: N^k = 0)
        powers = [np.eye(k)]
        for j in range(1, k + 1):
            powers.append(powers[-1] @ nil / j)
        self.powers = powers[:k] if k else []
        self.max_rate = float(np.max(np.abs(lam))) if lam.size else 0.0
        # conjugate pairs folded for real states: Re(v c e^{l t} + conj(...)) = 2 Re(v c e^{l t})
        # (LAPACK returns the pairs exactly conjugate); the methods below use this form
        keep = lam.imag >= 0.0
        weight = np.where(lam.imag > 0.0, 2.0, 1.0)[keep]
        self.rates = np.ascontiguousarray(lam[keep])
        self._modes = self.s1v[:, keep] * weight
        self._proj = self.in1[keep]
        self._s0_powers = (np.stack([self.s0 @ p for p in self.powers]) if k
                           else np.zeros((0, n, 0)))

    def coordinates(self, x):
        """``(c0, c1)``: the state in the split coordinates (``c1`` over :attr:`rates`)."""
        return self.in0 @ x, self._proj @ x

    def project(self, rows):
        """The constant part of :meth:`output_coefficients` for ``rows``, computed once."""
        rows = np.atleast_2d(np.asarray(rows, dtype=float))
        poly = (np.einsum("rn,jnk->rjk", rows, self._s0_powers) if self.k
                else np.zeros((rows.shape[0], 0, 0)))
        return poly, rows @ self._modes

    def output_coefficients(self, rows, coords):
        """Polynomial (rows x k) and exponential (rows x m) coefficients of ``rows @ x(t)``.

        The exponential coefficients go with :attr:`rates` (conjugate pairs folded).
        """
        return self.coefficients(self.project(rows), coords)

    def coefficients(self, projected, coords):
        """:meth:`output_coefficients` from the rows' :meth:`project` ``projected`` (the
        part that does not depend on the state: once per set of rows)."""
        c0, c1 = coords
        poly_m, expo_m = projected
        poly = poly_m @ c0 if self.k else np.zeros((expo_m.shape[0], 0))
        return poly, expo_m * c1[None, :]

    def evaluate(self, coefficients, taus, derivative=0):
        """Outputs (rows x len(taus)) at times ``taus`` from ``output_coefficients``."""
        return self.evaluate_orders(coefficients, taus, (derivative,))[0]

    def scalar(self, coefficients, tau, derivative=0):
        """The first output row's value (or ``derivative``-th derivative) at one ``tau``."""
        return float(self.evaluate(coefficients, [tau], derivative)[0, 0])

    def state(self, coords, tau):
        """The state ``x`` (shape (n,)) at ``tau`` from :meth:`coordinates` ``coords``."""
        return self.evaluate(self.output_coefficients(np.eye(self.n), coords), [tau])[:, 0]

    def product_integrals(self, projected, runs, pairs):
        """``sum over runs of int_0^h (rows[a] x(t)) (rows[b] x(t)) dt`` for each ``(a, b)``
        of ``pairs``, in closed form (:func:`impactpred.engine.product_integrals.
        product_integrals`): the rows given as :meth:`project` ``projected``, ``runs`` a
        list of ``(x0, h)`` (a run of this phase from state ``x0`` for ``h`` s)."""
        coefficient_runs = [(*self.coefficients(projected, self.coordinates(x0)), h)
                            for x0, h in runs]
        return product_integrals(self.rates, self.k, coefficient_runs, pairs)

    def evaluate_orders(self, coefficients, taus, derivatives=(0, 1)):
        """Outputs and their time derivatives at ``taus``, sharing the exponentials.

        Returns one (rows x len(taus)) array per entry of ``derivatives``.
        """
        poly, expo = coefficients
        taus = np.asarray(taus, dtype=float)
        k = poly.shape[1]
        lam = self.rates
        e = np.exp(np.outer(lam, taus)) if expo.shape[1] else None
        powers = taus[None, :] ** np.arange(k)[:, None] if k else None
        out = []
        for d in derivatives:
            value = np.zeros((poly.shape[0], taus.size))
            if k > d:
                factors = np.array([math.perm(j, d) for j in range(d, k)], dtype=float)
                value += (poly[:, d:] * factors) @ powers[:k - d]
            if e is not None:
                value += ((expo * lam[None, :] ** d) @ e).real
            out.append(value)
        return out
